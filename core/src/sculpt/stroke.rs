//! Strokes (paper §4.1, §6): 6-DOF samples with pressure, applied frame
//! by frame by a [`Sculptor`] (see [`super::sculptor`]), either as a whole
//! path ([`run_stroke`], what the `sculpt_stroke` op does) or one sample at
//! a time as a host sculpts live ([`StrokeFrames`]), with the same bits.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::brush::{check_finite, positive, BrushExtent, BrushPose, BrushShape};
use super::warp::{Falloff, Warp};
use super::SculptError;

pub use super::sculptor::{FrameInput, FrameStats, Sculptor};

/// One tracker sample: brush position, orientation and pressure.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrokeSample {
    /// Brush position (world space).
    pub position: [f64; 3],
    /// Brush orientation quaternion `[x, y, z, w]` (normalized on use).
    pub rotation: [f64; 4],
    /// Pressure in [0, 1].
    pub pressure: f64,
}

impl StrokeSample {
    /// The sample's mirror image across `m`: position reflected, the
    /// brush frame mirrored ([`MirrorPlane::frame`](crate::math::MirrorPlane::frame)), same pressure.
    pub fn mirrored(&self, m: &crate::math::MirrorPlane) -> Self {
        Self {
            position: m.point(DVec3::from_array(self.position)).to_array(),
            rotation: m.frame(DQuat::from_array(self.rotation)).to_array(),
            pressure: self.pressure,
        }
    }

    /// Checks the sample is finite, has a rotation and a pressure in [0, 1].
    pub fn validate(&self, index: usize) -> Result<(), SculptError> {
        check_finite(&format!("samples[{index}].position"), &self.position)?;
        check_finite(&format!("samples[{index}].rotation"), &self.rotation)?;
        check_finite(&format!("samples[{index}].pressure"), &[self.pressure])?;
        if DQuat::from_array(self.rotation).length() < 1e-9 {
            return Err(SculptError::ZeroRotation {
                field: format!("samples[{index}].rotation"),
            });
        }
        if !(0.0..=1.0).contains(&self.pressure) {
            return Err(SculptError::OutOfRange {
                field: format!("samples[{index}].pressure"),
                value: self.pressure,
                range: "[0, 1]",
            });
        }
        Ok(())
    }
}

/// Everything about a stroke except its path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrokeSettings {
    /// Brush shape (distance field in the brush frame).
    pub brush: BrushShape,
    /// Brush scale, separate from the model's scale.
    pub brush_scale: f64,
    /// Influence size `h`: weights fall to 0 at distance `h` from the brush.
    pub influence: f64,
    /// Weight falloff.
    pub falloff: Falloff,
    /// Warp operator.
    pub warp: Warp,
    /// Max edge length as a fraction of the brush size (the scaled radius
    /// of the brush's own surface, [`BrushShape::size_radius`]); at least
    /// 1e-3 (see `sculpt::budget`).
    #[schemars(range(min = 0.001))]
    pub max_edge_rel: f64,
    /// Min edge length as a fraction of the brush size; must be below half
    /// of `max_edge_rel`, so a bisected edge is never collapsed again.
    pub min_edge_rel: f64,
}

impl StrokeSettings {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), SculptError> {
        self.brush.validate()?;
        positive("brush_scale", self.brush_scale)?;
        positive("influence", self.influence)?;
        positive("max_edge_rel", self.max_edge_rel)?;
        if self.max_edge_rel < super::budget::MIN_MAX_EDGE_REL {
            return Err(SculptError::OutOfRange {
                field: "max_edge_rel".into(),
                value: self.max_edge_rel,
                range: "at least 1e-3 (finer edges than a thousandth of the brush size ask for billions of triangles)",
            });
        }
        positive("min_edge_rel", self.min_edge_rel)?;
        if let Warp::Explode { delta } = self.warp {
            check_finite("warp.delta", &[delta])?;
        }
        if self.min_edge_rel * 2.0 >= self.max_edge_rel {
            return Err(SculptError::OutOfRange {
                field: "min_edge_rel".into(),
                value: self.min_edge_rel,
                range: "below max_edge_rel / 2",
            });
        }
        Ok(())
    }

    /// Brush size in the brush's scaled units: the scaled
    /// [`BrushShape::size_radius`] (a pass over a grid brush's samples).
    pub fn brush_size(&self) -> f64 {
        self.brush.size_radius() * self.brush_scale
    }
}

/// A stroke applied one sample at a time: exactly the frames
/// [`run_stroke`] applies for the whole path, so a host can sculpt live
/// (one call per kept sample, then [`Sculptor::sync_render`]) and the
/// `sculpt_stroke` op it commits at the end replays to the same bits.
#[derive(Clone, Debug)]
pub struct StrokeFrames<'a> {
    shape: &'a BrushShape,
    settings: &'a StrokeSettings,
    model_scale: f64,
    /// The brush's extent, computed once.
    extent: BrushExtent,
    prev: Option<BrushPose>,
    total: FrameStats,
}

impl<'a> StrokeFrames<'a> {
    /// Starts a stroke on `sculptor` (see [`Sculptor::begin_stroke`]) with
    /// brush `shape` (a mesh brush already resolved to a grid), `settings`
    /// and the model's uniform scale.
    pub fn begin(
        sculptor: &mut Sculptor,
        shape: &'a BrushShape,
        settings: &'a StrokeSettings,
        model_scale: f64,
    ) -> Self {
        Self::begin_with(sculptor, shape, shape.extent(), settings, model_scale)
    }

    /// [`Self::begin`] with the shape's extent already computed.
    fn begin_with(
        sculptor: &mut Sculptor,
        shape: &'a BrushShape,
        extent: BrushExtent,
        settings: &'a StrokeSettings,
        model_scale: f64,
    ) -> Self {
        sculptor.begin_stroke();
        Self {
            shape,
            settings,
            model_scale,
            extent,
            prev: None,
            total: FrameStats::default(),
        }
    }

    /// Applies the frame of the next sample (model-space pose, pressure).
    pub fn frame(&mut self, sculptor: &mut Sculptor, pose: BrushPose, pressure: f64) -> FrameStats {
        let size = self.extent.size * self.settings.brush_scale / self.model_scale;
        let prev = self.prev.unwrap_or(pose);
        self.prev = Some(pose);
        let s = sculptor.apply_frame(&FrameInput {
            shape: self.shape,
            bound: self.extent.bound,
            prev,
            pose,
            pressure,
            influence: self.settings.influence / self.model_scale,
            falloff: self.settings.falloff,
            warp: self.settings.warp,
            max_len: self.settings.max_edge_rel * size,
            min_len: self.settings.min_edge_rel * size,
        });
        self.total += s;
        s
    }

    /// What the stroke did so far.
    pub fn total(&self) -> FrameStats {
        self.total
    }
}

/// Applies a whole stroke of model-space poses and pressures, after
/// checking its estimated cost ([`super::budget`], with `settings` holding
/// the resolved brush `shape`); fails with [`SculptError::OverBudget`] or
/// [`SculptError::TooSlow`] before any frame when the estimate is over the
/// budget, or after the frame that reached the sculptor's face limit or
/// did the work the time limit allows (the sculptor's surface is then
/// valid but the stroke unfinished).
pub fn run_stroke(
    sculptor: &mut Sculptor,
    shape: &BrushShape,
    settings: &StrokeSettings,
    model_scale: f64,
    poses: &[(BrushPose, f64)],
) -> Result<FrameStats, SculptError> {
    run_strokes(sculptor, shape, settings, model_scale, &[poses])
}

/// Several brushes moving together, one path each (a stroke and its
/// mirror image): frame `i` of every path in path order, then frame
/// `i + 1`, so where the brushes meet (near a mirror plane) each sees
/// the other's work of the frame before, as both hands would live. One
/// path is exactly [`run_stroke`]. The budget ([`super::budget`]) counts
/// every path's frames and the sculptor's mesh, and is checked before the
/// first frame; the backstop stops the stroke once it has done the work
/// the time limit allows.
pub fn run_strokes(
    sculptor: &mut Sculptor,
    shape: &BrushShape,
    settings: &StrokeSettings,
    model_scale: f64,
    paths: &[&[(BrushPose, f64)]],
) -> Result<FrameStats, SculptError> {
    let extent = shape.extent();
    let mut cost = estimate_on(sculptor, settings, extent, model_scale, paths)?;
    cost.check()?;
    cost.grid_samples = 0.0;
    run_costed(sculptor, shape, extent, settings, model_scale, paths, &cost)
}

/// The cost of `paths` on `sculptor`'s mesh as it is (its faces and
/// density), without a brush grid.
pub(super) fn estimate_on(
    sculptor: &Sculptor,
    settings: &StrokeSettings,
    extent: BrushExtent,
    model_scale: f64,
    paths: &[&[(BrushPose, f64)]],
) -> Result<super::budget::StrokeCost, SculptError> {
    let mut cost = super::budget::estimate_strokes(
        settings,
        extent,
        model_scale,
        paths,
        Some(&sculptor.grid),
    )?;
    cost.faces = sculptor.mesh().face_count() as f64;
    Ok(cost)
}

/// [`run_strokes`] after its estimate `cost` was checked: the frames, with
/// the face limit and the backstop on the work.
pub(super) fn run_costed(
    sculptor: &mut Sculptor,
    shape: &BrushShape,
    extent: BrushExtent,
    settings: &StrokeSettings,
    model_scale: f64,
    paths: &[&[(BrushPose, f64)]],
    cost: &super::budget::StrokeCost,
) -> Result<FrameStats, SculptError> {
    let limit = super::budget::face_limit(sculptor.mesh().face_count());
    sculptor.set_face_limit(limit);
    let unit_limit = cost.unit_limit();
    let mut units = 0.0;
    let mut done = 0;
    let mut frames: Vec<StrokeFrames> = paths
        .iter()
        .map(|_| StrokeFrames::begin_with(sculptor, shape, extent, settings, model_scale))
        .collect();
    let n = paths.iter().map(|p| p.len()).max().unwrap_or(0);
    for i in 0..n {
        for (f, path) in frames.iter_mut().zip(paths) {
            let Some(&(pose, pressure)) = path.get(i) else {
                continue;
            };
            let s = f.frame(sculptor, pose, pressure);
            done += 1;
            units += super::budget::frame_units(&s);
            if sculptor.over_budget() {
                return Err(super::budget::too_many_faces(sculptor.stopped_at(), limit));
            }
            if units > unit_limit {
                return Err(super::budget::too_much_work(cost, units, done));
            }
        }
    }
    let mut total = FrameStats::default();
    for f in &frames {
        total += f.total();
    }
    Ok(total)
}
