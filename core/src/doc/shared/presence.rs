//! Presence: where each participant's head and hands are and what they
//! have selected, sent on a plain subject (never stored) at up to
//! [`PRESENCE_HZ`]. Poses are in model space (the document's metres), so
//! each receiver places the others with their own model placement: two
//! people who scaled or moved the model differently still see each other
//! at the same spot on it.

use serde::{Deserialize, Serialize};

/// The most presence messages a participant sends per second.
pub const PRESENCE_HZ: f64 = 30.0;

/// The largest presence message accepted (bytes).
pub const MAX_PRESENCE_BYTES: usize = 1024;

/// A presence older than this is not drawn (the person left or lost
/// tracking), in seconds.
pub const PRESENCE_STALE_SECS: f64 = 2.0;

/// A pose in model space: position (metres) and orientation (unit
/// quaternion `[x, y, z, w]`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PresencePose {
    /// Position.
    pub p: [f32; 3],
    /// Orientation.
    pub q: [f32; 4],
}

/// One participant's presence.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Presence {
    /// Format version ([`PRESENCE_VERSION`]).
    pub v: u32,
    /// The head, when tracked.
    #[serde(default)]
    pub head: Option<PresencePose>,
    /// Left and right hand (controller grip or tracked palm), when tracked.
    #[serde(default)]
    pub hands: [Option<PresencePose>; 2],
    /// The object they have selected, if any.
    #[serde(default)]
    pub selected: Option<u32>,
}

/// The presence format version.
pub const PRESENCE_VERSION: u32 = 1;

/// Why a presence message was dropped (the sender's problem; nothing is
/// drawn for it).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PresenceError {
    /// Over [`MAX_PRESENCE_BYTES`].
    #[error("presence message of {0} bytes (at most {MAX_PRESENCE_BYTES})")]
    TooLarge(usize),
    /// Not a presence message of a version we read.
    #[error("not a presence message: {0}")]
    Malformed(String),
    /// A position or orientation is not finite, or an orientation is not
    /// a unit quaternion.
    #[error("presence pose is not finite or not a rotation")]
    BadPose,
}

impl PresencePose {
    fn is_valid(&self) -> bool {
        let n2: f32 = self.q.iter().map(|c| c * c).sum();
        self.p.iter().chain(&self.q).all(|c| c.is_finite())
            && self.p.iter().all(|c| c.abs() < 1.0e6)
            && (n2 - 1.0).abs() < 1.0e-2
    }
}

impl Presence {
    /// Nothing tracked, nothing selected.
    pub fn empty() -> Self {
        Self {
            v: PRESENCE_VERSION,
            head: None,
            hands: [None, None],
            selected: None,
        }
    }

    /// The message's bytes (JSON).
    pub fn to_bytes(&self) -> Vec<u8> {
        serde_json::to_vec(self).unwrap_or_default()
    }

    /// Reads a message, refusing what cannot be drawn.
    pub fn decode(bytes: &[u8]) -> Result<Self, PresenceError> {
        if bytes.len() > MAX_PRESENCE_BYTES {
            return Err(PresenceError::TooLarge(bytes.len()));
        }
        let p: Self =
            serde_json::from_slice(bytes).map_err(|e| PresenceError::Malformed(e.to_string()))?;
        if p.v != PRESENCE_VERSION {
            return Err(PresenceError::Malformed(format!("version {}", p.v)));
        }
        if p.head
            .iter()
            .chain(p.hands.iter().flatten())
            .any(|q| !q.is_valid())
        {
            return Err(PresenceError::BadPose);
        }
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f32) -> PresencePose {
        PresencePose {
            p: [x, 1.6, 0.0],
            q: [0.0, 0.0, 0.0, 1.0],
        }
    }

    #[test]
    fn presence_round_trips_and_bad_messages_are_refused() {
        let p = Presence {
            v: PRESENCE_VERSION,
            head: Some(pose(0.5)),
            hands: [Some(pose(0.3)), None],
            selected: Some((1 << 24) | 3),
        };
        let bytes = p.to_bytes();
        assert!(bytes.len() < 300, "{}", bytes.len());
        assert_eq!(Presence::decode(&bytes).unwrap(), p);
        assert_eq!(Presence::decode(br#"{"v":1}"#).unwrap(), Presence::empty());
        let nan = String::from_utf8(bytes.clone())
            .unwrap()
            .replace("0.5", "1e999");
        assert!(Presence::decode(nan.as_bytes()).is_err());
        let skew = Presence {
            head: Some(PresencePose {
                p: [0.0; 3],
                q: [0.0, 0.0, 0.0, 2.0],
            }),
            ..Presence::empty()
        };
        assert_eq!(
            Presence::decode(&skew.to_bytes()),
            Err(PresenceError::BadPose)
        );
        assert!(matches!(
            Presence::decode(br#"{"v":2}"#),
            Err(PresenceError::Malformed(_))
        ));
        assert!(matches!(
            Presence::decode(&vec![b' '; 2000]),
            Err(PresenceError::TooLarge(2000))
        ));
        assert!(matches!(
            Presence::decode(b"\xff"),
            Err(PresenceError::Malformed(_))
        ));
    }
}
