#!/usr/bin/env bash
# Certificates for a team's shared-session server (issue 35): a team CA
# and a server certificate signed by it, for TLS between every headset,
# Blender and the server. Clients verify the server against the CA (the
# `ca = ...` line of their credentials file), so nobody on the network can
# read the ops and passwords or pose as the server.
#
#   bash scripts/session_certs.sh DIR [HOST...]
#
# DIR gets:
#   ca.pem            the team CA's certificate: give it to every member
#                     (their credentials file names it)
#   ca-key.pem        the CA's private key: keep it offline; needed only to
#                     make another server certificate
#   server.pem        the server's certificate, for the HOSTs (names and IP
#                     addresses people use in the session address)
#   server-key.pem    the server's private key: stays on the server
# HOSTs default to this machine's name, its addresses, localhost and
# 127.0.0.1. Run again with other HOSTs to make a new server certificate
# signed by the same CA (an existing CA is kept). Then:
#   bash scripts/nats.sh --users team.txt --certs DIR
# Needs openssl (Debian's, installed with the system).
set -euo pipefail
dir="${1:?usage: session_certs.sh DIR [HOST...]}"
shift
command -v openssl >/dev/null 2>&1 || { echo "session_certs.sh: openssl is missing (apt-get install openssl)" >&2; exit 1; }
hosts=("$@")
if [ "${#hosts[@]}" -eq 0 ]; then
  hosts=(localhost 127.0.0.1 "$(hostname)")
  for ip in $(hostname -I 2>/dev/null || true); do hosts+=("$ip"); done
fi
san=""
for h in "${hosts[@]}"; do
  [ -n "$h" ] || continue
  if [[ "$h" =~ ^[0-9.]+$ || "$h" == *:* ]]; then kind=IP; else kind=DNS; fi
  san="${san:+$san,}$kind:$h"
done
mkdir -p "$dir"
umask 077
if [ ! -f "$dir/ca.pem" ] || [ ! -f "$dir/ca-key.pem" ]; then
  openssl req -x509 -new -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes \
    -keyout "$dir/ca-key.pem" -out "$dir/ca.pem" -days 3650 -sha256 \
    -subj "/CN=Shapewright team CA" \
    -addext "basicConstraints=critical,CA:TRUE" \
    -addext "keyUsage=critical,keyCertSign,cRLSign" 2>/dev/null
  echo "session_certs.sh: made the team CA $dir/ca.pem (its key $dir/ca-key.pem: keep it private)"
fi
ext="$(mktemp)"; csr="$(mktemp)"
trap 'rm -f "$ext" "$csr"' EXIT
printf 'subjectAltName=%s\nbasicConstraints=critical,CA:FALSE\nkeyUsage=critical,digitalSignature,keyEncipherment\nextendedKeyUsage=serverAuth\n' "$san" > "$ext"
openssl req -new -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes \
  -keyout "$dir/server-key.pem" -out "$csr" -subj "/CN=${hosts[0]}" 2>/dev/null
openssl x509 -req -in "$csr" -CA "$dir/ca.pem" -CAkey "$dir/ca-key.pem" -CAcreateserial \
  -out "$dir/server.pem" -days 825 -sha256 -extfile "$ext" 2>/dev/null
chmod 644 "$dir/ca.pem" "$dir/server.pem"
echo "session_certs.sh: server certificate $dir/server.pem for $san"
