#!/usr/bin/env bash
# Builds a small tree that breaks every rule, to prove check_repo_rules.sh can fail.
# usage: make_broken_tree.sh DIR
set -euo pipefail
dir=$1
rm -rf "$dir" && mkdir -p "$dir"/{proto,libs/textile,libs/contact,libs/base,.ci,scripts,third_party/x,docs}
printf '## Quick start\n\n```\nmake\n```\n' > "$dir/README.md"
printf '#!/bin/sh\nmake test\n' > "$dir/.ci/run"
touch "$dir/proto/a.pb.h" "$dir/third_party/x/x.h"
printf 'include(FetchContent)\nif(EXISTS ${dir}/x)\nendif()\n' > "$dir/CMakeLists.txt"
echo '#include <thread>' > "$dir/libs/textile/step.cc"
# a folder of tests nobody builds
mkdir -p "$dir/tests/forgotten" && printf 'add_subdirectory(listed)\n' > "$dir/tests/CMakeLists.txt"
# libs/base may read the clock in clock.h only, must stay std only, and no core may use the clock
printf '#include <chrono>\n#include <time.h>\n' > "$dir/libs/base/clock.h"
echo '#include <chrono>' > "$dir/libs/base/timer.h"
echo '#include <Eigen/Core>' > "$dir/libs/base/maths.h"
echo '#include "libs/base/clock.h"' > "$dir/libs/contact/timed.cc"
# Citations that do not resolve, assembled from pieces so that this script does not cite them
# itself.
d=docs; nd=note; nd+=s; shared=../; shared+=shared; machine=/; machine+=work/
printf '## 1. Only section\n\nSee %s/missing.md and [the guide](guide.md); %s/page.md section 4.\n' "$d" "$d" \
  > "$dir/docs/page.md"
printf 'Built in %sbuild-x.\n' "$machine" >> "$dir/docs/page.md"
printf '// After %s/physics.md section 1.1,\n// and %s/x.py.\n' "$nd" "$shared" > "$dir/libs/textile/cited.h"
printf '# computed by %s/scripts/table.py\n' "$nd" > "$dir/libs/textile/table.textproto"
# a C++ file the house style would reformat
printf 'BasedOnStyle: Google\n' > "$dir/.clang-format"
printf 'int   badly ( int x ){return x;}\n' > "$dir/libs/textile/unformatted.c""c"
