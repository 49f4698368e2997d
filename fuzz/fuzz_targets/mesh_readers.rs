//! STL (binary and ASCII), OBJ and PLY readers on any bytes: a mesh or a
//! typed error, never a panic, and no allocation beyond the input's size.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::mesh::{read_obj, read_ply, read_stl};

fuzz_target!(|data: &[u8]| {
    for mesh in [read_stl(data), read_obj(data), read_ply(data)]
        .into_iter()
        .flatten()
    {
        // What a reader returns is a usable mesh: indices in range.
        let n = mesh.positions.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        assert!(mesh.positions.iter().flatten().all(|x| x.is_finite()));
    }
});
