#!/usr/bin/env bash
# Coverage-guided fuzzing of every fuzz target (tests/fuzz) with libFuzzer, as a routine
# outside CI: builds the targets with clang (-DOMNIVIEW_FUZZ=ON, ASan + UBSan) into
# build-fuzz/, then runs each for SECONDS (default 60) from its seed corpus.
#
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]     (default: every target, e.g. urdf_fuzz)
#
# New inputs libFuzzer finds are kept in build-fuzz/corpus/TARGET (later runs go on from
# them; the seed corpus in tests/fuzz/corpus is never written). A crash, leak or UBSan
# report stops that target and leaves its input in build-fuzz/artifacts/; the script then
# ends non-zero, naming the targets that failed. Reproduce one with
#   build-fuzz/tests/fuzz/TARGET_libfuzzer build-fuzz/artifacts/TARGET-crash-...
# or, on any compiler, with the CTest replay binary (build/tests/fuzz/TARGET_replay FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: $0 [SECONDS per target] [TARGET...]" >&2; exit 2; }
shift $(($# > 0 ? 1 : 0))
only=("$@")

bash scripts/install-deps.sh
# libFuzzer comes with clang (its runtime is in libclang-rt-14-dev): fuzzing only, so not
# among the packages CI installs.
if ! command -v clang++ > /dev/null || ! compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" > /dev/null; then
  sudo_cmd=(); [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get install -y --no-install-recommends clang libclang-rt-14-dev
fi

CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DOMNIVIEW_FUZZ=ON -DOMNIVIEW_BUILD_TESTS=ON -DOMNIVIEW_BUILD_BENCH=OFF > /dev/null
# tests/fuzz/CMakeLists.txt lists "TARGET CORPUS_FOLDER" per target at configure time.
mapfile -t all_entries < build-fuzz/fuzz_targets.txt
entries=()
for entry in "${all_entries[@]}"; do
  if ((${#only[@]} == 0)) || [[ " ${only[*]} " == *" ${entry%% *} "* ]]; then entries+=("$entry"); fi
done
((${#entries[@]})) || { echo "no fuzz target named ${only[*]} (see build-fuzz/fuzz_targets.txt)" >&2; exit 2; }
targets=()
for entry in "${entries[@]}"; do targets+=("${entry%% *}_libfuzzer"); done
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"

mkdir -p build-fuzz/artifacts
failed=()
for entry in "${entries[@]}"; do
  name="${entry%% *}"
  seeds="${entry#* }"
  work="build-fuzz/corpus/$name"
  mkdir -p "$work"
  echo "== $name: ${seconds} s from $seeds =="
  # Leaks inside Debian's libraries that the targets cannot free are suppressed by frame
  # (tests/lsan.supp); the targets' own leaks are not.
  if ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp" \
     UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     "build-fuzz/tests/fuzz/${name}_libfuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 \
       -print_final_stats=1 -artifact_prefix="build-fuzz/artifacts/$name-" "$work" "$seeds" \
       > "build-fuzz/$name.log" 2>&1; then
    echo "   clean: $(grep -E '^stat::number_of_executed_units' "build-fuzz/$name.log" | awk '{print $2}') runs," \
         "$(find "$work" -type f | wc -l) inputs in its corpus"
  else
    echo "   FAILED: see build-fuzz/$name.log"; tail -n 30 "build-fuzz/$name.log"
    failed+=("$name")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz targets that failed: ${failed[*]}" >&2
  exit 1
fi
echo "all ${#entries[@]} fuzz targets ran clean for ${seconds} s each"
