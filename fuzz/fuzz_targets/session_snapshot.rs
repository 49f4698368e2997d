//! Replica snapshots as a late joiner loads them from the session's
//! bucket (issue 35): anything is a replica or a clear error, never a
//! panic; a replica loaded writes itself back byte for byte; and the
//! check against the stream decides without panicking (here against an
//! empty stream, which a non-empty snapshot can never match).
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::doc::shared::{Replica, SnapshotCheck, Verdict};

fuzz_target!(|data: &[u8]| {
    let Ok(r) = Replica::from_snapshot(data) else {
        return;
    };
    let bytes = r.snapshot();
    let back = Replica::from_snapshot(&bytes).expect("a snapshot reads back");
    assert_eq!(back.snapshot(), bytes);
    assert_eq!(back.document().content_hash(), r.document().content_hash());
    let mut check = SnapshotCheck::new(r.last_seq(), data.to_vec());
    let verdict = check.verdict();
    if r.last_seq() > 0 {
        assert!(matches!(verdict, Verdict::Differs(_)));
    }
});
