//! Shared-session stream messages (issue 35): whatever a dishonest editor
//! or a broken client appends, on whatever subject, a replica applies it
//! or skips it with a reason, never panics, and stays one that a fresh
//! replay agrees with. The first byte picks the subject's sender (one who
//! joined, one who did not, a token that is no participant's).
//!
//! Entries carrying ops (`op`, `seed`) are only decoded unless
//! `SW_FUZZ_APPLY=1`, as in `op_script`: applying any op needs every op's
//! budget (issue 22, other lanes); joins, undos, redos, impostors, junk
//! and oversized messages always run the replica's whole path.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::doc::shared::{Body, Entry, Replica, ENTRY_VERSION};

fn session() -> Replica {
    let mut r = Replica::new();
    for (seq, who) in [(1, "ana"), (2, "ben.k")] {
        let join = Entry {
            v: ENTRY_VERSION,
            author: who.into(),
            n: 1,
            base: 0,
            body: Body::Join {
                name: who.into(),
                colour: [0.5; 3],
            },
        };
        let token = shapewright::doc::shared::subject_token(who).unwrap();
        r.integrate(seq, &token, &join.to_bytes());
    }
    r
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, bytes)) = data.split_first() else {
        return;
    };
    let from = ["ana", "ben%2Ek", "eve", "a.b", ""][pick as usize % 5];
    if std::env::var_os("SW_FUZZ_APPLY").is_none() {
        if let Ok(e) = serde_json::from_slice::<Entry>(bytes) {
            if matches!(e.body, Body::Op { .. } | Body::Seed(_)) {
                return;
            }
        }
    }
    let mut r = session();
    let before = r.document().content_hash();
    let done = r.integrate(3, from, bytes);
    assert_eq!(r.last_seq(), 3);
    if done.result.is_err() {
        // A refused message changes nothing but the sender's counter.
        assert_eq!(r.document().content_hash(), before);
        assert_eq!(r.skipped().len(), 1);
    }
    // Applying the same message to a fresh replica decides the same way.
    let mut again = session();
    let twice = again.integrate(3, from, bytes);
    assert_eq!(done.result.is_ok(), twice.result.is_ok());
    assert_eq!(again.document().content_hash(), r.document().content_hash());
});
