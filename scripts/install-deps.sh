#!/usr/bin/env bash
# Installs the Debian 12 packages omniview builds and tests with (needs root or sudo).
# Skips apt entirely when everything is already there, so re-runs are instant.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libopencv-dev libyaml-cpp-dev
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc
  ccache mold libssl-dev openssl python3 python3-grpcio python3-protobuf
  libgtest-dev libgmock-dev libbenchmark-dev
  liburdfdom-dev liburdfdom-headers-dev libassimp-dev libosmesa6-dev
  libturbojpeg0-dev libjpeg62-turbo-dev libpng-dev  # JPEG and PNG (core/io/image_codec, server/pipeline): not OpenCV imgcodecs, whose GDAL & co. slow every start
  libx264-dev      # H.264 streams (server/video)
  libzstd-dev zlib1g-dev  # MCAP export (core/mcap): zstd chunks, CRC-32
  libavcodec-dev   # the video tests decode what the daemon sends (tests/video only)
  ffmpeg           # ffmpeg, ffprobe: the video tests read the CLI's H.264 pipe, RTSP and the Foxglove video channel as players do
  libgstrtspserver-1.0-dev libgstreamer-plugins-base1.0-dev  # RTSP (server/rtsp): the server library, appsrc
  gstreamer1.0-plugins-good gstreamer1.0-plugins-bad         # ... rtph264pay, h264parse
  libgstreamer-plugins-bad1.0-dev gstreamer1.0-nice  # WebRTC (server/webrtc): webrtcbin and its ICE (libnice)
  python3-aiortc  # tests/webrtc: an independent WebRTC stack (Python's aiortc, decoding with PyAV) as a WHEP viewer
  coturn          # tests/webrtc: a real TURN (and STUN) server the daemon relays its WebRTC media through
  iptables        # bench/webrtc_loss.sh: random packet loss between two network namespaces
  libboost-dev  # Boost.Beast and Asio (header-only): omniviewd's HTTP + WebSocket endpoint (server/web)
  nlohmann-json3-dev  # the web endpoint's client JSON (server/web/json)
  libjs-three   # three.js, served to the console's 3D cloud panel from /usr/share/javascript
  python3-websockets python3-selenium python3-yaml chromium chromium-driver  # tests/web
  xvfb xdotool  # omniview show's window, keys and mouse, tested on a virtual X display
  dpkg-dev systemd  # cpack -G DEB (dpkg-shlibdeps) and systemd-analyze verify: scripts/check-install.sh
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node and npm: tests/export reads exported MCAP files with Foxglove's own reader
# (@mcap/core, installed by the test into a cache). Any node >= 18 will do: Debian's
# nodejs + npm, or one already installed otherwise (NodeSource's bundles npm).
command -v node > /dev/null && command -v npm > /dev/null || missing+=(nodejs npm)
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing: ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
