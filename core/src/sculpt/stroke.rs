//! Strokes (paper §4.1, §6): 6-DOF samples with pressure, applied frame
//! by frame by a [`Sculptor`] (see [`super::sculptor`]), either as a whole
//! path ([`run_stroke`], what the `sculpt_stroke` op does) or one sample at
//! a time as a host sculpts live ([`StrokeFrames`]), with the same bits.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::brush::{check_finite, positive, BrushPose, BrushShape};
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
    /// brush frame mirrored ([`MirrorPlane::frame`]), same pressure.
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
    /// Max edge length as a fraction of the brush size (scaled bound
    /// radius of the brush shape); at least 1e-3 (see `sculpt::budget`).
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

    /// Brush size in the brush's scaled units.
    pub fn brush_size(&self) -> f64 {
        self.brush.bound_radius() * self.brush_scale
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
        sculptor.begin_stroke();
        Self {
            shape,
            settings,
            model_scale,
            prev: None,
            total: FrameStats::default(),
        }
    }

    /// Applies the frame of the next sample (model-space pose, pressure).
    pub fn frame(&mut self, sculptor: &mut Sculptor, pose: BrushPose, pressure: f64) -> FrameStats {
        let size = self.settings.brush_size() / self.model_scale;
        let prev = self.prev.unwrap_or(pose);
        self.prev = Some(pose);
        let s = sculptor.apply_frame(&FrameInput {
            shape: self.shape,
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
/// checking its estimated cost ([`super::budget::check_stroke`], with
/// `settings` holding the resolved brush `shape`); fails with
/// [`SculptError::OverBudget`] before any frame when the estimate is over
/// the budget, or after the frame that reached the sculptor's face limit
/// (the sculptor's surface is then valid but the stroke unfinished).
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
/// path is exactly [`run_stroke`]. The budget counts every path's frames.
pub fn run_strokes(
    sculptor: &mut Sculptor,
    shape: &BrushShape,
    settings: &StrokeSettings,
    model_scale: f64,
    paths: &[&[(BrushPose, f64)]],
) -> Result<FrameStats, SculptError> {
    super::budget::check_strokes(settings, model_scale, paths)?;
    let limit = super::budget::face_limit(sculptor.mesh().face_count());
    sculptor.set_face_limit(limit);
    let mut frames: Vec<StrokeFrames> = paths
        .iter()
        .map(|_| StrokeFrames::begin(sculptor, shape, settings, model_scale))
        .collect();
    let n = paths.iter().map(|p| p.len()).max().unwrap_or(0);
    for i in 0..n {
        for (f, path) in frames.iter_mut().zip(paths) {
            let Some(&(pose, pressure)) = path.get(i) else {
                continue;
            };
            f.frame(sculptor, pose, pressure);
            if sculptor.over_budget() {
                let faces = sculptor.mesh().face_count();
                return Err(super::budget::too_many_faces(faces, limit));
            }
        }
    }
    let mut total = FrameStats::default();
    for f in &frames {
        total += f.total();
    }
    Ok(total)
}
