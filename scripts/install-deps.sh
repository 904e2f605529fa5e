#!/usr/bin/env bash
# Installs the Debian bookworm packages icrkit builds against. Idempotent:
# it only calls apt-get (and only runs `apt-get update`) when a package is missing.
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  libeigen3-dev
  libmrpt-obs-dev libmrpt-maps-dev libmrpt-slam-dev libmrpt-poses-dev
  libopencv-dev
  libembree-dev
  liboctomap-dev
  libqhull-dev
  libsuitesparse-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  liblzf-dev libcli11-dev nlohmann-json3-dev libnanoflann-dev libtbb-dev libfmt-dev libspdlog-dev
  # MRPT's sample datasets: the reader test loads its tests_rgbd.rawlog.
  mrpt-common
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "icrkit: missing Debian packages: ${missing[*]}" >&2
  echo "icrkit: run this script as root (or install them with apt-get) and retry" >&2
  exit 2
fi

echo "icrkit: installing ${#missing[@]} Debian package(s): ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
