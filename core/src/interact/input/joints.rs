//! Raw hand tracking: the 26 joints of XR_EXT_hand_tracking ([`Joint`]),
//! one joint sample, where a hand's joints come from, and one hand sample.

use serde::{Deserialize, Serialize};

use super::pose::Pose;

/// Number of hand joints in the XR_EXT_hand_tracking layout.
pub const JOINT_COUNT: usize = 26;

/// The 26 joints of XR_EXT_hand_tracking (`XrHandJointEXT`), in its order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum Joint {
    Palm = 0,
    Wrist = 1,
    ThumbMetacarpal = 2,
    ThumbProximal = 3,
    ThumbDistal = 4,
    ThumbTip = 5,
    IndexMetacarpal = 6,
    IndexProximal = 7,
    IndexIntermediate = 8,
    IndexDistal = 9,
    IndexTip = 10,
    MiddleMetacarpal = 11,
    MiddleProximal = 12,
    MiddleIntermediate = 13,
    MiddleDistal = 14,
    MiddleTip = 15,
    RingMetacarpal = 16,
    RingProximal = 17,
    RingIntermediate = 18,
    RingDistal = 19,
    RingTip = 20,
    LittleMetacarpal = 21,
    LittleProximal = 22,
    LittleIntermediate = 23,
    LittleDistal = 24,
    LittleTip = 25,
}

impl Joint {
    /// The joint's index in the 26-joint array.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The five joints (metacarpal to tip) of each finger, index to little.
    pub const FINGERS: [[Joint; 5]; 4] = [
        [
            Joint::IndexMetacarpal,
            Joint::IndexProximal,
            Joint::IndexIntermediate,
            Joint::IndexDistal,
            Joint::IndexTip,
        ],
        [
            Joint::MiddleMetacarpal,
            Joint::MiddleProximal,
            Joint::MiddleIntermediate,
            Joint::MiddleDistal,
            Joint::MiddleTip,
        ],
        [
            Joint::RingMetacarpal,
            Joint::RingProximal,
            Joint::RingIntermediate,
            Joint::RingDistal,
            Joint::RingTip,
        ],
        [
            Joint::LittleMetacarpal,
            Joint::LittleProximal,
            Joint::LittleIntermediate,
            Joint::LittleDistal,
            Joint::LittleTip,
        ],
    ];

    /// The thumb's joints, metacarpal to tip.
    pub const THUMB: [Joint; 4] = [
        Joint::ThumbMetacarpal,
        Joint::ThumbProximal,
        Joint::ThumbDistal,
        Joint::ThumbTip,
    ];
}

/// One raw joint sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSample {
    /// The joint's pose.
    pub pose: Pose,
    /// The joint's radius (metres).
    pub radius: f64,
    /// Position and orientation valid (both OpenXR validity bits set).
    pub valid: bool,
}

impl Default for JointSample {
    fn default() -> Self {
        Self {
            pose: Pose::IDENTITY,
            radius: 0.01,
            valid: false,
        }
    }
}

/// Where a hand's joints come from (`XrHandTrackingDataSourceEXT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HandSource {
    /// The runtime did not say (no `XR_EXT_hand_tracking_data_source`).
    #[default]
    Unknown,
    /// Optical hand tracking (`XR_HAND_TRACKING_DATA_SOURCE_UNOBSTRUCTED_EXT`):
    /// the fingers are the user's.
    Optical,
    /// Derived from a held controller (`XR_HAND_TRACKING_DATA_SOURCE_CONTROLLER_EXT`):
    /// the fingers follow the controller's sensors, the buttons carry intent.
    Controller,
}

impl HandSource {
    pub(super) fn is_unknown(&self) -> bool {
        *self == HandSource::Unknown
    }
}

/// One raw hand sample: the 26 joints and whether the hand is tracked.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandSample {
    /// `XrHandJointLocationsEXT::isActive`.
    pub active: bool,
    /// The joints, indexed by [`Joint`].
    pub joints: [JointSample; JOINT_COUNT],
    /// Where the joints come from (left out of traces when unknown).
    #[serde(default, skip_serializing_if = "HandSource::is_unknown")]
    pub source: HandSource,
}
