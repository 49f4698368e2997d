//! Creating the action set from [`super::bindings`], per-session spaces
//! and hand trackers, and reading one sanitized [`InputFrame`].

use openxr as xr;

use super::bindings::{expand, ActionId, ACTIONS, PROFILES};
use super::input::{sanitize_pose, sanitize_value, HandInput, InputFrame, Pose};
use super::lifecycle::Running;

/// The instance-level actions (created once per instance).
pub struct Actions {
    set: xr::ActionSet,
    grip: xr::Action<xr::Posef>,
    aim: xr::Action<xr::Posef>,
    select: xr::Action<f32>,
    squeeze: xr::Action<f32>,
    menu: xr::Action<bool>,
    primary: xr::Action<bool>,
    hands: [xr::Path; 2],
    /// Profiles the runtime accepted bindings for.
    pub accepted_profiles: Vec<&'static str>,
}

impl Actions {
    /// Creates the set and its actions and suggests bindings for every
    /// profile whose extension (if any) is enabled. A profile the runtime
    /// rejects (XR_ERROR_PATH_UNSUPPORTED) is skipped; other errors fail.
    pub fn new(instance: &xr::Instance, enabled_exts: &[String]) -> xr::Result<Self> {
        let set = instance.create_action_set("shapewright", "Shapewright", 0)?;
        let hands = [
            instance.string_to_path("/user/hand/left")?,
            instance.string_to_path("/user/hand/right")?,
        ];
        let name = |id: ActionId| {
            ACTIONS
                .iter()
                .find(|a| a.0 == id)
                .map(|a| (a.1, a.2))
                .unwrap_or(("unnamed", "Unnamed"))
        };
        let (n, l) = name(ActionId::Grip);
        let grip = set.create_action::<xr::Posef>(n, l, &hands)?;
        let (n, l) = name(ActionId::Aim);
        let aim = set.create_action::<xr::Posef>(n, l, &hands)?;
        let (n, l) = name(ActionId::Select);
        let select = set.create_action::<f32>(n, l, &hands)?;
        let (n, l) = name(ActionId::Squeeze);
        let squeeze = set.create_action::<f32>(n, l, &hands)?;
        let (n, l) = name(ActionId::Menu);
        let menu = set.create_action::<bool>(n, l, &hands)?;
        let (n, l) = name(ActionId::Primary);
        let primary = set.create_action::<bool>(n, l, &hands)?;
        let mut accepted = Vec::new();
        for p in PROFILES {
            if let Some(ext) = p.extension {
                if !enabled_exts.iter().any(|e| e == ext) {
                    continue;
                }
            }
            let rows = expand(p);
            let mut paths = Vec::with_capacity(rows.len());
            for (_, path) in &rows {
                paths.push(instance.string_to_path(path)?);
            }
            let bindings: Vec<xr::Binding> = rows
                .iter()
                .zip(&paths)
                .map(|((id, _), &path)| match id {
                    ActionId::Grip => xr::Binding::new(&grip, path),
                    ActionId::Aim => xr::Binding::new(&aim, path),
                    ActionId::Select => xr::Binding::new(&select, path),
                    ActionId::Squeeze => xr::Binding::new(&squeeze, path),
                    ActionId::Menu => xr::Binding::new(&menu, path),
                    ActionId::Primary => xr::Binding::new(&primary, path),
                })
                .collect();
            let profile = instance.string_to_path(p.profile)?;
            match instance.suggest_interaction_profile_bindings(profile, &bindings) {
                Ok(()) => accepted.push(p.profile),
                Err(xr::sys::Result::ERROR_PATH_UNSUPPORTED) => {}
                Err(e) => return Err(e),
            }
        }
        Ok(Self {
            set,
            grip,
            aim,
            select,
            squeeze,
            menu,
            primary,
            hands,
            accepted_profiles: accepted,
        })
    }
}

/// Per-session objects: spaces and (optional) hand trackers. Dropped
/// before their session.
pub struct SessionInput {
    base: xr::Space,
    view: xr::Space,
    grip: [xr::Space; 2],
    aim: [xr::Space; 2],
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
        let grip = [
            actions.grip.create_space(session, actions.hands[0], id)?,
            actions.grip.create_space(session, actions.hands[1], id)?,
        ];
        let aim = [
            actions.aim.create_space(session, actions.hands[0], id)?,
            actions.aim.create_space(session, actions.hands[1], id)?,
        ];
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
            if actions.grip.is_active(session, path)? {
                hand.grip = locate(&self.grip[h], &self.base, time, drops)?;
            }
            if actions.aim.is_active(session, path)? {
                hand.aim = locate(&self.aim[h], &self.base, time, drops)?;
            }
            hand.select = float_state(&actions.select, session, path)?;
            hand.squeeze = float_state(&actions.squeeze, session, path)?;
            hand.menu = bool_state(&actions.menu, session, path)?;
            hand.primary = bool_state(&actions.primary, session, path)?;
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

fn float_state<G>(a: &xr::Action<f32>, s: &xr::Session<G>, path: xr::Path) -> xr::Result<f32> {
    let st = a.state(s, path)?;
    Ok(if st.is_active {
        sanitize_value(st.current_state)
    } else {
        0.0
    })
}

fn bool_state<G>(a: &xr::Action<bool>, s: &xr::Session<G>, path: xr::Path) -> xr::Result<bool> {
    let st = a.state(s, path)?;
    Ok(st.is_active && st.current_state)
}
