//! [`printable`]: gather, thicken, unite, validate at the written
//! precision, snap again if rounding broke it (see the module doc of
//! [`super`]). [`printable_with`] is the same path reporting its progress
//! and stoppable through a [`PrintControl`] (a host's progress bar and
//! Esc): it checks the flag between objects, between and inside the
//! union's steps and between the checks, and gives the same bits as
//! [`printable`] when not stopped.

use std::collections::BTreeSet;

use glam::{DAffine3, DVec3};

use super::control::{PrintControl, PrintStage};
use super::report::{PartReport, PrintReport, Treatment};
use super::thicken::{hollow, thicken};
use super::{ClosedSurfaces, PrintError, PrintSettings};
use crate::mesh::{
    at_precision_in, self_intersections, snap, union_snapped_with, validate, BooleanError,
    Precision, TriMesh, ValidationReport, ValidationSettings,
};

/// Rounds of snapping: the tolerance is the base times these factors.
const SNAP_FACTORS: [f64; 5] = [1.0, 4.0, 16.0, 64.0, 256.0];

/// One object handed to [`printable`].
#[derive(Clone, Copy, Debug)]
pub struct PrintPart<'a> {
    /// The object's id (its triangles' source in the result).
    pub id: u32,
    /// Its kind's name (`solid`, `curve_network`, ...), for messages.
    pub kind: &'a str,
    /// True for kinds that are surfaces by nature (curve networks): a
    /// closed one follows [`PrintSettings::closed_surfaces`].
    pub surface: bool,
    /// Its mesh in model space.
    pub mesh: &'a TriMesh,
}

impl PrintPart<'_> {
    /// `#id kind`, as messages name it.
    pub fn label(&self) -> String {
        format!("#{} {}", self.id, self.kind)
    }
}

/// A printable model: the mesh to write and what was done.
#[derive(Clone, Debug)]
pub struct Printable {
    /// One closed, oriented, embedded 2-manifold whose coordinates are
    /// exactly representable at the report's precision (writing it loses
    /// nothing), triangles tagged with their object's id, normals set.
    pub mesh: TriMesh,
    /// What was done and checked.
    pub report: PrintReport,
}

/// A part made ready for the union.
struct Ready {
    id: u32,
    mesh: TriMesh,
}

/// The printable model of `parts`: see the module doc of [`super`].
pub fn printable(parts: &[PrintPart], settings: &PrintSettings) -> Result<Printable, PrintError> {
    printable_with(parts, settings, &PrintControl::default())
}

/// [`printable`], reporting its progress to `control` and stopping with
/// [`PrintError::Cancelled`] once `control` is cancelled.
pub fn printable_with(
    parts: &[PrintPart],
    settings: &PrintSettings,
    control: &PrintControl,
) -> Result<Printable, PrintError> {
    settings.validate()?;
    if parts.is_empty() {
        return Err(PrintError::Empty {
            why: "the document has no objects".into(),
        });
    }
    let mut reports = Vec::with_capacity(parts.len());
    let mut ready = Vec::with_capacity(parts.len());
    for (k, part) in parts.iter().enumerate() {
        control.check()?;
        control.set(PrintStage::Preparing, k, parts.len());
        let (mut treatment, mesh) = prepare(part, settings)?;
        if let Some(mut mesh) = mesh {
            // A part duplicated in place adds nothing to the union, and
            // uniting exactly coincident surfaces is Manifold's hardest case.
            let same = ready.iter().find(|r: &&Ready| {
                r.mesh.positions == mesh.positions && r.mesh.triangles == mesh.triangles
            });
            if let Some(r) = same {
                treatment = Treatment::Identical { to: r.id };
            } else {
                mesh.set_source(part.id);
                ready.push(Ready { id: part.id, mesh });
            }
        }
        reports.push(PartReport {
            id: part.id,
            label: part.label(),
            treatment,
        });
    }
    if ready.is_empty() {
        let why = reports
            .iter()
            .map(|r| r.to_string())
            .collect::<Vec<_>>()
            .join("; ");
        return Err(PrintError::Empty {
            why: format!("every object was skipped: {why}"),
        });
    }
    let label_of = |id: u32| {
        parts
            .iter()
            .find(|p| p.id == id)
            .map_or(format!("#{id}"), |p| p.label())
    };
    let check = ValidationSettings {
        max_abs_coordinate: settings.max_abs_coordinate,
        ..ValidationSettings::default()
    };
    let base = base_tolerance(&ready, settings.precision);
    let meshes: Vec<&TriMesh> = ready.iter().map(|r| &r.mesh).collect();
    control.set(PrintStage::Uniting, 0, 2 * meshes.len());
    let united = union_snapped_with(
        &meshes,
        base,
        Some(control.boolean_cancel()),
        &|done, total| control.set(PrintStage::Uniting, done, total),
    )
    .map_err(|e| union_error(e, &ready, &label_of))?;
    let mut current = united;
    let mut last = None;
    for (round, factor) in SNAP_FACTORS.iter().enumerate() {
        control.check()?;
        control.set(PrintStage::Checking, round, SNAP_FACTORS.len());
        let tol = base * factor;
        if round > 0 {
            current = match snap(&current, tol) {
                Ok(m) => m,
                Err(_) => break,
            };
        }
        let written = at_precision_in(&current, settings.precision, settings.unit);
        let checks = validate(&written, &check);
        if checks.is_printable() {
            return Ok(Printable {
                mesh: written,
                report: PrintReport {
                    parts: reports,
                    precision: settings.precision,
                    unit: settings.unit,
                    tolerance: tol,
                    rounds: round as u32 + 1,
                    checks,
                },
            });
        }
        last = Some((written, checks, tol));
    }
    control.check()?;
    let Some((written, checks, tol)) = last else {
        return Err(PrintError::Union {
            objects: ready
                .iter()
                .map(|r| label_of(r.id))
                .collect::<Vec<_>>()
                .join(", "),
            status: "snapping failed".into(),
        });
    };
    Err(blame(
        &written, &checks, tol, &ready, parts, settings, &label_of,
    ))
}

/// Checks one object as it would print on its own, without uniting: the
/// edit-time hook for ops that can fold an object (GC edits, sculpt
/// strokes). `Ok` carries what printing would do with it.
pub fn check_part(part: &PrintPart, settings: &PrintSettings) -> Result<Treatment, PrintError> {
    settings.validate()?;
    let (treatment, mesh) = prepare(part, settings)?;
    if let Some(mesh) = mesh {
        let s = self_intersections(&mesh);
        if !s.pairs.is_empty() {
            return Err(PrintError::SelfIntersecting {
                object: part.label(),
                pairs: s.pairs.len(),
            });
        }
    }
    Ok(treatment)
}

/// The edit-time check of GC and sculpt ops under
/// [`super::SelfIntersectionPolicy::Refuse`]: `Err` when the edited
/// object's mesh `after` passes through itself and its mesh `before` the
/// edit did not (so an object that already intersected itself, made under
/// `flag`, can still be edited, e.g. to unfold it). `before` is `None` for
/// a creation. A mesh the exact search cannot check (non-finite or beyond
/// its coordinate range) passes here; the print path refuses it.
///
/// Cost: one exact self-intersection search of the edited object's mesh
/// (a BVH over its triangles; see [`crate::mesh::self_intersections`]),
/// plus one of the old mesh only when the new one fails.
pub fn check_edit(
    label: &str,
    before: Option<&TriMesh>,
    after: &TriMesh,
) -> Result<(), PrintError> {
    let s = self_intersections(after);
    if !s.checked || s.pairs.is_empty() {
        return Ok(());
    }
    if let Some(b) = before {
        let old = self_intersections(b);
        if !old.checked || !old.pairs.is_empty() {
            return Ok(());
        }
    }
    Err(PrintError::SelfIntersecting {
        object: label.to_string(),
        pairs: s.pairs.len(),
    })
}

/// Range checks, classification, thickening. `None` mesh: skipped.
fn prepare(
    part: &PrintPart,
    settings: &PrintSettings,
) -> Result<(Treatment, Option<TriMesh>), PrintError> {
    let scaled;
    let m = if settings.scale == 1.0 {
        part.mesh
    } else {
        let mut s = part.mesh.clone();
        s.transform(&DAffine3::from_scale(DVec3::splat(settings.scale)));
        scaled = s;
        &scaled
    };
    if m.triangles.is_empty() {
        let reason = if part.surface {
            "no patches yet: nothing to print"
        } else {
            "its mesh has no triangles"
        };
        return Ok((
            Treatment::Skipped {
                reason: reason.into(),
            },
            None,
        ));
    }
    if let Some(v) = m
        .positions
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return Err(PrintError::NonFinite {
            object: part.label(),
            vertex: v,
        });
    }
    let far = m
        .positions
        .iter()
        .flatten()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    if far > settings.max_abs_coordinate {
        return Err(PrintError::OutOfRange {
            object: part.label(),
            value: far,
            limit: settings.max_abs_coordinate,
        });
    }
    let r = validate(m, &ValidationSettings::topology_only());
    let thickness = settings.wall_thickness;
    let thicken_err = |reason: String| PrintError::Thicken {
        object: part.label(),
        thickness,
        reason,
    };
    if r.is_closed_manifold() {
        if part.surface && settings.closed_surfaces == ClosedSurfaces::Shell {
            let h = hollow(m, thickness).map_err(|e| thicken_err(e.to_string()))?;
            return Ok((Treatment::Hollowed { thickness }, Some(h)));
        }
        return Ok((Treatment::Solid, Some(m.clone())));
    }
    let open = r.boundary_edges > 0
        && r.non_manifold_edges == 0
        && r.misoriented_edges == 0
        && r.out_of_range_triangles == 0;
    if open {
        let (shell, walls) =
            thicken(m, thickness, settings.shell_offset).map_err(|e| thicken_err(e.to_string()))?;
        let s = self_intersections(&shell);
        if !s.pairs.is_empty() {
            return Err(thicken_err(format!(
                "the shell passes through itself ({} triangle pairs): the surface bends tighter than the wall or nearly touches itself; use a thinner wall",
                s.pairs.len()
            )));
        }
        return Ok((
            Treatment::Thickened {
                thickness,
                offset: settings.shell_offset,
                boundary_edges: walls,
            },
            Some(shell),
        ));
    }
    Err(PrintError::NotSolid {
        object: part.label(),
        problems: r.problems(),
    })
}

/// The first snapping tolerance: four steps of the output precision at the
/// largest coordinate (Manifold's own floor for float32 is one step).
fn base_tolerance(ready: &[Ready], precision: Precision) -> f64 {
    let far = ready
        .iter()
        .flat_map(|r| r.mesh.positions.iter().flatten())
        .fold(0.0f64, |a, x| a.max(x.abs()))
        .max(1e-6);
    let step = match precision {
        Precision::F32 => f32::EPSILON as f64,
        Precision::F64 => 1e-12,
    };
    4.0 * step * far
}

fn union_error(e: BooleanError, ready: &[Ready], label_of: &dyn Fn(u32) -> String) -> PrintError {
    match e {
        BooleanError::Malformed { index, reason } => PrintError::NotSolid {
            object: label_of(ready[index].id),
            problems: reason,
        },
        BooleanError::NotManifold { index, status } => PrintError::NotSolid {
            object: label_of(ready[index].id),
            problems: format!("Manifold refused it ({status})"),
        },
        BooleanError::Cancelled => PrintError::Cancelled,
        BooleanError::Failed(status) => PrintError::Union {
            objects: ready
                .iter()
                .map(|r| label_of(r.id))
                .collect::<Vec<_>>()
                .join(", "),
            status,
        },
    }
}

/// The error for a union that stayed invalid: an object that intersects
/// itself on its own is named alone; otherwise the objects owning the
/// faulty triangles.
fn blame(
    written: &TriMesh,
    checks: &ValidationReport,
    tol: f64,
    ready: &[Ready],
    parts: &[PrintPart],
    settings: &PrintSettings,
    label_of: &dyn Fn(u32) -> String,
) -> PrintError {
    let bad = crate::mesh::problem_triangles(written, checks);
    let ids: BTreeSet<u32> = bad
        .iter()
        .filter_map(|&t| written.tri_source.get(t as usize).copied())
        .collect();
    // An object that passes through itself is the cause, whatever else.
    for r in ready.iter().filter(|r| ids.contains(&r.id)) {
        let alone = at_precision_in(&r.mesh, settings.precision, settings.unit);
        let s = self_intersections(&alone);
        if !s.pairs.is_empty() {
            return PrintError::SelfIntersecting {
                object: label_of(r.id),
                pairs: s.pairs.len(),
            };
        }
    }
    let named: Vec<String> = if ids.is_empty() {
        parts.iter().map(|p| p.label()).collect()
    } else {
        ids.iter().map(|&id| label_of(id)).collect()
    };
    let objects = match named.len() {
        1 => format!("object {}", named[0]),
        _ => format!("objects {}", named.join(" and ")),
    };
    PrintError::Invalid {
        objects,
        precision: settings.precision.name(),
        problems: checks.problems(),
        tolerance: tol,
    }
}
