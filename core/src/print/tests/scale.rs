//! [`PrintSettings::scale`]: the printed model is the document scaled
//! about the origin, with walls of the true thickness; bad scales are
//! refused by name; [`crate::print::BedFit::print_scale`] fits.

use crate::math::fm::DetMath as _;
use crate::mesh::TriMesh;
use crate::print::{
    printable, PrintError, PrintPart, PrintSettings, PrintedSize, Printer, PrinterPreset, Treatment,
};
use crate::solid::{tessellate, SolidShape};

/// A flat square of side `side` in the z = 0 plane (an open surface).
fn square(side: f64) -> TriMesh {
    let h = side / 2.0;
    TriMesh {
        positions: vec![[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..TriMesh::default()
    }
}

fn part<'a>(id: u32, surface: bool, mesh: &'a TriMesh) -> PrintPart<'a> {
    PrintPart {
        id,
        kind: if surface { "curve_network" } else { "solid" },
        surface,
        mesh,
    }
}

#[test]
fn a_scaled_print_scales_the_solid_and_keeps_the_wall_thickness() {
    let ball = tessellate(&SolidShape::Sphere { radius: 0.1 }, 48).unwrap();
    let sheet = square(0.2);
    let parts = [part(1, false, &ball), part(2, true, &sheet)];
    let full = printable(&parts[..1], &PrintSettings::default()).unwrap();
    let settings = PrintSettings {
        scale: 0.25,
        ..PrintSettings::default()
    };
    let quarter = printable(&parts[..1], &settings).unwrap();
    // Volumes in model units (m³): the solid scales by s³.
    let (v1, v4) = (full.mesh.signed_volume(), quarter.mesh.signed_volume());
    assert!(
        (v4 / v1 - 0.25f64.fpowi(3)).abs() < 1e-4,
        "solid volume ratio {} (want 1/64)",
        v4 / v1
    );
    let e1 = full.report.size().unwrap().extent_mm();
    let e4 = quarter.report.size().unwrap().extent_mm();
    for k in 0..3 {
        assert!(
            (e4[k] - e1[k] / 4.0).abs() < 0.01,
            "extent {k}: {e4:?} vs {e1:?}"
        );
    }

    // The sheet's wall stays 2 mm thick: its slab is (0.2 s)² by 2 mm.
    let slab = printable(&parts[1..], &settings).unwrap();
    match &slab.report.parts[0].treatment {
        Treatment::Thickened { thickness, .. } => assert_eq!(*thickness, 0.002),
        t => panic!("the sheet was not thickened: {t:?}"),
    }
    let want = (0.2 * 0.25f64).fpowi(2) * 0.002;
    let got = slab.mesh.signed_volume();
    assert!(
        (got / want - 1.0).abs() < 0.01,
        "slab volume {got} (want {want})"
    );
    let e = slab.report.size().unwrap().extent_mm();
    assert!(
        (e[0] - 50.0).abs() < 0.01 && (e[2] - 2.0).abs() < 0.01,
        "slab extent {e:?} mm"
    );
}

#[test]
fn a_bad_scale_is_refused_by_name() {
    let ball = tessellate(&SolidShape::Sphere { radius: 0.1 }, 16).unwrap();
    for scale in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-4, 1e4] {
        let settings = PrintSettings {
            scale,
            ..PrintSettings::default()
        };
        match printable(&[part(1, false, &ball)], &settings) {
            Err(PrintError::Settings { field: "scale", .. }) => {}
            other => panic!("scale {scale}: {other:?}"),
        }
    }
}

#[test]
fn the_print_scale_of_a_model_too_big_for_the_bed_fits_it() {
    let mk4 = Printer::new(PrinterPreset::default(), None).unwrap();
    // 2 m across, like the sculpted bust: 1 m either side of the origin.
    for half in [1.0, 0.3, 0.126, 37.0] {
        let size = PrintedSize::new([[-half, -half, -half], [half, half, half]], None);
        let s = size.fit(&mk4).print_scale();
        let scaled = PrintedSize::new([[-half * s, -half * s, -half * s], [half * s; 3]], None);
        assert!(
            scaled.fit(&mk4).fits,
            "{half} m at {s}: {}",
            scaled.fit(&mk4)
        );
        assert!(s > 0.0 && s <= 1.0 && (s * 1000.0).fract() == 0.0, "{s}");
    }
    let small = PrintedSize::new([[0.0; 3], [0.05; 3]], None);
    assert_eq!(small.fit(&mk4).print_scale(), 1.0);
}
