#!/usr/bin/env bash
# Memory locality: what the mixing of a bed costs the rate, with and without the spatial sort
# (`run.sort_every`, engine::order).
#
# 1. A bed: the quick-start drum (periodic lattice, Rapaport's law) lengthened to hold about
#    PARTICLES particles, run LOCALITY_SETTLE rotations (default 0.3) on RANKS ranks -> bed.h5.
#    Its ids are still close to the lattice's order: particles with near ids are near.
# 2. The same bed with its ids randomly permuted (`tumbler export --lammps`, the ids of the
#    data file shuffled by awk with a fixed seed, `tumbler import`) -> random.h5: the most
#    that mixing can do to the order of the ids.
# 3. REPS rounds, alternating: each bed with the sort at its default and with
#    `run.sort_every = 0` (the order of the ids), LOCALITY_STEPS steps each (default 2000)
#    from the bed (`init.kind = "particles"`). Prints every run's rate and the medians.
#   benches/locality.sh [PARTICLES] [RANKS] [REPS]
# Defaults: 100000 particles, 1 rank, 3 rounds. TUMBLER=path/to/tumbler measures another
# binary; LOCALITY_WORK keeps the beds and logs in that directory (default: a temporary one).
set -euo pipefail
particles="${1:-100000}"
ranks="${2:-1}"
reps="${3:-3}"
steps="${LOCALITY_STEPS:-2000}"
settle="${LOCALITY_SETTLE:-0.3}"
work_dir="${LOCALITY_WORK:-}"
source "$(dirname "$0")/quickstart_bed.sh"
# 2513.3 steps per rotation
base=(--set drum.length="$length" --set output.progress_every=10.0)

echo "bed: $particles particles, $settle rotations on $ranks ranks (log $work/bed.log)" >&2
mpirun --oversubscribe -np "$ranks" "$bin" run "$case_file" "${base[@]}" \
  --set run.rotations="$settle" -o bed.h5 --overwrite >bed.log 2>&1 || {
  cat bed.log >&2
  exit 1
}
"$bin" export bed.h5 --lammps bed.data >export.log 2>&1
# Shuffle the ids: a seeded random permutation of 1..N applied to the Atoms and Velocities
# sections (the first column of each).
awk 'BEGIN { srand(7) }
  /^ *[0-9]+ atoms/ { n = $1; for (i = 1; i <= n; i++) p[i] = i
    for (i = n; i > 1; i--) { j = int(rand() * i) + 1; t = p[i]; p[i] = p[j]; p[j] = t } }
  /^(Atoms|Velocities)/ { sec = 1; print; next }
  /^[A-Z]/ { sec = 0 }
  sec && NF > 1 { $1 = p[$1] }
  { print }' bed.data >random.data
"$bin" import random.data --lammps data -o random.h5 >import.log 2>&1

rate() { sed -n 's/^done: .* \([0-9.]*\) M particle-steps\/s on .*/\1/p' "$1" | tail -1; }
rotations=$(awk -v s="$steps" 'BEGIN { printf "%.10f", (s + 0.5) / 2513.2741228718345 }')
declare -A rates
for r in $(seq 1 "$reps"); do
  for bed in bed random; do
    for sort in default 0; do
      set_sort=()
      [ "$sort" = 0 ] && set_sort=(--set run.sort_every=0)
      log="$bed-$sort-$r.log"
      mpirun --oversubscribe -np "$ranks" "$bin" run "$case_file" "${base[@]}" \
        --set 'init.kind="particles"' --set "init.file=\"$work/$bed.h5\"" \
        --set run.rotations="$rotations" "${set_sort[@]}" -o "run-$bed-$sort.h5" \
        --overwrite >"$log" 2>&1 || {
        cat "$log" >&2
        exit 1
      }
      rates[$bed.$sort]="${rates[$bed.$sort]:-} $(rate "$log")"
      echo "round $r: ids $bed, sort_every $sort: $(rate "$log") M particle-steps/s" >&2
    done
  done
done
median() { tr ' ' '\n' | grep . | sort -g | awk '{ a[NR] = $1 } END { print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2) }'; }
echo "| ids | run.sort_every | M particle-steps/s ($reps runs) | median |"
echo "|---|---|---|---|"
for bed in bed random; do
  for sort in default 0; do
    label=$([ "$bed" = bed ] && echo "as the bed has them" || echo "randomly permuted")
    echo "| $label | $sort | ${rates[$bed.$sort]# } | $(echo "${rates[$bed.$sort]}" | median) |"
  done
done
