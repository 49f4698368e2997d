//! [`GcToolSettings`]: thresholds and timings of the GC tool.

use crate::gc::Resolution;

/// Thresholds and timings of the GC tool (distances in model units unless
/// said otherwise; the desk placement has scale 1, so model units are
/// metres).
#[derive(Clone, Debug, PartialEq)]
pub struct GcToolSettings {
    /// How far rays reach, world metres.
    pub reach: f64,
    /// A spine key point is under the ray when the ray passes this close.
    pub key_point_radius: f64,
    /// A surface hit this close (along the spine) to a key section's
    /// centre picks that section.
    pub section_band: f64,
    /// The section band grows to a quarter of the gap to the neighbouring
    /// section, up to this.
    pub section_band_max: f64,
    /// A surface hit this close (along the spine) to a key section picks
    /// that section even when the ray also passes the section's key point:
    /// a ray aimed at a ring from outside crosses the spine near its key
    /// point, so without this the X-ray key point would shadow every
    /// section aimed at square on.
    pub ring_band: f64,
    /// The ring band grows like the section band, up to this.
    pub ring_band_max: f64,
    /// Seconds of an OPEN hold that delete or insert a section, and of a
    /// static FIST that instances a part (paper: 3 s).
    pub hold: f64,
    /// Seconds after OPEN within which a new gesture still counts as
    /// coming from OPEN (the classifier may pass through another gesture
    /// on the way, e.g. PINCH between OPEN and FIST).
    pub transition: f64,
    /// How far (world metres) the palm may drift during a hold.
    pub hold_drift: f64,
    /// Seconds a gesture survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Palm speed (m/s) above which a hand counts as teleported.
    pub max_hand_speed: f64,
    /// Time constant (s) of the ray filter (hand rays jitter).
    pub ray_smoothing: f64,
    /// Time constant (s) of the palm and pen filter.
    pub point_smoothing: f64,
    /// FIST motions shorter than this (world metres) are no edit.
    pub min_drag: f64,
    /// Most key sections a created part gets, spread evenly along its
    /// spine.
    pub sections: usize,
    /// Spine length per key section of a created part.
    pub section_spacing: f64,
    /// Spine stroke fitting tolerance (RDP), model units.
    pub spine_tolerance: f64,
    /// A child's spine end within this of its parent lands on it (handle).
    pub land_distance: f64,
    /// Template scores below this keep the sketched loop as the profile.
    pub min_template_score: f64,
    /// Shell thickness per metre of open-pinch finger gap.
    pub thickness_per_gap: f64,
    /// Thickness range.
    pub thickness_range: (f64, f64),
    /// Resolution of created parts.
    pub resolution: Resolution,
    /// Resolution of the preview mesh drawn during edits.
    pub preview_resolution: Resolution,
}

impl Default for GcToolSettings {
    fn default() -> Self {
        Self {
            reach: 3.0,
            key_point_radius: 0.006,
            section_band: 0.005,
            section_band_max: 0.01,
            ring_band: 0.003,
            ring_band_max: 0.007,
            hold: 3.0,
            transition: 0.3,
            hold_drift: 0.03,
            grace: 0.25,
            max_hand_speed: 12.0,
            ray_smoothing: 0.08,
            point_smoothing: 0.03,
            min_drag: 0.004,
            sections: 5,
            section_spacing: 0.04,
            spine_tolerance: 0.002,
            land_distance: 0.012,
            min_template_score: 0.7,
            thickness_per_gap: 0.08,
            thickness_range: (0.0015, 0.012),
            resolution: Resolution::DEFAULT,
            preview_resolution: Resolution::PREVIEW,
        }
    }
}
