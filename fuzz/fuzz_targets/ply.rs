//! The PLY reader on arbitrary bytes: it must return a mesh or an error, never panic, hang or
//! allocate more than the input can justify. A mesh it returns must be consistent.
//!
//! The same bytes are also read as a file, where the reader knows the size and refuses counts
//! the file cannot hold right after the header: that check must never refuse a file the
//! reader would accept, and both ways must give the same mesh.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use topoccd::io::{read_ply, read_ply_from, IoError, Mesh};

fn scratch() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = Path::new("/dev/shm");
        let dir = if dir.is_dir() {
            dir.to_path_buf()
        } else {
            std::env::temp_dir()
        };
        dir.join(format!("topoccd-fuzz-{}.ply", std::process::id()))
    })
}

fn same(a: &Mesh, b: &Mesh) -> bool {
    let bits =
        |m: &Mesh| -> Vec<u64> { m.positions.iter().flatten().map(|c| c.to_bits()).collect() };
    a.triangles == b.triangles && bits(a) == bits(b)
}

fuzz_target!(|data: &[u8]| {
    let from_bytes = read_ply_from(data, Path::new("fuzz.ply"));
    if let Ok(mesh) = &from_bytes {
        let n = mesh.positions.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
    }
    let path = scratch();
    std::fs::write(path, data).expect("write the scratch file");
    let from_file = read_ply(path);
    match (&from_bytes, &from_file) {
        (Ok(a), Ok(b)) => assert!(same(a, b), "the file and the bytes give different meshes"),
        (Ok(_), Err(e)) => panic!("the file is refused but the bytes are read: {e}"),
        (Err(_), Ok(_)) => panic!("the file is read but the bytes are refused"),
        (Err(_), Err(IoError::CountsExceedFile { .. })) => {}
        (Err(a), Err(b)) => {
            // The same error, but for the file's name at the start of the message.
            let (a, b) = (a.to_string(), b.to_string());
            let path = path.display().to_string();
            assert_eq!(a.strip_prefix("fuzz.ply"), b.strip_prefix(path.as_str()));
        }
    }
});
