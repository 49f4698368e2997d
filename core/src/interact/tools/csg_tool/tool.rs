//! [`CsgTool`]: the state machine over the gestures (idle, grab, select,
//! SceneOperate, drag, scale) and its [`Tool`] implementation (update,
//! preview, palette choices).

use crate::doc::{Create, Delete, Document, Edit, ObjectId, Op, ScriptCommand};
use crate::math::{DVec3, Transform};
use crate::sdf::volume::DEFAULT_STEP;
use crate::sdf::{Component, CsgOp, ScaleAxis, SdfVolume};
use crate::sdf::{
    OperandIndex, SdfAddOperand, SdfCancelOperand, SdfComponentFromObject, SdfCopyFused,
    SdfCopyOperand, SdfCreate, SdfSetOperandTransform, SdfSetStep, SdfUpdate,
};

use super::gestures::{volume, FusedDrag, OperandBoxes, OperandDrag, ScaleGesture, Target};
use super::settings::{CsgToolSettings, SceneOperate};
use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::Hand;
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::ctl_input::{cycle, remember, CtlInput, Flick};
use crate::interact::tools::lost_too_long;
use crate::interact::tools::pick::{pick, Ray};
use crate::interact::tools::{
    object_label, MovingPreview, OperandPreview, Preview, PreviewRay, Tool, ToolContext,
};

/// Paper 2's controller interface: grab, select, menu, update,
/// SceneOperate, scaling, copy, delete, undo and redo.
#[derive(Clone, Debug)]
pub struct CsgTool {
    pub(super) settings: CsgToolSettings,
    pub(super) preview: Preview,
    pub(super) prev: [CtlInput; 2],
    pub(super) flick: Flick,
    pub(super) component: usize,
    pub(super) scene_op: SceneOperate,
    pub(super) axis: ScaleAxis,
    pub(super) volume: Option<ObjectId>,
    /// The volume's grid step, as of the last frame.
    pub(super) step: Option<f64>,
    pub(super) selected: Option<Target>,
    pub(super) last_select: [Option<(f64, Target)>; 2],
    pub(super) drag: Option<OperandDrag>,
    pub(super) scale: Option<ScaleGesture>,
    pub(super) boxes: OperandBoxes,
    /// Grabs on the fused surface move the result ("Grab moves").
    pub(super) grab_fused: bool,
    pub(super) fused_drag: Option<FusedDrag>,
    /// The other objects of the document, for "Component from".
    pub(super) objects: Vec<(ObjectId, String)>,
    /// A component asked for by "Component from", made active once the
    /// volume has it.
    pub(super) pending_component: Option<String>,
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

    pub(super) fn update_mode(&mut self) {
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

    pub(super) fn idle(
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
    pub(super) fn start_grab(
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

    pub(super) fn click_select(
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

    pub(super) fn scene_operate_now(
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

    pub(super) fn dragging(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
    ) -> Option<ScriptCommand> {
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
        if let Some(m) = cx.grip_motion(&d.grip0, &grip) {
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

    pub(super) fn fused_dragging(
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
        if let Some(m) = cx.grip_motion(&d.grip0, &grip) {
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

    pub(super) fn commit_drag(&mut self, d: &OperandDrag) -> Option<ScriptCommand> {
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

    pub(super) fn scaling(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
    ) -> Option<ScriptCommand> {
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

    pub(super) fn commit_scale(&mut self, s: &ScaleGesture) -> Option<ScriptCommand> {
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
pub(super) const AXES: [ScaleAxis; 4] =
    [ScaleAxis::X, ScaleAxis::Y, ScaleAxis::Z, ScaleAxis::Uniform];
/// SDF grid steps the palette offers (metres; the op's range is 4 to 12 mm).
pub(super) const GRID_STEPS: [f64; 5] = [0.004, 0.006, 0.008, DEFAULT_STEP, 0.012];

/// A component's label.
pub(super) fn component_name(c: &Component) -> String {
    match c {
        Component::Solid { shape } => shape.name().to_string(),
        Component::Library { name } | Component::User { name } => name.clone(),
    }
}
