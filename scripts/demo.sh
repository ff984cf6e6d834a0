#!/usr/bin/env bash
# The main job on the built-in default, no robot needed: installs, builds, starts spot-mock
# (a simulated Spot speaking the robot's own gRPC API over TLS, with five body cameras
# looking at a synthetic room) and omniviewd with config/spot.yaml — the same config a real
# Spot takes, with its address and credentials — then drives the daemon with the `omniview`
# CLI the way an operator would: status, cameras, snapshots of the `front` and `birdseye`
# views, the bird's-eye on measured depth, a virtual pan-tilt-zoom camera, a short stream. Everything goes into out/demo/;
# both processes keep running for you to watch until Ctrl-C.
#
#   bash scripts/demo.sh           # ... and keep serving on 127.0.0.1:50051
#   bash scripts/demo.sh --exit    # ... and stop both at the end (scripts, CI)
set -euo pipefail
cd "$(dirname "$0")/.."
keep_serving=1
case "${1:-}" in
  --exit) keep_serving=0 ;;
  "") ;;
  *) echo "usage: bash scripts/demo.sh [--exit]" >&2; exit 2 ;;
esac

bash scripts/install-deps.sh
bash scripts/build.sh omniview omniviewd spot-mock

omniviewd=./build/daemon/omniviewd
omniview=./build/cli/omniview
spot_mock=./build/spot_adapter/mock/spot-mock
out=out/demo
robot=out/spot-mock   # the simulated robot's CA and login (config/spot.yaml points here)
rm -rf "$out"
mkdir -p "$out" "$robot"

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }

# However the script ends (done, an error, Ctrl-C at any point), both processes are
# stopped and, once they had served, that is said.
pids=()
served=0
stop_all() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2> /dev/null || true; done
  if [ "$served" = 1 ]; then echo "omniviewd and spot-mock stopped."; fi
  served=0
}
trap stop_all EXIT
trap 'echo; exit 130' INT TERM

# wait_ready NAME PID READY_FILE LOG: until the process has written its address.
wait_ready() {
  for _ in $(seq 300); do
    [ -s "$3" ] && { echo "$1 listening on $(head -n 1 "$3")"; return 0; }
    if ! kill -0 "$2" 2> /dev/null; then
      echo "$1 did not start:" >&2
      cat "$4" >&2
      exit 1
    fi
    sleep 0.1
  done
  echo "$1 did not get ready within 30 s" >&2
  cat "$4" >&2
  exit 1
}

step "starting spot-mock, a simulated Spot on 127.0.0.1:50443 (log: $out/spot-mock.log)"
"$spot_mock" --port 50443 --certs "$robot" --credentials "$robot/credentials.yaml" \
  --render-cache "$robot/render-cache" --ready-file "$out/spot-mock.ready" > "$out/spot-mock.log" 2>&1 &
pids+=($!)
wait_ready spot-mock "$!" "$out/spot-mock.ready" "$out/spot-mock.log"

step "starting omniviewd --config config/spot.yaml (log: $out/omniviewd.log)"
"$omniviewd" --config config/spot.yaml --ready-file "$out/omniviewd.ready" > "$out/omniviewd.log" 2>&1 &
pids+=($!)
wait_ready omniviewd "$!" "$out/omniviewd.ready" "$out/omniviewd.log"
served=1

# The daemon logs in to the robot and reads its cameras in the background.
for _ in $(seq 100); do
  grep -q "source 'spot': connected" "$out/omniviewd.log" && break
  sleep 0.1
done

step "omniview status"
"$omniview" status
step "omniview cameras (calibration and poses as the robot reports them)"
"$omniview" cameras

step "snapshots of the configured views"
for view in front birdseye; do
  "$omniview" snapshot "$view" -o "$out/$view.jpg"
done

step "a virtual pan-tilt-zoom camera on the robot's body: create it, then point it"
"$omniview" views create --set name=ptz --set type=perspective --set width=640 --set height=480 \
  --set frame=body --set position=0,0,0.1 --set hfov_deg=90 --set tilt=20
"$omniview" snapshot ptz -o "$out/ptz_ahead.jpg"
"$omniview" ptz ptz --pan 90 --zoom 1.5
"$omniview" snapshot ptz -o "$out/ptz_left_zoomed.jpg"
"$omniview" ptz ptz --relative --pan 90
"$omniview" snapshot ptz -o "$out/ptz_behind.jpg"

step "the bird's-eye view on what the robot measures (depth: measured: its lidar and depth cameras)"
"$omniview" views get birdseye > "$out/birdseye_measured.yaml"
"$omniview" views create --file "$out/birdseye_measured.yaml" --set name=birdseye_measured --set depth=measured
# Watched for two seconds: the geometry follows while someone watches; the last frame stands on it.
"$omniview" stream birdseye_measured --frames 30 -o "$out/birdseye_measured_stream" > /dev/null
cp "$(ls "$out"/birdseye_measured_stream/frame_*.jpg | tail -n 1)" "$out/birdseye_measured.jpg"
echo "$out/birdseye.jpg: on the ground; $out/birdseye_measured.jpg: on the lidar and depth cameras"

step "20 frames of the front view, with their latencies"
"$omniview" stream front --frames 20 -o "$out/front_stream"
echo "frame index: $out/front_stream/frames.csv"

step "an Insta360 Air's 360 deg panorama (config/insta360.yaml, playing its sample recording)"
"$omniviewd" --config config/insta360.yaml --listen 127.0.0.1:50052 --ready-file "$out/air.ready" \
  > "$out/omniviewd-air.log" 2>&1 &
air_pid=$!
pids+=($air_pid)
wait_ready "omniviewd (Air)" "$air_pid" "$out/air.ready" "$out/omniviewd-air.log"
"$omniview" snapshot panorama -o "$out/air_panorama.jpg" --server 127.0.0.1:50052
kill -TERM "$air_pid" && wait "$air_pid" 2> /dev/null || true

step "done"
echo "Everything above is in $(pwd)/$out/"
if [ "$keep_serving" = 0 ]; then exit 0; fi
cat << EOF

omniviewd keeps serving on 127.0.0.1:50051 (and spot-mock on 50443) until you press
Ctrl-C. Watch it in a browser: http://127.0.0.1:8765/?layout=split (the operator console,
over WebRTC where the browser can: drag to steer the front view, tap the bird's-eye to look
there), or connect Foxglove or Lichtblick to ws://127.0.0.1:8765. Any WHEP player watches a
view over WebRTC: http://127.0.0.1:8765/whep/VIEW (e.g. .../whep/front). In another terminal:
  $omniview watch birdseye              # live frame rate, latency and skipped frames
  $omniview ptz ptz --dpan 10           # pan the virtual camera 10 degrees left
  $omniview views get front             # a view as YAML: edit it, then 'views update --file'
  $omniview --help                      # every command
EOF
trap 'echo; exit 0' INT TERM  # Ctrl-C is how this ends: no error
wait
