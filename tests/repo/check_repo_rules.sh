#!/usr/bin/env bash
# The house rules that a test can check on the source tree. usage: check_repo_rules.sh ROOT
set -uo pipefail
root=$1
failed=0
fail() { echo "RULE BROKEN: $*"; failed=1; }

# files of the source tree, without build folders
files() { (cd "$root" && find . -path ./build -prune -o -path './build-*' -prune -o -path ./runs -prune \
  -o -path ./.git -prune -o -type f -print | sed 's|^\./||'); }

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
for lib in libs/textile libs/contact libs/tactile libs/device libs/base; do
  [[ -d "$root/$lib" ]] || continue
  impure=$(grep -rnE "$impure_re" "$root/$lib" 2>/dev/null | sed "s|$root/||" \
    | grep -vE '^libs/base/clock\.h:[0-9]+:#include\s*<(chrono|ctime|time\.h)>' || true)
  [[ -z "$impure" ]] || fail "$lib is not pure: $impure"
done
for core in libs/textile libs/contact libs/tactile libs/device; do
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

# 7. scripts the README names exist and are executable
for s in scripts/demo scripts/test scripts/setup .ci/run; do
  [[ -x "$root/$s" ]] || fail "$s is missing or not executable"
done

[[ $failed -eq 0 ]] && echo "repo rules: all hold"
exit $failed
