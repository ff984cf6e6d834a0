"""The web endpoint with the gRPC API's TLS certificate, on every interface (allowed: TLS
and tokens): HTTPS and WSS work for a client trusting the CA, plaintext gets nothing."""
import asyncio
import json
import socket
import ssl
import subprocess
import sys
import unittest
import urllib.request
from pathlib import Path

import websockets

import harness
from harness import OPERATOR_TOKEN, seconds

ARGS = None
SCRIPTS = Path(__file__).resolve().parents[2] / "scripts"


class TlsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        robot = harness.Robot(ARGS, web_listen="0.0.0.0:0",
                              extra="tls: {cert: DIR/tls/server.crt, key: DIR/tls/server.key}\n")
        subprocess.run(["bash", str(SCRIPTS / "make-test-certs.sh"), str(robot.dir / "tls")], check=True,
                       capture_output=True)
        cls.robot = robot.__enter__()
        cls.port = int(cls.robot.web.rsplit(":", 1)[1])
        cls.tls = ssl.create_default_context(cafile=str(robot.dir / "tls" / "ca.crt"))

    @classmethod
    def tearDownClass(cls):
        assert cls.robot.stop() == 0, cls.robot.log.read_text()

    def test_https_and_wss(self):
        self.assertIn(f"https://0.0.0.0:{self.port}/", self.robot.log.read_text())
        with urllib.request.urlopen(f"https://localhost:{self.port}/", context=self.tls, timeout=seconds(5)) as r:
            self.assertIn(b"omniview console", r.read())

        async def go():
            async with websockets.connect(f"wss://localhost:{self.port}/ws", ssl=self.tls,
                                          subprotocols=["omniview.console.v1"],
                                          extra_headers={"Authorization": "Bearer " + OPERATOR_TOKEN}) as ws:
                self.assertEqual(json.loads(await ws.recv())["role"], "operator")
                await ws.send(json.dumps({"op": "call", "id": 1, "method": "ListViews"}))
                self.assertEqual(len(json.loads(await ws.recv())["response"]["views"]), 2)
            async with websockets.connect(f"wss://localhost:{self.port}/?token={OPERATOR_TOKEN.replace('+', '%2B')}",
                                          ssl=self.tls, subprotocols=["foxglove.sdk.v1"]) as ws:
                self.assertEqual(json.loads(await ws.recv())["op"], "serverInfo")
        asyncio.run(go())

    def test_plaintext_gets_nothing(self):
        with socket.create_connection(("127.0.0.1", self.port), timeout=seconds(5)) as s:
            s.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
            try:
                answer = s.recv(100)
            except ConnectionResetError:
                answer = b""
            self.assertFalse(answer.startswith(b"HTTP/"), answer)
        self.assertTrue(self.robot.alive())


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
