#!/usr/bin/env bash
# Regenerates the speed table in bench/README.md (between the "speed-table" markers) from
# one run of map_bench (2 threads, then 1) and encode_bench: medians of 5 repetitions, each figure beside the
# anchor measured in the same run. Usage: bash bench/run_tables.sh [repetitions]
set -euo pipefail
cd "$(dirname "$0")/.."
reps="${1:-5}"
bash scripts/build.sh map_bench encode_bench
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
common=(--benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true --benchmark_format=json)
# 2 threads, wall time (the issue's setting); then 1 thread, whose CPU time is the whole
# work and moves less when other processes share the machine.
build/bench/map_bench "${common[@]}" > "$out/map.json"
OMNIVIEW_BENCH_THREADS=1 build/bench/map_bench "${common[@]}" > "$out/map1.json"
build/bench/encode_bench "${common[@]}" > "$out/encode.json"
python3 bench/make_table.py "$out/map.json" "$out/encode.json" "$out/map1.json" bench/README.md
