"""One measurement of bench/webrtc_loss.sh: the console in headless Chromium on one path
(WebRTC, or H.264 over the WebSocket) for SECONDS; prints one Markdown table row.

Latency is capture to display of each picture shown, on one clock (daemon and browser are
on one machine): WebRTC's pictures carry their capture time in the RTP timestamp
(docs/API.md "Capture times"), read in requestVideoFrameCallback with the picture's
expected display time; the WebSocket's H.264 frames carry it in their header, and a
picture counts as shown at the first paint after the decoder hands it to the canvas. A freeze is a gap between
shown pictures longer than max(3 x the mean gap, mean gap + 150 ms): the definition
WebRTC's own statistics use (freezeCount), applied to both paths alike."""
import argparse
import statistics
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service

HOOK = """
const p = omniviewConsole.panes[0];
window.benchSamples = [];  // [display ms (Unix), capture-to-display ms]
if (p.encoding === 'WebRTC') {
  const shown = p.onVideoFrame.bind(p);
  p.onVideoFrame = (video, meta) => {
    if (meta.captureMs !== null) benchSamples.push([meta.displayMs, meta.displayMs - meta.captureMs]);
    shown(video, meta);
  };
} else {
  const shown = p.onPicture.bind(p);
  p.onPicture = (frame) => {
    const captured = p.header && p.header.captureTime ? Date.parse(p.header.captureTime) : null;
    shown(frame);
    // Drawn into the canvas now: on screen at the next frame the page paints.
    requestAnimationFrame(() => {
      const now = performance.timeOrigin + performance.now();
      if (captured !== null) benchSamples.push([now, now - captured]);
    });
  };
}
return p.encoding;
"""


def percentile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))] if values else float("nan")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--url", required=True)
    parser.add_argument("--path", choices=["webrtc", "websocket"], required=True)
    parser.add_argument("--seconds", type=float, default=60)
    parser.add_argument("--loss", default="0")
    args = parser.parse_args()
    options = Options()
    options.binary_location = "/usr/bin/chromium"
    # WebCodecs (the WebSocket path's H.264) wants a secure context: the bench link's
    # plain http:// address counts as one here, as https:// would.
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,800",
              "--unsafely-treat-insecure-origin-as-secure=" + args.url.rstrip("/")):
        options.add_argument(a)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    try:
        query = "?layout=single&view=front" + ("&transport=websocket" if args.path == "websocket" else "")
        driver.get(args.url + query)
        want = "WebRTC" if args.path == "webrtc" else "H264"
        deadline = time.monotonic() + 60
        while True:
            encoding = driver.execute_script(
                "const p = (window.omniviewConsole || {panes: []}).panes[0];"
                "return p && p.frames > 10 ? p.encoding : null;")
            if encoding == want:
                break
            if time.monotonic() > deadline:
                raise SystemExit(f"the console did not play over {want} (pane on {encoding})")
            time.sleep(0.2)
        driver.execute_script(HOOK)
        stats0 = driver.execute_script("return omniviewConsole.panes[0].rtcStats") or {}
        time.sleep(args.seconds)
        samples = driver.execute_script("return benchSamples")
        stats1 = driver.execute_script("return omniviewConsole.panes[0].rtcStats") or {}
    finally:
        driver.quit()
    shown = [s[0] for s in samples]
    latency = [s[1] for s in samples]
    gaps = [b - a for a, b in zip(shown, shown[1:])]
    mean_gap = statistics.mean(gaps) if gaps else float("inf")
    limit = max(3 * mean_gap, mean_gap + 150)
    freezes = [g for g in gaps if g > limit]
    frozen = sum(freezes) / (args.seconds * 1000)
    label = "WebRTC" if args.path == "webrtc" else "H.264 over WebSocket"
    extra = ""
    if args.path == "webrtc" and stats1:
        extra = (f" (browser: {stats1.get('freezeCount', 0) - stats0.get('freezeCount', 0)} freezes, "
                 f"{stats1.get('nackCount', 0) - stats0.get('nackCount', 0)} NACKs)")
    print(f"| {label} | {args.loss} % | {statistics.median(latency):.0f} ms | {percentile(latency, 0.95):.0f} ms | "
          f"{len(samples) / args.seconds:.1f} | {len(freezes)}{extra} | {100 * frozen:.1f} % |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
