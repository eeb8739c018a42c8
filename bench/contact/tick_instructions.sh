#!/usr/bin/env bash
# Instructions per haptic tick, counted by callgrind: repeatable whatever else the machine does
# (tick timings on a shared 2-core host vary 1.4x between runs), so two builds of a change can
# be compared exactly. Counts ContactSolver + fabric step inside PatchSimulation::Tick, mostly
# over the 200-tick press each benchmark warms up with.
#
#   bench/contact/tick_instructions.sh [BUILD_DIR] [BENCHMARK_REGEX ...]
#   e.g. bench/contact/tick_instructions.sh build 'PinchTick/3$' 'OneFingerTick/3$'
set -euo pipefail
build=${1:-build}
shift || true
filters=("$@")
[[ ${#filters[@]} -gt 0 ]] || filters=('PinchTick/3$' 'OneFingerTick/3$')
bench=$build/bench/contact/contact_tick_bench
[[ -x $bench ]] || { echo "no $bench: build the contact_tick_bench target first" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for filter in "${filters[@]}"; do
  valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" --collect-atstart=no \
    '--toggle-collect=haptex::contact::PatchSimulation::Tick(*' \
    "$bench" --benchmark_filter="$filter" --benchmark_min_time=0.01 >/dev/null 2>&1
  # Total instructions collected, and the ticks: calls of the one fabric step per tick.
  python3 - "$out/cg.out" "$filter" <<'PY'
import re, sys
path, name = sys.argv[1], sys.argv[2]
names, total, ticks, callee = {}, None, 0, None
for line in open(path):
    m = re.match(r'(c?fn)=\((\d+)\)(?: (.*))?', line)
    if m:
        kind, ident, text = m.groups()
        if text:
            names[ident] = text.strip()
        if kind == 'cfn':
            callee = names.get(ident, '')
        continue
    m = re.match(r'calls=(\d+)', line)
    if m and callee and 'ImplicitEulerStep' in callee:
        ticks += int(m.group(1))
    m = re.match(r'(?:summary|totals): (\d+)', line)
    if m:
        total = int(m.group(1))
if not total or not ticks:
    sys.exit(f'{name}: nothing counted (total {total}, ticks {ticks})')
print(f'{name}: {ticks} ticks, {total / ticks / 1e6:.3f} M instructions per tick')
PY
done
