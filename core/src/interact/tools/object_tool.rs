//! [`ObjectTool`]: select, place, grab, move, rotate and scale document
//! objects with controllers or hands, delete, copy, undo and redo.
//!
//! Each hand is read either from its controller (if one is present) or
//! from its tracked joints and gesture (paper 1 §4: OPEN aims a ray from
//! the palm, FIST grabs). Per hand:
//!
//! | input               | controller          | hand gesture      |
//! |---------------------|---------------------|-------------------|
//! | ray                 | aim pose            | palm, OPEN/other  |
//! | grab / drag         | `grab` (squeeze)    | FIST              |
//! | select              | `select` (trigger)  | closed PINCH      |
//! | place / copy        | `primary`           | —                 |
//! | delete              | `secondary`         | —                 |
//! | next shape          | `menu`              | —                 |
//! | undo / redo         | stick flick ← / →   | —                 |
//!
//! A grab starts on the press edge with the ray on an object; the object
//! follows the hand rigidly. When the other hand also grabs (and, for
//! tracked hands, is not DOWN), the two hands drive it with the handle bar
//! (7 DOF, scale clamped to `[0.4, 4]`); either hand may let go and the
//! other continues. When the last hand lets go, exactly one `set_transform`
//! op is emitted with the final placement.
//!
//! Palette: "Shape" (what `primary` places); "Wall" (1.2, 2 or 3 mm:
//! `set_wall_thickness`, the document's wall for printing surfaces as
//! solids — a document setting, not one per object, since that is what the
//! op sets; there is no "solid" option because the document stores only
//! the thickness); "Overlaps" (`set_self_intersection_policy`: refuse or
//! flag edits that fold an object through itself); "Scale" (uniform, x, y,
//! z): with an axis chosen, a two-hand grab scales the grabbed object only
//! along that axis of its own frame (its placement's per-axis scale, by
//! the same `set_transform`; the hands still move and turn it); "Printer"
//! (`set_printer` with a preset: the build volume the HUD's print line
//! holds the model against; a custom size is typed on the desktop). Sculpts
//! refuse a per-axis placement (their brushes work in a uniformly scaled
//! frame), so a sculpt always scales uniformly and the readout says so.
//!
//! Bad input during a drag:
//! - tracking lost (no grip pose, or no recognizable gesture): the preview
//!   freezes; if tracking returns within [`ObjectToolSettings::grace`]
//!   seconds the drag continues, else it is cancelled and the document is
//!   unchanged;
//! - a controller or hand that teleports (moves faster than a hand can):
//!   the drag is committed at its last good placement, and a new drag needs
//!   a new press;
//! - NaN samples never reach the tool (the sanitizer drops them).

use crate::doc::{
    AddSolid, Delete, Document, Duplicate, ObjectId, ObjectKind, Op, ScriptCommand, SetTransform,
};
use crate::math::{DVec3, Transform};
use crate::print::{
    PrintSetup, PrinterPreset, SelfIntersectionPolicy, SetPrinter, SetSelfIntersectionPolicy,
    SetWallThickness,
};
use crate::solid::SolidShape;

use crate::interact::gesture::bimanual::HandleBar;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::Gesture;
use crate::interact::input::{Hand, Joint, Pose};
use crate::interact::palette::{ChoiceGroup, Snap};
use crate::interact::tools::lost_too_long;
use crate::interact::tools::pick::{pick, Ray};
use crate::interact::tools::snap::{snap_to_objects, ObjectSnap};
use crate::interact::tools::{MovingPreview, Preview, PreviewRay, Tool, ToolContext, ToolPreview};

/// Settings of the object tool.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectToolSettings {
    /// How far rays reach (metres).
    pub reach: f64,
    /// Seconds a drag survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Shapes placed by `primary`, cycled by `menu`.
    pub palette: Vec<SolidShape>,
    /// Segments of placed solids.
    pub segments: u32,
    /// Hand speed (m/s) above which a hand counts as teleported.
    pub max_hand_speed: f64,
}

impl Default for ObjectToolSettings {
    fn default() -> Self {
        Self {
            reach: 5.0,
            grace: 0.25,
            palette: vec![
                SolidShape::Box {
                    size: [0.12, 0.12, 0.12],
                },
                SolidShape::Sphere { radius: 0.07 },
                SolidShape::Cylinder {
                    radius: 0.05,
                    height: 0.14,
                },
                SolidShape::Cone {
                    radius: 0.06,
                    height: 0.13,
                },
                SolidShape::Torus {
                    major_radius: 0.06,
                    minor_radius: 0.02,
                },
                SolidShape::Capsule {
                    radius: 0.04,
                    length: 0.08,
                },
                SolidShape::Ellipsoid {
                    radii: [0.05, 0.04, 0.07],
                },
            ],
            segments: 32,
            max_hand_speed: 12.0,
        }
    }
}

/// One hand's input this frame, from its controller or its gesture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct HandInput {
    /// Tracking usable this frame.
    tracked: bool,
    grip: Option<Pose>,
    ray: Option<Ray>,
    grab: bool,
    select: bool,
    primary: bool,
    secondary: bool,
    menu: bool,
    stick_x: f64,
    teleported: bool,
    /// May join a two-hand grab (not DOWN).
    can_join: bool,
}

fn read_hand(
    cx: &ToolContext,
    hand: Hand,
    last_palm: &mut [Option<(f64, DVec3)>; 2],
    max_speed: f64,
) -> HandInput {
    if let Some(c) = cx.frame.controller(hand) {
        let b = c.buttons.unwrap_or_default();
        return HandInput {
            tracked: c.grip.is_some() && c.buttons.is_some(),
            grip: c.grip,
            ray: c.aim.map(|a| Ray {
                origin: a.position,
                dir: a.forward(),
            }),
            grab: b.grab > 0.5,
            select: b.select > 0.5,
            primary: b.primary,
            secondary: b.secondary,
            menu: b.menu,
            stick_x: b.stick[0],
            teleported: c.teleported,
            can_join: true,
        };
    }
    let g = cx.gestures[hand.index()];
    let Some(h) = cx.frame.hand(hand) else {
        last_palm[hand.index()] = None;
        return HandInput::default();
    };
    let (Some(wrist), Some(knuckle)) = (h.pose(Joint::Wrist), h.pos(Joint::MiddleProximal)) else {
        return HandInput::default();
    };
    let palm = h
        .pos(Joint::Palm)
        .unwrap_or((wrist.position + knuckle) * 0.5);
    let t = cx.frame.time;
    let teleported = match last_palm[hand.index()] {
        Some((t0, p0)) => (palm - p0).length() / (t - t0).max(1e-6) > max_speed,
        None => false,
    };
    last_palm[hand.index()] = Some((t, palm));
    let dir = (knuckle - wrist.position).normalize_or(DVec3::NEG_Z);
    HandInput {
        tracked: g.gesture != Gesture::None,
        grip: Some(Pose::new(palm, wrist.orientation)),
        ray: Some(Ray { origin: palm, dir }),
        grab: g.gesture == Gesture::Fist,
        select: g.gesture == Gesture::Pinch && g.pinch_closed,
        teleported,
        can_join: !g.down,
        ..HandInput::default()
    }
}

/// A drag in progress.
#[derive(Clone, Debug)]
struct Drag {
    id: ObjectId,
    /// The object's placement when the drag started (model space).
    base: Transform,
    /// World motion accumulated up to the last change of hands.
    before: Similarity,
    /// Hands holding, with their grip poses at the last change of hands.
    hands: Vec<(Hand, Pose)>,
    bar: Option<HandleBar>,
    /// The latest world motion since the drag started.
    current: Similarity,
    lost_since: Option<f64>,
    /// The object axis a two-hand scale acts on (`None`: uniform).
    axis: Option<usize>,
}

impl Drag {
    fn rebase(&mut self, hands: Vec<(Hand, Pose)>) {
        self.before = self.current;
        self.bar = match hands.as_slice() {
            [(_, a), (_, b)] => HandleBar::new(*a, *b),
            _ => None,
        };
        self.hands = hands;
    }

    fn motion_now(&self, grips: &[Pose]) -> Option<Similarity> {
        let step = match (self.hands.as_slice(), grips) {
            ([(_, a0)], [a]) => Similarity::from_pose(&a.compose(&a0.inverse())),
            ([_, _], [a, b]) => self.bar?.transform(a, b)?,
            _ => return None,
        };
        let m = step.compose(&self.before);
        m.is_valid().then_some(m)
    }
}

/// Select, place, grab, move, rotate, scale, delete, copy, undo, redo.
#[derive(Clone, Debug)]
pub struct ObjectTool {
    settings: ObjectToolSettings,
    preview: Preview,
    prev: [HandInput; 2],
    last_palm: [Option<(f64, DVec3)>; 2],
    stick_armed: [bool; 2],
    palette_index: usize,
    drag: Option<Drag>,
    /// The document's print settings, as of the last frame.
    print: PrintSetup,
    /// "Scale": `None` uniform, else the object axis.
    scale_axis: Option<usize>,
}

/// Wall thicknesses the palette offers (metres).
pub const WALLS: [f64; 3] = [0.0012, 0.002, 0.003];
/// The self-intersection policies in palette order.
const POLICIES: [SelfIntersectionPolicy; 2] =
    [SelfIntersectionPolicy::Refuse, SelfIntersectionPolicy::Flag];

impl Default for ObjectTool {
    fn default() -> Self {
        Self::new(ObjectToolSettings::default())
    }
}

impl ObjectTool {
    /// A tool with `settings`.
    pub fn new(settings: ObjectToolSettings) -> Self {
        let placing = settings.palette.first().copied();
        Self {
            settings,
            preview: Preview {
                tool: ToolPreview::Placing(placing),
                ..Preview::default()
            },
            prev: [HandInput::default(); 2],
            last_palm: [None; 2],
            stick_armed: [true; 2],
            palette_index: 0,
            drag: None,
            print: PrintSetup::default(),
            scale_axis: None,
        }
    }

    fn idle(&mut self, cx: &ToolContext, inputs: &[HandInput; 2]) -> Option<ScriptCommand> {
        let to_model = cx.model.inverse();
        let mut hits = [None, None];
        for hand in Hand::BOTH {
            let i = hand.index();
            self.preview.rays[i] = None;
            let Some(ray) = inputs[i].ray else { continue };
            let model_ray = Ray {
                origin: to_model.apply(ray.origin),
                dir: to_model.apply_dir(ray.dir),
            };
            let reach = self.settings.reach / cx.model.scale;
            let hit = pick(cx.doc, &model_ray, reach);
            self.preview.rays[i] = Some(PreviewRay {
                origin: ray.origin,
                dir: ray.dir,
                length: hit.map_or(self.settings.reach, |h| h.t * cx.model.scale),
                hit: hit.is_some(),
            });
            hits[i] = hit;
        }
        self.preview.highlighted = hits[1].or(hits[0]).map(|h| h.id);
        if self
            .preview
            .selected
            .is_some_and(|id| cx.doc.get(id).is_err())
        {
            self.preview.selected = None;
        }
        for hand in [Hand::Right, Hand::Left] {
            let i = hand.index();
            let (now, was) = (&inputs[i], &self.prev[i]);
            if now.grab && !was.grab && now.tracked {
                if let (Some(hit), Some(grip)) = (hits[i], now.grip) {
                    if let Ok(obj) = cx.doc.get(hit.id) {
                        {
                            let base = obj.transform();
                            let sculpt = matches!(obj.kind, ObjectKind::SculptMesh(_));
                            self.drag = Some(Drag {
                                id: hit.id,
                                base,
                                before: Similarity::IDENTITY,
                                hands: vec![(hand, grip)],
                                bar: None,
                                current: Similarity::IDENTITY,
                                lost_since: None,
                                axis: self.scale_axis.filter(|_| !sculpt),
                            });
                            self.preview.selected = Some(hit.id);
                            return None;
                        }
                    }
                }
            }
            if now.select && !was.select {
                self.preview.selected = hits[i].map(|h| h.id);
            }
            if now.menu && !was.menu && !self.settings.palette.is_empty() {
                self.palette_index = (self.palette_index + 1) % self.settings.palette.len();
                *self.preview.placing_mut() = Some(self.settings.palette[self.palette_index]);
            }
            if now.primary && !was.primary {
                if let Some(id) = self.preview.selected {
                    return Some(ScriptCommand::Op(Op::Duplicate(Duplicate { id })));
                }
                if let (Some(grip), Some(shape)) =
                    (now.grip, self.preview.placing().copied().flatten())
                {
                    let at = to_model.apply(grip.position);
                    return Some(ScriptCommand::Op(Op::AddSolid(AddSolid {
                        shape,
                        segments: self.settings.segments,
                        transform: Transform::translation(at.to_array()),
                    })));
                }
            }
            if now.secondary && !was.secondary {
                if let Some(id) = self.preview.selected.take() {
                    return Some(ScriptCommand::Op(Op::Delete(Delete { id })));
                }
            }
            if self.stick_armed[i] && now.stick_x.abs() > 0.8 {
                self.stick_armed[i] = false;
                return Some(if now.stick_x < 0.0 {
                    ScriptCommand::Undo
                } else {
                    ScriptCommand::Redo
                });
            }
            if now.stick_x.abs() < 0.3 {
                self.stick_armed[i] = true;
            }
        }
        None
    }

    fn dragging(&mut self, cx: &ToolContext, inputs: &[HandInput; 2]) -> Option<ScriptCommand> {
        let mut drag = self.drag.take()?;
        let t = cx.frame.time;
        // A participant that teleported: commit what we had before the jump.
        if drag.hands.iter().any(|(h, _)| inputs[h.index()].teleported) {
            return self.commit(cx, &drag);
        }
        // A participant without tracking: freeze, then cancel.
        let lost = drag
            .hands
            .iter()
            .any(|(h, _)| !inputs[h.index()].tracked || inputs[h.index()].grip.is_none());
        if lost {
            if lost_too_long(&mut drag.lost_since, t, self.settings.grace) {
                self.preview.moving = None;
                return None;
            }
            self.drag = Some(drag);
            return None;
        }
        drag.lost_since = None;
        // Hands joining or letting go.
        let holding: Vec<(Hand, Pose)> = Hand::BOTH
            .iter()
            .filter_map(|&h| {
                let inp = &inputs[h.index()];
                let was_in = drag.hands.iter().any(|(d, _)| *d == h);
                let joins = !was_in && inp.grab && !self.prev[h.index()].grab && inp.can_join;
                ((was_in && inp.grab) || joins)
                    .then_some(())
                    .and(inp.grip.map(|g| (h, g)))
            })
            .collect();
        if holding.is_empty() {
            return self.commit(cx, &drag);
        }
        let same = holding.len() == drag.hands.len()
            && holding
                .iter()
                .zip(&drag.hands)
                .all(|((a, _), (b, _))| a == b);
        if !same {
            drag.rebase(holding.clone());
        }
        let grips: Vec<Pose> = holding.iter().map(|(_, g)| *g).collect();
        if let Some(m) = drag.motion_now(&grips) {
            drag.current = m;
        }
        let (transform, motion, to) = snapped(cx, &drag);
        self.preview.readout = readout(&drag.base, &motion, cx.snap);
        if let Some(to) = to {
            self.preview.readout += &format!("  snapped to {}", to.label());
        }
        match drag.axis {
            Some(k) => self.preview.readout += &format!("  along {}", ["x", "y", "z"][k]),
            None if self.scale_axis.is_some() => self.preview.readout += "  uniform (sculpt)",
            None => {}
        }
        self.preview.moving = Some(MovingPreview {
            id: drag.id,
            transform,
            motion,
        });
        for hand in Hand::BOTH {
            self.preview.rays[hand.index()] = None;
        }
        self.drag = Some(drag);
        None
    }

    fn commit(&mut self, cx: &ToolContext, drag: &Drag) -> Option<ScriptCommand> {
        self.preview.moving = None;
        self.preview.readout.clear();
        let (transform, _, _) = snapped(cx, drag);
        if transform.validate().is_err() || transform == drag.base {
            return None;
        }
        Some(ScriptCommand::Op(Op::SetTransform(SetTransform {
            id: drag.id,
            transform,
        })))
    }
}

/// The placement a drag would give now, its model-space motion and what
/// it snapped to among the other objects, with the session's snapping: the
/// rotation to the angle step (relative to where the drag began), the
/// position to the model-space grid, then (with "Snap to objects") onto
/// another object's centre, surface or axis line
/// ([`crate::interact::tools::snap`]), which wins over the grid.
fn snapped(cx: &ToolContext, drag: &Drag) -> (Transform, Similarity, Option<ObjectSnap>) {
    let mut motion = cx.model.conjugate(&drag.current);
    motion.rotate = cx.snap.rotate(motion.rotate);
    let mut t = motion.then_transform(&drag.base);
    let base = DVec3::from_array(drag.base.translate);
    let mut at = cx.snap.translate(DVec3::from_array(t.translate));
    t.translate = at.to_array();
    if let Some(k) = drag.axis {
        // Only along the object's axis `k`: the other axes keep their scale.
        t.scale = drag.base.scale;
        t.scale[k] *= motion.scale;
    }
    let to = cx
        .snap
        .objects
        .then(|| moved_bbox(cx, drag, &t))
        .flatten()
        .and_then(|b| snap_to_objects(cx.doc, drag.id, b));
    if let Some(s) = &to {
        at += s.offset;
        t.translate = at.to_array();
    }
    motion.translate = at - motion.rotate * (base * motion.scale);
    (t, motion, to)
}

/// Vertices of a dragged mesh mapped exactly for the snapping box; above
/// this, its bounding box's corners are mapped instead (a looser box).
const SNAP_EXACT_VERTICES: usize = 50_000;

/// The bounding box (model space) of the dragged object at placement `t`.
fn moved_bbox(cx: &ToolContext, drag: &Drag, t: &Transform) -> Option<(DVec3, DVec3)> {
    let mesh = &cx.doc.get(drag.id).ok()?.mesh;
    let map = t.to_affine().ok()? * drag.base.to_affine().ok()?.inverse();
    let fold = |it: &mut dyn Iterator<Item = DVec3>| {
        let first = map.transform_point3(it.next()?);
        Some(it.fold((first, first), |(lo, hi), p| {
            let q = map.transform_point3(p);
            (lo.min(q), hi.max(q))
        }))
    };
    if mesh.positions.len() <= SNAP_EXACT_VERTICES {
        fold(&mut mesh.positions.iter().map(|p| DVec3::from_array(*p)))
    } else {
        let (lo, hi) = mesh.bbox()?;
        fold(&mut (0..8).map(|k| {
            DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        }))
    }
}

/// What a drag has done so far, for the readout next to the hand:
/// distance moved, angle turned, scale, and the snapping in effect.
pub(crate) fn readout(base: &Transform, motion: &Similarity, snap: Snap) -> String {
    let moved = motion.apply(DVec3::from_array(base.translate)) - DVec3::from_array(base.translate);
    let angle = motion.rotate.to_axis_angle().1.to_degrees();
    let mut s = format!(
        "{:.1} cm  {:.0}°  x{:.2}",
        moved.length() * 100.0,
        angle,
        motion.scale
    );
    if snap.grid > 0.0 {
        s += &format!(
            "  grid {}",
            crate::interact::palette::length_label(snap.grid)
        );
    }
    if snap.angle > 0.0 {
        s += &format!("  snap {}°", snap.angle);
    }
    s
}

impl Tool for ObjectTool {
    fn name(&self) -> &'static str {
        "object"
    }

    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand> {
        self.print = *cx.doc.print_setup();
        let max_speed = self.settings.max_hand_speed;
        let inputs = Hand::BOTH.map(|h| read_hand(cx, h, &mut self.last_palm, max_speed));
        let out = if self.drag.is_some() {
            self.dragging(cx, &inputs)
        } else {
            self.idle(cx, &inputs)
        };
        // Keep the previous state of hands only while tracked, so a lost
        // hand that comes back pressing does not fire a fresh edge.
        for (prev, now) in self.prev.iter_mut().zip(inputs) {
            if now.tracked {
                *prev = now;
            }
        }
        out
    }

    fn cancel(&mut self) {
        self.drag = None;
        self.preview.moving = None;
    }

    fn preview(&self) -> &Preview {
        &self.preview
    }

    fn choices(&self) -> Vec<ChoiceGroup> {
        vec![
            ChoiceGroup {
                name: "Shape",
                options: self
                    .settings
                    .palette
                    .iter()
                    .map(|s| s.name().to_string())
                    .collect(),
                active: self.palette_index,
            },
            ChoiceGroup {
                name: "Wall",
                options: ["1.2 mm", "2 mm", "3 mm"].map(String::from).to_vec(),
                active: WALLS
                    .iter()
                    .position(|w| *w == self.print.wall_thickness)
                    .unwrap_or(usize::MAX),
            },
            ChoiceGroup {
                name: "Overlaps",
                options: vec!["refuse".into(), "flag".into()],
                active: POLICIES
                    .iter()
                    .position(|p| *p == self.print.on_self_intersection)
                    .unwrap_or(usize::MAX),
            },
            ChoiceGroup {
                name: "Scale",
                options: ["uniform", "x", "y", "z"].map(String::from).to_vec(),
                active: self.scale_axis.map_or(0, |k| k + 1),
            },
            ChoiceGroup {
                name: "Printer",
                options: PrinterPreset::ALL
                    .iter()
                    .map(|p| p.label().to_string())
                    .collect(),
                active: PrinterPreset::ALL
                    .iter()
                    .position(|p| *p == self.print.printer.preset)
                    .unwrap_or(usize::MAX),
            },
        ]
    }

    fn choose(&mut self, doc: &Document, group: usize, option: usize) -> Option<ScriptCommand> {
        let setup = doc.print_setup();
        match group {
            0 if option < self.settings.palette.len() => {
                self.palette_index = option;
                *self.preview.placing_mut() = Some(self.settings.palette[option]);
            }
            1 if option < WALLS.len() && setup.wall_thickness != WALLS[option] => {
                return Some(ScriptCommand::Op(Op::SetWallThickness(SetWallThickness {
                    thickness: WALLS[option],
                })));
            }
            2 if option < POLICIES.len() && setup.on_self_intersection != POLICIES[option] => {
                return Some(ScriptCommand::Op(Op::SetSelfIntersectionPolicy(
                    SetSelfIntersectionPolicy {
                        policy: POLICIES[option],
                    },
                )));
            }
            3 if option < 4 => self.scale_axis = option.checked_sub(1),
            4 if PrinterPreset::ALL
                .get(option)
                .is_some_and(|p| *p != setup.printer.preset) =>
            {
                return Some(ScriptCommand::Op(Op::SetPrinter(SetPrinter {
                    printer: PrinterPreset::ALL[option],
                    size: None,
                })));
            }
            _ => {}
        }
        None
    }
}
