//! The puppet scripts of `tests/data/mug.trace.jsonl` and
//! `tests/data/teapot.trace.jsonl`: a right hand models the mug and the
//! teapot of `tests/data/{mug,teapot}.jsonl` by gestures only (OPEN aims,
//! POINT selects and sketches, FIST drags, PINCH sets the shape type),
//! recorded as raw joints at 25 Hz (hand frames are ~3 KB of JSON, so
//! 25 Hz keeps each trace under 4 MB).
//!
//! The scripts place the hand in model coordinates (the desk placement)
//! and turn the wrist so that the tool's hand ray (palm, along the mean
//! knuckle direction) points at the intended target.

use crate::math::fm::DetMath as _;
use crate::math::{DMat3, DQuat, DVec3};

use crate::interact::gesture::controller_hand::point_tip_offset;
use crate::interact::gesture::handmodel::{hand_pose, HandParams, Rng};
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::GestureLabel;
use crate::interact::input::{Hand, Joint, Pose};
use crate::interact::testkit::puppet::{Button, Puppet};
use crate::interact::trace::{ModelPlacement, Trace};

const FPS: f64 = 25.0;
const R: Hand = Hand::Right;

/// A right-hand puppet working in model coordinates: a tracked hand, or a
/// controller whose buttons stand for the gestures (see
/// [`crate::interact::gesture::controller_hand`]).
pub(crate) struct Rig {
    pub(crate) p: Puppet,
    place: ModelPlacement,
    model: Similarity,
    /// Current ray orientation: the hand ray (or the aim) along its -Z.
    q: DQuat,
    /// Current palm (world).
    palm: DVec3,
    /// Drive a controller instead of a tracked hand.
    controller: bool,
}

fn local(label: GestureLabel, j: Joint) -> DVec3 {
    let mut rng = Rng::new(label as u64 + 100);
    let mut p = HandParams::sample(label, &mut rng);
    p.size = 1.0;
    hand_pose(&p, R, &Pose::IDENTITY)[j.index()].position
}

fn ray_local() -> DVec3 {
    let k = [
        Joint::IndexProximal,
        Joint::MiddleProximal,
        Joint::RingProximal,
        Joint::LittleProximal,
    ]
    .map(|j| local(GestureLabel::Open, j));
    ((k[0] + k[1] + k[2] + k[3]) * 0.25).normalize()
}

/// A rotation whose -Z points along `dir`, +Y up as far as possible.
fn look_along(dir: DVec3) -> DQuat {
    let z = -dir.normalize();
    let up = if z.y.abs() > 0.95 { DVec3::Z } else { DVec3::Y };
    let x = up.cross(z).normalize();
    let y = z.cross(x);
    DQuat::from_mat3(&DMat3::from_cols(x, y, z))
}

impl Rig {
    pub(crate) fn new(place: ModelPlacement) -> Rig {
        Self::start(place, false)
    }

    /// The same puppet holding a controller.
    pub(crate) fn with_controller(place: ModelPlacement) -> Rig {
        Self::start(place, true)
    }

    /// A controller rig on an existing puppet (a mixed session hands its
    /// puppet over for the GC part and takes it back with `r.p`).
    #[cfg(test)]
    pub(crate) fn on(p: Puppet, place: ModelPlacement) -> Rig {
        let model = place.similarity().unwrap_or(Similarity::IDENTITY);
        let mut r = Rig {
            p,
            place,
            model,
            q: look_along(DVec3::new(0.0, -0.5, -1.0)),
            palm: DVec3::new(0.15, 1.15, -0.25),
            controller: true,
        };
        r.go(0.3);
        r
    }

    fn start(place: ModelPlacement, controller: bool) -> Rig {
        let model = place.similarity().unwrap_or(Similarity::IDENTITY);
        let q = look_along(DVec3::new(0.0, -0.5, -1.0));
        let palm = DVec3::new(0.15, 1.15, -0.25);
        let mut r = Rig {
            p: Puppet::new(FPS),
            place,
            model,
            q,
            palm,
            controller,
        };
        if controller {
            r.p.controller(R, Pose::new(palm, q));
        } else {
            let w = r.wrist();
            r.p.hand(R, GestureLabel::Open, w);
        }
        r.p.wait(0.3);
        r
    }

    /// The pose the puppet moves: the wrist of the tracked hand, or the
    /// controller's aim.
    fn pose(&self) -> Pose {
        if self.controller {
            Pose::new(self.palm, self.q)
        } else {
            self.wrist()
        }
    }

    pub(crate) fn w(&self, m: DVec3) -> DVec3 {
        self.model.apply(m)
    }

    pub(crate) fn wrist(&self) -> Pose {
        let q = self.q * DQuat::from_rotation_arc(ray_local(), DVec3::NEG_Z);
        Pose::new(self.palm - q * local(GestureLabel::Open, Joint::Palm), q)
    }

    fn go(&mut self, secs: f64) -> &mut Self {
        let w = self.pose();
        self.p.move_to(R, w, secs);
        self
    }

    /// OPEN hand `from` (model offset) of `target`, aiming at it.
    pub(crate) fn aim(&mut self, target: DVec3, from: DVec3, secs: f64) -> &mut Self {
        let (t, o) = (self.w(target), self.w(target + from));
        self.q = look_along(t - o);
        self.palm = o;
        self.go(secs)
    }

    /// Changes the gesture over `secs`: the hand blends its pose; the
    /// controller presses the gesture's buttons (then holds still).
    pub(crate) fn gesture(&mut self, g: GestureLabel, secs: f64) -> &mut Self {
        if !self.controller {
            self.p.gesture(R, g, secs);
            return self;
        }
        let (select, grab, primary) = match g {
            GestureLabel::Open => (0.0, false, false),
            GestureLabel::Point => (1.0, false, false),
            GestureLabel::Fist => (0.0, true, false),
            GestureLabel::PinchOpen => (0.4, false, true),
            GestureLabel::PinchClosed => (1.0, false, true),
        };
        self.p.set(R, Button::Grab, grab);
        self.p.set(R, Button::Primary, primary);
        self.p.trigger(R, select);
        self.p.wait((secs - 3.0 / FPS).max(1.0 / FPS));
        self
    }

    pub(crate) fn wait(&mut self, secs: f64) -> &mut Self {
        self.p.wait(secs);
        self
    }

    /// Moves the palm by `d` (model space), keeping the orientation.
    pub(crate) fn drag(&mut self, d: DVec3, secs: f64) -> &mut Self {
        self.palm += self.model.apply_dir(d);
        self.go(secs)
    }

    /// Puts the POINT index tip at `m` (model).
    pub(crate) fn pen_to(&mut self, m: DVec3, secs: f64) -> &mut Self {
        let offset = if self.controller {
            self.q * point_tip_offset(R)
        } else {
            let tip = local(GestureLabel::Point, Joint::IndexTip);
            let palm = local(GestureLabel::Open, Joint::Palm);
            self.wrist().orientation * (tip - palm)
        };
        self.palm = self.w(m) - offset;
        self.go(secs)
    }

    /// Sketches through `pts` (model), one frame per point, with POINT,
    /// ending with OPEN.
    pub(crate) fn stroke(&mut self, pts: &[DVec3]) -> &mut Self {
        self.pen_to(pts[0], 0.4);
        self.gesture(GestureLabel::Point, 0.15).wait(0.1);
        for p in &pts[1..] {
            self.pen_to(*p, 1.0 / FPS);
        }
        self.wait(0.1).gesture(GestureLabel::Open, 0.15).wait(0.15)
    }

    /// OPEN → `g` on `target` (aimed `from`), then back to OPEN.
    pub(crate) fn select(&mut self, target: DVec3, from: DVec3, g: GestureLabel) -> &mut Self {
        self.aim(target, from, 0.4)
            .wait(0.25)
            .gesture(g, 0.15)
            .wait(0.1)
    }

    /// A FIST drag of `target` by `d` (model space).
    pub(crate) fn fist_drag(&mut self, target: DVec3, from: DVec3, d: DVec3) -> &mut Self {
        self.select(target, from, GestureLabel::Fist)
            .drag(d, 0.6)
            .wait(0.25)
            .gesture(GestureLabel::Open, 0.15)
            .wait(0.1)
    }

    /// An open PINCH on `target`.
    pub(crate) fn pinch(&mut self, target: DVec3, from: DVec3) -> &mut Self {
        self.select(target, from, GestureLabel::PinchOpen)
            .wait(0.3)
            .gesture(GestureLabel::Open, 0.15)
            .wait(0.1)
    }

    pub(crate) fn trace(&self, note: &str) -> Trace {
        let mut t = self.p.trace(self.place, note);
        t.header.tool = "gc".to_string();
        t
    }
}

/// A closed loop of `n` points: an ellipse with radii `a`, `b` in the
/// plane spanned by `u`, `v` about `c`.
pub(crate) fn loop_points(c: DVec3, u: DVec3, v: DVec3, a: f64, b: f64, n: usize) -> Vec<DVec3> {
    (0..=n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            c + u * (a * t.fcos()) + v * (b * t.fsin())
        })
        .collect()
}

/// A polyline through `pts`, `per` points per segment.
pub(crate) fn path(pts: &[DVec3], per: usize) -> Vec<DVec3> {
    let mut out = vec![pts[0]];
    for w in pts.windows(2) {
        for k in 1..=per {
            out.push(w[0].lerp(w[1], k as f64 / per as f64));
        }
    }
    out
}

/// Creates a part: select `start` (aimed `from`), sketch the section loop
/// `section`, then the spine `spine`.
pub(crate) fn create(r: &mut Rig, start: DVec3, from: DVec3, section: &[DVec3], spine: &[DVec3]) {
    r.select(start, from, GestureLabel::Point)
        .gesture(GestureLabel::Open, 0.15)
        .stroke(section)
        .stroke(spine);
}

/// A point on a body of revolution about the model z axis.
pub(crate) fn ring(radius: f64, angle_deg: f64, z: f64) -> DVec3 {
    let a = angle_deg.to_radians();
    DVec3::new(radius * a.fcos(), radius * a.fsin(), z)
}

pub(crate) fn outward(angle_deg: f64, dist: f64, up: f64) -> DVec3 {
    ring(dist, angle_deg, up)
}

/// The mug: a container body with a flared rim and a handle, by a
/// tracked hand.
pub fn mug_trace() -> Trace {
    mug(Rig::new(ModelPlacement::desk()))
}

/// The mug by a controller (buttons for gestures).
pub fn mug_controller_trace() -> Trace {
    mug(Rig::with_controller(ModelPlacement::desk()))
}

/// The mug's body, drawn in empty space: start on the desk, a circle of
/// r = 4.2 cm, a spine 10 cm up.
pub(crate) fn mug_body(r: &mut Rig) {
    let sec = loop_points(
        DVec3::new(0.0, 0.0, 0.02),
        DVec3::X,
        DVec3::Y,
        0.042,
        0.042,
        28,
    );
    let spine = path(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 0.1)], 14);
    create(r, DVec3::ZERO, DVec3::new(0.05, -0.2, 0.25), &sec, &spine);
}

fn mug(mut r: Rig) -> Trace {
    mug_body(&mut r);
    // Flare the rim by 6 mm (radial FIST on the top section; drags under
    // the tool's 4 mm minimum are no edit).
    let a = -50.0;
    r.fist_drag(
        ring(0.042, a, 0.097),
        outward(a, 0.18, 0.12),
        ring(0.006, a, 0.0),
    );
    // Open the top: a container (open PINCH on the top section).
    r.pinch(ring(0.048, a, 0.097), outward(a, 0.18, 0.12));
    // Handle on the -x side: section r = 7 mm, spine out and back.
    let o = DVec3::new(-0.042, 0.0, 0.08);
    let n = DVec3::NEG_X;
    let sec = loop_points(o + n * 0.05, DVec3::Y, DVec3::Z, 0.007, 0.007, 24);
    let pt = |a: f64, b: f64| o + n * a + DVec3::Z * b;
    let spine = path(
        &[
            pt(0.0, 0.0),
            pt(0.02, -0.004),
            pt(0.03, -0.018),
            pt(0.031, -0.038),
            pt(0.022, -0.053),
            pt(0.0, -0.06),
        ],
        5,
    );
    create(&mut r, o, DVec3::new(-0.22, -0.1, 0.08), &sec, &spine);
    r.wait(0.3);
    let how = if r.controller {
        "a controller"
    } else {
        "hand gestures"
    };
    r.trace(&format!(
        "mug by {how}: body (create, flare, open top), handle (create on the body)"
    ))
}

/// The teapot of `tests/data/teapot.jsonl` (body, spout, handle and lid)
/// by a tracked hand.
pub fn teapot_trace() -> Trace {
    teapot(Rig::new(ModelPlacement::desk()))
}

/// The teapot by a controller (buttons for gestures), as in Blender's VR
/// session.
pub fn teapot_controller_trace() -> Trace {
    teapot(Rig::with_controller(ModelPlacement::desk()))
}

fn teapot(mut r: Rig) -> Trace {
    let a = -50.0;
    // Body: circle r = 9 cm on the desk, spine 16 cm up (5 sections).
    let sec = loop_points(
        DVec3::new(0.0, 0.0, 0.02),
        DVec3::X,
        DVec3::Y,
        0.09,
        0.09,
        32,
    );
    let spine = path(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 0.16)], 16);
    create(
        &mut r,
        DVec3::ZERO,
        DVec3::new(0.05, -0.25, 0.3),
        &sec,
        &spine,
    );
    // Shape it: bottom 6.5 cm, belly 10 cm, top 5.6 cm.
    r.fist_drag(
        ring(0.09, a, 0.003),
        outward(a, 0.2, 0.1),
        ring(-0.025, a, 0.0),
    );
    r.fist_drag(
        ring(0.09, a, 0.08),
        outward(a, 0.2, 0.1),
        ring(0.01, a, 0.0),
    );
    r.fist_drag(
        ring(0.09, a, 0.157),
        outward(a, 0.2, 0.1),
        ring(-0.034, a, 0.0),
    );
    // Open top: container.
    r.pinch(ring(0.056, a, 0.157), outward(a, 0.2, 0.1));
    // Spout on +x at 6 cm height, circle r = 2.4 cm.
    let o = DVec3::new(0.097, 0.0, 0.06);
    let sec = loop_points(o + DVec3::X * 0.08, DVec3::Y, DVec3::Z, 0.024, 0.024, 28);
    let pt = |a: f64, b: f64| o + DVec3::X * a + DVec3::Z * b;
    let spine = path(
        &[
            pt(0.0, 0.0),
            pt(0.035, 0.012),
            pt(0.07, 0.045),
            pt(0.095, 0.095),
            pt(0.118, 0.125),
        ],
        6,
    );
    create(&mut r, o, DVec3::new(0.22, -0.1, 0.05), &sec, &spine);
    // Taper the spout's tip to about 1 cm and open it.
    // The spine is sunk 0.6 r = 1.44 cm into the body; aim 2 mm below the tip.
    let tip = pt(0.118 - 0.0144 - 0.0012, 0.125 - 0.0016);
    r.fist_drag(
        tip + DVec3::new(0.0, -0.024, 0.0),
        DVec3::new(0.05, -0.2, 0.05),
        DVec3::new(0.0, 0.0135, 0.0),
    );
    r.pinch(
        tip + DVec3::new(0.0, -0.0105, 0.0),
        DVec3::new(0.05, -0.2, 0.05),
    );
    // Handle on -x at 10 cm height, circle r = 9 mm, landing lower.
    let o = DVec3::new(-0.097, 0.0, 0.1);
    let n = DVec3::NEG_X;
    let sec = loop_points(o + n * 0.06, DVec3::Y, DVec3::Z, 0.009, 0.009, 24);
    let pt = |a: f64, b: f64| o + n * a + DVec3::Z * b;
    let spine = path(
        &[
            pt(0.0, 0.0),
            pt(0.03, -0.005),
            pt(0.045, -0.025),
            pt(0.042, -0.05),
            pt(0.02, -0.068),
            pt(-0.008, -0.072),
        ],
        5,
    );
    create(&mut r, o, DVec3::new(-0.22, -0.1, 0.05), &sec, &spine);
    // Lid: a new root on the desk to the right, r = 6.1 cm, 4.6 cm tall.
    let base = DVec3::new(0.3, 0.0, 0.0);
    let sec = loop_points(base + DVec3::Z * 0.02, DVec3::X, DVec3::Y, 0.061, 0.061, 28);
    let spine = path(&[base, base + DVec3::Z * 0.046], 10);
    create(&mut r, base, DVec3::new(0.05, -0.25, 0.3), &sec, &spine);
    // Dome it: top section to 1.4 cm, middle to 3.5 cm (radial FIST
    // drags on the rings, aimed a little from above and level).
    r.fist_drag(
        base + ring(0.061, a, 0.044),
        outward(a, 0.2, 0.02),
        ring(-0.047, a, 0.0),
    );
    r.fist_drag(
        base + ring(0.061, a, 0.023),
        outward(a, 0.2, 0.0),
        ring(-0.026, a, 0.0),
    );
    // A knob: a 3 s OPEN hold on the surface at 3.45 cm inserts a section
    // there (the surface keeps its shape), then a FIST pulls its ring in
    // to a waist of about 8 mm.
    r.aim(base + ring(0.02, a, 0.0345), outward(a, 0.2, 0.0), 0.4)
        .wait(3.4);
    r.fist_drag(
        base + ring(0.022, a, 0.0345),
        outward(a, 0.2, 0.0),
        ring(-0.014, a, 0.0),
    );
    // Put it on the body: FIST on the lid's side between its lowest two
    // sections, and carry it over.
    let side = base + ring(0.06, -90.0, 0.011);
    r.fist_drag(
        side,
        DVec3::new(0.0, -0.2, 0.0),
        DVec3::new(-0.3, 0.0, 0.154),
    );
    r.wait(0.3);
    let how = if r.controller {
        "a controller"
    } else {
        "hand gestures"
    };
    r.trace(&format!("teapot by {how}: body (create, shape, open top), spout (create, taper, open), handle, lid (create, dome, insert a knob section, place)"))
}
