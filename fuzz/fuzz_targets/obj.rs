//! The OBJ reader on arbitrary bytes: a mesh with indices in range, or an error; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = topoccd::io::read_obj_from(data, Path::new("fuzz.obj")) {
        let n = mesh.positions.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
    }
});
