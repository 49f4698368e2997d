//! The printed size and the printer's bed (issue 31): [`Printer`] is the
//! document's build volume (set by the `set_printer` op, a preset or a
//! custom size), [`PrintedSize`] the model's bounding box in millimetres
//! and its volume in cm³, and [`BedFit`] whether it fits and, if not, by
//! how much along each axis.
//!
//! Choices:
//! - The model's z is up (as USD's `upAxis = "Z"` and the slicers' beds):
//!   x and y lie on the bed, z is the print's height. A model that fits
//!   only when turned a quarter turn on the bed counts as fitting (every
//!   slicer turns objects on the plate) and the fit says so.
//! - The size is the bounding box of what would print (the printable
//!   union; hosts that show it per edit use the objects' boxes, the same
//!   box without the union's cost).
//! - Presets are a few common printers' published build volumes; `custom`
//!   takes any size from 1 cm to 2 m per axis.

use std::fmt;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::PrintError;

/// A printer the document can name, with its build volume.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PrinterPreset {
    /// Prusa MK4 (and MK3S): 250 x 210 x 220 mm, the default.
    #[default]
    PrusaMk4,
    /// Prusa MINI: 180 x 180 x 180 mm.
    PrusaMini,
    /// Prusa XL: 360 x 360 x 360 mm.
    PrusaXl,
    /// Bambu Lab X1 (X1 Carbon, X1E): 256 x 256 x 256 mm.
    BambuX1,
    /// Bambu Lab P1 (P1P, P1S): 256 x 256 x 256 mm.
    BambuP1,
    /// Creality Ender 3 (V2, Pro): 220 x 220 x 250 mm.
    Ender3,
    /// Any other printer: give its build volume as `size`.
    Custom,
}

/// Smallest build volume side the document accepts, in metres.
pub const MIN_BED_SIDE: f64 = 0.01;
/// Largest build volume side the document accepts, in metres.
pub const MAX_BED_SIDE: f64 = 2.0;

impl PrinterPreset {
    /// Every preset with a size, in menu order.
    pub const ALL: [PrinterPreset; 6] = [
        Self::PrusaMk4,
        Self::PrusaMini,
        Self::PrusaXl,
        Self::BambuX1,
        Self::BambuP1,
        Self::Ender3,
    ];

    /// The build volume in metres (`None` for [`Self::Custom`]).
    pub fn size(self) -> Option<[f64; 3]> {
        Some(match self {
            Self::PrusaMk4 => [0.25, 0.21, 0.22],
            Self::PrusaMini => [0.18, 0.18, 0.18],
            Self::PrusaXl => [0.36, 0.36, 0.36],
            Self::BambuX1 | Self::BambuP1 => [0.256, 0.256, 0.256],
            Self::Ender3 => [0.22, 0.22, 0.25],
            Self::Custom => return None,
        })
    }

    /// The printer's name as people say it.
    pub fn label(self) -> &'static str {
        match self {
            Self::PrusaMk4 => "Prusa MK4",
            Self::PrusaMini => "Prusa MINI",
            Self::PrusaXl => "Prusa XL",
            Self::BambuX1 => "Bambu X1",
            Self::BambuP1 => "Bambu P1",
            Self::Ender3 => "Ender 3",
            Self::Custom => "custom printer",
        }
    }
}

/// The printer a document is for: a preset and its build volume.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Printer {
    /// Which printer.
    pub preset: PrinterPreset,
    /// Its build volume (x, y on the bed; z up), in metres.
    pub size: [f64; 3],
}

impl Default for Printer {
    fn default() -> Self {
        let preset = PrinterPreset::default();
        Self {
            preset,
            size: preset.size().unwrap_or([0.25, 0.21, 0.22]),
        }
    }
}

impl Printer {
    /// True for the default printer.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The printer of a `set_printer` op: a preset's own size, or a custom
    /// size; refuses a preset given a size, a custom printer without one,
    /// and sizes outside 1 cm..2 m, naming the field.
    pub fn new(preset: PrinterPreset, size: Option<[f64; 3]>) -> Result<Self, PrintError> {
        let size = match (preset.size(), size) {
            (Some(s), None) => s,
            (None, Some(s)) => s,
            (Some(_), Some(s)) => {
                return Err(PrintError::Settings {
                    field: "size",
                    value: s[0],
                    reason:
                        "a preset has its own build volume; give a size only with printer `custom`",
                })
            }
            (None, None) => {
                return Err(PrintError::Settings {
                    field: "size",
                    value: f64::NAN,
                    reason: "printer `custom` needs its build volume as size [x, y, z] in metres",
                })
            }
        };
        let p = Self { preset, size };
        p.validate()?;
        Ok(p)
    }

    /// Refuses a build volume side that is not finite or outside
    /// [`MIN_BED_SIDE`]..=[`MAX_BED_SIDE`].
    pub fn validate(&self) -> Result<(), PrintError> {
        for v in self.size {
            if !(v.is_finite() && (MIN_BED_SIDE..=MAX_BED_SIDE).contains(&v)) {
                return Err(PrintError::Settings {
                    field: "size",
                    value: v,
                    reason: "each side of the build volume must be between 0.01 m and 2 m; the model is in metres (250 mm is 0.25)",
                });
            }
        }
        Ok(())
    }

    /// `Prusa MK4 (250 x 210 x 220 mm)`.
    pub fn describe(&self) -> String {
        format!("{} ({})", self.preset.label(), mm3(self.size))
    }
}

/// `250 x 210 x 220 mm` for a size in metres.
pub fn mm3(size: [f64; 3]) -> String {
    let [x, y, z] = size.map(|v| v * 1e3);
    format!("{} x {} x {} mm", mm(x), mm(y), mm(z))
}

/// A length in mm as people read it: one decimal, none when whole.
fn mm(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    if r == r.trunc() {
        format!("{r:.0}")
    } else {
        format!("{r:.1}")
    }
}

/// The printed size of a model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PrintedSize {
    /// The bounding box's low corner, in metres.
    pub min: [f64; 3],
    /// The bounding box's high corner, in metres.
    pub max: [f64; 3],
    /// The enclosed volume in m³ (`None`: not known, e.g. before the
    /// union).
    pub volume: Option<f64>,
}

impl PrintedSize {
    /// The size of a bounding box `[min, max]` (metres), with a volume.
    pub fn new(bbox: [[f64; 3]; 2], volume: Option<f64>) -> Self {
        Self {
            min: bbox[0],
            max: bbox[1],
            volume,
        }
    }

    /// The box's extent along x, y, z in metres.
    pub fn extent(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.max[k] - self.min[k])
    }

    /// The extent in millimetres.
    pub fn extent_mm(&self) -> [f64; 3] {
        self.extent().map(|v| v * 1e3)
    }

    /// The volume in cm³.
    pub fn volume_cm3(&self) -> Option<f64> {
        self.volume.map(|v| v * 1e6)
    }

    /// How the model fits `printer`'s build volume.
    pub fn fit(&self, printer: &Printer) -> BedFit {
        let e = self.extent();
        let over = |size: [f64; 3], a: usize, b: usize| {
            [e[a] - size[0], e[b] - size[1], e[2] - size[2]].map(|d| d.max(0.0) * 1e3)
        };
        let as_is = over(printer.size, 0, 1);
        let turned = over(printer.size, 1, 0);
        let fits = as_is == [0.0; 3];
        let fits_turned = !fits && turned == [0.0; 3];
        // The largest uniform scale that fits, as it lies or turned.
        let b = printer.size;
        let ratio = |bed: f64, ext: f64| bed / ext.max(f64::MIN_POSITIVE);
        let as_is_scale = ratio(b[0], e[0]).min(ratio(b[1], e[1]));
        let turned_scale = ratio(b[0], e[1]).min(ratio(b[1], e[0]));
        let scale = as_is_scale.max(turned_scale).min(ratio(b[2], e[2]));
        BedFit {
            printer: *printer,
            over_mm: as_is,
            fits: fits || fits_turned,
            turned: fits_turned,
            scale_to_fit: scale.min(1.0),
        }
    }
}

impl fmt::Display for PrintedSize {
    /// `352.14 x 201.30 x 180.20 mm, 55.213 cm³` (hundredths of a mm:
    /// what a slicer's own reading is compared with).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.extent_mm();
        write!(f, "{x:.2} x {y:.2} x {z:.2} mm")?;
        if let Some(v) = self.volume_cm3() {
            write!(f, ", {v:.3} cm³")?;
        }
        Ok(())
    }
}

/// Whether a model fits a printer's build volume.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BedFit {
    /// The printer.
    pub printer: Printer,
    /// How far the model sticks out of the build volume along x, y, z as
    /// it lies (millimetres; zero where it fits).
    pub over_mm: [f64; 3],
    /// True when it fits as it lies or turned a quarter turn on the bed.
    pub fits: bool,
    /// True when it fits only turned a quarter turn on the bed.
    pub turned: bool,
    /// The largest uniform scale (at most 1) at which it fits, turned or
    /// not.
    pub scale_to_fit: f64,
}

impl BedFit {
    /// `too big by x 12.3 mm, z 4.0 mm`, or empty when it fits.
    pub fn overhang(&self) -> String {
        if self.fits {
            return String::new();
        }
        format!("too big by {}", self.over_axes())
    }

    /// `x 12.3 mm, z 4.0 mm`: the axes along which it sticks out as it
    /// lies.
    pub fn over_axes(&self) -> String {
        let axes: Vec<String> = self
            .over_mm
            .iter()
            .zip(["x", "y", "z"])
            .filter(|(d, _)| **d > 0.0)
            .map(|(d, a)| format!("{a} {d:.1} mm"))
            .collect();
        axes.join(", ")
    }

    /// The scale to print at so that the model fits: [`Self::scale_to_fit`]
    /// rounded down to a tenth of a percent (a number a person can repeat),
    /// 1 when it fits, never below [`MIN_PRINT_SCALE`]
    /// ([`super::PrintSettings::scale`]).
    pub fn print_scale(&self) -> f64 {
        if self.fits {
            return 1.0;
        }
        floor_print_scale(self.scale_to_fit)
    }
}

/// The smallest [`super::PrintSettings::scale`]: a tenth of a percent.
pub const MIN_PRINT_SCALE: f64 = 1e-3;

/// `scale` rounded down to a tenth of a percent, never below
/// [`MIN_PRINT_SCALE`]: the scales a fit prints at.
pub fn floor_print_scale(scale: f64) -> f64 {
    ((scale * 1000.0).floor() / 1000.0).max(MIN_PRINT_SCALE)
}

impl fmt::Display for BedFit {
    /// `fits the Prusa MK4 (250 x 210 x 220 mm)` or `does NOT fit the
    /// Prusa MK4 (...): too big by x 12.3 mm; scale to 91% or pick a
    /// larger printer`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let printer = self.printer.describe();
        if self.fits && self.turned {
            write!(f, "fits the {printer} turned a quarter turn on the bed")
        } else if self.fits {
            write!(f, "fits the {printer}")
        } else {
            write!(
                f,
                "does NOT fit the {printer}: {}; scale it to {:.0}% or set a larger printer (set_printer)",
                self.overhang(),
                (self.scale_to_fit * 100.0).floor()
            )
        }
    }
}

/// What a host shows about the print after each edit (the headset's HUD,
/// Blender's History panel): one short line, and whether it is a warning.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PrintStatus {
    /// The model's size.
    pub size: PrintedSize,
    /// How it fits the document's printer.
    pub fit: BedFit,
}

impl PrintStatus {
    /// True when the model outgrows the printer (show it as a warning).
    pub fn warn(&self) -> bool {
        !self.fit.fits
    }

    /// `print 120 x 80 x 95 mm, fits Prusa MK4`, or `print 350 x 200 x
    /// 250 mm: too big for Prusa MK4 by x 100.0 mm, z 30.0 mm`.
    pub fn line(&self) -> String {
        let [x, y, z] = self.size.extent_mm();
        let label = self.fit.printer.preset.label();
        if self.fit.fits {
            let turned = if self.fit.turned { " turned" } else { "" };
            format!("print {x:.0} x {y:.0} x {z:.0} mm, fits {label}{turned}")
        } else {
            format!(
                "print {x:.0} x {y:.0} x {z:.0} mm: too big for {label} by {}",
                self.fit.over_axes()
            )
        }
    }
}

/// Set the printer the document is for (its build volume): a preset, or
/// `custom` with its size. Exports and the headset say when the model
/// does not fit it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SetPrinter {
    /// The printer: `prusa_mk4` (250 x 210 x 220 mm, the default),
    /// `prusa_mini`, `prusa_xl`, `bambu_x1`, `bambu_p1`, `ender3`, or
    /// `custom` with `size`.
    pub printer: PrinterPreset,
    /// A custom printer's build volume [x, y, z] in metres (each 0.01 to
    /// 2); only with `custom`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-unit" = "m"))]
    pub size: Option<[f64; 3]>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sized(x: f64, y: f64, z: f64) -> PrintedSize {
        PrintedSize::new([[0.0; 3], [x, y, z]], Some(x * y * z))
    }

    #[test]
    fn a_model_that_fits_and_one_that_does_not_say_by_how_much() {
        let mk4 = Printer::default();
        assert_eq!(mk4.describe(), "Prusa MK4 (250 x 210 x 220 mm)");
        let cube = sized(0.1, 0.1, 0.1);
        assert!(cube.fit(&mk4).fits);
        assert_eq!(
            cube.to_string(),
            "100.00 x 100.00 x 100.00 mm, 1000.000 cm³"
        );
        let teapot = sized(0.35, 0.2, 0.25);
        let fit = teapot.fit(&mk4);
        assert!(!fit.fits);
        assert_eq!(fit.over_mm.map(|v| v.round()), [100.0, 0.0, 30.0]);
        assert_eq!(fit.overhang(), "too big by x 100.0 mm, z 30.0 mm");
        assert!(fit.to_string().contains("scale it to 71%"), "{fit}");
        // Turned a quarter turn, a 200 x 240 mm plate fits 250 x 210.
        let long = sized(0.2, 0.24, 0.05);
        let fit = long.fit(&mk4);
        assert!(fit.fits && fit.turned, "{fit}");
        let status = PrintStatus {
            size: teapot,
            fit: teapot.fit(&mk4),
        };
        assert!(status.warn());
        assert_eq!(
            status.line(),
            "print 350 x 200 x 250 mm: too big for Prusa MK4 by x 100.0 mm, z 30.0 mm"
        );
    }

    #[test]
    fn presets_and_custom_sizes_are_checked() {
        let x1 = Printer::new(PrinterPreset::BambuX1, None).unwrap();
        assert_eq!(x1.size, [0.256; 3]);
        assert!(Printer::new(PrinterPreset::Custom, None).is_err());
        assert!(Printer::new(PrinterPreset::Ender3, Some([0.3; 3])).is_err());
        let bad = Printer::new(PrinterPreset::Custom, Some([250.0, 210.0, 220.0]));
        assert!(
            matches!(bad, Err(PrintError::Settings { field: "size", .. })),
            "{bad:?}"
        );
        let c = Printer::new(PrinterPreset::Custom, Some([0.3, 0.3, 0.4])).unwrap();
        assert_eq!(c.describe(), "custom printer (300 x 300 x 400 mm)");
        for p in PrinterPreset::ALL {
            Printer::new(p, None).unwrap();
        }
    }
}
