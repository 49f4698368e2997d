#!/usr/bin/env bash
# A NATS server with JetStream for shared sessions (issue 23), installed by
# scripts/setup.sh (Debian's nats-server). Ctrl-C stops it; every committed
# edit is kept in the store directory and is there when it starts again.
#
#   bash scripts/nats.sh [--users FILE] [PORT]
#                                        one server (default 4222), store ./nats-store
#   bash scripts/nats.sh --cluster       three servers on this machine (4222-4224,
#                                        routes 6222-6224), store ./nats-store/n1..n3;
#                                        streams made with `--replicas 3` survive one
#                                        server's loss
#   --users FILE                         only the people in FILE get in, each with
#                                        their own rights per document; one line each:
#                                        USER PASSWORD DOC:editor|viewer ...
#                                        (editors append, viewers only read; they join
#                                        with nats://USER:PASSWORD@HOST:PORT/DOC)
#
# Then, on each headset or desktop:
#   shapewright-xr run --join nats://THIS-HOST:4222/DOC
# (DOC names the document: letters, digits, _ and -). A cluster's clients
# can list every server: nats://h1:4222,h2:4223,h3:4224/DOC.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
command -v nats-server >/dev/null 2>&1 || {
  echo "nats.sh: nats-server is missing; run scripts/setup.sh (it installs Debian's nats-server)" >&2
  exit 1
}
addr="${SHAPEWRIGHT_NATS_ADDR:-0.0.0.0}"
store="${SHAPEWRIGHT_NATS_STORE:-$root/nats-store}"
here="$(hostname -I 2>/dev/null | cut -d' ' -f1)"; here="${here:-127.0.0.1}"

cluster=""; users=""; port=""
while [ $# -gt 0 ]; do
  case "$1" in
    --cluster) cluster=1 ;;
    --users) users="${2:?--users needs a file}"; shift ;;
    *) port="$1" ;;
  esac
  shift
done
conf=()
if [ -n "$users" ]; then
  # The server-side rules come from the host (shapewright_net::access).
  bin="$root/target/release/shapewright-xr"
  [ -x "$bin" ] || (cd "$root" && cargo build --release -q -p shapewright-xr)
  mkdir -p "$store"
  "$bin" session-access "$users" > "$store/access.conf"
  conf=(-c "$store/access.conf")
  echo "nats.sh: members from $users (rules in $store/access.conf)" >&2
fi

if [ -n "$cluster" ]; then
  pids=()
  trap 'kill "${pids[@]}" 2>/dev/null; wait' INT TERM EXIT
  routes="nats://127.0.0.1:6222,nats://127.0.0.1:6223,nats://127.0.0.1:6224"
  for i in 1 2 3; do
    mkdir -p "$store/n$i"
    nats-server "${conf[@]}" -a "$addr" -p $((4221 + i)) -js --store_dir "$store/n$i" \
      --server_name "sw-n$i" --cluster_name shapewright \
      --cluster "nats://127.0.0.1:$((6221 + i))" --routes "$routes" &
    pids+=("$!")
  done
  echo "shared sessions (3-node cluster): nats://$here:4222,$here:4223,$here:4224/DOC  (Ctrl-C stops)"
  wait
else
  port="${port:-4222}"
  mkdir -p "$store"
  echo "shared sessions: nats://$here:$port/DOC  (Ctrl-C stops; edits are kept in $store)"
  exec nats-server "${conf[@]}" -a "$addr" -p "$port" -js --store_dir "$store"
fi
