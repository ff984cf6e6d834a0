#!/usr/bin/env python3
"""Save frames of an omniview view as image files, with Debian's python3-grpcio.

    python3 save_frames.py front --frames 10 -o frames/
    python3 save_frames.py front --server robot:50051 --tls-ca ca.crt --token-file viewer.token

The Python gRPC modules are generated from proto/ on first use (protoc and
grpc_python_plugin, Debian packages protobuf-compiler and protobuf-compiler-grpc) and
cached under ~/.cache/omniview-python/.
"""
import argparse
import hashlib
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

import grpc

PROTO_ROOT = pathlib.Path(__file__).resolve().parents[2] / "proto"
PROTO_FILE = PROTO_ROOT / "omniview" / "v1" / "omniview.proto"


def load_api():
    """Generates omniview_pb2(_grpc).py for this version of the proto, once, and imports them."""
    digest = hashlib.sha256(PROTO_FILE.read_bytes()).hexdigest()[:16]
    cache_root = pathlib.Path(os.environ.get("XDG_CACHE_HOME", pathlib.Path.home() / ".cache"))
    cache = cache_root / "omniview-python" / digest
    if not cache.exists():
        cache.parent.mkdir(parents=True, exist_ok=True)
        staging = tempfile.mkdtemp(dir=cache.parent)  # renamed into place when complete
        subprocess.run(["protoc", f"--proto_path={PROTO_ROOT}", f"--python_out={staging}",
                        f"--grpc_python_out={staging}",
                        "--plugin=protoc-gen-grpc_python=/usr/bin/grpc_python_plugin", str(PROTO_FILE)],
                       check=True)
        try:
            os.rename(staging, cache)
        except OSError:  # another run got there first
            shutil.rmtree(staging)
    sys.path.insert(0, str(cache))
    from omniview.v1 import omniview_pb2, omniview_pb2_grpc
    return omniview_pb2, omniview_pb2_grpc


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("view")
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("-o", "--output", default="frames")
    parser.add_argument("--encoding", choices=["jpg", "png"], default="jpg")
    parser.add_argument("--server", default=os.environ.get("OMNIVIEW_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--tls-ca", help="CA certificate (PEM): connect with TLS")
    parser.add_argument("--token-file", help="access token (default: $OMNIVIEW_TOKEN)")
    args = parser.parse_args()

    pb, pb_grpc = load_api()
    options = [("grpc.max_receive_message_length", 256 << 20)]  # big views make big frames
    if args.tls_ca:
        credentials = grpc.ssl_channel_credentials(pathlib.Path(args.tls_ca).read_bytes())
        channel = grpc.secure_channel(args.server, credentials, options)
    else:
        channel = grpc.insecure_channel(args.server, options)
    token = pathlib.Path(args.token_file).read_text().strip() if args.token_file else os.environ.get("OMNIVIEW_TOKEN")
    metadata = [("authorization", f"Bearer {token}")] if token else []

    request = pb.StreamFramesRequest(view=args.view, encoding=pb.JPEG if args.encoding == "jpg" else pb.PNG)
    out = pathlib.Path(args.output)
    stream = pb_grpc.OmniviewStub(channel).StreamFrames(request, metadata=metadata)
    saved = 0
    try:
        for frame in stream:
            saved += 1
            out.mkdir(parents=True, exist_ok=True)
            path = out / f"frame_{saved:06d}.{args.encoding}"
            path.write_bytes(frame.data)
            latency = frame.latency_ms
            print(f"{path}: sequence {frame.sequence}, {frame.width}x{frame.height}, latency {latency:.1f} ms")
            if saved == args.frames:
                stream.cancel()  # tells the daemon we are done
                break
    except grpc.RpcError as error:
        if error.code() != grpc.StatusCode.CANCELLED:
            sys.exit(f"omniview: {error.code().name}: {error.details()}")
    print(f"saved {saved} frames to {out}/")


if __name__ == "__main__":
    main()
