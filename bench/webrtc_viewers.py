"""The daemon's CPU for one WebRTC viewer of a view against four (issue 30: the viewers share
the view's one H.264 encoder, so each more costs only its packetising, SRTP and RTCP).

Starts spot-mock (room scene, 15 Hz) and omniviewd with the shipped front view (1024x512),
then for 1 and for 4 viewers in turn: aiortc WHEP viewers (Debian's python3-aiortc, their
own ICE/DTLS/SRTP stack, decoding with PyAV), watching for a fixed time after a warm-up.
Reports the daemon's CPU (/proc utime + stime over the window, % of one core), the pictures
each viewer decoded per second, and the difference.

  /usr/bin/python3 bench/webrtc_viewers.py --omniviewd build/daemon/omniviewd \\
      --omniview build/cli/omniview --spot-mock build/spot_adapter/mock/spot-mock [--seconds 20]

The viewers decode on this machine too: their CPU is not counted, but they compete with the
daemon for the cores (the figures are noisier than on a robot with a remote operator).
"""
import argparse
import asyncio
import os
import sys
import time
import urllib.request
from pathlib import Path

from aiortc import RTCPeerConnection, RTCSessionDescription
from aiortc.mediastreams import MediaStreamError

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "web"))
import harness  # noqa: E402


def shipped_front(text):
    return text.replace("width: 320, height: 160", "width: 1024, height: 512")


def cpu_seconds(pid):
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


async def viewer(url, token, counts, index, stop):
    pc = RTCPeerConnection()
    pc.addTransceiver("video", direction="recvonly")

    @pc.on("track")
    def on_track(track):
        async def read():
            while not stop.is_set():
                try:
                    await track.recv()
                except MediaStreamError:  # the connection closed at the end
                    return
                counts[index] += 1
        asyncio.ensure_future(read())

    await pc.setLocalDescription(await pc.createOffer())
    request = urllib.request.Request(url, data=pc.localDescription.sdp.encode(), method="POST",
                                     headers={"Content-Type": "application/sdp", "Authorization": "Bearer " + token})
    with urllib.request.urlopen(request, timeout=10) as r:
        answer, location = r.read().decode(), r.headers["Location"]
    await pc.setRemoteDescription(RTCSessionDescription(sdp=answer, type="answer"))
    await stop.wait()
    urllib.request.urlopen(urllib.request.Request(url.split("/whep/")[0] + location, method="DELETE",
                                                  headers={"Authorization": "Bearer " + token}), timeout=10).read()
    await pc.close()


async def measure(robot, n, seconds, warmup=5):
    url = f"http://{robot.web}/whep/front"
    counts = [0] * n
    stop = asyncio.Event()
    tasks = [asyncio.ensure_future(viewer(url, harness.OPERATOR_TOKEN, counts, i, stop)) for i in range(n)]
    await asyncio.sleep(warmup)
    c0, t0, f0 = cpu_seconds(robot.daemon.pid), time.monotonic(), list(counts)
    await asyncio.sleep(seconds)
    c1, t1, f1 = cpu_seconds(robot.daemon.pid), time.monotonic(), list(counts)
    stop.set()
    await asyncio.gather(*tasks)
    cpu = 100 * (c1 - c0) / (t1 - t0)
    rates = [(b - a) / (t1 - t0) for a, b in zip(f0, f1)]
    return cpu, rates


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--omniviewd", required=True)
    parser.add_argument("--omniview", required=True)
    parser.add_argument("--spot-mock", required=True)
    parser.add_argument("--seconds", type=float, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with harness.Robot(args, edit_config=shipped_front, scene="room") as robot:
        rows = {1: [], 4: []}
        for _ in range(args.repeats):
            for n in (1, 4):
                rows[n].append(asyncio.run(measure(robot, n, args.seconds)))
                time.sleep(2)
    median = lambda xs: sorted(xs)[len(xs) // 2]
    print("| WebRTC viewers of front (1024x512) | daemon CPU, % of one core (median of runs) | runs | "
          "pictures/s per viewer |")
    print("|---|---|---|---|")
    for n in (1, 4):
        cpus = [c for c, _ in rows[n]]
        rates = [r for _, rs in rows[n] for r in rs]
        print(f"| {n} | {median(cpus):.1f} | {', '.join(f'{c:.1f}' for c in cpus)} | "
              f"{min(rates):.1f} to {max(rates):.1f} |")
    print(f"\nthree more viewers: +{median([c for c, _ in rows[4]]) - median([c for c, _ in rows[1]]):.1f} % of a core")


if __name__ == "__main__":
    main()
