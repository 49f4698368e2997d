//! [`CsgTool`]: the controller interface of paper 2 (EasyVRModeling §4)
//! over the `sdf_*` ops.
//!
//! The paper's eight modes on two 6-DOF controllers, adapted to the action
//! map of [`crate::interact::ActionMap`] (either hand works, as in the paper, except
//! where noted):
//!
//! | paper mode      | action                      | op                          |
//! |-----------------|-----------------------------|-----------------------------|
//! | select          | `select` (trigger) on a ray | — (selection)               |
//! | grab            | `grab` held on an operand   | `sdf_set_operand_transform` |
//! | scale (§4.3)    | both `grab` on one operand  | `sdf_scale_two_hand`        |
//! | scale axis      | right stick quadrant        | X (→), Y (↑), Z (←), A (↓)  |
//! | menu            | `menu`: right next, left previous | — (component)         |
//! | SceneOperate    | stick ↑/↓ picks, `primary` applies | `sdf_add_operand` / `sdf_cancel_operand` |
//! | update          | `secondary`                 | `sdf_update`                |
//! | copy (§4.4)     | `secondary` with an operand selected | `sdf_copy_operand` |
//! | delete          | double `select` on a target | `sdf_cancel_operand` / `delete` |
//! | undo / redo     | stick flick ← / →           | undo / redo                 |
//!
//! Choices:
//! - Paper 2 applies union / intersect / subtract to an operand already in
//!   the scene; here SceneOperate with a CSG operation places the menu's
//!   current component at the controller as a new pending operand with that
//!   operation (the op log's `sdf_add_operand` carries both), and *cancel*
//!   removes the selected pending operand.
//! - In a document without an SDF volume, SceneOperate creates one
//!   (`sdf_create`, one op for that press); the tool keeps working on the
//!   volume it found first while it exists, else on the newest one.
//! - As in the paper, copy is the update button with one operand selected;
//!   the copy is placed [`CsgToolSettings::copy_offset`] away.
//! - Operands are picked by their placed local bounding box (cheap every
//!   frame; the fused surface is picked by the document's mesh).
//! - Scaling starts when the second hand grabs the operand the first one
//!   holds (or the selected one): a drag in progress is committed first.
//!   The op stores both hands' model-space positions at start and end, so
//!   the ratio of Eq. 1 (clamped to `[0.4, 4]`) is recomputed by the op.
//!
//! - Palette "Grab moves: operand | fused result": with *fused result*,
//!   a grab on the fused surface drags the whole result (paper 2 §4.4's
//!   moving of a result as such); on release one `sdf_move_fused` carries
//!   the motion (a similarity in the volume's own frame). Pending operand
//!   boxes are not grabbed in that mode.
//! - Palette "Component from": every other object of the document; picking
//!   one is `sdf_component_from_object` (the object's closed mesh becomes a
//!   user component of the volume), and once applied that component is
//!   added to the "Component" menu and made the active one, so the next
//!   SceneOperate places it.
//!
//! Bad input during a drag or a scale: tracking lost → the preview
//! freezes and, after [`CsgToolSettings::grace`] s, the gesture is cancelled
//! (document unchanged); a teleport → the gesture is committed at its last
//! good state; NaN samples never reach the tool.

use crate::doc::{Create, Delete, Document, Edit, ObjectId, ObjectKind, Op, ScriptCommand};
use crate::math::{DAffine3, DVec3, Transform};
use crate::sdf::placement::two_hand_ratio;
use crate::sdf::volume::DEFAULT_STEP;
use crate::sdf::{Component, CsgOp, ScaleAxis, SdfVolume};
use crate::sdf::{
    OperandIndex, SdfAddOperand, SdfCancelOperand, SdfComponentFromObject, SdfCopyFused,
    SdfCopyOperand, SdfCreate, SdfMoveFused, SdfScaleTwoHand, SdfSetOperandTransform, SdfSetStep,
    SdfUpdate,
};
use crate::solid::SolidShape;

use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::ctl_input::{cycle, remember, CtlInput, Flick};
use crate::interact::input::{Hand, Pose};
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::lost_too_long;
use crate::interact::tools::pick::{pick, Ray};
use crate::interact::tools::{
    object_label, MovingPreview, OperandPreview, Preview, PreviewRay, Tool, ToolContext,
};

/// A SceneOperate choice (paper 2 §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneOperate {
    /// Add with union.
    Union,
    /// Add with intersection.
    Intersect,
    /// Add with subtraction.
    Subtract,
    /// Remove the selected operand.
    Cancel,
}

impl SceneOperate {
    /// The four choices in menu order.
    pub const ALL: [SceneOperate; 4] = [
        SceneOperate::Union,
        SceneOperate::Intersect,
        SceneOperate::Subtract,
        SceneOperate::Cancel,
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            SceneOperate::Union => "union",
            SceneOperate::Intersect => "intersect",
            SceneOperate::Subtract => "subtract",
            SceneOperate::Cancel => "cancel",
        }
    }
}

/// Settings of the CSG tool.
#[derive(Clone, Debug, PartialEq)]
pub struct CsgToolSettings {
    /// How far rays reach (metres).
    pub reach: f64,
    /// Seconds a gesture survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Grid step of volumes the tool creates.
    pub step: f64,
    /// The component menu.
    pub components: Vec<Component>,
    /// Where a copy goes relative to its original (model units).
    pub copy_offset: [f64; 3],
    /// Two presses of `select` within this many seconds are a double click.
    pub double_click: f64,
}

/// The library components on the tool's menu after its primitives, in
/// menu order: listed here, so a component added to the library never
/// shifts the menu (a test checks every name is in the library).
pub const MENU_LIBRARY: &[&str] = &[
    "chair_seat",
    "chair_back",
    "chair_leg",
    "chair_leg_square",
    "chair_armrest",
    "chair_crossbar",
    "cup_body",
    "cup_hollow",
    "cup_handle",
    "cup_saucer",
    "cup_rim",
    "blob",
    "bean",
    "mushroom",
    "snowman",
];

impl Default for CsgToolSettings {
    fn default() -> Self {
        let solid = |shape| Component::Solid { shape };
        let mut components = vec![
            solid(SolidShape::Cylinder {
                radius: 0.05,
                height: 0.1,
            }),
            solid(SolidShape::Torus {
                major_radius: 0.04,
                minor_radius: 0.01,
            }),
            solid(SolidShape::Sphere { radius: 0.05 }),
            solid(SolidShape::Box {
                size: [0.1, 0.1, 0.1],
            }),
            solid(SolidShape::Cone {
                radius: 0.05,
                height: 0.1,
            }),
            solid(SolidShape::Capsule {
                radius: 0.03,
                length: 0.06,
            }),
        ];
        components.extend(MENU_LIBRARY.iter().map(|n| Component::Library {
            name: (*n).to_string(),
        }));
        Self {
            reach: 5.0,
            grace: 0.25,
            step: DEFAULT_STEP,
            components,
            copy_offset: [0.15, 0.0, 0.0],
            double_click: 0.4,
        }
    }
}

/// What a ray or the selection points at, in the tool's volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Operand(usize),
    Volume,
}

/// One hand dragging a pending operand.
#[derive(Clone, Copy, Debug)]
struct OperandDrag {
    volume: ObjectId,
    index: usize,
    base: Transform,
    hand: Hand,
    grip0: Pose,
    /// Model-space motion so far.
    motion: Similarity,
    lost_since: Option<f64>,
}

impl OperandDrag {
    fn transform(&self) -> Transform {
        self.motion.then_transform(&self.base)
    }
}

/// One hand dragging the fused result of a volume.
#[derive(Clone, Copy, Debug)]
struct FusedDrag {
    volume: ObjectId,
    /// The volume's placement (its own frame to model space).
    placement: Transform,
    hand: Hand,
    grip0: Pose,
    /// Model-space motion so far.
    motion: Similarity,
    lost_since: Option<f64>,
}

impl FusedDrag {
    /// The op moving the result by the motion so far, in the volume's own
    /// frame; `None` for no motion or a placement with a per-axis scale
    /// (the motion would not stay a similarity there).
    fn op(&self) -> Option<Op> {
        let p = &self.placement;
        let [a, b, c] = p.scale;
        if a != b || b != c || a <= 0.0 {
            return None;
        }
        let own = Similarity {
            translate: DVec3::from_array(p.translate),
            rotate: crate::math::DQuat::from_array(p.rotate).normalize(),
            scale: a,
        };
        let local = own.conjugate(&self.motion);
        let transform = local.then_transform(&Transform::IDENTITY);
        if !local.is_valid() || transform.validate().is_err() || transform == Transform::IDENTITY {
            return None;
        }
        Some(Op::SdfMoveFused(Edit::new(
            self.volume,
            SdfMoveFused { transform },
        )))
    }
}

/// Both hands scaling a pending operand.
#[derive(Clone, Copy, Debug)]
struct ScaleGesture {
    volume: ObjectId,
    index: usize,
    base: Transform,
    /// Model-space hand positions (left, right) at the start and now.
    start: [DVec3; 2],
    end: [DVec3; 2],
    axis: ScaleAxis,
    lost_since: Option<f64>,
}

impl ScaleGesture {
    fn op(&self) -> Edit<SdfScaleTwoHand> {
        Edit::new(
            self.volume,
            SdfScaleTwoHand {
                operand: OperandIndex(self.index),
                axis: self.axis,
                hands_start: self.start.map(|p| p.to_array()),
                hands_end: self.end.map(|p| p.to_array()),
            },
        )
    }

    /// The operand's placement if the gesture ended now.
    fn transform(&self) -> Transform {
        let op = self.op().edit;
        let r = two_hand_ratio(op.hands_start, op.hands_end).unwrap_or(1.0);
        let mut t = self.base;
        match self.axis {
            ScaleAxis::X => t.scale[0] *= r,
            ScaleAxis::Y => t.scale[1] *= r,
            ScaleAxis::Z => t.scale[2] *= r,
            ScaleAxis::Uniform => t.scale = t.scale.map(|s| s * r),
        }
        t
    }
}

/// Local boxes of the pending operands, for picking.
#[derive(Clone, Debug, Default)]
struct OperandBoxes {
    key: Option<(ObjectId, Vec<crate::sdf::Operand>)>,
    boxes: Vec<Option<(DAffine3, DVec3, DVec3)>>,
}

impl OperandBoxes {
    fn refresh(&mut self, id: ObjectId, v: &SdfVolume) {
        if self
            .key
            .as_ref()
            .is_some_and(|(k, p)| *k == id && *p == v.pending)
        {
            return;
        }
        self.boxes = v
            .pending
            .iter()
            .map(|o| {
                let f = v.placed(o).ok()?;
                Some((f.inverse, f.local_box.0, f.local_box.1))
            })
            .collect();
        self.key = Some((id, v.pending.clone()));
    }

    /// The nearest operand box along `ray` (model space) within `max_t`.
    fn pick(&self, ray: &Ray, max_t: f64) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, b) in self.boxes.iter().enumerate() {
            let Some((inv, lo, hi)) = b else { continue };
            let o = inv.transform_point3(ray.origin);
            let d = inv.transform_vector3(ray.dir);
            // The local ray's parameter equals the model one (same t).
            let Some(t) = slab(o, d, *lo, *hi) else {
                continue;
            };
            if t <= max_t && best.is_none_or(|(_, bt)| t <= bt) {
                best = Some((i, t));
            }
        }
        best
    }
}

/// Entry parameter of the ray `o + t d` into the box (0 when inside).
fn slab(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<f64> {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-15 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then_some(t0)
}

/// The volume the tool edits: `preferred` if still there, else the newest.
fn volume(doc: &Document, preferred: Option<ObjectId>) -> Option<(ObjectId, &SdfVolume)> {
    let as_volume = |id: ObjectId| match &doc.get(id).ok()?.kind {
        ObjectKind::SdfVolume(v) => Some((id, v)),
        #[allow(unreachable_patterns)]
        _ => None,
    };
    preferred
        .and_then(as_volume)
        .or_else(|| doc.objects().filter_map(|(id, _)| as_volume(id)).last())
}

/// Paper 2's controller interface: grab, select, menu, update,
/// SceneOperate, scaling, copy, delete, undo and redo.
#[derive(Clone, Debug)]
pub struct CsgTool {
    settings: CsgToolSettings,
    preview: Preview,
    prev: [CtlInput; 2],
    flick: Flick,
    component: usize,
    scene_op: SceneOperate,
    axis: ScaleAxis,
    volume: Option<ObjectId>,
    /// The volume's grid step, as of the last frame.
    step: Option<f64>,
    selected: Option<Target>,
    last_select: [Option<(f64, Target)>; 2],
    drag: Option<OperandDrag>,
    scale: Option<ScaleGesture>,
    boxes: OperandBoxes,
    /// Grabs on the fused surface move the result ("Grab moves").
    grab_fused: bool,
    fused_drag: Option<FusedDrag>,
    /// The other objects of the document, for "Component from".
    objects: Vec<(ObjectId, String)>,
    /// A component asked for by "Component from", made active once the
    /// volume has it.
    pending_component: Option<String>,
}

impl Default for CsgTool {
    fn default() -> Self {
        Self::new(CsgToolSettings::default())
    }
}

impl CsgTool {
    /// A tool with `settings`.
    pub fn new(settings: CsgToolSettings) -> Self {
        let mut t = Self {
            settings,
            preview: Preview::default(),
            prev: [CtlInput::default(); 2],
            flick: Flick::default(),
            component: 0,
            scene_op: SceneOperate::Union,
            axis: ScaleAxis::Uniform,
            volume: None,
            step: None,
            selected: None,
            last_select: [None; 2],
            drag: None,
            scale: None,
            boxes: OperandBoxes::default(),
            grab_fused: false,
            fused_drag: None,
            objects: Vec::new(),
            pending_component: None,
        };
        t.update_mode();
        t
    }

    /// The component SceneOperate places next.
    pub fn component(&self) -> Option<&Component> {
        self.settings.components.get(self.component)
    }

    /// The SceneOperate choice.
    pub fn scene_operate(&self) -> SceneOperate {
        self.scene_op
    }

    fn update_mode(&mut self) {
        let comp = self
            .component()
            .map_or_else(|| "-".to_string(), component_name);
        let axis = match self.axis {
            ScaleAxis::X => "x",
            ScaleAxis::Y => "y",
            ScaleAxis::Z => "z",
            ScaleAxis::Uniform => "a",
        };
        self.preview.mode = format!("{} {} scale:{}", self.scene_op.name(), comp, axis);
    }

    fn idle(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
        vol: Option<(ObjectId, &SdfVolume)>,
    ) -> Option<ScriptCommand> {
        let to_model = cx.model.inverse();
        let reach = self.settings.reach / cx.model.scale;
        let mut hits: [Option<Target>; 2] = [None, None];
        let mut highlighted_object = None;
        for hand in Hand::BOTH {
            let i = hand.index();
            self.preview.rays[i] = None;
            let Some(ray) = inputs[i].ray.filter(|_| inputs[i].tracked) else {
                continue;
            };
            let m = Ray {
                origin: to_model.apply(ray.origin),
                dir: to_model.apply_dir(ray.dir),
            };
            let op_hit = self.boxes.pick(&m, reach);
            let doc_hit = pick(cx.doc, &m, reach);
            let on_volume = |id| vol.is_some_and(|(v, _)| v == id);
            let (target, t) = match (op_hit, doc_hit) {
                (_, Some(h)) if self.grab_fused && on_volume(h.id) => {
                    (Some(Target::Volume), Some(h.t))
                }
                (Some((k, t)), _) => (Some(Target::Operand(k)), Some(t)),
                (None, Some(h)) if vol.is_some_and(|(id, _)| id == h.id) => {
                    (Some(Target::Volume), Some(h.t))
                }
                (None, Some(h)) => {
                    highlighted_object = Some(h.id);
                    (None, Some(h.t))
                }
                _ => (None, None),
            };
            self.preview.rays[i] = Some(PreviewRay {
                origin: ray.origin,
                dir: ray.dir,
                length: t.map_or(self.settings.reach, |t| t * cx.model.scale),
                hit: t.is_some(),
            });
            hits[i] = target;
        }
        let hover = hits[1].or(hits[0]);
        self.preview.highlighted = match hover {
            Some(Target::Volume) => vol.map(|(id, _)| id),
            _ => highlighted_object,
        };
        self.preview.csg_mut().highlighted_operand = match hover {
            Some(Target::Operand(k)) => Some(k),
            _ => None,
        };
        for hand in [Hand::Right, Hand::Left] {
            let i = hand.index();
            let (now, was) = (inputs[i], self.prev[i]);
            if !now.tracked {
                continue;
            }
            // Grab: one hand drags, the second one on the same operand scales.
            if now.grab && !was.grab {
                if let Some(cmd) = self.start_grab(cx, inputs, hand, hits[i], vol) {
                    return cmd;
                }
            }
            if now.select > 0.5 && was.select <= 0.5 {
                if let Some(cmd) = self.click_select(cx.frame.time, hand, hits[i], vol) {
                    return Some(cmd);
                }
            }
            if now.menu && !was.menu {
                let dir = if hand == Hand::Left { -1 } else { 1 };
                self.component = cycle(self.component, dir, self.settings.components.len());
                self.update_mode();
            }
            if let Some(d) = self.flick.fired(hand, 1, &now) {
                let k = SceneOperate::ALL.iter().position(|s| *s == self.scene_op);
                self.scene_op = SceneOperate::ALL[cycle(k.unwrap_or(0), -d, 4)];
                self.update_mode();
            }
            if now.primary && !was.primary {
                return self.scene_operate_now(cx, now, vol);
            }
            if now.secondary && !was.secondary {
                let (id, v) = vol?;
                if let Some(Target::Operand(k)) = self.selected {
                    let o = v.pending.get(k)?;
                    let mut t = o.transform;
                    for (a, d) in t.translate.iter_mut().zip(self.settings.copy_offset) {
                        *a += d;
                    }
                    return Some(ScriptCommand::Op(Op::SdfCopyOperand(Edit::new(
                        id,
                        SdfCopyOperand {
                            operand: OperandIndex(k),
                            transform: t,
                        },
                    ))));
                }
                return Some(ScriptCommand::Op(Op::SdfUpdate(Edit::new(
                    id,
                    SdfUpdate {},
                ))));
            }
            if let Some(d) = self.flick.fired(hand, 0, &now) {
                return Some(if d < 0 {
                    ScriptCommand::Undo
                } else {
                    ScriptCommand::Redo
                });
            }
        }
        None
    }

    /// A grab press of `hand` on `hit`. `Some(cmd)` ends the frame's
    /// input handling (`cmd` may be `None`).
    fn start_grab(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
        hand: Hand,
        hit: Option<Target>,
        vol: Option<(ObjectId, &SdfVolume)>,
    ) -> Option<Option<ScriptCommand>> {
        let (id, v) = vol?;
        if self.grab_fused {
            if hit != Some(Target::Volume) {
                return None;
            }
            self.fused_drag = Some(FusedDrag {
                volume: id,
                placement: cx.doc.get(id).ok()?.transform(),
                hand,
                grip0: inputs[hand.index()].grip?,
                motion: Similarity::IDENTITY,
                lost_since: None,
            });
            self.selected = Some(Target::Volume);
            return Some(None);
        }
        let other = inputs[hand.other().index()];
        let target = match hit {
            Some(Target::Operand(k)) => Some(k),
            _ if other.grab => match self.selected {
                Some(Target::Operand(k)) => Some(k),
                _ => None,
            },
            _ => None,
        }?;
        let base = v.pending.get(target)?.transform;
        let grip = inputs[hand.index()].grip?;
        if other.grab && other.tracked {
            let og = other.grip?;
            let to_model = cx.model.inverse();
            let mut start = [DVec3::ZERO; 2];
            start[hand.index()] = to_model.apply(grip.position);
            start[hand.other().index()] = to_model.apply(og.position);
            self.scale = Some(ScaleGesture {
                volume: id,
                index: target,
                base,
                start,
                end: start,
                axis: self.axis,
                lost_since: None,
            });
            self.selected = Some(Target::Operand(target));
            return Some(None);
        }
        self.drag = Some(OperandDrag {
            volume: id,
            index: target,
            base,
            hand,
            grip0: grip,
            motion: Similarity::IDENTITY,
            lost_since: None,
        });
        self.selected = Some(Target::Operand(target));
        Some(None)
    }

    fn click_select(
        &mut self,
        time: f64,
        hand: Hand,
        hit: Option<Target>,
        vol: Option<(ObjectId, &SdfVolume)>,
    ) -> Option<ScriptCommand> {
        let i = hand.index();
        let double = self.last_select[i]
            .is_some_and(|(t0, tg)| Some(tg) == hit && time - t0 <= self.settings.double_click);
        self.selected = hit;
        if !double {
            self.last_select[i] = hit.map(|h| (time, h));
            return None;
        }
        self.last_select[i] = None;
        self.selected = None;
        let (id, _) = vol?;
        Some(ScriptCommand::Op(match hit? {
            Target::Operand(k) => Op::SdfCancelOperand(Edit::new(
                id,
                SdfCancelOperand {
                    operand: OperandIndex(k),
                },
            )),
            Target::Volume => Op::Delete(Delete { id }),
        }))
    }

    fn scene_operate_now(
        &mut self,
        cx: &ToolContext,
        now: CtlInput,
        vol: Option<(ObjectId, &SdfVolume)>,
    ) -> Option<ScriptCommand> {
        let Some((id, v)) = vol else {
            return Some(ScriptCommand::Op(Op::SdfCreate(Create(SdfCreate {
                step: self.settings.step,
            }))));
        };
        let csg = match self.scene_op {
            SceneOperate::Union => CsgOp::Union,
            SceneOperate::Intersect => CsgOp::Intersect,
            SceneOperate::Subtract => CsgOp::Subtract,
            SceneOperate::Cancel => {
                let Some(Target::Operand(k)) = self.selected else {
                    return None;
                };
                self.selected = None;
                return (k < v.pending.len()).then_some(ScriptCommand::Op(Op::SdfCancelOperand(
                    Edit::new(
                        id,
                        SdfCancelOperand {
                            operand: OperandIndex(k),
                        },
                    ),
                )));
            }
        };
        let at = cx.model.inverse().apply(now.grip?.position);
        Some(ScriptCommand::Op(Op::SdfAddOperand(Edit::new(
            id,
            SdfAddOperand {
                component: self.component()?.clone(),
                csg,
                transform: Transform::translation(at.to_array()),
            },
        ))))
    }

    fn dragging(&mut self, cx: &ToolContext, inputs: &[CtlInput; 2]) -> Option<ScriptCommand> {
        let mut d = self.drag.take()?;
        let now = inputs[d.hand.index()];
        if now.teleported {
            return self.commit_drag(&d);
        }
        if !now.tracked || now.grip.is_none() {
            if lost_too_long(&mut d.lost_since, cx.frame.time, self.settings.grace) {
                self.preview.csg_mut().moving_operand = None;
                return None;
            }
            self.drag = Some(d);
            return None;
        }
        d.lost_since = None;
        let grip = now.grip?;
        let world = Similarity::from_pose(&grip.compose(&d.grip0.inverse()));
        let m = cx.model.conjugate(&world);
        if m.is_valid() {
            d.motion = m;
        }
        let other = inputs[d.hand.other().index()];
        let was_other = self.prev[d.hand.other().index()];
        let joining = other.tracked && other.grab && !was_other.grab;
        if let Some(og) = other.grip.filter(|_| joining) {
            // The second hand joins: commit the move, then scale from here.
            let cmd = self.commit_drag(&d);
            let to_model = cx.model.inverse();
            let mut start = [DVec3::ZERO; 2];
            start[d.hand.index()] = to_model.apply(grip.position);
            start[d.hand.other().index()] = to_model.apply(og.position);
            self.scale = Some(ScaleGesture {
                volume: d.volume,
                index: d.index,
                base: d.transform(),
                start,
                end: start,
                axis: self.axis,
                lost_since: None,
            });
            return cmd;
        }
        if !now.grab {
            return self.commit_drag(&d);
        }
        self.preview.csg_mut().moving_operand = Some(OperandPreview {
            volume: d.volume,
            index: d.index,
            transform: d.transform(),
        });
        self.preview.rays = [None, None];
        self.drag = Some(d);
        None
    }

    fn fused_dragging(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
    ) -> Option<ScriptCommand> {
        let mut d = self.fused_drag.take()?;
        let now = inputs[d.hand.index()];
        if now.teleported || (now.tracked && !now.grab) {
            self.preview.moving = None;
            return d.op().map(ScriptCommand::Op);
        }
        if !now.tracked || now.grip.is_none() {
            if lost_too_long(&mut d.lost_since, cx.frame.time, self.settings.grace) {
                self.preview.moving = None;
                return None;
            }
            self.fused_drag = Some(d);
            return None;
        }
        d.lost_since = None;
        let grip = now.grip?;
        let world = Similarity::from_pose(&grip.compose(&d.grip0.inverse()));
        let m = cx.model.conjugate(&world);
        if m.is_valid() {
            d.motion = m;
        }
        self.preview.moving = Some(MovingPreview {
            id: d.volume,
            transform: d.motion.then_transform(&d.placement),
            motion: d.motion,
        });
        self.preview.readout =
            crate::interact::tools::object_tool::readout(&d.placement, &d.motion, cx.snap);
        self.preview.rays = [None, None];
        self.fused_drag = Some(d);
        None
    }

    fn commit_drag(&mut self, d: &OperandDrag) -> Option<ScriptCommand> {
        self.preview.csg_mut().moving_operand = None;
        let t = d.transform();
        if t.validate().is_err() || t == d.base {
            return None;
        }
        Some(ScriptCommand::Op(Op::SdfSetOperandTransform(Edit::new(
            d.volume,
            SdfSetOperandTransform {
                operand: OperandIndex(d.index),
                transform: t,
            },
        ))))
    }

    fn scaling(&mut self, cx: &ToolContext, inputs: &[CtlInput; 2]) -> Option<ScriptCommand> {
        let mut s = self.scale.take()?;
        if inputs.iter().any(|i| i.teleported) {
            return self.commit_scale(&s);
        }
        if inputs.iter().any(|i| !i.tracked || i.grip.is_none()) {
            if lost_too_long(&mut s.lost_since, cx.frame.time, self.settings.grace) {
                self.preview.csg_mut().moving_operand = None;
                return None;
            }
            self.scale = Some(s);
            return None;
        }
        s.lost_since = None;
        if inputs.iter().any(|i| !i.grab) {
            return self.commit_scale(&s);
        }
        let to_model = cx.model.inverse();
        for (e, i) in s.end.iter_mut().zip(inputs) {
            if let Some(g) = i.grip {
                *e = to_model.apply(g.position);
            }
        }
        // The right stick's quadrant picks the axis (the paper's touchpad).
        let [x, y] = inputs[Hand::Right.index()].stick;
        if x.abs().max(y.abs()) > 0.5 {
            s.axis = if x.abs() >= y.abs() {
                if x > 0.0 {
                    ScaleAxis::X
                } else {
                    ScaleAxis::Z
                }
            } else if y > 0.0 {
                ScaleAxis::Y
            } else {
                ScaleAxis::Uniform
            };
            self.axis = s.axis;
            self.update_mode();
        }
        self.preview.csg_mut().moving_operand = Some(OperandPreview {
            volume: s.volume,
            index: s.index,
            transform: s.transform(),
        });
        self.preview.rays = [None, None];
        self.scale = Some(s);
        None
    }

    fn commit_scale(&mut self, s: &ScaleGesture) -> Option<ScriptCommand> {
        self.preview.csg_mut().moving_operand = None;
        if s.transform() == s.base {
            return None;
        }
        Some(ScriptCommand::Op(Op::SdfScaleTwoHand(s.op())))
    }
}

impl Tool for CsgTool {
    fn name(&self) -> &'static str {
        "csg"
    }

    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand> {
        let inputs = Hand::BOTH.map(|h| CtlInput::read(cx, h));
        let vol = volume(cx.doc, self.volume);
        self.volume = vol.map(|(id, _)| id);
        self.step = vol.map(|(_, v)| v.step);
        match vol {
            Some((id, v)) => self.boxes.refresh(id, v),
            None => self.boxes = OperandBoxes::default(),
        }
        // A selection the document lost (undo, cancel) is dropped.
        if let (Some(Target::Operand(k)), Some((_, v))) = (self.selected, vol) {
            if k >= v.pending.len() {
                self.selected = None;
            }
        }
        if vol.is_none() {
            self.selected = None;
        }
        self.objects.clear();
        self.objects.extend(
            cx.doc
                .objects()
                .filter(|(id, _)| Some(*id) != self.volume)
                .map(|(id, o)| (id, object_label(id, o))),
        );
        if let (Some(name), Some((_, v))) = (&self.pending_component, vol) {
            if v.user_components.contains_key(name) {
                let c = Component::User { name: name.clone() };
                let k = match self.settings.components.iter().position(|x| *x == c) {
                    Some(k) => k,
                    None => {
                        self.settings.components.push(c);
                        self.settings.components.len() - 1
                    }
                };
                self.component = k;
                self.pending_component = None;
                self.update_mode();
            }
        }
        if self.fused_drag.is_none() {
            self.preview.readout.clear();
        }
        let out = if self.fused_drag.is_some() {
            self.fused_dragging(cx, &inputs)
        } else if self.scale.is_some() {
            self.scaling(cx, &inputs)
        } else if self.drag.is_some() {
            self.dragging(cx, &inputs)
        } else {
            self.idle(cx, &inputs, vol)
        };
        self.preview.selected = match self.selected {
            Some(Target::Volume) => self.volume,
            _ => None,
        };
        self.preview.csg_mut().selected_operand = match self.selected {
            Some(Target::Operand(k)) => Some(k),
            _ => None,
        };
        remember(&mut self.prev, &inputs);
        out
    }

    fn cancel(&mut self) {
        self.drag = None;
        self.scale = None;
        self.fused_drag = None;
        self.preview.moving = None;
        self.preview.readout.clear();
        self.preview.csg_mut().moving_operand = None;
    }

    fn preview(&self) -> &Preview {
        &self.preview
    }

    fn choices(&self) -> Vec<ChoiceGroup> {
        let axis = AXES.iter().position(|a| *a == self.axis).unwrap_or(0);
        let step = GRID_STEPS
            .iter()
            .position(|s| Some(*s) == self.step)
            .unwrap_or(usize::MAX);
        vec![
            ChoiceGroup {
                name: "Component",
                options: self
                    .settings
                    .components
                    .iter()
                    .map(component_name)
                    .collect(),
                active: self.component,
            },
            ChoiceGroup {
                name: "Operation",
                options: SceneOperate::ALL
                    .iter()
                    .map(|o| o.name().to_string())
                    .collect(),
                active: SceneOperate::ALL
                    .iter()
                    .position(|o| *o == self.scene_op)
                    .unwrap_or(0),
            },
            ChoiceGroup {
                name: "Scale axis",
                options: ["x", "y", "z", "all"].map(String::from).to_vec(),
                active: axis,
            },
            ChoiceGroup {
                name: "Fused result",
                options: vec!["copy beside".into()],
                active: usize::MAX,
            },
            ChoiceGroup {
                name: "Grid step",
                options: GRID_STEPS
                    .iter()
                    .map(|s| crate::interact::palette::length_label(*s))
                    .collect(),
                active: step,
            },
            ChoiceGroup {
                name: "Grab moves",
                options: vec!["operand".into(), "fused result".into()],
                active: usize::from(self.grab_fused),
            },
            ChoiceGroup {
                name: "Component from",
                options: self.objects.iter().map(|(_, l)| l.clone()).collect(),
                active: usize::MAX,
            },
        ]
    }

    fn choose(&mut self, doc: &Document, group: usize, option: usize) -> Option<ScriptCommand> {
        match group {
            0 if option < self.settings.components.len() => self.component = option,
            1 if option < SceneOperate::ALL.len() => self.scene_op = SceneOperate::ALL[option],
            2 if option < AXES.len() => self.axis = AXES[option],
            3 if option == 0 => {
                // A copy of the fused result beside it (paper 2's reuse of a
                // result as a component): queued, fused by the next update.
                let (id, v) = volume(doc, self.volume)?;
                if v.fused.is_empty() {
                    return None;
                }
                let name = (1..)
                    .map(|k| format!("result {k}"))
                    .find(|n| !v.user_components.contains_key(n))?;
                return Some(ScriptCommand::Op(Op::SdfCopyFused(Edit::new(
                    id,
                    SdfCopyFused {
                        name,
                        csg: CsgOp::Union,
                        transform: Transform::translation(self.settings.copy_offset),
                    },
                ))));
            }
            4 if option < GRID_STEPS.len() => {
                let (id, v) = volume(doc, self.volume)?;
                let step = GRID_STEPS[option];
                if v.step == step {
                    return None;
                }
                return Some(ScriptCommand::Op(Op::SdfSetStep(Edit::new(
                    id,
                    SdfSetStep { step },
                ))));
            }
            5 if option < 2 => self.grab_fused = option == 1,
            6 if option < self.objects.len() => {
                // The object as a user component of the volume, made the
                // active component once the op has applied (see update).
                let (id, v) = volume(doc, self.volume)?;
                let (object, label) = &self.objects[option];
                let taken = |n: &String| {
                    v.user_components.contains_key(n)
                        || self
                            .settings
                            .components
                            .iter()
                            .any(|c| component_name(c) == *n)
                };
                let name = std::iter::once(label.clone())
                    .chain((2..).map(|k| format!("{label} {k}")))
                    .find(|n| !taken(n))?;
                self.pending_component = Some(name.clone());
                return Some(ScriptCommand::Op(Op::SdfComponentFromObject(Edit::new(
                    id,
                    SdfComponentFromObject {
                        object: *object,
                        name,
                        csg: None,
                    },
                ))));
            }
            _ => return None,
        }
        self.update_mode();
        None
    }
}

/// The scale axes in palette order.
const AXES: [ScaleAxis; 4] = [ScaleAxis::X, ScaleAxis::Y, ScaleAxis::Z, ScaleAxis::Uniform];
/// SDF grid steps the palette offers (metres; the op's range is 4 to 12 mm).
const GRID_STEPS: [f64; 5] = [0.004, 0.006, 0.008, DEFAULT_STEP, 0.012];

/// A component's label.
fn component_name(c: &Component) -> String {
    match c {
        Component::Solid { shape } => shape.name().to_string(),
        Component::Library { name } | Component::User { name } => name.clone(),
    }
}
