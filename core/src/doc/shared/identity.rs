//! Participants by id: their colour ([`colour_for`]), message ids, and ids
//! as NATS subject tokens.

/// A participant's colour, from their id (hosts draw them with it):
/// saturated and light enough to read on the headset's dark background.
pub fn colour_for(id: &str) -> [f32; 3] {
    let h = id.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    });
    let hue = (h % 360) as f32 / 60.0;
    let x = 1.0 - (hue % 2.0 - 1.0).abs();
    let (r, g, b) = match hue as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    [0.25 + 0.75 * r, 0.25 + 0.75 * g, 0.25 + 0.75 * b]
}

/// The message id of `author`'s entry `n`.
pub fn msg_id(author: &str, n: u64) -> String {
    format!("{author}:{n}")
}

/// True when `id` is a valid participant id.
pub fn valid_author(id: &str) -> bool {
    !id.is_empty()
        && id.len() <= 64
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'.')
}

/// Participant `id` as one token of a NATS subject (the last of
/// `sw.DOC.log.<token>` and `sw.DOC.presence.<token>`): a `.` would split
/// the subject, so it becomes `%2E`; ids never hold `%`, so two ids never
/// share a token. `None` when `id` is not a valid participant id.
pub fn subject_token(id: &str) -> Option<String> {
    valid_author(id).then(|| id.replace('.', "%2E"))
}

/// The participant id whose [`subject_token`] is `token`, if any.
pub fn id_from_token(token: &str) -> Option<String> {
    let id = token.replace("%2E", ".");
    (subject_token(&id).as_deref() == Some(token)).then_some(id)
}
