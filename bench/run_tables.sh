#!/usr/bin/env bash
# Regenerates the speed table in bench/README.md (between the "speed-table" markers) from
# one run of map_bench and encode_bench: medians of 5 repetitions, each figure beside the
# anchor measured in the same run. Usage: bash bench/run_tables.sh [repetitions]
set -euo pipefail
cd "$(dirname "$0")/.."
reps="${1:-5}"
bash scripts/build.sh map_bench encode_bench
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
common=(--benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true --benchmark_format=json)
build/bench/map_bench "${common[@]}" > "$out/map.json"
build/bench/encode_bench "${common[@]}" > "$out/encode.json"
python3 bench/make_table.py "$out/map.json" "$out/encode.json" bench/README.md
