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
        if let Some(line) = self.due(done, total, Instant::now()) {
            self.show(&line);
        }
    }

    /// Notes that `fraction` (0 to 1) of the work is done, `detail` saying
    /// where it is (e.g. "uniting objects 3/9"); prints when due.
    pub fn fraction(&mut self, fraction: f64, detail: &str) {
        if let Some(line) = self.due_fraction(fraction, detail, Instant::now()) {
            self.show(&line);
        }
    }

    fn show(&self, line: &str) {
        let mut err = std::io::stderr().lock();
        let _ = if self.tty {
            write!(err, "\r{line}")
        } else {
            writeln!(err, "{line}")
        };
    }

    /// Whether a line is due at `now` (and notes it shown if so).
    fn due_at(&mut self, now: Instant) -> bool {
        let since = self.last.unwrap_or(self.start);
        if now.saturating_duration_since(since) < self.every {
            return false;
        }
        self.last = Some(now);
        true
    }

    fn seconds(&self, now: Instant) -> f64 {
        now.saturating_duration_since(self.start).as_secs_f64()
    }

    /// The line to show at `now`, if one is due (and notes it shown).
    fn due(&mut self, done: usize, total: usize, now: Instant) -> Option<String> {
        if done >= total || !self.due_at(now) {
            return None;
        }
        let pct = 100.0 * done as f64 / total.max(1) as f64;
        Some(format!(
            "{}: {done}/{total} ({pct:.0}%), {:.0} s",
            self.what,
            self.seconds(now)
        ))
    }

    /// [`Self::due`] for [`Self::fraction`].
    fn due_fraction(&mut self, fraction: f64, detail: &str, now: Instant) -> Option<String> {
        if fraction >= 1.0 || !self.due_at(now) {
            return None;
        }
        Some(format!(
            "{}: {:.0}% ({detail}), {:.0} s",
            self.what,
            100.0 * fraction.max(0.0),
            self.seconds(now)
        ))
    }

    /// Ends the report: a closing line with the total time, only if
    /// progress was shown.
    pub fn finish(self, total: usize) {
        self.close(&format!("{total}/{total}"));
    }

    /// Ends a [`Self::fraction`] report as [`Self::finish`] does.
    pub fn finish_fraction(self) {
        self.close("done");
    }

    fn close(self, done: &str) {
        if self.last.is_none() {
            return;
        }
        let line = format!(
            "{}: {done} in {:.1} s",
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

    #[test]
    fn a_fraction_is_shown_as_a_percentage_with_where_the_work_is() {
        let mut p = Progress::new("exporting out.stl");
        let t0 = p.start;
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(p.due_fraction(0.1, "preparing objects 1/2", at(500)), None);
        assert_eq!(
            p.due_fraction(0.35, "uniting objects 3/9", at(1200))
                .as_deref(),
            Some("exporting out.stl: 35% (uniting objects 3/9), 1 s")
        );
        assert_eq!(p.due_fraction(0.5, "uniting objects 5/9", at(1900)), None);
        assert_eq!(p.due_fraction(1.0, "done", at(9000)), None);
    }
}
