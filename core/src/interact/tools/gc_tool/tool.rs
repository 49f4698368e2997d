//! [`GcTool`]: the Figure 10 state machine, one right hand acting (the
//! left hand joins only for the bimanual whole-shape manipulation).
//!
//! | state            | gesture in            | goes to / emits                         |
//! |------------------|-----------------------|-----------------------------------------|
//! | idle (OPEN ray)  | hold OPEN 3 s         | `gc_delete_section` / `gc_insert_section` |
//! | idle             | → POINT on surface/empty | placed (start point `O_s`)           |
//! | placed           | POINT … OPEN          | sectioned (template matched)            |
//! | sectioned        | POINT … OPEN          | `gc_add_child` / `gc_create`            |
//! | idle             | → POINT on key point / section | replace: POINT … OPEN sketches, `gc_replace_spine` / `gc_replace_section` |
//! | idle             | → FIST on key point   | drag … OPEN: `gc_edit_part` (bend)      |
//! | idle             | → FIST on section     | drag … OPEN: `gc_edit_part` (resize / shift / twist) |
//! | idle             | → FIST on part        | drag … OPEN: `gc_transform_part`; FIST static 3 s first: `gc_copy`, then the copy is dragged |
//! | idle             | → FIST on empty space | view: one hand rigid, two hands handle bar (7 DOF); no op |
//! | idle             | → PINCH on end section| pinch … OPEN: `gc_set_shape`            |
//!
//! Palette: "Instance" (copy / mirror), "Release" (coplanar, concentric,
//! symmetric: `gc_release` of that recorded relation between the part the
//! ray last pointed at and its parent, or the other part of the relation
//! when it is with a sibling; nothing when none is recorded), and
//! "Resolution" (coarse / normal / fine: the mesh resolution of created
//! parts and, as `gc_set_resolution`, of every part of the assembly last
//! pointed at, one op per part on consecutive frames, since a frame
//! carries at most one command).
//!
//! A FIST during creation cancels it. Commands are emitted only when a
//! gesture completes; everything else is [`Preview`] state.
//!
//! Gesture changes: a gesture counts as coming from OPEN when OPEN was
//! seen within [`GcToolSettings::transition`] (0.3 s), since the
//! classifier may pass through another gesture on the way (a frame or two
//! of PINCH between OPEN and FIST is common); a PINCH that turns into
//! FIST or POINT that quickly is taken as that gesture. A hold acts on
//! where the ray points when it fires, not where it started.
//!
//! Bad input: NaN samples never reach the tool (the sanitizer drops
//! them). A hand that vanishes (or shows no gesture) freezes the state for
//! [`GcToolSettings::grace`] seconds; if it does not come back, the gesture
//! is cancelled and the document is unchanged. A hand that teleports ends
//! a drag with the motion it had before the jump (committed cleanly), and
//! is skipped in a sketch.
//!
//! The whole-shape manipulation changes where the model is shown (the
//! paper uses it to inspect the shape and find a view), not the document:
//! the tool keeps the view on top of the session's placement, picks
//! through it and reports it in [`GcPreview::view`] for the host to draw
//! with.

use std::sync::Arc;

use std::collections::VecDeque;

use crate::assembly::{ensure_recorded, GcRelease, RelationKind};
use crate::doc::{Document, Edit, ObjectId, ObjectKind, Op, ScriptCommand};
use crate::gc::{mesh_gc, GcAssembly, GcSetResolution, PartId, Resolution};
use crate::math::DVec3;
use crate::mesh::TriMesh;

use super::create::{create_op, replace_op, replace_plane, section_profile, Start};
use super::edit::{drag_op, end_of, hold_op, pinch_shape, shape_op};
use super::hand::{HandFilter, HandIn};
use super::state::{Drag, Hold, PinchState, State, ViewGrab};
use super::target::GeoCache;
use super::GcTarget;
use super::GcToolSettings;
use crate::interact::gesture::bimanual::HandleBar;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::Gesture;
use crate::interact::input::{Hand, Joint, Pose};
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::lost_too_long;
use crate::interact::tools::pick::Ray;
use crate::interact::tools::{Preview, PreviewRay, Tool, ToolContext};

/// The copy a 3 s FIST makes of `part`: where it is (the drag that
/// follows moves it), mirrored across its parent's symmetry plane only
/// when `mirror` (the palette's "Instance: mirror") and the part has a
/// parent; `None` for a part the assembly does not have.
pub(crate) fn instance_op(
    asm: &crate::gc::GcAssembly,
    part: usize,
    mirror: bool,
) -> Option<crate::assembly::GcCopy> {
    let p = asm.parts.get(part)?;
    Some(crate::assembly::GcCopy {
        part: crate::gc::PartId(part),
        mirror: mirror && p.parent.is_some(),
        translate: DVec3::ZERO,
        rotate: [0.0, 0.0, 0.0, 1.0],
        tolerance: 1e-3,
    })
}

/// The paper-1 hand-gesture tool (Figure 10).
#[derive(Clone, Debug)]
pub struct GcTool {
    settings: GcToolSettings,
    preview: Preview,
    state: State,
    filters: [HandFilter; 2],
    prev: Gesture,
    /// When the right hand last showed OPEN in idle: a gesture that
    /// follows within [`GcToolSettings::transition`] counts as coming from
    /// OPEN even when the classifier passed through another gesture on
    /// the way (OPEN to FIST often shows PINCH for a frame or two).
    open_time: f64,
    /// Target under the ray in the last frame (idle).
    last_target: Option<GcTarget>,
    hold: Option<Hold>,
    lost_since: Option<f64>,
    view: Similarity,
    /// A 3 s FIST instance of a child part mirrors it across its parent's
    /// symmetry plane (the palette's "Instance: mirror"); by default the
    /// copy is a plain copy where the hand drops it.
    mirror_instances: bool,
    geo: GeoCache,
    mesh_time: f64,
    /// Times of the current stroke's samples.
    stroke_times: Vec<f64>,
    /// The part the ray last pointed at (kept while it points elsewhere,
    /// e.g. at the palette): what "Release" and "Resolution" act on.
    part: Option<(ObjectId, usize)>,
    /// Parts still to get the chosen resolution (one op per frame).
    resolution_queue: VecDeque<(ObjectId, usize, Resolution)>,
}

/// The palette's "Resolution" options.
pub const RESOLUTIONS: [(&str, Resolution); 3] = [
    ("coarse", Resolution::PREVIEW),
    ("normal", Resolution::DEFAULT),
    ("fine", Resolution { u: 160, v: 112 }),
];

/// The palette's "Release" options.
const RELEASES: [RelationKind; 3] = [
    RelationKind::Coplanar,
    RelationKind::Concentric,
    RelationKind::Symmetric,
];

fn assembly_of(doc: &Document, id: ObjectId) -> Option<&GcAssembly> {
    match &doc.get(id).ok()?.kind {
        ObjectKind::GcAssembly(a) => Some(a),
        _ => None,
    }
}

/// `gc_release` of the recorded `relation` between `part` and its parent
/// (or else the first part it has that relation with).
fn release_op(doc: &Document, id: ObjectId, part: usize, relation: RelationKind) -> Option<Op> {
    let mut asm = assembly_of(doc, id)?.clone();
    let parent = asm.parts.get(part)?.parent;
    ensure_recorded(&mut asm);
    let rec = asm.relations.as_ref()?;
    let list = match relation {
        RelationKind::Coplanar => &rec.coplanar,
        RelationKind::Concentric => &rec.concentric,
        RelationKind::Symmetric => &rec.symmetric,
        RelationKind::Connected => return None,
    };
    let others: Vec<usize> = list
        .iter()
        .filter_map(|&(a, b)| match (a == part, b == part) {
            (true, _) => Some(b),
            (_, true) => Some(a),
            _ => None,
        })
        .collect();
    let other = parent
        .filter(|p| others.contains(p))
        .or_else(|| others.first().copied())?;
    Some(Op::GcRelease(Edit::new(
        id,
        GcRelease {
            part: PartId(part),
            other: PartId(other),
            relation,
        },
    )))
}

impl Default for GcTool {
    fn default() -> Self {
        Self::new(GcToolSettings::default())
    }
}

fn cmd(op: Option<Op>) -> Option<ScriptCommand> {
    op.map(ScriptCommand::Op)
}

impl GcTool {
    /// A tool with `settings`.
    pub fn new(settings: GcToolSettings) -> Self {
        Self {
            settings,
            preview: Preview::default(),
            state: State::Idle,
            filters: [HandFilter::default(); 2],
            prev: Gesture::None,
            open_time: f64::NEG_INFINITY,
            last_target: None,
            hold: None,
            lost_since: None,
            view: Similarity::IDENTITY,
            mirror_instances: false,
            geo: GeoCache::default(),
            mesh_time: f64::NEG_INFINITY,
            stroke_times: Vec::new(),
            part: None,
            resolution_queue: VecDeque::new(),
        }
    }

    /// The current state's name.
    pub fn mode(&self) -> &'static str {
        self.state.name()
    }

    fn model(&self, cx: &ToolContext) -> Similarity {
        self.view.compose(cx.model)
    }

    fn to_model_ray(&self, cx: &ToolContext, ray: &Ray) -> Ray {
        let inv = self.model(cx).inverse();
        Ray {
            origin: inv.apply(ray.origin),
            dir: inv.apply_dir(ray.dir).normalize_or(DVec3::NEG_Z),
        }
    }

    fn to_model(&self, cx: &ToolContext, p: DVec3) -> DVec3 {
        self.model(cx).inverse().apply(p)
    }

    fn to_model_dir(&self, cx: &ToolContext, d: DVec3) -> DVec3 {
        let m = self.model(cx);
        m.inverse().apply_dir(d)
    }

    fn idle(&mut self, cx: &ToolContext, h: &HandIn) -> Option<ScriptCommand> {
        let (Some(ray), Some(palm)) = (h.ray, h.palm) else {
            return None;
        };
        let t = cx.frame.time;
        if h.gesture == Gesture::Open {
            let mray = self.to_model_ray(cx, &ray);
            let m = self.model(cx);
            let target =
                self.geo
                    .pick(cx.doc, &mray, self.settings.reach / m.scale, &self.settings);
            let dist = (m.apply(target.point()) - ray.origin).length();
            self.preview.rays[1] = Some(PreviewRay {
                origin: ray.origin,
                dir: ray.dir,
                length: dist.min(self.settings.reach),
                hit: target.part().is_some(),
            });
            self.preview.highlighted = target.part().map(|p| p.0);
            if let Some(p) = target.part() {
                self.part = Some(p);
            }
            self.preview.gc_mut().target = Some(target);
            self.last_target = Some(target);
            self.open_time = t;
            return self.holding(t, palm, target);
        }
        self.hold = None;
        self.preview.gc_mut().hold = 0.0;
        if h.gesture == self.prev || t - self.open_time > self.settings.transition {
            return None;
        }
        let target = self.last_target?;
        let view_dir = self.to_model_dir(cx, ray.dir);
        match (h.gesture, target) {
            (Gesture::Point, GcTarget::Surface { .. } | GcTarget::Empty { .. }) => {
                if let Some(start) = Start::at(&target, view_dir, &self.geo) {
                    self.state = State::Placed(start);
                }
            }
            (Gesture::Point, GcTarget::KeyPoint { .. } | GcTarget::Section { .. }) => {
                if let Some(plane) = replace_plane(&target, &self.geo) {
                    self.state = State::ReplaceArmed(target, plane);
                }
            }
            (Gesture::Fist, GcTarget::Empty { .. }) => {
                self.state = State::View(ViewGrab {
                    before: self.view,
                    hands: Vec::new(),
                    bar: None,
                });
            }
            (Gesture::Fist, _) => {
                self.state = State::Drag(Drag {
                    target,
                    start: palm,
                    started: t,
                    motion: DVec3::ZERO,
                    may_instance: matches!(target, GcTarget::Surface { .. }),
                });
            }
            (
                Gesture::Pinch,
                GcTarget::Section {
                    id, part, section, ..
                },
            ) => {
                let is_end = self
                    .geo
                    .assembly(id)
                    .and_then(|a| end_of(a, part, section))
                    .is_some();
                if is_end {
                    self.state = State::Pinch(PinchState {
                        target,
                        history: Vec::new(),
                    });
                }
            }
            _ => {}
        }
        None
    }

    fn holding(&mut self, t: f64, palm: DVec3, target: GcTarget) -> Option<ScriptCommand> {
        let s = &self.settings;
        let keep = self
            .hold
            .filter(|h| h.target.same_element(&target) && (palm - h.palm).length() <= s.hold_drift);
        let mut hold = keep.unwrap_or(Hold {
            target,
            since: t,
            palm,
            fired: false,
        });
        // The hold is timed from its start, but acts where the ray points
        // now: the ray settles while the hand comes to rest, so the first
        // hit of a surface hold can be a centimetre off.
        hold.target = target;
        let progress = ((t - hold.since) / s.hold).clamp(0.0, 1.0);
        let holdable = hold_op(&hold.target).is_some();
        self.preview.gc_mut().hold = if holdable && !hold.fired {
            progress
        } else {
            0.0
        };
        let out = if holdable && !hold.fired && progress >= 1.0 {
            hold.fired = true;
            cmd(hold_op(&hold.target))
        } else {
            None
        };
        self.hold = Some(hold);
        out
    }

    fn sketching(&mut self, cx: &ToolContext, h: &HandIn) -> Option<ScriptCommand> {
        let state = std::mem::replace(&mut self.state, State::Idle);
        let pen = h.pen.map(|p| self.to_model(cx, p));
        let t = cx.frame.time;
        // The fingertip also settles for a moment after POINT is reported
        // (a hook at the start): drop the stroke's first 0.1 s.
        let t0 = self.stroke_times.first().copied().unwrap_or(t);
        let skip_n = self
            .stroke_times
            .iter()
            .filter(|&&st| st < t0 + 0.1)
            .count();
        let keep_n = self
            .stroke_times
            .iter()
            .filter(|&&st| st <= t - 0.15)
            .count();
        let times = &mut self.stroke_times;
        let mut add = |stroke: &mut Vec<DVec3>| {
            if stroke.is_empty() {
                times.clear();
            }
            if let (Some(p), false) = (pen, h.teleported) {
                if stroke.last().is_none_or(|q| (*q - p).length() > 2e-4) {
                    stroke.push(p);
                    times.push(t);
                }
            }
        };
        // The fingers move while the gesture changes back to OPEN (the
        // classifier reports it a little later): drop the stroke's last
        // 0.15 s.
        let cut = |mut v: Vec<DVec3>| -> Vec<DVec3> {
            v.truncate(keep_n.max(2));
            if v.len() >= skip_n + 2 {
                v.drain(..skip_n);
            }
            v
        };
        let s = &self.settings;
        // A stroke starts on an OPEN -> POINT change, not on the POINT
        // that selected the start point.
        let fresh = self.prev == Gesture::Open;
        let (next, out) = match (state, h.gesture) {
            (
                st @ (State::Placed(_) | State::Sectioned(..) | State::ReplaceArmed(..)),
                Gesture::Point,
            ) if !fresh => (st, None),
            (State::Placed(st), Gesture::Point) => {
                let mut v = Vec::new();
                add(&mut v);
                (State::SketchSection(st, v), None)
            }
            (State::Sectioned(st, p), Gesture::Point) => {
                let mut v = Vec::new();
                add(&mut v);
                (State::SketchSpine(st, p, v), None)
            }
            (State::ReplaceArmed(t, plane), Gesture::Point) => {
                let mut v = Vec::new();
                add(&mut v);
                (State::Replace(t, plane, v), None)
            }
            (
                st @ (State::Placed(_) | State::Sectioned(..) | State::ReplaceArmed(..)),
                Gesture::Open,
            ) => (st, None),
            (State::SketchSection(st, mut v), Gesture::Point) => {
                add(&mut v);
                (State::SketchSection(st, v), None)
            }
            (State::SketchSection(st, v), Gesture::Open) => {
                match section_profile(&cut(v), &st.section_plane, s) {
                    Some(p) => (State::Sectioned(st, p), None),
                    None => (State::Placed(st), None),
                }
            }
            (State::SketchSpine(st, p, mut v), Gesture::Point) => {
                add(&mut v);
                (State::SketchSpine(st, p, v), None)
            }
            (State::SketchSpine(st, p, v), Gesture::Open) => {
                match create_op(&st, &p, &cut(v), &self.geo, s) {
                    Some(op) => (State::Idle, Some(op)),
                    None => (State::Sectioned(st, p), None),
                }
            }
            (State::Replace(t, plane, mut v), Gesture::Point) => {
                add(&mut v);
                (State::Replace(t, plane, v), None)
            }
            (State::Replace(t, plane, v), Gesture::Open) => {
                let asm = t.part().and_then(|(id, _)| self.geo.assembly(id));
                match asm.and_then(|a| replace_op(&t, &plane, &cut(v), a, s)) {
                    Some(op) => (State::Idle, Some(op)),
                    // A stroke that fits nothing: sketch it again.
                    None => (State::ReplaceArmed(t, plane), None),
                }
            }
            // FIST or PINCH while creating or sketching: cancel.
            _ => (State::Idle, None),
        };
        self.state = next;
        cmd(out)
    }

    fn dragging(&mut self, cx: &ToolContext, h: &HandIn) -> Option<ScriptCommand> {
        let State::Drag(mut d) = std::mem::replace(&mut self.state, State::Idle) else {
            return None;
        };
        let t = cx.frame.time;
        let s = &self.settings;
        if h.teleported || h.gesture != Gesture::Fist {
            // Released (or jumped): commit the last good motion.
            self.preview.gc_mut().mesh = None;
            if d.motion.length() * self.model(cx).scale < s.min_drag {
                return None;
            }
            return cmd(drag_op(&d.target, d.motion, &self.geo));
        }
        let palm = h.palm?;
        d.motion = self.to_model_dir(cx, palm - d.start);
        let moved = (palm - d.start).length();
        if moved > s.hold_drift {
            d.may_instance = false;
        }
        if d.may_instance && t - d.started >= s.hold {
            if let GcTarget::Surface { id, part, point, v } = d.target {
                let asm = self.geo.assembly(id)?;
                let copy = instance_op(asm, part, self.mirror_instances)?;
                let new_part = asm.parts.len();
                d.may_instance = false;
                d.target = GcTarget::Surface {
                    id,
                    part: new_part,
                    point,
                    v,
                };
                d.start = palm;
                d.motion = DVec3::ZERO;
                self.state = State::Drag(d);
                return Some(ScriptCommand::Op(Op::GcCopy(crate::doc::Edit::new(
                    id, copy,
                ))));
            }
        }
        self.preview.gc_mut().hold = if d.may_instance {
            ((t - d.started) / s.hold).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if t - self.mesh_time >= 0.1 {
            self.mesh_time = t;
            self.preview.gc_mut().mesh = self.preview_mesh(&d);
        }
        self.preview.gc_mut().target = Some(d.target);
        self.state = State::Drag(d);
        None
    }

    /// The edited part, meshed at preview resolution, as the drag would
    /// leave it. The drag's edit is applied to a copy of the assembly's
    /// parameters only: applying the op to the document would also unite
    /// all parts (tens of milliseconds once a part has children), which a
    /// 90 Hz frame cannot afford.
    fn preview_mesh(&self, d: &Drag) -> Option<Arc<TriMesh>> {
        let (id, part) = d.target.part()?;
        let mut asm = self.geo.assembly(id)?.clone();
        match drag_op(&d.target, d.motion, &self.geo)? {
            Op::GcEditPart(e) => e.edit.apply_to(&mut asm).ok()?,
            Op::GcTransformPart(t) => t.edit.apply_to(&mut asm).ok()?,
            _ => return None,
        }
        let mut gc = asm.parts.get(part)?.gc.clone();
        gc.resolution = self.settings.preview_resolution;
        mesh_gc(&gc).ok().map(Arc::new)
    }

    fn pinching(&mut self, cx: &ToolContext, h: &HandIn) -> Option<ScriptCommand> {
        let State::Pinch(mut p) = std::mem::replace(&mut self.state, State::Idle) else {
            return None;
        };
        let GcTarget::Section {
            id, part, section, ..
        } = p.target
        else {
            return None;
        };
        let asm = self.geo.assembly(id)?;
        let end = end_of(asm, part, section)?;
        let t = cx.frame.time;
        if h.gesture == Gesture::Pinch {
            let gap = (!h.state.pinch_closed).then_some(h.state.pinch_gap);
            let current = asm.parts.get(part)?.gc.shape;
            let child = asm.parts.get(part)?.parent.is_some();
            p.history
                .push((t, pinch_shape(current, end, gap, child, &self.settings)));
            p.history.retain(|(ht, _)| t - ht <= 0.5);
            self.state = State::Pinch(p);
            return None;
        }
        if h.gesture != Gesture::Open {
            // A PINCH that was only the way from OPEN to FIST or POINT:
            // act on that gesture instead.
            if t - self.open_time <= self.settings.transition && p.history.len() <= 3 {
                return self.idle(cx, h);
            }
            return None;
        }
        // The fingers open through wider gaps before the gesture changes:
        // use the proposal from 0.15 s before the release.
        let shape = p
            .history
            .iter()
            .rev()
            .find(|(ht, _)| t - ht >= 0.15)
            .or(p.history.first())?
            .1;
        cmd(shape_op(id, part, shape, asm))
    }

    fn viewing(&mut self, cx: &ToolContext, hands: &[HandIn; 2]) -> Option<ScriptCommand> {
        let State::View(mut g) = std::mem::replace(&mut self.state, State::Idle) else {
            return None;
        };
        let grip = |hand: Hand| -> Option<Pose> {
            let h = &hands[hand.index()];
            let wrist = cx.frame.hand(hand)?.pose(Joint::Wrist)?;
            Some(Pose::new(h.palm?, wrist.orientation))
        };
        let holding: Vec<(Hand, Pose)> = Hand::BOTH
            .iter()
            .filter(|&&hand| {
                let h = &hands[hand.index()];
                h.gesture == Gesture::Fist
                    && !h.teleported
                    && (hand == Hand::Right || !h.state.down)
            })
            .filter_map(|&hand| grip(hand).map(|p| (hand, p)))
            .collect();
        if !holding.iter().any(|(hand, _)| *hand == Hand::Right) {
            return None;
        }
        let same =
            holding.len() == g.hands.len() && holding.iter().zip(&g.hands).all(|(a, b)| a.0 == b.0);
        if !same {
            g.before = self.view;
            g.bar = match holding.as_slice() {
                [(_, a), (_, b)] => HandleBar::new(*a, *b),
                _ => None,
            };
            g.hands = holding.clone();
        }
        let step = match (g.hands.as_slice(), holding.as_slice()) {
            ([(_, a0)], [(_, a)]) => Some(Similarity::from_pose(&a.compose(&a0.inverse()))),
            ([_, _], [(_, a), (_, b)]) => g.bar.and_then(|bar| bar.transform(a, b)),
            _ => None,
        };
        if let Some(v) = step.map(|s| s.compose(&g.before)).filter(|v| v.is_valid()) {
            self.view = v;
        }
        self.state = State::View(g);
        None
    }
}

impl Tool for GcTool {
    fn name(&self) -> &'static str {
        "gc"
    }

    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand> {
        self.geo.refresh(cx.doc);
        let s = self.settings.clone();
        let hands = [
            self.filters[0].read(cx, Hand::Left, &s),
            self.filters[1].read(cx, Hand::Right, &s),
        ];
        let h = hands[1];
        self.preview.rays = [None, None];
        if !matches!(self.state, State::Idle) {
            self.preview.gc_mut().target = None;
        }
        let t = cx.frame.time;
        let out = if !h.tracked() {
            self.hold = None;
            self.preview.gc_mut().hold = 0.0;
            if lost_too_long(&mut self.lost_since, t, s.grace) {
                self.cancel();
            }
            None
        } else {
            self.lost_since = None;
            let out = match self.state {
                State::Idle => self.idle(cx, &h),
                State::Drag(_) => self.dragging(cx, &h),
                State::Pinch(_) => self.pinching(cx, &h),
                State::View(_) => self.viewing(cx, &hands),
                _ => self.sketching(cx, &h),
            };
            self.prev = h.gesture;
            out
        };
        self.update_preview();
        out.or_else(|| self.next_resolution(cx.doc))
    }

    fn cancel(&mut self) {
        self.state = State::Idle;
        self.hold = None;
        self.prev = Gesture::None;
        self.open_time = f64::NEG_INFINITY;
        self.last_target = None;
        self.preview.gc_mut().mesh = None;
    }

    fn preview(&self) -> &Preview {
        &self.preview
    }

    fn choices(&self) -> Vec<ChoiceGroup> {
        vec![
            ChoiceGroup {
                name: "Instance",
                options: vec!["copy".into(), "mirror".into()],
                active: usize::from(self.mirror_instances),
            },
            ChoiceGroup {
                name: "Release",
                options: RELEASES.iter().map(|r| r.to_string()).collect(),
                active: usize::MAX,
            },
            ChoiceGroup {
                name: "Resolution",
                options: RESOLUTIONS.iter().map(|(n, _)| n.to_string()).collect(),
                active: RESOLUTIONS
                    .iter()
                    .position(|(_, r)| *r == self.settings.resolution)
                    .unwrap_or(usize::MAX),
            },
        ]
    }

    fn choose(
        &mut self,
        doc: &crate::doc::Document,
        group: usize,
        option: usize,
    ) -> Option<ScriptCommand> {
        match group {
            0 if option < 2 => self.mirror_instances = option == 1,
            1 if option < RELEASES.len() => {
                let (id, part) = self.part?;
                return release_op(doc, id, part, RELEASES[option]).map(ScriptCommand::Op);
            }
            2 if option < RESOLUTIONS.len() => {
                let res = RESOLUTIONS[option].1;
                self.settings.resolution = res;
                let id = self.part.map(|p| p.0).or_else(|| {
                    doc.objects()
                        .filter(|(_, o)| matches!(o.kind, ObjectKind::GcAssembly(_)))
                        .map(|(id, _)| id)
                        .last()
                })?;
                let parts = assembly_of(doc, id)?.parts.len();
                self.resolution_queue = (0..parts).map(|k| (id, k, res)).collect();
                return self.next_resolution(doc);
            }
            _ => {}
        }
        None
    }

    fn uses_hands(&self) -> bool {
        true
    }
}

impl GcTool {
    /// The next queued `gc_set_resolution` whose part does not have its
    /// resolution yet (a twin may have got it with its part).
    fn next_resolution(&mut self, doc: &Document) -> Option<ScriptCommand> {
        while let Some((id, part, resolution)) = self.resolution_queue.pop_front() {
            let Some(p) = assembly_of(doc, id).and_then(|a| a.parts.get(part)) else {
                continue;
            };
            if p.gc.resolution != resolution {
                return Some(ScriptCommand::Op(Op::GcSetResolution(Edit::new(
                    id,
                    GcSetResolution {
                        part: PartId(part),
                        resolution,
                    },
                ))));
            }
        }
        None
    }

    fn update_preview(&mut self) {
        let p = &mut self.preview;
        p.gc_mut().mode = self.state.name();
        p.gc_mut().view = (self.view != Similarity::IDENTITY).then_some(self.view);
        let (sketch, plane, profile) = match &self.state {
            State::Placed(st) => (None, Some(&st.section_plane), None),
            State::SketchSection(st, v) => (Some(v), Some(&st.section_plane), None),
            State::Sectioned(st, pr) => (None, Some(&st.spine_plane), Some(pr)),
            State::SketchSpine(st, pr, v) => (Some(v), Some(&st.spine_plane), Some(pr)),
            State::ReplaceArmed(_, pl) => (None, Some(pl), None),
            State::Replace(_, pl, v) => (Some(v), Some(pl), None),
            _ => (None, None, None),
        };
        p.sketch = sketch.cloned().unwrap_or_default();
        p.gc_mut().plane = plane.map(|pl| (pl.origin, pl.normal));
        p.gc_mut().profile = profile.map(|d| d.profile.clone());
        if !matches!(self.state, State::Drag(_)) {
            p.gc_mut().mesh = None;
        }
        if let State::Drag(d) = &self.state {
            p.gc_mut().target = Some(d.target);
        }
        if let State::Pinch(pi) = &self.state {
            p.gc_mut().target = Some(pi.target);
        }
    }
}
