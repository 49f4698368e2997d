//! A scripted hand/controller puppet that records traces: tests and the
//! fixtures in `tests/data` are written as short scripts of moves, presses
//! and gestures rather than captured in a headset.
//!
//! Poses are in stage space. Controller aim and grip coincide (the aim
//! points along the grip's -Z). Hands use the kinematic hand model.

use crate::math::{DQuat, DVec3};

use super::hand_sequences::hand_sample;
use crate::interact::gesture::handmodel::{hand_pose, HandParams, Rng};
use crate::interact::gesture::GestureLabel;
use crate::interact::input::{ControllerButtons, ControllerSample, Hand, InputFrame, Pose};
use crate::interact::trace::{ModelPlacement, Trace, TraceHeader, TRACE_FORMAT, TRACE_VERSION};

/// A controller button of the puppet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Button {
    /// Trigger.
    Select,
    /// Squeeze.
    Grab,
    /// A / X.
    Primary,
    /// B / Y.
    Secondary,
    /// Menu.
    Menu,
}

/// The puppet: current state plus the frames recorded so far.
#[derive(Clone, Debug)]
pub struct Puppet {
    fps: f64,
    time: f64,
    head: Pose,
    controllers: [Option<ControllerSample>; 2],
    hands: [Option<(HandParams, Pose)>; 2],
    jitter: f64,
    rng: Rng,
    frames: Vec<InputFrame>,
}

impl Puppet {
    /// A puppet at `fps` frames per second, head at 1.6 m, no controllers
    /// and no hands yet.
    pub fn new(fps: f64) -> Puppet {
        Puppet {
            fps,
            time: 0.0,
            head: Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY),
            controllers: [None, None],
            hands: [None, None],
            jitter: 0.001,
            rng: Rng::new(7),
            frames: Vec::new(),
        }
    }

    /// Turns the head (keeping its position) to look at `target` with
    /// world +Y up.
    pub fn look_at(&mut self, target: DVec3) -> &mut Self {
        let z = (self.head.position - target).normalize();
        let x = DVec3::Y.cross(z).normalize();
        let y = z.cross(x);
        self.head.orientation =
            DQuat::from_mat3(&crate::math::DMat3::from_cols(x, y, z)).normalize();
        self
    }

    /// Gives `hand` a controller at `pose`, all buttons released.
    pub fn controller(&mut self, hand: Hand, pose: Pose) -> &mut Self {
        self.controllers[hand.index()] = Some(ControllerSample {
            grip: pose,
            grip_valid: true,
            aim: pose,
            aim_valid: true,
            buttons: ControllerButtons::default(),
            buttons_valid: true,
        });
        self
    }

    /// Shows a tracked hand making `label` with its wrist at `wrist`.
    pub fn hand(&mut self, hand: Hand, label: GestureLabel, wrist: Pose) -> &mut Self {
        self.hands[hand.index()] = Some((hand_params(label), wrist));
        self
    }

    /// Removes `hand`'s tracked hand (tracking lost).
    pub fn hide_hand(&mut self, hand: Hand) -> &mut Self {
        self.hands[hand.index()] = None;
        self
    }

    /// Records frames for `secs` seconds with nothing changing.
    pub fn wait(&mut self, secs: f64) -> &mut Self {
        let n = (secs * self.fps).round().max(1.0) as usize;
        for _ in 0..n {
            self.emit();
        }
        self
    }

    /// Moves `hand`'s controller (or tracked wrist) to `to` over `secs`.
    pub fn move_to(&mut self, hand: Hand, to: Pose, secs: f64) -> &mut Self {
        let from = self.pose_of(hand);
        let n = (secs * self.fps).round().max(1.0) as usize;
        for k in 1..=n {
            let a = k as f64 / n as f64;
            let a = a * a * (3.0 - 2.0 * a);
            let p = Pose::new(
                from.position.lerp(to.position, a),
                from.orientation.slerp(to.orientation, a),
            );
            self.set_pose(hand, p);
            self.emit();
        }
        self
    }

    /// Moves `hand` to `position`, aiming at `target`, over `secs`.
    pub fn aim(&mut self, hand: Hand, position: DVec3, target: DVec3, secs: f64) -> &mut Self {
        let q = DQuat::from_rotation_arc(DVec3::NEG_Z, (target - position).normalize());
        self.move_to(hand, Pose::new(position, q), secs)
    }

    /// Changes `hand`'s tracked gesture over `secs` (blending the pose).
    pub fn gesture(&mut self, hand: Hand, label: GestureLabel, secs: f64) -> &mut Self {
        let Some((from, wrist)) = self.hands[hand.index()] else {
            return self;
        };
        let to = hand_params(label);
        let n = (secs * self.fps).round().max(1.0) as usize;
        for k in 1..=n {
            let p = from.lerp(&to, k as f64 / n as f64);
            self.hands[hand.index()] = Some((p, wrist));
            self.emit();
        }
        self
    }

    /// Presses (`true`) or releases a button, then records one frame.
    pub fn set(&mut self, hand: Hand, button: Button, down: bool) -> &mut Self {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            let b = &mut c.buttons;
            let v = if down { 1.0 } else { 0.0 };
            match button {
                Button::Select => b.select = v,
                Button::Grab => b.grab = v,
                Button::Primary => b.primary = down,
                Button::Secondary => b.secondary = down,
                Button::Menu => b.menu = down,
            }
        }
        self.emit();
        self
    }

    /// Sets `hand`'s trigger (`select`) to `value` (a partial press, e.g.
    /// brush pressure), then records one frame.
    pub fn trigger(&mut self, hand: Hand, value: f64) -> &mut Self {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.buttons.select = value;
        }
        self.emit();
        self
    }

    /// Press, hold 0.1 s, release, wait 0.1 s.
    pub fn click(&mut self, hand: Hand, button: Button) -> &mut Self {
        self.set(hand, button, true)
            .wait(0.1)
            .set(hand, button, false)
            .wait(0.1)
    }

    /// Pushes the stick fully left (`-1`) or right (`1`) for 0.1 s, then
    /// lets it spring back.
    pub fn flick(&mut self, hand: Hand, x: f64) -> &mut Self {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.buttons.stick = [x, 0.0];
        }
        self.wait(0.1);
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.buttons.stick = [0.0, 0.0];
        }
        self.wait(0.1)
    }

    /// Pushes the stick fully down (`-1`) or up (`1`) for 0.1 s, then lets
    /// it spring back.
    pub fn flick_y(&mut self, hand: Hand, y: f64) -> &mut Self {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.buttons.stick = [0.0, y];
        }
        self.wait(0.1);
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.buttons.stick = [0.0, 0.0];
        }
        self.wait(0.1)
    }

    /// Marks `hand`'s controller poses invalid for `secs` (tracking lost).
    pub fn lose_tracking(&mut self, hand: Hand, secs: f64) -> &mut Self {
        self.set_valid(hand, false);
        self.wait(secs);
        self.set_valid(hand, true);
        self
    }

    /// Records one frame whose `hand` controller pose is NaN.
    pub fn nan_frame(&mut self, hand: Hand) -> &mut Self {
        let keep = self.controllers[hand.index()];
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.grip.position.x = f64::NAN;
            c.aim.orientation.w = f64::NAN;
        }
        self.emit();
        self.controllers[hand.index()] = keep;
        self
    }

    /// Jumps `hand`'s controller by `offset` in one frame (a teleport).
    pub fn teleport(&mut self, hand: Hand, offset: DVec3) -> &mut Self {
        let p = self.pose_of(hand);
        self.set_pose(hand, Pose::new(p.position + offset, p.orientation));
        self.emit();
        self
    }

    /// The frames recorded so far.
    pub fn frames(&self) -> &[InputFrame] {
        &self.frames
    }

    /// The recorded trace.
    pub fn trace(&self, model: ModelPlacement, note: &str) -> Trace {
        Trace {
            header: TraceHeader {
                format: TRACE_FORMAT.to_string(),
                version: TRACE_VERSION,
                fps: self.fps,
                model,
                tool: "object".to_string(),
                note: note.to_string(),
                modeler: false,
            },
            frames: self.frames.clone(),
        }
    }

    fn set_valid(&mut self, hand: Hand, valid: bool) {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.grip_valid = valid;
            c.aim_valid = valid;
        }
    }

    fn pose_of(&self, hand: Hand) -> Pose {
        if let Some(c) = &self.controllers[hand.index()] {
            return c.grip;
        }
        self.hands[hand.index()].map_or(Pose::IDENTITY, |(_, w)| w)
    }

    fn set_pose(&mut self, hand: Hand, p: Pose) {
        if let Some(c) = self.controllers[hand.index()].as_mut() {
            c.grip = p;
            c.aim = p;
        } else if let Some((_, w)) = self.hands[hand.index()].as_mut() {
            *w = p;
        }
    }

    fn emit(&mut self) {
        let hands = [0, 1].map(|i| {
            self.hands[i].map(|(p, w)| {
                let h = if i == 0 { Hand::Left } else { Hand::Right };
                hand_sample(&hand_pose(&p, h, &w), self.jitter, &mut self.rng)
            })
        });
        // Rounded to 10 µm and 1e-6 so traces stay short; the trace, not
        // the script, is what replays bit for bit.
        let controllers = self.controllers.map(|c| {
            c.map(|mut c| {
                c.grip = quantize(c.grip);
                c.aim = quantize(c.aim);
                c
            })
        });
        let hands = hands.map(|h| {
            h.map(|mut h| {
                for j in h.joints.iter_mut() {
                    j.pose = quantize(j.pose);
                }
                h
            })
        });
        self.frames.push(InputFrame {
            time: (self.time * 1e6).round() / 1e6,
            head: Some(self.head),
            hands,
            controllers,
        });
        self.time += 1.0 / self.fps;
    }
}

fn quantize(p: Pose) -> Pose {
    let r = |x: f64, s: f64| (x * s).round() / s;
    let v = p.position;
    let q = p.orientation;
    Pose::new(
        DVec3::new(r(v.x, 1e5), r(v.y, 1e5), r(v.z, 1e5)),
        DQuat::from_xyzw(r(q.x, 1e6), r(q.y, 1e6), r(q.z, 1e6), r(q.w, 1e6)),
    )
}

/// The hand shape [`Puppet::hand`] holds for `label` (one fixed sample of
/// the hand model, unit size), for tests that place its joints.
pub fn hand_params(label: GestureLabel) -> HandParams {
    let mut rng = Rng::new(label as u64 + 100);
    let mut p = HandParams::sample(label, &mut rng);
    p.size = 1.0;
    p
}

/// Feeds the frames `p` recorded since `fed` to `s`, none of which may
/// make a command (palette and gesture tests).
pub fn feed_quietly(
    p: &Puppet,
    s: &mut crate::interact::Session,
    doc: &crate::doc::Document,
    fed: &mut usize,
) {
    for f in &p.frames()[*fed..] {
        assert!(s.step(f, doc).is_none(), "a command at t = {}", f.time);
    }
    *fed = p.frames().len();
}
