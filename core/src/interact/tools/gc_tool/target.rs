//! Ray selection (paper §4, OPEN): what the ray points at — a spine key
//! point, a key section (curve), the side surface of a part, or empty
//! space — in that order of priority.
//!
//! - Key points lie inside their part; they are drawn on top and picked
//!   when the ray passes within [`super::GcToolSettings::key_point_radius`]
//!   of one, through the surface (X-ray), as handles usually are.
//! - Otherwise the ray is intersected with the document's meshes; the hit
//!   is projected on each part's side surface and the nearest part wins.
//!   A hit within [`super::GcToolSettings::section_band`] (along the spine)
//!   of a key section picks that section, else the surface at parameter
//!   `v`. A hit within [`super::GcToolSettings::ring_band`] of a ring
//!   picks the section even if the ray also passes its key point (aimed
//!   square at a ring, a ray crosses the spine at the key point), and
//!   a hit within the section band picks the section over its own key
//!   point (a ray level with a ring passes through its centre). Both
//!   bands widen to a quarter of the gap to the neighbouring section (up
//!   to `section_band_max` / `ring_band_max`), since hand rays jitter.
//! - With no hit, the empty-space point is where the ray meets the model's
//!   ground plane `z = 0` (within reach), else the point at a fixed
//!   distance along the ray; it starts a new root part.
//!
//! Part surfaces and frames are cached per object and rebuilt only when
//! the object's assembly changed.

use std::collections::BTreeMap;

use crate::assembly::project_to_surface;
use crate::doc::{Document, ObjectId, ObjectKind};
use crate::gc::GcAssembly;
use crate::math::{DVec3, Frame};
use crate::nurbs::NurbsSurface;

use super::{GcTarget, GcToolSettings};
use crate::interact::tools::pick::{pick, Ray};

/// Cached geometry of one part.
#[derive(Clone, Debug)]
pub(super) struct PartGeo {
    /// The side surface.
    pub surface: NurbsSurface,
    /// RMF frames at the key sections.
    pub frames: Vec<Frame>,
}

#[derive(Clone, Debug)]
struct ObjGeo {
    asm: GcAssembly,
    parts: Vec<Option<PartGeo>>,
}

/// Part geometry, cached per object.
#[derive(Clone, Debug, Default)]
pub(super) struct GeoCache {
    objects: BTreeMap<ObjectId, ObjGeo>,
}

fn part_geo(asm: &GcAssembly, i: usize) -> Option<PartGeo> {
    let gc = &asm.parts[i].gc;
    let surface = gc.surface().ok()?;
    let frames = gc.frames().ok()?;
    let frames = gc
        .sections
        .iter()
        .map(|s| frames.at(&gc.spine, s.v).ok())
        .collect::<Option<Vec<_>>>()?;
    Some(PartGeo { surface, frames })
}

impl GeoCache {
    /// Brings the cache up to date with `doc`.
    pub fn refresh(&mut self, doc: &Document) {
        self.objects.retain(|id, _| doc.get(*id).is_ok());
        for (id, obj) in doc.objects() {
            let ObjectKind::GcAssembly(asm) = &obj.kind else {
                continue;
            };
            if self.objects.get(&id).is_some_and(|g| &g.asm == asm) {
                continue;
            }
            let parts = (0..asm.parts.len()).map(|i| part_geo(asm, i)).collect();
            self.objects.insert(
                id,
                ObjGeo {
                    asm: asm.clone(),
                    parts,
                },
            );
        }
    }

    /// The cached geometry of a part.
    pub fn part(&self, id: ObjectId, part: usize) -> Option<&PartGeo> {
        self.objects.get(&id)?.parts.get(part)?.as_ref()
    }

    /// The assembly of an object, as cached.
    pub fn assembly(&self, id: ObjectId) -> Option<&GcAssembly> {
        self.objects.get(&id).map(|g| &g.asm)
    }

    /// What `ray` (model space) selects, looking at most `reach` far.
    pub fn pick(&self, doc: &Document, ray: &Ray, reach: f64, s: &GcToolSettings) -> GcTarget {
        let key = self.pick_key_point(ray, reach, s);
        if let Some(hit) = pick(doc, ray, reach) {
            let on_ring = self.classify_hit(hit.id, hit.point, s.ring_band, s.ring_band_max);
            if let Some(t @ GcTarget::Section { .. }) = on_ring {
                return t;
            }
            let near = self.classify_hit(hit.id, hit.point, s.section_band, s.section_band_max);
            return match (key, near) {
                // A ray aimed level at a ring passes through the ring's
                // own key point: the ring is what it aims at.
                (
                    Some(GcTarget::KeyPoint {
                        id, part, section, ..
                    }),
                    Some(
                        t @ GcTarget::Section {
                            id: i2,
                            part: p2,
                            section: s2,
                            ..
                        },
                    ),
                ) if (id, part, section) == (i2, p2, s2) => t,
                (Some(k), _) => k,
                (None, Some(t)) => t,
                (None, None) => GcTarget::Empty { point: hit.point },
            };
        }
        if let Some(t) = key {
            return t;
        }
        let t = if ray.dir.z < -1e-6 {
            (-ray.origin.z / ray.dir.z).min(reach)
        } else {
            0.5 * reach
        };
        GcTarget::Empty {
            point: ray.origin + ray.dir * t.max(0.0),
        }
    }

    fn pick_key_point(&self, ray: &Ray, reach: f64, s: &GcToolSettings) -> Option<GcTarget> {
        let mut best: Option<(f64, GcTarget)> = None;
        for (&id, g) in &self.objects {
            for (part, geo) in g.parts.iter().enumerate() {
                let Some(geo) = geo else { continue };
                for (section, f) in geo.frames.iter().enumerate() {
                    let d = f.origin - ray.origin;
                    let t = d.dot(ray.dir);
                    if !(0.0..=reach).contains(&t) {
                        continue;
                    }
                    let miss = (d - ray.dir * t).length();
                    if miss < s.key_point_radius && best.as_ref().is_none_or(|b| miss < b.0) {
                        let point = f.origin;
                        best = Some((
                            miss,
                            GcTarget::KeyPoint {
                                id,
                                part,
                                section,
                                point,
                            },
                        ));
                    }
                }
            }
        }
        best.map(|b| b.1)
    }

    /// The section (within `band` along the spine, widened up to
    /// `band_max` where the sections are far apart) or surface a mesh hit
    /// lies on.
    fn classify_hit(&self, id: ObjectId, p: DVec3, band: f64, band_max: f64) -> Option<GcTarget> {
        let g = self.objects.get(&id)?;
        let mut best: Option<(f64, usize, DVec3, f64)> = None;
        for (part, geo) in g.parts.iter().enumerate() {
            let Some(geo) = geo else { continue };
            let proj = project_to_surface(&geo.surface, p);
            if best.is_none_or(|b| proj.distance < b.0) {
                best = Some((proj.distance, part, proj.point, proj.anchor.v));
            }
        }
        let (_, part, point, v) = best?;
        let gc = &g.asm.parts[part].gc;
        let c = gc.spine.curve.point(v);
        let geo = g.parts[part].as_ref()?;
        let near = geo
            .frames
            .iter()
            .enumerate()
            .map(|(k, f)| (k, (c - f.origin).length()))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        // The band grows with the room around the section (a quarter of
        // the gap to its nearest neighbour), up to `band_max`: hand rays
        // jitter by millimetres, and sections far apart can afford it.
        let f = &geo.frames;
        let gap = [near.0.wrapping_sub(1), near.0 + 1]
            .iter()
            .filter_map(|&j| f.get(j))
            .map(|g| (g.origin - f[near.0].origin).length())
            .fold(f64::INFINITY, f64::min);
        let band = (0.25 * gap).clamp(band, band_max.max(band));
        Some(if near.1 < band {
            GcTarget::Section {
                id,
                part,
                section: near.0,
                point,
            }
        } else {
            GcTarget::Surface { id, part, point, v }
        })
    }
}
