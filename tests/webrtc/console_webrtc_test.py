"""The operator console on WebRTC (WHEP), in headless Chromium against the real omniviewd and
spot-mock: WebRTC first, its picture and latency in the status line, tokens, the picture
resuming after the link drops, and the WebSocket where WebRTC cannot serve (the status
line says why)."""
import os
import signal
import sys
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "web"))
import harness  # noqa: E402
from harness import OPERATOR_TOKEN, VIEWER_TOKEN, seconds  # noqa: E402
from console_browser_test import browser, wait_until  # noqa: E402

ARGS = None

PANE = "const p = (window.omniviewConsole || {panes: []}).panes.find(p => p.view === arguments[0]);"
# What the pane's video element shows: [lit pixels, a fingerprint].
VIDEO_PIXELS = PANE + """
if (!p || !p.videoEl.videoWidth) return null;
const c = document.createElement('canvas');
c.width = p.videoEl.videoWidth; c.height = p.videoEl.videoHeight;
const g = c.getContext('2d');
g.drawImage(p.videoEl, 0, 0);
const d = g.getImageData(0, 0, c.width, c.height).data;
let lit = 0, s = 0;
for (let i = 0; i < d.length; i += 4) { if (d[i] > 16) lit++; s = (s * 31 + d[i]) % 1000000007; }
return [lit, s];
"""


def pane(driver, view="front"):
    return driver.execute_script(PANE + "return p && {encoding: p.encoding, frames: p.frames, age: p.rtcAgeMs, "
                                 "why: p.rtcWhy, restarts: p.rtc ? p.rtc.restarts : null};", view)


def ice_threads(pid):
    """The daemon's threads that are ICE agents' (libnice's, named by webrtcbin)."""
    count = 0
    for t in os.listdir(f"/proc/{pid}/task"):
        try:
            count += Path(f"/proc/{pid}/task/{t}/comm").read_text().strip().startswith("webrtc:ice")
        except OSError:
            pass
    return count


def status_line(driver):
    return driver.execute_script("return document.getElementById('status').textContent")


class ConsoleOnWebrtc(unittest.TestCase):
    robot_options = {}

    @classmethod
    def setUpClass(cls):
        cls.robot = harness.Robot(ARGS, **cls.robot_options).__enter__()
        cls.url = f"http://{cls.robot.web}/"
        try:
            cls.chromium = browser()
        except BaseException:
            cls.robot.stop()
            raise
        cls.home_tab = cls.chromium.current_window_handle

    @classmethod
    def tearDownClass(cls):
        try:
            cls.chromium.quit()
        finally:
            code = cls.robot.stop()
            assert code == 0, f"omniviewd exited with {code}:\n{cls.robot.log.read_text()}"

    def open(self, token, query="?layout=single&view=front"):
        driver = self.chromium
        driver.switch_to.window(self.home_tab)
        driver.switch_to.new_window("tab")
        tab = driver.current_window_handle

        def close_tab():  # a tab per test: no test sees another's token or streams
            driver.switch_to.window(tab)
            driver.close()
            driver.switch_to.window(self.home_tab)
        self.addCleanup(close_tab)
        driver.get(self.url + query + (f"#token={token}" if token else ""))
        return driver

    def wait_webrtc(self, driver, frames=20):
        return wait_until(lambda: (lambda p: p if p and p["encoding"] == "WebRTC" and p["frames"] >= frames else None)(
            pane(driver)), seconds(30), f"{frames} WebRTC pictures in the page (pane: {pane(driver)})")


class ConsoleWebrtcTest(ConsoleOnWebrtc):
    def test_the_console_plays_over_webrtc_first_and_says_so(self):
        driver = self.open(OPERATOR_TOKEN)
        p = self.wait_webrtc(driver)
        status = wait_until(lambda: (lambda t: t if "front WebRTC" in t and " ms" in t else None)(status_line(driver)),
                            seconds(5), "the status line naming WebRTC and a latency")
        print(f"console on WebRTC: {p}; status: {status}", file=sys.stderr)
        # Capture to display, from the RTP timestamps (Omniview-Capture-Clock): a picture
        # is shown within a second of its capture on loopback.
        age = wait_until(lambda: pane(driver)["age"], seconds(5), "a latency figure")
        self.assertGreater(age, 0)
        self.assertLess(age, seconds(1000))
        # The room is in the picture, and it moves on.
        pixels = wait_until(lambda: driver.execute_script(VIDEO_PIXELS, "front"), seconds(5), "the video's pixels")
        self.assertGreater(pixels[0], 320 * 160 // 4, "the picture is mostly black")
        self.assertIn("webrtc:", self.robot.status())
        # Gestures keep working: the view's spec for degrees per pixel, the picture's place.
        self.assertTrue(driver.execute_script(PANE + "return p.degreesPerPixel() > 0 && p.toImage(640, 400) !== null;",
                                              "front"))
        shot = driver.execute_async_script(PANE.replace("arguments[0]", "'front'") +
                                           "p.snapshot().then(s => arguments[0](s && [s.ext, s.blob.size]));")
        self.assertEqual(shot[0], "png")
        self.assertGreater(shot[1], 1000)

    def test_a_viewer_token_watches_over_webrtc(self):
        driver = self.open(VIEWER_TOKEN)
        self.wait_webrtc(driver, frames=5)

    def test_a_wrong_token_gets_the_login_and_no_session(self):
        sessions = lambda: self.robot.status().count("webrtc:")
        before = sessions()
        driver = self.open("not-a-token")
        wait_until(lambda: driver.execute_script("return !document.getElementById('login').hidden"), seconds(10),
                   "the login form")
        time.sleep(1)
        self.assertLessEqual(sessions(), before, "a session for a page without a valid token")

    def test_a_page_closed_ends_its_session_at_once(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=single&view=birdseye")
        wait_until(lambda: (lambda p: p and p["encoding"] == "WebRTC" and p["frames"] >= 5)(pane(driver, "birdseye")),
                   seconds(30), "WebRTC pictures of birdseye")
        self.assertIn("birdseye", self.robot.status().split("clients:")[1])
        driver.get("about:blank")  # the page goes: its DELETE, or the viewer's RTCP BYE, ends the session
        wait_until(lambda: "birdseye" not in self.robot.status().split("clients:")[1], seconds(5),
                   "the session ended (not after the 10 s of silence that frees a vanished viewer)")
        # And its ICE agent with it: Chromium's offer names its host by mDNS (<uuid>.local),
        # and an agent handed such a candidate once stayed for good (a thread and a UDP port
        # per address, every page load). GLib's pool idles a thread up to 15 s.
        wait_until(lambda: ice_threads(self.robot.daemon.pid) == 0, seconds(25), "the session's ICE agent gone")

    def pictures_per_second(self, driver, over=3.0):
        first, start = pane(driver)["frames"], time.monotonic()
        time.sleep(over)
        return (pane(driver)["frames"] - first) / (time.monotonic() - start)

    def test_zz_the_picture_resumes_after_the_link_drops_for_5_s(self):
        driver = self.open(OPERATOR_TOKEN)
        self.wait_webrtc(driver, frames=10)
        rate = self.pictures_per_second(driver)
        # The robot's end of the link goes silent for 5 s (the daemon stopped: nothing
        # reaches the browser, UDP or TCP), then comes back.
        self.robot.daemon.send_signal(signal.SIGSTOP)
        try:
            time.sleep(5)
        finally:
            self.robot.daemon.send_signal(signal.SIGCONT)
        before = pane(driver)["frames"]
        resumed = wait_until(lambda: (lambda p: p if p["encoding"] == "WebRTC" and p["frames"] >= before + 30 else None)(
            pane(driver)), seconds(40), "the picture resuming over WebRTC")
        print(f"after a 5 s drop: {resumed}", file=sys.stderr)
        wait_until(lambda: "front WebRTC" in status_line(driver), seconds(5), "the status line on WebRTC again")
        # Each picture counted once after the reconnect too (the page once armed a second
        # chain of frame callbacks per reconnect: twice the view's rate after one drop).
        self.assertGreaterEqual(pane(driver)["restarts"], 1, "the console did not reconnect: no test of it")
        after = self.pictures_per_second(driver)
        self.assertLess(after, 1.4 * rate + 1, f"{after:.1f} pictures/s after the drop, {rate:.1f} before")


class ConsoleWebrtcWithoutTokens(ConsoleOnWebrtc):
    robot_options = {"tokens": False}

    def test_a_daemon_without_tokens_serves_webrtc_to_anyone(self):
        driver = self.open(None)
        self.wait_webrtc(driver, frames=5)


def without_webrtc(text):
    return text.replace("web:\n", "web:\n  webrtc: {enabled: false}\n", 1)


class ConsoleWhereWebrtcIsOff(ConsoleOnWebrtc):
    robot_options = {"edit_config": without_webrtc}

    def test_the_console_falls_back_to_the_websocket_and_says_why(self):
        driver = self.open(OPERATOR_TOKEN)
        p = wait_until(lambda: (lambda p: p if p and p["encoding"] in ("H264", "JPEG") and p["frames"] >= 5 else None)(
            pane(driver)), seconds(30), "pictures over the WebSocket")
        self.assertIn("WebRTC is off", p["why"])
        if p["encoding"] == "H264":
            wait_until(lambda: "no WebRTC: WHEP 404" in status_line(driver), seconds(5), "the status line saying why")


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
