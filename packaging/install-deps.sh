#!/usr/bin/env bash
# Installs every build, test and run dependency of Atelier from Debian's packages.
# Idempotent: packages already present are left alone; safe to run again.
set -euo pipefail

PACKAGES=(
  cmake g++ ninja-build pkg-config ccache git clang-format
  libeigen3-dev nlohmann-json3-dev libassimp-dev libcli11-dev zlib1g-dev
  qt6-base-dev libqt6opengl6-dev libepoxy-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  dpkg-dev python3-yaml slurm-wlm munge
  librsvg2-bin
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
