#!/usr/bin/env bash
# Memory per particle, measured against `tumbler check`'s estimate, on 1 and 2 ranks.
# Runs the quick-start bed (periodic lattice drum) lengthened to hold about PARTICLES
# particles, and a tiny one (the process's fixed cost: libraries, MPI, HDF5, the case's
# diagnostics), each for 100 steps with samples, the outputs and the final checkpoint,
# with GNU time around every rank. Prints per rank count: the peak RSS of every rank, the
# net bytes per particle ((sum of peak RSS - the tiny run's sum) / (particles - the tiny
# run's)), `tumbler check`'s estimate of the same ((its memory over the ranks for the run -
# for the tiny run) / (particles - the tiny run's): particles, lists, ghosts, a checkpoint's
# gather and the window sums) and the ratio estimate / measured.
#   benches/memory.sh [PARTICLES] [RANK_COUNTS] [-- extra --set arguments]
# Defaults: 100000 particles, "1 2". TUMBLER=path/to/tumbler measures another binary.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
particles="${1:-100000}"
counts="${2:-1 2}"
shift $(($# > 2 ? 2 : $#))
[ "${1:-}" = "--" ] && shift
extra=("$@")
bin="${TUMBLER:-$here/target/release/tumbler}"
case_file="$here/cases/quickstart.toml"
[ -x "$bin" ] || cargo build --release --manifest-path "$here/Cargo.toml"
[ -x /usr/bin/time ] || { echo "needs GNU time (apt-get install time)" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# the quick-start bed holds 2314 particles in 64 length units; 2513.3 steps per rotation
length_for() { awk -v n="$1" 'BEGIN { printf "%.1f", 64.0 * n / 2314.0 }'; }
big=$(length_for "$particles")
tiny=8.0 # about 290 particles: two slabs of 4 still fit the reach
args=(--set run.rotations=0.0398 --set output.sample_every=0.02 --set output.progress_every=1.0
  --set output.checkpoint_every=0.0398)

# run TAG LENGTH NP: sets rss_sum[TAG.NP] (KiB), rss_all[TAG.NP], count[TAG]
declare -A rss_sum rss_all count
run() {
  local tag="$1" length="$2" np="$3" dir="$work/$1-$3"
  mpirun --oversubscribe -np "$np" --output-filename "$dir" \
    /usr/bin/time -f "peak-rss-kib %M" "$bin" run "$case_file" --set drum.length="$length" \
    "${args[@]}" "${extra[@]}" -o "$dir.h5" >"$dir.log" 2>&1 || {
    cat "$dir.log" "$dir"/1/rank.*/stderr >&2
    exit 1
  }
  local rss
  rss=$(cat "$dir"/1/rank.*/stderr | sed -n 's/^peak-rss-kib \([0-9]*\)/\1/p')
  rss_sum[$tag.$np]=$(echo "$rss" | awk '{ s += $1 } END { print s }')
  rss_all[$tag.$np]=$(echo "$rss" | awk '{ printf "%s%.1f", (NR > 1 ? " + " : ""), $1 / 1024 }')
  count[$tag]=$(sed -n 's/.*: \([0-9]*\) particles on .*/\1/p' "$dir/1/rank.0/stderr" | head -1)
}

echo "| ranks | particles | peak RSS per rank (MiB) | tiny run: particles, peak RSS per rank (MiB) | net B/particle, measured | \`tumbler check\` estimate, B/particle | estimate / measured |"
echo "|---|---|---|---|---|---|---|"
for np in $counts; do
  run tiny "$tiny" "$np"
  run big "$big" "$np"
  estimate() { # LENGTH: check's MiB over the ranks
    "$bin" check "$case_file" --set drum.length="$1" "${args[@]}" "${extra[@]}" --ranks "$np" 2>/dev/null |
      sed -n 's/.* \([0-9.]*\) MiB over the ranks.*/\1/p'
  }
  awk -v np="$np" -v n="${count[big]}" -v s="${rss_sum[big.$np]}" -v all="${rss_all[big.$np]}" \
    -v ns="${count[tiny]}" -v s0="${rss_sum[tiny.$np]}" -v all0="${rss_all[tiny.$np]}" \
    -v e="$(estimate "$big")" -v e0="$(estimate "$tiny")" 'BEGIN {
      net = (s - s0) * 1024 / (n - ns)
      est = (e - e0) * 1048576 / (n - ns)
      printf "| %d | %d | %s | %d: %s | %.0f | %.0f | %.2f |\n", np, n, all, ns, all0, net, est, est / net }'
done
