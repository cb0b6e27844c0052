#!/usr/bin/perl
# tests/fpmakecheck.pl - fpmake.pp is the one list of the library's units
# (called by tests/packaging.sh). Fails when a unit of src/<part>/ or its
# unix/ and win/ folders is missing from fpmake.pp (or listed but gone),
# when a unit's folder is not the part fpmake.pp lists it under, when its OS
# set does not fit its folder, or when the dependencies fpmake.pp declares
# for a unit are not the package units its uses clauses name (interface
# and implementation, {$IFDEF}ed ones included). Prints ok/FAIL lines.
use strict; use warnings;
open my $fh, '<', 'fpmake.pp' or die "fpmake.pp: $!";
my (%listed, %oses, %deps, %part, $cur, $curpart, @optional);
while (<$fh>) {
  if (/Optional = '([^']*)'/) { @optional = map { s/\.pas$//r } split ' ', $1; }
  if (/^\s*Part\(P, '(\w+)'\);/) { $curpart = $1; }
  if (/AddUnit\(P, '(\w+)\.pas', (\w+), \[([^\]]*)/) {
    $cur = $1; $listed{$cur} = 1; $oses{$cur} = $2; $part{$cur} = $curpart // '?';
    $deps{$cur} = { map { $_ => 1 } ($3 =~ /'(\w+)'/g) };
    # a dependency list continued on the next line
    while ($_ !~ /\]\);/ && defined($_ = <$fh>)) { $deps{$cur}{$_} = 1 for /'(\w+)'/g; }
  } elsif (/T\.Dependencies\.AddUnit\('(\w+)'/ && $cur) { $deps{$cur}{$1} = 1; }
}
my %dir = (AllOSes => '', AllUnixOSes => '/unix', AllWindowsOSes => '/win');
my (%file, @bad);
for my $f (glob("src/*.pas"), glob("src/*/*.pas"), glob("src/*/*/*.pas")) {
  my ($n) = $f =~ m{(\w+)\.pas$};
  push @bad, "$f: a unit outside the part folders src/<part>/ (and their unix/, win/)"
    unless $f =~ m{^src/\w+/(?:(?:unix|win)/)?\w+\.pas$};
  push @bad, "$n is twice in src/: $file{$n} and $f" if $file{$n};
  $file{$n} = $f;
}
my %opt = map { $_ => 1 } @optional;
for my $n (sort keys %file) {
  next if $opt{$n};
  if (!$listed{$n}) { push @bad, "$file{$n} is missing from fpmake.pp"; next; }
  my $want = "src/$part{$n}" . ($dir{$oses{$n}} // '?');
  push @bad, "$n: listed under Part '$part{$n}' with OS set $oses{$n}, but the file is $file{$n}"
    if "$want/$n.pas" ne $file{$n};
}
for my $n (sort keys %listed) { push @bad, "fpmake.pp lists $n, which is not in src/" unless $file{$n}; }
# the package units each unit uses
for my $n (sort keys %listed) {
  next unless $file{$n};
  open my $h, '<', $file{$n} or next; local $/; my $t = <$h>;
  $t =~ s/\{[^}]*\}//gs; $t =~ s/\(\*.*?\*\)//gs; $t =~ s{//[^\n]*}{}g; $t =~ s/'[^']*'//g;
  my %used;
  while ($t =~ /\buses\b(.*?);/gis) {
    for my $w ($1 =~ /(\w+)/g) { $used{$w} = 1 if $file{$w} && $w ne 'in'; }
  }
  my @missing = grep { !$deps{$n}{$_} && !$opt{$_} } sort keys %used;
  my @extra = grep { !$used{$_} } sort keys %{$deps{$n}};
  push @bad, "$n uses @missing, not declared in fpmake.pp" if @missing;
  push @bad, "$n: fpmake.pp declares @extra, which it does not use" if @extra;
}
if (@bad) { print "FAIL  package: fpmake.pp is the list of units: $_\n" for @bad; exit 1; }
printf "ok    package: fpmake.pp lists every unit of src/ (%d) with its OSes and its real dependencies\n",
  scalar(keys %listed);
