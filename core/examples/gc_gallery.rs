//! Writes a few generalized cylinders as STL files for rendering: a bent
//! and twisted vase (container), a bent shell pipe, a solid with polygon
//! and rectangle sections. Usage: `cargo run --example gc_gallery -- OUTDIR`.

use std::fs::File;
use std::io::BufWriter;

use glam::DVec3;
use shapewright::gc::{
    fit_spine, mesh_gc, ClosedEnd, Gc, KeySection, Profile, Resolution, ShapeType,
};
use shapewright::mesh::{validate, write_stl};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    std::fs::create_dir_all(&out)?;
    let sec = |p: Profile, v: f64| KeySection::new(p, v);

    // Vase: container, bent and twisted.
    let spine = fit_spine(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 1.4)], DVec3::Y)?;
    let mut vase = Gc::new(
        spine,
        vec![
            sec(Profile::Circle { radius: 0.28 }, 0.0),
            sec(
                Profile::Polygon {
                    sides: 6,
                    radius: 0.5,
                },
                0.3,
            ),
            sec(
                Profile::Polygon {
                    sides: 6,
                    radius: 0.36,
                },
                0.6,
            ),
            sec(Profile::Circle { radius: 0.16 }, 0.85),
            sec(Profile::Circle { radius: 0.24 }, 1.0),
        ],
        ShapeType::Container {
            thickness: 0.03,
            closed_end: ClosedEnd::Start,
        },
        Resolution::DEFAULT,
    )?;
    vase.twist(2, 0.9)?;
    let k = vase.key_points();
    vase.bend(3, k[3] + DVec3::new(0.25, 0.0, 0.0))?;
    vase.bend(4, k[4] + DVec3::new(0.4, 0.0, -0.05))?;

    // Shell: a bent pipe with an elliptic section.
    let spine = fit_spine(
        &[
            DVec3::ZERO,
            DVec3::new(0.4, 0.0, 0.6),
            DVec3::new(1.2, 0.0, 0.8),
        ],
        DVec3::Y,
    )?;
    let shell = Gc::new(
        spine,
        vec![
            sec(Profile::Circle { radius: 0.2 }, 0.0),
            sec(Profile::Ellipse { rx: 0.15, ry: 0.25 }, 0.5),
            sec(Profile::Circle { radius: 0.1 }, 1.0),
        ],
        ShapeType::Shell { thickness: 0.025 },
        Resolution::DEFAULT,
    )?;

    // Container: an open box-like tray from rectangles to a circle.
    let spine = fit_spine(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 0.7)], DVec3::Y)?;
    let mut tray = Gc::new(
        spine,
        vec![
            sec(
                Profile::Rectangle {
                    width: 0.8,
                    height: 0.6,
                },
                0.0,
            ),
            sec(
                Profile::Rectangle {
                    width: 0.9,
                    height: 0.7,
                },
                0.5,
            ),
            sec(Profile::Circle { radius: 0.45 }, 1.0),
        ],
        ShapeType::Container {
            thickness: 0.04,
            closed_end: ClosedEnd::Start,
        },
        Resolution::DEFAULT,
    )?;
    tray.insert_section(0.75)?;
    tray.resize(3, 1.15)?;

    // Solid: twisted square column.
    let spine = fit_spine(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 1.5)], DVec3::Y)?;
    let mut column = Gc::new(
        spine,
        vec![
            sec(
                Profile::Polygon {
                    sides: 4,
                    radius: 0.3,
                },
                0.0,
            ),
            sec(
                Profile::Polygon {
                    sides: 4,
                    radius: 0.3,
                },
                0.5,
            ),
            sec(
                Profile::Polygon {
                    sides: 4,
                    radius: 0.3,
                },
                1.0,
            ),
        ],
        ShapeType::Solid,
        Resolution::DEFAULT,
    )?;
    column.twist(1, 1.2)?;

    for (name, gc) in [
        ("vase", &vase),
        ("shell", &shell),
        ("tray", &tray),
        ("column", &column),
    ] {
        let m = mesh_gc(gc)?;
        let r = validate(&m, &Default::default());
        println!(
            "{name}: {} triangles, closed manifold {}, genus {:?}, volume {:.5}",
            m.triangle_count(),
            r.is_closed_manifold(),
            r.genus,
            r.signed_volume
        );
        write_stl(
            &m,
            &mut BufWriter::new(File::create(format!("{out}/{name}.stl"))?),
        )?;
    }
    Ok(())
}
