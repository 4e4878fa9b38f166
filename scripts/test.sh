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
  # The suite's longest end-to-end runs are left to the Release suite above: under the
  # sanitizers (-O1) these eight took 1,050 s of the 2-core machine's time, about 9 minutes of
  # CI, and their code paths run under the sanitizers in the shorter end-to-end tests too
  # (the synthetic street online and offline, the depth demo, real KITTI, DynamicMap and
  # ROS 2 logs). SANITIZE_ALL=1 runs them as well.
  long='^(OfflineRun\.AStaticStreetLosesNothingOffline|Pipeline\.RealStreetRunsEndToEndAndFindsTheTraffic|'
  long+='DepthRun\.TheTableSceneIsCleanedWithGivenPosesAndWithOdometry|OfflineRun\.DynamicPointsLeaveTheOdometryMapWhileOdometryRuns|'
  long+='SyntheticStreet\.FastModeAgreesWithExactMode|SceneZoo\.ACarThatStopsForTwoSecondsStaysMoving|'
  long+='OfflineRun\.BothModesOnTheSyntheticStreetAndNothingLeftBehind|SceneZoo\.ATruckCrawlingBesideAMovingSensorIsFollowed)$'
  skip=()
  if [ "${SANITIZE_ALL:-}" != "1" ]; then skip=(-E "$long"); fi
  ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}" \
    ctest --test-dir build-asan --output-on-failure -j "$(nproc)" --no-tests=error "${skip[@]}"
  # A CI machine's disk can be nearly full (one run failed to link for want of space): its
  # sanitizer build (~1.3 GB) is thrown away once its tests pass, before the fuzz build.
  if [ "${CI:-}" = "true" ]; then rm -rf build-asan; fi
  bash scripts/fuzz.sh "${FUZZ_SECONDS:-10}"
fi
