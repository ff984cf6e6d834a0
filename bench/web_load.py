"""Load on the web endpoint against the gRPC path, on loopback (issue 19's figures).

Starts spot-mock (room scene, 15 Hz) and omniviewd with the shipped front (1024x512) and
bird's-eye (800x800) views, then for each path in turn: N viewers, each streaming both
views as JPEG at the default quality, for a fixed time. Reports the daemon's CPU (its
/proc utime + stime over the window, % of one core) and each path's frame latency from
capture to arrival in the client (same machine, same clock), p50 and p95.

  /usr/bin/python3 bench/web_load.py --omniviewd build/daemon/omniviewd \\
      --omniview build/cli/omniview --spot-mock build/spot_adapter/mock/spot-mock [--viewers 4] [--seconds 10]

The clients are Python threads on the same machine: their own CPU is not counted, but on
a loaded machine they compete with the daemon for the cores, as a browser on the robot's
computer would not.
"""
import argparse
import asyncio
import datetime
import json
import os
import statistics
import struct
import sys
import threading
import time
from pathlib import Path

import grpc
import websockets

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "web"))
sys.path.insert(0, str(ROOT / "examples" / "python"))
import harness  # noqa: E402
from save_frames import load_api  # noqa: E402

VIEWS = ("front", "birdseye")


def shipped_sizes(text):
    return (text.replace("width: 320, height: 160", "width: 1024, height: 512")
                .replace("width: 240, height: 240", "width: 800, height: 800"))


def cpu_seconds(pid):
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class Samples:
    def __init__(self):
        self.lock = threading.Lock()
        self.latency_ms = []
        self.frames = 0
        self.recording = False

    def add(self, capture_s):
        with self.lock:
            if self.recording:
                self.latency_ms.append((time.time() - capture_s) * 1000)
                self.frames += 1


def grpc_viewer(address, view, samples, stop):
    pb, pb_grpc = load_api()
    channel = grpc.insecure_channel(address, options=[("grpc.max_receive_message_length", 64 << 20)])
    stub = pb_grpc.OmniviewStub(channel)
    call = stub.StreamFrames(pb.StreamFramesRequest(view=view, encoding=pb.JPEG))
    try:
        for frame in call:
            samples.add(frame.capture_time.seconds + frame.capture_time.nanos / 1e9)
            if stop.is_set():
                break
    except grpc.RpcError:
        pass
    call.cancel()


async def web_viewer(address, samples, stop):
    async with websockets.connect(f"ws://{address}/ws", subprotocols=["omniview.console.v1"], max_size=None) as ws:
        await ws.recv()
        for i, view in enumerate(VIEWS):
            await ws.send(json.dumps({"op": "subscribe", "id": i, "view": view}))
        while not stop.is_set():
            try:
                m = await asyncio.wait_for(ws.recv(), 0.5)
            except asyncio.TimeoutError:
                continue
            if isinstance(m, bytes):
                n = struct.unpack_from("<I", m, 4)[0]
                header = json.loads(m[8:8 + n])
                capture = datetime.datetime.fromisoformat(header["captureTime"].replace("Z", "+00:00"))
                samples.add(capture.timestamp())


def measure(robot, path, viewers, seconds):
    samples, stop = Samples(), threading.Event()
    threads = []
    if path == "grpc":
        for _ in range(viewers):
            for view in VIEWS:
                threads.append(threading.Thread(target=grpc_viewer, args=(robot.grpc, view, samples, stop)))
    else:
        for _ in range(viewers):
            threads.append(threading.Thread(target=lambda: asyncio.run(web_viewer(robot.web, samples, stop))))
    for t in threads:
        t.start()
    time.sleep(3)  # every stream running, maps built, the source at its rate
    with samples.lock:
        samples.recording = True
    t0, c0 = time.monotonic(), cpu_seconds(robot.daemon.pid)
    time.sleep(seconds)
    cpu = (cpu_seconds(robot.daemon.pid) - c0) / (time.monotonic() - t0) * 100
    with samples.lock:
        samples.recording = False
    stop.set()
    for t in threads:
        t.join()
    lat = sorted(samples.latency_ms)
    return {"cpu_pct": cpu, "fps_per_stream": samples.frames / seconds / (viewers * len(VIEWS)),
            "p50_ms": statistics.median(lat), "p95_ms": lat[int(len(lat) * 0.95)]}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--viewers", type=int, default=4)
    parser.add_argument("--seconds", type=float, default=10)
    parser.add_argument("--rounds", type=int, default=2)
    args, _ = parser.parse_known_args()
    programs, _ = harness.programs()
    with harness.Robot(programs, tokens=False, edit_config=shipped_sizes, scene="room") as robot:
        print(f"{args.viewers} viewers x {VIEWS}, {args.seconds:.0f} s each, load average "
              f"{os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
        for r in range(args.rounds):  # alternating, so a change in the machine's load hits both
            for path in ("grpc", "web"):
                m = measure(robot, path, args.viewers, args.seconds)
                print(f"round {r + 1} {path:4}: daemon CPU {m['cpu_pct']:5.1f} % of a core, "
                      f"{m['fps_per_stream']:4.1f} fps per stream, latency p50 {m['p50_ms']:5.1f} ms, "
                      f"p95 {m['p95_ms']:5.1f} ms", flush=True)


if __name__ == "__main__":
    main()
