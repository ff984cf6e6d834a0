"""The operator console in headless Chromium (Debian's chromium + chromium-driver, driven
by Selenium) against the real omniviewd in front of the real spot-mock."""
import sys
import time
import unittest
from pathlib import Path

from selenium import webdriver
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.common.exceptions import NoSuchWindowException

import harness
from harness import OPERATOR_TOKEN, VIEWER_TOKEN, seconds

ARGS = None


WINDOW = (1280, 800)  # the browser's window; open() emulates other sizes (a phone's)


def browser():
    options = Options()
    options.binary_location = "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              f"--window-size={WINDOW[0]},{WINDOW[1]}", "--use-gl=swiftshader", "--enable-unsafe-swiftshader"):
        options.add_argument(a)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def wait_until(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        try:
            last = predicate()
            if last:
                return last
        except Exception as e:  # the page may still be loading
            last = e
        time.sleep(0.1)
    raise AssertionError(f"{what}: not within {timeout:.1f} s (last: {last!r})")


# A cheap fingerprint of what a pane's canvas shows.
CANVAS_SUM = """
const pane = document.querySelector('.pane[data-view="' + arguments[0] + '"] canvas');
if (!pane || !pane.width) return null;
const d = pane.getContext('2d').getImageData(0, 0, pane.width, pane.height).data;
let s = 0, lit = 0;
for (let i = 0; i < d.length; i += 4) { s = (s * 31 + d[i] + d[i + 1] * 7) % 1000000007; if (d[i] > 16) lit++; }
return [s, lit];
"""


class ConsoleBrowserTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # The furnished room: what the README's screenshot shows.
        cls.robot = harness.Robot(ARGS, scene="room").__enter__()
        cls.url = f"http://{cls.robot.web}/"
        # One Chromium for the class (each start costs a second); every page opens in a tab of
        # its own, closed after its test, so no page sees another's sessionStorage (where the
        # console keeps its token), scripts or streams. test_zz_... quits a browser of its own.
        try:
            cls.chromium = browser()
        except BaseException:
            cls.robot.stop()  # tearDownClass does not run when setUpClass fails
            raise
        cls.home_tab = cls.chromium.current_window_handle

    @classmethod
    def tearDownClass(cls):
        try:
            cls.chromium.quit()
        finally:
            code = cls.robot.stop()
            assert code == 0, f"omniviewd exited with {code}:\n{cls.robot.log.read_text()}"

    def open(self, token, query="?layout=single&view=front", width=WINDOW[0], height=WINDOW[1]):
        """A page in a new tab (the returned driver is the class's, switched to it)."""
        driver = self.chromium
        driver.switch_to.window(self.home_tab)  # a window that exists, whatever the last test left
        driver.switch_to.new_window("tab")
        tab = driver.current_window_handle

        def close_tab():
            try:
                driver.switch_to.window(tab)
                driver.close()
            except NoSuchWindowException:  # the page went by itself
                pass
            finally:
                driver.switch_to.window(self.home_tab)
        self.addCleanup(close_tab)
        if (width, height) != WINDOW:  # headless windows are at least 500 px wide: a phone is emulated
            driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                                   {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
        # These tests are of the WebSocket paths (H.264 and JPEG), which the console takes
        # where WebRTC cannot serve; tests/webrtc/console_webrtc_test.py tests WebRTC.
        if "transport=" not in query:
            query += ("&" if "?" in query else "?") + "transport=websocket"
        driver.get(self.url + query + (f"#token={token}" if token else ""))
        return driver

    def frames(self, driver, view="front"):
        return driver.execute_script(
            "const p = (window.omniviewConsole || {panes: []}).panes.find(p => p.view === arguments[0]);"
            "return p ? p.frames : 0;", view)

    def wait_live(self, driver, view="front"):
        wait_until(lambda: self.frames(driver, view) >= 2, seconds(20), f"frames of {view} in the page")
        return wait_until(lambda: (driver.execute_script(CANVAS_SUM, view) or [0, 0])[1] > 100, seconds(5),
                          f"a drawn frame of {view}")

    def encoding(self, driver, view="front"):
        return wait_until(lambda: driver.execute_script(
            "const p = omniviewConsole.panes.find(p => p.view === arguments[0]);"
            "return p && p.channel !== null && p.encoding;", view), seconds(10), "the pane's encoding")

    def test_h264_where_webcodecs_decodes_it_else_jpeg_by_itself(self):
        driver = self.open(OPERATOR_TOKEN)
        self.wait_live(driver)
        support = driver.execute_async_script(
            "import('./js/video.js').then(m => m.h264Support()).then(arguments[0], e => arguments[0]({ok: false, reason: String(e)}))")
        encoding = self.encoding(driver)
        status = wait_until(lambda: (lambda t: t if "front" in t else None)(driver.find_element(By.ID, "status").text),
                            seconds(5), "the status line")
        print(f"console: WebCodecs H.264 {support}; pane on {encoding}; status: {status}", file=sys.stderr)
        if support["ok"]:
            self.assertEqual(encoding, "H264")
            self.assertIn("front H264", status)
            # Decoded pictures on the canvas, changing, with no decoder error.
            pictures = lambda: driver.execute_script("return omniviewConsole.panes[0].picture !== null")
            wait_until(pictures, seconds(5), "a decoded picture")
            first = driver.execute_script(CANVAS_SUM, "front")
            wait_until(lambda: driver.execute_script(CANVAS_SUM, "front") != first, seconds(5), "the video moving")
            self.assertTrue(driver.execute_script("return omniviewConsole.panes[0].video.firstKey"),
                            "the daemon's first frame was a key frame")
            # Each picture comes out of the decoder as its own access unit goes in: the decoder
            # adds no frame of latency (chunks are numbered in order).
            behind = driver.execute_async_script("""
                const done = arguments[0], p = omniviewConsole.panes[0], show = p.onPicture.bind(p), lag = [];
                p.onPicture = (f) => { lag.push(p.video.timestamp - 1 - f.timestamp); show(f); };
                setTimeout(() => { p.onPicture = show; done(lag); }, 1000);""")
            self.assertGreater(len(behind), 3)
            self.assertEqual(sorted(behind)[len(behind) // 2], 0, f"frames the decoder held back: {behind}")
            # A decode failure falls back to JPEG by itself, and the status line says why.
            driver.execute_script("omniviewConsole.panes[0].video.fail('test failure')")
            wait_until(lambda: "JPEG (test failure)" in driver.find_element(By.ID, "status").text, seconds(5),
                       "the JPEG fallback in the status line")
        else:
            self.assertEqual(encoding, "JPEG")
            self.assertIn(f"JPEG ({support['reason']})", status)
        frames = self.frames(driver)
        wait_until(lambda: self.frames(driver) > frames + 2, seconds(5), "frames after the fallback")
        self.assertEqual(self.encoding(driver), "JPEG")

    def test_a_view_of_odd_size_plays_at_its_own_size(self):
        # H.264 codes it one pixel larger (its edge repeated); the pane draws the view's own
        # 321x161, as the frame's header says (issue 29).
        self.robot.cli("views", "create", "--set", "name=odd", "--set", "type=perspective",
                       "--set", "source=spot", "--set", "width=321", "--set", "height=161")
        self.addCleanup(self.robot.cli, "views", "delete", "odd")
        driver = self.open(OPERATOR_TOKEN, "?layout=single&view=odd")
        self.wait_live(driver, "odd")
        support = driver.execute_async_script(
            "import('./js/video.js').then(m => m.h264Support()).then(arguments[0], e => arguments[0]({ok: false, reason: String(e)}))")
        status = wait_until(lambda: (lambda t: t if "odd" in t else None)(driver.find_element(By.ID, "status").text),
                            seconds(5), "the status line")
        print(f"odd-sized view: {status}", file=sys.stderr)
        self.assertEqual(self.encoding(driver, "odd"), "H264" if support["ok"] else "JPEG", status)
        rect = wait_until(lambda: driver.execute_script(
            "const p = omniviewConsole.panes.find(p => p.view === 'odd'); return p.rect"),
            seconds(5), "a picture drawn")
        self.assertEqual((rect["iw"], rect["ih"]), (321, 161))

    def test_a_decoder_that_cannot_keep_up_gets_fewer_frames_not_restarts(self):
        # A busy machine decodes slower than the view's 15 Hz: each picture here takes the
        # browser 150 ms (at most ~6.7 a second). The pane used to start its stream over at
        # a key frame whenever four frames waited, about twice a second for good (issue 29,
        # the paper layout's churn); it now asks for fewer frames and stays subscribed.
        driver = self.open(OPERATOR_TOKEN, "?layout=single&view=front")
        self.wait_live(driver)
        support = driver.execute_async_script(
            "import('./js/video.js').then(m => m.h264Support()).then(arguments[0], e => arguments[0]({ok: false, reason: String(e)}))")
        if not support["ok"]:
            self.skipTest(f"this Chromium decodes no H.264: {support}")
        wait_until(lambda: self.encoding(driver) == "H264", seconds(5), "H.264")
        driver.execute_script("""
            const p = omniviewConsole.panes[0], show = p.onPicture.bind(p), subscribe = p.link.subscribe.bind(p.link);
            window.subscriptions = 0;
            window.pictures = 0;
            p.link.subscribe = (...a) => { window.subscriptions++; return subscribe(...a); };
            p.onPicture = (f) => { const t = performance.now(); while (performance.now() - t < 150) {} window.pictures++; show(f); };""")
        time.sleep(10)
        subscriptions, pictures = driver.execute_script("return [window.subscriptions, window.pictures]")
        time.sleep(8)
        later, later_pictures = driver.execute_script("return [window.subscriptions, window.pictures]")
        rate = driver.execute_script("return omniviewConsole.panes[0].rateHz")
        status = driver.find_element(By.ID, "status").text
        print(f"slow decoder: {subscriptions} subscriptions in 10 s, {later - subscriptions} in the next 8 s, "
              f"{(later_pictures - pictures) / 8:.1f} pictures/s at {rate} Hz; status: {status}", file=sys.stderr)
        self.assertLessEqual(later - subscriptions, 1, "the stream keeps starting over")
        self.assertLess(rate, 15)
        self.assertGreater(later_pictures - pictures, 8, "pictures keep coming")
        self.assertIn("decoder behind", status)

    def test_jpeg_forced_by_the_url(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=single&view=front&encoding=jpeg")
        self.wait_live(driver)
        self.assertEqual(self.encoding(driver), "JPEG")
        wait_until(lambda: "front JPEG (forced)" in driver.find_element(By.ID, "status").text, seconds(5),
                   "JPEG (forced) in the status line")

    def test_video_logic_without_the_decoder(self):
        # The decode logic against a stand-in VideoDecoder that records what it is fed: runs
        # whatever this Chromium's own H.264 support.
        driver = self.open(OPERATOR_TOKEN, "?layout=single&view=front&encoding=jpeg")
        self.wait_live(driver)
        r = driver.execute_async_script("""
            const done = arguments[0];
            import('./js/video.js').then(async (m) => {
              const fed = [], configs = [], errors = [];
              let decoderError = null;
              window.VideoDecoder = class {
                constructor(init) { this.state = 'unconfigured'; this.decodeQueueSize = 0; decoderError = init.error; }
                static async isConfigSupported(c) { return {supported: c.codec.startsWith('avc1.64')}; }
                configure(c) { configs.push(c); this.state = 'configured'; }
                decode(chunk) { fed.push(chunk.type); }
                close() { this.state = 'closed'; }
              };
              window.EncodedVideoChunk = class { constructor(c) { this.type = c.type; } };
              const au = (...nals) => new Uint8Array(nals.flatMap((n) => [0, 0, 0, 1, ...n]));
              const key = au([0x67, 0x64, 0x00, 0x1f, 0xac], [0x68, 0xee], [0x65, 0x88]);
              const delta = au([0x41, 0x9a]);
              let resyncs = 0;
              const s = new m.H264Stream((f) => {}, (why) => errors.push(why), () => resyncs++);
              await s.push(delta); await s.push(delta);
              await s.push(key); await s.push(delta);
              s.decoder.decodeQueueSize = 10;  // a browser that cannot keep up
              await s.push(delta);
              s.decoder.decodeQueueSize = 0;
              await s.push(delta); await s.push(key);
              decoderError(new Error('boom'));
              await s.push(key);
              const baseline = new m.H264Stream(() => {}, (why) => errors.push(why));
              await baseline.push(au([0x67, 0x42, 0xc0, 0x1e], [0x68, 0xce], [0x65, 0x88]));
              const Stub = window.VideoDecoder;
              window.VideoDecoder = class extends Stub { configure() { throw new Error('refused'); } };
              const refused = new m.H264Stream(() => {}, (why) => errors.push(why));
              await refused.push(key);
              done({fed, codecs: configs.map((c) => c.codec), desc: configs.some((c) => 'description' in c),
                    waited: s.waited, resyncs, firstKey: s.firstKey, errors, types: m.nalUnits(key).map(m.nalType), isKey: [m.isKeyFrame(key), m.isKeyFrame(delta)]});
            }, (e) => done(String(e)));""")
        self.assertEqual(r["types"], [7, 8, 5])
        self.assertEqual(r["isKey"], [True, False])
        self.assertFalse(r["firstKey"])
        self.assertEqual(r["waited"], 4, "delta frames without their key frame are not decoded")
        self.assertEqual(r["resyncs"], 1, "falling behind asks for a key frame (a new subscription)")
        self.assertEqual(r["fed"], ["key", "delta", "key"], "key, delta, skip to the next key; nothing after an error")
        self.assertEqual(r["codecs"], ["avc1.64001F"], "the codec string from the SPS; Annex-B (no description)")
        self.assertFalse(r["desc"])
        self.assertEqual(r["errors"], ["decoder: boom", "avc1.42C01E not supported", "refused"])

    def test_live_view_and_drag_steers_through_the_api(self):
        driver = self.open(OPERATOR_TOKEN)
        self.wait_live(driver)
        self.assertEqual(driver.find_element(By.ID, "role").text, "operator")
        # Frames keep coming: the sequence advances.
        n = self.frames(driver)
        wait_until(lambda: self.frames(driver) >= n + 5, seconds(5), "five more frames")
        before_pixels = driver.execute_script(CANVAS_SUM, "front")
        yaw0, pitch0 = self.robot.yaw_pitch("front")
        pane = driver.find_element(By.CSS_SELECTOR, '.pane[data-view="front"]')
        t0 = time.monotonic()
        ActionChains(driver).move_to_element(pane).click_and_hold().move_by_offset(60, 0) \
            .move_by_offset(60, 20).move_by_offset(60, 20).release().perform()
        yaw1, pitch1 = wait_until(lambda: (lambda yp: yp if yp[0] > yaw0 + 5 else None)(self.robot.yaw_pitch("front")),
                                  seconds(5), "the drag turning the view left (yaw up)")
        self.assertGreater(pitch0, pitch1, "dragging down tilts up (pitch falls)")
        # The page shows the steered view: its pixels change.
        wait_until(lambda: driver.execute_script(CANVAS_SUM, "front") != before_pixels, seconds(5),
                   "the canvas showing the new view")
        print(f"drag: yaw {yaw0:.1f} -> {yaw1:.1f}, pitch {pitch0:.1f} -> {pitch1:.1f}; "
              f"new picture {time.monotonic() - t0:.2f} s after the drag began", file=sys.stderr)
        # Double click re-centres on the view as the console first saw it.
        ActionChains(driver).move_to_element(pane).double_click().perform()
        wait_until(lambda: abs(self.robot.yaw_pitch("front")[0] - yaw0) < 0.01, seconds(5), "re-centred")
        # Wheel zooms: hfov narrows.
        hfov0 = driver.execute_script("return omniviewConsole.panes[0].header.camera.spec.hfovDeg")
        driver.execute_script("""
            const el = document.querySelector('.pane[data-view="front"]');
            el.dispatchEvent(new WheelEvent('wheel', {deltaY: -300, bubbles: true, cancelable: true}));""")
        wait_until(lambda: driver.execute_script("return omniviewConsole.panes[0].header.camera.spec.hfovDeg") < hfov0 - 5,
                   seconds(5), "a frame rendered with the zoomed hfov")

    def test_status_shows_the_robots_rate_and_update_latency(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=split")
        self.wait_live(driver, "birdseye")
        self.wait_live(driver, "front")
        rate = wait_until(lambda: (lambda r: r if r and 10 <= float(r) <= 16.5 else None)(
            driver.find_element(By.ID, "status").get_attribute("data-source-rate")), seconds(10),
            "the mock's 15 Hz in the status line")
        self.assertIn("spot", driver.find_element(By.ID, "status").text)
        self.assertEqual(driver.find_element(By.ID, "status").get_attribute("data-connected"), "true")
        # From an UpdateView reply to the first frame of the new revision, in the page.
        latency = driver.execute_async_script("""
            const done = arguments[arguments.length - 1];
            const app = omniviewConsole, pane = app.panes.find(p => p.view === 'front');
            const t0 = performance.now();
            app.link.call('UpdateView', {name: 'front', delta: {yawDeg: 1}}).then((view) => {
              const want = Number(view.revision);
              const check = () => (Number(pane.header.camera.revision) >= want) ? done(performance.now() - t0)
                                                                              : setTimeout(check, 2);
              check();
            }, (e) => done(-1));""")
        print(f"UpdateView sent -> a frame of the new revision in the page: {latency:.0f} ms", file=sys.stderr)
        self.assertGreater(latency, 0)
        self.assertLess(latency, 1000 * harness.time_scale())
        if ARGS.screenshot:
            # The front view as configured (earlier tests steered it), then the picture.
            driver.execute_script("omniviewConsole.link.call('UpdateView', {name: 'front', set: "
                                  "{yawDeg: 0, pitchDeg: 27, hfovDeg: 115}})")
            Path(ARGS.screenshot).parent.mkdir(parents=True, exist_ok=True)
            time.sleep(1.2)  # a status line with its first fps figures
            driver.save_screenshot(ARGS.screenshot)

    def test_viewer_token_watches_but_cannot_steer(self):
        driver = self.open(VIEWER_TOKEN)
        self.wait_live(driver)
        self.assertIn("viewer", driver.find_element(By.ID, "role").text)
        self.assertEqual(driver.find_elements(By.CSS_SELECTOR, ".pane .hint"), [], "no steering hints for a viewer")
        yaw0, _ = self.robot.yaw_pitch("front")
        pane = driver.find_element(By.CSS_SELECTOR, '.pane[data-view="front"]')
        ActionChains(driver).move_to_element(pane).click_and_hold().move_by_offset(150, 0).release().perform()
        toast = wait_until(lambda: driver.find_element(By.ID, "toast").text, seconds(5), "the refusal shown")
        self.assertIn("PERMISSION_DENIED", toast)
        self.assertEqual(self.robot.yaw_pitch("front")[0], yaw0)

    def test_wrong_token_is_refused(self):
        driver = self.open("not-a-token")
        wait_until(lambda: driver.find_element(By.ID, "login").is_displayed(), seconds(10), "the login form")
        self.assertIn("unknown token", driver.find_element(By.ID, "status").text)
        self.assertEqual(self.frames(driver), 0)
        no_token = self.open(None)  # the same driver, now on the second tab
        wait_until(lambda: no_token.find_element(By.ID, "login").is_displayed(), seconds(10), "the login form")

    def test_phone_layout_fits(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=split", width=390, height=844)
        self.wait_live(driver, "front")
        self.assertEqual(driver.execute_script("return window.innerWidth"), 390)
        overflow = driver.execute_script("return document.documentElement.scrollWidth - window.innerWidth")
        self.assertLessEqual(overflow, 0)
        boxes = driver.execute_script("return [...document.querySelectorAll('.pane')].map(p => p.getBoundingClientRect().height)")
        self.assertEqual(len(boxes), 2)
        self.assertTrue(all(h > 150 for h in boxes), boxes)
        # The status line wraps rather than cutting anything off: the source's rate and each
        # pane's fps, frame age and dropped frames all show.
        status = wait_until(lambda: (lambda t: t if t.count(" ms") == 2 and "Hz" in t else None)(
            driver.find_element(By.ID, "status").text), seconds(10), "both panes' figures in the status line")
        for words in ("spot", "birdseye", "front", "fps", "dropped"):
            self.assertIn(words, status)
        clipped = driver.execute_script(
            "const s = document.getElementById('status'); return s.scrollWidth - s.clientWidth;")
        self.assertLessEqual(clipped, 0, status)
        if ARGS.screenshot:
            driver.save_screenshot(str(Path(ARGS.screenshot).with_name("console_phone.png")))

    def ptz_view(self):
        """A view named ptz, off screen in Split: what the console once turned instead of front."""
        self.robot.cli("views", "create", "--set", "name=ptz", "--set", "type=perspective", "--set", "source=spot",
                       "--set", "width=64", "--set", "height=48", "--set", "yaw_deg=-30", "--set", "pitch_deg=10")
        self.addCleanup(self.robot.cli, "views", "delete", "ptz")
        return self.robot.yaw_pitch("ptz")

    def test_tap_on_the_birdseye_turns_the_front_view_there(self):
        ptz = self.ptz_view()
        driver = self.open(OPERATOR_TOKEN, "?layout=split")
        self.wait_live(driver, "birdseye")
        self.wait_live(driver, "front")
        rect = driver.execute_script(
            "return omniviewConsole.panes.find(p => p.view === 'birdseye').rect")
        pane = driver.find_element(By.CSS_SELECTOR, '.pane[data-view="birdseye"]')
        size = pane.size
        # Ahead and to the left of the robot (forward is up in the bird's-eye, left is left).
        x = rect["x"] + rect["w"] * 0.25 - size["width"] / 2
        y = rect["y"] + rect["h"] * 0.2 - size["height"] / 2
        ActionChains(driver).move_to_element_with_offset(pane, x, y).click().perform()
        yaw, pitch = wait_until(lambda: (lambda yp: yp if yp[0] > 20 else None)(self.robot.yaw_pitch("front")),
                                seconds(5), "the front view turned left toward the tapped ground")
        self.assertLess(yaw, 70)
        self.assertGreater(pitch, 0, "looks down at the ground")
        self.assertEqual(self.robot.yaw_pitch("ptz"), ptz, "the view on screen turned, not the hidden ptz")
        print(f"tap-to-look: front now yaw {yaw:.1f}, pitch {pitch:.1f}", file=sys.stderr)

    def test_paper_layout_cloud_and_backward_camera(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=paper")
        self.addCleanup(lambda: self.robot.cli("views", "delete", "console_back"))
        wait_until(lambda: driver.execute_script("return omniviewConsole.cloud && omniviewConsole.cloud.points"),
                   seconds(20), "points in the cloud panel")
        self.wait_live(driver, "front")
        self.wait_live(driver, "console_back")
        self.assertIn("console_back", self.robot.cli("views", "list"))
        yaw_back, _ = self.robot.yaw_pitch("console_back")
        self.assertAlmostEqual(abs(yaw_back - self.robot.yaw_pitch("front")[0]), 180, delta=0.01)
        if ARGS.screenshot:
            driver.save_screenshot(str(Path(ARGS.screenshot).with_name("console_paper.png")))

    def test_viewer_paper_says_why_there_is_no_backward_camera(self):
        driver = self.open(VIEWER_TOKEN, "?layout=paper")
        self.wait_live(driver, "front")
        message = wait_until(lambda: driver.find_element(By.CSS_SELECTOR, ".pane.missing").text, seconds(5),
                             "the backward pane's message")
        self.assertIn("back", message)
        self.assertIn("operator", message)
        self.assertEqual(driver.find_elements(By.CSS_SELECTOR, ".pane .hint"), [])

    def test_dropdown_names_the_main_pane(self):
        # Single without a view in the address: front, not the list's first (birdseye).
        driver = self.open(OPERATOR_TOKEN, "?layout=single")
        self.wait_live(driver, "front")
        select = lambda: driver.execute_script("return document.getElementById('view-select').value")
        self.assertEqual(select(), "front")
        driver.find_element(By.CSS_SELECTOR, '#layouts button[data-layout="split"]').click()
        self.wait_live(driver, "birdseye")
        self.assertEqual(select(), driver.execute_script("return omniviewConsole.panes[0].view"))

    def test_phone_paper_labels_stay_readable(self):
        driver = self.open(OPERATOR_TOKEN, "?layout=paper", width=390, height=844)
        self.addCleanup(lambda: self.robot.cli("views", "delete", "console_back"))
        self.wait_live(driver, "front")
        self.wait_live(driver, "console_back")
        self.assertEqual(driver.execute_script("return document.getElementById('view-select').value"), "front")
        # No pane's hint covers its label (a hidden hint has an empty box).
        overlaps = driver.execute_script("""
            return [...document.querySelectorAll('.pane')].map((p) => {
              const l = p.querySelector('.label'), h = p.querySelector('.hint');
              if (!l || !h) return null;
              const a = l.getBoundingClientRect(), b = h.getBoundingClientRect();
              return b.width > 0 && a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom
                ? p.dataset.view : null;
            }).filter((v) => v);""")
        self.assertEqual(overlaps, [])
        if ARGS.screenshot:
            driver.save_screenshot(str(Path(ARGS.screenshot).with_name("console_paper_phone.png")))

    def test_pinch_zooms_and_double_tap_recentres(self):
        driver = self.open(OPERATOR_TOKEN)
        self.wait_live(driver)
        hfov0 = driver.execute_script("return omniviewConsole.panes[0].header.camera.spec.hfovDeg")
        # Two fingers moving apart, as touch pointer events.
        driver.execute_script("""
            const el = document.querySelector('.pane[data-view="front"]');
            const r = el.getBoundingClientRect(), cx = r.left + r.width / 2, cy = r.top + r.height / 2;
            const ev = (type, id, x) => el.dispatchEvent(new PointerEvent(type, {pointerId: id, pointerType: 'touch',
                clientX: x, clientY: cy, bubbles: true, isPrimary: id === 1}));
            ev('pointerdown', 1, cx - 20); ev('pointerdown', 2, cx + 20);
            for (let d = 30; d <= 120; d += 10) { ev('pointermove', 1, cx - d); ev('pointermove', 2, cx + d); }
            ev('pointerup', 1, cx - 120); ev('pointerup', 2, cx + 120);""")
        wait_until(lambda: driver.execute_script("return omniviewConsole.panes[0].header.camera.spec.hfovDeg") < hfov0 - 10,
                   seconds(5), "a frame rendered with the pinched hfov")
        # Double tap: back to the view as the page first saw it.
        driver.execute_script("""
            const el = document.querySelector('.pane[data-view="front"]');
            const r = el.getBoundingClientRect(), x = r.left + 50, y = r.top + 50;
            for (let i = 0; i < 2; i++) for (const type of ['pointerdown', 'pointerup'])
              el.dispatchEvent(new PointerEvent(type, {pointerId: 7, pointerType: 'touch', clientX: x, clientY: y,
                                                       bubbles: true, isPrimary: true}));""")
        wait_until(lambda: abs(driver.execute_script("return omniviewConsole.panes[0].header.camera.spec.hfovDeg") - hfov0)
                   < 0.01, seconds(5), "the hfov back after a double tap")

    def test_robot_away_shows_the_banner_and_snapshot_downloads(self):
        driver = self.open(OPERATOR_TOKEN)
        self.wait_live(driver)
        downloads = self.robot.dir / "downloads"
        downloads.mkdir(exist_ok=True)
        driver.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(downloads)})
        self.addCleanup(driver.execute_cdp_cmd, "Browser.setDownloadBehavior", {"behavior": "default"})
        driver.find_element(By.ID, "snapshot").click()
        # JPEG as received, or the last decoded H.264 picture as PNG.
        shot = wait_until(lambda: [p for p in downloads.glob("front-*.*") if p.suffix in (".jpg", ".png")
                                   and p.stat().st_size > 0], seconds(5), "the snapshot downloaded")[0]
        if self.encoding(driver) == "H264":
            self.assertEqual(shot.read_bytes()[:8], b"\x89PNG\r\n\x1a\n")
        else:
            self.assertEqual(shot.read_bytes()[:2], b"\xff\xd8")
        try:
            self.robot.mock_control("--set", "away=true")
            # The first failed calls may show "Robot link degraded" for a moment (frames came
            # within the last second); then the robot is gone, or the picture stale.
            def gone_banner():
                b = driver.find_element(By.ID, "banner")
                return b.text if b.is_displayed() and ("Robot disconnected" in b.text or "Not live" in b.text) else None
            banner = wait_until(gone_banner, seconds(10), "the disconnected/stale banner")
            self.assertTrue("Robot disconnected" in banner or "Not live" in banner, banner)
            wait_until(lambda: driver.find_element(By.CSS_SELECTOR, '.pane[data-view="front"] .stale').is_displayed(),
                       seconds(10), "the pane marked stale (Frame.stale)")
        finally:
            self.robot.mock_control("--set", "away=false")
        wait_until(lambda: not driver.find_element(By.ID, "banner").is_displayed(), seconds(15), "live again")

    def test_gamepad_steers(self):
        ptz = self.ptz_view()
        driver = self.open(OPERATOR_TOKEN)
        self.wait_live(driver)
        yaw0, pitch0 = self.robot.yaw_pitch("front")
        # A gamepad whose left stick is held left: the Gamepad API as the page reads it.
        driver.execute_script("""
            const pad = {connected: true, axes: [-1, 0, 0, 0], buttons: []};
            navigator.getGamepads = () => [pad];
            window.testPad = pad;
            setTimeout(() => { pad.axes[0] = 0; }, 500);""")
        wait_until(lambda: self.robot.yaw_pitch("front")[0] > yaw0 + 10, seconds(5), "the stick turning the view left")
        self.assertEqual(self.robot.yaw_pitch("front")[1], pitch0)
        # A re-centres the view the stick steered (not the ptz view off screen).
        time.sleep(0.3)  # the stick's last steps sent
        driver.execute_script("testPad.buttons = [{value: 1}]; setTimeout(() => { testPad.buttons = []; }, 300);")
        wait_until(lambda: abs(self.robot.yaw_pitch("front")[0] - yaw0) < 0.01, seconds(5), "A re-centring front")
        self.assertEqual(self.robot.yaw_pitch("ptz"), ptz)

    def test_zz_daemon_survives_a_page_closed_mid_stream(self):
        driver = browser()
        driver.get(self.url + "?layout=split&transport=websocket#token=" + OPERATOR_TOKEN)
        self.wait_live(driver, "front")
        driver.quit()  # the browser goes, streams and all, without closing anything
        self.assertTrue(self.robot.alive())
        wait_until(lambda: "(web)" not in self.robot.status(), seconds(10), "the web clients gone from status")
        again = self.open(OPERATOR_TOKEN)
        self.wait_live(again)


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
