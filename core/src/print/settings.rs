//! [`PrintSettings`]: what the printable path needs to know besides the
//! objects. The wall thickness becomes a document setting (an op sets it);
//! until then hosts pass it here.

use serde::{Deserialize, Serialize};

use super::PrintError;
use crate::mesh::Precision;

/// Where a shell lies relative to the surface it thickens.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShellOffset {
    /// Half the thickness on each side: the surface is the wall's middle.
    #[default]
    Centered,
    /// All of it behind the surface (against its normals): the surface is
    /// the outside of the wall.
    Inward,
    /// All of it in front of the surface: the surface is the inside.
    Outward,
}

/// How a closed surface object (a curve network whose patches close up)
/// prints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClosedSurfaces {
    /// As the solid it encloses (what the README's styled box shows).
    #[default]
    Fill,
    /// Hollow: a wall of the thickness inside the surface, with a sealed
    /// void (print with a drain hole, or use `Fill`).
    Shell,
}

/// Settings of [`super::printable`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PrintSettings {
    /// Wall thickness of thickened surfaces, in model units (metres):
    /// 0.002 (2 mm) by default, enough for FDM and resin printers.
    pub wall_thickness: f64,
    /// Where the wall lies relative to an open surface.
    pub shell_offset: ShellOffset,
    /// How closed surface objects print.
    pub closed_surfaces: ClosedSurfaces,
    /// Precision of the file to be written ([`Precision::of_format`]).
    pub precision: Precision,
    /// Coordinates beyond this magnitude (model units) are refused:
    /// 1e6 (a thousand kilometres) by default.
    pub max_abs_coordinate: f64,
}

impl Default for PrintSettings {
    fn default() -> Self {
        Self {
            wall_thickness: 0.002,
            shell_offset: ShellOffset::Centered,
            closed_surfaces: ClosedSurfaces::Fill,
            precision: Precision::F32,
            max_abs_coordinate: 1e6,
        }
    }
}

impl PrintSettings {
    /// The settings for a file at `precision`, the rest default.
    pub fn for_precision(precision: Precision) -> Self {
        Self {
            precision,
            ..Self::default()
        }
    }

    /// Refuses non-finite and out-of-range values, naming the field.
    pub fn validate(&self) -> Result<(), PrintError> {
        let bad = |field: &'static str, value: f64, reason: &'static str| {
            Err(PrintError::Settings {
                field,
                value,
                reason,
            })
        };
        if !(self.wall_thickness.is_finite() && self.wall_thickness > 0.0) {
            return bad(
                "wall_thickness",
                self.wall_thickness,
                "must be a positive finite length",
            );
        }
        if self.wall_thickness > 1.0 {
            return bad(
                "wall_thickness",
                self.wall_thickness,
                "is over a metre; the model is in metres (2 mm is 0.002)",
            );
        }
        if !(self.max_abs_coordinate.is_finite() && self.max_abs_coordinate > 0.0)
            || self.max_abs_coordinate > self.precision.max_finite() / 4.0
        {
            return bad(
                "max_abs_coordinate",
                self.max_abs_coordinate,
                "must be positive, finite and well inside the precision's range",
            );
        }
        Ok(())
    }
}
