#!/usr/bin/env bash
# bench_lammps_scale: one fill of MESH at N spheres on the OpenCL engine and
# on the LAMMPS engine at each P of NPS (mpirun -np P), one after the other
# on the same cores; for each run: count, packing, largest overlap,
# containment, the passes' steps and seconds, the wall time, and the peak
# resident memory of every rank (/usr/bin/time per rank). Prints the load
# average before each run: wall times compare only between runs close in
# time and load (docs/lammps_engine.md "Figures"). A run stopped by LIMIT
# prints its last progress line (count and steps so far).
#
#   bench/bench_lammps_scale.sh [N [SEED [NPS [MESH [PFILL]]]]]
#     defaults: 100000, 1, "2 1", /work/shared/meshes/spot.obj, build/pfill
#   (PFILL: better a copy under a name no other process has, e.g.
#   /tmp/pfill-scale: a stopped run's memory is sampled by that name)
#   LIMIT=SECONDS: each run's wall-time cap (timeout; default 3600)
#   ENGINES="opencl lammps": which engines (default both)
#   PARTS=1: LAMMPS runs write a file per rank (-o out.%r.csv), so that no
#     rank gathers the whole result (the memory a rank needs at scale)
set -uo pipefail
n=${1:-100000}
seed=${2:-1}
nps=${3:-"2 1"}
mesh=${4:-/work/shared/meshes/spot.obj}
pfill=$(readlink -f "${5:-build/pfill}")
limit=${LIMIT:-3600}
engines=${ENGINES:-"opencl lammps"}
lammps_out=out.csv
[ "${PARTS:-0}" = 1 ] && lammps_out='out.%r.csv'
[ -x "$pfill" ] || { echo "bench_lammps_scale: $pfill not found; build it (make -C build pfill)"; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# summary NAME DIR WALL: one line from rank 0's report and every rank's time file
summary() {
  python3 - "$1" "$2" "$3" <<'PY'
import glob, json, os, sys
name, d, wall = sys.argv[1], sys.argv[2], sys.argv[3]
rss = []
for f in sorted(glob.glob(os.path.join(d, "time.*"))):
    fields = open(f).read().split()
    if len(fields) >= 2 and fields[-1].isdigit():
        rss.append(int(fields[-1]) // 1024)
if not rss:  # stopped: the sampled peaks, per process
    peak = {}
    for line in open(os.path.join(d, "hwm")):
        f = line.split()
        if len(f) == 2:
            peak[f[0]] = max(peak.get(f[0], 0), int(f[1]) // 1024)
    rss = sorted(peak.values())
try:
    r = json.load(open(os.path.join(d, "r.json")))
except (OSError, ValueError):
    print(f"{name}: no report (wall {wall} s; stopped or failed), peak RSS MiB per rank {rss}")
    sys.exit(0)
m = r["metrics"]
passes = ", ".join(f'{p["pass"]} {p["steps"]} steps {p["seconds"]:.0f}s' for p in r["passes"])
print(f'{name}: {m["particles"]} spheres, packing {m["packing_fraction"]:.4f}, largest overlap '
      f'{100 * m["max_overlap"]:.3f}% r, inside {100 * m["contained_share"]:.2f}%, penetration '
      f'{100 * m["max_penetration"]:.2f}% r; wall {wall} s (fill {r["seconds"]:.0f} s: {passes}); '
      f'peak RSS MiB per rank {rss}')
PY
}

# one NAME NP ARGS...: a timed fill (NP 0: without mpirun)
one() {
  local name=$1 np=$2
  shift 2
  local d="$work/$name"
  mkdir -p "$d"
  echo "-- $name: $(uptime | sed 's/.*load/load/')"
  local t0 t1
  t0=$(date +%s.%N)
  # Every rank's peak RSS (VmHWM) sampled: a run stopped by LIMIT writes no time file.
  ( while sleep 5; do
      for pid in $(pgrep -x "$(basename "$pfill" | cut -c1-15)"); do
        echo "$pid $(awk '/VmHWM/ {print $2}' /proc/"$pid"/status 2> /dev/null)"
      done
    done > "$d/hwm" ) &
  local sampler=$!
  if [ "$np" = 0 ]; then
    timeout "$limit" /usr/bin/time -f "%e %M" -o "$d/time.0" "$pfill" fill "$mesh" -n "$n" --seed "$seed" \
      -o "$d/out.csv" --report "$d/r.json" "$@" > "$d/stdout" 2> "$d/stderr"
  else
    timeout "$limit" mpirun --oversubscribe -np "$np" bash -c \
      '/usr/bin/time -f "%e %M" -o "$0/time.$OMPI_COMM_WORLD_RANK" "$@"' "$d" \
      "$pfill" fill "$mesh" -n "$n" --seed "$seed" -o "$d/$lammps_out" --report "$d/r.json" --engine lammps "$@" \
      > "$d/stdout" 2> "$d/stderr"
  fi
  local rc=$?
  t1=$(date +%s.%N)
  kill "$sampler" 2> /dev/null; wait "$sampler" 2> /dev/null
  # stopped (timeout: 124) or failed: the last progress line says how far it got
  [ $rc -eq 0 ] || { echo "   exit $rc; last progress: $(tr '\r' '\n' < "$d/stderr" | grep -v '^$' | tail -2 | tr '\n' ' ')"; }
  summary "$name" "$d" "$(python3 -c "print(round($t1 - $t0, 1))")"
}

echo "bench_lammps_scale: $mesh -n $n --seed $seed, $(nproc) cores, pfill $pfill"
for e in $engines; do
  if [ "$e" = opencl ]; then
    one opencl 0
  else
    for np in $nps; do one "lammps-np$np" "$np"; done
  fi
done
echo "-- end: $(uptime | sed 's/.*load/load/')"
