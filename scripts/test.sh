#!/usr/bin/env bash
# Configures, builds and runs the whole test suite. CI runs exactly this (with CI=true, which
# also turns warnings into errors).
set -euo pipefail
cd "$(dirname "$0")/.."
werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCLEANMAP_WERROR=$werror > /dev/null
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)" --no-tests=error
