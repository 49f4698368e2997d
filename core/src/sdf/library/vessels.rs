//! Vessel families (paper 2 §6.2's cup task, and the teapots, lamps and
//! kitchenware users build from its dataset): bodies, handles, spouts,
//! knobs, lids and lamp shades.
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

/// `profile` (from the axis outwards) closed by an arc around
/// `(0, cz)` of radius `r` from angle `a0` up to the axis.
fn capped(mut profile: Vec<[f64; 2]>, cz: f64, r: f64, a0: f64, k: usize) -> Vec<[f64; 2]> {
    let mut a = arc([0.0, cz], r, a0, FRAC_PI_2, k);
    a.pop();
    profile.extend(a);
    profile.push([0.0, cz + r]);
    profile
}

/// An open shell of revolution: the outer wall `outer` (bottom to top),
/// thickness `t` inwards (in r), closed into one loop.
fn shell(outer: &[[f64; 2]], t: f64) -> Vec<[f64; 2]> {
    let mut loop_ = outer.to_vec();
    loop_.extend(outer.iter().rev().map(|&[r, z]| [r - t, z]));
    loop_
}

fn handle_d(d: Detail) -> TriMesh {
    let path: Vec<DVec3> = rounded_rect(0.07, 0.12, 0.025, d.stations(8))
        .into_iter()
        .map(|[x, z]| DVec3::new(x + 0.035, 0.0, z))
        .collect();
    let radii = vec![0.011; path.len()];
    sweep(
        &round_section(d.segments().min(24)),
        &path,
        &radii,
        DVec3::Y,
        true,
    )
}

fn handle_c(d: Detail) -> TriMesh {
    let a = 100f64.to_radians();
    let path = arc_xz([0.0, 0.0], 0.05, a, -a, d.stations(24));
    tube(&path, 0.01, d.segments().min(24), DVec3::Y)
}

fn handle_bar(d: Detail) -> TriMesh {
    let k = d.stations(8);
    let mut path = vec![DVec3::new(0.0, 0.0, 0.0)];
    path.extend(arc_xz([0.02, 0.015], 0.02, PI, FRAC_PI_2, k));
    path.extend(arc_xz([0.13, 0.015], 0.02, FRAC_PI_2, 0.0, k));
    path.push(DVec3::new(0.15, 0.0, 0.0));
    tube(&path, 0.007, d.segments().min(16), DVec3::Y)
}

fn handle_t(d: Detail) -> TriMesh {
    union(&[
        solid_at(
            Capsule {
                radius: 0.014,
                length: 0.12,
            },
            d,
            [0.0, 0.0, 0.07],
            rot([0.0, 1.0, 0.0], FRAC_PI_2),
        ),
        solid_at(
            Cylinder {
                radius: 0.01,
                height: 0.07,
            },
            d,
            [0.0, 0.0, 0.035],
            NO_ROT,
        ),
    ])
}

fn handle_ear(d: Detail) -> TriMesh {
    let k = d.stations(20);
    let mut poly = arc([0.0, 0.0], 0.05, 0.0, PI, k);
    poly.extend(arc([0.0, 0.0], 0.028, PI, 0.0, k));
    extrude(&poly, -0.008, 0.008)
}

fn handle_teapot(d: Detail) -> TriMesh {
    let m = d.stations(40);
    let (mut path, mut radii) = (Vec::new(), Vec::new());
    for i in 0..m {
        let a = TAU * i as f64 / m as f64;
        path.push(DVec3::new(0.07 + 0.07 * a.fcos(), 0.0, 0.1 * a.fsin()));
        radii.push(0.015 + 0.004 * a.fcos());
    }
    sweep(
        &round_section(d.segments().min(24)),
        &path,
        &radii,
        DVec3::Y,
        true,
    )
}

fn tapered(path: &[DVec3], r0: f64, r1: f64, d: Detail) -> TriMesh {
    let m = path.len() - 1;
    let radii: Vec<f64> = (0..=m)
        .map(|i| r0 + (r1 - r0) * i as f64 / m as f64)
        .collect();
    sweep(
        &round_section(d.segments().min(32)),
        path,
        &radii,
        DVec3::Y,
        false,
    )
}

fn spout_curved(d: Detail) -> TriMesh {
    let path = arc_xz([0.2, 0.0], 0.2, PI, FRAC_PI_2 * 1.3, d.stations(24));
    tapered(&path, 0.03, 0.012, d)
}

fn spout_gooseneck(d: Detail) -> TriMesh {
    let m = d.stations(32);
    let path: Vec<DVec3> = (0..=m)
        .map(|i| {
            let t = i as f64 / m as f64;
            DVec3::new(
                0.12 * (3.0 * t * t - 2.0 * t * t * t),
                0.0,
                0.22 * t + 0.03 * (TAU * t).fsin(),
            )
        })
        .collect();
    tapered(&path, 0.025, 0.01, d)
}

fn spout_watering(d: Detail) -> TriMesh {
    union(&[
        lathe(
            &[[0.0, 0.0], [0.02, 0.0], [0.012, 0.3], [0.0, 0.3]],
            d.segments(),
        ),
        solid_at(
            Cylinder {
                radius: 0.04,
                height: 0.016,
            },
            d,
            [0.0, 0.0, 0.3],
            NO_ROT,
        ),
    ])
}

fn knob_fluted(d: Detail) -> TriMesh {
    union(&[
        extrude(&star(10, 0.035, 0.028), 0.02, 0.05),
        solid_at(
            Cylinder {
                radius: 0.01,
                height: 0.03,
            },
            d,
            [0.0, 0.0, 0.015],
            NO_ROT,
        ),
    ])
}

fn knob_toggle(d: Detail) -> TriMesh {
    union(&[
        solid_at(
            Cylinder {
                radius: 0.012,
                height: 0.04,
            },
            d,
            [0.0, 0.0, 0.02],
            NO_ROT,
        ),
        solid_at(
            Capsule {
                radius: 0.012,
                length: 0.07,
            },
            d,
            [0.0, 0.0, 0.045],
            rot([0.0, 1.0, 0.0], FRAC_PI_2),
        ),
    ])
}

fn knob_square(d: Detail) -> TriMesh {
    union(&[
        extrude(&rounded_rect(0.05, 0.05, 0.01, d.stations(6)), 0.02, 0.05),
        solid_at(
            Cylinder {
                radius: 0.01,
                height: 0.03,
            },
            d,
            [0.0, 0.0, 0.015],
            NO_ROT,
        ),
    ])
}

fn lid_pot(d: Detail) -> TriMesh {
    union(&[
        lathe(
            &[
                [0.0, 0.0],
                [0.17, 0.0],
                [0.17, 0.015],
                [0.2, 0.015],
                [0.2, 0.03],
                [0.0, 0.035],
            ],
            d.segments() * 2,
        ),
        solid_at(
            Torus {
                major_radius: 0.04,
                minor_radius: 0.01,
            },
            d,
            [0.0, 0.0, 0.05],
            rot([1.0, 0.0, 0.0], FRAC_PI_2),
        ),
    ])
}

/// The vessel entries.
pub(super) fn entries() -> Vec<Entry> {
    vec![
        // Bodies.
        Entry {
            name: "body_vase",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.06, 0.0],
                        [0.1, 0.05],
                        [0.11, 0.12],
                        [0.08, 0.22],
                        [0.045, 0.28],
                        [0.05, 0.32],
                        [0.0, 0.32],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "body_vase_shell",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.06, 0.0],
                        [0.1, 0.05],
                        [0.11, 0.12],
                        [0.08, 0.22],
                        [0.045, 0.28],
                        [0.05, 0.32],
                        [0.043, 0.32],
                        [0.038, 0.28],
                        [0.073, 0.22],
                        [0.102, 0.12],
                        [0.092, 0.055],
                        [0.055, 0.012],
                        [0.0, 0.012],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "body_bottle",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.07, 0.0],
                        [0.075, 0.01],
                        [0.075, 0.18],
                        [0.06, 0.23],
                        [0.022, 0.27],
                        [0.02, 0.32],
                        [0.024, 0.325],
                        [0.024, 0.34],
                        [0.0, 0.34],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "body_bowl",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.06, 0.0],
                        [0.14, 0.04],
                        [0.19, 0.09],
                        [0.2, 0.12],
                        [0.19, 0.12],
                        [0.18, 0.094],
                        [0.13, 0.052],
                        [0.05, 0.015],
                        [0.0, 0.015],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "body_mug_shell",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.1, 0.0],
                        [0.1, 0.2],
                        [0.09, 0.2],
                        [0.09, 0.012],
                        [0.0, 0.012],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "body_teapot",
            category: Body,
            build: |d| {
                let mut p = vec![[0.0, 0.0], [0.08, 0.0]];
                p.extend(arc([0.05, 0.09], 0.09, -1.2, 1.1, d.stations(16)));
                p.push([0.075, 0.19]);
                p.push([0.0, 0.19]);
                lathe(&p, d.segments())
            },
        },
        Entry {
            name: "body_pot",
            category: Body,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.14, 0.0],
                        [0.15, 0.01],
                        [0.15, 0.16],
                        [0.165, 0.17],
                        [0.165, 0.18],
                        [0.14, 0.18],
                        [0.14, 0.012],
                        [0.0, 0.012],
                    ],
                    d.segments() * 2,
                )
            },
        },
        // Handles.
        Entry {
            name: "handle_d",
            category: Handle,
            build: handle_d,
        },
        Entry {
            name: "handle_c",
            category: Handle,
            build: handle_c,
        },
        Entry {
            name: "handle_bar",
            category: Handle,
            build: handle_bar,
        },
        Entry {
            name: "handle_t",
            category: Handle,
            build: handle_t,
        },
        Entry {
            name: "handle_ear",
            category: Handle,
            build: handle_ear,
        },
        Entry {
            name: "handle_teapot",
            category: Handle,
            build: handle_teapot,
        },
        // Spouts.
        Entry {
            name: "spout_straight",
            category: Spout,
            build: |d| {
                lathe(
                    &[[0.0, 0.0], [0.03, 0.0], [0.012, 0.2], [0.0, 0.2]],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "spout_curved",
            category: Spout,
            build: spout_curved,
        },
        Entry {
            name: "spout_gooseneck",
            category: Spout,
            build: spout_gooseneck,
        },
        Entry {
            name: "spout_hollow",
            category: Spout,
            build: |d| {
                lathe_ring(
                    &[[0.03, 0.0], [0.014, 0.2], [0.009, 0.2], [0.024, 0.0]],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "spout_kettle",
            category: Spout,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.045, 0.0],
                        [0.028, 0.06],
                        [0.022, 0.085],
                        [0.03, 0.095],
                        [0.0, 0.095],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "spout_watering",
            category: Spout,
            build: spout_watering,
        },
        // Knobs.
        Entry {
            name: "knob_round",
            category: Knob,
            build: |d| {
                let a0 = -65f64.to_radians();
                lathe(
                    &capped(
                        vec![[0.0, 0.0], [0.03 * a0.fcos(), 0.0]],
                        0.055,
                        0.03,
                        a0,
                        d.stations(16),
                    ),
                    d.segments(),
                )
            },
        },
        Entry {
            name: "knob_disc",
            category: Knob,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.01, 0.0],
                        [0.01, 0.02],
                        [0.035, 0.022],
                        [0.04, 0.03],
                        [0.04, 0.04],
                        [0.035, 0.045],
                        [0.0, 0.045],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "knob_cone",
            category: Knob,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.01, 0.0],
                        [0.01, 0.02],
                        [0.035, 0.025],
                        [0.008, 0.06],
                        [0.0, 0.062],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "knob_mushroom",
            category: Knob,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.01, 0.0],
                        [0.01, 0.02],
                        [0.04, 0.025],
                        [0.045, 0.035],
                        [0.035, 0.05],
                        [0.015, 0.058],
                        [0.0, 0.06],
                    ],
                    d.segments(),
                )
            },
        },
        Entry {
            name: "knob_knurled",
            category: Knob,
            build: |d| {
                let n = match d {
                    Detail::Full => 144,
                    Detail::Preview => 24,
                };
                lathe_mod(
                    &[
                        [0.0, 0.0],
                        [0.012, 0.0],
                        [0.012, 0.02],
                        [0.032, 0.02],
                        [0.032, 0.05],
                        [0.0, 0.05],
                    ],
                    n,
                    |a| 1.0 + 0.04 * (12.0 * a).fcos(),
                )
            },
        },
        Entry {
            name: "knob_fluted",
            category: Knob,
            build: knob_fluted,
        },
        Entry {
            name: "knob_toggle",
            category: Knob,
            build: knob_toggle,
        },
        Entry {
            name: "knob_square",
            category: Knob,
            build: knob_square,
        },
        // Lids.
        Entry {
            name: "lid_flat",
            category: Lid,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.17, 0.0],
                        [0.17, 0.02],
                        [0.2, 0.02],
                        [0.2, 0.035],
                        [0.0, 0.035],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "lid_dome",
            category: Lid,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.17, 0.0],
                        [0.17, 0.015],
                        [0.2, 0.015],
                        [0.2, 0.025],
                        [0.18, 0.03],
                        [0.16, 0.06],
                        [0.12, 0.085],
                        [0.06, 0.1],
                        [0.0, 0.105],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "lid_knob",
            category: Lid,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.17, 0.0],
                        [0.17, 0.015],
                        [0.2, 0.015],
                        [0.2, 0.025],
                        [0.18, 0.03],
                        [0.16, 0.06],
                        [0.12, 0.085],
                        [0.06, 0.1],
                        [0.015, 0.104],
                        [0.015, 0.12],
                        [0.03, 0.13],
                        [0.025, 0.145],
                        [0.0, 0.148],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "lid_conical",
            category: Lid,
            build: |d| {
                lathe(
                    &[
                        [0.0, 0.0],
                        [0.17, 0.0],
                        [0.17, 0.015],
                        [0.2, 0.015],
                        [0.2, 0.025],
                        [0.02, 0.12],
                        [0.0, 0.125],
                    ],
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "lid_pot",
            category: Lid,
            build: lid_pot,
        },
        Entry {
            name: "lid_jar",
            category: Lid,
            build: |d| {
                let mut p = vec![[0.0, 0.0], [0.1, 0.0]];
                for i in 1..8 {
                    p.push([if i % 2 == 1 { 0.105 } else { 0.1 }, 0.005 * i as f64]);
                }
                p.push([0.1, 0.04]);
                p.push([0.0, 0.04]);
                lathe(&p, d.segments() * 2)
            },
        },
        // Lamp shades: open shells of revolution (genus 1).
        Entry {
            name: "shade_drum",
            category: Shade,
            build: |d| lathe_ring(&shell(&[[0.15, 0.0], [0.15, 0.2]], 0.005), d.segments() * 2),
        },
        Entry {
            name: "shade_cone",
            category: Shade,
            build: |d| lathe_ring(&shell(&[[0.2, 0.0], [0.08, 0.18]], 0.005), d.segments() * 2),
        },
        Entry {
            name: "shade_empire",
            category: Shade,
            build: |d| lathe_ring(&shell(&[[0.18, 0.0], [0.11, 0.2]], 0.005), d.segments() * 2),
        },
        Entry {
            name: "shade_bell",
            category: Shade,
            build: |d| {
                lathe_ring(
                    &shell(
                        &[
                            [0.2, 0.0],
                            [0.18, 0.03],
                            [0.15, 0.08],
                            [0.13, 0.14],
                            [0.12, 0.2],
                            [0.08, 0.24],
                        ],
                        0.005,
                    ),
                    d.segments() * 2,
                )
            },
        },
        Entry {
            name: "shade_dome",
            category: Shade,
            build: |d| {
                let top = 80f64.to_radians();
                let k = d.stations(16);
                let mut p = arc([0.0, 0.0], 0.2, 0.0, top, k);
                p.extend(arc([0.0, 0.0], 0.194, top, 0.0, k));
                lathe_ring(&p, d.segments() * 2)
            },
        },
        Entry {
            name: "shade_pleated",
            category: Shade,
            build: |d| {
                let n = match d {
                    Detail::Full => 192,
                    Detail::Preview => 32,
                };
                lathe_ring_mod(&shell(&[[0.2, 0.0], [0.1, 0.2]], 0.005), n, |a| {
                    1.0 + 0.05 * (16.0 * a).fcos()
                })
            },
        },
    ]
}
