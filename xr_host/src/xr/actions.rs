//! Creating the action set from the core's binding data
//! ([`shapewright::interact::ActionMap::default_map`], the single source
//! of bindings for both hosts), per-session spaces and hand trackers, and
//! reading one sanitized [`InputFrame`].

use openxr as xr;
use shapewright::interact::{ActionMap, ActionType};

use super::input::{sanitize_axis, sanitize_pose, sanitize_value, HandInput, InputFrame, Pose};
use super::lifecycle::Running;

/// The instance extension an interaction profile needs, if any (the
/// profiles of the core's map are core OpenXR 1.0 except bare hands).
pub fn profile_extension(profile: &str) -> Option<&'static str> {
    (profile == "/interaction_profiles/ext/hand_interaction_ext")
        .then_some("XR_EXT_hand_interaction")
}

/// One created action, typed.
enum AnyAction {
    Pose(xr::Action<xr::Posef>),
    Float(xr::Action<f32>),
    Bool(xr::Action<bool>),
}

/// A button action's value this frame.
enum Value {
    Float(f32),
    Bool(bool),
}

/// The instance-level actions (created once per instance).
pub struct Actions {
    set: xr::ActionSet,
    actions: Vec<(String, AnyAction)>,
    hands: [xr::Path; 2],
    /// Profiles the runtime accepted bindings for.
    pub accepted_profiles: Vec<String>,
}

impl Actions {
    /// Creates the set and one action per item of the core's default map
    /// (vibration items are left out: the host sends no haptics), and
    /// suggests the map's bindings for every profile whose extension (if
    /// any) is enabled. A profile the runtime rejects
    /// (XR_ERROR_PATH_UNSUPPORTED) is skipped; other errors fail.
    pub fn new(instance: &xr::Instance, enabled_exts: &[String]) -> xr::Result<Self> {
        Self::from_map(instance, enabled_exts, &ActionMap::default_map())
    }

    /// As [`Actions::new`] with another map.
    pub fn from_map(
        instance: &xr::Instance,
        enabled_exts: &[String],
        map: &ActionMap,
    ) -> xr::Result<Self> {
        let set = instance.create_action_set("shapewright", "Shapewright", 0)?;
        let user = ["/user/hand/left", "/user/hand/right"];
        let hands = [
            instance.string_to_path(user[0])?,
            instance.string_to_path(user[1])?,
        ];
        let mut actions = Vec::new();
        for item in &map.items {
            let (n, l) = (item.name.as_str(), item.name.replace('_', " "));
            let a = match item.kind {
                ActionType::Pose => AnyAction::Pose(set.create_action(n, &l, &hands)?),
                ActionType::Float => AnyAction::Float(set.create_action(n, &l, &hands)?),
                ActionType::Button => AnyAction::Bool(set.create_action(n, &l, &hands)?),
                ActionType::Vibration => continue,
            };
            actions.push((item.name.clone(), a));
        }
        let mut profiles: Vec<&str> = Vec::new();
        for b in map.items.iter().flat_map(|i| &i.bindings) {
            if !profiles.contains(&b.profile.as_str()) {
                profiles.push(&b.profile);
            }
        }
        let mut accepted = Vec::new();
        for profile in profiles {
            if let Some(ext) = profile_extension(profile) {
                if !enabled_exts.iter().any(|e| e == ext) {
                    continue;
                }
            }
            let mut rows = Vec::new();
            for (item, action) in map
                .items
                .iter()
                .filter_map(|i| Some((i, &actions.iter().find(|a| a.0 == i.name)?.1)))
            {
                let Some(b) = item.bindings.iter().find(|b| b.profile == profile) else {
                    continue;
                };
                for (u, comp) in user.iter().zip(&b.component_paths) {
                    if let Some(comp) = comp {
                        rows.push((action, instance.string_to_path(&format!("{u}{comp}"))?));
                    }
                }
            }
            let bindings: Vec<xr::Binding> = rows
                .iter()
                .map(|(action, path)| match action {
                    AnyAction::Pose(a) => xr::Binding::new(a, *path),
                    AnyAction::Float(a) => xr::Binding::new(a, *path),
                    AnyAction::Bool(a) => xr::Binding::new(a, *path),
                })
                .collect();
            let path = instance.string_to_path(profile)?;
            match instance.suggest_interaction_profile_bindings(path, &bindings) {
                Ok(()) => accepted.push(profile.to_string()),
                Err(xr::sys::Result::ERROR_PATH_UNSUPPORTED) => {}
                Err(e) => return Err(e),
            }
        }
        Ok(Self {
            set,
            actions,
            hands,
            accepted_profiles: accepted,
        })
    }

    fn get(&self, name: &str) -> Option<&AnyAction> {
        self.actions.iter().find(|a| a.0 == name).map(|a| &a.1)
    }

    fn pose(&self, name: &str) -> Option<&xr::Action<xr::Posef>> {
        match self.get(name)? {
            AnyAction::Pose(a) => Some(a),
            _ => None,
        }
    }
}

/// Per-session objects: spaces and (optional) hand trackers. Dropped
/// before their session.
pub struct SessionInput {
    base: xr::Space,
    view: xr::Space,
    grip: [Option<xr::Space>; 2],
    aim: [Option<xr::Space>; 2],
    trackers: Option<[xr::HandTracker; 2]>,
}

/// Counts of what was dropped while reading input.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DropCounts {
    /// Poses (head, grip, aim) dropped for VALID bits unset or bad numbers.
    pub poses: u64,
    /// Hand joints dropped.
    pub joints: u64,
}

impl SessionInput {
    /// Attaches the action set and creates spaces (LOCAL base, VIEW head)
    /// and, if `hand_tracking`, one hand tracker per hand.
    pub fn new<G: xr::Graphics>(
        session: &xr::Session<G>,
        actions: &Actions,
        hand_tracking: bool,
    ) -> xr::Result<Self> {
        session.attach_action_sets(&[&actions.set])?;
        let id = xr::Posef::IDENTITY;
        let base = session.create_reference_space(xr::ReferenceSpaceType::LOCAL, id)?;
        let view = session.create_reference_space(xr::ReferenceSpaceType::VIEW, id)?;
        let space = |name: &str, h: usize| match actions.pose(name) {
            Some(a) => a.create_space(session, actions.hands[h], id).map(Some),
            None => Ok(None),
        };
        let grip = [space("grip_pose", 0)?, space("grip_pose", 1)?];
        let aim = [space("aim_pose", 0)?, space("aim_pose", 1)?];
        let trackers = if hand_tracking {
            Some([
                session.create_hand_tracker(xr::Hand::LEFT)?,
                session.create_hand_tracker(xr::Hand::RIGHT)?,
            ])
        } else {
            None
        };
        Ok(Self {
            base,
            view,
            grip,
            aim,
            trackers,
        })
    }

    /// The base (LOCAL) space.
    pub fn base(&self) -> &xr::Space {
        &self.base
    }

    /// Syncs actions and reads one frame at `time`. Only a running session
    /// can be read (the `Running` witness).
    pub fn read<G: xr::Graphics>(
        &self,
        running: &Running<xr::Session<G>>,
        actions: &Actions,
        time: xr::Time,
        index: u64,
        drops: &mut DropCounts,
    ) -> xr::Result<InputFrame> {
        let session = running.session();
        session.sync_actions(&[xr::ActiveActionSet::new(&actions.set)])?;
        let mut frame = InputFrame {
            index,
            time_ns: time.as_nanos(),
            ..Default::default()
        };
        frame.head = locate(&self.view, &self.base, time, drops)?;
        for h in 0..2 {
            let path = actions.hands[h];
            let hand = &mut frame.hands[h];
            for (space, pose_name, out) in [
                (&self.grip[h], "grip_pose", &mut hand.grip),
                (&self.aim[h], "aim_pose", &mut hand.aim),
            ] {
                if let (Some(space), Some(action)) = (space, actions.pose(pose_name)) {
                    if action.is_active(session, path)? {
                        *out = locate(space, &self.base, time, drops)?;
                    }
                }
            }
            for (name, action) in &actions.actions {
                // Inactive actions (nothing bound on this hand) keep defaults.
                let value = match action {
                    AnyAction::Pose(_) => continue,
                    AnyAction::Float(a) => {
                        let st = a.state(session, path)?;
                        st.is_active.then_some(Value::Float(st.current_state))
                    }
                    AnyAction::Bool(a) => {
                        let st = a.state(session, path)?;
                        st.is_active.then_some(Value::Bool(st.current_state))
                    }
                };
                let Some(value) = value else { continue };
                hand.active = true;
                match (name.as_str(), value) {
                    ("select", Value::Float(v)) => hand.select = sanitize_value(v),
                    ("grab", Value::Float(v)) => hand.squeeze = sanitize_value(v),
                    ("stick_x", Value::Float(v)) => hand.stick[0] = sanitize_axis(v),
                    ("stick_y", Value::Float(v)) => hand.stick[1] = sanitize_axis(v),
                    ("primary", Value::Bool(b)) => hand.primary = b,
                    ("secondary", Value::Bool(b)) => hand.secondary = b,
                    ("menu", Value::Bool(b)) => hand.menu = b,
                    _ => {}
                }
            }
            if let Some(trackers) = &self.trackers {
                read_joints(&self.base, &trackers[h], time, hand, drops)?;
            }
        }
        Ok(frame)
    }
}

fn locate(
    space: &xr::Space,
    base: &xr::Space,
    time: xr::Time,
    drops: &mut DropCounts,
) -> xr::Result<Option<Pose>> {
    let loc = space.locate(base, time)?;
    let f = loc.location_flags;
    let pose = sanitize_pose(
        f.contains(xr::SpaceLocationFlags::POSITION_VALID),
        f.contains(xr::SpaceLocationFlags::ORIENTATION_VALID),
        [
            loc.pose.position.x,
            loc.pose.position.y,
            loc.pose.position.z,
        ],
        [
            loc.pose.orientation.x,
            loc.pose.orientation.y,
            loc.pose.orientation.z,
            loc.pose.orientation.w,
        ],
    );
    if pose.is_none() {
        drops.poses += 1;
    }
    Ok(pose)
}

fn read_joints(
    base: &xr::Space,
    tracker: &xr::HandTracker,
    time: xr::Time,
    hand: &mut HandInput,
    drops: &mut DropCounts,
) -> xr::Result<()> {
    let Some(joints) = base.locate_hand_joints(tracker, time)? else {
        return Ok(());
    };
    hand.joints = joints
        .iter()
        .map(|j| {
            let f = j.location_flags;
            let p = sanitize_pose(
                f.contains(xr::SpaceLocationFlags::POSITION_VALID),
                f.contains(xr::SpaceLocationFlags::ORIENTATION_VALID),
                [j.pose.position.x, j.pose.position.y, j.pose.position.z],
                [
                    j.pose.orientation.x,
                    j.pose.orientation.y,
                    j.pose.orientation.z,
                    j.pose.orientation.w,
                ],
            );
            if p.is_none() {
                drops.joints += 1;
            }
            p
        })
        .collect();
    Ok(())
}
