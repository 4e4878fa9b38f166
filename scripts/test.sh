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

# CI (CI=true), or SANITIZE=1: the whole suite again, built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan; any report fails its test), then every fuzz target
# for a bounded smoke run (FUZZ_SECONDS each, default 10; `bash scripts/fuzz.sh 600` runs long).
if [ "${CI:-}" = "true" ] || [ "${SANITIZE:-}" = "1" ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DCLEANMAP_SANITIZE=ON \
    -DCLEANMAP_BUILD_BENCH=OFF -DCLEANMAP_PYTHON=OFF -DCLEANMAP_WERROR=$werror > /dev/null
  cmake --build build-asan -j "$(nproc)"
  ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}" \
    ctest --test-dir build-asan --output-on-failure -j "$(nproc)" --no-tests=error
  # A CI machine's disk can be nearly full (one run failed to link for want of space): its
  # sanitizer build (~1.3 GB) is thrown away once its tests pass, before the fuzz build.
  if [ "${CI:-}" = "true" ]; then rm -rf build-asan; fi
  bash scripts/fuzz.sh "${FUZZ_SECONDS:-10}"
fi
