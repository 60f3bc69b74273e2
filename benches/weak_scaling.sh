#!/usr/bin/env bash
# Weak scaling of memory and time: a long periodic lattice drum (the quick-start bed) with a
# fixed number of particles per rank, on 1, 2, 4 and 8 ranks (oversubscribed where there are
# fewer cores), 100 steps and the final checkpoint. Reports per run the particles, the peak
# resident memory of the smallest and largest rank and of rank 0 (GNU time around each
# rank), the time of the 100 steps and the rest (initial state, output and checkpoint).
#   benches/weak_scaling.sh [PARTICLES_PER_RANK] [RANK_COUNTS]
# Defaults: 100000 particles per rank, "1 2 4 8". TUMBLER_BIN: the binary to measure (default
# target/release/tumbler; a copy lets a build go on meanwhile).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
per_rank="${1:-100000}"
counts="${2:-1 2 4 8}"
bin="${TUMBLER_BIN:-$here/target/release/tumbler}"
case_file="$here/cases/quickstart.toml"
[ -x "$bin" ] || cargo build --release --manifest-path "$here/Cargo.toml"
[ -x /usr/bin/time ] || { echo "needs GNU time (apt-get install time)" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# the quick-start bed holds 2314 particles in 64 length units; 2513.3 steps per rotation
printf "| ranks | particles | peak RSS per rank, min / max (MiB) | rank 0 (MiB) | ghosts per rank, min / max | kB sent per step per rank, min / max | 100 steps (s) | init + output + checkpoint (s) |\n|---|---|---|---|---|---|---|---|\n"
for np in $counts; do
  length=$(awk -v n="$per_rank" -v p="$np" 'BEGIN { printf "%.1f", 64.0 * n * p / 2314.0 }')
  log="$work/np$np.log"
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$np" --output-filename "$work/rank$np" \
    /usr/bin/time -f "peak-rss-kib %M" "$bin" run "$case_file" \
    --set drum.length="$length" --set run.rotations=0.0398 --set output.sample_every=0.02 \
    --set output.progress_every=1.0 -o "$work/out$np.h5" >"$log" 2>&1
  end=$(date +%s.%N)
  total=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
  rss=$(cat "$work"/rank"$np"/1/rank.*/stderr | sed -n 's/^peak-rss-kib \([0-9]*\)/\1/p')
  rss0=$(sed -n 's/^peak-rss-kib \([0-9]*\)/\1/p' "$work/rank$np/1/rank.0/stderr")
  n=$(sed -n 's/.*: \([0-9]*\) particles on .*/\1/p' "$work/rank$np/1/rank.0/stderr" | head -1)
  steps=$(sed -n 's/.*done: [0-9]* steps in \([0-9.]*\) s.*/\1/p' "$work/rank$np/1/rank.0/stderr")
  ghosts=$(sed -n 's/.*particles (rough-wall ones included), \([0-9]*\) to \([0-9]*\) ghosts.*/\1 \/ \2/p' "$work/rank$np/1/rank.0/stderr")
  kb=$(sed -n 's/.* ghosts, \([0-9.]*\) to \([0-9.]*\) kB sent per step.*/\1 \/ \2/p' "$work/rank$np/1/rank.0/stderr")
  minmax=$(echo "$rss" | sort -n | awk 'NR==1 {lo=$1} {hi=$1} END { printf "%.0f / %.0f", lo/1024, hi/1024 }')
  rest=$(awk -v t="$total" -v s="$steps" 'BEGIN { printf "%.1f", t - s }')
  printf "| %s | %s | %s | %.0f | %s | %s | %s | %s |\n" "$np" "$n" "$minmax" "$(awk -v k="$rss0" 'BEGIN{print k/1024}')" "$ghosts" "$kb" "$steps" "$rest"
done
