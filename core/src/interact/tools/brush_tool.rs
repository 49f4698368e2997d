//! [`BrushTool`]: the two-handed controller interface of paper 4 (warp
//! brushes on an adaptive mesh, interaction) over the `sculpt_*` ops.
//!
//! | action (dominant = right hand)   | effect                                  |
//! |----------------------------------|-----------------------------------------|
//! | trigger held                     | a stroke; pressure = trigger value      |
//! | non-dominant `grab` held         | orients the model (it follows the hand) |
//! | both `grab` held                 | scales model and brush by the hands' distance ratio (clamped to `[0.4, 4]`) |
//! | `menu`                           | next (right) / previous (left) preset   |
//! | stick ↑ / ↓                      | brush 1.25× larger / smaller            |
//! | `primary` with no sculpt object  | `sculpt_create` (a sphere)              |
//! | stick flick ← / →                | undo / redo                             |
//!
//! One `sculpt_stroke` op per held trigger, carrying the sampled path in
//! document space (the op replays bit for bit). Orienting and scaling the
//! model are view changes ([`Preview::view`]), not document edits, so they
//! make no op. Brush sizes are set in world metres: the brush keeps its
//! size in the hand while the model is scaled, so in model units it shrinks
//! when the model grows — the paper's two-handed paradigm for working on
//! details at a larger scale.
//!
//! Sampling: a sample is kept when the brush moved a tenth of its radius
//! (model units) or the pressure changed by 0.1 since the last kept one;
//! the last held sample always ends the stroke. This keeps ops compact
//! without changing the path the drag warp follows by more than that step.
//!
//! Bad input during a stroke: tracking lost → the stroke pauses, and after
//! [`BrushToolSettings::grace`] s it is committed with the samples so far; a
//! teleport → committed at its last good sample; NaN samples never reach the
//! tool. The orienting hand losing tracking or teleporting lets go of the
//! model where it was.

use crate::math::fm::DetMath as _;
use std::sync::Arc;

use crate::doc::{Create, Document, Edit, ObjectId, ObjectKind, Op, ScriptCommand};
use crate::math::{DVec3, Transform};
use crate::mesh::TriMesh;
use crate::sculpt::mesh_brush::MAX_BRUSH_SAMPLES;
use crate::sculpt::{
    BrushShape, Falloff, MeshBrush, MeshSource, SculptBase, SculptCreate, SculptStroke,
    StrokeSample, StrokeSettings, Warp,
};

use crate::interact::gesture::bimanual::{ModelFrame, OrientGrab};
use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::{Hand, Pose};
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::ctl_input::{cycle, remember, CtlInput, Flick};
use crate::interact::tools::lost_too_long;
use crate::interact::tools::{object_label, BrushPreview, Preview, Tool, ToolContext};

/// Cells across the largest side of a brush made from an object.
pub const MESH_BRUSH_CELLS: f64 = 40.0;
/// Explode / collapse amount per frame, as a fraction of the influence.
pub const EXPLODE_DELTA: f64 = 0.15;

/// A named brush of the preset menu; sizes in world metres.
#[derive(Clone, Debug, PartialEq)]
pub struct BrushPreset {
    /// Menu label.
    pub name: String,
    /// The stroke settings at brush size factor 1 and model scale 1.
    pub settings: StrokeSettings,
}

fn preset(name: &str, brush: BrushShape, influence: f64, warp: Warp, max: f64) -> BrushPreset {
    BrushPreset {
        name: name.to_string(),
        settings: StrokeSettings {
            brush,
            brush_scale: 1.0,
            influence,
            falloff: Falloff::Smooth,
            warp,
            max_edge_rel: max,
            min_edge_rel: max * (2.0 / 7.0),
        },
    }
}

/// Settings of the brush tool.
#[derive(Clone, Debug, PartialEq)]
pub struct BrushToolSettings {
    /// The hand that sculpts; the other one holds the model.
    pub dominant: Hand,
    /// Trigger values above this hold a stroke.
    pub trigger: f64,
    /// Seconds a stroke survives lost tracking before it is committed.
    pub grace: f64,
    /// The brush menu.
    pub presets: Vec<BrushPreset>,
    /// Radius of the sphere `primary` creates (model units).
    pub sphere_radius: f64,
    /// Its target edge length.
    pub sphere_edge: f64,
}

impl Default for BrushToolSettings {
    fn default() -> Self {
        let sphere = |radius| BrushShape::Sphere { radius };
        let d = Warp::Drag;
        Self {
            dominant: Hand::Right,
            trigger: 0.05,
            grace: 0.25,
            presets: vec![
                preset("pull large", sphere(0.07), 0.07, d, 0.1),
                preset("pull", sphere(0.045), 0.045, d, 0.14),
                preset("pull small", sphere(0.03), 0.035, d, 0.2333),
                BrushPreset {
                    name: "whittle".into(),
                    ..preset("", sphere(0.06), 0.03, Warp::Whittle, 0.1167)
                },
                preset(
                    "capsule",
                    BrushShape::Capsule {
                        radius: 0.024,
                        half_length: 0.012,
                    },
                    0.032,
                    d,
                    0.1944,
                ),
                preset(
                    "flat",
                    BrushShape::Ellipsoid {
                        radii: [0.095, 0.04, 0.02],
                    },
                    0.035,
                    d,
                    0.0737,
                ),
                preset("fine", sphere(0.01), 0.015, d, 0.7),
                preset(
                    "groove",
                    BrushShape::Ellipsoid {
                        radii: [0.016, 0.006, 0.005],
                    },
                    0.008,
                    d,
                    0.4375,
                ),
                preset(
                    "fine capsule",
                    BrushShape::Capsule {
                        radius: 0.008,
                        half_length: 0.03,
                    },
                    0.012,
                    d,
                    0.1842,
                ),
                preset(
                    "fine ellipsoid",
                    BrushShape::Ellipsoid {
                        radii: [0.006, 0.01, 0.018],
                    },
                    0.01,
                    d,
                    0.3889,
                ),
                BrushPreset {
                    name: "whittle fine".into(),
                    ..preset("", sphere(0.05), 0.02, Warp::Whittle, 0.14)
                },
                preset(
                    "explode",
                    sphere(0.045),
                    0.045,
                    Warp::Explode {
                        delta: EXPLODE_DELTA,
                    },
                    0.14,
                ),
                preset(
                    "collapse",
                    sphere(0.045),
                    0.045,
                    Warp::Explode {
                        delta: -EXPLODE_DELTA,
                    },
                    0.14,
                ),
            ],
            sphere_radius: 0.1,
            sphere_edge: 0.006,
        }
    }
}

/// A stroke in progress.
#[derive(Clone, Debug)]
struct Stroke {
    id: ObjectId,
    settings: StrokeSettings,
    samples: Vec<StrokeSample>,
    /// The last sample held (kept or not).
    last: StrokeSample,
    /// Minimum spacing of kept samples (model units).
    spacing: f64,
    lost_since: Option<f64>,
    /// The palette's mirror plane at the press (per stroke, like snapping).
    mirror: Option<Box<crate::math::MirrorPlane>>,
}

impl Stroke {
    fn push(&mut self, s: StrokeSample) {
        let keep = match self.samples.last() {
            None => true,
            Some(k) => {
                let d = DVec3::from_array(k.position).distance(DVec3::from_array(s.position));
                d >= self.spacing || (k.pressure - s.pressure).abs() >= 0.1
            }
        };
        if keep {
            self.samples.push(s);
        }
        self.last = s;
    }

    fn op(mut self) -> Option<ScriptCommand> {
        if self.samples.len() == 1 || self.samples.last() != Some(&self.last) {
            self.samples.push(self.last);
        }
        // A stroke starts with one sample, so it has at least two now (a
        // dab held still is two equal samples).
        Some(ScriptCommand::Op(Op::SculptStroke(Edit::new(
            self.id,
            SculptStroke {
                settings: self.settings,
                samples: self.samples,
                mirror: self.mirror,
            },
        ))))
    }
}

/// An object of the document offered as a brush (cached by `update`, since
/// [`Tool::choices`] has no document).
#[derive(Clone, Debug)]
struct BrushSource {
    id: ObjectId,
    label: String,
    mesh: Arc<TriMesh>,
    /// Its mesh's bounding box (model space) and the farthest distance of
    /// a vertex from the box's centre, if it has vertices.
    bounds: Option<((DVec3, DVec3), f64)>,
}

/// A mesh's bounding box and the farthest distance of a vertex from the
/// box's centre: the radius of the ball about the centre that holds it,
/// which is the size a brush made from it has (the grid brush is
/// centred on the box's centre, [`crate::sculpt::BrushShape::size_radius`]).
pub(crate) fn mesh_bounds(mesh: &TriMesh) -> Option<((DVec3, DVec3), f64)> {
    let (lo, hi) = mesh.bbox()?;
    let c = (lo + hi) * 0.5;
    let r = mesh
        .positions
        .iter()
        .map(|p| DVec3::from_array(*p).distance(c))
        .fold(0.0, f64::max);
    Some(((lo, hi), r))
}

/// The mesh brush made from an object with bounding box `lo..hi` whose
/// vertices lie within `extent` of the box's centre, scaled so that ball
/// has radius `radius` (model units): the brush then has the size of the
/// preset it replaces (for a sphere, that preset's sphere), so it refines
/// alike. `influence` (model units) sets the grid's padding. Returns
/// `(brush, scale)`.
pub(crate) fn mesh_brush(
    id: ObjectId,
    ((lo, hi), extent): ((DVec3, DVec3), f64),
    radius: f64,
    influence: f64,
) -> Option<(MeshBrush, f64)> {
    let ext = hi - lo;
    if !(extent.is_finite() && extent > 0.0 && radius > 0.0) {
        return None;
    }
    let scale = radius / extent;
    let side = ext.max_element();
    // Padding: the influence band around the mesh, in the mesh's units,
    // at most half its largest side (beyond the grid the brush uses the
    // nearest sample plus the distance to it).
    let padding = (influence / scale).min(side * 0.5);
    let mut step = side / MESH_BRUSH_CELLS;
    let samples =
        |step: f64| (((ext + 2.0 * padding) / step).ceil() + DVec3::ONE).element_product();
    while samples(step) > MAX_BRUSH_SAMPLES as f64 / 2.0 {
        step *= 1.25;
    }
    Some((
        MeshBrush {
            source: MeshSource::Object { id },
            step,
            padding,
        },
        scale,
    ))
}

/// The newest sculpt object.
fn sculpt_target(doc: &Document) -> Option<ObjectId> {
    doc.objects()
        .filter(|(_, o)| matches!(o.kind, ObjectKind::SculptMesh(_)))
        .map(|(id, _)| id)
        .last()
}

fn frame_of(s: &Similarity) -> ModelFrame {
    ModelFrame {
        pose: Pose::new(s.translate, s.rotate),
        scale: s.scale,
    }
}

fn similarity_of(f: &ModelFrame) -> Similarity {
    Similarity {
        translate: f.pose.position,
        rotate: f.pose.orientation,
        scale: f.scale,
    }
}

/// Paper 4's two-handed sculpting: strokes with pressure, the other hand
/// orienting the model, both hands scaling model and brush.
#[derive(Clone, Debug)]
pub struct BrushTool {
    settings: BrushToolSettings,
    preview: Preview,
    prev: [CtlInput; 2],
    flick: Flick,
    preset: usize,
    size: f64,
    view: Option<ModelFrame>,
    orient: Option<OrientGrab>,
    stroke: Option<Stroke>,
    /// The other objects of the document, for "Brush from".
    sources: Vec<BrushSource>,
    /// The object strokes use as the brush (`None`: the preset's shape).
    brush_from: Option<ObjectId>,
}

impl Default for BrushTool {
    fn default() -> Self {
        Self::new(BrushToolSettings::default())
    }
}

impl BrushTool {
    /// A tool with `settings`.
    pub fn new(settings: BrushToolSettings) -> Self {
        let mut t = Self {
            settings,
            preview: Preview::default(),
            prev: [CtlInput::default(); 2],
            flick: Flick::default(),
            preset: 0,
            size: 1.0,
            view: None,
            orient: None,
            stroke: None,
            sources: Vec::new(),
            brush_from: None,
        };
        t.update_mode();
        t
    }

    /// The brush preset in use.
    pub fn preset(&self) -> Option<&BrushPreset> {
        self.settings.presets.get(self.preset)
    }

    fn update_mode(&mut self) {
        let name = self.preset().map_or("-", |p| p.name.as_str()).to_string();
        self.preview.mode = format!("{name} x{:.3}", self.size);
        if let Some(s) = self.source() {
            self.preview.mode += &format!(" from {}", s.label);
        }
    }

    /// The object chosen as the brush, if it is still in the document.
    fn source(&self) -> Option<&BrushSource> {
        let id = self.brush_from?;
        self.sources.iter().find(|s| s.id == id)
    }

    /// Caches the objects "Brush from" offers: every object but the one
    /// sculpted (boxes recomputed only for meshes that changed).
    fn refresh_sources(&mut self, doc: &Document) {
        let target = sculpt_target(doc);
        let old = std::mem::take(&mut self.sources);
        self.sources = doc
            .objects()
            .filter(|(id, _)| Some(*id) != target)
            .map(|(id, obj)| {
                let label = object_label(id, obj);
                match old
                    .iter()
                    .find(|s| s.id == id && Arc::ptr_eq(&s.mesh, &obj.mesh))
                {
                    Some(s) => BrushSource { label, ..s.clone() },
                    None => BrushSource {
                        id,
                        label,
                        mesh: obj.mesh.clone(),
                        bounds: mesh_bounds(&obj.mesh),
                    },
                }
            })
            .collect();
        if self.brush_from.is_some() && self.source().is_none() {
            self.brush_from = None;
            self.update_mode();
        }
    }

    /// World radius of the brush.
    fn world_radius(&self) -> f64 {
        self.preset()
            .map_or(0.0, |p| p.settings.brush_size() * self.size)
    }

    /// The stroke settings now: preset sizes times the size factor, in
    /// model units of the current view; with the brush's bounding radius
    /// (a mesh brush is sized like its preset).
    fn stroke_settings(&self, view: &ModelFrame) -> Option<(StrokeSettings, f64)> {
        let mut s = self.preset()?.settings.clone();
        let k = self.size / view.scale;
        s.brush_scale *= k;
        s.influence *= k;
        let radius = s.brush_size();
        if let Some(src) = self.source() {
            let (brush, scale) = mesh_brush(src.id, src.bounds?, radius, s.influence)?;
            s.brush = BrushShape::Mesh(brush);
            s.brush_scale = scale;
        }
        Some((s, radius))
    }

    fn orienting(&mut self, inputs: &[CtlInput; 2], view: &mut ModelFrame) {
        let nd = self.settings.dominant.other();
        let (h, d) = (inputs[nd.index()], inputs[self.settings.dominant.index()]);
        let holding = h.tracked && h.grab && !h.teleported;
        match (self.orient.as_mut(), h.grip.filter(|_| holding)) {
            (Some(g), Some(grip)) => {
                let other = (d.tracked && d.grab && self.stroke.is_none())
                    .then_some(d.grip)
                    .flatten()
                    .map(|p| p.position);
                let f = g.frame(&grip, other);
                if f.pose.is_finite() && f.scale.is_finite() && f.scale > 0.0 {
                    *view = f;
                }
            }
            (None, Some(grip)) if !self.prev[nd.index()].grab => {
                self.orient = Some(OrientGrab::new(grip, *view));
            }
            (Some(_), None) => self.orient = None,
            _ => {}
        }
    }

    fn sample(view: &ModelFrame, grip: &Pose, pressure: f64) -> StrokeSample {
        let p = view.to_model(grip.position);
        let q = (view.pose.orientation.inverse() * grip.orientation).normalize();
        StrokeSample {
            position: p.to_array(),
            rotation: q.to_array(),
            pressure: pressure.clamp(0.0, 1.0),
        }
    }

    fn stroking(
        &mut self,
        cx: &ToolContext,
        d: &CtlInput,
        view: &ModelFrame,
    ) -> Option<ScriptCommand> {
        let mut s = self.stroke.take()?;
        if cx.doc.get(s.id).is_err() {
            return None;
        }
        if d.teleported {
            return s.op();
        }
        let Some(grip) = d.grip.filter(|_| d.tracked) else {
            if lost_too_long(&mut s.lost_since, cx.frame.time, self.settings.grace) {
                return s.op();
            }
            self.stroke = Some(s);
            return None;
        };
        s.lost_since = None;
        if d.select <= self.settings.trigger {
            return s.op();
        }
        s.push(Self::sample(view, &grip, d.select));
        self.stroke = Some(s);
        None
    }

    fn idle(
        &mut self,
        cx: &ToolContext,
        inputs: &[CtlInput; 2],
        view: &ModelFrame,
    ) -> Option<ScriptCommand> {
        let dom = self.settings.dominant;
        let d = inputs[dom.index()];
        let target = sculpt_target(cx.doc);
        let pressed = d.select > self.settings.trigger
            && self.prev[dom.index()].select <= self.settings.trigger;
        if d.tracked && !d.grab && pressed {
            if let (Some(id), Some(grip), Some((settings, radius))) =
                (target, d.grip, self.stroke_settings(view))
            {
                // Sample spacing: a tenth of the brush radius in model units.
                let spacing = 0.1 * radius;
                let first = Self::sample(view, &grip, d.select);
                self.stroke = Some(Stroke {
                    id,
                    settings,
                    samples: vec![first],
                    last: first,
                    spacing,
                    lost_since: None,
                    mirror: cx.snap.mirror.map(|m| Box::new(m.plane)),
                });
                return None;
            }
        }
        for hand in [dom, dom.other()] {
            let (now, was) = (inputs[hand.index()], self.prev[hand.index()]);
            if !now.tracked {
                continue;
            }
            if now.menu && !was.menu {
                let dir = if hand == Hand::Left { -1 } else { 1 };
                self.preset = cycle(self.preset, dir, self.settings.presets.len());
                self.update_mode();
            }
            if let Some(k) = self.flick.fired(hand, 1, &now) {
                self.size = (self.size * 1.25f64.fpowi(k)).clamp(0.1, 10.0);
                self.update_mode();
            }
            if now.primary && !was.primary && target.is_none() {
                return Some(ScriptCommand::Op(Op::SculptCreate(Create(SculptCreate {
                    base: SculptBase::Sphere {
                        radius: self.settings.sphere_radius,
                        edge_length: self.settings.sphere_edge,
                    },
                    transform: Transform::default(),
                }))));
            }
            if let Some(k) = self.flick.fired(hand, 0, &now) {
                return Some(if k < 0 {
                    ScriptCommand::Undo
                } else {
                    ScriptCommand::Redo
                });
            }
        }
        None
    }
}

impl Tool for BrushTool {
    fn name(&self) -> &'static str {
        "sculpt"
    }

    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand> {
        self.refresh_sources(cx.doc);
        let inputs = Hand::BOTH.map(|h| CtlInput::read(cx, h));
        let mut view = self.view.unwrap_or_else(|| frame_of(cx.model));
        self.orienting(&inputs, &mut view);
        let d = inputs[self.settings.dominant.index()];
        let out = if self.stroke.is_some() {
            self.stroking(cx, &d, &view)
        } else {
            self.idle(cx, &inputs, &view)
        };
        self.view = Some(view);
        self.preview.view = Some(similarity_of(&view));
        self.preview.highlighted = sculpt_target(cx.doc);
        self.preview.sketch = self.stroke.as_ref().map_or_else(Vec::new, |s| {
            s.samples
                .iter()
                .map(|p| DVec3::from_array(p.position))
                .collect()
        });
        *self.preview.brush_mut() = d.grip.filter(|_| d.tracked).map(|g| BrushPreview {
            position: g.position,
            radius: self.world_radius(),
            pressure: d.select,
            stroking: self.stroke.is_some(),
        });
        remember(&mut self.prev, &inputs);
        out
    }

    fn mirror_centre(&self, doc: &Document) -> Option<DVec3> {
        let id = sculpt_target(doc)?;
        Some(DVec3::from_array(doc.get(id).ok()?.transform().translate))
    }

    fn cancel(&mut self) {
        self.stroke = None;
        self.orient = None;
        self.preview.sketch.clear();
    }

    fn preview(&self) -> &Preview {
        &self.preview
    }

    fn choices(&self) -> Vec<ChoiceGroup> {
        vec![
            ChoiceGroup {
                name: "Brush",
                options: self
                    .settings
                    .presets
                    .iter()
                    .map(|p| p.name.clone())
                    .collect(),
                active: self.preset,
            },
            ChoiceGroup {
                name: "Size",
                options: SIZES.iter().map(|s| format!("x{s}")).collect(),
                active: SIZES
                    .iter()
                    .position(|s| *s == self.size)
                    .unwrap_or(usize::MAX),
            },
            ChoiceGroup {
                name: "Brush from",
                options: std::iter::once("preset".to_string())
                    .chain(self.sources.iter().map(|s| s.label.clone()))
                    .collect(),
                active: self
                    .brush_from
                    .and_then(|id| self.sources.iter().position(|s| s.id == id))
                    .map_or(0, |k| k + 1),
            },
        ]
    }

    fn choose(&mut self, _doc: &Document, group: usize, option: usize) -> Option<ScriptCommand> {
        match group {
            0 if option < self.settings.presets.len() => self.preset = option,
            1 if option < SIZES.len() => self.size = SIZES[option],
            2 if option == 0 => self.brush_from = None,
            2 if option <= self.sources.len() => {
                self.brush_from = Some(self.sources[option - 1].id);
            }
            _ => return None,
        }
        self.update_mode();
        None
    }
}

/// Brush size factors the palette offers (the stick flick scales by 1.25
/// in between).
const SIZES: [f64; 6] = [0.5, 0.8, 1.0, 1.25, 1.6, 2.0];
