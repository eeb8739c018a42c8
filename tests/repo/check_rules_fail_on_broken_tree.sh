#!/usr/bin/env bash
# Proves check_repo_rules.sh fails, naming each broken rule, on a tree that breaks them all.
# usage: check_rules_fail_on_broken_tree.sh WORK_DIR
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
"$here/make_broken_tree.sh" "$1/broken"
out=$("$here/check_repo_rules.sh" "$1/broken")
status=$?
echo "$out"
[[ $status -ne 0 ]] || { echo "checker passed a broken tree"; exit 1; }
for rule in "generated protobuf code" "build files that download" "vendored code" \
            "README quick start" ".ci/run does more" "libs/textile is not pure" "scripts/demo is missing" \
            "libs/base is not pure: libs/base/timer.h" "libs/base is not std only: libs/base/maths.h" \
            "libs/contact uses the clock" "silent guards in the build: CMakeLists.txt:2"; do
  grep -qF "$rule" <<<"$out" || { echo "checker missed: $rule"; exit 1; }
done
# the one clock may read the time
! grep -qF "libs/base/clock.h:" <<<"$out" || { echo "checker flagged libs/base/clock.h"; exit 1; }
echo "checker caught every broken rule"
