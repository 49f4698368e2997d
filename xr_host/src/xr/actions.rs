//! Creating the action set from the core's binding data
//! ([`shapewright::interact::ActionMap::default_map`], the single source
//! of bindings for both hosts), per-session spaces and hand trackers, and
//! reading one frame into the core's [`InputFrame`].
//!
//! A profile's bindings are suggested only when the instance may use it
//! (its extension is enabled, or the instance's OpenXR version made it
//! core): a runtime rejects the whole suggestion otherwise. Haptics go out
//! through the map's `haptic` action.

use openxr as xr;
use shapewright::interact::{
    profile_named, ActionMap, ActionType, ControllerButtons, ControllerSample, HandSample,
    HandSource, InputFrame, JointSample, Pose, JOINT_COUNT,
};
use shapewright::math::{DQuat, DVec3};

use super::input::Haptic;
use super::lifecycle::Running;
use super::spaces::{self, BaseKind, BasePlan, Fallback};
use crate::gfx::xr_raw::{self, DataSource};

/// One created action, typed.
enum AnyAction {
    Pose(xr::Action<xr::Posef>),
    Float(xr::Action<f32>),
    Bool(xr::Action<bool>),
    Haptic(xr::Action<xr::Haptic>),
}

/// The user paths of the two hands.
pub const HAND_PATHS: [&str; 2] = ["/user/hand/left", "/user/hand/right"];

/// The instance-level actions (created once per instance).
pub struct Actions {
    set: xr::ActionSet,
    actions: Vec<(String, AnyAction)>,
    hands: [xr::Path; 2],
    /// Profiles the runtime accepted bindings for.
    pub accepted_profiles: Vec<String>,
    /// Profiles whose bindings the runtime refused with something other
    /// than XR_ERROR_PATH_UNSUPPORTED (skipped, as that one is).
    pub fallbacks: Vec<Fallback>,
}

impl Actions {
    /// Creates the set and one action per item of the core's default map,
    /// and suggests the map's bindings for every profile this instance may
    /// use (`api` version, `enabled_exts`). A profile the runtime rejects
    /// is skipped (any refusal but a loss; one it does not know,
    /// XR_ERROR_PATH_UNSUPPORTED, silently, others with a [`Fallback`]).
    pub fn new(
        instance: &xr::Instance,
        api: [u16; 2],
        enabled_exts: &[String],
    ) -> xr::Result<Self> {
        Self::from_map(instance, api, enabled_exts, &ActionMap::default_map())
    }

    /// As [`Actions::new`] with another map.
    pub fn from_map(
        instance: &xr::Instance,
        api: [u16; 2],
        enabled_exts: &[String],
        map: &ActionMap,
    ) -> xr::Result<Self> {
        let set = instance.create_action_set("shapewright", "Shapewright", 0)?;
        let hands = [
            instance.string_to_path(HAND_PATHS[0])?,
            instance.string_to_path(HAND_PATHS[1])?,
        ];
        let mut actions = Vec::new();
        for item in &map.items {
            let (n, l) = (item.name.as_str(), item.name.replace('_', " "));
            let a = match item.kind {
                ActionType::Pose => AnyAction::Pose(set.create_action(n, &l, &hands)?),
                ActionType::Float => AnyAction::Float(set.create_action(n, &l, &hands)?),
                ActionType::Button => AnyAction::Bool(set.create_action(n, &l, &hands)?),
                ActionType::Vibration => AnyAction::Haptic(set.create_action(n, &l, &hands)?),
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
        let mut fallbacks = Vec::new();
        for profile in profiles {
            // The map's own gate first (it travels with the JSON), then the
            // core's table for maps that predate it.
            let gate = map
                .items
                .iter()
                .flat_map(|i| &i.bindings)
                .find(|b| b.profile == profile);
            let usable = match (gate, profile_named(profile)) {
                (_, Some(p)) => p.available(api, enabled_exts),
                (Some(b), None) => {
                    let by_ext = b
                        .extension
                        .as_ref()
                        .is_some_and(|e| enabled_exts.contains(e));
                    let by_core = b.core_since.is_some_and(|v| api >= v);
                    (b.extension.is_none() && b.core_since.is_none()) || by_ext || by_core
                }
                (None, None) => true,
            };
            if !usable {
                continue;
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
                for (u, comp) in HAND_PATHS.iter().zip(&b.component_paths) {
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
                    AnyAction::Haptic(a) => xr::Binding::new(a, *path),
                })
                .collect();
            let path = instance.string_to_path(profile)?;
            match instance.suggest_interaction_profile_bindings(path, &bindings) {
                Ok(()) => accepted.push(profile.to_string()),
                Err(xr::sys::Result::ERROR_PATH_UNSUPPORTED) => {}
                Err(e) if super::is_loss(e) => return Err(e),
                Err(e) => fallbacks.push(Fallback::refused(
                    &format!("bindings for {profile}"),
                    e,
                    "that profile is skipped",
                )),
            }
        }
        Ok(Self {
            set,
            actions,
            hands,
            accepted_profiles: accepted,
            fallbacks,
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

    /// Sends `pulse` through the `haptic` action (nothing if the map has
    /// none or nothing is bound to it).
    pub fn vibrate<G: xr::Graphics>(
        &self,
        session: &xr::Session<G>,
        pulse: &Haptic,
    ) -> xr::Result<()> {
        let Some(AnyAction::Haptic(a)) = self.get("haptic") else {
            return Ok(());
        };
        let Some(&hand) = self.hands.get(pulse.hand) else {
            return Ok(());
        };
        let event = xr::HapticVibration::new()
            .amplitude(pulse.amplitude.clamp(0.0, 1.0))
            .duration(xr::Duration::from_nanos(
                i64::from(pulse.millis) * 1_000_000,
            ))
            // XR_FREQUENCY_UNSPECIFIED: the runtime picks.
            .frequency(0.0);
        a.apply_feedback(session, hand, &event)
    }

    /// The profile bound to each hand (after a sync), as path strings.
    pub fn bound_profiles<G: xr::Graphics>(
        &self,
        session: &xr::Session<G>,
    ) -> xr::Result<[Option<String>; 2]> {
        let mut out = [None, None];
        for (o, &hand) in out.iter_mut().zip(&self.hands) {
            let p = session.current_interaction_profile(hand)?;
            if p != xr::Path::NULL {
                *o = Some(session.instance().path_to_string(p)?);
            }
        }
        Ok(out)
    }
}

/// Per-session objects: spaces and (optional) hand trackers. Dropped
/// before their session.
pub struct SessionInput {
    base: Option<xr::Space>,
    measuring: Option<(xr::Space, xr::Space)>,
    /// Display time of the first attempt to measure, and the attempts.
    measuring_since: Option<(xr::Time, u32)>,
    /// The base space kind and the floor offset (known once `base` is).
    pub base_kind: Option<(BaseKind, f32)>,
    /// Reference spaces the session offered.
    pub offered_spaces: Vec<String>,
    view: xr::Space,
    grip: [Option<xr::Space>; 2],
    aim: [Option<xr::Space>; 2],
    trackers: Option<[xr::HandTracker; 2]>,
    data_source: bool,
    /// Rungs given up since the host last took them ([`SessionInput::take_fallbacks`]).
    fallbacks: Vec<Fallback>,
}

/// What one read saw besides the frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadInfo {
    /// Hands the runtime reported active, and their data source.
    pub hands: [Option<HandSource>; 2],
}

fn to_pose(p: &xr::Posef) -> Pose {
    let (o, q) = (p.position, p.orientation);
    Pose::new(
        DVec3::new(f64::from(o.x), f64::from(o.y), f64::from(o.z)),
        DQuat::from_xyzw(
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
            f64::from(q.w),
        ),
    )
}

fn valid(flags: xr::SpaceLocationFlags) -> bool {
    flags.contains(
        xr::SpaceLocationFlags::POSITION_VALID | xr::SpaceLocationFlags::ORIENTATION_VALID,
    )
}

impl SessionInput {
    /// Attaches the action set, plans the base space (see
    /// [`super::spaces`]), creates the VIEW space, the controllers' pose
    /// spaces and, if `hand_tracking` (the system can track hands), one
    /// hand tracker per hand. Refused space and tracker creations fall
    /// back (see [`super::spaces`], [`hand_trackers`]) and are listed by
    /// [`SessionInput::take_fallbacks`].
    pub fn new<G: xr::Graphics>(
        session: &xr::Session<G>,
        actions: &Actions,
        caps: &super::InstanceCaps,
    ) -> xr::Result<Self> {
        session.attach_action_sets(&[&actions.set])?;
        let id = xr::Posef::IDENTITY;
        let (plan, offered, mut fallbacks) = spaces::plan(session, caps.local_floor)?;
        let (base, measuring, base_kind) = match plan {
            BasePlan::Ready(s, kind, h) => (Some(s), None, Some((kind, h))),
            BasePlan::Measure { local, stage } => (None, Some((local, stage)), None),
        };
        let view = session.create_reference_space(xr::ReferenceSpaceType::VIEW, id)?;
        let space = |name: &str, h: usize| match actions.pose(name) {
            Some(a) => a.create_space(session, actions.hands[h], id).map(Some),
            None => Ok(None),
        };
        let grip = [space("grip_pose", 0)?, space("grip_pose", 1)?];
        let aim = [space("aim_pose", 0)?, space("aim_pose", 1)?];
        let (trackers, data_source) = if caps.hand_tracking {
            hand_trackers(session, caps.hand_data_source, &mut fallbacks)?
        } else {
            (None, false)
        };
        Ok(Self {
            base,
            measuring,
            measuring_since: None,
            base_kind,
            offered_spaces: offered,
            view,
            grip,
            aim,
            trackers,
            data_source,
            fallbacks,
        })
    }

    /// The rungs given up since the last call (space and tracker
    /// refusals, a STAGE that never located LOCAL), oldest first.
    pub fn take_fallbacks(&mut self) -> Vec<Fallback> {
        std::mem::take(&mut self.fallbacks)
    }

    /// The base space, once established (see [`SessionInput::establish`]).
    pub fn base(&self) -> Option<&xr::Space> {
        self.base.as_ref()
    }

    /// The VIEW space.
    pub fn view(&self) -> &xr::Space {
        &self.view
    }

    /// Whether hand trackers exist.
    pub fn tracks_hands(&self) -> bool {
        self.trackers.is_some()
    }

    /// Makes sure the base space exists (measuring LOCAL in STAGE when
    /// that is the plan, for at most [`spaces::MEASURE_PATIENCE_S`] of
    /// display time or [`spaces::MEASURE_PATIENCE_FRAMES`] frames, then LOCAL at the assumed eye height, said in the
    /// log). Returns whether it does.
    pub fn establish<G: xr::Graphics>(
        &mut self,
        session: &xr::Session<G>,
        time: xr::Time,
    ) -> xr::Result<bool> {
        if self.base.is_some() {
            return Ok(true);
        }
        let Some((local, stage)) = &self.measuring else {
            return Ok(false);
        };
        let measured = match spaces::measure(session, local, stage, time) {
            Ok(m) => m,
            Err(r) if super::is_loss(r) => return Err(r),
            Err(r) => {
                self.fallbacks.push(Fallback::refused(
                    "locating LOCAL in STAGE",
                    r,
                    &format!(
                        "LOCAL at an assumed eye height of {} m",
                        spaces::ASSUMED_EYE_HEIGHT
                    ),
                ));
                return self.assume(session);
            }
        };
        if let Some((base, h)) = measured {
            self.base = Some(base);
            self.base_kind = Some((BaseKind::LocalMeasured, h));
            self.measuring = None;
            return Ok(true);
        }
        let (since, tries) = self.measuring_since.get_or_insert((time, 0));
        *tries += 1;
        let waited = (time.as_nanos() - since.as_nanos()) as f64 * 1e-9;
        if waited > spaces::MEASURE_PATIENCE_S || *tries > spaces::MEASURE_PATIENCE_FRAMES {
            self.fallbacks.push(Fallback(format!(
                "LOCAL could not be located in STAGE ({tries} frames, {waited:.1} s): \
                 LOCAL at an assumed eye height of {} m",
                spaces::ASSUMED_EYE_HEIGHT
            )));
            return self.assume(session);
        }
        Ok(false)
    }

    /// The last rung: LOCAL at the assumed eye height.
    fn assume<G: xr::Graphics>(&mut self, session: &xr::Session<G>) -> xr::Result<bool> {
        self.base = Some(spaces::local_assumed(session)?);
        self.base_kind = Some((BaseKind::LocalAssumed, spaces::ASSUMED_EYE_HEIGHT));
        self.measuring = None;
        Ok(true)
    }

    /// Syncs actions and reads one frame at `time` (seconds in the frame:
    /// `time_s`). Only a running session can be read (the `Running`
    /// witness); the base space must be established.
    pub fn read<G: xr::Graphics>(
        &self,
        running: &Running<xr::Session<G>>,
        actions: &Actions,
        time: xr::Time,
        time_s: f64,
    ) -> xr::Result<(InputFrame, ReadInfo)> {
        let session = running.session();
        session.sync_actions(&[xr::ActiveActionSet::new(&actions.set)])?;
        let Some(base) = &self.base else {
            return Err(xr::sys::Result::ERROR_CALL_ORDER_INVALID);
        };
        let mut frame = InputFrame {
            time: time_s,
            ..Default::default()
        };
        let mut info = ReadInfo::default();
        let head = self.view.locate(base, time)?;
        frame.head = valid(head.location_flags).then(|| to_pose(&head.pose));
        for h in 0..2 {
            let path = actions.hands[h];
            let mut c = ControllerSample {
                grip: Pose::IDENTITY,
                grip_valid: false,
                aim: Pose::IDENTITY,
                aim_valid: false,
                buttons: ControllerButtons::default(),
                buttons_valid: false,
            };
            let mut present = false;
            for (space, pose_name, is_grip) in [
                (&self.grip[h], "grip_pose", true),
                (&self.aim[h], "aim_pose", false),
            ] {
                let (Some(space), Some(action)) = (space, actions.pose(pose_name)) else {
                    continue;
                };
                if !action.is_active(session, path)? {
                    continue;
                }
                present = true;
                let loc = space.locate(base, time)?;
                if valid(loc.location_flags) {
                    let p = to_pose(&loc.pose);
                    if is_grip {
                        (c.grip, c.grip_valid) = (p, true);
                    } else {
                        (c.aim, c.aim_valid) = (p, true);
                    }
                }
            }
            for (name, action) in &actions.actions {
                // Inactive actions (nothing bound on this hand) keep defaults.
                let b = &mut c.buttons;
                match action {
                    AnyAction::Float(a) => {
                        let st = a.state(session, path)?;
                        if !st.is_active {
                            continue;
                        }
                        let v = f64::from(st.current_state);
                        match name.as_str() {
                            "select" => b.select = v,
                            "grab" => b.grab = v,
                            "stick_x" => b.stick[0] = v,
                            "stick_y" => b.stick[1] = v,
                            _ => continue,
                        }
                    }
                    AnyAction::Bool(a) => {
                        let st = a.state(session, path)?;
                        if !st.is_active {
                            continue;
                        }
                        match name.as_str() {
                            "primary" => b.primary = st.current_state,
                            "secondary" => b.secondary = st.current_state,
                            "menu" => b.menu = st.current_state,
                            _ => continue,
                        }
                    }
                    AnyAction::Pose(_) | AnyAction::Haptic(_) => continue,
                }
                c.buttons_valid = true;
                present = true;
            }
            if present {
                frame.controllers[h] = Some(c);
            }
            if let Some(trackers) = &self.trackers {
                let j = xr_raw::locate_hand_joints(base, &trackers[h], time, self.data_source)?;
                if j.active {
                    let source = match j.source {
                        Some(DataSource::Unobstructed) => HandSource::Optical,
                        Some(DataSource::Controller) => HandSource::Controller,
                        _ => HandSource::Unknown,
                    };
                    info.hands[h] = Some(source);
                    let mut joints = [JointSample::default(); JOINT_COUNT];
                    for (o, l) in joints.iter_mut().zip(&j.joints) {
                        if valid(l.location_flags) {
                            *o = JointSample {
                                pose: to_pose(&l.pose),
                                radius: f64::from(l.radius),
                                valid: true,
                            };
                        }
                    }
                    frame.hands[h] = Some(HandSample {
                        active: true,
                        joints,
                        source,
                    });
                }
            }
        }
        Ok((frame, info))
    }
}

/// One hand tracker per hand, falling back (each step a [`Fallback`]):
/// with the data-source struct chained (when `data_source`), then plain,
/// then none (the session runs on controllers). Returns the trackers and
/// whether they report their data source; only a loss is an error.
pub fn hand_trackers<G: xr::Graphics>(
    session: &xr::Session<G>,
    data_source: bool,
    fallbacks: &mut Vec<Fallback>,
) -> xr::Result<(Option<[xr::HandTracker; 2]>, bool)> {
    let pair = |source: bool| -> xr::Result<[xr::HandTracker; 2]> {
        Ok([
            xr_raw::create_hand_tracker(session, xr::Hand::LEFT, source)?,
            xr_raw::create_hand_tracker(session, xr::Hand::RIGHT, source)?,
        ])
    };
    if data_source {
        match pair(true) {
            Ok(t) => return Ok((Some(t), true)),
            Err(r) if super::is_loss(r) => return Err(r),
            Err(r) => fallbacks.push(Fallback::refused(
                "hand trackers with a data source",
                r,
                "trying without",
            )),
        }
    }
    match pair(false) {
        Ok(t) => Ok((Some(t), false)),
        Err(r) if super::is_loss(r) => Err(r),
        Err(r) => {
            fallbacks.push(Fallback::refused(
                "hand trackers",
                r,
                "no hand tracking, controllers only",
            ));
            Ok((None, false))
        }
    }
}
