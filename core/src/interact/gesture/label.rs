//! The four hand gestures ([`Gesture`]) and the labels a recorded frame
//! carries ([`GestureLabel`]).

use serde::{Deserialize, Serialize};

/// A classified hand gesture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Gesture {
    /// No hand, or no gesture recognized.
    None,
    /// Open palm: select by ray.
    Open,
    /// Fist: grab and manipulate.
    Fist,
    /// Index pointing, the others curled: sketch.
    Point,
    /// Thumb and index opposed: shape type and thickness.
    Pinch,
}

/// The five poses the classifier tells apart (PINCH split by open/closed):
/// the labels of the test set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GestureLabel {
    /// OPEN.
    Open,
    /// FIST.
    Fist,
    /// POINT.
    Point,
    /// PINCH with a gap.
    PinchOpen,
    /// PINCH with the fingers touching.
    PinchClosed,
}

impl GestureLabel {
    /// Every label.
    pub const ALL: [GestureLabel; 5] = [
        GestureLabel::Open,
        GestureLabel::Fist,
        GestureLabel::Point,
        GestureLabel::PinchOpen,
        GestureLabel::PinchClosed,
    ];

    /// The gesture this label belongs to.
    pub fn gesture(self) -> Gesture {
        match self {
            GestureLabel::Open => Gesture::Open,
            GestureLabel::Fist => Gesture::Fist,
            GestureLabel::Point => Gesture::Point,
            GestureLabel::PinchOpen | GestureLabel::PinchClosed => Gesture::Pinch,
        }
    }
}
