//! Helpers shared by the `io_*` tests: temporary directories, the shared data, and a PLY encoder
//! independent of the crate's writer (any encoding, coordinate and index type, extra data).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use topoccd::io::Mesh;

/// A fresh directory under the system temp dir, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("topoccd-{tag}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes `bytes` to `name` in the directory and returns the path.
    pub fn file(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.path(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create dir");
        }
        std::fs::write(&path, bytes).expect("write temp file");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The directory of a shared whole-step scene, or `None` (with a loud message) if the shared
/// data is absent.
pub fn scene_dir(scene: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/scenes")
        .join(scene);
    if dir.is_dir() {
        Some(dir)
    } else {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent (see the README)"
        );
        eprintln!(
            "\n!!!!! SKIPPED: shared data not found at {} -- this test checked NOTHING !!!!!\n",
            dir.display()
        );
        None
    }
}

/// Byte order of a PLY file written by [`encode_ply`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enc {
    Ascii,
    Little,
    Big,
}

/// How [`encode_ply`] lays a mesh out.
#[derive(Clone, Copy, Debug)]
pub struct PlySpec {
    pub enc: Enc,
    /// `double` coordinates, else `float`.
    pub double: bool,
    /// Type of the list length (`uchar`, `int`, ...).
    pub count_ty: &'static str,
    /// Type of the indices (`int`, `uint`, `ushort`, ...).
    pub index_ty: &'static str,
    /// `vertex_indices` or `vertex_index`.
    pub list_name: &'static str,
    /// Add normals, colours, an extra element and extra face properties.
    pub extras: bool,
}

impl Default for PlySpec {
    fn default() -> Self {
        PlySpec {
            enc: Enc::Little,
            double: true,
            count_ty: "uchar",
            index_ty: "int",
            list_name: "vertex_indices",
            extras: false,
        }
    }
}

/// Encodes faces given as index lists (any length), so that malformed faces can be written.
pub fn encode_ply_faces(positions: &[[f64; 3]], faces: &[Vec<i64>], spec: &PlySpec) -> Vec<u8> {
    let format = match spec.enc {
        Enc::Ascii => "ascii",
        Enc::Little => "binary_little_endian",
        Enc::Big => "binary_big_endian",
    };
    let coord = if spec.double { "double" } else { "float" };
    let mut h = format!(
        "ply\nformat {format} 1.0\ncomment test file\nelement vertex {}\n",
        positions.len()
    );
    for axis in ["x", "y", "z"] {
        h += &format!("property {coord} {axis}\n");
    }
    if spec.extras {
        h += "property float nx\nproperty float ny\nproperty float nz\n";
        h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        h += "element material 2\nproperty float shininess\nproperty list uchar int tags\n";
    }
    h += &format!("element face {}\n", faces.len());
    if spec.extras {
        h += "property uchar flags\n";
    }
    h += &format!(
        "property list {} {} {}\n",
        spec.count_ty, spec.index_ty, spec.list_name
    );
    if spec.extras {
        h += "property list uchar float texcoord\n";
    }
    h += "end_header\n";
    let mut out = h.into_bytes();
    let mut w = Writer {
        out: &mut out,
        enc: spec.enc,
    };
    for p in positions {
        for &c in p {
            w.float(spec.double, c);
        }
        if spec.extras {
            for c in [0.0, 0.0, 1.0] {
                w.float(false, c);
            }
            for c in [255, 128, 0] {
                w.int("uchar", c);
            }
        }
        w.end();
    }
    if spec.extras {
        for m in 0..2 {
            w.float(false, 0.5 * f64::from(m));
            w.int("uchar", 2);
            w.int("int", 7);
            w.int("int", -7);
            w.end();
        }
    }
    for f in faces {
        if spec.extras {
            w.int("uchar", 9);
        }
        w.int(spec.count_ty, f.len() as i64);
        for &i in f {
            w.int(spec.index_ty, i);
        }
        if spec.extras {
            w.int("uchar", 2);
            w.float(false, 0.25);
            w.float(false, 0.75);
        }
        w.end();
    }
    out
}

/// Encodes a mesh (see [`encode_ply_faces`]).
pub fn encode_ply(mesh: &Mesh, spec: &PlySpec) -> Vec<u8> {
    let positions: Vec<[f64; 3]> = mesh.positions.clone();
    let faces: Vec<Vec<i64>> = mesh
        .triangles
        .iter()
        .map(|t| t.iter().map(|&i| i64::from(i)).collect())
        .collect();
    encode_ply_faces(&positions, &faces, spec)
}

struct Writer<'a> {
    out: &'a mut Vec<u8>,
    enc: Enc,
}

impl Writer<'_> {
    fn bytes<const N: usize>(&mut self, le: [u8; N], be: [u8; N], text: String) {
        match self.enc {
            Enc::Little => self.out.extend_from_slice(&le),
            Enc::Big => self.out.extend_from_slice(&be),
            Enc::Ascii => {
                self.out.extend_from_slice(text.as_bytes());
                self.out.push(b' ');
            }
        }
    }

    fn float(&mut self, double: bool, v: f64) {
        if double {
            self.bytes(v.to_le_bytes(), v.to_be_bytes(), format!("{v:?}"));
        } else {
            let v = v as f32;
            self.bytes(v.to_le_bytes(), v.to_be_bytes(), format!("{v:?}"));
        }
    }

    fn int(&mut self, ty: &str, v: i64) {
        let t = v.to_string();
        match ty {
            "char" => self.bytes((v as i8).to_le_bytes(), (v as i8).to_be_bytes(), t),
            "uchar" => self.bytes((v as u8).to_le_bytes(), (v as u8).to_be_bytes(), t),
            "short" => self.bytes((v as i16).to_le_bytes(), (v as i16).to_be_bytes(), t),
            "ushort" => self.bytes((v as u16).to_le_bytes(), (v as u16).to_be_bytes(), t),
            "int" => self.bytes((v as i32).to_le_bytes(), (v as i32).to_be_bytes(), t),
            "uint" => self.bytes((v as u32).to_le_bytes(), (v as u32).to_be_bytes(), t),
            other => panic!("unknown PLY integer type {other}"),
        }
    }

    fn end(&mut self) {
        if self.enc == Enc::Ascii {
            self.out.pop();
            self.out.push(b'\n');
        }
    }
}

/// Positions compared bit for bit.
pub fn same_bits(a: &Mesh, b: &Mesh) -> bool {
    a.triangles == b.triangles
        && a.positions.len() == b.positions.len()
        && a.positions
            .iter()
            .zip(&b.positions)
            .all(|(p, q)| p.iter().zip(q).all(|(x, y)| x.to_bits() == y.to_bits()))
}

/// The header of a PLY file as text (up to and including `end_header`).
pub fn ply_header(path: &Path) -> String {
    let bytes = std::fs::read(path).expect("read PLY");
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("PLY has end_header")
        + 11;
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}
