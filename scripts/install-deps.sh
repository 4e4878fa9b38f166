#!/usr/bin/env bash
# Installs every Debian package cleanmap builds, tests and benchmarks with. Idempotent; run as root
# (or through sudo) on Debian 12.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# linux-perf: the profiles behind bench/PROFILE.md. pybind11, numpy, pytest, Open3D: the Python
# module, its tests and examples (Debian's /usr/bin/python3, not a pyenv one first on PATH).
$SUDO apt-get install -y -qq \
  build-essential cmake ninja-build pkg-config \
  libeigen3-dev libceres-dev libpcl-dev liboctomap-dev libnanoflann-dev libtbb-dev \
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev robin-map-dev python3-matplotlib \
  libgtest-dev libgmock-dev libbenchmark-dev \
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev libgeometry-msgs-dev \
  librcpputils-dev librcutils-dev libament-index-cpp-dev \
  clang libclang-rt-14-dev linux-perf \
  libsqlite3-dev libzstd-dev liblz4-dev zlib1g-dev libpng-dev \
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-open3d \
  chromium \
  > /dev/null
# Node.js and npm come with this machine image (v20, npm 11); Debian's are the fallback (its npm
# package would clash with the image's Node.js).
if ! command -v npm > /dev/null; then $SUDO apt-get install -y -qq nodejs npm > /dev/null; fi
# The report's 3D view (three.js, bundled by esbuild) and its page check (playwright-core driving
# Debian's chromium, pngjs): versions pinned in apps/report/package-lock.json.
(cd "$(dirname "$0")/../apps/report" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error > /dev/null)
echo "install-deps: all packages present"
