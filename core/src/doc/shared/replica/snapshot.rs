//! Replica snapshots: what a late joiner starts from (checked against
//! the stream's replay, see [`super::super::SnapshotCheck`]).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::{Checkpoint, Effect, OpRec, Participant, Replica};
use crate::doc::shared::{valid_author, ENTRY_VERSION, MAX_PARTICIPANTS};
use crate::doc::{Document, LinearLog, Op};

/// The format name of a replica snapshot.
pub const SNAPSHOT_FORMAT: &str = "shapewright-replica";

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Snapshot {
    format: String,
    version: u32,
    last_seq: u64,
    /// The newest entry version the replica applied (absent in snapshots
    /// of version 1, which the version check then refuses by name).
    #[serde(default)]
    newest_version: u32,
    participants: Vec<Participant>,
    seed: Vec<Op>,
    ops: Vec<SnapshotOp>,
    redo: Vec<Vec<u64>>,
    document: Document,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SnapshotOp {
    author: usize,
    n: u64,
    op: Op,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    ids_from: Option<u32>,
    undone: bool,
    effect: Effect,
}

impl Replica {
    /// The replica as a snapshot (JSON): a late joiner loads it and
    /// replays only the entries after [`Self::last_seq`]. It holds every
    /// op with whether it is undone or in effect (so everyone's undo goes
    /// on working) and the document as its objects' parameters (meshes are
    /// evaluated again on load).
    pub fn snapshot(&self) -> Vec<u8> {
        let s = Snapshot {
            format: SNAPSHOT_FORMAT.into(),
            version: ENTRY_VERSION,
            last_seq: self.last_seq,
            newest_version: self.newest_version,
            participants: self.participants.clone(),
            seed: self.seed.clone(),
            ops: self
                .ops
                .iter()
                .map(|r| SnapshotOp {
                    author: r.author,
                    n: r.n,
                    op: (*r.op).clone(),
                    ids_from: r.ids_from,
                    undone: r.undone,
                    effect: r.effect.clone(),
                })
                .collect(),
            redo: self.redo.clone(),
            document: self.doc.clone(),
        };
        serde_json::to_vec(&s).unwrap_or_default()
    }

    /// A replica from [`Self::snapshot`]'s bytes, or why they are not
    /// one (the joiner then replays the stream from the start).
    pub fn from_snapshot(bytes: &[u8]) -> Result<Self, String> {
        let s: Snapshot =
            serde_json::from_slice(bytes).map_err(|e| format!("not a replica snapshot: {e}"))?;
        if s.format != SNAPSHOT_FORMAT || s.version != ENTRY_VERSION {
            return Err(format!(
                "snapshot format {} version {} (this build reads {SNAPSHOT_FORMAT} {})",
                s.format, s.version, ENTRY_VERSION
            ));
        }
        let mut r = Self::new();
        r.check_version(s.newest_version)
            .map_err(|e| format!("snapshot's newest entry: {e}"))?;
        let np = s.participants.len();
        let slots_ok = s
            .participants
            .iter()
            .enumerate()
            .all(|(i, p)| p.slot == i as u32 + 1 && valid_author(&p.id));
        if !slots_ok || s.redo.len() != np || np as u32 > MAX_PARTICIPANTS {
            return Err("snapshot's participants are inconsistent".into());
        }
        r.last_seq = s.last_seq;
        r.newest_version = s.newest_version;
        for (i, p) in s.participants.iter().enumerate() {
            r.by_id.insert(p.id.clone(), i);
        }
        r.participants = s.participants;
        r.redo = s.redo;
        let mut base = LinearLog::new();
        for op in &s.seed {
            base.apply(op.clone())
                .map_err(|e| format!("snapshot's seed does not replay: {e}"))?;
        }
        r.seed = s.seed;
        for o in s.ops {
            if o.author >= np || r.by_key.insert((o.author, o.n), r.ops.len()).is_some() {
                return Err("snapshot's ops name an unknown participant or repeat".into());
            }
            r.ops.push(OpRec {
                author: o.author,
                n: o.n,
                op: Arc::new(o.op),
                ids_from: o.ids_from,
                undone: o.undone,
                effect: o.effect,
            });
        }
        r.checkpoints = vec![
            Checkpoint {
                at: 0,
                doc: base.document().clone(),
            },
            Checkpoint {
                at: r.ops.len(),
                doc: s.document.clone(),
            },
        ];
        r.checkpoints.dedup_by_key(|c| c.at);
        r.doc = s.document;
        Ok(r)
    }
}
