#!/usr/bin/env bash
# Install what is missing on a Debian machine, build tumbler, and run the quick case on two
# MPI ranks (writes quickstart.h5 and quickstart_spacetime.png in the current directory).
#   scripts/setup.sh            install + build + quick case
#   scripts/setup.sh --no-run   install + build only
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"

# HDF5 built with MPI-IO (every rank writes its rows of the O(N) datasets): installing it
# makes pkg-config's `hdf5` the MPI build (an alternative of higher priority than the serial
# libhdf5-dev, which may be installed too).
pkgs="libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libclang-dev pkg-config"
missing=""
for p in $pkgs; do
  dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
if [ -n "$missing" ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "installing:$missing"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >/dev/null
fi
if ! pkg-config --cflags hdf5 2>/dev/null | grep -q mpi; then
  echo "error: pkg-config's hdf5 is not the MPI build ($(pkg-config --cflags hdf5 2>&1));" \
    "select it with: update-alternatives --set hdf5.pc /usr/lib/x86_64-linux-gnu/pkgconfig/hdf5-openmpi.pc" >&2
  exit 1
fi
if ! command -v cargo >/dev/null 2>&1; then
  echo "error: cargo not found; install Rust (https://rustup.rs) and run this again" >&2
  exit 1
fi

cargo build --release --manifest-path "$here/Cargo.toml"
[ "${1:-}" = "--no-run" ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
mpirun --oversubscribe -np 2 "$here/target/release/tumbler" run "$here/cases/quickstart.toml" \
  -o quickstart.h5 --overwrite
