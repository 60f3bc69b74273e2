#!/usr/bin/env bash
# Throughput of tumbler in particle-steps per second on 1 and 2 ranks, alternating the runs,
# with medians over REPEATS runs, the 2-rank/1-rank parallel efficiency and the per-phase
# times of the last run.
#   benches/throughput.sh [CASE] [ROTATIONS] [REPEATS]
# Defaults: cases/rapaport2002-A.toml, 6 rotations, 3 repeats.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
case_file="${1:-$here/cases/rapaport2002-A.toml}"
rotations="${2:-6}"
repeats="${3:-3}"
bin="$here/target/release/tumbler"
[ -x "$bin" ] || cargo build --release --manifest-path "$here/Cargo.toml"
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

declare -A rates
for r in $(seq "$repeats"); do
  for np in 1 2; do
    log="$work/np$np.$r.log"
    mpirun --oversubscribe -np "$np" "$bin" run "$case_file" --set run.rotations="$rotations" \
      -o "$work/out.h5" --overwrite >"$log" 2>&1
    rate=$(sed -n 's/.*done: .* \([0-9.]*\) M particle-steps\/s on.*/\1/p' "$log")
    rates[$np]="${rates[$np]:-} $rate"
    echo "run $r, $np rank(s): $rate M particle-steps/s"
  done
done

median() { tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
m1=$(echo "${rates[1]}" | median)
m2=$(echo "${rates[2]}" | median)
echo
echo "case: $case_file, $rotations rotations, $repeats alternating runs"
printf "| ranks | M particle-steps/s (median) | per rank | parallel efficiency |\n|---|---|---|---|\n"
printf "| 1 | %s | %s | 100%% |\n" "$m1" "$m1"
awk -v a="$m1" -v b="$m2" 'BEGIN { printf "| 2 | %s | %.3f | %.0f%% |\n", b, b/2, 100*b/(2*a) }'
echo
echo "per-phase times of the last 2-rank run:"
sed -n '/done: /,$p' "$work/np2.$repeats.log" | grep -E " s +[0-9.]+%$" | sed 's/^\[[^]]*\]//'
