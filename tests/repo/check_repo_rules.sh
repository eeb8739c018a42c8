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

# 5. the cores are pure: no sockets, threads, clocks, logging or messages
for core in libs/textile libs/contact libs/tactile libs/device libs/netsim; do
  [[ -d "$root/$core" ]] || continue
  impure=$(grep -rnE '#include\s*[<"](asio|spdlog|thread|chrono|mutex|condition_variable|future|sys/socket\.h|netinet/|google/protobuf|haptex/v1/|ctime|time\.h|iostream)' \
    "$root/$core" 2>/dev/null | sed "s|$root/||" || true)
  [[ -z "$impure" ]] || fail "$core is not pure: $impure"
done

# 6. scripts the README names exist and are executable
for s in scripts/demo scripts/test scripts/setup .ci/run; do
  [[ -x "$root/$s" ]] || fail "$s is missing or not executable"
done

[[ $failed -eq 0 ]] && echo "repo rules: all hold"
exit $failed
