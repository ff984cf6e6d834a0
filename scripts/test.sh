#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (CTest), the way CI does.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh -DOMNIVIEW_BUILD_TESTS=ON -DOMNIVIEW_BUILD_BENCH=ON
ctest --test-dir build --output-on-failure -j "$(nproc)"
