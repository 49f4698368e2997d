//! Mesh readers on garbage: random bytes and mutated or truncated valid
//! files never panic; they return a mesh or a typed error.

use proptest::prelude::*;
use shapewright::mesh::{read_obj, read_stl, validate, write_obj, write_stl};
use shapewright::solid::{tessellate, SolidShape};

fn valid_files() -> (Vec<u8>, Vec<u8>) {
    let m = tessellate(
        &SolidShape::Torus {
            major_radius: 1.0,
            minor_radius: 0.3,
        },
        12,
    )
    .unwrap();
    let (mut obj, mut stl) = (Vec::new(), Vec::new());
    write_obj(&m, &mut obj).unwrap();
    write_stl(&m, &mut stl).unwrap();
    (obj, stl)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        let _ = read_obj(&bytes);
        let _ = read_stl(&bytes);
    }

    #[test]
    fn mutated_files_never_panic(cut in 0.0f64..1.0, flips in prop::collection::vec((0.0f64..1.0, any::<u8>()), 0..8)) {
        let (obj, stl) = valid_files();
        for file in [obj, stl] {
            let mut f = file[..(file.len() as f64 * cut) as usize].to_vec();
            for (at, b) in &flips {
                if !f.is_empty() {
                    let i = ((f.len() - 1) as f64 * at) as usize;
                    f[i] = *b;
                }
            }
            for m in [read_obj(&f), read_stl(&f)].into_iter().flatten() {
                // Whatever was read is a mesh the validator can judge.
                let _ = validate(&m, &Default::default());
            }
        }
    }
}
