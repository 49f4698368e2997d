//! Progress for long command-line work (issue 22): silent for the first
//! second, then one line on stderr at most every second (`\r`-updated on
//! a terminal, a line each otherwise, so logs stay readable), ending with
//! the total time. A cancel (Ctrl-C) needs nothing here: every command
//! writes its output crash-safely at the end ([`crate::files`]), so an
//! interrupted command leaves the files as they were.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Reports `done / total` of a task named `what`.
pub struct Progress {
    what: String,
    start: Instant,
    last: Option<Instant>,
    every: Duration,
    tty: bool,
}

impl Progress {
    /// Starts timing `what` (e.g. "applying ops").
    pub fn new(what: &str) -> Self {
        Self {
            what: what.to_string(),
            start: Instant::now(),
            last: None,
            every: Duration::from_secs(1),
            tty: std::io::stderr().is_terminal(),
        }
    }

    /// Notes that `done` of `total` steps are done; prints when due.
    pub fn step(&mut self, done: usize, total: usize) {
        let Some(line) = self.due(done, total, Instant::now()) else {
            return;
        };
        let mut err = std::io::stderr().lock();
        let _ = if self.tty {
            write!(err, "\r{line}")
        } else {
            writeln!(err, "{line}")
        };
    }

    /// The line to show at `now`, if one is due (and notes it shown).
    fn due(&mut self, done: usize, total: usize, now: Instant) -> Option<String> {
        let since = self.last.unwrap_or(self.start);
        if now.saturating_duration_since(since) < self.every || done >= total {
            return None;
        }
        self.last = Some(now);
        let pct = 100.0 * done as f64 / total.max(1) as f64;
        Some(format!(
            "{}: {done}/{total} ({pct:.0}%), {:.0} s",
            self.what,
            now.saturating_duration_since(self.start).as_secs_f64()
        ))
    }

    /// Ends the report: a closing line with the total time, only if
    /// progress was shown.
    pub fn finish(self, total: usize) {
        if self.last.is_none() {
            return;
        }
        let line = format!(
            "{}: {total}/{total} in {:.1} s",
            self.what,
            self.start.elapsed().as_secs_f64()
        );
        let mut err = std::io::stderr().lock();
        let _ = if self.tty {
            writeln!(err, "\r{line}")
        } else {
            writeln!(err, "{line}")
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn silent_for_a_second_then_at_most_once_a_second_never_at_the_end() {
        let mut p = Progress::new("applying ops");
        let t0 = p.start;
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(p.due(10, 100, at(999)), None);
        assert_eq!(
            p.due(20, 100, at(1000)).as_deref(),
            Some("applying ops: 20/100 (20%), 1 s")
        );
        assert_eq!(p.due(30, 100, at(1500)), None);
        assert!(p.due(40, 100, at(2000)).is_some());
        // The last step is the closing line's job.
        assert_eq!(p.due(100, 100, at(9000)), None);
    }
}
