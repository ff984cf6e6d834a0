"""WHEP through a TURN relay and with a STUN server (web.webrtc.turn_server, stun_server).

A real TURN server (Debian's coturn) on loopback, with a user and a password; the daemon is
configured with it as its TURN and STUN server. The viewer (aiortc, an independent WebRTC
stack) stands behind a "firewall": it is handed the daemon's answer with every candidate
but the relayed ones removed, and it ignores connectivity checks that do not come through
the relay (everything here shares 127.0.0.1, so the relay's ports tell them apart), so the
picture can only reach it through the daemon's allocation on the TURN server: frames
decoded, and the TURN server's own account of that allocation shows the bytes it relayed. Then a
wrong password in the daemon's config: no relayed candidate, and the session still comes
up on host candidates (a robot's LAN does not need the relay). Skipped where coturn is not
installed (scripts/install-deps.sh installs it for the tests)."""
import asyncio
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import aioice.ice
from aiortc import RTCPeerConnection, RTCSessionDescription

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "web"))
import harness  # noqa: E402
from harness import seconds  # noqa: E402
from whep_test import Whep, collect_frames, make_offer  # noqa: E402

ARGS = None
TURN_USER, TURN_PASSWORD = "robot", "s3cret-relay"


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class TurnServer:
    """coturn on 127.0.0.1: long-term credentials, relay ports in a small range of its own."""

    def __init__(self):
        self.dir = Path(tempfile.mkdtemp(prefix="omniview_turn_"))
        self.port = free_udp_port()
        self.log = self.dir / "turnserver.log"
        self.relay_ports = (self.port + 1, self.port + 40) if self.port < 65000 else (self.port - 40, self.port - 1)
        # A config file of its own: Debian's /etc/turnserver.conf sends the log to syslog.
        conf = self.dir / "turnserver.conf"
        conf.write_text("\n".join([
            "listening-ip=127.0.0.1", "relay-ip=127.0.0.1", f"listening-port={self.port}",
            f"min-port={self.relay_ports[0]}", f"max-port={self.relay_ports[1]}", "lt-cred-mech",
            f"user={TURN_USER}:{TURN_PASSWORD}", "realm=omniview.test", "allow-loopback-peers", "no-tls", "no-dtls",
            "no-cli", "no-stdout-log", "simple-log", f"log-file={self.log}", f"userdb={self.dir / 'turndb'}",
            f"pidfile={self.dir / 'turnserver.pid'}", "verbose", ""]))
        self.process = subprocess.Popen(["turnserver", "-c", str(conf)], stdout=subprocess.DEVNULL,
                                        stderr=subprocess.STDOUT)
        deadline = time.monotonic() + seconds(15)
        while not self.log_text().count("IPv4. UDP listener opened on") and time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RuntimeError("turnserver exited:\n" + self.log_text())
            time.sleep(0.1)

    def log_text(self):
        try:
            return self.log.read_text(errors="replace")
        except OSError:
            return ""

    def stop(self):
        self.process.terminate()
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.dir, ignore_errors=True)


def with_turn(turn, password):
    webrtc = (f"  webrtc: {{stun_server: \"stun://127.0.0.1:{turn.port}\", "
              f"turn_server: \"turn://{TURN_USER}:{password}@127.0.0.1:{turn.port}\"}}\n")
    return lambda text: text.replace("web:\n", "web:\n" + webrtc, 1)


def only_relayed_candidates(answer):
    """The answer with its host and server-reflexive candidates removed."""
    lines = answer.replace("\r\n", "\n").split("\n")
    kept = [l for l in lines if not l.startswith("a=candidate:") or " typ relay" in l]
    return "\r\n".join(kept)


class RelayOnlyFirewall:
    """While active, the viewer's ICE ignores checks from any port outside the relay's range:
    the daemon's host candidates cannot reach it, as behind a firewall that passes only the
    TURN server (aioice answers a check from an unknown address with a peer-reflexive pair,
    which would carry the picture past the relay)."""

    def __init__(self, relay_ports):
        self.relay_ports = relay_ports
        self.original = aioice.ice.Connection.request_received
        self.ignored = 0

    def __enter__(self):
        original, low, high = self.original, *self.relay_ports

        def request_received(connection, message, addr, protocol, raw_data):
            if not low <= addr[1] <= high:
                self.ignored += 1
                return
            original(connection, message, addr, protocol, raw_data)

        aioice.ice.Connection.request_received = request_received
        return self

    def __exit__(self, *exc):
        aioice.ice.Connection.request_received = self.original


async def watch(http, answer_filter=lambda a: a, frames_wanted=15):
    """Views `front` over WHEP; the decoded frames and the answer as the daemon sent it."""
    pc, offer = await make_offer()
    frames, enough = collect_frames(pc, frames_wanted)
    status, answer, headers = http.request("POST", "/whep/front", offer)
    assert status == 201, f"{status}: {answer}"
    try:
        await pc.setRemoteDescription(RTCSessionDescription(sdp=answer_filter(answer), type="answer"))
        await asyncio.wait_for(enough.wait(), seconds(30))
    finally:
        http.request("DELETE", headers["Location"])
        await pc.close()
    return frames, answer, headers


@unittest.skipUnless(shutil.which("turnserver"), "coturn's turnserver is not installed (scripts/install-deps.sh)")
class WhepThroughTurn(unittest.TestCase):
    def setUp(self):
        self.turn = TurnServer()
        self.robot = None

    def tearDown(self):
        if self.robot:
            self.assertEqual(self.robot.stop(), 0, self.robot.log.read_text())
        self.turn.stop()

    def start(self, password):
        self.robot = harness.Robot(ARGS, edit_config=with_turn(self.turn, password)).__enter__()
        return Whep(self.robot.web)

    def test_the_picture_reaches_a_viewer_through_the_relay_alone(self):
        http = self.start(TURN_PASSWORD)
        with RelayOnlyFirewall(self.turn.relay_ports) as firewall:
            frames, answer, headers = asyncio.run(watch(http, only_relayed_candidates, frames_wanted=20))
        http.close()
        self.assertGreater(firewall.ignored, 0, "the daemon's direct checks were not kept out: the test proves nothing")
        relayed = re.findall(r"a=candidate:.* (\d+\.\d+\.\d+\.\d+) (\d+) typ relay", answer)
        self.assertTrue(relayed, "the answer holds no relayed candidate:\n" + answer)
        for address, port in relayed:
            self.assertEqual(address, "127.0.0.1")
            self.assertTrue(self.turn.relay_ports[0] <= int(port) <= self.turn.relay_ports[1], port)
        # The relay as a WHEP Link for the viewer (the last of the Link headers: the TURN one).
        self.assertRegex(headers.get("Link", ""), rf'^<turn:127.0.0.1:{self.turn.port}>; rel="ice-server"; '
                                                  rf'username="{TURN_USER}"; credential="{TURN_PASSWORD}"')
        # Decoded by libavcodec (PyAV): the view, a picture, not a flat field.
        self.assertEqual((frames[-1].width, frames[-1].height), (320, 160))
        self.assertGreater(frames[-1].to_ndarray(format="gray").std(), 10, "the decoded picture is flat")
        # The TURN server's own account, written as the daemon's allocations close (the
        # session ended above): the daemon's user allocated a relay, and the picture went to
        # the viewer through it ("peer usage" sb: bytes the relay sent to its peer).
        deadline = time.monotonic() + seconds(20)
        while time.monotonic() < deadline and "peer usage" not in self.turn.log_text():
            time.sleep(0.25)
        log = self.turn.log_text()
        self.assertRegex(log, r"user <robot>: incoming packet ALLOCATE processed, success", log[-3000:])
        relayed = [int(b) for b in re.findall(r"peer usage: .*username=<robot>, .*sb=(\d+)", log)]
        self.assertTrue(relayed and max(relayed) > 10000, "the relay carried no picture:\n" + log[-3000:])

    def test_the_relay_password_only_for_a_token_that_may_watch(self):
        http = self.start(TURN_PASSWORD)
        for token in (None, "wrong-token"):
            status, _, headers = http.request("OPTIONS", "/whep/front", token=token)
            self.assertEqual(status, 204)
            self.assertNotIn(TURN_PASSWORD, str(headers), f"OPTIONS with token {token} got the TURN password")
        status, _, headers = http.request("OPTIONS", "/whep/front")  # the viewer's token
        self.assertEqual(status, 204)
        self.assertIn(f'credential="{TURN_PASSWORD}"', headers.get("Link", ""))
        http.close()

    def test_a_wrong_relay_password_leaves_the_lan_path_working(self):
        http = self.start("not-the-password")
        frames, answer, _ = asyncio.run(watch(http, frames_wanted=5))
        http.close()
        self.assertNotRegex(answer, r"typ relay", "a relayed candidate with a wrong password")
        self.assertRegex(answer, r"typ host")
        self.assertEqual(len(frames), 5)
        self.assertRegex(self.turn.log_text(), r"(?i)401|unauthori[sz]ed|wrong", "the TURN server refused the daemon")
        # And the daemon's log says so (the operator reads that one).
        self.assertIn("the TURN server (web.webrtc.turn_server) gave no relay candidate", self.robot.log.read_text())


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
