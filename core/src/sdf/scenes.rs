//! The paper's Table 1 scenes (Cube–Sphere, Chair, Cup; §6), built from
//! library components as the paper builds them: the workloads of the
//! bench (`examples/sdf_bench.rs`) and of the topology tests, defined once.

use super::csg::CsgOp;
use super::volume::{Component, Operand};
use crate::math::Transform;

fn lib(name: &str) -> Component {
    Component::Library { name: name.into() }
}

fn t(translate: [f64; 3], rotate: [f64; 4], scale: [f64; 3]) -> Transform {
    Transform {
        translate,
        rotate,
        scale,
    }
}

const ID: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// A Table 1 scene: its name, its operands in fusion order, and the
/// operand a drag moves in the bench.
pub struct Table1Scene {
    /// `cube_sphere`, `chair` or `cup`.
    pub name: &'static str,
    /// The operands, in fusion order.
    pub operands: Vec<Operand>,
    /// The operand the bench's drag frame moves.
    pub dragged: usize,
}

/// The three Table 1 scenes.
pub fn table1() -> Vec<Table1Scene> {
    let o = Operand::new;
    let s2 = 0.5f64.sqrt();
    let leg = |x: f64, y: f64| {
        o(
            lib("chair_leg"),
            CsgOp::Union,
            t([x, y, 0.22], ID, [1.0, 1.0, 1.1]),
        )
    };
    vec![
        Table1Scene {
            name: "cube_sphere",
            operands: vec![
                o(lib("box"), CsgOp::Union, t([0.0; 3], ID, [1.0; 3])),
                o(
                    lib("sphere"),
                    CsgOp::Union,
                    t([0.15, 0.1, 0.1], ID, [1.2; 3]),
                ),
            ],
            dragged: 1,
        },
        Table1Scene {
            name: "chair",
            operands: vec![
                o(
                    lib("chair_seat"),
                    CsgOp::Union,
                    t([0.0, 0.0, 0.455], ID, [1.0; 3]),
                ),
                leg(0.17, 0.17),
                leg(-0.17, 0.17),
                leg(0.17, -0.17),
                leg(-0.17, -0.17),
                o(
                    lib("chair_back"),
                    CsgOp::Union,
                    t([0.0, 0.178, 0.69], ID, [1.1; 3]),
                ),
            ],
            dragged: 5,
        },
        Table1Scene {
            // The library cylinder is 0.4 across and tall: 0.6 makes the
            // paper's cup body (radius 0.12, height 0.24).
            name: "cup",
            operands: vec![
                o(lib("cylinder"), CsgOp::Union, t([0.0; 3], ID, [0.6; 3])),
                o(
                    lib("cup_handle"),
                    CsgOp::Union,
                    t([0.17, 0.0, 0.0], [s2, 0.0, 0.0, s2], [0.38; 3]),
                ),
                o(
                    lib("cylinder"),
                    CsgOp::Subtract,
                    t([0.0, 0.0, 0.03], ID, [0.525, 0.525, 0.6]),
                ),
            ],
            dragged: 1,
        },
    ]
}
