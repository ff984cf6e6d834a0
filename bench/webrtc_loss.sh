#!/usr/bin/env bash
# The console's picture over a lossy link, WebRTC against H.264 over the WebSocket, in the
# same run: two network namespaces joined by a veth pair, random packet loss on it both
# ways (iptables' `statistic` match: this kind of kernel may lack netem), spot-mock and
# omniviewd in one, headless Chromium with the console in the other. For each path and
# loss (0 %, 1 %, 3 %), over SECONDS (default 60) each: capture-to-display latency (median,
# p95), pictures shown per second, freezes. Prints a Markdown table (bench/README.md has
# one). Needs root (namespaces, iptables) and a build (bash scripts/build.sh).
#
#   sudo bash bench/webrtc_loss.sh [SECONDS] [LOSSES]     e.g.  bash bench/webrtc_loss.sh 60 "0 1 3"
#
# The namespaces, their processes and rules go however the script ends.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
losses=${2:-"0 1 3"}
[ "$(id -u)" -eq 0 ] || { echo "webrtc_loss.sh needs root (network namespaces, iptables): run it with sudo" >&2; exit 1; }
command -v iptables > /dev/null || { echo "webrtc_loss.sh needs iptables (apt-get install iptables)" >&2; exit 1; }
for p in build/daemon/omniviewd build/spot_adapter/mock/spot-mock; do
  [ -x "$p" ] || { echo "webrtc_loss.sh needs $p: run bash scripts/build.sh first" >&2; exit 1; }
done

# Named after this run (two runs side by side do not share, or delete, each other's).
robot=ovloss-robot-$$ operator=ovloss-operator-$$
work=""
remove_namespace() {
  if ip netns pids "$1" > /dev/null 2>&1; then
    ip netns pids "$1" | xargs -r kill 2> /dev/null || true
    sleep 0.5
    ip netns pids "$1" | xargs -r kill -9 2> /dev/null || true
    ip netns del "$1" 2> /dev/null || true
  fi
}
cleanup() {
  for ns in $robot $operator; do remove_namespace $ns; done
  [ -z "$work" ] || rm -rf "$work"
}
trap cleanup EXIT INT TERM
# Namespaces an earlier run left (killed hard: no trap ran) go first: those whose script
# no longer runs.
for ns in $(ip netns list 2> /dev/null | awk '/^ovloss-(robot|operator)-[0-9]+/ {print $1}'); do
  kill -0 "${ns##*-}" 2> /dev/null || remove_namespace "$ns"
done
work=$(mktemp -d /tmp/omniview_webrtc_loss.XXXXXX)

ip netns add $robot
ip netns add $operator
ip link add ovloss0 netns $robot type veth peer name ovloss1 netns $operator
ip -n $robot addr add 10.77.0.1/24 dev ovloss0
ip -n $operator addr add 10.77.0.2/24 dev ovloss1
for ns in $robot $operator; do
  ip -n $ns link set lo up
done
ip -n $robot link set ovloss0 up
ip -n $operator link set ovloss1 up

# The robot: spot-mock on its loopback, omniviewd serving the web port on the link.
ip netns exec $robot build/spot_adapter/mock/spot-mock --port 0 --certs "$work/certs" \
  --credentials "$work/credentials.yaml" --ready-file "$work/mock_ready" --scene room --supersample 1 \
  > "$work/spot_mock.log" 2>&1 &
for _ in $(seq 100); do [ -s "$work/mock_ready" ] && break; sleep 0.1; done
mock=$(cut -d' ' -f1 "$work/mock_ready")
cat > "$work/omniviewd.yaml" <<EOF
listen: 127.0.0.1:0
# A bench link between two namespaces of this machine: nobody else is on it.
allow_insecure_remote: true
web: {listen: "10.77.0.1:8765"}
sources:
  - name: spot
    type: spot
    robot: $mock
    ca_file: $work/certs/ca.pem
    credentials_file: $work/credentials.yaml
    cameras: [frontleft_fisheye_image, frontright_fisheye_image]
    rate_hz: 15
views:
  - {name: front, type: perspective, source: spot, width: 640, height: 320, frame: footprint,
     pose: {xyz: [0.42, 0, 0.52], ypr_deg: [0, 27, 0]}, hfov_deg: 115, distance: 3.0, ground: true}
EOF
ip netns exec $robot build/daemon/omniviewd --config "$work/omniviewd.yaml" --ready-file "$work/ready" \
  > "$work/omniviewd.log" 2>&1 &
for _ in $(seq 200); do [ -s "$work/ready" ] && break; sleep 0.1; done
[ -s "$work/ready" ] || { cat "$work/omniviewd.log" >&2; exit 1; }

drop() {  # PERCENT: random loss on the link, each way
  for ns in $robot $operator; do
    ip netns exec $ns iptables -F OUTPUT
    if [ "$1" != 0 ]; then
      ip netns exec $ns iptables -A OUTPUT -o "$([ $ns = $robot ] && echo ovloss0 || echo ovloss1)" \
        -m statistic --mode random --probability "$(awk "BEGIN { print $1 / 100 }")" -j DROP
    fi
  done
}

rows=()
for loss in $losses; do
  drop "$loss"
  for path in webrtc websocket; do
    echo "measuring $path at $loss % loss for $seconds s ..." >&2
    rows+=("$(ip netns exec $operator /usr/bin/python3 bench/webrtc_loss.py --url http://10.77.0.1:8765/ \
      --path $path --seconds "$seconds" --loss "$loss")")
  done
done
drop 0
echo
echo "| path | loss (each way) | median capture to display | p95 | pictures/s | freezes | frozen |"
echo "|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
