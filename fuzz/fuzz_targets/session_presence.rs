//! Presence messages (issue 35): anything on a presence subject is drawn
//! or dropped, never a panic; what is drawn is finite, bounded and reads
//! back as itself.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::doc::shared::{Presence, MAX_PRESENCE_BYTES};

fuzz_target!(|data: &[u8]| {
    let Ok(p) = Presence::decode(data) else {
        return;
    };
    assert!(data.len() <= MAX_PRESENCE_BYTES);
    for pose in p.head.iter().chain(p.hands.iter().flatten()) {
        assert!(pose.p.iter().chain(&pose.q).all(|c| c.is_finite()));
    }
    assert_eq!(Presence::decode(&p.to_bytes()).as_ref(), Ok(&p));
});
