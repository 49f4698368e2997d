//! Wheels, more primitives and organic shapes (paper 2 §3: "simple
//! geometric primitives, animal models and chair components"; its users'
//! snail, flower and Pikachu-on-a-dog scenes need wheels and blobs).

use crate::math::fm::DetMath as _;
use std::f64::consts::{FRAC_PI_2, TAU};

use super::kit::*;
use super::{Category, Entry};
use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::solid::SolidShape;

use Category::*;
use SolidShape::*;

fn wheel_tyre(d: Detail) -> TriMesh {
    // A rounded-rectangle cross-section around (0.16, 0): tread and walls.
    let section: Vec<[f64; 2]> = rounded_rect(0.08, 0.07, 0.025, d.stations(8))
        .into_iter()
        .map(|[r, z]| [0.16 + r, z])
        .collect();
    lathe_ring(&section, d.segments() * 2)
}

fn wheel_spoked(d: Detail) -> TriMesh {
    let rim = lathe_ring(
        &[[0.2, -0.02], [0.2, 0.02], [0.175, 0.02], [0.175, -0.02]],
        d.segments() * 2,
    );
    let mut parts = vec![
        rim,
        solid_at(
            Cylinder {
                radius: 0.035,
                height: 0.05,
            },
            d,
            [0.0; 3],
            NO_ROT,
        ),
    ];
    for k in 0..6 {
        let spoke = solid_at(
            Cylinder {
                radius: 0.008,
                height: 0.17,
            },
            d,
            [0.0, 0.0, 0.1],
            NO_ROT,
        );
        // Lay the spoke along +x, then turn it to its place.
        let spoke = rotated(spoke, rot([0.0, 1.0, 0.0], FRAC_PI_2));
        parts.push(rotated(spoke, rot([0.0, 0.0, 1.0], TAU * k as f64 / 6.0)));
    }
    union(&parts)
}

fn wheel_caster(d: Detail) -> TriMesh {
    let axle = rot([1.0, 0.0, 0.0], FRAC_PI_2);
    let p = |size: [f64; 3], at: [f64; 3]| solid_at(Box { size }, d, at, NO_ROT);
    union(&[
        solid_at(
            Cylinder {
                radius: 0.05,
                height: 0.03,
            },
            d,
            [0.0, 0.0, 0.05],
            axle,
        ),
        p([0.03, 0.008, 0.08], [0.0, 0.021, 0.075]),
        p([0.03, 0.008, 0.08], [0.0, -0.021, 0.075]),
        p([0.04, 0.05, 0.008], [0.0, 0.0, 0.115]),
        solid_at(
            Cylinder {
                radius: 0.008,
                height: 0.04,
            },
            d,
            [0.0, 0.0, 0.135],
            NO_ROT,
        ),
        solid_at(
            Cylinder {
                radius: 0.006,
                height: 0.05,
            },
            d,
            [0.0, 0.0, 0.05],
            axle,
        ),
    ])
}

fn wheel_gear(d: Detail) -> TriMesh {
    let mut outline = Vec::new();
    // 20 teeth: each a trapezoid between root and tip circles.
    let (n, root, tip) = (20, 0.18, 0.2);
    for i in 0..n {
        let a = TAU * i as f64 / n as f64;
        let w = TAU / n as f64;
        for (f, r) in [(0.0, root), (0.2, tip), (0.5, tip), (0.7, root)] {
            let t = a + w * f;
            outline.push([r * t.fcos(), r * t.fsin()]);
        }
    }
    let gear = extrude(&outline, -0.02, 0.02);
    difference(
        &gear,
        &[solid_at(
            Cylinder {
                radius: 0.03,
                height: 0.06,
            },
            d,
            [0.0; 3],
            NO_ROT,
        )],
    )
}

fn organic_drop(d: Detail) -> TriMesh {
    implicit(
        |p| {
            let s = dist(&Sphere { radius: 0.12 }, p, [0.0, 0.0, 0.0]);
            let c = dist(
                &Cone {
                    radius: 0.09,
                    height: 0.24,
                },
                p,
                [0.0, 0.0, 0.14],
            );
            smin(s, c, 0.06)
        },
        DVec3::new(-0.13, -0.13, -0.13),
        DVec3::new(0.13, 0.13, 0.27),
        d,
    )
}

fn organic_pebble(d: Detail) -> TriMesh {
    implicit(
        |p| {
            let e = dist(
                &Ellipsoid {
                    radii: [0.2, 0.14, 0.08],
                },
                p,
                [0.0; 3],
            );
            let bump = dist(&Sphere { radius: 0.07 }, p, [0.09, 0.05, 0.03]);
            smin(e, bump, 0.05)
        },
        DVec3::new(-0.21, -0.15, -0.09),
        DVec3::new(0.21, 0.15, 0.11),
        d,
    )
}

fn organic_peanut(d: Detail) -> TriMesh {
    implicit(
        |p| {
            let a = dist(&Sphere { radius: 0.12 }, p, [-0.11, 0.0, 0.0]);
            let b = dist(&Sphere { radius: 0.13 }, p, [0.11, 0.0, 0.0]);
            smin(a, b, 0.08)
        },
        DVec3::new(-0.24, -0.14, -0.14),
        DVec3::new(0.25, 0.14, 0.14),
        d,
    )
}

/// The wheel, primitive and organic entries.
pub(super) fn entries() -> Vec<Entry> {
    vec![
        // Wheels.
        Entry {
            name: "wheel_disc",
            category: Wheel,
            build: |d| {
                lathe(
                    &[
                        [0.0, -0.035],
                        [0.03, -0.035],
                        [0.04, -0.025],
                        [0.15, -0.025],
                        [0.19, -0.02],
                        [0.2, 0.0],
                        [0.19, 0.02],
                        [0.15, 0.025],
                        [0.04, 0.025],
                        [0.03, 0.035],
                        [0.0, 0.035],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "wheel_tyre",
            category: Wheel,
            build: wheel_tyre,
        },
        Entry {
            name: "wheel_spoked",
            category: Wheel,
            build: wheel_spoked,
        },
        Entry {
            name: "wheel_caster",
            category: Wheel,
            build: wheel_caster,
        },
        Entry {
            name: "wheel_gear",
            category: Wheel,
            build: wheel_gear,
        },
        Entry {
            name: "wheel_pulley",
            category: Wheel,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.15, 0.0],
                        [0.15, 0.01],
                        [0.12, 0.03],
                        [0.15, 0.05],
                        [0.15, 0.06],
                        [0.0, 0.06],
                    ],
                    d.segments() * 2,
                )
            },
        },
        // Primitives.
        Entry {
            name: "prism_hex",
            category: Primitive,
            build: |_| extrude(&regular(6, 0.2, 0.0), -0.15, 0.15),
        },
        Entry {
            name: "pyramid",
            category: Primitive,
            build: |_| lathe(&[[0.0, 0.0], [0.2, 0.0], [0.0, 0.3]], 4),
        },
        Entry {
            name: "wedge",
            category: Primitive,
            build: |_| extrude(&[[-0.2, 0.0], [0.2, 0.0], [-0.2, 0.2]], -0.1, 0.1),
        },
        Entry {
            name: "tube",
            category: Primitive,
            build: |d| {
                lathe_ring(
                    &[[0.2, -0.2], [0.2, 0.2], [0.15, 0.2], [0.15, -0.2]],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "star_prism",
            category: Primitive,
            build: |_| extrude(&star(5, 0.2, 0.09), -0.04, 0.04),
        },
        // Organic.
        Entry {
            name: "organic_drop",
            category: Organic,
            build: organic_drop,
        },
        Entry {
            name: "organic_pebble",
            category: Organic,
            build: organic_pebble,
        },
        Entry {
            name: "organic_peanut",
            category: Organic,
            build: organic_peanut,
        },
    ]
}
