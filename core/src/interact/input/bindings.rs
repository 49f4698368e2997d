//! Controller bindings as data, shared by both hosts.
//!
//! The layout mirrors Blender's bundled `viewport_vr_preview` add-on
//! (`defaults.py`): an action map holds action items (a name, a type, the
//! user paths `/user/hand/left` and `/user/hand/right`), and each item has
//! one binding per interaction profile giving the component path for each
//! user path, a threshold and axis regions. The OpenXR host creates its
//! actions and suggested bindings from [`ActionMap::default_map`]; the
//! Blender add-on reads the same map as JSON (`to_json`) and registers it
//! through `XrActionMaps`. Hosts then fill [`crate::interact::ControllerButtons`] by
//! action name. Profiles and component paths are those of the OpenXR 1.1
//! specification and its extensions; where Blender binds an action, the
//! same component is used here (e.g. the simple controller grabs with
//! `menu/click`, the Index with `squeeze/force`).
//!
//! The profiles ([`PROFILES`]) cover the headsets people own in 2026: Quest
//! 3/3S (`meta/touch_controller_plus` through XR_META_touch_controller_plus,
//! and its OpenXR 1.1 name `meta/touch_plus_controller`), Quest 2 and
//! older (`oculus/touch_controller`), Quest Pro
//! (`facebook/touch_controller_pro`), Pico 4 (`bytedance/pico4_controller`),
//! Vive Focus 3, Index, Vive wands, WMR, `khr/simple_controller` and bare
//! hands (`ext/hand_interaction_ext`). Each binding names the instance
//! extension it needs ([`Binding::extension`]) or the OpenXR version that
//! made the profile core ([`Binding::core_since`]); a host suggests a
//! profile only when one of them holds (a runtime rejects the whole
//! suggestion otherwise).
//!
//! **Menu on every controller.** Tools cycle their palette with `menu`. A
//! controller whose menu button is reserved by the system on one hand (the
//! right Touch family controllers have only `system/click` there) or that
//! has none (Index) gets the thumbstick click instead, so `menu` reaches the
//! tools on both hands of every controller profile. Two profiles have no
//! spare input for it: `khr/simple_controller` (two buttons, select and
//! grab) and bare hands, which tools reach through gestures.

use serde::{Deserialize, Serialize};

use crate::interact::input::Hand;

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
    /// The instance extension the profile needs (None: core OpenXR).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extension: Option<String>,
    /// The OpenXR version `[major, minor]` that made the profile core.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub core_since: Option<[u16; 2]>,
}

/// One action and its bindings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ActionItem {
    /// The action's name (a field of [`crate::interact::ControllerButtons`], or a pose).
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

/// An interaction profile with default bindings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Profile {
    /// Short name used in the component table.
    pub short: &'static str,
    /// The interaction profile path.
    pub path: &'static str,
    /// The instance extension that defines the profile (None: core).
    pub extension: Option<&'static str>,
    /// The OpenXR version `[major, minor]` that made it core, if any (a
    /// 1.1 instance may suggest it without the extension).
    pub core_since: Option<[u16; 2]>,
}

const fn profile(
    short: &'static str,
    path: &'static str,
    extension: Option<&'static str>,
    core_since: Option<[u16; 2]>,
) -> Profile {
    Profile {
        short,
        path,
        extension,
        core_since,
    }
}

/// Interaction profiles with default bindings.
pub const PROFILES: [Profile; 11] = [
    profile(
        "simple",
        "/interaction_profiles/khr/simple_controller",
        None,
        None,
    ),
    profile(
        "oculus",
        "/interaction_profiles/oculus/touch_controller",
        None,
        None,
    ),
    profile(
        "touch_plus_ext",
        "/interaction_profiles/meta/touch_controller_plus",
        Some("XR_META_touch_controller_plus"),
        None,
    ),
    profile(
        "touch_plus",
        "/interaction_profiles/meta/touch_plus_controller",
        None,
        Some([1, 1]),
    ),
    profile(
        "touch_pro",
        "/interaction_profiles/facebook/touch_controller_pro",
        Some("XR_FB_touch_controller_pro"),
        None,
    ),
    profile(
        "pico4",
        "/interaction_profiles/bytedance/pico4_controller",
        Some("XR_BD_controller_interaction"),
        Some([1, 1]),
    ),
    profile(
        "focus3",
        "/interaction_profiles/htc/vive_focus3_controller",
        Some("XR_HTC_vive_focus3_controller_interaction"),
        Some([1, 1]),
    ),
    profile(
        "index",
        "/interaction_profiles/valve/index_controller",
        None,
        None,
    ),
    profile(
        "vive",
        "/interaction_profiles/htc/vive_controller",
        None,
        None,
    ),
    profile(
        "wmr",
        "/interaction_profiles/microsoft/motion_controller",
        None,
        None,
    ),
    profile(
        "hand",
        "/interaction_profiles/ext/hand_interaction_ext",
        Some("XR_EXT_hand_interaction"),
        None,
    ),
];

/// The profile with this path, if it is one of [`PROFILES`].
pub fn profile_named(path: &str) -> Option<&'static Profile> {
    PROFILES.iter().find(|p| p.path == path)
}

impl Profile {
    /// Whether an instance of OpenXR `version` with `enabled` extensions
    /// may suggest bindings for this profile.
    pub fn available(&self, version: [u16; 2], enabled: &[String]) -> bool {
        let by_ext = self
            .extension
            .is_some_and(|e| enabled.iter().any(|x| x == e));
        let by_core = self.core_since.is_some_and(|v| version >= v);
        (self.extension.is_none() && self.core_since.is_none()) || by_ext || by_core
    }
}

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

/// The Touch-like controllers: X/Y on the left, A/B on the right, a menu
/// button on the left only, a thumbstick, analog trigger and squeeze.
fn touch_like(profile: &str) -> bool {
    matches!(
        profile,
        "oculus" | "touch_plus_ext" | "touch_plus" | "touch_pro" | "pico4" | "focus3"
    )
}

/// The component of `action` on `profile` (short name) for (left, right).
fn component(profile: &str, action: &str) -> (Option<&'static str>, Option<&'static str>) {
    let both = |p: &'static str| (Some(p), Some(p));
    let touch = touch_like(profile);
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
        ("grab", "index") => both("/input/squeeze/force"),
        ("grab", _) if touch => both("/input/squeeze/value"),
        ("grab", _) => both("/input/squeeze/click"),
        ("primary", _) if touch => (Some("/input/x/click"), Some("/input/a/click")),
        ("primary", "index") => both("/input/a/click"),
        ("primary", "vive" | "wmr") => both("/input/trackpad/click"),
        ("secondary", _) if touch => (Some("/input/y/click"), Some("/input/b/click")),
        ("secondary", "index") => both("/input/b/click"),
        // The right Touch-like controller's menu button is the system's.
        ("menu", _) if touch => (Some("/input/menu/click"), Some("/input/thumbstick/click")),
        ("menu", "index") => both("/input/thumbstick/click"),
        ("menu", "vive" | "wmr") => both("/input/menu/click"),
        ("stick_x", "index" | "wmr") => both("/input/thumbstick/x"),
        ("stick_y", "index" | "wmr") => both("/input/thumbstick/y"),
        ("stick_x", _) if touch => both("/input/thumbstick/x"),
        ("stick_y", _) if touch => both("/input/thumbstick/y"),
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
                    .filter_map(|p| {
                        let (l, r) = component(p.short, name);
                        (l.is_some() || r.is_some()).then(|| Binding {
                            profile: p.path.to_string(),
                            component_paths: [l.map(String::from), r.map(String::from)],
                            threshold: 0.3,
                            axis0_region: AxisRegion::Any,
                            extension: p.extension.map(String::from),
                            core_since: p.core_since,
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
        for p in PROFILES {
            for action in ["grip_pose", "aim_pose", "select", "grab"] {
                for hand in Hand::BOTH {
                    let c = map.component(p.path, action, hand);
                    assert!(c.is_some(), "{} {action} {hand:?}", p.path);
                }
            }
        }
        let touch = PROFILES[1].path;
        assert_eq!(
            map.component(touch, "primary", Hand::Left),
            Some("/input/x/click")
        );
        assert_eq!(
            map.component(touch, "primary", Hand::Right),
            Some("/input/a/click")
        );
        assert_eq!(map.component(PROFILES[0].path, "stick_x", Hand::Left), None);
    }

    #[test]
    fn every_controller_has_a_menu_on_both_hands() {
        // Issue 16: the Index had none ("No bindings!" in Monado), so the
        // object tool could not cycle shapes on it.
        let map = ActionMap::default_map();
        for p in PROFILES {
            let has = Hand::BOTH.map(|h| map.component(p.path, "menu", h).is_some());
            match p.short {
                // Two buttons (select, grab), or bare hands: documented.
                "simple" | "hand" => assert_eq!(has, [false, false], "{}", p.path),
                _ => assert_eq!(has, [true, true], "{}", p.path),
            }
        }
        let index = profile_named("/interaction_profiles/valve/index_controller").unwrap();
        assert_eq!(
            map.component(index.path, "menu", Hand::Right),
            Some("/input/thumbstick/click")
        );
    }

    #[test]
    fn the_2026_headsets_are_covered_and_gated_by_their_extension() {
        for (path, ext) in [
            (
                "meta/touch_controller_plus",
                Some("XR_META_touch_controller_plus"),
            ),
            ("meta/touch_plus_controller", None),
            (
                "facebook/touch_controller_pro",
                Some("XR_FB_touch_controller_pro"),
            ),
            (
                "bytedance/pico4_controller",
                Some("XR_BD_controller_interaction"),
            ),
            (
                "htc/vive_focus3_controller",
                Some("XR_HTC_vive_focus3_controller_interaction"),
            ),
            ("valve/index_controller", None),
            ("htc/vive_controller", None),
            ("microsoft/motion_controller", None),
            ("khr/simple_controller", None),
            ("ext/hand_interaction_ext", Some("XR_EXT_hand_interaction")),
        ] {
            let p = profile_named(&format!("/interaction_profiles/{path}")).unwrap();
            assert_eq!(p.extension, ext, "{path}");
            if let Some(e) = ext {
                // Not on a 1.0 instance without the extension; on one with it.
                assert!(!p.available([1, 0], &[]), "{path}");
                assert!(p.available([1, 0], &[e.to_string()]), "{path}");
            }
        }
        // The 1.1 names need a 1.1 instance; core 1.0 profiles are always there.
        let plus = profile_named("/interaction_profiles/meta/touch_plus_controller").unwrap();
        assert!(!plus.available([1, 0], &[]) && plus.available([1, 1], &[]));
        let pico = profile_named("/interaction_profiles/bytedance/pico4_controller").unwrap();
        assert!(pico.available([1, 1], &[]));
        assert!(PROFILES[1].available([1, 0], &[]));
        // The map carries the gate, so Blender can skip what it cannot enable.
        let map = ActionMap::default_map();
        let b = map.items[0]
            .bindings
            .iter()
            .find(|b| b.profile == pico.path)
            .unwrap();
        assert_eq!(b.extension.as_deref(), Some("XR_BD_controller_interaction"));
        assert_eq!(b.core_since, Some([1, 1]));
    }

    #[test]
    fn no_component_is_bound_twice_per_hand_and_paths_are_openxr() {
        let map = ActionMap::default_map();
        for p in PROFILES {
            for hand in Hand::BOTH {
                let mut seen = Vec::new();
                for item in &map.items {
                    if let Some(c) = map.component(p.path, &item.name, hand) {
                        assert!(c.starts_with("/input/") || c.starts_with("/output/"));
                        assert!(!seen.contains(&c), "{} {c} bound twice", p.path);
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
        // Maps written before the gates existed still load.
        let old = r#"{"name":"m","items":[{"name":"select","type":"float","user_paths":[],
            "bindings":[{"profile":"/interaction_profiles/khr/simple_controller",
            "component_paths":["/input/select/click",null],"threshold":0.3,"axis0_region":"any"}]}]}"#;
        let m = ActionMap::from_json(old).unwrap();
        assert_eq!(m.items[0].bindings[0].extension, None);
    }
}
