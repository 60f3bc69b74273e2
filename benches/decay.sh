#!/usr/bin/env bash
# The rate over a long run: does it fall as the bed mixes? The quick-start drum (periodic
# lattice, Rapaport's law) lengthened to hold about PARTICLES particles, run ROTATIONS
# rotations on 1 rank with a thermo line every rotation, twice side by side (one process per
# core, so that both see the same machine): with the spatial sort at its default and with
# `run.sort_every = 0` (the order of the ids). Prints the rate of every rotation (the
# thermo's PSteps/s: particle-steps per second since the line before) and, per run, the
# first rotation's rate, the median of the last five and their ratio, and the same ratio
# against the median of rotations 2-6 (the bed settled; the first rotation starts from the lattice).
#   benches/decay.sh [PARTICLES] [ROTATIONS]
# DECAY_ALONE=1 runs the two one after the other (a quiet machine; twice as long).
# Defaults: 100000 particles, 30 rotations (about 30 minutes on a 2-core machine).
# TUMBLER=path/to/tumbler measures another binary; DECAY_WORK keeps the logs there.
set -euo pipefail
particles="${1:-100000}"
rotations="${2:-30}"
work_dir="${DECAY_WORK:-}"
source "$(dirname "$0")/quickstart_bed.sh"
args=(--set drum.length="$length" --set run.rotations="$rotations" --set output.thermo_every=1.0
  --set output.progress_every=100.0 --set output.sample_every=1.0)
alone="${DECAY_ALONE:-0}"
how="side by side"; [ "$alone" = 1 ] && how="one after the other"
echo "$particles particles, $rotations rotations, sorted and not, $how (logs in $work)" >&2
run_one() { # NAME [extra --set ...]: runs in the background; its pid in $!
  local name="$1"; shift
  "$bin" run "$case_file" "${args[@]}" "$@" -o "$name.h5" --overwrite >"$name.log" 2>&1 &
}
finish() { wait "$1" || { cat "$2.log" >&2; exit 1; }; }
run_one sorted
a=$!
[ "$alone" = 1 ] && finish "$a" sorted
run_one unsorted --set run.sort_every=0
b=$!
[ "$alone" = 1 ] || finish "$a" sorted
finish "$b" unsorted
# the thermo lines: step, rotations, ... PSteps/s last (nan on the first line)
# (lines every rotation; the run's last line, a few steps after the last of them, is left out)
rates() {
  awk '$1 ~ /^[0-9]+$/ && NF >= 10 && tolower($NF) != "nan" && $2 > last + 0.5 { print $2, $NF; last = $2 }' "$1"
}
echo "| rotation | sorted (default) | order of the ids (sort_every = 0) |"
echo "|---|---|---|"
paste <(rates sorted.log) <(rates unsorted.log) | awk '{ printf "| %.0f | %.3f | %.3f |\n", $1, $2 / 1e6, $4 / 1e6 }'
# The first rotation starts from the lattice, with no contacts at all (the bed settles
# during it), so it does less work per step than the rest: the settled start is the median of
# rotations 2-6, and the end is compared with both.
summary() {
  rates "$1" | awk '
    function median(a, b,    i, j, k, x, t) {   # median of r[a..b]
      k = 0; for (i = a; i <= b; i++) t[++k] = r[i]
      for (i = 2; i <= k; i++) for (j = i; j > 1 && t[j - 1] > t[j]; j--) { x = t[j]; t[j] = t[j - 1]; t[j - 1] = x }
      return (k % 2 ? t[(k + 1) / 2] : (t[k / 2] + t[k / 2 + 1]) / 2)
    }
    { r[NR] = $2 }
    END {
      n = NR; k = (n >= 5 ? 5 : n); m = median(n - k + 1, n)
      printf "first rotation %.3f M, median of the last %d %.3f M: %.1f %% of the first", r[1] / 1e6, k, m / 1e6, 100 * m / r[1]
      if (n >= 11) { s = median(2, 6); printf "; rotations 2-6 %.3f M: %.1f %% of the settled start", s / 1e6, 100 * m / s }
      printf "\n"
    }'
}
echo "sorted:              $(summary sorted.log)"
echo "order of the ids:    $(summary unsorted.log)"
