//! [`PrintSettings`]: what the printable path needs to know besides the
//! objects; [`PrintSetup`]: the part of it the document stores (set by the
//! `set_wall_thickness`, `set_self_intersection_policy` and `set_printer`
//! ops, saved with the document, replayed like any op).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{PrintError, Printer};
use crate::mesh::{FileUnit, MeshFormat, Precision};

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
    /// [`crate::doc::print_document`] takes it from the document's
    /// [`PrintSetup`]; [`super::printable`] uses it as given.
    pub wall_thickness: f64,
    /// Where the wall lies relative to an open surface.
    pub shell_offset: ShellOffset,
    /// How closed surface objects print.
    pub closed_surfaces: ClosedSurfaces,
    /// Precision of the file to be written ([`Precision::of_format`]).
    pub precision: Precision,
    /// Unit of the file to be written ([`MeshFormat::unit`]): the model is
    /// rounded and validated as the file stores it (float32 millimetres
    /// for STL and 3MF).
    pub unit: FileUnit,
    /// Coordinates beyond this magnitude (model units) are refused:
    /// 1e6 (a thousand kilometres) by default.
    pub max_abs_coordinate: f64,
    /// Uniform scale of the printed model, 1 (true size) by default: every
    /// object is scaled about the origin before it is thickened, so a
    /// surface printed at 10% still gets walls of `wall_thickness`, the
    /// thickness a printer needs. Hosts set it from
    /// [`super::BedFit::scale_to_fit`] (`export --scale-to-fit`).
    pub scale: f64,
}

impl Default for PrintSettings {
    fn default() -> Self {
        Self {
            wall_thickness: 0.002,
            shell_offset: ShellOffset::Centered,
            closed_surfaces: ClosedSurfaces::Fill,
            precision: Precision::F32,
            unit: FileUnit::Millimetre,
            max_abs_coordinate: 1e6,
            scale: 1.0,
        }
    }
}

impl PrintSettings {
    /// The settings for a file in metres at `precision`, the rest default
    /// (use [`Self::for_format`] for a mesh file).
    pub fn for_precision(precision: Precision) -> Self {
        Self {
            precision,
            unit: FileUnit::Metre,
            ..Self::default()
        }
    }

    /// The settings for writing `format`: its precision and unit, the rest
    /// default. The default settings are STL's (float32 millimetres).
    pub fn for_format(format: MeshFormat) -> Self {
        Self {
            precision: Precision::of_format(format),
            unit: format.unit(),
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
            || self.max_abs_coordinate > self.precision.max_finite_in(self.unit) / 4.0
        {
            return bad(
                "max_abs_coordinate",
                self.max_abs_coordinate,
                "must be positive, finite and well inside the precision's range",
            );
        }
        if !(self.scale.is_finite() && (super::MIN_PRINT_SCALE..=1e3).contains(&self.scale)) {
            return bad(
                "scale",
                self.scale,
                "must be between 0.001 and 1000 (1 prints at true size)",
            );
        }
        Ok(())
    }
}

/// Smallest wall thickness the document setting accepts, in metres
/// (0.1 mm: about the finest wall a resin printer makes).
pub const MIN_WALL_THICKNESS: f64 = 1e-4;
/// Largest wall thickness the document setting accepts, in metres (10 cm:
/// beyond it a "wall" is a block; a larger value is a unit mistake).
pub const MAX_WALL_THICKNESS: f64 = 0.1;

/// What an edit that would make its object pass through itself does (a GC
/// spine bent tighter than its sections, a warp that folds a sculpt). The
/// issue leaves the choice to the user; the default is [`Self::Flag`]:
/// modelling is never blocked mid-gesture and every print exit names the
/// object and why. `refuse` catches the fold at the edit, while the object
/// is in the user's hand, but costs an exact self-intersection search on
/// every GC or sculpt commit (a median of 6x the edit itself on the teapot trace
/// in the bench) and refused 85 of the 300 random GCs `gc_proptest` makes
/// (issue 17): a choice for users who print every object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SelfIntersectionPolicy {
    /// The edit is refused with [`super::PrintError::SelfIntersecting`]
    /// naming the object; the document is unchanged. An object that
    /// already intersected itself before the edit (loaded from a file made
    /// under `flag`) may still be edited.
    Refuse,
    /// The edit applies; the object is not printable until fixed, and
    /// every print exit (`info`, export, save) names it and says why.
    #[default]
    Flag,
}

/// The print settings a document stores. Default: 2 mm walls, folding
/// edits flagged, a 250 x 210 x 220 mm printer (Prusa MK4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PrintSetup {
    /// Wall thickness of surfaces made solid for printing, in metres, in
    /// [`MIN_WALL_THICKNESS`]..=[`MAX_WALL_THICKNESS`].
    pub wall_thickness: f64,
    /// What an edit that would fold its object does.
    pub on_self_intersection: SelfIntersectionPolicy,
    /// The printer the model is for (its build volume); omitted from the
    /// saved document while it is the default, so documents that never
    /// set it keep their bytes and hashes.
    #[serde(skip_serializing_if = "Printer::is_default")]
    pub printer: Printer,
}

impl Default for PrintSetup {
    fn default() -> Self {
        Self {
            wall_thickness: PrintSettings::default().wall_thickness,
            on_self_intersection: SelfIntersectionPolicy::default(),
            printer: Printer::default(),
        }
    }
}

impl PrintSetup {
    /// True for the default setup (documents that never changed it
    /// serialize and hash as before it existed).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Refuses a wall thickness that is not finite or outside its range,
    /// naming the field.
    pub fn validate(&self) -> Result<(), PrintError> {
        let t = self.wall_thickness;
        if !(t.is_finite() && (MIN_WALL_THICKNESS..=MAX_WALL_THICKNESS).contains(&t)) {
            return Err(PrintError::Settings {
                field: "wall_thickness",
                value: t,
                reason: "must be between 0.0001 m (0.1 mm) and 0.1 m; the model is in metres (2 mm is 0.002)",
            });
        }
        self.printer.validate()
    }

    /// `settings` with this document's wall thickness.
    pub fn apply_to(&self, settings: &PrintSettings) -> PrintSettings {
        PrintSettings {
            wall_thickness: self.wall_thickness,
            ..*settings
        }
    }
}

/// Set the document's wall thickness for printing surfaces (curve
/// networks' patches, open sculpts) as solids.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SetWallThickness {
    /// The wall thickness in metres (2 mm is 0.002).
    #[schemars(range(min = 0.0001, max = 0.1), extend("x-unit" = "m"))]
    pub thickness: f64,
}

/// Choose what a GC or sculpt edit that would make its object pass
/// through itself does: refuse it (default) or apply it and flag the
/// object as not printable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SetSelfIntersectionPolicy {
    /// `refuse` (the edit fails, the document is unchanged) or `flag` (the
    /// edit applies; printing names the object until it is fixed).
    pub policy: SelfIntersectionPolicy,
}
