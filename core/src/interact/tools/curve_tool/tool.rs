//! [`CurveNetworkTool`]: the tool's state machine (draw, edit, fill,
//! delete, undo, redo) and its [`Tool`] implementation (update, preview,
//! palette choices).

use crate::doc::{Create, Document, Edit, ObjectId, ObjectKind, Op, ScriptCommand};
use crate::math::DVec3;
use crate::styling::select::{
    nearest_loop, nearest_patch_point, select_in_network, CurveTool as TableTool,
};
use crate::styling::tools::MAX_FRAMES;
use crate::styling::CurveNetwork;
use crate::styling::{
    CurveAttract, CurveDelete, CurveDraw, CurveDrawInFrame, CurveFillAuto, CurveFillLoop, CurveId,
    CurveNetworkCreate, CurvePull, CurveSharpen, CurveSmooth, ModelingFrame, PatchId,
    SurfaceEquilibrium, SurfacePull, SurfaceSharpen, SurfaceSmooth,
};

use super::modes::{attractor_of, read_pen, Pen, Stroke, SURFACE_MARGIN};
use super::settings::CurveToolSettings;
use super::{CurveMode, CurvePreview, CurveTarget, DrawPlane, PatchTarget, SurfaceTool};
use crate::interact::input::Hand;
use crate::interact::palette::ChoiceGroup;
use crate::interact::tools::lost_too_long;
use crate::interact::tools::{Preview, PreviewRay, Tool, ToolContext, ToolPreview};

/// Draw, smooth, sharpen, pull, fill, delete, undo, redo on curve networks.
#[derive(Clone, Debug)]
pub struct CurveNetworkTool {
    pub(super) settings: CurveToolSettings,
    pub(super) preview: Preview,
    pub(super) prev: [Pen; 2],
    pub(super) stick_armed: [bool; 2],
    pub(super) stroke: Option<Stroke>,
    /// Commands waiting for a frame of their own (a mirrored stroke).
    pub(super) pending: std::collections::VecDeque<ScriptCommand>,
    /// The palette's trigger mode (index into [`MODES`]; 0: Table 1).
    pub(super) forced: usize,
    /// Strokes are drawn in the modeling frame the other hand holds
    /// (paper 3 §5.4, `curve_draw_in_frame`): the network moves with the
    /// hand while drawing. The palette's "Draw in: left hand".
    pub(super) in_frame: bool,
    /// `primary` fills the pointed loop (`curve_fill_loop`) instead of
    /// every loop. The palette's "A fills".
    pub(super) fill_pointed: bool,
}

impl Default for CurveNetworkTool {
    fn default() -> Self {
        Self::new(CurveToolSettings::default())
    }
}

/// The network the tool works on: the first curve network of the document.
pub(super) fn network(doc: &Document) -> Option<(ObjectId, &CurveNetwork)> {
    doc.objects().find_map(|(id, o)| match &o.kind {
        ObjectKind::CurveNetwork(n) => Some((id, n)),
        #[allow(unreachable_patterns)]
        _ => None,
    })
}

pub(super) fn arr(p: &[DVec3]) -> Vec<[f64; 3]> {
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

    pub(super) fn cp(&mut self) -> &mut CurvePreview {
        self.preview.curve_mut()
    }

    /// The pen tip and direction in model space.
    pub(super) fn tip(&self, cx: &ToolContext, pen: &Pen) -> Option<(DVec3, DVec3)> {
        let aim = pen.aim?;
        let to_model = cx.model.inverse();
        let dir = aim.forward();
        let tip = aim.position + dir * self.settings.tip_offset;
        Some((to_model.apply(tip), to_model.apply_dir(dir)))
    }

    /// The plane the other hand offers now (model space).
    pub(super) fn held_plane(cx: &ToolContext, pen: &Pen) -> Option<DrawPlane> {
        let (grip, aim) = (pen.grip?, pen.aim?);
        let to_model = cx.model.inverse();
        let normal = to_model.apply_dir(aim.forward()).normalize_or_zero();
        (normal != DVec3::ZERO).then_some(DrawPlane {
            origin: to_model.apply(grip.position),
            normal,
        })
    }

    /// The modeling frame the other hand holds: its grip, in model space.
    pub(super) fn held_frame(cx: &ToolContext, pen: &Pen) -> Option<ModelingFrame> {
        let grip = pen.grip?;
        let to_model = cx.model.inverse();
        Some(ModelingFrame::new(
            to_model.apply(grip.position),
            (to_model.rotate * grip.orientation).normalize(),
        ))
    }

    pub(super) fn target(cx: &ToolContext, tip: DVec3, dir: DVec3) -> Option<CurveTarget> {
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
    pub(super) fn patch_target(
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
    pub(super) fn mode_of(
        &self,
        target: Option<&CurveTarget>,
        patch: Option<&PatchTarget>,
    ) -> CurveMode {
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

    pub(super) fn idle(&mut self, cx: &ToolContext, pens: &[Pen; 2]) -> Option<ScriptCommand> {
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

    pub(super) fn show_stroke(&mut self) {
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

    pub(super) fn stroking(&mut self, cx: &ToolContext, pens: &[Pen; 2]) -> Option<ScriptCommand> {
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
    pub(super) fn commit(&mut self, cx: &ToolContext, s: Stroke) -> Option<ScriptCommand> {
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
    pub(super) fn commit_other(
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

    pub(super) fn draw(&self, id: ObjectId, samples: &[DVec3]) -> Edit<CurveDraw> {
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
    pub(super) fn flick(&mut self, pens: &[Pen; 2]) -> Option<ScriptCommand> {
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

    pub(super) fn ray(&mut self, pens: &[Pen; 2]) {
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
pub(super) const MODES: [(&str, Option<CurveMode>); 6] = [
    ("auto", None),
    ("draw", Some(CurveMode::Draw)),
    ("smooth", Some(CurveMode::Edit(TableTool::SmoothSegment))),
    ("sharpen", Some(CurveMode::Edit(TableTool::SharpenSegment))),
    ("pull", Some(CurveMode::Edit(TableTool::EditDataPoint))),
    ("attract", Some(CurveMode::Attract)),
];
