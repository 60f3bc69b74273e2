# Sourced by the benchmarks that run the quick-start drum lengthened to a number of particles
# (benches/locality.sh, benches/decay.sh). Needs `particles` and `work_dir` (a directory to
# keep, or empty for a temporary one) set; sets `here`, `bin`, `case_file`, `length` (the
# drum length that holds about `particles`) and `work`, and enters `work`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${TUMBLER:-$here/target/release/tumbler}"
case_file="$here/cases/quickstart.toml"
[ -x "$bin" ] || cargo build --release --manifest-path "$here/Cargo.toml"
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1
if [ -n "$work_dir" ]; then
  work="$work_dir"
  mkdir -p "$work"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
cd "$work"
# the quick-start bed holds 2314 particles in 64 length units
length=$(awk -v n="$particles" 'BEGIN { printf "%.1f", 64.0 * n / 2314.0 }')
