#!/usr/bin/env bash
# The main job on the built-in default: installs, builds, starts omniviewd with
# config/omniviewd.yaml (the bundled dual-fisheye example rig and images played as a live
# camera), drives it with the `omniview` CLI the way an operator would — status, cameras,
# snapshots of the configured views, a virtual pan-tilt-zoom camera, a short stream — writes
# everything into out/demo/, and leaves the daemon running for you to watch until Ctrl-C.
#
#   bash scripts/demo.sh           # ... and keep serving on 127.0.0.1:50051
#   bash scripts/demo.sh --exit    # ... and stop the daemon at the end (scripts, CI)
set -euo pipefail
cd "$(dirname "$0")/.."
keep_serving=1
case "${1:-}" in
  --exit) keep_serving=0 ;;
  "") ;;
  *) echo "usage: bash scripts/demo.sh [--exit]" >&2; exit 2 ;;
esac

bash scripts/install-deps.sh
bash scripts/build.sh omniview omniviewd

omniviewd=./build/server/daemon/omniviewd
omniview=./build/cli/omniview
out=out/demo
rm -rf "$out"
mkdir -p "$out"

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }

step "starting omniviewd --config config/omniviewd.yaml (log: $out/omniviewd.log)"
"$omniviewd" --config config/omniviewd.yaml --ready-file "$out/omniviewd.ready" > "$out/omniviewd.log" 2>&1 &
daemon=$!
stop_daemon() {
  if kill -0 "$daemon" 2> /dev/null; then
    kill -TERM "$daemon" 2> /dev/null || true
    wait "$daemon" 2> /dev/null || true
  fi
}
trap stop_daemon EXIT
for _ in $(seq 300); do
  [ -s "$out/omniviewd.ready" ] && break
  if ! kill -0 "$daemon" 2> /dev/null; then
    echo "omniviewd did not start:" >&2
    cat "$out/omniviewd.log" >&2
    exit 1
  fi
  sleep 0.1
done
[ -s "$out/omniviewd.ready" ] || { echo "omniviewd did not get ready within 30 s" >&2; cat "$out/omniviewd.log" >&2; exit 1; }
echo "listening on $(cat "$out/omniviewd.ready")"

step "omniview status"
"$omniview" status
step "omniview cameras"
"$omniview" cameras

step "snapshots of the configured views"
for view in front birdseye panorama; do
  "$omniview" snapshot "$view" -o "$out/$view.jpg"
done

step "a virtual pan-tilt-zoom camera: create it, then point it"
"$omniview" views create --set name=ptz --set type=perspective --set width=640 --set height=480 \
  --set frame=base_link --set position=0,0,1 --set hfov_deg=90
"$omniview" snapshot ptz -o "$out/ptz_ahead.jpg"
"$omniview" ptz ptz --pan 120 --tilt 15 --zoom 2
"$omniview" snapshot ptz -o "$out/ptz_left_back_zoomed.jpg"
"$omniview" ptz ptz --relative --pan 90
"$omniview" snapshot ptz -o "$out/ptz_panned_further.jpg"

step "20 frames of the front view, with their latencies"
"$omniview" stream front --frames 20 -o "$out/front_stream"
echo "frame index: $out/front_stream/frames.csv"

step "done"
echo "Everything above is in $(pwd)/$out/"
if [ "$keep_serving" = 0 ]; then exit 0; fi
cat << EOF

omniviewd keeps serving on 127.0.0.1:50051 until you press Ctrl-C. In another terminal:
  $omniview watch front                 # live frame rate, latency and drops
  $omniview ptz ptz --dpan 10           # pan the virtual camera 10 degrees left
  $omniview views get panorama          # a view as YAML: edit it, then 'views update --file'
  $omniview --help                      # every command
EOF
trap 'stop_daemon; echo; echo "omniviewd stopped."; exit 0' INT TERM
wait "$daemon"
