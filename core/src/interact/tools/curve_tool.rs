//! [`CurveNetworkTool`]: the controller interface of paper 3 (variational
//! curve styling, §6): draw curves in space, edit them with the smoother,
//! sharpener and puller chosen by the pointer pose (Table 1), fill loops,
//! undo and redo. Registered for traces as `"curve"`.
//!
//! The dominant hand (right by default) holds the pen; its tip is the aim
//! pose's position plus [`CurveToolSettings::tip_offset`] along the aim.
//! The other hand holds a plane.
//!
//! | input (dominant hand)   | action                                      |
//! |-------------------------|---------------------------------------------|
//! | trigger held            | draw, or apply the tool chosen at the press |
//! | `primary` (A)           | fill every loop found (`curve_fill_auto`), or the pointed loop (`curve_fill_loop`) when the palette says so |
//! | `secondary` (B)         | delete the pointed curve (Table 1 bands)    |
//! | stick flick ← / → (either hand) | undo / redo                         |
//!
//! | input (other hand)      | plane (through the grip, normal = its aim)  |
//! |-------------------------|---------------------------------------------|
//! | `grab` held at the press | drawing plane: samples are projected on it |
//! | trigger held at the press | symmetry plane: the stroke is mirrored    |
//!
//! At the trigger's press edge, [`crate::styling::select::select_in_network`]
//! applies Table 1 to the curve nearest to the tip: `d < 2 cm` and the
//! pointer across the curve (60°..120°) pulls the pointed point (puller),
//! `2..4 cm` across sharpens, `2..4 cm` along (≤ 30° or ≥ 150°) smooths. The
//! choice holds until release. Anything else (attach: `d < 2 cm` along;
//! far away; between the angle bands) draws a new curve, which the network
//! snaps to the curves it passes within [`CurveToolSettings::snap_tol`].
//! The palette's "Trigger" group can force one tool instead ("auto" is
//! Table 1). Forced smooth, sharpen and pull act on the pointed *surface*
//! (paper 3 §4: `surface_smooth`, `surface_sharpen`, `surface_pull` at the
//! pointed `(u0, v0)`) when a patch is at least [`SURFACE_MARGIN`] nearer
//! to the tip than any curve, and on the nearest curve otherwise; "auto"
//! never edits a surface, so a stroke started over a patch still draws.
//! Forced "attract" draws the pointed curve towards what the other hand
//! holds at the press (§2.2, `curve_attract`, local around the pointed
//! point): its grip point, the line along its aim when its trigger is
//! held, the plane through its grip normal to its aim when its grip is
//! held; one frame of attraction per frame held.
//!
//! Each held application is one op carrying its sampled path: `curve_draw`
//! with the tip samples (model space, at least `min_spacing` apart),
//! `curve_pull` / `curve_smooth` / `curve_sharpen` with the tip per frame.
//! The first press with no network in the document emits
//! `curve_network_create` (the stroke goes on; its curve goes to the new
//! network at release). A mirrored stroke is a second `curve_draw` on the
//! next frame (at most one command per frame). The planes are taken at the
//! press and held for the stroke, so a wobbling hand does not bend it.
//!
//! Bad input during a stroke (as [`crate::interact::ObjectTool`]): NaN poses never
//! reach the tool (the sanitizer drops them; the frame adds no sample);
//! tracking lost freezes the stroke and cancels it (nothing emitted) after
//! [`CurveToolSettings::grace`] seconds; a teleport commits the stroke as
//! it was before the jump.
//!
//! Preview each frame: the pen ray, the sketch being drawn (model space),
//! and [`CurvePreview`] (the mode the trigger would start or is running,
//! the pointed curve point, the planes, the held path).

use crate::doc::{Create, Document, Edit, ObjectId, ObjectKind, Op, ScriptCommand};
use crate::math::DVec3;
use crate::styling::curve::FitMode;
use crate::styling::select::{
    nearest_loop, nearest_patch_point, select_in_network, CurveTool as TableTool, PatchPoint,
};
use crate::styling::surface::SurfaceWeights;
use crate::styling::tools::{PullParams, SharpenLimits, SmoothParams, MAX_FRAMES};
use crate::styling::CurveNetwork;
use crate::styling::{
    AttractParams, Attractor, CurveAttract, CurveDelete, CurveDraw, CurveDrawInFrame,
    CurveFillAuto, CurveFillLoop, CurveId, CurveNetworkCreate, CurvePull, CurveSharpen,
    CurveSmooth, ModelingFrame, PatchId, SurfaceEquilibrium, SurfacePull, SurfaceSharpen,
    SurfaceSmooth,
};

use crate::interact::input::{Hand, Pose};
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::lost_too_long;
use crate::interact::tools::{Preview, PreviewRay, Tool, ToolContext, ToolPreview};

/// Settings of the curve tool. Lengths are metres in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveToolSettings {
    /// The hand holding the pen.
    pub dominant: Hand,
    /// Pen tip distance along the aim from the aim pose.
    pub tip_offset: f64,
    /// Length of the drawn ray.
    pub reach: f64,
    /// Seconds a stroke survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Smallest spacing of drawn samples (closer ones are skipped).
    pub min_spacing: f64,
    /// How drawn samples become a curve.
    pub fit: FitMode,
    /// Arc-length resampling of drawn samples before fitting.
    pub resample: Option<f64>,
    /// Closest approach under which a new curve joins an existing one.
    pub snap_tol: f64,
    /// Mesh samples per patch side of a new network.
    pub resolution: u32,
    /// Surface-tool control points per patch side of a new network.
    pub surface_n: u32,
    /// Smoother weights.
    pub smooth: SmoothParams,
    /// Sharpener weights.
    pub sharpen: SmoothParams,
    /// Where the sharpener stops.
    pub sharpen_limits: SharpenLimits,
    /// Puller weights.
    pub pull: PullParams,
    /// Attractor weights (`curve_attract`).
    pub attract: AttractParams,
    /// Surface tools' internal energy weights.
    pub surface: SurfaceWeights,
    /// Surface smoother's factor on `w_q` per frame, in (0, 1).
    pub surface_smooth_f: f64,
    /// Surface sharpener's factor on `w_q` per frame, in (1, 2], and its cap.
    pub surface_sharpen: (f64, f64),
    /// How far from the pen tip the surface smoother and sharpener act
    /// (the gaussian radius of their weight on the patch), metres in the
    /// model.
    pub surface_radius: f64,
    /// The most the surface smoother and sharpener move any point of the
    /// patch in one frame (metres in the model): 1 s held changes a
    /// patch by at most this times the frame rate.
    pub surface_max_step: f64,
    /// Surface puller's attractor weight.
    pub surface_wpp: f64,
}

impl Default for CurveToolSettings {
    fn default() -> Self {
        Self {
            dominant: Hand::Right,
            tip_offset: 0.0,
            reach: 5.0,
            grace: 0.25,
            min_spacing: 0.003,
            fit: FitMode::Approximate { tol: 0.001 },
            resample: Some(0.01),
            snap_tol: 0.02,
            resolution: 24,
            surface_n: 8,
            smooth: SmoothParams {
                wb: 1e-6,
                ws: 0.0,
                wp0: 1.0,
                wp1: 0.0,
                wp2: 0.0,
                alpha: 20.0,
            },
            sharpen: SmoothParams {
                wb: 2e-6,
                ws: 0.0,
                wp0: 1.0,
                wp1: 0.0,
                wp2: 3e-6,
                alpha: 30.0,
            },
            sharpen_limits: SharpenLimits {
                max_step: 0.004,
                max_growth: 4.0,
            },
            pull: PullParams {
                wpp: 200.0,
                wp0: 1.0,
                wp1: 0.001,
            },
            // 3% of the way per frame: about 2/3 of the way in a 0.5 s
            // hold at 72 Hz, so the user sees it move and can stop.
            attract: AttractParams {
                weight: 0.03,
                wp0: 1.0,
                wp1: 0.0,
                alpha: 20.0,
                keep_ends: false,
            },
            // The values of the styled fixtures (tests/data/lampshade.jsonl).
            surface: SurfaceWeights { wb: 1.0, ws: 0.0 },
            // Both act within about 5 cm of the pen and move the patch at
            // most 0.25 mm a frame: 1.8 cm in a held second at 72 Hz, 3 cm
            // at 120 Hz (issue 33: 1.2 per frame up to 4 times took a
            // 4.7 cm bump to 18.4 cm in one second, and stronger settings
            // made it overhang). Where the pen is, the smoother takes the
            // patch 0.95 of the way to its minimal shape in a second at
            // 72 Hz, the sharpener away from it by up to 3 times.
            surface_smooth_f: 0.96,
            surface_sharpen: (1.03, 3.0),
            surface_radius: 0.05,
            surface_max_step: 0.000_25,
            surface_wpp: 2000.0,
        }
    }
}

/// A plane held by the non-dominant hand (model space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawPlane {
    /// A point on it (the grip position).
    pub origin: DVec3,
    /// Unit normal (the hand's aim direction).
    pub normal: DVec3,
}

impl DrawPlane {
    fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * (p - self.origin).dot(self.normal)
    }

    fn mirror(&self, p: DVec3) -> DVec3 {
        crate::math::reflect(p, self.origin, self.normal)
    }
}

/// A patch is this much nearer to the tip than every curve (metres)
/// before a forced smooth, sharpen or pull acts on the surface.
pub const SURFACE_MARGIN: f64 = 0.01;

/// A surface tool of paper 3 §4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceTool {
    /// `surface_smooth`.
    Smooth,
    /// `surface_sharpen`.
    Sharpen,
    /// `surface_pull` at the pointed point.
    Pull,
}

/// What the trigger starts (idle) or is doing (held).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveMode {
    /// Draw a new curve.
    Draw,
    /// A Table 1 tool on the pointed curve (`AttachNewCurve` draws).
    Edit(TableTool),
    /// `curve_attract` on the pointed curve.
    Attract,
    /// A surface tool on the pointed patch.
    Surface(SurfaceTool),
}

impl CurveMode {
    /// What the headset shows next to the pen.
    pub fn label(&self) -> &'static str {
        match self {
            CurveMode::Draw | CurveMode::Edit(TableTool::AttachNewCurve) => "draw",
            CurveMode::Edit(TableTool::SmoothSegment) => "smooth curve",
            CurveMode::Edit(TableTool::SharpenSegment) => "sharpen curve",
            CurveMode::Edit(TableTool::EditDataPoint) => "pull curve",
            CurveMode::Attract => "attract curve",
            CurveMode::Surface(SurfaceTool::Smooth) => "smooth surface",
            CurveMode::Surface(SurfaceTool::Sharpen) => "sharpen surface",
            CurveMode::Surface(SurfaceTool::Pull) => "pull surface",
        }
    }
}

/// The patch point the pen points at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchTarget {
    /// The network.
    pub network: ObjectId,
    /// The patch point (model space; distance in model units).
    pub at: PatchPoint,
    /// Tip distance to it (metres).
    pub distance: f64,
}

/// The curve point the pen points at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveTarget {
    /// The network.
    pub network: ObjectId,
    /// The curve index.
    pub curve: usize,
    /// Parameter of the pointed point (t0).
    pub t0: f64,
    /// The pointed point (model space).
    pub point: DVec3,
    /// Tip distance to it (metres).
    pub distance: f64,
    /// Angle between the pen and the curve tangent (degrees).
    pub angle_deg: f64,
    /// What Table 1 selects there.
    pub tool: Option<TableTool>,
}

/// What a forced attract draws the curve towards: held by the other hand.
fn attractor_of(cx: &ToolContext, pen: &Pen) -> Option<Attractor> {
    let (grip, aim) = (pen.grip?, pen.aim?);
    let to_model = cx.model.inverse();
    let a = to_model.apply(grip.position).to_array();
    let dir = to_model.apply_dir(aim.forward()).normalize_or_zero();
    if dir == DVec3::ZERO {
        return None;
    }
    Some(if pen.grab {
        Attractor::Plane {
            a,
            normal: dir.to_array(),
        }
    } else if pen.trigger {
        Attractor::Line {
            a,
            dir: dir.to_array(),
        }
    } else {
        Attractor::Point { p: a }
    })
}

/// The curve tool's preview state.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvePreview {
    /// The pen tip (model space), when tracked.
    pub tip: Option<DVec3>,
    /// The mode a press would start, or the held stroke's mode.
    pub mode: Option<CurveMode>,
    /// The pointed curve point (for a held edit: as at the press).
    pub target: Option<CurveTarget>,
    /// The pointed patch point, when a forced surface tool would act on it.
    pub patch: Option<PatchTarget>,
    /// The drawing plane in use or offered.
    pub plane: Option<DrawPlane>,
    /// The symmetry plane in use or offered.
    pub symmetry: Option<DrawPlane>,
    /// The pointer path of a held edit (model space).
    pub path: Vec<DVec3>,
    /// A stroke is frozen by lost tracking.
    pub frozen: bool,
}

/// One hand's controller this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Pen {
    tracked: bool,
    aim: Option<Pose>,
    grip: Option<Pose>,
    trigger: bool,
    grab: bool,
    primary: bool,
    secondary: bool,
    stick_x: f64,
    teleported: bool,
}

fn read_pen(cx: &ToolContext, hand: Hand) -> Pen {
    let Some(c) = cx.frame.controller(hand) else {
        return Pen::default();
    };
    let b = c.buttons.unwrap_or_default();
    Pen {
        tracked: c.aim.is_some() && c.buttons.is_some(),
        aim: c.aim,
        grip: c.grip,
        trigger: b.select > 0.5,
        grab: b.grab > 0.5,
        primary: b.primary,
        secondary: b.secondary,
        stick_x: b.stick[0],
        teleported: c.teleported,
    }
}

/// A held trigger.
#[derive(Clone, Debug)]
struct Stroke {
    mode: CurveMode,
    target: Option<CurveTarget>,
    patch: Option<PatchTarget>,
    /// A forced attract's attractor, taken at the press.
    attractor: Option<Attractor>,
    plane: Option<DrawPlane>,
    symmetry: Option<DrawPlane>,
    /// Tip samples (model space).
    path: Vec<DVec3>,
    /// The other hand's modeling frame at each sample (model space), when
    /// drawing in the held frame (paper 3 §5.4).
    frames: Vec<ModelingFrame>,
    lost_since: Option<f64>,
}

/// Draw, smooth, sharpen, pull, fill, delete, undo, redo on curve networks.
#[derive(Clone, Debug)]
pub struct CurveNetworkTool {
    settings: CurveToolSettings,
    preview: Preview,
    prev: [Pen; 2],
    stick_armed: [bool; 2],
    stroke: Option<Stroke>,
    /// Commands waiting for a frame of their own (a mirrored stroke).
    pending: std::collections::VecDeque<ScriptCommand>,
    /// The palette's trigger mode (index into [`MODES`]; 0: Table 1).
    forced: usize,
    /// Strokes are drawn in the modeling frame the other hand holds
    /// (paper 3 §5.4, `curve_draw_in_frame`): the network moves with the
    /// hand while drawing. The palette's "Draw in: left hand".
    in_frame: bool,
    /// `primary` fills the pointed loop (`curve_fill_loop`) instead of
    /// every loop. The palette's "A fills".
    fill_pointed: bool,
}

impl Default for CurveNetworkTool {
    fn default() -> Self {
        Self::new(CurveToolSettings::default())
    }
}

/// The network the tool works on: the first curve network of the document.
fn network(doc: &Document) -> Option<(ObjectId, &CurveNetwork)> {
    doc.objects().find_map(|(id, o)| match &o.kind {
        ObjectKind::CurveNetwork(n) => Some((id, n)),
        #[allow(unreachable_patterns)]
        _ => None,
    })
}

fn arr(p: &[DVec3]) -> Vec<[f64; 3]> {
    p.iter().map(|v| v.to_array()).collect()
}

impl CurveNetworkTool {
    /// A tool with `settings`.
    pub fn new(settings: CurveToolSettings) -> Self {
        Self {
            settings,
            preview: Preview {
                tool: ToolPreview::Curve(CurvePreview::default()),
                ..Preview::default()
            },
            prev: [Pen::default(); 2],
            stick_armed: [true; 2],
            stroke: None,
            pending: Default::default(),
            forced: 0,
            in_frame: false,
            fill_pointed: false,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &CurveToolSettings {
        &self.settings
    }

    fn cp(&mut self) -> &mut CurvePreview {
        self.preview.curve_mut()
    }

    /// The pen tip and direction in model space.
    fn tip(&self, cx: &ToolContext, pen: &Pen) -> Option<(DVec3, DVec3)> {
        let aim = pen.aim?;
        let to_model = cx.model.inverse();
        let dir = aim.forward();
        let tip = aim.position + dir * self.settings.tip_offset;
        Some((to_model.apply(tip), to_model.apply_dir(dir)))
    }

    /// The plane the other hand offers now (model space).
    fn held_plane(cx: &ToolContext, pen: &Pen) -> Option<DrawPlane> {
        let (grip, aim) = (pen.grip?, pen.aim?);
        let to_model = cx.model.inverse();
        let normal = to_model.apply_dir(aim.forward()).normalize_or_zero();
        (normal != DVec3::ZERO).then_some(DrawPlane {
            origin: to_model.apply(grip.position),
            normal,
        })
    }

    /// The modeling frame the other hand holds: its grip, in model space.
    fn held_frame(cx: &ToolContext, pen: &Pen) -> Option<ModelingFrame> {
        let grip = pen.grip?;
        let to_model = cx.model.inverse();
        Some(ModelingFrame::new(
            to_model.apply(grip.position),
            (to_model.rotate * grip.orientation).normalize(),
        ))
    }

    fn target(cx: &ToolContext, tip: DVec3, dir: DVec3) -> Option<CurveTarget> {
        let (network, net) = network(cx.doc)?;
        let (curve, s) = select_in_network(net, tip, dir, cx.model.scale)?;
        Some(CurveTarget {
            network,
            curve,
            t0: s.t,
            point: net.curve(curve).ok()?.point(s.t),
            distance: s.distance * cx.model.scale,
            angle_deg: s.angle_deg,
            tool: s.tool,
        })
    }

    /// The patch a forced smooth, sharpen or pull would act on: one
    /// [`SURFACE_MARGIN`] nearer to the tip than the pointed curve. Only
    /// searched in those modes (the search samples every patch).
    fn patch_target(
        &self,
        cx: &ToolContext,
        tip: DVec3,
        curve: Option<&CurveTarget>,
    ) -> Option<PatchTarget> {
        let forced = MODES.get(self.forced).and_then(|m| m.1);
        if !matches!(forced, Some(CurveMode::Edit(_))) {
            return None;
        }
        let (network, net) = network(cx.doc)?;
        let at = nearest_patch_point(net, tip)?;
        let distance = at.distance * cx.model.scale;
        let nearer = curve.is_none_or(|c| distance + SURFACE_MARGIN < c.distance);
        nearer.then_some(PatchTarget {
            network,
            at,
            distance,
        })
    }

    /// What the trigger starts at `target` (or `patch`): the palette's
    /// forced mode, or Table 1's choice by distance and angle ("auto").
    fn mode_of(&self, target: Option<&CurveTarget>, patch: Option<&PatchTarget>) -> CurveMode {
        let forced = match MODES.get(self.forced).map(|m| m.1) {
            Some(Some(CurveMode::Draw)) => return CurveMode::Draw,
            Some(Some(CurveMode::Attract)) if target.is_some() => return CurveMode::Attract,
            Some(Some(CurveMode::Attract)) => return CurveMode::Draw,
            Some(Some(CurveMode::Edit(t))) => Some(t),
            _ => None,
        };
        if let (Some(t), Some(_)) = (forced, patch) {
            return CurveMode::Surface(match t {
                TableTool::SmoothSegment => SurfaceTool::Smooth,
                TableTool::SharpenSegment => SurfaceTool::Sharpen,
                _ => SurfaceTool::Pull,
            });
        }
        if let (Some(t), Some(_)) = (forced, target) {
            return CurveMode::Edit(t);
        }
        match target.and_then(|t| t.tool) {
            Some(
                t @ (TableTool::EditDataPoint
                | TableTool::SharpenSegment
                | TableTool::SmoothSegment),
            ) => CurveMode::Edit(t),
            _ => CurveMode::Draw,
        }
    }

    fn idle(&mut self, cx: &ToolContext, pens: &[Pen; 2]) -> Option<ScriptCommand> {
        let d = self.settings.dominant.index();
        let o = self.settings.dominant.other().index();
        let (now, was) = (pens[d], self.prev[d]);
        let tip = self.tip(cx, &now);
        let target = tip.and_then(|(p, dir)| Self::target(cx, p, dir));
        let patch = tip.and_then(|(p, _)| self.patch_target(cx, p, target.as_ref()));
        let other = pens[o];
        let offered = Self::held_plane(cx, &other);
        let plane = offered.filter(|_| other.grab);
        // The held plane while the off trigger is held, else the palette's.
        let symmetry = offered
            .filter(|_| other.trigger && !other.grab)
            .or_else(|| {
                cx.snap.mirror.map(|m| DrawPlane {
                    origin: DVec3::from_array(m.plane.point),
                    normal: DVec3::from_array(m.plane.normal),
                })
            });
        self.preview.highlighted = target
            .filter(|t| t.tool.is_some())
            .map(|t| t.network)
            .or(patch.map(|p| p.network));
        {
            let mode = self.mode_of(target.as_ref(), patch.as_ref());
            self.preview.mode = tip.map_or("", |_| mode.label()).to_string();
            let cp = self.cp();
            cp.tip = tip.map(|t| t.0);
            cp.target = target;
            cp.patch = patch;
            cp.mode = tip.map(|_| mode);
            cp.plane = plane;
            cp.symmetry = symmetry;
            cp.path.clear();
            cp.frozen = false;
        }
        if !now.tracked {
            return None;
        }
        if now.trigger && !was.trigger {
            let (p, _) = tip?;
            let mode = self.mode_of(target.as_ref(), patch.as_ref());
            let start = match mode {
                CurveMode::Draw => plane.map_or(p, |pl| pl.project(p)),
                _ => p,
            };
            let attractor = match mode {
                CurveMode::Attract => Some(attractor_of(cx, &other)?),
                _ => None,
            };
            self.stroke = Some(Stroke {
                mode,
                target,
                patch: patch.filter(|_| matches!(mode, CurveMode::Surface(_))),
                attractor,
                plane: plane.filter(|_| mode == CurveMode::Draw),
                symmetry: symmetry.filter(|_| mode == CurveMode::Draw),
                path: vec![start],
                frames: Vec::new(),
                lost_since: None,
            });
            if let Some(s) = self.stroke.as_mut() {
                if self.in_frame && mode == CurveMode::Draw {
                    s.frames.extend(Self::held_frame(cx, &other));
                    if s.frames.is_empty() {
                        // No frame to draw in: the left hand is not tracked.
                        self.stroke = None;
                        self.show_stroke();
                        return None;
                    }
                }
            }
            self.show_stroke();
            if network(cx.doc).is_none() {
                return Some(ScriptCommand::Op(Op::CurveNetworkCreate(Create(
                    CurveNetworkCreate {
                        resolution: self.settings.resolution,
                        surface_n: self.settings.surface_n,
                    },
                ))));
            }
            return None;
        }
        if now.primary && !was.primary {
            if let Some((id, net)) = network(cx.doc) {
                if self.fill_pointed {
                    let loops = net.find_loops();
                    let (p, _) = tip?;
                    let pieces = nearest_loop(net, &loops, p)?.clone();
                    return Some(ScriptCommand::Op(Op::CurveFillLoop(Edit::new(
                        id,
                        CurveFillLoop { pieces },
                    ))));
                }
                if !net.find_loops().is_empty() {
                    return Some(ScriptCommand::Op(Op::CurveFillAuto(Edit::new(
                        id,
                        CurveFillAuto {},
                    ))));
                }
            }
        }
        if now.secondary && !was.secondary {
            if let Some(t) = target.filter(|t| t.tool.is_some()) {
                return Some(ScriptCommand::Op(Op::CurveDelete(Edit::new(
                    t.network,
                    CurveDelete {
                        curve: CurveId(t.curve),
                    },
                ))));
            }
        }
        None
    }

    fn show_stroke(&mut self) {
        let Some(s) = self.stroke.clone() else {
            self.preview.sketch.clear();
            return;
        };
        let draw = s.mode == CurveMode::Draw;
        self.preview.sketch = if draw { s.path.clone() } else { Vec::new() };
        self.preview.mode = s.mode.label().to_string();
        let cp = self.cp();
        cp.mode = Some(s.mode);
        cp.target = s.target;
        cp.patch = s.patch;
        cp.plane = s.plane;
        cp.symmetry = s.symmetry;
        cp.path = if draw { Vec::new() } else { s.path };
        cp.frozen = s.lost_since.is_some();
    }

    fn stroking(&mut self, cx: &ToolContext, pens: &[Pen; 2]) -> Option<ScriptCommand> {
        let mut s = self.stroke.take()?;
        let now = pens[self.settings.dominant.index()];
        let t = cx.frame.time;
        // A teleport: commit what was drawn before the jump.
        if now.teleported {
            return self.commit(cx, s);
        }
        let tip = self.tip(cx, &now).filter(|_| now.tracked);
        let Some((p, _)) = tip else {
            if lost_too_long(&mut s.lost_since, t, self.settings.grace) {
                self.stroke = None;
                self.show_stroke();
                return None;
            }
            self.stroke = Some(s);
            self.show_stroke();
            return None;
        };
        s.lost_since = None;
        if !now.trigger {
            return self.commit(cx, s);
        }
        match s.mode {
            CurveMode::Draw if !s.frames.is_empty() => {
                // In the held frame: raw tip samples, each with the frame as
                // it is now (the op projects and maps them).
                let other = pens[self.settings.dominant.other().index()];
                let last = s.path[s.path.len() - 1];
                if (p - last).length() * cx.model.scale >= self.settings.min_spacing {
                    if let Some(f) = Self::held_frame(cx, &other) {
                        s.path.push(p);
                        s.frames.push(f);
                    }
                }
            }
            CurveMode::Draw => {
                let q = s.plane.map_or(p, |pl| pl.project(p));
                let last = s.path[s.path.len() - 1];
                if (q - last).length() * cx.model.scale >= self.settings.min_spacing {
                    s.path.push(q);
                }
            }
            CurveMode::Edit(_) | CurveMode::Attract | CurveMode::Surface(_) => {
                if s.path.len() < MAX_FRAMES {
                    s.path.push(p);
                }
            }
        }
        self.stroke = Some(s);
        self.show_stroke();
        None
    }

    /// The op of a finished stroke (`None` when it is too short or there
    /// is no network to put it in).
    fn commit(&mut self, cx: &ToolContext, s: Stroke) -> Option<ScriptCommand> {
        self.stroke = None;
        self.show_stroke();
        let (id, net) = network(cx.doc)?;
        let path = arr(&s.path);
        if let Some(op) = self.commit_other(id, net, &s, &path) {
            return op.map(ScriptCommand::Op);
        }
        let op = match (s.mode, s.target) {
            (CurveMode::Draw, _) if !s.frames.is_empty() => {
                if s.path.len() < 4 {
                    return None;
                }
                Op::CurveDrawInFrame(CurveDrawInFrame {
                    id,
                    samples: path,
                    frames: s.frames,
                    onto_plane: s.plane.is_some(),
                    mirror: s.symmetry.is_some(),
                    fit: self.settings.fit,
                    resample: self.settings.resample,
                    snap_tol: self.settings.snap_tol,
                })
            }
            (CurveMode::Draw, _) => {
                if s.path.len() < 4 {
                    return None;
                }
                if let Some(m) = s.symmetry {
                    let mirrored: Vec<DVec3> = s.path.iter().map(|p| m.mirror(*p)).collect();
                    self.pending
                        .push_back(ScriptCommand::Op(Op::CurveDraw(self.draw(id, &mirrored))));
                }
                Op::CurveDraw(self.draw(id, &s.path))
            }
            (CurveMode::Edit(tool), Some(target)) => {
                if target.network != id || net.curve(target.curve).is_err() {
                    return None;
                }
                let curve = CurveId(target.curve);
                match tool {
                    TableTool::EditDataPoint => Op::CurvePull(Edit::new(
                        id,
                        CurvePull {
                            curve,
                            params: self.settings.pull,
                            path,
                        },
                    )),
                    TableTool::SharpenSegment => Op::CurveSharpen(Edit::new(
                        id,
                        CurveSharpen {
                            curve,
                            params: self.settings.sharpen,
                            limits: self.settings.sharpen_limits,
                            path,
                        },
                    )),
                    TableTool::SmoothSegment => Op::CurveSmooth(Edit::new(
                        id,
                        CurveSmooth {
                            curve,
                            params: self.settings.smooth,
                            path,
                        },
                    )),
                    TableTool::AttachNewCurve => return None,
                }
            }
            (CurveMode::Edit(_), None) | (CurveMode::Attract | CurveMode::Surface(_), _) => {
                return None
            }
        };
        Some(ScriptCommand::Op(op))
    }

    /// The op of a finished attract or surface stroke (`Some(None)`: that
    /// kind of stroke, nothing to emit; `None`: another kind).
    fn commit_other(
        &self,
        id: ObjectId,
        net: &CurveNetwork,
        s: &Stroke,
        path: &[[f64; 3]],
    ) -> Option<Option<Op>> {
        let st = &self.settings;
        match s.mode {
            CurveMode::Attract => Some((|| {
                let t = s.target.filter(|t| t.network == id)?;
                net.curve(t.curve).ok()?;
                Some(Op::CurveAttract(Edit::new(
                    id,
                    CurveAttract {
                        curve: CurveId(t.curve),
                        attractor: s.attractor?,
                        params: st.attract,
                        at: path.first().copied(),
                        frames: path.len() as u32,
                    },
                )))
            })()),
            CurveMode::Surface(tool) => Some((|| {
                let t = s.patch.filter(|t| t.network == id)?;
                net.patch(t.at.patch).ok()?;
                let patch = PatchId(t.at.patch);
                let eq = |f: f64, wq_max: f64| SurfaceEquilibrium {
                    patch,
                    weights: st.surface,
                    f,
                    wq_max,
                    path: path.to_vec(),
                    radius: Some(st.surface_radius),
                    max_step: Some(st.surface_max_step),
                };
                Some(match tool {
                    SurfaceTool::Smooth => Op::SurfaceSmooth(Edit::new(
                        id,
                        SurfaceSmooth(eq(st.surface_smooth_f, 1.0)),
                    )),
                    SurfaceTool::Sharpen => Op::SurfaceSharpen(Edit::new(
                        id,
                        SurfaceSharpen(eq(st.surface_sharpen.0, st.surface_sharpen.1)),
                    )),
                    SurfaceTool::Pull => Op::SurfacePull(Edit::new(
                        id,
                        SurfacePull {
                            patch,
                            weights: st.surface,
                            wpp: st.surface_wpp,
                            u0: t.at.u,
                            v0: t.at.v,
                            path: path.to_vec(),
                        },
                    )),
                })
            })()),
            _ => None,
        }
    }

    fn draw(&self, id: ObjectId, samples: &[DVec3]) -> Edit<CurveDraw> {
        Edit::new(
            id,
            CurveDraw {
                samples: arr(samples),
                fit: self.settings.fit,
                resample: self.settings.resample,
                snap_tol: self.settings.snap_tol,
            },
        )
    }

    /// Undo / redo by a stick flick of either hand (not while stroking).
    fn flick(&mut self, pens: &[Pen; 2]) -> Option<ScriptCommand> {
        for hand in [Hand::Right, Hand::Left] {
            let i = hand.index();
            let x = pens[i].stick_x;
            if !pens[i].tracked {
                continue;
            }
            if self.stick_armed[i] && x.abs() > 0.8 {
                self.stick_armed[i] = false;
                return Some(if x < 0.0 {
                    ScriptCommand::Undo
                } else {
                    ScriptCommand::Redo
                });
            }
            if x.abs() < 0.3 {
                self.stick_armed[i] = true;
            }
        }
        None
    }

    fn ray(&mut self, pens: &[Pen; 2]) {
        let reach = self.settings.reach;
        let d = self.settings.dominant;
        self.preview.rays = [None, None];
        if let Some(aim) = pens[d.index()].aim {
            self.preview.rays[d.index()] = Some(PreviewRay {
                origin: aim.position,
                dir: aim.forward(),
                length: reach,
                hit: self.preview.highlighted.is_some(),
            });
        }
    }
}

impl Tool for CurveNetworkTool {
    fn name(&self) -> &'static str {
        "curve"
    }

    fn update(&mut self, cx: &ToolContext) -> Option<ScriptCommand> {
        let pens = Hand::BOTH.map(|h| read_pen(cx, h));
        let queued = !self.pending.is_empty();
        let out = if self.stroke.is_some() {
            self.stroking(cx, &pens)
        } else {
            match self.idle(cx, &pens) {
                Some(c) => Some(c),
                None if self.stroke.is_none() => self.flick(&pens),
                None => None,
            }
        };
        self.ray(&pens);
        // A lost controller keeps its last state, so it does not fire a
        // fresh press edge when it comes back.
        for (prev, now) in self.prev.iter_mut().zip(pens) {
            if now.tracked {
                *prev = now;
            }
        }
        // Commands queued on an earlier frame go first.
        if !queued {
            return out;
        }
        self.pending.extend(out);
        self.pending.pop_front()
    }

    fn cancel(&mut self) {
        self.stroke = None;
        self.pending.clear();
        self.show_stroke();
    }

    fn preview(&self) -> &Preview {
        &self.preview
    }

    fn choices(&self) -> Vec<ChoiceGroup> {
        vec![
            ChoiceGroup {
                name: "Trigger",
                options: MODES.iter().map(|m| m.0.to_string()).collect(),
                active: self.forced,
            },
            ChoiceGroup {
                name: "Draw in",
                options: vec!["the world".into(), "left hand".into()],
                active: usize::from(self.in_frame),
            },
            ChoiceGroup {
                name: "A fills",
                options: vec!["every loop".into(), "pointed loop".into()],
                active: usize::from(self.fill_pointed),
            },
        ]
    }

    fn choose(&mut self, _doc: &Document, group: usize, option: usize) -> Option<ScriptCommand> {
        match (group, option) {
            (0, o) if o < MODES.len() => self.forced = o,
            (1, o) if o < 2 => self.in_frame = o == 1,
            (2, o) if o < 2 => self.fill_pointed = o == 1,
            _ => {}
        }
        None
    }
}

/// The trigger's modes in the palette: "auto" lets Table 1 choose by the
/// pen's distance and angle to the curve; the others force one tool on
/// the pointed curve or surface (drawing when nothing is pointed).
const MODES: [(&str, Option<CurveMode>); 6] = [
    ("auto", None),
    ("draw", Some(CurveMode::Draw)),
    ("smooth", Some(CurveMode::Edit(TableTool::SmoothSegment))),
    ("sharpen", Some(CurveMode::Edit(TableTool::SharpenSegment))),
    ("pull", Some(CurveMode::Edit(TableTool::EditDataPoint))),
    ("attract", Some(CurveMode::Attract)),
];
