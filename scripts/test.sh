#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (CTest), the way CI does: first the
# release build, then the same tests under AddressSanitizer + UndefinedBehaviorSanitizer,
# then the serving half (daemon, sources, clients: label `server`) under ThreadSanitizer.
# Each stage's time is printed at the end (also when a stage fails), so a slower stage is
# seen at once; ccache (scripts/install-deps.sh) keeps rebuilds of unchanged files cheap.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/stages.sh
source scripts/lib/test_costs.sh
jobs=$(nproc)

stage "install dependencies" bash scripts/install-deps.sh
command -v ccache > /dev/null && ccache --zero-stats > /dev/null  # counts for this run only
stage "release: build" bash scripts/build.sh
seed_test_costs build
stage "release: tests" ctest --test-dir build --output-on-failure -j "$jobs"

# Sanitizer trees: -g1 (function names and lines, no variable info) keeps them quick to
# build; no benchmarks, examples or other programs their tests do not run.
sanitizer_tree() {  # DIR FLAG
  cmake -S . -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -D"$2"=ON -DOMNIVIEW_BUILD_TESTS=ON -DOMNIVIEW_BUILD_BENCH=OFF > /dev/null
}

# Tests whose premise is a rate the sanitizers' slowdown cannot reach (a recording client
# outrun by a 30 Hz source): they run in the release build above.
timing_bound="Recording.AClientFarBehindSkipsAndSaysHowMany"
# The exposure tests start ~110 daemons to judge listen addresses: a single-threaded check
# at start-up, nothing for ThreadSanitizer to see: built here (CTest wants every server
# test program), run in the release and ASan trees.
not_threaded="Exposure\\."

echo "== the same tests under ASan + UBSan =="
stage "asan: configure" sanitizer_tree build-asan OMNIVIEW_SANITIZE
stage "asan: build" cmake --build build-asan -j "$jobs"
# Three golden sweeps repeat, at 3x3 supersampling, map code that the other golden and map
# tests already run under ASan; their ray casting alone would take minutes here.
seed_test_costs build-asan
stage "asan: tests" env OMNIVIEW_TEST_TIME_SCALE=2 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp" UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$jobs" \
  -E "GoldenDualFisheye.GreyAndMixedInputs|GoldenModels.PerspectiveThroughEachModel|GoldenDualFisheye.NaiveBackToBackStitch|$timing_bound"

echo "== the serving half under ThreadSanitizer =="
# Only the programs the `server` tests run are built in this tree.
tsan_targets=(omniviewd omniview views_api_test streaming_test auth_test
  lifecycle_test clients_test rate_average_test pipeline_queues_test images_source_test replay_source_test
  recording_test cli_client_test client_cli_test overlay_test spot-mock spot_mock_test spot_daemon_test
  insta360_capture_test insta360_daemon_test operator_test
  request_bounds_test exposure_test cloud_api_test cloud_message_test)
stage "tsan: configure" sanitizer_tree build-tsan OMNIVIEW_TSAN
stage "tsan: build" cmake --build build-tsan -j "$jobs" --target "${tsan_targets[@]}"
seed_test_costs build-tsan
stage "tsan: tests" env OMNIVIEW_THREADS=1 OMNIVIEW_TEST_TIME_SCALE=3 \
  TSAN_OPTIONS="suppressions=$PWD/tests/tsan.supp halt_on_error=1 second_deadlock_stack=1" \
  ctest --test-dir build-tsan -L server --output-on-failure -j "$jobs" -E "$timing_bound|$not_threaded"
