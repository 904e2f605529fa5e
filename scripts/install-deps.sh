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
  # ROS 2 bags (MCAP): zstd- and lz4-compressed chunks.
  libzstd-dev liblz4-dev
  # MRPT's sample datasets: the reader test loads its tests_rgbd.rawlog.
  mrpt-common
  # The icrkit Python package (python/) and its tests, for the system python3.
  pybind11-dev python3-dev python3-numpy python3-pytest
  # ... and its examples (examples/python: a matplotlib plot, Open3D interop).
  python3-matplotlib python3-open3d
  # The independent grasp executor of the planner's test (tests/executor/, scipy's ConvexHull).
  python3-scipy
)
# `./run fuzz`: libFuzzer (clang and its runtime), only when asked for.
if [ "${ICRKIT_INSTALL_FUZZ:-0}" = "1" ]; then
  packages+=(clang-14 libclang-rt-14-dev)
fi

# Optional tools, keyed by the command they provide (a Node.js install from
# elsewhere already brings npm; Debian's package would conflict with it).
# Without them icrkit still builds and passes its tests:
#   npm       scripts/vendor-threejs.sh fetches three.js for the 3D viewer of
#             `icrkit report` (without it the report says the viewer is unavailable);
#             with node, tests/cli_bag.sh writes its ROS 2 bags with the npm
#             packages of tests/bags (`npm ci --prefix tests/bags`; skipped without them)
#   chromium  the headless-browser checks of tests/cli_report.sh (skipped
#             without it); set ICRKIT_INSTALL_BROWSER=0 to leave it out
#   slurmctld, munged (Debian slurm-wlm, munge)  tests/slurm_study.sh runs the
#             job scripts of docs/scaling.md (scripts/slurm/) on a single-node
#             Slurm it configures, starts and stops itself (skipped without
#             them; it uses none of the packages' system services); set
#             ICRKIT_INSTALL_SLURM=0 to leave them out
optional=()
command -v npm >/dev/null 2>&1 || optional+=(npm)
if [ "${ICRKIT_INSTALL_BROWSER:-1}" != "0" ] && ! command -v chromium >/dev/null 2>&1 &&
   ! command -v chromium-browser >/dev/null 2>&1; then
  optional+=(chromium)
fi
if [ "${ICRKIT_INSTALL_SLURM:-1}" != "0" ]; then  # sbin tools: not on a user's PATH
  command -v slurmctld >/dev/null 2>&1 || [ -x /usr/sbin/slurmctld ] || optional+=(slurm-wlm)
  command -v munged >/dev/null 2>&1 || [ -x /usr/sbin/munged ] || optional+=(munge)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  if [ ${#missing[@]} -gt 0 ]; then
    echo "icrkit: missing Debian packages: ${missing[*]}" >&2
    echo "icrkit: run this script as root (or install them with apt-get) and retry" >&2
    exit 2
  fi
  echo "icrkit: note: optional packages not installed (not root): ${optional[*]}" >&2
  exit 0
fi

export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
if [ ${#missing[@]} -gt 0 ]; then
  echo "icrkit: installing ${#missing[@]} Debian package(s): ${missing[*]}" >&2
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi
# One at a time, and never fatal: a missing optional tool only disables a feature or a test.
for p in "${optional[@]}"; do
  echo "icrkit: installing optional Debian package $p" >&2
  apt-get install -y -qq --no-install-recommends "$p" >&2 ||
    echo "icrkit: note: could not install $p; see the comment above 'optional=' in $0 for what that disables" >&2
done
