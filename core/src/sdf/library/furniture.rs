//! Furniture families (paper 2 §6.2's chair task and the COSEG chair
//! parts of its dataset): legs, seats, backs, bases and brackets.
//!
//! Long function: `entries` is a table (one entry per component, each a
//! name and a closure building its shape), not logic; split by family it
//! would only scatter the catalogue.

use crate::math::fm::DetMath as _;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::kit::*;
use super::{Category, Entry};
use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

use Category::*;
use SolidShape::*;

fn square_section() -> Vec<[f64; 2]> {
    vec![[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]]
}

fn leg_cabriole(d: Detail) -> TriMesh {
    let m = d.stations(32);
    let (mut path, mut radii) = (Vec::new(), Vec::new());
    for i in 0..=m {
        let t = i as f64 / m as f64;
        // Knee out, ankle in, foot out: an S in the XZ plane.
        let x = 0.035 * (PI * t).fsin() * (1.0 - 2.0 * t) - 0.01 * t;
        path.push(DVec3::new(x, 0.0, 0.06 + 0.39 * t));
        radii.push(0.016 + 0.016 * t * t + 0.006 * (PI * t).fsin());
    }
    let shaft = sweep(&round_section(d.segments()), &path, &radii, DVec3::Y, false);
    let foot = solid_at(
        Ellipsoid {
            radii: [0.032, 0.032, 0.04],
        },
        d,
        [0.0, 0.0, 0.05],
        NO_ROT,
    );
    union(&[shaft, foot])
}

fn leg_hairpin(d: Detail) -> TriMesh {
    // Down the left rod, round the bend at the floor, up the right rod.
    let mut path = vec![DVec3::new(-0.06, 0.0, 0.45)];
    path.extend(arc_xz([0.0, 0.03], 0.015, PI, TAU, d.stations(12)));
    path.push(DVec3::new(0.06, 0.0, 0.45));
    tube(&path, 0.006, d.segments().min(16), DVec3::Y)
}

fn seat_saddle(d: Detail) -> TriMesh {
    let h = DVec3::new(0.2, 0.21, 0.035);
    implicit(
        |p| {
            let dip = 0.03 * (1.0 - (p.x / 0.2).fpowi(2)) - 0.02 * (p.y / 0.21).fpowi(2);
            rounded_box(p + DVec3::new(0.0, 0.0, dip), h, 0.03)
        },
        DVec3::new(-0.21, -0.22, -0.07),
        DVec3::new(0.21, 0.22, 0.07),
        d,
    )
}

fn back_slatted(d: Detail) -> TriMesh {
    let b = |size: [f64; 3], at: [f64; 3]| solid_at(Box { size }, d, at, NO_ROT);
    let mut parts = vec![
        b([0.46, 0.04, 0.07], [0.0, 0.0, 0.465]),
        b([0.46, 0.04, 0.05], [0.0, 0.0, 0.025]),
    ];
    for i in 0..5 {
        parts.push(b(
            [0.05, 0.025, 0.46],
            [-0.18 + 0.09 * i as f64, 0.0, 0.245],
        ));
    }
    union(&parts)
}

fn back_curved(_d: Detail) -> TriMesh {
    let k = 24;
    let (r0, r1, a) = (0.6, 0.57, 0.4);
    let mut poly = Vec::new();
    for i in 0..=k {
        let t = -a + 2.0 * a * i as f64 / k as f64;
        poly.push([r0 * t.fsin(), r0 * t.fcos() - r0]);
    }
    for i in (0..=k).rev() {
        let t = -a + 2.0 * a * i as f64 / k as f64;
        poly.push([r1 * t.fsin(), r1 * t.fcos() - r0]);
    }
    extrude(&poly, 0.0, 0.42)
}

fn back_ladder(d: Detail) -> TriMesh {
    let post = |x: f64| {
        solid_at(
            Cylinder {
                radius: 0.022,
                height: 0.55,
            },
            d,
            [x, 0.0, 0.275],
            NO_ROT,
        )
    };
    let rail = |z: f64| {
        solid_at(
            Box {
                size: [0.42, 0.02, 0.05],
            },
            d,
            [0.0, 0.0, z],
            NO_ROT,
        )
    };
    union(&[post(-0.21), post(0.21), rail(0.2), rail(0.33), rail(0.46)])
}

fn back_spindle(d: Detail) -> TriMesh {
    let mut parts = vec![
        solid_at(
            Box {
                size: [0.46, 0.05, 0.06],
            },
            d,
            [0.0, 0.0, 0.47],
            NO_ROT,
        ),
        solid_at(
            Box {
                size: [0.46, 0.05, 0.04],
            },
            d,
            [0.0, 0.0, 0.02],
            NO_ROT,
        ),
    ];
    for i in 0..6 {
        parts.push(solid_at(
            Cylinder {
                radius: 0.012,
                height: 0.46,
            },
            d,
            [-0.19 + 0.076 * i as f64, 0.0, 0.245],
            NO_ROT,
        ));
    }
    union(&parts)
}

/// A plate in the XZ plane (thickness along Y) of outline `poly`.
fn plate_xz(poly: &[[f64; 2]], thickness: f64) -> TriMesh {
    rotated(
        extrude(poly, -thickness / 2.0, thickness / 2.0),
        rot([1.0, 0.0, 0.0], FRAC_PI_2),
    )
}

fn back_oval(d: Detail) -> TriMesh {
    let n = d.segments() * 2;
    let poly: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = TAU * i as f64 / n as f64;
            [0.22 * a.fcos(), 0.27 * a.fsin()]
        })
        .collect();
    plate_xz(&poly, 0.03)
}

fn back_arched(d: Detail) -> TriMesh {
    let mut poly = vec![[0.22, 0.0]];
    for p in arc([0.0, 0.3], 0.22, 0.0, PI, d.stations(24)) {
        poly.push(p);
    }
    poly.push([-0.22, 0.0]);
    plate_xz(&poly, 0.035)
}

fn base_tripod(d: Detail) -> TriMesh {
    let mut parts = vec![solid_at(
        Cylinder {
            radius: 0.05,
            height: 0.1,
        },
        d,
        [0.0, 0.0, 0.07],
        NO_ROT,
    )];
    for k in 0..3 {
        let a = TAU * k as f64 / 3.0;
        let foot = solid_at(
            Box {
                size: [0.28, 0.04, 0.035],
            },
            d,
            [0.14, 0.0, 0.0175],
            NO_ROT,
        );
        parts.push(rotated(foot, rot([0.0, 0.0, 1.0], a)));
    }
    union(&parts)
}

fn base_cross(d: Detail) -> TriMesh {
    let bar = |a: f64| {
        rotated(
            solid_at(
                Box {
                    size: [0.5, 0.05, 0.04],
                },
                d,
                [0.0, 0.0, 0.02],
                NO_ROT,
            ),
            rot([0.0, 0.0, 1.0], a),
        )
    };
    union(&[
        bar(0.0),
        bar(FRAC_PI_2),
        solid_at(
            Cylinder {
                radius: 0.05,
                height: 0.1,
            },
            d,
            [0.0, 0.0, 0.05],
            NO_ROT,
        ),
    ])
}

fn l_profile(a: f64, b: f64, t: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [a, 0.0], [a, t], [t, t], [t, b], [0.0, b]]
}

fn bracket_gusset(_: Detail) -> TriMesh {
    let l = extrude(&l_profile(0.1, 0.1, 0.01), 0.0, 0.04);
    let g = extrude(
        &[[0.005, 0.005], [0.085, 0.005], [0.005, 0.085]],
        0.016,
        0.024,
    );
    union(&[l, g])
}

fn bracket_shelf(d: Detail) -> TriMesh {
    let l = extrude(&l_profile(0.12, 0.1, 0.008), 0.0, 0.04);
    let hole = |at: [f64; 3], q: [f64; 4]| {
        solid_at(
            Cylinder {
                radius: 0.006,
                height: 0.05,
            },
            d,
            at,
            q,
        )
    };
    let up = rot([1.0, 0.0, 0.0], FRAC_PI_2);
    let side = rot([0.0, 1.0, 0.0], FRAC_PI_2);
    difference(
        &l,
        &[
            hole([0.05, 0.0, 0.02], up),
            hole([0.095, 0.0, 0.02], up),
            hole([0.0, 0.055, 0.02], side),
        ],
    )
}

fn bracket_corner(d: Detail) -> TriMesh {
    let p = |size: [f64; 3], at: [f64; 3]| solid_at(Box { size }, d, at, NO_ROT);
    union(&[
        p([0.08, 0.08, 0.008], [0.04, 0.04, 0.004]),
        p([0.08, 0.008, 0.08], [0.04, 0.004, 0.04]),
        p([0.008, 0.08, 0.08], [0.004, 0.04, 0.04]),
    ])
}

/// The furniture entries.
pub(super) fn entries() -> Vec<Entry> {
    vec![
        // Legs.
        Entry {
            name: "leg_tapered",
            category: Leg,
            build: |d| {
                lathe(
                    &[[0.0, 0.0], [0.016, 0.0], [0.028, 0.45], [0.0, 0.45]],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "leg_turned",
            category: Leg,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.02, 0.0],
                        [0.02, 0.05],
                        [0.03, 0.07],
                        [0.018, 0.1],
                        [0.022, 0.2],
                        [0.032, 0.26],
                        [0.022, 0.32],
                        [0.026, 0.4],
                        [0.035, 0.42],
                        [0.035, 0.45],
                        [0.0, 0.45],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "leg_hex",
            category: Leg,
            build: |_| extrude(&regular(6, 0.026, 0.0), 0.0, 0.45),
        },
        Entry {
            name: "leg_cabriole",
            category: Leg,
            build: leg_cabriole,
        },
        Entry {
            name: "leg_hairpin",
            category: Leg,
            build: leg_hairpin,
        },
        Entry {
            name: "leg_bun_foot",
            category: Leg,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.04, 0.0],
                        [0.055, 0.015],
                        [0.06, 0.035],
                        [0.052, 0.055],
                        [0.03, 0.07],
                        [0.016, 0.075],
                        [0.016, 0.11],
                        [0.0, 0.11],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "leg_splayed",
            category: Leg,
            build: |d| {
                let m = d.stations(8);
                let path: Vec<DVec3> = (0..=m)
                    .map(|i| DVec3::new(0.07, 0.0, 0.45) * (i as f64 / m as f64))
                    .collect();
                let radii: Vec<f64> = (0..=m)
                    .map(|i| 0.014 + 0.01 * i as f64 / m as f64)
                    .collect();
                sweep(&square_section(), &path, &radii, DVec3::Y, false)
            },
        },
        // Seats.
        Entry {
            name: "seat_round",
            category: Seat,
            build: |d| {
                let mut p = vec![[0.0, 0.0]];
                p.extend(arc(
                    [0.19, 0.02],
                    0.02,
                    -FRAC_PI_2,
                    FRAC_PI_2,
                    d.stations(9),
                ));
                p.push([0.0, 0.04]);
                lathe(&p, d.segments() * 2)
            },
        },
        Entry {
            name: "seat_cushion",
            category: Seat,
            build: |d| {
                let h = DVec3::new(0.22, 0.22, 0.05);
                implicit(|p| rounded_box(p, h, 0.04), -h, h, d)
            },
        },
        Entry {
            name: "seat_saddle",
            category: Seat,
            build: seat_saddle,
        },
        Entry {
            name: "seat_bench",
            category: Seat,
            build: |d| extrude(&rounded_rect(0.9, 0.3, 0.04, d.stations(6)), 0.0, 0.04),
        },
        Entry {
            name: "seat_stool",
            category: Seat,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.15, 0.0],
                        [0.17, 0.025],
                        [0.17, 0.05],
                        [0.155, 0.07],
                        [0.0, 0.07],
                    ],
                    d.segments() * 2,
                )
            },
        },
        // Backs.
        Entry {
            name: "back_slatted",
            category: Back,
            build: back_slatted,
        },
        Entry {
            name: "back_curved",
            category: Back,
            build: back_curved,
        },
        Entry {
            name: "back_ladder",
            category: Back,
            build: back_ladder,
        },
        Entry {
            name: "back_spindle",
            category: Back,
            build: back_spindle,
        },
        Entry {
            name: "back_oval",
            category: Back,
            build: back_oval,
        },
        Entry {
            name: "back_arched",
            category: Back,
            build: back_arched,
        },
        // Bases.
        Entry {
            name: "base_round",
            category: Base,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.2, 0.0],
                        [0.2, 0.02],
                        [0.17, 0.04],
                        [0.0, 0.04],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "base_square",
            category: Base,
            build: |d| extrude(&rounded_rect(0.4, 0.4, 0.03, d.stations(6)), 0.0, 0.04),
        },
        Entry {
            name: "base_pedestal",
            category: Base,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.18, 0.0],
                        [0.18, 0.02],
                        [0.1, 0.04],
                        [0.05, 0.08],
                        [0.035, 0.15],
                        [0.035, 0.38],
                        [0.06, 0.4],
                        [0.06, 0.42],
                        [0.0, 0.42],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "base_tripod",
            category: Base,
            build: base_tripod,
        },
        Entry {
            name: "base_cross",
            category: Base,
            build: base_cross,
        },
        Entry {
            name: "base_stepped",
            category: Base,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.2, 0.0],
                        [0.2, 0.02],
                        [0.15, 0.02],
                        [0.15, 0.04],
                        [0.1, 0.04],
                        [0.1, 0.06],
                        [0.0, 0.06],
                    ],
                    d.segments() * 2,
                )
            },
        },
        // Brackets.
        Entry {
            name: "bracket_l",
            category: Bracket,
            build: |_| extrude(&l_profile(0.1, 0.1, 0.01), 0.0, 0.04),
        },
        Entry {
            name: "bracket_t",
            category: Bracket,
            build: |_| {
                extrude(
                    &[
                        [-0.06, 0.09],
                        [-0.06, 0.1],
                        [0.06, 0.1],
                        [0.06, 0.09],
                        [0.005, 0.09],
                        [0.005, 0.0],
                        [-0.005, 0.0],
                        [-0.005, 0.09],
                    ],
                    0.0,
                    0.04,
                )
            },
        },
        Entry {
            name: "bracket_u",
            category: Bracket,
            build: |_| {
                extrude(
                    &[
                        [-0.05, 0.0],
                        [0.05, 0.0],
                        [0.05, 0.06],
                        [0.04, 0.06],
                        [0.04, 0.01],
                        [-0.04, 0.01],
                        [-0.04, 0.06],
                        [-0.05, 0.06],
                    ],
                    0.0,
                    0.04,
                )
            },
        },
        Entry {
            name: "bracket_z",
            category: Bracket,
            build: |_| {
                extrude(
                    &[
                        [0.0, 0.0],
                        [0.05, 0.0],
                        [0.05, 0.07],
                        [0.1, 0.07],
                        [0.1, 0.08],
                        [0.04, 0.08],
                        [0.04, 0.01],
                        [0.0, 0.01],
                    ],
                    0.0,
                    0.04,
                )
            },
        },
        Entry {
            name: "bracket_gusset",
            category: Bracket,
            build: bracket_gusset,
        },
        Entry {
            name: "bracket_shelf",
            category: Bracket,
            build: bracket_shelf,
        },
        Entry {
            name: "bracket_corner",
            category: Bracket,
            build: bracket_corner,
        },
    ]
}
