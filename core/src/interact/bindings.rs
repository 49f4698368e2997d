//! Controller bindings as data, shared by both hosts.
//!
//! The layout mirrors Blender's bundled `viewport_vr_preview` add-on
//! (`defaults.py`): an action map holds action items (a name, a type, the
//! user paths `/user/hand/left` and `/user/hand/right`), and each item has
//! one binding per interaction profile giving the component path for each
//! user path, a threshold and axis regions. The OpenXR host creates its
//! actions and suggested bindings from [`ActionMap::default_map`]; the
//! Blender add-on reads the same map as JSON (`to_json`) and registers it
//! through `XrActionMaps`. Hosts then fill [`super::ControllerButtons`] by
//! action name. Profiles and component paths are those of the OpenXR 1.0
//! specification (and XR_EXT_hand_interaction for bare hands); where
//! Blender binds an action, the same component is used here (e.g. the
//! simple controller grabs with `menu/click`, the Index with
//! `squeeze/force`).

use serde::{Deserialize, Serialize};

use super::input::Hand;

/// The kind of value an action reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ActionType {
    /// A pose (`XR_ACTION_TYPE_POSE_INPUT`).
    Pose,
    /// A float in `[0, 1]` or `[-1, 1]` (`XR_ACTION_TYPE_FLOAT_INPUT`).
    Float,
    /// A button (`XR_ACTION_TYPE_BOOLEAN_INPUT`).
    Button,
    /// Haptic output (`XR_ACTION_TYPE_VIBRATION_OUTPUT`).
    Vibration,
}

/// Which part of an axis triggers a float action (Blender's
/// `axis0_region`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisRegion {
    /// Either sign.
    Any,
    /// Positive values only.
    Positive,
    /// Negative values only.
    Negative,
}

/// One profile's binding of one action.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Binding {
    /// The interaction profile path.
    pub profile: String,
    /// Component path for the left and the right hand (`None`: the
    /// controller has no such component on that hand).
    pub component_paths: [Option<String>; 2],
    /// Float actions count as pressed above this value.
    pub threshold: f64,
    /// Axis region of the first axis.
    pub axis0_region: AxisRegion,
}

/// One action and its bindings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActionItem {
    /// The action's name (a field of [`super::ControllerButtons`], or a pose).
    pub name: String,
    /// Its value type.
    #[serde(rename = "type")]
    pub kind: ActionType,
    /// The user paths it is bound for.
    pub user_paths: Vec<String>,
    /// One binding per profile.
    pub bindings: Vec<Binding>,
}

/// A set of actions and their bindings for every supported profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActionMap {
    /// Name of the action set.
    pub name: String,
    /// The actions.
    pub items: Vec<ActionItem>,
}

/// Interaction profiles with default bindings: `(short name, path)`.
pub const PROFILES: [(&str, &str); 6] = [
    ("simple", "/interaction_profiles/khr/simple_controller"),
    ("oculus", "/interaction_profiles/oculus/touch_controller"),
    ("index", "/interaction_profiles/valve/index_controller"),
    ("vive", "/interaction_profiles/htc/vive_controller"),
    ("wmr", "/interaction_profiles/microsoft/motion_controller"),
    ("hand", "/interaction_profiles/ext/hand_interaction_ext"),
];

/// Actions of the default map, with their types.
pub const ACTIONS: [(&str, ActionType); 10] = [
    ("grip_pose", ActionType::Pose),
    ("aim_pose", ActionType::Pose),
    ("select", ActionType::Float),
    ("grab", ActionType::Float),
    ("primary", ActionType::Button),
    ("secondary", ActionType::Button),
    ("menu", ActionType::Button),
    ("stick_x", ActionType::Float),
    ("stick_y", ActionType::Float),
    ("haptic", ActionType::Vibration),
];

/// The component of `action` on `profile` (short name) for (left, right).
fn component(profile: &str, action: &str) -> (Option<&'static str>, Option<&'static str>) {
    let both = |p: &'static str| (Some(p), Some(p));
    match (action, profile) {
        ("grip_pose", _) => both("/input/grip/pose"),
        ("aim_pose", _) => both("/input/aim/pose"),
        ("haptic", "hand") => (None, None),
        ("haptic", _) => both("/output/haptic"),
        ("select", "simple") => both("/input/select/click"),
        ("select", "hand") => both("/input/pinch_ext/value"),
        ("select", _) => both("/input/trigger/value"),
        ("grab", "simple") => both("/input/menu/click"),
        ("grab", "hand") => both("/input/grasp_ext/value"),
        ("grab", "oculus") => both("/input/squeeze/value"),
        ("grab", "index") => both("/input/squeeze/force"),
        ("grab", _) => both("/input/squeeze/click"),
        ("primary", "oculus") => (Some("/input/x/click"), Some("/input/a/click")),
        ("primary", "index") => both("/input/a/click"),
        ("primary", "vive" | "wmr") => both("/input/trackpad/click"),
        ("secondary", "oculus") => (Some("/input/y/click"), Some("/input/b/click")),
        ("secondary", "index") => both("/input/b/click"),
        ("menu", "oculus") => (Some("/input/menu/click"), None),
        ("menu", "vive" | "wmr") => both("/input/menu/click"),
        ("stick_x", "oculus" | "index" | "wmr") => both("/input/thumbstick/x"),
        ("stick_y", "oculus" | "index" | "wmr") => both("/input/thumbstick/y"),
        ("stick_x", "vive") => both("/input/trackpad/x"),
        ("stick_y", "vive") => both("/input/trackpad/y"),
        _ => (None, None),
    }
}

impl ActionMap {
    /// Shapewright's default action map for every profile in [`PROFILES`].
    /// An action a controller cannot provide has no binding for it.
    pub fn default_map() -> ActionMap {
        let items = ACTIONS
            .iter()
            .map(|&(name, kind)| ActionItem {
                name: name.to_string(),
                kind,
                user_paths: vec!["/user/hand/left".into(), "/user/hand/right".into()],
                bindings: PROFILES
                    .iter()
                    .filter_map(|&(short, path)| {
                        let (l, r) = component(short, name);
                        (l.is_some() || r.is_some()).then(|| Binding {
                            profile: path.to_string(),
                            component_paths: [l.map(String::from), r.map(String::from)],
                            threshold: 0.3,
                            axis0_region: AxisRegion::Any,
                        })
                    })
                    .collect(),
            })
            .collect();
        ActionMap {
            name: "shapewright_default".to_string(),
            items,
        }
    }

    /// The component path bound to `action` for `hand` on `profile`.
    pub fn component(&self, profile: &str, action: &str, hand: Hand) -> Option<&str> {
        self.items
            .iter()
            .find(|i| i.name == action)?
            .bindings
            .iter()
            .find(|b| b.profile == profile)?
            .component_paths[hand.index()]
        .as_deref()
    }

    /// The map as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// A map from JSON.
    pub fn from_json(text: &str) -> Result<ActionMap, serde_json::Error> {
        serde_json::from_str(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_profile_has_poses_select_and_grab() {
        let map = ActionMap::default_map();
        for (_, profile) in PROFILES {
            for action in ["grip_pose", "aim_pose", "select", "grab"] {
                for hand in Hand::BOTH {
                    let c = map.component(profile, action, hand);
                    assert!(c.is_some(), "{profile} {action} {hand:?}");
                }
            }
        }
        assert_eq!(
            map.component(PROFILES[1].1, "primary", Hand::Left),
            Some("/input/x/click")
        );
        assert_eq!(
            map.component(PROFILES[1].1, "primary", Hand::Right),
            Some("/input/a/click")
        );
        assert_eq!(map.component(PROFILES[0].1, "stick_x", Hand::Left), None);
    }

    #[test]
    fn no_component_is_bound_twice_per_hand_and_paths_are_openxr() {
        let map = ActionMap::default_map();
        for (_, profile) in PROFILES {
            for hand in Hand::BOTH {
                let mut seen = Vec::new();
                for item in &map.items {
                    if let Some(c) = map.component(profile, &item.name, hand) {
                        assert!(c.starts_with("/input/") || c.starts_with("/output/"));
                        assert!(!seen.contains(&c), "{profile} {c} bound twice");
                        seen.push(c);
                    }
                }
            }
        }
    }

    #[test]
    fn json_round_trip() {
        let map = ActionMap::default_map();
        let back = ActionMap::from_json(&map.to_json()).unwrap();
        assert_eq!(back, map);
        assert!(map.to_json().contains("\"type\": \"pose\""));
    }
}
