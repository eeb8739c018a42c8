#!/usr/bin/env bash
# The house rules that a test can check on the source tree. usage: check_repo_rules.sh ROOT
set -uo pipefail
root=$1
failed=0
fail() { echo "RULE BROKEN: $*"; failed=1; }

# files of the source tree, without build folders and installed npm packages (web/node_modules,
# scripts/setup)
files() { (cd "$root" && find . -path ./build -prune -o -path './build-*' -prune -o -path ./runs -prune \
  -o -path ./.git -prune -o -name node_modules -prune -o -type f -print | sed 's|^\./||'); }

# 1. generated protobuf code is built, never committed
gen=$(files | grep -E '\.pb\.(h|cc)$|_pb2\.py$' || true)
[[ -z "$gen" ]] || fail "generated protobuf code in the tree: $gen"

# 2. nothing vendored, nothing downloaded at build time
dl=$(files | grep -E '(^|/)(CMakeLists\.txt|[^/]*\.cmake)$' | (cd "$root" && xargs grep -lE 'FetchContent|ExternalProject_Add|file\(DOWNLOAD' 2>/dev/null) || true)
[[ -z "$dl" ]] || fail "build files that download: $dl"
vendored=$(files | grep -E '^(third_party|vendor|external|extern)/' | head -3 || true)
[[ -z "$vendored" ]] || fail "vendored code: $vendored"

# 3. the README's quick start is exactly the two commands
quick=$(awk '/^## Quick start/{f=1;next} /^## /{f=0} f' "$root/README.md" | awk '/^```/{c=!c;next} c' | sed '/^\s*$/d')
[[ "$quick" == $'scripts/demo\nscripts/test' ]] || fail "README quick start is not exactly 'scripts/demo' and 'scripts/test': $quick"

# 4. CI runs scripts/test and nothing else
ci=$(grep -vE '^\s*(#|$)|^set -|^cd ' "$root/.ci/run")
[[ "$ci" == "exec scripts/test" ]] || fail ".ci/run does more than 'exec scripts/test': $ci"

# 5. the cores and libs/base are pure: no sockets, threads, clocks, logging or messages. libs/base
#    holds the one clock: <chrono>, <ctime> and <time.h> are allowed in libs/base/clock.h only,
#    which the cores must not include (time comes into a core as dt). libs/base is std only.
impure_re='#include\s*[<"](asio|spdlog|thread|chrono|mutex|condition_variable|future|sys/socket\.h|netinet/|google/protobuf|haptex/v1/|ctime|time\.h|iostream)'
for lib in libs/textile libs/contact libs/dual_layer libs/tactile libs/device libs/netsim libs/base; do
  [[ -d "$root/$lib" ]] || continue
  impure=$(grep -rnE "$impure_re" "$root/$lib" 2>/dev/null | sed "s|$root/||" \
    | grep -vE '^libs/base/clock\.h:[0-9]+:#include\s*<(chrono|ctime|time\.h)>' || true)
  [[ -z "$impure" ]] || fail "$lib is not pure: $impure"
done
for core in libs/textile libs/contact libs/dual_layer libs/tactile libs/device libs/netsim; do
  [[ -d "$root/$core" ]] || continue
  clock=$(grep -rnE '#include\s*"libs/base/clock\.h"' "$root/$core" 2>/dev/null | sed "s|$root/||" || true)
  [[ -z "$clock" ]] || fail "$core uses the clock: $clock"
done
if [[ -d "$root/libs/base" ]]; then
  not_std=$(grep -rnE '#include\s*("|<(Eigen|OpenMesh|google|spdlog|asio|CLI|sodium|gtest|gmock|benchmark|haptex)/)' \
    "$root/libs/base" 2>/dev/null | sed "s|$root/||" | grep -vE '#include\s*"libs/base/' || true)
  [[ -z "$not_std" ]] || fail "libs/base is not std only: $not_std"
fi

# 6. no silent guards in the build: folders and tests are listed, so a missing one fails the
#    configure instead of vanishing (no existence or target checks, no globbed folders)
guards=$(files | grep -E '(^|/)(CMakeLists\.txt|[^/]*\.cmake)$' | (cd "$root" && xargs grep -HnE \
  'if\s*\(\s*(NOT\s+)?(EXISTS|TARGET)\b|LIST_DIRECTORIES\s+true' 2>/dev/null) || true)
[[ -z "$guards" ]] || fail "silent guards in the build: $guards"
# and every folder of tests is listed: one left out would build and run nothing, silently
if [[ -f "$root/tests/CMakeLists.txt" ]]; then
  for folder in "$root"/tests/*/; do
    name=$(basename "$folder")
    grep -qE "^add_subdirectory\($name\)" "$root/tests/CMakeLists.txt" ||
      fail "tests/$name is not listed in tests/CMakeLists.txt: its tests never run"
  done
fi

# 7. scripts the README names exist and are executable
for s in scripts/demo scripts/test scripts/setup .ci/run; do
  [[ -x "$root/$s" ]] || fail "$s is missing or not executable"
done

# 8. citations resolve inside the repository: a path under a top-level folder with a file extension
#    (in comments, strings, docs), a markdown link relative to its document, and "FILE.md section N"
#    must name what exists; nothing may point outside the tree (the shared folder beside a checkout,
#    a notes folder, machine-local absolute paths): a reader of the project could not follow it.
read -r -d '' citations_pl <<'PERL'
use strict; use warnings;
my $root = shift;
opendir(my $dh, $root) or die "$root: $!";
my %top = map { $_ => 1 } grep { -d "$root/$_" && !/^\./ && !/^build/ && $_ ne 'runs' } readdir($dh);
$top{$_} = 1 for qw(bench cli cmake data docs launch libs proto scripts services tests .ci), 'note' . 's';
my $tops = join '|', map { quotemeta } sort keys %top;
my $ext = 'md|hpp|hh|h|cpp|cc|c|py|sh|textproto|proto|txt|cmake|gp|json|csv|png|pgm|yaml|yml';
my $up = '\.\./' . 'shared';
my $abs = '/' . 'work/';
my $nd = 'note' . 's/';
my %headings;
sub sections_of {
  my ($md) = @_;
  return $headings{$md} if $headings{$md};
  my %s;
  if (open(my $fh, '<', "$root/$md")) {
    my $fence = 0;
    while (<$fh>) {
      $fence = !$fence if /^\s*```/;
      next if $fence;
      $s{$1} = 1 if /^#{1,6}\s+(\d+(?:\.\d+)*)(?:[.\s:)]|$)/;
    }
  }
  return $headings{$md} = \%s;
}
sub placeholder { my ($p) = @_; return $p =~ m{(^|/)[A-Z][A-Z0-9_]*(\.|/|$)} && $p !~ m{(^|/)(README|CMakeLists|RESULTS)\.}; }
my %build_tree;  # a folder holding CMakeCache.txt is a build tree (any name): generated, not cited
sub in_build_tree {
  my ($dir) = @_;
  while ($dir ne '') {
    $build_tree{$dir} //= -e "$root/$dir/CMakeCache.txt" ? 1 : 0;
    return 1 if $build_tree{$dir};
    $dir =~ s{/?[^/]*$}{};
  }
  return 0;
}
while (my $file = <STDIN>) {
  chomp $file;
  my $path = "$root/$file";
  next unless -T $path;
  open(my $fh, '<', $path) or next;
  (my $dir = $file) =~ s{/?[^/]*$}{};
  next if in_build_tree($dir);
  my $is_md = $file =~ /\.md$/;
  my $fence = 0;
  while (my $line = <$fh>) {
    my $at = "$file:$.";
    while ($line =~ /($up|$abs\S*|(?<![A-Za-z0-9_])$nd\S*?\.md|(?<![A-Za-z0-9_])${nd}scripts)/g) {
      print "OUTSIDE\t$at\t$1\n";
    }
    while ($line =~ m{(?<![A-Za-z0-9_./\-\$~{}])((?:$tops)/[A-Za-z0-9_./+\-]*?[A-Za-z0-9_\-]\.(?:\{[a-z0-9,]+\}|(?:$ext)))(?![A-Za-z0-9_])}g) {
      my $cited = $1;
      next if placeholder($cited);
      my @paths = ($cited);
      if ($cited =~ /^(.*)\.\{([a-z0-9,]+)\}$/) { my $b = $1; @paths = map { "$b.$_" } split /,/, $2; }
      for my $p (@paths) { print "MISSING\t$at\t$p\n" unless -e "$root/$p"; }
    }
    $fence = !$fence if $is_md && $line =~ /^\s*```/;
    if ($is_md && !$fence) {
      while ($line =~ /\]\(([^)\s]+)\)/g) {
        my $t = $1;
        next if $t =~ /^(?:[a-z][a-z0-9+.-]*:|#)/i;
        $t =~ s/#.*//;
        my $p = $dir eq '' ? $t : "$dir/$t";
        print "LINK\t$at\t$t\n" unless -e "$root/$p";
      }
    }
    while ($line =~ m{((?:[A-Za-z0-9_\-]+/)*[A-Za-z0-9_\-]+\.md),? (?:section|sections|§) ?(\d+(?:\.\d+)*)}g) {
      my ($md, $n) = ($1, $2);
      my ($found) = grep { -f "$root/$_" } ($md, ($dir eq '' ? () : "$dir/$md"), "docs/$md");
      next unless $found;
      print "SECTION\t$at\t$md section $n\n" unless sections_of($found)->{$n};
    }
  }
}
PERL
cites=$(files | perl -e "$citations_pl" "$root")
outside=$(awk -F'\t' '$1 == "OUTSIDE" {print $2 ": " $3}' <<<"$cites")
[[ -z "$outside" ]] || fail "cites material outside the repository (write it into docs/ instead): $outside"
missing=$(awk -F'\t' '$1 == "MISSING" {print $2 ": " $3}' <<<"$cites")
[[ -z "$missing" ]] || fail "cites a missing file: $missing"
links=$(awk -F'\t' '$1 == "LINK" {print $2 ": " $3}' <<<"$cites")
[[ -z "$links" ]] || fail "markdown link to a missing file: $links"
sections=$(awk -F'\t' '$1 == "SECTION" {print $2 ": " $3}' <<<"$cites")
[[ -z "$sections" ]] || fail "cites a missing section: $sections"

# 9. C++ is formatted as the tree's .clang-format says (clang-format from Debian, scripts/setup)
if [[ -f "$root/.clang-format" ]]; then
  if command -v clang-format >/dev/null; then
    unformatted=$(cd "$root" && files | grep -E '\.(cc|h)$' | while read -r f; do
      clang-format --style=file --dry-run -Werror "$f" >/dev/null 2>&1 || echo "$f"; done)
    [[ -z "$unformatted" ]] || fail "not formatted by .clang-format (run clang-format -i): $(echo $unformatted)"
  else
    fail "clang-format is missing (scripts/setup installs it)"
  fi
else
  fail ".clang-format is missing"
fi

[[ $failed -eq 0 ]] && echo "repo rules: all hold"
exit $failed
