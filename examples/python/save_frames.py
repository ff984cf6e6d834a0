#!/usr/bin/env python3
"""Save frames of an omniview view as image files, with Debian's python3-grpcio.

    python3 save_frames.py front --frames 10 -o frames/
    python3 save_frames.py front --server robot:50051 --tls-ca ca.crt --token-file viewer.token
    python3 save_frames.py front --tls-ca ca.crt --tls-cert client.crt --tls-key client.key

The Python gRPC modules are generated from proto/ on first use (protoc and
grpc_python_plugin, Debian packages protobuf-compiler and protobuf-compiler-grpc) and
cached under ~/.cache/omniview-python/.
"""
import argparse
import hashlib
import os
import pathlib
import shutil
import socket
import ssl
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


def server_requests_client_certificate(server):
    """gRPC says only "Socket closed" when a TLS 1.3 server refuses a missing client
    certificate. Python's ssl cannot see the server's certificate request, but it sees the
    refusal: the connection closes right after the handshake (an accepting gRPC server
    sends its HTTP/2 settings or waits for ours instead)."""
    host, _, port = server.rpartition(":")
    host = host.strip("[]")
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname = False  # only the server's request matters here
    context.verify_mode = ssl.CERT_NONE
    context.set_alpn_protocols(["h2"])
    try:
        with socket.create_connection((host, int(port)), timeout=3) as sock:
            with context.wrap_socket(sock, server_hostname=host) as tls:
                tls.settimeout(1)
                return tls.recv(1) == b""  # the refusal arrives after the handshake
    except socket.timeout:
        return False
    except ssl.SSLError as error:
        return "CERTIFICATE_REQUIRED" in f"{error.reason} {error}".upper().replace(" ", "_")
    except (OSError, ValueError):
        return False
    return False


def read_token(token_file):
    """As the CLI: --token-file, else $OMNIVIEW_TOKEN (the token), else $OMNIVIEW_TOKEN_FILE."""
    if not token_file and os.environ.get("OMNIVIEW_TOKEN", "").strip():
        return os.environ["OMNIVIEW_TOKEN"].strip()
    token_file = token_file or os.environ.get("OMNIVIEW_TOKEN_FILE")
    if not token_file:
        return None
    try:
        lines = pathlib.Path(token_file).read_text().splitlines()
    except OSError as error:
        sys.exit(f"omniview: cannot read token file '{token_file}': {error.strerror}")
    if not lines or not lines[0].strip():
        sys.exit(f"omniview: token file '{token_file}' is empty")
    return lines[0].strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("view")
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("-o", "--output", default="frames")
    parser.add_argument("--encoding", choices=["jpg", "png"], default="jpg")
    parser.add_argument("--server", default=os.environ.get("OMNIVIEW_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--tls-ca", help="CA certificate (PEM): connect with TLS")
    parser.add_argument("--tls-cert", help="client certificate (PEM), for a daemon that requires one (tls.client_ca)")
    parser.add_argument("--tls-key", help="the private key (PEM) of --tls-cert")
    parser.add_argument("--token-file",
                        help="access token file (default: $OMNIVIEW_TOKEN, the token, or $OMNIVIEW_TOKEN_FILE)")
    args = parser.parse_args()
    if bool(args.tls_cert) != bool(args.tls_key):
        parser.error("--tls-cert and --tls-key go together")
    if args.tls_cert and not args.tls_ca:
        parser.error("--tls-cert needs --tls-ca")

    pb, pb_grpc = load_api()
    options = [("grpc.max_receive_message_length", 256 << 20)]  # big views make big frames
    if args.tls_ca:
        credentials = grpc.ssl_channel_credentials(
            pathlib.Path(args.tls_ca).read_bytes(),
            pathlib.Path(args.tls_key).read_bytes() if args.tls_key else None,
            pathlib.Path(args.tls_cert).read_bytes() if args.tls_cert else None)
        channel = grpc.secure_channel(args.server, credentials, options)
    else:
        channel = grpc.insecure_channel(args.server, options)
    metadata = [("authorization", f"Bearer {token}")] if (token := read_token(args.token_file)) else []

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
            print(f"saved {saved} frames to {out}/")
            details = error.details() or ""
            if (error.code() == grpc.StatusCode.UNAVAILABLE and args.tls_ca and not args.tls_cert
                    and server_requests_client_certificate(args.server)):
                sys.exit("omniview: the daemon requires a client certificate: pass --tls-cert FILE --tls-key FILE")
            sys.exit(f"omniview: {error.code().name}: {details}")
    print(f"saved {saved} frames to {out}/")


if __name__ == "__main__":
    main()
