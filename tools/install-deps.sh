#!/usr/bin/env bash
# Installs the Debian 12 packages popc needs to build, test and draw reports,
# if any is missing. Needs root (or sudo) only when something is missing.
set -euo pipefail
pkgs=(gcc meson ninja-build pkg-config libinih-dev libmodbus-dev libcmocka-dev
      gnuplot-nox socat parallel slurm-wlm munge python3)
pkgs+=("$@") # more for one caller: tools/run-tests.sh asks for clang
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "popc: installing ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
