#!/usr/bin/env bash
# Installs the Debian packages wiresketch builds and tests with, only those
# that are missing (as root, non-interactive). Nothing else is downloaded.
set -euo pipefail
packages="build-essential pkg-config libopenblas-dev libpng-dev zlib1g-dev libcjson-dev libgif-dev python3"
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
