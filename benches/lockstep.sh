#!/usr/bin/env bash
# The ceiling of parallel efficiency that this machine sets for a code in lock step: the
# same work per step on every rank, run free and then with one reduction per step, for
# several step lengths (examples/lockstep.rs). tumbler's steps on the bench bed of
# benches/peer.sh take about 850 µs on each of 2 ranks, LAMMPS' about 2,800 µs: their
# efficiencies can be no better than the ceiling at those lengths.
#   benches/lockstep.sh [RANKS] [STEP_US,...] [SECONDS] [REPS]
# Defaults: 2 ranks; 400,850,1700,2800,5600 µs; 8 s per run; 3 alternating repetitions
# (about 8 minutes).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
ranks="${1:-2}"
lengths="${2:-400,850,1700,2800,5600}"
seconds="${3:-8}"
reps="${4:-3}"
[[ "$ranks" =~ ^[1-9][0-9]*$ ]] || { echo "usage: benches/lockstep.sh [RANKS] [STEP_US,...] [SECONDS] [REPS]" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
(cd "$here" && cargo build --release --quiet --example lockstep)
echo "$(date -u '+%Y-%m-%d %H:%M UTC'); $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg) at the start"
mpirun --oversubscribe -np "$ranks" "$here/target/release/examples/lockstep" "$lengths" "$seconds" "$reps"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end"
