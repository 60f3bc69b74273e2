#!/usr/bin/env bash
# A 10-million-particle drum on 2 ranks: the quick-start bed (periodic lattice) lengthened,
# initial state, 100 steps and a checkpoint; then a restart from that checkpoint for 100
# more steps. Reports the peak resident memory of each rank in each run (GNU time).
#   benches/ten_million.sh [PARTICLES] [RANKS]      defaults: 10000000 2
# The per-slice window sums grow with the drum's length: the cross-section of the binned
# diagnostics is cut to 8 x 8 (the default 40 x 40 would need 28 GB on rank 0 here).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
n="${1:-10000000}"
np="${2:-2}"
bin="$here/target/release/tumbler"
[ -x "$bin" ] || cargo build --release --manifest-path "$here/Cargo.toml"
[ -x /usr/bin/time ] || { echo "needs GNU time (apt-get install time)" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# the quick-start bed holds 2314 particles in 64 length units; 2513.3 steps per rotation
length=$(awk -v n="$n" 'BEGIN { printf "%.1f", 64.0 * n / 2314.0 }')
common=(--set drum.length="$length" --set output.sample_every=0.02 --set output.progress_every=1.0
  --set 'diagnostics.fields.grid=[8,8,16]' --set output.checkpoint_every=0.0398)
run() {
  local tag="$1"
  shift
  local start end
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$np" --output-filename "$work/$tag" \
    /usr/bin/time -f "peak-rss-kib %M" "$bin" run "$here/cases/quickstart.toml" "${common[@]}" \
    -o "$work/big.h5" "$@" >"$work/$tag.log" 2>&1
  end=$(date +%s.%N)
  for r in $(seq 0 $((np - 1))); do
    kib=$(sed -n 's/^peak-rss-kib \([0-9]*\)/\1/p' "$work/$tag/1/rank.$r/stderr")
    printf "%s: rank %d peak RSS %.2f GiB\n" "$tag" "$r" "$(awk -v k="$kib" 'BEGIN { print k / 1048576 }')"
  done
  grep -h "done:" "$work/$tag/1/rank.0/stderr" | sed 's/.*done:/  done:/'
  awk -v a="$start" -v b="$end" -v t="$tag" 'BEGIN { printf "  %s: %.0f s in all\n", t, b - a }'
}
run start --set run.rotations=0.0398
ls -l "$work/big.ckpt.h5" | awk '{ printf "  checkpoint: %.2f GB\n", $5 / 1e9 }'
run restart --set run.rotations=0.0796 --restart "$work/big.ckpt.h5"
