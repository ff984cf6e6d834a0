"""The Foxglove WebSocket protocol on omniviewd's web endpoint, spoken by a Python client
(python3-websockets) against the real daemon in front of spot-mock: serverInfo, advertise,
subscribe, messages decoded with the advertised protobuf schemas (the H.264 channel also by
ffmpeg), unsubscribe."""
import asyncio
import base64
import json
import struct
import subprocess
import sys
import time
import unittest

import websockets
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

import harness
from harness import OPERATOR_TOKEN, VIEWER_TOKEN, seconds

ARGS = None


def decoder(channel):
    """A message class for `channel`, built from its advertised FileDescriptorSet alone."""
    assert channel["encoding"] == "protobuf"
    assert channel["schemaEncoding"] == "protobuf"
    files = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(channel["schema"]))
    pool = descriptor_pool.DescriptorPool()
    for f in files.file:
        pool.Add(f)
    return message_factory.MessageFactory(pool).GetPrototype(pool.FindMessageTypeByName(channel["schemaName"]))


def message_data(raw):
    assert raw[0] == 1, f"opcode {raw[0]}, expected messageData (1)"
    subscription, stamp = struct.unpack_from("<IQ", raw, 1)
    return subscription, stamp, raw[13:]


class Client:
    def __init__(self, url, protocol="foxglove.websocket.v1"):
        self.url = url
        self.protocol = protocol

    async def __aenter__(self):
        self.ws = await websockets.connect(self.url, subprotocols=[self.protocol], max_size=None)
        self.server_info = json.loads(await self.ws.recv())
        self.advertise = json.loads(await self.ws.recv())
        self.channels = {c["topic"]: c for c in self.advertise["channels"]}
        return self

    async def __aexit__(self, *exc):
        await self.ws.close()

    async def subscribe(self, *subs):
        await self.ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": sid, "channelId": self.channels[topic]["id"]} for sid, topic in subs]}))

    async def next(self, subscription, timeout):
        """The next message of `subscription` (text messages: returned as dicts)."""
        deadline = time.monotonic() + timeout
        while True:
            raw = await asyncio.wait_for(self.ws.recv(), max(0.01, deadline - time.monotonic()))
            if isinstance(raw, str):
                msg = json.loads(raw)
                if msg.get("op") == "status" and msg.get("level", 0) >= 2:
                    raise AssertionError("status error: " + msg["message"])
                continue
            sid, stamp, payload = message_data(raw)
            if sid == subscription:
                return stamp, payload


def nal_types(unit):
    """The NAL unit types of an Annex-B access unit, in order."""
    return [unit[i + 3] & 0x1F for i in range(len(unit) - 3) if unit[i:i + 3] == b"\0\0\1"]


def run(coroutine):
    return asyncio.run(coroutine)


class FoxgloveProtocolTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.robot = harness.Robot(ARGS).__enter__()
        cls.url = f"ws://{cls.robot.web}/?token={OPERATOR_TOKEN.replace('+', '%2B').replace('/', '%2F').replace('=', '%3D')}"

    @classmethod
    def tearDownClass(cls):
        assert cls.robot.stop() == 0, cls.robot.log.read_text()

    def test_server_info_and_advertise(self):
        async def go():
            for protocol in ("foxglove.sdk.v1", "foxglove.websocket.v1"):
                async with Client(self.url, protocol) as c:
                    self.assertEqual(c.ws.subprotocol, protocol, "answers with the subprotocol offered")
                    self.assertEqual(c.server_info["op"], "serverInfo")
                    self.assertIn("omniviewd", c.server_info["name"])
                    self.assertEqual(c.advertise["op"], "advertise")
                    schemas = {t: ch["schemaName"] for t, ch in c.channels.items()}
                    self.assertEqual(schemas["/front/image"], "foxglove.CompressedImage")
                    self.assertEqual(schemas["/front/video"], "foxglove.CompressedVideo")
                    self.assertEqual(schemas["/front/calibration"], "foxglove.CameraCalibration")
                    self.assertEqual(schemas["/birdseye/image"], "foxglove.CompressedImage")
                    self.assertEqual(schemas["/spot/cloud"], "foxglove.PointCloud")
                    self.assertEqual(schemas["/tf"], "foxglove.FrameTransforms")
        run(go())

    def test_messages_decode_with_the_advertised_schemas(self):
        async def go():
            async with Client(self.url) as c:
                await c.subscribe((1, "/front/image"), (2, "/front/calibration"), (3, "/tf"))
                Image = decoder(c.channels["/front/image"])
                stamp, payload = await c.next(1, seconds(15))
                image = Image.FromString(payload)
                self.assertEqual(image.format, "jpeg")
                self.assertEqual(image.data[:2], b"\xff\xd8")
                self.assertEqual(image.frame_id, "view/front/optical")
                self.assertEqual(stamp, image.timestamp.seconds * 10**9 + image.timestamp.nanos)
                self.assertLess(abs(time.time() - stamp / 1e9), seconds(5), "capture time is now-ish")
                Calibration = decoder(c.channels["/front/calibration"])
                calibration = Calibration.FromString((await c.next(2, seconds(5)))[1])
                self.assertEqual((calibration.width, calibration.height), (320, 160))
                self.assertEqual(len(calibration.K), 9)
                self.assertAlmostEqual(calibration.K[2], 159.5)
                self.assertGreater(calibration.K[0], 50)
                self.assertEqual(len(calibration.P), 12)
                self.assertEqual(calibration.frame_id, image.frame_id)
                Transforms = decoder(c.channels["/tf"])
                tf = Transforms.FromString((await c.next(3, seconds(5)))[1])
                children = {t.child_frame_id: t.parent_frame_id for t in tf.transforms}
                self.assertEqual(children["view/front/optical"], "view/front")
                self.assertIn("view/front", children)
                self.assertIn("frontleft_fisheye", children)
        run(go())

    def test_a_view_named_like_a_robot_frame_keeps_its_transforms(self):
        """Spot's rig has a frame `back`: a view `back` must not take its place in /tf, and
        its images' and calibration's frame has a chain of transforms to the robot's root."""
        async def go():
            async with Client(self.url) as c:
                Transforms = decoder(c.channels["/tf"])
                await c.subscribe((20, "/tf"))
                # /tf comes once a second; the robot's frames once the daemon has its rig (under a
                # sanitizer the login may still be under way when the test starts).
                before, deadline = {}, time.monotonic() + seconds(15)
                while "back" not in before and time.monotonic() < deadline:
                    before = {t.child_frame_id: t.parent_frame_id
                              for t in Transforms.FromString((await c.next(20, seconds(5)))[1]).transforms}
                self.assertIn("back", before, "the rig has a frame named as the view")
                self.robot.cli("views", "create", "--set", "name=back", "--set", "type=perspective",
                               "--set", "source=spot", "--set", "width=64", "--set", "height=48")
                try:
                    new = None
                    while not new:
                        raw = await asyncio.wait_for(c.ws.recv(), seconds(5))
                        if isinstance(raw, str) and json.loads(raw)["op"] == "advertise":  # /tf's are bytes
                            new = {ch["topic"]: ch for ch in json.loads(raw)["channels"]}
                    c.channels.update(new)
                    await c.subscribe((21, "/back/image"), (22, "/back/calibration"))
                    image = decoder(c.channels["/back/image"]).FromString((await c.next(21, seconds(15)))[1])
                    calibration = decoder(c.channels["/back/calibration"]).FromString(
                        (await c.next(22, seconds(5)))[1])
                    tf = Transforms.FromString((await c.next(20, seconds(5)))[1])
                finally:
                    self.robot.cli("views", "delete", "back")
                self.assertEqual(image.frame_id, "view/back/optical")
                self.assertEqual(calibration.frame_id, image.frame_id)
                parents = {t.child_frame_id: t.parent_frame_id for t in tf.transforms}
                for child, parent in before.items():
                    self.assertEqual(parents.get(child), parent, f"the robot's {child} keeps its parent")
                self.assertEqual(parents["view/back/optical"], "view/back")
                roots = set(parents.values()) - set(parents)
                self.assertEqual(len(roots), 1, f"one tree: {roots}")
                for frame in (image.frame_id, "view/front/optical", "view/birdseye/optical"):
                    chain = [frame]
                    while chain[-1] in parents and len(chain) < 50:
                        chain.append(parents[chain[-1]])
                    self.assertIn(chain[-1], roots, f"{frame} reaches the robot's root: {chain}")
        run(go())

    def test_video_starts_at_a_key_frame_and_decodes(self):
        async def go():
            async with Client(self.url) as c:
                # The JPEG channel beside it: both served at once, each its own encoding.
                await c.subscribe((11, "/front/video"), (12, "/front/image"))
                Video = decoder(c.channels["/front/video"])
                units = []
                for _ in range(10):
                    stamp, payload = await c.next(11, seconds(15))
                    video = Video.FromString(payload)
                    self.assertEqual(video.format, "h264")
                    self.assertEqual(video.frame_id, "view/front/optical")
                    self.assertEqual(stamp, video.timestamp.seconds * 10**9 + video.timestamp.nanos)
                    units.append(video.data)
                self.assertEqual(units[0][:4], b"\0\0\0\1", "Annex-B")
                types = [nal_types(u) for u in units]
                self.assertTrue({7, 8, 5} <= set(types[0]), f"first message a key frame with SPS/PPS: {types[0]}")
                self.assertTrue(all(5 not in t for t in types[1:3]), f"then delta frames: {types[:3]}")
                image = decoder(c.channels["/front/image"]).FromString(
                    (await c.next(12, seconds(5)))[1])
                self.assertEqual(image.format, "jpeg")
            # A real decoder takes the stream from its first message, every frame 320x160.
            out = subprocess.run(["ffmpeg", "-v", "error", "-f", "h264", "-i", "-", "-f", "rawvideo",
                                  "-pix_fmt", "gray", "-"], input=b"".join(units), capture_output=True,
                                 timeout=seconds(20))
            self.assertEqual(out.returncode, 0, out.stderr.decode())
            self.assertEqual(out.stderr, b"", "decodes without errors")
            self.assertEqual(len(out.stdout), 10 * 320 * 160)
            probe = subprocess.run(["ffprobe", "-v", "error", "-f", "h264", "-show_entries", "stream=width,height",
                                    "-of", "csv=p=0", "-"], input=b"".join(units), capture_output=True,
                                   timeout=seconds(20))
            self.assertEqual(probe.stdout.decode().strip(), "320,160")
        run(go())

    def test_cloud_decodes_and_never_holds_a_view_back(self):
        async def go():
            async with Client(self.url) as c:
                await c.subscribe((7, "/spot/cloud"), (8, "/front/image"))
                Cloud = decoder(c.channels["/spot/cloud"])
                cloud = Cloud.FromString((await c.next(7, seconds(20)))[1])
                fields = {f.name: (f.offset, f.type) for f in cloud.fields}
                Field = cloud.fields[0].__class__
                float32, uint8 = Field.NumericType.Value("FLOAT32"), Field.NumericType.Value("UINT8")
                for n in ("x", "y", "z"):
                    self.assertEqual(fields[n][1], float32, n)
                # The names Foxglove's 3D panel colours points by (all four), beside the extras.
                for n in ("red", "green", "blue", "alpha", "flags", "camera"):
                    self.assertEqual(fields[n][1], uint8, n)
                for n in ("r", "g", "b"):
                    self.assertNotIn(n, fields)
                self.assertEqual(cloud.point_stride, 18)
                self.assertGreater(len(cloud.data), 1000 * 18)
                self.assertEqual(len(cloud.data) % cloud.point_stride, 0)
                alpha, flags = fields["alpha"][0], fields["flags"][0]
                # Coloured points (flags bit 0) within a few clouds (the first may precede the images).
                deadline = time.monotonic() + seconds(10)
                while True:
                    n = len(cloud.data) // cloud.point_stride
                    self.assertTrue(all(cloud.data[i * 18 + alpha] == 255 for i in range(n)), "opaque points")
                    if any(cloud.data[i * 18 + flags] & 1 for i in range(n)):
                        break
                    self.assertLess(time.monotonic(), deadline, "a cloud with coloured points")
                    cloud = Cloud.FromString((await c.next(7, seconds(5)))[1])
                # With the cloud streaming, the view still comes at the robot's rate.
                t0 = time.monotonic()
                n = 0
                while time.monotonic() - t0 < 2.0:
                    await c.next(8, seconds(5))
                    n += 1
                rate = n / (time.monotonic() - t0)
                print(f"front image at {rate:.1f} Hz beside the cloud", file=sys.stderr)
                self.assertGreater(rate, 8 / harness.time_scale())
        run(go())

    def test_unsubscribe_stops_the_view(self):
        async def go():
            async with Client(self.url) as c:
                await c.subscribe((5, "/birdseye/image"))
                await c.next(5, seconds(15))
                self.assertIn("(foxglove)", self.robot.status())
                await c.ws.send(json.dumps({"op": "unsubscribe", "subscriptionIds": [5]}))
                deadline = time.monotonic() + seconds(5)
                while "(foxglove)" in self.robot.status():
                    self.assertLess(time.monotonic(), deadline, "the subscriber left GetStatus")
                    await asyncio.sleep(0.1)
        run(go())

    def test_views_created_and_deleted_are_advertised(self):
        async def go():
            async with Client(self.url) as c:
                self.robot.cli("views", "create", "--set", "name=side", "--set", "type=perspective",
                               "--set", "source=spot", "--set", "width=64", "--set", "height=48")
                try:
                    new = None
                    while not new:
                        msg = json.loads(await asyncio.wait_for(c.ws.recv(), seconds(5)))
                        if msg["op"] == "advertise":
                            new = {ch["topic"]: ch for ch in msg["channels"]}
                    self.assertEqual(sorted(new), ["/side/calibration", "/side/image", "/side/video"])
                    await c.ws.send(json.dumps({"op": "subscribe", "subscriptions": [
                        {"id": 9, "channelId": new["/side/image"]["id"]}]}))
                finally:
                    self.robot.cli("views", "delete", "side")
                while True:
                    raw = await asyncio.wait_for(c.ws.recv(), seconds(5))
                    if isinstance(raw, str) and json.loads(raw)["op"] == "unadvertise":
                        self.assertEqual(sorted(json.loads(raw)["channelIds"]),
                                         sorted(ch["id"] for ch in new.values()))
                        break
        run(go())

    def test_a_view_of_odd_size_has_a_video_channel_too(self):
        async def go():
            async with Client(self.url) as c:
                # Coded one pixel larger, its edge repeated (issue 29): video as for any view.
                self.robot.cli("views", "create", "--set", "name=odd", "--set", "type=perspective",
                               "--set", "source=spot", "--set", "width=65", "--set", "height=48")
                try:
                    new = None
                    while not new:
                        msg = json.loads(await asyncio.wait_for(c.ws.recv(), seconds(5)))
                        if msg["op"] == "advertise":
                            new = {ch["topic"] for ch in msg["channels"]}
                    self.assertEqual(sorted(new), ["/odd/calibration", "/odd/image", "/odd/video"])
                finally:
                    self.robot.cli("views", "delete", "odd")
        run(go())

    def test_tokens_are_required_and_roles_reported(self):
        async def go():
            bare = f"ws://{self.robot.web}/"
            with self.assertRaises(websockets.exceptions.InvalidStatusCode) as refused:
                await websockets.connect(bare, subprotocols=["foxglove.websocket.v1"])
            self.assertEqual(refused.exception.status_code, 401)
            with self.assertRaises(websockets.exceptions.InvalidStatusCode) as wrong:
                await websockets.connect(bare + "?token=wrong", subprotocols=["foxglove.websocket.v1"])
            self.assertEqual(wrong.exception.status_code, 401)
            async with Client(bare + "?token=" + VIEWER_TOKEN) as c:
                self.assertEqual(c.server_info["metadata"]["role"], "viewer")
            # The header works too, for clients that can set one.
            async with websockets.connect(bare, subprotocols=["foxglove.sdk.v1"],
                                          extra_headers={"Authorization": "Bearer " + VIEWER_TOKEN}) as ws:
                self.assertEqual(json.loads(await ws.recv())["op"], "serverInfo")
        run(go())


if __name__ == "__main__":
    ARGS, rest = harness.programs()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
