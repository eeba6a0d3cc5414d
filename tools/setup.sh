#!/usr/bin/env bash
# Installs the Debian packages wiresketch builds and tests with, only those
# that are missing (as root, non-interactive). Nothing else is downloaded.
# `tools/setup.sh fuzz` adds what `make fuzz` needs (clang with libFuzzer and
# the sanitizer runtimes, clang's OpenMP, llvm-symbolizer); CI does not fuzz.
# `tools/setup.sh mpi` adds Open MPI for `make MPI=1` and `make test-mpi`.
set -euo pipefail
packages="build-essential pkg-config libopenblas-dev libpng-dev zlib1g-dev libcjson-dev libgif-dev libjpeg62-turbo-dev python3"
if [ "${1:-}" = fuzz ]; then
    packages="$packages clang libclang-rt-14-dev libomp-14-dev llvm-14"
fi
if [ "${1:-}" = mpi ]; then
    packages="$packages openmpi-bin libopenmpi-dev"
fi
missing=""
for p in $packages; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "installing:$missing"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends $missing
