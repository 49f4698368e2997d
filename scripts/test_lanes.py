#!/usr/bin/env python3
"""Runs the workspace's Rust tests as `cargo test --workspace` does, in two
lanes: the test binaries that mostly wait run beside the ones that compute.

    python3 scripts/test_lanes.py [--wait NAME ...]

Why: on CI's 2-core machine the binaries run one after another, and four
of them spend most of their time waiting, not computing: the Monado
sessions are paced by the runtime's frames (98 s wall, 18 s CPU), the
OpenXR test runtime, the dishonest-editor and NATS tests by a server's
timeouts and a participant cut off for ten seconds (66 s wall, 22 s CPU
together, measured 2026-11-30). `cargo test` cannot run two test binaries
at once, so this builds them with `cargo test --no-run`, runs the waiting
ones in a lane of their own while the rest run in order, each binary as
cargo runs it (in its package's directory, with its manifest dir set),
then runs the doc tests with cargo. Every binary's time is printed, and a
failing binary's whole output; the exit status is 1 if any failed.

An integration-test binary whose tests are in modules (a crate's
`tests/suite`, one module per subject) runs one subject at a time, each
its own process with its own time and timeout, as when each subject was a
binary: folded into one binary the core's subjects ran past the timeout
beside CI's cold background builds (1,200 s, 2026-12-02), and a slow run
should say which subject was slow.

Tests that measure time measure their own process's CPU time
(`core/tests/common`), so a binary beside them does not change what they
assert; the waiting lane's binaries share nothing with the others (each
server and runtime on its own free port and directories; every binary that
starts a NATS server is in the waiting lane).

The computing lane runs at `nice` 10, as CI's background builds do: the
waiting lane's hosts get the CPU first when they need it, as they did
when they ran alone beside those builds. The first run of the two lanes,
at equal priority (2026-11-30), found a race in the host: starved of CPU,
it dragged the original after a duplicate where the replay of its own
recording drags the copy (3 `testrt` tests failed). The host is fixed (its
tool never steps against a document older than the commands it made;
`xr_host/src/interaction/frame.rs`), and `testrt` and `monado` pass beside
two CPU-bound test binaries at equal priority; the priority is a margin.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time

# The binaries that wait (test targets). `shared_session` computes little
# too, and it is here above all because it starts NATS servers: a server
# `nats` restarts keeps its port, which a test in the other lane could
# take while it is down.
WAITING = ["monado", "testrt", "dishonest", "nats", "shared_session"]

# A binary still running after this long is stopped and shown as failed
# with what it printed (the whole suite's longest takes 100 s), so a hang
# says where it is instead of stalling CI silently.
TIMEOUT_SECONDS = 1200


def test_binaries(cargo_args: list[str]) -> list[dict]:
    """Builds the workspace's test binaries; returns them in cargo's order."""
    cmd = ["cargo", "test", "--workspace", "--no-run", "-q"]
    cmd += ["--message-format=json-render-diagnostics", *cargo_args]
    out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, check=False)
    if out.returncode != 0:
        sys.exit(out.returncode)
    bins = []
    for line in out.stdout.splitlines():
        msg = json.loads(line)
        if msg.get("reason") != "compiler-artifact" or not msg.get("executable"):
            continue
        if not msg["profile"]["test"]:
            continue
        bins.append(
            {
                "name": msg["target"]["name"],
                "kind": msg["target"]["kind"][0],
                "exe": msg["executable"],
                "dir": os.path.dirname(msg["manifest_path"]),
            }
        )
    return bins


def subjects(b: dict) -> list[dict]:
    """`b` as one run per top-level module of its tests (by exact names),
    or as itself when its tests are not in modules."""
    if b["kind"] != "test":
        return [b]
    listing = subprocess.run(
        [b["exe"], "--list", "--format", "terse"],
        cwd=b["dir"],
        env=dict(os.environ, CARGO_MANIFEST_DIR=b["dir"]),
        stdout=subprocess.PIPE,
        text=True,
        check=True,
    ).stdout
    groups: dict[str, list[str]] = {}
    for line in listing.splitlines():
        name, sep, kind = line.rpartition(": ")
        if sep and kind == "test":
            groups.setdefault(name.split("::")[0] if "::" in name else "", []).append(name)
    if len(groups) < 2 or "" in groups:
        return [b]
    return [
        dict(b, subject=module, args=["--exact", *names]) for module, names in sorted(groups.items())
    ]


class Lane(threading.Thread):
    def __init__(self, name: str, bins: list[dict], lock: threading.Lock, nice: int):
        super().__init__(name=name)
        self.bins = bins
        self.lock = lock
        self.nice = nice
        self.failed: list[str] = []

    def run(self) -> None:
        for b in self.bins:
            env = dict(os.environ, CARGO_MANIFEST_DIR=b["dir"])
            start = time.monotonic()
            try:
                p = subprocess.run(
                    ["nice", "-n", str(self.nice), b["exe"], "-q", *b.get("args", [])],
                    cwd=b["dir"],
                    env=env,
                    stdout=subprocess.PIPE,
                    stderr=subprocess.STDOUT,
                    text=True,
                    check=False,
                    timeout=TIMEOUT_SECONDS,
                )
                code, out = p.returncode, p.stdout
            except subprocess.TimeoutExpired as e:
                partial = e.stdout or ""
                if isinstance(partial, bytes):
                    partial = partial.decode(errors="replace")
                code, out = "timeout", partial + f"\n(stopped after {TIMEOUT_SECONDS} s)\n"
            took = time.monotonic() - start
            subject = f"::{b['subject']}" if "subject" in b else ""
            label = f"{os.path.basename(b['dir'])}/{b['name']}{subject} ({b['kind']})"
            summary = [line for line in out.splitlines() if line.startswith("test result:")]
            with self.lock:
                if code != 0:
                    self.failed.append(label)
                    print(f"---- {label} FAILED ({code}) after {took:.1f} s [{self.name} lane]")
                    print(out, end="")
                else:
                    result = summary[-1] if summary else "no tests"
                    print(f"{took:6.1f} s  {label} [{self.name}]: {result}")
                sys.stdout.flush()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--wait",
        nargs="*",
        default=WAITING,
        help="test targets that run in the waiting lane (default: %(default)s)",
    )
    args = ap.parse_args()
    t0 = time.monotonic()
    bins = test_binaries([])
    print(f"test_lanes: {len(bins)} test binaries built in {time.monotonic() - t0:.0f} s")
    waits = [b for b in bins if b["kind"] == "test" and b["name"] in args.wait]
    missing = set(args.wait) - {b["name"] for b in waits}
    if missing:
        print(f"test_lanes: no test target named {sorted(missing)}", file=sys.stderr)
        return 2
    rest = [s for b in bins if b not in waits for s in subjects(b)]
    lock = threading.Lock()
    lanes = [Lane("compute", rest, lock, 10), Lane("waiting", waits, lock, 0)]
    t1 = time.monotonic()
    for lane in lanes:
        lane.start()
    for lane in lanes:
        lane.join()
    print(f"test_lanes: the binaries ran in {time.monotonic() - t1:.0f} s")
    t2 = time.monotonic()
    doc = subprocess.run(["cargo", "test", "--workspace", "--doc", "-q"], check=False)
    print(f"test_lanes: doc tests in {time.monotonic() - t2:.0f} s")
    failed = [f for lane in lanes for f in lane.failed]
    if doc.returncode != 0:
        failed.append("doc tests")
    if failed:
        print(f"test_lanes: FAILED: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
