"""The real spot-mock and omniviewd as processes on loopback ports, for the web tests.

Programs come from the command line (CTest passes the build's): --omniviewd, --omniview,
--spot-mock. Every time bound is multiplied by OMNIVIEW_TEST_TIME_SCALE (sanitizer builds
run slower), as the C++ tests' are.
"""
import argparse
import os
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import yaml

OPERATOR_TOKEN = "op-Secret+/token=1"   # base64's characters, as `openssl rand -base64` makes
VIEWER_TOKEN = "viewer-token-2"


def time_scale():
    try:
        return max(1.0, float(os.environ.get("OMNIVIEW_TEST_TIME_SCALE", "1")))
    except ValueError:
        return 1.0


def seconds(s):
    return s * time_scale()


def programs():
    parser = argparse.ArgumentParser()
    parser.add_argument("--omniviewd", required=True)
    parser.add_argument("--omniview", required=True)
    parser.add_argument("--spot-mock", required=True)
    parser.add_argument("--screenshot", default="")
    args, rest = parser.parse_known_args()
    return args, rest


def wait_for_file(path, timeout, what, log=None):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if path.exists() and path.stat().st_size > 0:
            return path.read_text()
        time.sleep(0.05)
    extra = ("\n" + log.read_text()) if log and log.exists() else ""
    raise AssertionError(f"{what} not ready within {timeout:.0f} s{extra}")


def daemon_config(mock_port, certs, credentials, tokens=True, web_listen="127.0.0.1:0", extra=""):
    text = f"""listen: 127.0.0.1:0
web:
  listen: "{web_listen}"
  max_message_bytes: 4096
  max_connections: 32
sources:
  - name: spot
    type: spot
    robot: 127.0.0.1:{mock_port}
    ca_file: {certs}/ca.pem
    credentials_file: {credentials}
    cameras: [frontleft_fisheye_image, frontright_fisheye_image, left_fisheye_image,
              right_fisheye_image, back_fisheye_image]
    rate_hz: 15
views:
  - {{name: front, type: perspective, source: spot, width: 320, height: 160, frame: footprint,
      pose: {{xyz: [0.42, 0, 0.52], ypr_deg: [0, 27, 0]}}, hfov_deg: 115, distance: 3.0, ground: true}}
  - {{name: birdseye, type: birdseye, source: spot, width: 240, height: 240, frame: footprint,
      pose: {{xyz: [0, 0, 0], ypr_deg: [0, 90, 0]}}, height_m: 3.0, hfov_deg: 110}}
"""
    if tokens:
        text += f"""tokens:
  - {{role: operator, token: "{OPERATOR_TOKEN}"}}
  - {{role: viewer, token: "{VIEWER_TOKEN}"}}
"""
    return text + extra


class Robot:
    """spot-mock and omniviewd in front of it; `with Robot(args) as r:` stops both."""

    def __init__(self, args, tokens=True, web_listen="127.0.0.1:0", extra="", edit_config=None, scene="test"):
        self.args = args
        self.dir = Path(tempfile.mkdtemp(prefix="omniview_web_"))
        self.tokens = tokens
        self.web_listen = web_listen
        self.extra = extra
        self.edit_config = edit_config or (lambda text: text)
        self.scene = scene
        self.mock = self.daemon = None

    def __enter__(self):
        certs = self.dir / "certs"
        credentials = self.dir / "credentials.yaml"
        mock_ready = self.dir / "mock_ready"
        self.mock_log = self.dir / "spot_mock.log"
        with self.mock_log.open("w") as log:
            self.mock = subprocess.Popen(
                [self.args.spot_mock, "--port", "0", "--certs", str(certs), "--credentials", str(credentials),
                 "--ready-file", str(mock_ready), "--scene", self.scene, "--supersample", "1"],
                stdout=log, stderr=subprocess.STDOUT)
        mock_address = wait_for_file(mock_ready, seconds(60), "spot-mock", self.mock_log).split()[0]
        self.mock_port = int(mock_address.rsplit(":", 1)[1])
        config = self.dir / "omniviewd.yaml"
        config.write_text(self.edit_config(daemon_config(self.mock_port, certs, credentials, self.tokens,
                                                         self.web_listen, self.extra.replace("DIR", str(self.dir)))))
        ready = self.dir / "ready"
        self.log = self.dir / "omniviewd.log"
        with self.log.open("w") as log:
            self.daemon = subprocess.Popen([self.args.omniviewd, "--config", str(config), "--ready-file", str(ready)],
                                           stdout=log, stderr=subprocess.STDOUT)
        lines = wait_for_file(ready, seconds(60), "omniviewd", self.log).split("\n")
        self.grpc = lines[0].strip()
        web = [l for l in lines if l.startswith("web ")]
        assert web, "the ready file names no web endpoint:\n" + "\n".join(lines)
        self.web = web[0].split()[1]
        return self

    def __exit__(self, *exc):
        self.stop()

    def alive(self):
        return self.daemon.poll() is None

    def stop(self):
        """Stops both; returns omniviewd's exit status (0: an orderly shutdown)."""
        code = None
        for p in (self.daemon, self.mock):
            if p and p.poll() is None:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(timeout=seconds(10))
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
        if self.daemon:
            code = self.daemon.returncode
        return code

    def cli(self, *args, token=OPERATOR_TOKEN):
        env = dict(os.environ, OMNIVIEW_SERVER=self.grpc)
        if token:
            env["OMNIVIEW_TOKEN"] = token
        r = subprocess.run([self.args.omniview, "--server", self.grpc, *args], env=env, capture_output=True,
                           text=True, timeout=seconds(30))
        assert r.returncode == 0, f"omniview {' '.join(args)}: {r.stdout}{r.stderr}"
        return r.stdout

    def yaw_pitch(self, view):
        """The view's yaw and pitch as the daemon holds them (through the CLI, over gRPC)."""
        text = self.cli("views", "get", view)
        ypr = (yaml.safe_load(text).get("pose") or {}).get("ypr_deg")
        assert ypr, "no pose.ypr_deg in:\n" + text
        return float(ypr[0]), float(ypr[1])

    def status(self):
        return self.cli("status")

    def mock_control(self, *args):
        """`spot-mock control ARGS` against this mock (faults: --set away=true, ...)."""
        r = subprocess.run([self.args.spot_mock, "control", "--port", str(self.mock_port), "--certs",
                            str(self.dir / "certs"), *args], capture_output=True, text=True, timeout=seconds(30))
        assert r.returncode == 0, r.stdout + r.stderr
        return r.stdout
