#!/usr/bin/env bash
# Installs every Debian package cleanmap builds, tests and benchmarks with. Idempotent; run as root
# (or through sudo) on Debian 12.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq \
  build-essential cmake ninja-build pkg-config \
  libeigen3-dev libceres-dev libpcl-dev liboctomap-dev libnanoflann-dev libtbb-dev \
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev robin-map-dev python3-matplotlib \
  libgtest-dev libgmock-dev libbenchmark-dev \
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev libgeometry-msgs-dev \
  librcpputils-dev librcutils-dev libament-index-cpp-dev \
  clang libclang-rt-14-dev \
  > /dev/null
echo "install-deps: all packages present"
