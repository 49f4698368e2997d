#!/usr/bin/env bash
# A NATS server with JetStream for shared sessions (issues 23 and 35),
# installed by scripts/setup.sh (Debian's nats-server). Ctrl-C stops it;
# every committed edit is kept in the store directory and is there when it
# starts again.
#
#   bash scripts/nats.sh [PORT]          this machine only: listens on 127.0.0.1
#                                        (default port 4222), no members, no TLS;
#                                        store ./nats-store
#   bash scripts/nats.sh --users FILE --certs DIR [PORT]
#                                        a team: only the members in FILE get in,
#                                        each with their rights per document, over
#                                        TLS with DIR's server certificate; listens
#                                        on every interface (SHAPEWRIGHT_NATS_ADDR
#                                        to choose one)
#   bash scripts/nats.sh --cluster [--users FILE --certs DIR]
#                                        three servers on this machine (4222-4224,
#                                        routes 6222-6224 on 127.0.0.1), store
#                                        ./nats-store/n1..n3; streams made with
#                                        `--replicas 3` survive one server's loss
#
# A team's setup, once (see the README's "Shared sessions"):
#   bash scripts/session_certs.sh certs HOST-NAME-OR-IP      # CA + server certificate
#   shapewright-xr session-access team.txt --invite ana --grant chair:editor --ca certs/ca.pem
#       (adds ana with a fresh password, stored hashed, and writes ana.credentials for her)
#   bash scripts/nats.sh --users team.txt --certs certs
# Then each person, with their credentials file:
#   shapewright-xr run --join tls://HOST:4222/chair --credentials ana.credentials
# (DOC names the document: letters, digits, _ and -). A cluster's clients
# list every server: tls://h:4222,h:4223,h:4224/DOC.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
command -v nats-server >/dev/null 2>&1 || {
  echo "nats.sh: nats-server is missing; run scripts/setup.sh (it installs Debian's nats-server)" >&2
  exit 1
}
store="${SHAPEWRIGHT_NATS_STORE:-$root/nats-store}"
here="$(hostname -I 2>/dev/null | cut -d' ' -f1)"; here="${here:-127.0.0.1}"

cluster=""; users=""; certs=""; port=""
while [ $# -gt 0 ]; do
  case "$1" in
    --cluster) cluster=1 ;;
    --users) users="${2:?--users needs a member list}"; shift ;;
    --certs) certs="${2:?--certs needs the folder scripts/session_certs.sh made}"; shift ;;
    *) port="$1" ;;
  esac
  shift
done
conf=(); tls=(); scheme=nats
if [ -n "$users" ]; then
  if [ -z "$certs" ]; then
    echo "nats.sh: members' passwords and edits must not cross the network in clear: make certificates with" >&2
    echo "  bash scripts/session_certs.sh certs $here" >&2
    echo "and start with --users $users --certs certs" >&2
    exit 1
  fi
  for f in server.pem server-key.pem; do
    [ -f "$certs/$f" ] || { echo "nats.sh: $certs/$f is missing (scripts/session_certs.sh $certs HOST makes it)" >&2; exit 1; }
  done
  # The server-side rules come from the host (shapewright_net::access);
  # the configuration holds bcrypt hashes only.
  bin="${CARGO_TARGET_DIR:-$root/target}/release/shapewright-xr"
  [ -x "$bin" ] || (cd "$root" && cargo build --release -q -p shapewright-xr)
  mkdir -p "$store"
  (umask 077; "$bin" session-access "$users" > "$store/access.conf")
  conf=(-c "$store/access.conf")
  tls=(--tls --tlscert "$certs/server.pem" --tlskey "$certs/server-key.pem")
  scheme=tls
  addr="${SHAPEWRIGHT_NATS_ADDR:-0.0.0.0}"
  echo "nats.sh: members from $users (rules in $store/access.conf), TLS with $certs/server.pem" >&2
else
  [ -z "$certs" ] || tls=(--tls --tlscert "$certs/server.pem" --tlskey "$certs/server-key.pem")
  [ -z "$certs" ] || scheme=tls
  addr=127.0.0.1
  here=127.0.0.1
  echo "nats.sh: no member list, so only this machine can join (127.0.0.1). To open it to a team:" >&2
  echo "  bash scripts/session_certs.sh certs $(hostname -I 2>/dev/null | cut -d' ' -f1)" >&2
  echo "  shapewright-xr session-access team.txt --invite NAME --grant DOC:editor --ca certs/ca.pem" >&2
  echo "  bash scripts/nats.sh --users team.txt --certs certs" >&2
fi

if [ -n "$cluster" ]; then
  pids=()
  trap 'kill "${pids[@]}" 2>/dev/null; wait' INT TERM EXIT
  routes="nats://127.0.0.1:6222,nats://127.0.0.1:6223,nats://127.0.0.1:6224"
  for i in 1 2 3; do
    mkdir -p "$store/n$i"
    nats-server "${conf[@]}" "${tls[@]}" -a "$addr" -p $((4221 + i)) -js --store_dir "$store/n$i" \
      --server_name "sw-n$i" --cluster_name shapewright \
      --cluster "nats://127.0.0.1:$((6221 + i))" --routes "$routes" &
    pids+=("$!")
  done
  echo "shared sessions (3-node cluster): $scheme://$here:4222,$here:4223,$here:4224/DOC  (Ctrl-C stops)"
  wait
else
  port="${port:-4222}"
  mkdir -p "$store"
  echo "shared sessions: $scheme://$here:$port/DOC  (Ctrl-C stops; edits are kept in $store)"
  exec nats-server "${conf[@]}" "${tls[@]}" -a "$addr" -p "$port" -js --store_dir "$store"
fi
