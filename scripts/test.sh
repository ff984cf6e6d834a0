#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (CTest), the way CI does: first the
# release build, then the same tests under AddressSanitizer + UndefinedBehaviorSanitizer,
# then the serving half (daemon, sources, clients: label `server`) under ThreadSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"

echo "== the same tests under ASan + UBSan =="
# Sanitizer trees: -g1 (function names and lines, no variable info) keeps them quick to build.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DOMNIVIEW_SANITIZE=ON \
  -DOMNIVIEW_BUILD_TESTS=ON -DOMNIVIEW_BUILD_BENCH=OFF > /dev/null
cmake --build build-asan -j "$(nproc)"
# Tests whose premise is a rate the sanitizers' slowdown cannot reach (a recording client
# outrun by a 30 Hz source): they run in the release build above.
timing_bound="Recording.AClientFarBehindSkipsAndSaysHowMany"
# Three golden sweeps repeat, at 3x3 supersampling, map code that the other golden and map
# tests already run under ASan; their ray casting alone would take minutes here.
OMNIVIEW_TEST_TIME_SCALE=2 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp" UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" \
  -E "GoldenDualFisheye.GreyAndMixedInputs|GoldenModels.PerspectiveThroughEachModel|GoldenDualFisheye.NaiveBackToBackStitch|$timing_bound"

echo "== the serving half under ThreadSanitizer =="
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DOMNIVIEW_TSAN=ON \
  -DOMNIVIEW_BUILD_TESTS=ON -DOMNIVIEW_BUILD_BENCH=OFF > /dev/null
cmake --build build-tsan -j "$(nproc)" --target omniviewd omniview views_api_test streaming_test auth_test \
  lifecycle_test clients_test rate_average_test pipeline_queues_test images_source_test replay_source_test recording_test cli_client_test client_cli_test \
  overlay_test spot-mock spot_mock_test spot_daemon_test request_bounds_test
OMNIVIEW_THREADS=1 OMNIVIEW_TEST_TIME_SCALE=3 TSAN_OPTIONS="suppressions=$PWD/tests/tsan.supp halt_on_error=1 second_deadlock_stack=1" \
  ctest --test-dir build-tsan -L server --output-on-failure -j "$(nproc)" -E "$timing_bound"
