//! [`PrintReport`]: what the printable path did and checked, for `info`,
//! the CLI summaries and the hosts' panels.

use std::fmt;

use serde::Serialize;

use super::{PrintedSize, ShellOffset};
use crate::mesh::{FileUnit, Precision, ValidationReport};

/// What happened to one object.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "treatment", rename_all = "snake_case")]
pub enum Treatment {
    /// Printed as the closed solid its mesh is.
    Solid,
    /// An open surface made into a shell.
    Thickened {
        /// Wall thickness (model units).
        thickness: f64,
        /// Where the wall lies.
        offset: ShellOffset,
        /// Boundary edges closed by walls.
        boundary_edges: usize,
    },
    /// A closed surface hollowed to a wall ([`super::ClosedSurfaces::Shell`]).
    Hollowed {
        /// Wall thickness (model units).
        thickness: f64,
    },
    /// Left out of the union: its (prepared) mesh is bit-identical to an
    /// earlier object's, so it prints as that one does.
    Identical {
        /// The earlier object's id.
        to: u32,
    },
    /// Left out: it has nothing to print (e.g. a curve network with no
    /// patches yet).
    Skipped {
        /// Why.
        reason: String,
    },
}

/// One object in the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartReport {
    /// Object id.
    pub id: u32,
    /// `#id kind`, as messages name it.
    pub label: String,
    /// What was done.
    pub treatment: Treatment,
}

/// What [`super::printable`] did and found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PrintReport {
    /// Every object, in order.
    pub parts: Vec<PartReport>,
    /// The precision the mesh was validated (and rounded) at.
    pub precision: Precision,
    /// The unit of the file it was rounded for (float32 millimetres and
    /// float32 metres round differently).
    pub unit: FileUnit,
    /// The snapping tolerance that gave a valid mesh (model units).
    pub tolerance: f64,
    /// Snapping rounds run (1 when the first was valid).
    pub rounds: u32,
    /// The checks of the final mesh, at `precision`.
    pub checks: ValidationReport,
}

impl PrintReport {
    /// Objects that were thickened or hollowed, as labels.
    pub fn thickened(&self) -> Vec<&str> {
        self.parts
            .iter()
            .filter(|p| {
                matches!(
                    p.treatment,
                    Treatment::Thickened { .. } | Treatment::Hollowed { .. }
                )
            })
            .map(|p| p.label.as_str())
            .collect()
    }

    /// Objects that were skipped, as labels.
    pub fn skipped(&self) -> Vec<&str> {
        self.parts
            .iter()
            .filter(|p| matches!(p.treatment, Treatment::Skipped { .. }))
            .map(|p| p.label.as_str())
            .collect()
    }

    /// The printed size: the checked mesh's bounding box and volume
    /// (`None` for an empty mesh, which the path never returns).
    pub fn size(&self) -> Option<PrintedSize> {
        self.checks
            .bbox
            .map(|b| PrintedSize::new(b, Some(self.checks.signed_volume)))
    }
}

impl fmt::Display for PartReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.treatment {
            Treatment::Solid => write!(f, "{}: solid", self.label),
            Treatment::Thickened {
                thickness,
                offset,
                boundary_edges,
            } => write!(
                f,
                "{}: open surface thickened to a {} mm shell ({offset:?}, {boundary_edges} boundary edges walled)",
                self.label,
                thickness * 1e3
            ),
            Treatment::Hollowed { thickness } => write!(
                f,
                "{}: closed surface hollowed to a {} mm wall",
                self.label,
                thickness * 1e3
            ),
            Treatment::Skipped { reason } => write!(f, "{}: skipped ({reason})", self.label),
            Treatment::Identical { to } => {
                write!(f, "{}: identical to #{to}, printed once", self.label)
            }
        }
    }
}

impl fmt::Display for PrintReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for p in &self.parts {
            writeln!(f, "  {p}")?;
        }
        if let Some(size) = self.size() {
            writeln!(f, "  printed size {size}")?;
        }
        write!(
            f,
            "  checked at {} in {}, snapping tolerance {:.3e} m ({} round{})",
            self.precision.name(),
            self.unit.symbol(),
            self.tolerance,
            self.rounds,
            if self.rounds == 1 { "" } else { "s" }
        )
    }
}
