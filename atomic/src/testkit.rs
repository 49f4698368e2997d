//! The kill -9 harness that the crash tests of `usd` and `xr_host` share
//! (feature `testkit`; not part of the writer).
//!
//! A crash test re-runs its own test binary as a child, filtered to one
//! test (the writer), with an environment variable naming what to write.
//! The child prints `ACK n` once its write n returned. The parent kills
//! it at a pseudo-random moment and checks the file against the last
//! acknowledgement. [`Writer`] is that child; [`Delays`] the reproducible
//! kill moments; [`runs`] the number of kills (`CRASH_RUNS`).

use std::ffi::OsStr;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The number of kills a crash test makes: `CRASH_RUNS`, or `default`.
pub fn runs(default: usize) -> usize {
    std::env::var("CRASH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// xorshift64*: reproducible kill delays without another dependency.
pub struct Delays(u64);

impl Delays {
    /// A stream starting from `seed` (not 0).
    pub fn new(seed: u64) -> Self {
        Delays(seed)
    }

    /// The next number of the stream.
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.0;
        *s ^= *s >> 12;
        *s ^= *s << 25;
        *s ^= *s >> 27;
        s.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

/// A writer child: this test binary re-run on one test, its stdout read
/// for `ACK n` lines on a thread.
pub struct Writer {
    child: Child,
    acks: Receiver<usize>,
    reader: Option<JoinHandle<Option<usize>>>,
}

impl Writer {
    /// Starts the test `test` of the running test binary with `env` set to
    /// `value`.
    pub fn spawn(test: &str, env: &str, value: impl AsRef<OsStr>) -> Self {
        let exe = std::env::current_exe().expect("the test binary's path");
        let mut child = Command::new(exe)
            .args([test, "--exact", "--nocapture", "--test-threads=1"])
            .env(env, value)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("the writer child starts");
        let stdout = child.stdout.take().expect("a piped stdout");
        let (tx, acks) = channel();
        let reader = std::thread::spawn(move || {
            let mut last = None;
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                // The first ACK shares its line with libtest's "test name
                // ... ", printed without a newline: read the line's end.
                if let Some(n) = line
                    .rsplit_once("ACK ")
                    .and_then(|(_, n)| n.trim().parse().ok())
                {
                    last = Some(n);
                    let _ = tx.send(n);
                }
            }
            last
        });
        Writer {
            child,
            acks,
            reader: Some(reader),
        }
    }

    /// Waits up to `timeout` for the first acknowledgement; `None` when
    /// none came.
    pub fn first_ack(&self, timeout: Duration) -> Option<usize> {
        self.ack_at_least(0, timeout)
    }

    /// Waits up to `timeout` for an acknowledgement of at least `n`
    /// writes; returns it, or `None` when none came in time (the child
    /// stopped or is slower than that).
    ///
    /// A kill timed from a count the child reached, rather than from its
    /// start, lands mid-session however slow the machine: a kill delay
    /// of fixed milliseconds from the first acknowledgement landed before
    /// the next write returned in most runs of a loaded CI machine.
    pub fn ack_at_least(&self, n: usize, timeout: Duration) -> Option<usize> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.checked_duration_since(Instant::now())?;
            match self.acks.recv_timeout(left) {
                Ok(k) if k >= n => return Some(k),
                Ok(_) => continue,
                Err(_) => return None,
            }
        }
    }

    /// Kills the child (SIGKILL; `TerminateProcess` on Windows) and
    /// returns the last count it acknowledged.
    pub fn kill(mut self) -> Option<usize> {
        self.child.kill().expect("the writer child is killed");
        self.child.wait().expect("the writer child is reaped");
        let reader = self.reader.take().expect("killed once");
        reader.join().expect("the ACK reader ends")
    }
}

impl Drop for Writer {
    /// A test that panics before [`Writer::kill`] leaves no writer behind.
    fn drop(&mut self) {
        if self.reader.is_some() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
