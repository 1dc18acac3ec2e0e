#!/usr/bin/env bash
# Installs the Debian 12 packages gapchain needs, only those missing. Idempotent and quiet when
# everything is present. Run as root (or with sudo available).
set -euo pipefail
packages=(g++ cmake make pkg-config libeigen3-dev libspectra-dev libfftw3-dev libgsl-dev
          nlohmann-json3-dev doctest-dev libcli11-dev gnuplot-nox libopenmpi-dev openmpi-bin
          pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib libboost-dev)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "gapchain: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
