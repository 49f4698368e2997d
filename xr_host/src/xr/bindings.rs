//! Actions and suggested bindings, kept as data (as Blender's
//! `viewport_vr_preview` does): one table row per (profile, action, path).
//! Adding a controller means adding rows, not code.

/// The actions the host reads, each per hand (`/user/hand/left|right`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ActionId {
    /// Grip pose (where the hand holds the controller).
    Grip,
    /// Aim pose (the pointing ray).
    Aim,
    /// Select / trigger / pinch, 0..1.
    Select,
    /// Squeeze / grab / grasp, 0..1.
    Squeeze,
    /// Menu button.
    Menu,
    /// Primary face button (A/X, trackpad click): undo in the modeler.
    Primary,
}

/// Action names as OpenXR sees them (lowercase, unique in the set).
pub const ACTIONS: &[(ActionId, &str, &str)] = &[
    (ActionId::Grip, "grip_pose", "Grip pose"),
    (ActionId::Aim, "aim_pose", "Aim pose"),
    (ActionId::Select, "select", "Select"),
    (ActionId::Squeeze, "squeeze", "Squeeze"),
    (ActionId::Menu, "menu", "Menu"),
    (ActionId::Primary, "primary", "Primary button"),
];

/// One interaction profile's suggested bindings.
#[derive(Clone, Copy, Debug)]
pub struct ProfileBindings {
    /// The interaction profile path.
    pub profile: &'static str,
    /// The instance extension the profile needs, if any.
    pub extension: Option<&'static str>,
    /// (action, component path under both `/user/hand/{left,right}`).
    pub both_hands: &'static [(ActionId, &'static str)],
    /// Bindings for the left hand only (full paths).
    pub left_only: &'static [(ActionId, &'static str)],
    /// Bindings for the right hand only (full paths).
    pub right_only: &'static [(ActionId, &'static str)],
}

const POSES: [(ActionId, &str); 2] = [
    (ActionId::Grip, "input/grip/pose"),
    (ActionId::Aim, "input/aim/pose"),
];

/// The suggested bindings for every supported profile.
pub const PROFILES: &[ProfileBindings] = &[
    ProfileBindings {
        profile: "/interaction_profiles/khr/simple_controller",
        extension: None,
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/select/click"),
            (ActionId::Menu, "input/menu/click"),
        ],
        left_only: &[],
        right_only: &[],
    },
    ProfileBindings {
        profile: "/interaction_profiles/oculus/touch_controller",
        extension: None,
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/trigger/value"),
            (ActionId::Squeeze, "input/squeeze/value"),
        ],
        left_only: &[
            (ActionId::Menu, "/user/hand/left/input/menu/click"),
            (ActionId::Primary, "/user/hand/left/input/x/click"),
        ],
        right_only: &[(ActionId::Primary, "/user/hand/right/input/a/click")],
    },
    ProfileBindings {
        profile: "/interaction_profiles/valve/index_controller",
        extension: None,
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/trigger/value"),
            (ActionId::Squeeze, "input/squeeze/value"),
            (ActionId::Menu, "input/b/click"),
            (ActionId::Primary, "input/a/click"),
        ],
        left_only: &[],
        right_only: &[],
    },
    ProfileBindings {
        profile: "/interaction_profiles/htc/vive_controller",
        extension: None,
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/trigger/value"),
            (ActionId::Squeeze, "input/squeeze/click"),
            (ActionId::Menu, "input/menu/click"),
            (ActionId::Primary, "input/trackpad/click"),
        ],
        left_only: &[],
        right_only: &[],
    },
    ProfileBindings {
        profile: "/interaction_profiles/microsoft/motion_controller",
        extension: None,
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/trigger/value"),
            (ActionId::Squeeze, "input/squeeze/click"),
            (ActionId::Menu, "input/menu/click"),
            (ActionId::Primary, "input/trackpad/click"),
        ],
        left_only: &[],
        right_only: &[],
    },
    ProfileBindings {
        profile: "/interaction_profiles/ext/hand_interaction_ext",
        extension: Some("XR_EXT_hand_interaction"),
        both_hands: &[
            POSES[0],
            POSES[1],
            (ActionId::Select, "input/pinch_ext/value"),
            (ActionId::Squeeze, "input/grasp_ext/value"),
        ],
        left_only: &[],
        right_only: &[],
    },
];

/// All (action, full path) pairs of `p`.
pub fn expand(p: &ProfileBindings) -> Vec<(ActionId, String)> {
    let mut out = Vec::new();
    for hand in ["left", "right"] {
        for (a, comp) in p.both_hands {
            out.push((*a, format!("/user/hand/{hand}/{comp}")));
        }
    }
    for (a, path) in p.left_only.iter().chain(p.right_only) {
        out.push((*a, path.to_string()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_profile_binds_both_poses_and_select_for_both_hands() {
        for p in PROFILES {
            let b = expand(p);
            for hand in ["left", "right"] {
                for a in [ActionId::Grip, ActionId::Aim, ActionId::Select] {
                    assert!(
                        b.iter()
                            .any(|(x, path)| *x == a
                                && path.starts_with(&format!("/user/hand/{hand}/"))),
                        "{} lacks {a:?} for {hand}",
                        p.profile
                    );
                }
            }
            let mut paths: Vec<_> = b.iter().map(|x| &x.1).collect();
            paths.sort();
            let n = paths.len();
            paths.dedup();
            assert_eq!(n, paths.len(), "{} binds a path twice", p.profile);
        }
        assert_eq!(PROFILES.len(), 6);
    }
}
