#!/usr/bin/env bash
# The rate over a long run: does it fall as the bed mixes? The quick-start drum (periodic
# lattice, Rapaport's law) lengthened to hold about PARTICLES particles, run ROTATIONS
# rotations on 1 rank with a thermo line every rotation, twice side by side (one process per
# core, so that both see the same machine): with the spatial sort at its default and with
# `run.sort_every = 0` (the order of the ids). Prints the rate of every rotation (the
# thermo's PSteps/s: particle-steps per second since the line before) and, per run, the
# first rotation's rate, the median of the last five and their ratio.
#   benches/decay.sh [PARTICLES] [ROTATIONS]
# Defaults: 100000 particles, 30 rotations (about 30 minutes on a 2-core machine).
# TUMBLER=path/to/tumbler measures another binary; DECAY_WORK keeps the logs there.
set -euo pipefail
particles="${1:-100000}"
rotations="${2:-30}"
work_dir="${DECAY_WORK:-}"
source "$(dirname "$0")/quickstart_bed.sh"
args=(--set drum.length="$length" --set run.rotations="$rotations" --set output.thermo_every=1.0
  --set output.progress_every=100.0 --set output.sample_every=1.0)
echo "$particles particles, $rotations rotations, sorted and not, side by side (logs in $work)" >&2
"$bin" run "$case_file" "${args[@]}" -o sorted.h5 --overwrite >sorted.log 2>&1 &
a=$!
"$bin" run "$case_file" "${args[@]}" --set run.sort_every=0 -o unsorted.h5 --overwrite \
  >unsorted.log 2>&1 &
b=$!
wait "$a" || { cat sorted.log >&2; exit 1; }
wait "$b" || { cat unsorted.log >&2; exit 1; }
# the thermo lines: step, rotations, ... PSteps/s last (nan on the first line)
# (lines every rotation; the run's last line, a few steps after the last of them, is left out)
rates() {
  awk '$1 ~ /^[0-9]+$/ && NF >= 10 && tolower($NF) != "nan" && $2 > last + 0.5 { print $2, $NF; last = $2 }' "$1"
}
echo "| rotation | sorted (default) | order of the ids (sort_every = 0) |"
echo "|---|---|---|"
paste <(rates sorted.log) <(rates unsorted.log) | awk '{ printf "| %.0f | %.3f | %.3f |\n", $1, $2 / 1e6, $4 / 1e6 }'
summary() {
  rates "$1" | awk '{ r[NR] = $2 } END {
    n = NR; k = (n >= 5 ? 5 : n); for (i = 1; i <= k; i++) t[i] = r[n - i + 1]
    for (i = 2; i <= k; i++) for (j = i; j > 1 && t[j - 1] > t[j]; j--) { x = t[j]; t[j] = t[j - 1]; t[j - 1] = x }
    m = (k % 2 ? t[(k + 1) / 2] : (t[k / 2] + t[k / 2 + 1]) / 2)
    printf "first rotation %.3f M, median of the last %d %.3f M: %.1f %% of the first\n", r[1] / 1e6, k, m / 1e6, 100 * m / r[1] }'
}
echo "sorted:              $(summary sorted.log)"
echo "order of the ids:    $(summary unsorted.log)"
