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
            "libs/base is not pure: libs/base/timer" "libs/base is not std only: libs/base/maths" \
            "libs/contact uses the clock" "silent guards in the build: CMakeLists.txt:2" \
            "cites material outside the repository" "cites a missing file" "markdown link to a missing file" \
            "cites a missing section" "not formatted by .clang-format" \
            "tests/forgotten is not listed in tests/CMakeLists.txt"; do
  grep -qF "$rule" <<<"$out" || { echo "checker missed: $rule"; exit 1; }
done
# the one clock may read the time
! grep -qF "libs/base/clock.h:" <<<"$out" || { echo "checker flagged libs/base/clock.h"; exit 1; }
# each kind of outside citation is named (assembled, so that this script does not cite them)
d=docs; nd=note; nd+=s; shared=../; shared+=shared; machine=/; machine+=work/
for cited in "cited.h:1: $nd/physics.md" "cited.h:2: $shared" "table.textproto:1: $nd/scripts" \
             "page.md:4: ${machine}build-x" "page.md:3: $d/missing.md" "page.md:3: guide.md" \
             "page.md:3: $d/page.md section 4"; do
  grep -qF "$cited" <<<"$out" || { echo "checker missed the citation $cited"; exit 1; }
done
# the badly formatted file is named (assembled: this script cites no file that does not exist)
u=libs; u+=/textile/unformatted.cc
grep -qF "$u" <<<"$out" || { echo "checker missed the unformatted $u"; exit 1; }
echo "checker caught every broken rule"
