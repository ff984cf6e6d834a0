#!/usr/bin/env bash
# The main job on the built-in default: installs, builds, and renders every example view
# from the bundled dual-fisheye rig and its images into out/examples/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh omniview

example=config/examples/dual_fisheye
out=out/examples
views=(config/examples/views/*.yaml)
./build/cli/omniview render --rig "$example/rig.yaml" \
  --image front="$example/front.jpg" --image back="$example/back.jpg" \
  $(printf -- '--view %s ' "${views[@]}") --out "$out/"
echo
echo "Rendered ${#views[@]} views into $(pwd)/$out/"
