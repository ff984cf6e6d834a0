"""WebRTC viewers over WHEP (server/webrtc) against the real daemon and spot-mock.

The viewer is an independent WebRTC stack: Python's aiortc (Debian's python3-aiortc: its
own ICE, DTLS, SRTP and RTP), decoding the H.264 with PyAV (ffmpeg's libavcodec). Also:
tokens, bad offers and requests, a flood of POSTs, viewers that never connect or vanish
without DELETE: clear HTTP errors, sessions and threads back where they were, the daemon
serving on throughout."""
import asyncio
import http.client
import os
import re
import signal
import socket
import sys
import time
import unittest
from pathlib import Path

from aiortc import RTCPeerConnection, RTCSessionDescription
from aiortc.mediastreams import MediaStreamError

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "web"))
import harness  # noqa: E402
from harness import OPERATOR_TOKEN, VIEWER_TOKEN, seconds  # noqa: E402

ARGS = None

# A media's streaming threads come from GStreamer's task pool (GLib's thread pool): one
# that ran a session's task idles up to 15 s under that task's name ("nicesrc0:src") before
# GLib ends it, so "back to zero" is judged after that.
THREADS_GONE = harness.seconds(25)

# Room for the flood below: 6 viewers in all, 4 from one address.
WEBRTC_CONFIG = "  webrtc: {max_sessions: 6, max_sessions_per_client: 4}\n"


def with_webrtc_limits(text):
    return text.replace("web:\n", "web:\n" + WEBRTC_CONFIG, 1)


# Hand-written offers for what a viewer must not send (the good ones are aiortc's own).
VP8_ONLY = """v=0\r
o=- 1 1 IN IP4 127.0.0.1\r
s=-\r
t=0 0\r
m=video 9 UDP/TLS/RTP/SAVPF 96\r
c=IN IP4 0.0.0.0\r
a=mid:0\r
a=recvonly\r
a=rtpmap:96 VP8/90000\r
"""
AUDIO_ONLY = VP8_ONLY.replace("m=video", "m=audio").replace("VP8/90000", "opus/48000/2")
SENDONLY = VP8_ONLY.replace("a=recvonly", "a=sendonly").replace("VP8/90000", "H264/90000") + \
    "a=fmtp:96 packetization-mode=1;profile-level-id=42e01f\r\n"
PLAIN_RTP = VP8_ONLY.replace("UDP/TLS/RTP/SAVPF", "RTP/AVP").replace("VP8/90000", "H264/90000") + \
    "a=fmtp:96 packetization-mode=1\r\n"


async def make_offer():
    """An aiortc peer connection with one recvonly video transceiver and its gathered offer."""
    pc = RTCPeerConnection()
    pc.addTransceiver("video", direction="recvonly")
    await pc.setLocalDescription(await pc.createOffer())
    return pc, pc.localDescription.sdp


def collect_frames(pc, wanted):
    """The frames of `pc`'s incoming track as they come, and an event set once `wanted` came."""
    frames, enough = [], asyncio.Event()

    @pc.on("track")
    def on_track(track):
        async def read():
            while len(frames) < wanted:
                frames.append(await track.recv())
            enough.set()
        asyncio.ensure_future(read())

    return frames, enough


class Whep:
    """HTTP to the daemon's web port (one keep-alive connection)."""

    def __init__(self, address):
        host, port = address.rsplit(":", 1)
        self.conn = http.client.HTTPConnection(host, int(port), timeout=seconds(20))

    def request(self, method, path, body=None, token=VIEWER_TOKEN, content_type="application/sdp"):
        headers = {}
        if token:
            headers["Authorization"] = "Bearer " + token
        if body is not None:
            headers["Content-Type"] = content_type
        for attempt in (0, 1):
            try:
                self.conn.request(method, path, body=body.encode() if body is not None else None, headers=headers)
                r = self.conn.getresponse()
                return r.status, r.read().decode(errors="replace"), dict(r.getheaders())
            except (ConnectionError, http.client.HTTPException):
                # The daemon closes a keep-alive connection idle for 15 s: open a new one.
                self.conn.close()
                if attempt:
                    raise

    def close(self):
        self.conn.close()


class WhepTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.robot = harness.Robot(ARGS, edit_config=with_webrtc_limits).__enter__()
        cls.pid = cls.robot.daemon.pid

    @classmethod
    def tearDownClass(cls):
        assert cls.robot.stop() == 0, cls.robot.log.read_text()

    def setUp(self):
        self.http = Whep(self.robot.web)

    def tearDown(self):
        self.http.close()
        self.assertTrue(self.robot.alive(), "omniviewd died:\n" + self.robot.log.read_text())

    def webrtc_clients(self):
        return len(re.findall(r"^\s*webrtc:", self.robot.status(), re.M))

    def thread_names(self):
        names = {}
        for t in os.listdir(f"/proc/{self.pid}/task"):
            try:
                n = Path(f"/proc/{self.pid}/task/{t}/comm").read_text().strip()
            except OSError:
                continue
            names[n] = names.get(n, 0) + 1
        return names

    def media_threads(self):
        """The threads of WebRTC media (webrtcbin's, libnice's, our feed threads)."""
        return sum(n for name, n in self.thread_names().items() if name.startswith(("webrtc", "whep", "nice")))

    def wait_for(self, what, predicate, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if predicate():
                return
            time.sleep(0.25)
        self.fail(f"{what} within {timeout:.0f} s (threads now: {self.thread_names()})\n" +
                  self.robot.log.read_text()[-3000:])

    def test_an_independent_webrtc_stack_receives_and_decodes_the_view(self):
        async def go():
            pc, offer = await make_offer()
            frames, enough = collect_frames(pc, 20)
            status, answer, headers = self.http.request("POST", "/whep/front", offer)
            self.assertEqual(status, 201, answer)
            self.assertEqual(headers["Content-Type"], "application/sdp")
            self.assertRegex(headers["Location"], r"^/whep/front/[0-9a-f]{32}$")
            self.assertRegex(headers["Omniview-Capture-Clock"], r"^rtp=\d+; unix_us=\d+$")
            self.assertIn("a=sendonly", answer)
            self.assertIn("H264/90000", answer)
            self.assertRegex(answer, r"a=rtcp-fb:\d+ nack\r?\n", "NACK retransmission is on")
            self.assertRegex(answer, r"a=candidate:.* typ host", "the answer holds the daemon's candidates")
            self.assertNotRegex(answer, r"(?i)a=candidate:\S+ \d+ TCP ", "UDP media only: no ICE-TCP candidates")
            await pc.setRemoteDescription(RTCSessionDescription(sdp=answer, type="answer"))
            await asyncio.wait_for(enough.wait(), seconds(30))
            self.assertEqual(self.webrtc_clients(), 1)
            # PEER VIEW ENCODING SENT DROPPED: the frames offered while webrtcbin negotiated
            # are not the viewer's drops (they showed as 4-7 on every new viewer).
            line = re.search(r"^\s*webrtc:\S+\s+front\s+.*?(\d+)\s+(\d+)\s*$", self.robot.status(), re.M)
            self.assertIsNotNone(line, self.robot.status())
            self.assertLessEqual(int(line.group(2)), 2, line.group(0))
            # Named by its session, as the log names it.
            self.assertIn("#" + headers["Location"].rsplit("/", 1)[1][:8], line.group(0))
            status, text, _ = self.http.request("DELETE", headers["Location"])
            self.assertEqual(status, 200, text)
            status, text, _ = self.http.request("DELETE", headers["Location"])
            self.assertEqual(status, 404, "a session ends once")
            await pc.close()
            return frames

        frames = asyncio.run(go())
        # Decoded by libavcodec (PyAV): the view's size, and a picture, not a flat field.
        for f in frames:
            self.assertEqual((f.width, f.height), (320, 160))
        grey = frames[-1].to_ndarray(format="gray")
        self.assertGreater(grey.std(), 10, "the decoded picture is flat: no scene in it")
        self.assertGreater(len({f.pts for f in frames}), 15, "frames repeat")
        self.wait_for("the session's client gone from the status", lambda: self.webrtc_clients() == 0, seconds(10))
        self.wait_for("the session's threads gone", lambda: self.media_threads() == 0, THREADS_GONE)

    def test_tokens_as_on_every_other_route(self):
        async def go():
            pc, offer = await make_offer()
            for token, expected in ((None, 401), ("wrong-token", 401)):
                status, text, headers = self.http.request("POST", "/whep/front", offer, token=token)
                self.assertEqual(status, expected, text)
                self.assertEqual(headers.get("WWW-Authenticate"), "Bearer")
                # In HTTP's words (not the gRPC metadata's the authenticator speaks of).
                self.assertIn("Authorization: Bearer TOKEN" if token is None else "unknown token", text)
                self.assertNotIn("metadata", text)
            for token in (VIEWER_TOKEN, OPERATOR_TOKEN):  # a viewer may watch
                status, text, headers = self.http.request("POST", "/whep/front", offer, token=token)
                self.assertEqual(status, 201, text)
                status, text, _ = self.http.request("DELETE", headers["Location"], token=None)
                self.assertEqual(status, 401, "ending a session needs a token too")
                if token == OPERATOR_TOKEN:
                    status, text, _ = self.http.request("DELETE", headers["Location"], token=VIEWER_TOKEN)
                    self.assertEqual(status, 403, "another viewer's token ends no one else's session: " + text)
                status, text, _ = self.http.request("DELETE", headers["Location"], token=token)
                self.assertEqual(status, 200, text)
            # An operator's token ends any session.
            status, text, headers = self.http.request("POST", "/whep/front", offer, token=VIEWER_TOKEN)
            self.assertEqual(status, 201, text)
            status, text, _ = self.http.request("DELETE", headers["Location"], token=OPERATOR_TOKEN)
            self.assertEqual(status, 200, text)
            await pc.close()

        asyncio.run(go())

    def test_bad_offers_and_requests_get_clear_http_errors(self):
        cases = [
            ("POST", "/whep/front", "this is not sdp", "application/sdp", 400, "not an SDP offer"),
            ("POST", "/whep/front", "", "application/sdp", 400, "no SDP offer"),
            ("POST", "/whep/front", AUDIO_ONLY, "application/sdp", 400, "no video m-line"),
            ("POST", "/whep/front", SENDONLY, "application/sdp", 400, "recvonly"),
            ("POST", "/whep/front", PLAIN_RTP, "application/sdp", 400, "UDP/TLS/RTP/SAVPF"),
            ("POST", "/whep/front", VP8_ONLY, "application/sdp", 406, "offered: VP8"),
            ("POST", "/whep/front", VP8_ONLY, "application/json", 415, "application/sdp"),
            ("POST", "/whep/nosuchview", None, "application/sdp", 404, "nosuchview"),
            ("POST", "/whep/", VP8_ONLY, "application/sdp", 404, "POST an SDP offer to /whep/VIEW"),
            ("GET", "/whep/front", None, None, 405, "POST, OPTIONS"),
            ("PATCH", "/whep/front/0123", "a=candidate", "application/trickle-ice-sdpfrag", 405, "trickle ICE"),
            ("DELETE", "/whep/front/0123456789abcdef0123456789abcdef", None, None, 404, "no WebRTC session"),
            ("DELETE", "/whep/front", None, None, 405, "POST, OPTIONS"),
        ]

        async def good_offer():
            pc, offer = await make_offer()
            await pc.close()
            return offer

        offer = asyncio.run(good_offer())
        for method, path, body, content_type, expected, says in cases:
            if body is None and method == "POST":
                body = offer
            status, text, _ = self.http.request(method, path, body, content_type=content_type or "application/sdp")
            self.assertEqual(status, expected, f"{method} {path}: {text}")
            self.assertIn(says, text, f"{method} {path}")
        # The log says why too (a few lines per host every 10 s), for whoever's player "gets nothing".
        self.assertRegex(self.robot.log.read_text(), r"webrtc: refused \S+: the body is not an SDP offer")
        status, _, headers = self.http.request("OPTIONS", "/whep/front")
        self.assertEqual(status, 204)
        self.assertEqual(headers.get("Accept-Post"), "application/sdp")
        # OPTIONS says what POST and DELETE would of an unknown view or session (to a token
        # that may watch; a preflight without one gets 204: view names are not for anyone).
        status, text, _ = self.http.request("OPTIONS", "/whep/nosuchview")
        self.assertEqual((status, "nosuchview" in text), (404, True), text)
        status, text, _ = self.http.request("OPTIONS", "/whep/front/0123456789abcdef0123456789abcdef")
        self.assertEqual((status, "no WebRTC session" in text), (404, True), text)
        status, _, _ = self.http.request("OPTIONS", "/whep/nosuchview", token=None)
        self.assertEqual(status, 204)
        self.assertEqual(self.webrtc_clients(), 0)

    def test_a_viewer_keeps_its_picture_after_the_daemon_stalls_for_5_s(self):
        # The daemon stopped (SIGSTOP) 5 s, as a loaded robot computer may: its viewer was
        # ended ~10 s after the stall in half the runs, for webrtcbin's stats of the viewer's
        # receiver reports stood still after it (whep_session.cc).
        async def go():
            pc, offer = await make_offer()
            arrivals = []

            @pc.on("track")
            def on_track(track):
                async def read():
                    try:
                        while True:
                            await track.recv()
                            arrivals.append(time.monotonic())
                    except MediaStreamError:  # the peer connection closed: the test is over
                        pass
                asyncio.ensure_future(read())

            status, answer, headers = self.http.request("POST", "/whep/front", offer)
            self.assertEqual(status, 201, answer)
            await pc.setRemoteDescription(RTCSessionDescription(sdp=answer, type="answer"))
            deadline = time.monotonic() + seconds(30)
            while len(arrivals) < 10 and time.monotonic() < deadline:
                await asyncio.sleep(0.1)
            self.assertGreaterEqual(len(arrivals), 10, "no picture before the stall")
            os.kill(self.pid, signal.SIGSTOP)
            try:
                await asyncio.sleep(5)
            finally:
                os.kill(self.pid, signal.SIGCONT)
            resumed = time.monotonic()
            await asyncio.sleep(seconds(20))  # twice the daemon's 10 s grace
            late = [t for t in arrivals if t > resumed + seconds(15)]
            self.assertGreater(len(late), 5, f"the picture stopped after the stall ({len(arrivals)} frames in all)\n" +
                               self.robot.log.read_text()[-2000:])
            session = headers["Location"].rsplit("/", 1)[1][:8]
            self.assertNotIn(f"session {session} on 'front' ended", self.robot.log.read_text())
            status, text, _ = self.http.request("DELETE", headers["Location"])
            self.assertEqual(status, 200, text)
            await pc.close()

        asyncio.run(go())

    def test_an_offer_with_mdns_candidates_leaves_nothing_behind(self):
        # Browsers hide their addresses behind mDNS names (<uuid>.local host candidates);
        # webrtcbin's ICE agent that was handed one never went away: a thread and a UDP port
        # per address kept after the session ended, every console page load.
        async def offer():
            pc, sdp = await make_offer()
            await pc.close()
            return sdp

        sdp = asyncio.run(offer())
        mdns = "a=candidate:1 1 udp 2122260223 0b2c1d3e-4f50-4a6b-8c7d-9e0f1a2b3c4d.local 54321 typ host\r\n"
        sdp = re.sub(r"(a=mid:[^\r\n]*\r?\n)", lambda m: m.group(1) + mdns, sdp, count=1)
        self.assertIn(".local", sdp)
        for _ in range(3):
            status, text, headers = self.http.request("POST", "/whep/front", sdp)
            self.assertEqual(status, 201, text)
            self.assertEqual(self.http.request("DELETE", headers["Location"])[0], 200)
        self.wait_for("the sessions' threads gone", lambda: self.media_threads() == 0, THREADS_GONE)

    def test_a_flood_of_offers_is_capped_and_viewers_that_never_connect_are_freed(self):
        async def offer_of_a_vanished_viewer():
            pc, offer = await make_offer()
            await pc.close()  # its ports close: ICE can never complete
            return offer

        offer = asyncio.run(offer_of_a_vanished_viewer())
        statuses = {}
        refusal = ""
        for _ in range(1000):
            status, text, _ = self.http.request("POST", "/whep/front", offer)
            statuses[status] = statuses.get(status, 0) + 1
            if status == 503:
                refusal = text
        # 4 viewers from one address at once (max_sessions_per_client); a session whose ICE
        # fails during the flood frees its slot for a later POST (a slow sanitizer build
        # sees that), so at least 4 were made, and never more than 4 at once.
        self.assertEqual(set(statuses), {201, 503}, statuses)
        self.assertGreaterEqual(statuses[201], 4, statuses)
        self.assertGreater(statuses[503], 900, statuses)
        self.assertIn("max_sessions_per_client", refusal)
        self.assertLessEqual(self.webrtc_clients(), 4)
        # Nothing is sent to a viewer before its ICE and DTLS are up (webrtcbin would drop it):
        # the status shows them with no frames sent.
        sent = [int(m.group(1)) for m in re.finditer(r"^\s*webrtc:\S+\s+front\s+.*?(\d+)\s+(\d+)\s*$",
                                                     self.robot.status(), re.M)]
        self.assertEqual(sum(sent), 0, self.robot.status())
        # None of them ever connects: freed when ICE fails, at the latest ~15 s after their
        # answer (whep_server.cc).
        self.wait_for("the sessions that never connected freed", lambda: self.webrtc_clients() == 0, seconds(40))
        self.assertRegex(self.robot.log.read_text(), "ended: (ICE failed|ICE did not connect within)")
        self.wait_for("the sessions' threads gone", lambda: self.media_threads() == 0, THREADS_GONE)

        # And a real viewer is served again.
        async def watch():
            pc, good = await make_offer()
            status, answer, headers = self.http.request("POST", "/whep/front", good)
            self.assertEqual(status, 201, answer)
            got = asyncio.Event()

            @pc.on("track")
            def on_track(track):
                async def read():
                    await track.recv()
                    got.set()
                asyncio.ensure_future(read())

            await pc.setRemoteDescription(RTCSessionDescription(sdp=answer, type="answer"))
            await asyncio.wait_for(got.wait(), seconds(30))
            # Gone without DELETE (a closed laptop): its receiver reports stop, and the
            # session is freed within seconds.
            await pc.close()

        asyncio.run(watch())
        self.wait_for("a viewer that vanished without DELETE freed", lambda: self.webrtc_clients() == 0, seconds(30))
        self.assertIn("no receiver report (RTCP) from the viewer", self.robot.log.read_text())
        self.wait_for("the session's threads gone", lambda: self.media_threads() == 0, THREADS_GONE)


def free_udp_pair():
    """Two consecutive UDP ports free on every address now (web.webrtc.udp_ports' smallest range)."""
    for _ in range(100):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as a:
            a.bind(("0.0.0.0", 0))
            port = a.getsockname()[1]
            if port >= 65535:
                continue
            try:
                with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as b:
                    b.bind(("0.0.0.0", port + 1))
                    return port
            except OSError:
                continue
    raise RuntimeError("no two consecutive free UDP ports")


class WhepWithFewPorts(unittest.TestCase):
    """web.webrtc.udp_ports with room for a viewer or two: the next is refused, not answered
    without candidates (it waited for ICE in vain, and the log said nothing)."""

    def test_a_viewer_beyond_the_udp_ports_gets_503_naming_them(self):
        low = free_udp_pair()
        config = f"  webrtc: {{udp_ports: \"{low}-{low + 1}\"}}\n"
        with harness.Robot(ARGS, edit_config=lambda text: text.replace("web:\n", "web:\n" + config, 1)) as robot:
            http = Whep(robot.web)

            async def offer():
                pc, sdp = await make_offer()
                await pc.close()
                return sdp

            sdp = asyncio.run(offer())
            made, refusal = [], None
            for _ in range(4):
                status, text, headers = http.request("POST", "/whep/front", sdp)
                if status == 201:
                    self.assertRegex(text, r"a=candidate:.* typ host")
                    made.append(headers["Location"])
                else:
                    refusal = (status, text)
                    break
            self.assertGreaterEqual(len(made), 1, refusal)
            self.assertIsNotNone(refusal, f"{len(made)} viewers on two UDP ports")
            self.assertEqual(refusal[0], 503, refusal)
            self.assertIn(f"web.webrtc.udp_ports ({low}-{low + 1}", refusal[1])
            self.assertIn("refused", robot.log.read_text())
            self.assertIn("no free UDP port", robot.log.read_text())
            self.assertIn("web.webrtc.udp_ports holds 2 ports, fewer than", robot.log.read_text())
            for location in made:  # their ports come back: a viewer is served again
                self.assertEqual(http.request("DELETE", location)[0], 200)
            status, text, headers = http.request("POST", "/whep/front", sdp)
            self.assertEqual(status, 201, text)
            http.request("DELETE", headers["Location"])
            http.close()


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
