"""Bad input on omniviewd's web endpoint: oversized messages, garbage JSON, unknown ops,
methods and channels, malformed HTTP, and web listen addresses the exposure rule
refuses. Every refusal says what is wrong; the daemon keeps serving throughout."""
import asyncio
import json
import socket
import subprocess
import sys
import time
import unittest
import urllib.error
import urllib.request

import websockets

import harness
from harness import OPERATOR_TOKEN, VIEWER_TOKEN, seconds

ARGS = None


class BadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.robot = harness.Robot(ARGS).__enter__()

    @classmethod
    def tearDownClass(cls):
        assert cls.robot.stop() == 0, cls.robot.log.read_text()

    def tearDown(self):
        self.assertTrue(self.robot.alive(), "omniviewd died:\n" + self.robot.log.read_text())

    async def console(self, token=OPERATOR_TOKEN):
        ws = await websockets.connect(f"ws://{self.robot.web}/ws", subprotocols=["omniview.console.v1"],
                                      max_size=None)
        hello = json.loads(await ws.recv())
        self.assertEqual(hello["auth"], "required")
        await ws.send(json.dumps({"op": "auth", "id": 0, "token": token}))
        self.assertIn("response", json.loads(await ws.recv()))
        return ws

    async def reply(self, ws):
        while True:
            m = await asyncio.wait_for(ws.recv(), seconds(10))
            if isinstance(m, str):
                return json.loads(m)

    def test_console_garbage_unknown_ops_and_methods(self):
        async def go():
            ws = await self.console()
            cases = [
                ("{not json", "INVALID_ARGUMENT", "not a JSON object"),
                ("[1, 2]", "INVALID_ARGUMENT", "not a JSON object"),
                (json.dumps({"id": 1}), "INVALID_ARGUMENT", "no 'op'"),
                (json.dumps({"op": "dance", "id": 2}), "INVALID_ARGUMENT", "unknown op 'dance'"),
                (json.dumps({"op": "call", "id": 3, "method": "Shutdown"}), "UNIMPLEMENTED", "no method 'Shutdown'"),
                (json.dumps({"op": "call", "id": 4, "method": "GetView", "request": {"nmae": "front"}}),
                 "INVALID_ARGUMENT", "GetViewRequest"),
                (json.dumps({"op": "call", "id": 5, "method": "GetView", "request": {"name": "nope"}}),
                 "NOT_FOUND", "no view named 'nope'"),
                (json.dumps({"op": "call", "id": 6, "method": "UpdateView",
                             "request": {"name": "front", "set": {"hfovDeg": 500}}}), "INVALID_ARGUMENT", "hfov"),
                (json.dumps({"op": "call", "id": 7, "method": 12}), "INVALID_ARGUMENT", "'method' must be a string"),
                (json.dumps({"op": "subscribe", "id": 8, "view": "nope"}), "NOT_FOUND", "no view named 'nope'"),
                (json.dumps({"op": "subscribe", "id": 9, "view": "front", "quality": 1000}), "INVALID_ARGUMENT",
                 "quality"),
                (json.dumps({"op": "subscribe", "id": 10, "view": "front", "max_rate_hz": -1}), "INVALID_ARGUMENT",
                 "max_rate_hz"),
                (json.dumps({"op": "subscribe", "id": 14, "view": "front", "encoding": "VP9"}), "INVALID_ARGUMENT",
                 "JPEG, PNG, RAW or H264"),
                (json.dumps({"op": "subscribe", "id": 15, "view": "front", "max_bitrate_kbps": 500}),
                 "INVALID_ARGUMENT", "H264 streams only"),
                (json.dumps({"op": "subscribe", "id": 16, "view": "front", "encoding": "H264", "max_bitrate_kbps": 1}),
                 "INVALID_ARGUMENT", "max_bitrate_kbps must be"),
                (json.dumps({"op": "unsubscribe", "id": 11, "channel": 99}), "NOT_FOUND", "no channel 99"),
                (json.dumps({"op": "subscribe_cloud", "id": 12, "request": {"source": "nope"}}), "NOT_FOUND", "nope"),
                (json.dumps({"op": "call", "id": 13, "method": "GetView", "request": [1]}), "INVALID_ARGUMENT",
                 "'request' must be an object"),
            ]
            for text, code, words in cases:
                await ws.send(text)
                r = await self.reply(ws)
                self.assertIn("error", r, text)
                self.assertEqual(r["error"]["code"], code, f"{text}: {r}")
                self.assertIn(words, r["error"]["message"], text)
            await ws.send(b"\x00\x01binary")
            r = await self.reply(ws)
            self.assertIn("binary messages are not part", r["error"]["message"])
            # Still a working connection after all that.
            await ws.send(json.dumps({"op": "call", "id": 20, "method": "ListViews"}))
            r = await self.reply(ws)
            self.assertEqual(sorted(v["spec"]["name"] for v in r["response"]["views"]), ["birdseye", "front"])
            await ws.close()
        asyncio.run(go())

    def test_numbers_beyond_double_range_get_an_error_before_any_token(self):
        # Once ended the daemon (an exception nlohmann throws as out_of_range, not parse_error),
        # from a connection that had sent no token.
        bad = ['{"op": 1e400}', '{"op": "auth", "id": -1e309}', '{"a": {"b": [1, 1e400]}}']
        async def go():
            for subprotocols in (["omniview.console.v1"], None):
                ws = await websockets.connect(f"ws://{self.robot.web}/ws", subprotocols=subprotocols)
                self.assertEqual(json.loads(await ws.recv())["auth"], "required")
                for text in bad:
                    await ws.send(text)
                    r = await self.reply(ws)
                    self.assertEqual(r["error"]["code"], "INVALID_ARGUMENT", text)
                    self.assertIn("not a JSON object", r["error"]["message"], text)
                await ws.send(json.dumps({"op": "auth", "id": 1, "token": VIEWER_TOKEN}))
                self.assertIn("response", await self.reply(ws))  # the connection still works
                await ws.close()
            fox = await websockets.connect(f"ws://{self.robot.web}/?token={VIEWER_TOKEN}",
                                           subprotocols=["foxglove.sdk.v1"], max_size=None)
            for text in bad:
                await fox.send(text)
                while True:
                    m = json.loads(await asyncio.wait_for(fox.recv(), seconds(10)))
                    if m["op"] == "status":
                        break
                self.assertEqual(m["level"], 2)
                self.assertIn("not a JSON object", m["message"])
            await fox.close()
        asyncio.run(go())

    def test_every_token_a_request_carries_must_be_valid(self):
        # A good header token beside a wrong ?token= is refused (401), as docs/API.md says.
        async def go(path, headers):
            ws = await websockets.connect(f"ws://{self.robot.web}{path}", subprotocols=["foxglove.sdk.v1"],
                                          extra_headers=headers)
            await ws.close()
        with self.assertRaises(websockets.exceptions.InvalidStatusCode) as e:
            asyncio.run(go("/?token=wrong", {"Authorization": f"Bearer {VIEWER_TOKEN}"}))
        self.assertEqual(e.exception.status_code, 401)
        with self.assertRaises(websockets.exceptions.InvalidStatusCode) as e:
            asyncio.run(go(f"/?token={VIEWER_TOKEN}", {"Authorization": "Bearer wrong"}))
        self.assertEqual(e.exception.status_code, 401)
        asyncio.run(go(f"/?token={VIEWER_TOKEN}", {"Authorization": f"Bearer {OPERATOR_TOKEN}"}))  # both good
        # A '+' not percent-encoded reads as a space: the refusal says how to write the token.
        host, port = self.robot.web.rsplit(":", 1)
        with socket.create_connection((host, int(port)), timeout=seconds(5)) as s:
            s.sendall(b"GET /?token=ab+cd/e= HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                      b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                      b"Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n")
            answer = b""
            while b"%2B" not in answer:
                chunk = s.recv(4096)
                if not chunk:
                    break
                answer += chunk
            self.assertTrue(answer.startswith(b"HTTP/1.1 401"), answer)
            self.assertIn(b"percent-encode", answer)

    def test_http11_needs_exactly_one_host(self):
        host, port = self.robot.web.rsplit(":", 1)
        for raw, status in ((b"GET / HTTP/1.1\r\n\r\n", b"400"),
                            (b"GET / HTTP/1.1\r\nHost: a\r\nHost: b\r\n\r\n", b"400"),
                            (b"GET / HTTP/1.0\r\n\r\n", b"200"),  # HTTP/1.0 has no Host rule
                            (b"GET / HTTP/1.1\r\nHost: a\r\n\r\n", b"200")):
            with socket.create_connection((host, int(port)), timeout=seconds(5)) as s:
                s.sendall(raw)
                answer = s.recv(64)
                self.assertTrue(answer.split(b" ")[1] == status, (raw, answer))

    def test_oversized_messages_close_with_1009(self):
        async def go():
            for protocol, path in (("omniview.console.v1", "/ws"), ("foxglove.websocket.v1", "/")):
                ws = await websockets.connect(f"ws://{self.robot.web}{path}?token={VIEWER_TOKEN}",
                                              subprotocols=[protocol], max_size=None)
                await ws.recv()
                await ws.send(json.dumps({"op": "call", "pad": "x" * 10000}))  # web.max_message_bytes is 4096
                with self.assertRaises(websockets.exceptions.ConnectionClosed) as closed:
                    while True:
                        await asyncio.wait_for(ws.recv(), seconds(10))
                self.assertEqual(closed.exception.rcvd.code, 1009, protocol)
        asyncio.run(go())
        self.assertIn("over web.max_message_bytes", self.robot.log.read_text())

    def test_viewer_cannot_steer_and_unauthenticated_cannot_call(self):
        async def go():
            ws = await self.console(VIEWER_TOKEN)
            await ws.send(json.dumps({"op": "call", "id": 1, "method": "UpdateView",
                                      "request": {"name": "front", "delta": {"yawDeg": 5}}}))
            r = await self.reply(ws)
            self.assertEqual(r["error"]["code"], "PERMISSION_DENIED")
            await ws.close()
            bare = await websockets.connect(f"ws://{self.robot.web}/ws", subprotocols=["omniview.console.v1"])
            await bare.recv()
            await bare.send(json.dumps({"op": "call", "id": 1, "method": "ListViews"}))
            self.assertEqual((await self.reply(bare))["error"]["code"], "UNAUTHENTICATED")
            await bare.send(json.dumps({"op": "auth", "id": 2, "token": "wrong"}))
            self.assertEqual((await self.reply(bare))["error"]["message"], "unknown token")
            with self.assertRaises(websockets.exceptions.ConnectionClosed) as closed:
                await asyncio.wait_for(bare.recv(), seconds(5))
            self.assertEqual(closed.exception.rcvd.code, 1008)
        asyncio.run(go())

    def test_foxglove_bad_input_gets_status_errors(self):
        async def go():
            ws = await websockets.connect(f"ws://{self.robot.web}/?token={VIEWER_TOKEN}",
                                          subprotocols=["foxglove.sdk.v1"], max_size=None)
            await ws.recv()
            advertise = json.loads(await ws.recv())
            image = next(c["id"] for c in advertise["channels"] if c["topic"] == "/front/image")
            cases = [
                ("{garbage", "not a JSON object"),
                (json.dumps({"op": "advertise", "channels": []}), "not supported"),
                (json.dumps({"op": "subscribe", "subscriptions": [{"id": 1, "channelId": 4242}]}), "no channel 4242"),
                (json.dumps({"op": "subscribe", "subscriptions": "all"}), "'subscriptions' list"),
                (json.dumps({"op": "subscribe", "subscriptions": [{"id": 2}]}), "needs 'id' and 'channelId'"),
                (json.dumps({"op": "unsubscribe", "subscriptionIds": [77]}), "no subscription 77"),
            ]
            for text, words in cases:
                await ws.send(text)
                m = json.loads(await asyncio.wait_for(ws.recv(), seconds(5)))
                self.assertEqual(m["op"], "status", text)
                self.assertIn(words, m["message"], text)
            await ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 3, "channelId": image}]}))
            await ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 3, "channelId": image}]}))
            while True:  # frames of subscription 3 may come first
                m = await asyncio.wait_for(ws.recv(), seconds(10))
                if isinstance(m, str):
                    self.assertIn("already in use", json.loads(m)["message"])
                    break
            await ws.close()
        asyncio.run(go())

    def test_http_bad_requests(self):
        base = f"http://{self.robot.web}"
        for path, code in (("/%2e%2e/%2e%2e/etc/passwd", 400), ("/no/such/file.js", 404), ("/%zz", 400)):
            with self.assertRaises(urllib.error.HTTPError) as e:
                urllib.request.urlopen(base + path, timeout=seconds(5))
            self.assertEqual(e.exception.code, code, path)
        with self.assertRaises(urllib.error.HTTPError) as e:
            urllib.request.urlopen(urllib.request.Request(base + "/", data=b"x", method="POST"), timeout=seconds(5))
        self.assertEqual(e.exception.code, 405)
        # A raw request with a header far over the limit, and plain garbage.
        host, port = self.robot.web.rsplit(":", 1)
        for raw in (b"GET / HTTP/1.1\r\nX: " + b"a" * 20000 + b"\r\n\r\n", b"\x16\x03\x01garbage\r\n\r\n"):
            with socket.create_connection((host, int(port)), timeout=seconds(5)) as s:
                s.sendall(raw)
                answer = s.recv(200)
                self.assertTrue(answer.startswith(b"HTTP/1.1 4"), answer)
        # An unknown subprotocol is refused with the ones served named.
        async def unknown_subprotocol():
            await websockets.connect(f"ws://{self.robot.web}/", subprotocols=["mqtt"])
        with self.assertRaises(websockets.exceptions.InvalidStatusCode) as e:
            asyncio.run(unknown_subprotocol())
        self.assertEqual(e.exception.status_code, 400)
        with urllib.request.urlopen(base + "/", timeout=seconds(5)) as r:
            self.assertIn(b"omniview console", r.read())

    def test_head_says_the_length_and_sends_no_body(self):
        # Each HEAD is followed on the same connection by a GET, sent at once: a body after
        # the HEAD's headers would be read as the start of the GET's reply. (A raw socket:
        # http.client drops what arrived with a HEAD reply's headers, so it would not see it.)
        host, port = self.robot.web.rsplit(":", 1)
        with urllib.request.urlopen(f"http://{self.robot.web}/", timeout=seconds(5)) as r:
            page = r.read()
        for path, code, length in (("/", 200, len(page)), ("/no/such/file.js", 404, len(b"not found\n")),
                                   ("/%zz", 400, len(b"bad path\n"))):
            with socket.create_connection((host, int(port)), timeout=seconds(5)) as s:
                s.sendall(f"HEAD {path} HTTP/1.1\r\nHost: x\r\n\r\nGET / HTTP/1.1\r\nHost: x\r\n\r\n".encode())
                received = b""
                while not received.endswith(page):
                    chunk = s.recv(65536)
                    self.assertTrue(chunk, f"{path}: closed after {received[:300]!r}")
                    received += chunk
            head, rest = received.split(b"\r\n\r\n", 1)
            self.assertTrue(head.startswith(f"HTTP/1.1 {code} ".encode()), head)
            self.assertIn(f"\r\nContent-Length: {length}\r\n".encode(), head + b"\r\n")
            self.assertTrue(rest.startswith(b"HTTP/1.1 200 "), f"{path}: after the HEAD reply's headers: {rest[:60]!r}")

    def test_a_client_that_never_reads_slows_nobody(self):
        host, port = self.robot.web.rsplit(":", 1)
        stalled = socket.socket()
        stalled.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        stalled.settimeout(seconds(5))
        stalled.connect((host, int(port)))
        stalled.sendall(("GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                         f"Authorization: Bearer {VIEWER_TOKEN}\r\n\r\n").encode())
        answer = b""
        while b"\r\n\r\n" not in answer:
            answer += stalled.recv(1)
        self.assertTrue(answer.startswith(b"HTTP/1.1 101"), answer)
        # One masked text frame (clients must mask): subscribe to RAW frames, then never read.
        payload = json.dumps({"op": "subscribe", "id": 1, "view": "front", "encoding": "RAW"}).encode()
        mask = b"\x01\x02\x03\x04"
        stalled.sendall(bytes([0x81, 0x80 | len(payload)]) + mask +
                        bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

        async def go():
            ws = await self.console(VIEWER_TOKEN)
            await asyncio.sleep(seconds(3))  # the stalled socket's buffers fill up
            await ws.send(json.dumps({"op": "subscribe", "id": 2, "view": "front"}))
            await self.reply(ws)
            t0, n = time.monotonic(), 0
            while time.monotonic() - t0 < 2:
                if isinstance(await asyncio.wait_for(ws.recv(), seconds(5)), bytes):
                    n += 1
            rate = n / (time.monotonic() - t0)
            await ws.send(json.dumps({"op": "call", "id": 3, "method": "GetStatus"}))
            status = (await self.reply(ws))["response"]
            await ws.close()
            return rate, status
        rate, status = asyncio.run(go())
        stalled.close()
        self.assertGreater(rate, 10 / harness.time_scale(), "a reading client keeps the robot's 15 Hz")
        raw = [c for c in status["clients"] if c["encoding"] == "raw"]
        self.assertEqual(len(raw), 1, status["clients"])
        self.assertGreater(int(raw[0]["framesDropped"]), 10, "the stalled client's frames are dropped, not queued")
        print(f"beside a stalled client: {rate:.1f} fps; the stalled one sent {raw[0]['framesSent']}, "
              f"dropped {raw[0]['framesDropped']}", file=sys.stderr)

    def test_connections_beyond_the_limit_are_closed(self):
        host, port = self.robot.web.rsplit(":", 1)
        held = [socket.create_connection((host, int(port)), timeout=seconds(5)) for _ in range(40)]
        answered = 0
        try:
            for s in held:
                s.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
            for s in held:
                try:
                    answered += s.recv(12).startswith(b"HTTP/1.1 200")
                except ConnectionResetError:
                    pass
        finally:
            for s in held:
                s.close()
        self.assertLessEqual(answered, 32, "web.max_connections is 32")
        self.assertGreaterEqual(answered, 28, "the others were served")
        self.assertIn("web.max_connections (32) reached", self.robot.log.read_text())
        # The places come back once those connections close.
        deadline = time.monotonic() + seconds(5)
        while True:
            try:
                with urllib.request.urlopen(f"http://{self.robot.web}/", timeout=seconds(5)) as r:
                    if r.status == 200:
                        break
            except (urllib.error.URLError, ConnectionError):
                pass
            self.assertLess(time.monotonic(), deadline, "served again once the others closed")
            time.sleep(0.1)

    def test_non_loopback_web_without_tls_is_refused_at_start(self):
        d = self.robot.dir
        for listen, tokens in (("0.0.0.0:0", False), ("0.0.0.0:0", True), ("[::]:0", True)):
            config = d / "exposed.yaml"
            config.write_text(harness.daemon_config(self.robot.mock_port, d / "certs", d / "credentials.yaml",
                                                    tokens=tokens, web_listen=listen))
            for mode in (["--check"], ["--ready-file", str(d / "never")]):
                r = subprocess.run([ARGS.omniviewd, "--config", str(config), *mode], capture_output=True, text=True,
                                   timeout=seconds(30))
                self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
                self.assertIn(f"{config}:3: web.listen:", r.stderr)
                self.assertIn("reachable from other machines", r.stderr)
        # The running daemon's web port: in use.
        config.write_text(harness.daemon_config(self.robot.mock_port, d / "certs", d / "credentials.yaml",
                                                web_listen=self.robot.web))
        r = subprocess.run([ARGS.omniviewd, "--config", str(config), "--ready-file", str(d / "never")],
                           capture_output=True, text=True, timeout=seconds(30))
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn(f"{config}:3: web.listen: cannot listen on '{self.robot.web}'", r.stderr)
        config.write_text(harness.daemon_config(self.robot.mock_port, d / "certs", d / "credentials.yaml",
                                                web_listen="127.0.0.1:0", extra="  \nweb_typo: 1\n"))
        r = subprocess.run([ARGS.omniviewd, "--config", str(config), "--check"], capture_output=True, text=True,
                           timeout=seconds(30))
        self.assertEqual(r.returncode, 1)
        self.assertIn("web_typo", r.stderr)


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
