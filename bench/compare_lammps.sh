#!/usr/bin/env bash
# compare_lammps: the same Lennard-Jones systems in LAMMPS (Debian's `lammps`,
# 2 MPI processes, its fastest CPU style here: -sf opt, i.e. lj/cut/opt) and
# in pfill's engine (bench_step, on PFILL_DEVICE), one after the other on the
# same cores; prints both rates and their ratio.
#   N = 1e5, rc = 2.5 sigma and purely repulsive: particle-steps per second.
#   N = 4000, purely repulsive, thermo output every step: steps per second.
# Same density (reduced 0.81: packing 0.6 of spheres of diameter 2^(1/6)
# sigma), fcc start, dt = 0.005 tau. Each program uses its own default
# neighbour skin: LAMMPS 0.3 sigma (0.5 was no faster there), pfill its
# automatic one (0.5 sigma on CPUs, with inner lists of 0.07 at rc 2.5).
# Differences: LAMMPS runs a periodic box, pfill a walled box (its wall
# costs are in).
#
# With ROUNDS > 1 each case alternates the two programs ROUNDS times and
# prints the medians: the rates', and the ratios' of each round's pair
# (this machine's speed swings by 20-30% within minutes).
#
#   bench/compare_lammps.sh [BUILD_DIR [ROUNDS]]     (defaults: build, 1)
set -euo pipefail
build=${1:-build}
rounds=${2:-1}
bench="$build/bench/bench_step"
command -v lmp >/dev/null || { echo "compare_lammps: lmp not found; apt-get install lammps"; exit 1; }
[ -x "$bench" ] || { echo "compare_lammps: $bench not found; build first (scripts/build.sh)"; exit 1; }
procs=${PFILL_LAMMPS_PROCS:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# lammps_rate CELLS CUTOFF STEPS THERMO -> prints "atoms steps/s cpu-seconds/step"
lammps_rate() {
  local cells=$1 cutoff=$2 steps=$3 thermo=$4
  cat > "$work/in.lj" <<IN
units lj
atom_style atomic
lattice fcc 0.81
region box block 0 $cells 0 $cells 0 $cells
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 0.1 87287 loop geom
pair_style lj/cut $cutoff
pair_coeff 1 1 1.0 1.0
pair_modify shift yes
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
fix 1 all nve
timestep 0.005
thermo $thermo
run 20
run $steps
IN
  mpirun --allow-run-as-root --oversubscribe -np "$procs" lmp -sf opt -in "$work/in.lj" -log none -screen "$work/out.txt" >/dev/null 2>&1
  # The last "Loop time of T on P procs for S steps with N atoms" and the
  # "C% CPU use with P MPI tasks" after it are the timed run's.
  local loop cpu
  loop=$(grep "^Loop time" "$work/out.txt" | tail -1)
  cpu=$(grep "% CPU use with" "$work/out.txt" | tail -1 | sed 's/%.*//')
  echo "$loop" | awk -v cpu="$cpu" '{print $12, $9 / $4, $4 * $6 * cpu / 100 / $9}'
}

# pfill_rate N CUTOFF_LABEL -> "steps/s cpu-seconds/step" from bench_step's text line
pfill_rate() {
  "$bench" --only "$1" --cutoff "$([ "$2" = "2.5 sigma" ] && echo lj || echo repulsive)" | awk -v label="$2" '/^N=/ && index($0, label) && !index($0, "+b") {
    for (i = 1; i < NF; ++i) {
      if ($(i + 1) == "steps/s") rate = $i
      if ($(i + 1) == "cpu-us/step") cpu = $i / 1e6
    }
    print rate, cpu; exit }'
}

# row LABEL < lines "LAMMPS_RATE LAMMPS_CPU PFILL_RATE PFILL_CPU" (one a round): the
# median rates, the median wall ratio, and the median ratio of CPU time per
# step (steadier on a shared machine).
row() {
  awk -v name="$1" '
    function median(a, n,   i, j, t) {
      for (i = 2; i <= n; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
      return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
    }
    { ++n; lr[n] = $1; pr[n] = $3; w[n] = $3 / $1; c[n] = $2 / $4 }
    END { printf "%-34s %12.4g %12.4g %7.2f %11.2f\n", name, median(lr, n), median(pr, n), median(w, n), median(c, n) }'
}

printf "%-34s %12s %12s %7s %11s\n" "case" "LAMMPS" "pfill" "ratio" "cpu ratio"
for cutoff in 2.5 1.122462; do
  label=$([ "$cutoff" = 2.5 ] && echo "2.5 sigma" || echo "repulsive")
  for ((r = 0; r < rounds; ++r)); do
    read -r atoms lsteps lcpu < <(lammps_rate 29 "$cutoff" 200 1000)
    read -r psteps pcpu < <(pfill_rate 100000 "$label")
    # Per particle: LAMMPS has 4 * 29^3 atoms, pfill 1e5.
    awk -v a="$atoms" -v s="$lsteps" -v c="$lcpu" -v ps="$psteps" -v pc="$pcpu" 'BEGIN {
      print a * s, c / a, ps * 1e5, pc / 1e5 }'
  done | row "N=1e5 $label (particle-steps/s)"
done
for ((r = 0; r < rounds; ++r)); do
  read -r atoms lsteps lcpu < <(lammps_rate 10 1.122462 4000 1)
  read -r psteps pcpu < <(pfill_rate 4000 "repulsive")
  echo "$lsteps $lcpu $psteps $pcpu"
done | row "N=4000 repulsive (steps/s, thermo)"
echo "ratio: pfill / LAMMPS wall rates; cpu ratio: LAMMPS / pfill CPU time per particle-step (all processes or threads); medians of $rounds round(s)."
echo "(LAMMPS: $procs MPI processes, -sf opt; pfill $("$bench" --only 1 | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg))"
