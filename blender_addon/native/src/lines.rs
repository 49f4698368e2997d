//! The log's ops as JSON lines, each serialized once, when it is appended,
//! with a running hash of every prefix. A host that keeps its own copy of
//! the history (Blender's scene, which its undo steps restore) stores only
//! `(count, prefix hash)`, never the whole log, and asks
//! [`Lines::prefix_hash`] whether the session still holds that history
//! (an undo came back to an earlier state of the same log) or must be
//! rebuilt. Recording an op costs the same at op 10 as at op 10,000; the
//! whole text is joined only to save it.

use shapewright::doc::{ContentHasher, Op};

/// The serialized ops of a log and their prefix hashes.
#[derive(Clone, Debug, Default)]
pub(crate) struct Lines {
    text: Vec<String>,
    /// `prefix[k]`: hash of the first `k` ops (`prefix[0]` of none).
    prefix: Vec<u64>,
}

fn chain(prev: u64, line: &str) -> u64 {
    let mut h = ContentHasher::new();
    h.u64(prev);
    h.bytes(line.as_bytes());
    h.finish()
}

impl Lines {
    /// The lines of `ops`.
    pub(crate) fn of(ops: &[Op]) -> Self {
        let mut out = Self::default();
        out.sync_from(ops, 0);
        out
    }

    /// Brings the lines in step with `ops`, which equal the cached ones
    /// before index `from` (an apply after an undo drops the tail from the
    /// cursor; a shared session may change anything: `from` 0).
    pub(crate) fn sync_from(&mut self, ops: &[Op], from: usize) {
        if self.prefix.is_empty() {
            self.prefix.push(ContentHasher::new().finish());
        }
        let keep = from.min(self.text.len()).min(ops.len());
        self.text.truncate(keep);
        self.prefix.truncate(keep + 1);
        for op in &ops[keep..] {
            // An op is a plain serde value: serializing cannot fail.
            let line = serde_json::to_string(op).unwrap_or_default();
            let h = chain(self.prefix[self.text.len()], &line);
            self.text.push(line);
            self.prefix.push(h);
        }
    }

    /// Number of ops.
    pub(crate) fn len(&self) -> usize {
        self.text.len()
    }

    /// The hash of the first `count` ops, as hex (None past the end).
    pub(crate) fn prefix_hash(&self, count: usize) -> Option<String> {
        self.prefix.get(count).map(|h| format!("{h:016x}"))
    }

    /// Every op as JSON lines (each ending in a newline).
    pub(crate) fn joined(&self) -> String {
        let mut out = String::with_capacity(self.text.iter().map(|l| l.len() + 1).sum());
        for line in &self.text {
            out.push_str(line);
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ops(n: usize) -> Vec<Op> {
        (0..n)
            .map(|i| {
                serde_json::from_str(&format!(r#"{{"op":"rename_object","id":1,"name":"n{i}"}}"#))
                    .unwrap()
            })
            .collect()
    }

    #[test]
    fn appending_keeps_the_prefix_hashes_and_a_new_tail_changes_only_its_own() {
        let all = ops(6);
        let mut lines = Lines::of(&all[..4]);
        let h2 = lines.prefix_hash(2);
        let h4 = lines.prefix_hash(4);
        lines.sync_from(&all, 4);
        assert_eq!(lines.len(), 6);
        assert_eq!(lines.prefix_hash(4), h4);
        assert_eq!(Lines::of(&all).prefix_hash(6), lines.prefix_hash(6));
        // An undo to 2 and a different op: the tail from 2 is replaced.
        let mut other = all[..2].to_vec();
        other.push(ops(9)[8].clone());
        lines.sync_from(&other, 2);
        assert_eq!(lines.len(), 3);
        assert_eq!(lines.prefix_hash(2), h2);
        assert_ne!(lines.prefix_hash(3), Lines::of(&all).prefix_hash(3));
        assert_eq!(lines.prefix_hash(4), None);
        assert_eq!(lines.joined().lines().count(), 3);
    }
}
