#!/usr/bin/perl
# tests/doccheck.pl - the API reference gives every description to the
# declaration it was written for. pasdoc (make doc) takes a comment as the
# description of the declaration AFTER it; a comment that ends a line of
# code ("A: Byte;   { about A }") describes what is before it, and only
# its back-comment form ({< ...}, (*< ...*), //< ...) tells pasdoc so -
# a plain one lands on the next field, constant or method, and pasdoc
# says nothing. This script reads the interface section of every unit
# given, prints each comment that follows code on its line without being
# a back comment, and each back comment on a "record"/"object"/"class"
# line (pasdoc finds no item before it: put the type's description above
# the type), as FILE:LINE: text, and exits 1 if there is any. Compiler
# directives ({$...}) are not comments.
use strict;
use warnings;
my $bad = 0;
for my $file (@ARGV) {
    open(my $fh, '<', $file) or die "$file: $!";
    local $/;
    my $src = <$fh>;
    close $fh;
    my ($iface) = $src =~ /^(.*?)^\s*implementation\b/msi;
    next unless defined $iface;
    my @lines = split /\n/, $src;
    my ($line, $code, $i, $n) = (1, '', 0, length $iface);
    while ($i < $n) {
        my $c = substr($iface, $i, 1);
        if ($c eq "\n") { $line++; $code = ''; $i++; next; }
        if ($c eq "'") {                      # a string literal
            my $j = index($iface, "'", $i + 1);
            $j = $n if $j < 0;
            $code .= 'S';
            $i = $j + 1;
            next;
        }
        my ($open, $close);
        if (substr($iface, $i, 2) eq '(*') { ($open, $close) = ('(*', '*)'); }
        elsif ($c eq '{') { ($open, $close) = ('{', '}'); }
        elsif (substr($iface, $i, 2) eq '//') { ($open, $close) = ('//', "\n"); }
        if (!$open) { $code .= $c; $i++; next; }
        my $j = index($iface, $close, $i + length $open);
        $j = $n if $j < 0;
        my $body = substr($iface, $i, $j - $i);
        my $directive = $open eq '{' && substr($iface, $i + 1, 1) eq '$';
        my $back = substr($iface, $i + length $open, 1) eq '<';
        (my $pre = $code) =~ s/^\s+|\s+$//g;
        if (!$directive && $pre ne '') {
            my $why = '';
            if (!$back) {
                $why = "a comment after a declaration goes to the NEXT one in the API reference: write ${open}< (back comment)";
            } elsif ($pre =~ /\b(record|object|class|interface)\b(\s*\([^)]*\))?\s*$/i) {
                $why = "a back comment after \"$1\" describes nothing (pasdoc): put the type's description above it";
            }
            if ($why ne '') {
                print "$file:$line: $why: $lines[$line - 1]\n";
                $bad = 1;
            }
        }
        my $nl = ($body =~ tr/\n//);
        $line += $nl;
        $code = '' if $nl;
        $i = $j + ($close eq "\n" ? 0 : length $close);
    }
}
exit $bad;
