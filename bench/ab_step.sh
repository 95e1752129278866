#!/usr/bin/env bash
# ab_step: two bench_step builds (or one build with two option sets) run
# alternately, so that a shared machine's swings hit both alike; prints the
# medians per case: steps/s, and the profiled update time of the steps that
# rebuilt the lists and of the others (bench_step's "update X us then, Y
# otherwise"), which are steadier than steps/s. Each side keeps its own
# POCL_CACHE_DIR, so neither compiles the other's kernels.
#
#   bench/ab_step.sh ROUNDS "BENCH_ARGS" BIN_A BIN_B ["ARGS_A" "ARGS_B"]
#   e.g. bench/ab_step.sh 5 "--only 100000" /tmp/old/bench_step build/bench/bench_step
#        bench/ab_step.sh 5 "--only 100000" build/bench/bench_step build/bench/bench_step "--inner-lists off" ""
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,12p' "$0"; exit 2; }
rounds=$1 common=$2 bin_a=$3 bin_b=$4 args_a=${5:-} args_b=${6:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for ((r = 1; r <= rounds; ++r)); do
  for side in A B; do
    if [ "$side" = A ]; then bin=$bin_a args=$args_a; else bin=$bin_b args=$args_b; fi
    # shellcheck disable=SC2086  # the argument strings split into words on purpose
    POCL_CACHE_DIR="$work/cache_$side" "$bin" $common $args | grep -E '^(N=|fill)' | sed "s/^/$side /" >> "$work/out"
  done
done
python3 - "$work/out" <<'PY'
import re, statistics, sys
runs = {}
for line in open(sys.argv[1]):
    side, rest = line.split(' ', 1)
    words = rest.split()
    case = 'fill regime' if rest.startswith('fill') else ' '.join(
        [words[0]] + (['+b'] if words[1] == '+b' else []) + ['2.5 sigma' if '2.5 sigma' in rest else 'repulsive'])
    rate = float(re.search(r'([\d.]+) steps/s', rest).group(1))
    m = re.search(r'update ([\d.]+) us then, ([\d.]+) otherwise', rest)
    runs.setdefault((case, side), []).append((rate,) + ((float(m.group(1)), float(m.group(2))) if m else (0.0, 0.0)))
print('%-22s %4s %10s %18s %16s  %s' % ('case', 'side', 'steps/s', 'rebuild step (us)', 'other step (us)', 'steps/s of each run'))
for (case, side), v in sorted(runs.items()):
    med = lambda k: statistics.median(x[k] for x in v)
    print('%-22s %4s %10.1f %18.0f %16.0f  %s' % (case, side, med(0), med(1), med(2), ' '.join('%g' % x[0] for x in v)))
PY
