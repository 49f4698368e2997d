//! [`PrintControl`]: the progress and the cancel flag of one print job,
//! shared between the thread that runs [`super::printable_with`] and the
//! host that shows it (Blender's progress bar and Esc, the headset's save).
//!
//! The job writes its stage and step counts; the host reads them at any
//! time ([`PrintControl::progress`]) and may call [`PrintControl::cancel`]
//! from any thread. Cancelling is checked between objects, between the
//! union's steps and inside each step (Manifold's own cancellation points),
//! and between the checks, so a job stops within one stage of one boolean;
//! a cancelled job returns [`super::PrintError::Cancelled`], never a mesh.
//! Without cancelling, a job with a control gives the same bits as one
//! without (the union is the same fold).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::mesh::BooleanCancel;

/// What a print job is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrintStage {
    /// Checking and thickening each object (steps: objects).
    Preparing,
    /// Importing and uniting the objects (steps: imports, then unions).
    Uniting,
    /// Validating the union at the written precision (steps: snap rounds).
    Checking,
    /// The host writes the file (set by the host).
    Writing,
    /// Finished (or stopped).
    Done,
}

impl PrintStage {
    const ALL: [Self; 5] = [
        Self::Preparing,
        Self::Uniting,
        Self::Checking,
        Self::Writing,
        Self::Done,
    ];

    /// The stage as a progress bar says it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Preparing => "preparing objects",
            Self::Uniting => "uniting objects",
            Self::Checking => "checking the result",
            Self::Writing => "writing",
            Self::Done => "done",
        }
    }

    /// The share of the whole job this stage covers, as `[from, to)`.
    /// The union is most of the work on a big document.
    fn span(self) -> (f64, f64) {
        match self {
            Self::Preparing => (0.0, 0.05),
            Self::Uniting => (0.05, 0.85),
            Self::Checking => (0.85, 0.95),
            Self::Writing => (0.95, 1.0),
            Self::Done => (1.0, 1.0),
        }
    }
}

/// A job's progress at one moment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PrintProgress {
    /// The stage.
    pub stage: PrintStage,
    /// Steps of the stage done.
    pub done: u32,
    /// Steps of the stage in all (0: unknown).
    pub total: u32,
}

impl PrintProgress {
    /// How far the whole job is, in `[0, 1]`.
    pub fn fraction(&self) -> f64 {
        let (from, to) = self.stage.span();
        let within = if self.total == 0 {
            0.0
        } else {
            f64::from(self.done.min(self.total)) / f64::from(self.total)
        };
        from + (to - from) * within
    }
}

/// Steps fit in 28 bits each (a document of 268 million objects is
/// refused long before); the stage in the top 8. One atomic word, so a
/// reader never sees one stage's count with another's total.
const STEP_BITS: u32 = 28;
const STEP_MASK: u64 = (1 << STEP_BITS) - 1;

#[derive(Debug, Default)]
struct Inner {
    cancel: BooleanCancel,
    state: AtomicU64,
}

/// Progress and cancellation of one print job; clones share them.
#[derive(Clone, Debug, Default)]
pub struct PrintControl(Arc<Inner>);

impl PrintControl {
    /// A control for a new job (preparing, not cancelled).
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the job to stop (from any thread). It stops at its next check
    /// and returns [`super::PrintError::Cancelled`].
    pub fn cancel(&self) {
        self.0.cancel.cancel();
    }

    /// Whether [`Self::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.cancel.is_cancelled()
    }

    /// `Err(Cancelled)` once [`Self::cancel`] was called.
    pub(crate) fn check(&self) -> Result<(), super::PrintError> {
        if self.is_cancelled() {
            Err(super::PrintError::Cancelled)
        } else {
            Ok(())
        }
    }

    /// The flag Manifold's booleans check.
    pub(crate) fn boolean_cancel(&self) -> &BooleanCancel {
        &self.0.cancel
    }

    /// The job's progress now.
    pub fn progress(&self) -> PrintProgress {
        let s = self.0.state.load(Ordering::Relaxed);
        let stage = PrintStage::ALL[((s >> (2 * STEP_BITS)) as usize).min(4)];
        PrintProgress {
            stage,
            done: ((s >> STEP_BITS) & STEP_MASK) as u32,
            total: (s & STEP_MASK) as u32,
        }
    }

    /// Records that the job is at step `done` of `total` of `stage`
    /// (hosts set [`PrintStage::Writing`] and [`PrintStage::Done`]).
    pub fn set(&self, stage: PrintStage, done: usize, total: usize) {
        let clamp = |x: usize| (x as u64).min(STEP_MASK);
        let index = PrintStage::ALL
            .iter()
            .position(|&s| s == stage)
            .unwrap_or(4) as u64;
        let word = (index << (2 * STEP_BITS)) | (clamp(done) << STEP_BITS) | clamp(total);
        self.0.state.store(word, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_reads_back_what_was_set_and_only_grows_by_stage() {
        let c = PrintControl::new();
        assert_eq!(c.progress().stage, PrintStage::Preparing);
        assert_eq!(c.progress().fraction(), 0.0);
        let mut last = -1.0;
        for (stage, total) in [
            (PrintStage::Preparing, 3),
            (PrintStage::Uniting, 6),
            (PrintStage::Checking, 5),
            (PrintStage::Writing, 1),
        ] {
            for done in 0..=total {
                c.set(stage, done, total);
                let p = c.progress();
                assert_eq!(
                    (p.stage, p.done as usize, p.total as usize),
                    (stage, done, total)
                );
                assert!(p.fraction() >= last, "{p:?}");
                last = p.fraction();
            }
        }
        c.set(PrintStage::Done, 0, 0);
        assert_eq!(c.progress().fraction(), 1.0);
    }

    #[test]
    fn clones_share_the_cancel_flag() {
        let c = PrintControl::new();
        let other = c.clone();
        assert!(c.check().is_ok());
        other.cancel();
        assert!(c.is_cancelled());
        assert!(matches!(
            c.check(),
            Err(crate::print::PrintError::Cancelled)
        ));
    }
}
