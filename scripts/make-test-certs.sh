#!/usr/bin/env bash
# Throw-away certificates for tests: make-test-certs.sh DIR
#
# Writes into DIR (created if needed), all PEM, ECDSA P-256, valid for one day:
#   ca.crt ca.key           a test CA
#   server.crt server.key   for "localhost" (SAN DNS:localhost, IP:127.0.0.1), signed by the CA
#   client.crt client.key   a client certificate ("omniview-test-client"), signed by the CA
# Never use these outside tests: the CA key sits next to them.
set -euo pipefail

if [[ $# -ne 1 ]]; then
  echo "usage: $0 DIR" >&2
  exit 2
fi
dir=$1
mkdir -p "$dir"
cd "$dir"
umask 077  # keys readable by their owner only
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

new_key() { openssl ecparam -name prime256v1 -genkey -noout -out "$1" 2>/dev/null; }

# sign NAME SUBJECT EXTENSIONS: NAME.key -> NAME.csr -> NAME.crt signed by the CA
sign() {
  local name=$1 subject=$2 extensions=$3
  new_key "$name.key"
  openssl req -new -key "$name.key" -subj "$subject" -out "$work/$name.csr" 2>/dev/null
  printf '%s\n' "$extensions" > "$work/$name.ext"
  openssl x509 -req -in "$work/$name.csr" -CA ca.crt -CAkey ca.key -CAcreateserial -CAserial "$work/ca.srl" \
    -days 1 -sha256 -extfile "$work/$name.ext" -out "$name.crt" 2>/dev/null
}

new_key ca.key
openssl req -new -x509 -key ca.key -subj "/CN=omniview test CA" -days 1 -sha256 \
  -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign" \
  -out ca.crt 2>/dev/null

sign server "/CN=localhost" "basicConstraints=CA:FALSE
keyUsage=critical,digitalSignature,keyEncipherment
extendedKeyUsage=serverAuth
subjectAltName=DNS:localhost,IP:127.0.0.1"

sign client "/CN=omniview-test-client" "basicConstraints=CA:FALSE
keyUsage=critical,digitalSignature
extendedKeyUsage=clientAuth"

chmod 644 ca.crt server.crt client.crt
