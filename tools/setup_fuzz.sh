#!/usr/bin/env bash
# Installs what `make fuzz` needs on top of tools/setup.sh, only what is
# missing (as root, non-interactive): clang with libFuzzer and the sanitizer
# runtimes, clang's OpenMP, and llvm-symbolizer for readable stack traces.
# Developers only: CI does not fuzz, so .ci/run does not call this.
set -euo pipefail
packages="clang libclang-rt-14-dev libomp-14-dev llvm-14"
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
