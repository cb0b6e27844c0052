#!/usr/bin/perl
# tests/apicheck.pl - the string and integer rule of docs/LAYERS.md, checked
# over every library unit given on the command line: no unit switches to
# long strings ({$H+}, {$LONGSTRINGS ON}) and no interface section names
# Integer, Cardinal or plain "string" (their size follows the compiler
# mode); string[N], ShortString and AnsiString are fine. Prints each
# offence as FILE:LINE: text and exits 1 if there is any.
use strict;
use warnings;
my $bad = 0;
for my $file (@ARGV) {
    open(my $fh, '<', $file) or die "$file: $!";
    local $/;
    my $src = <$fh>;
    close $fh;
    # switches anywhere in the unit
    while ($src =~ /\{\$(H\+|LONGSTRINGS\s+ON)[^}]*\}/gi) {
        my $line = 1 + (substr($src, 0, pos($src)) =~ tr/\n//);
        print "$file:$line: switches to long strings ({\$$1})\n";
        $bad = 1;
    }
    # blank out comments and literals, keeping line breaks for the numbers
    my $code = $src;
    $code =~ s/(\{[^}]*\}|\(\*.*?\*\)|\/\/[^\n]*|'[^'\n]*')/my $m = $1; $m =~ s{[^\n]}{ }g; $m/gse;
    my ($iface) = $code =~ /^(.*?)^\s*implementation\b/msi;
    next unless defined $iface;
    my $n = 0;
    for my $l (split /\n/, $iface) {
        $n++;
        if ($l =~ /\b(integer|cardinal)\b/i || $l =~ /\bstring\b(?!\s*\[)/i) {
            my @orig = split /\n/, $src;
            print "$file:$n: mode-dependent type in the interface: $orig[$n-1]\n";
            $bad = 1;
        }
    }
}
exit $bad;
