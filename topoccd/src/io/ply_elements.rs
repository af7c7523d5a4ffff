//! The elements of a PLY mesh as `ply-rs-bw` fills them: a vertex's coordinates, a face's
//! index list, and a sink for elements we skip.

use super::{IoError, Location};
use ply_rs_bw::ply::{PropertyAccess, PropertyAccessResult};
use std::path::Path;

/// The names under which a face lists its vertex indices.
pub(super) const INDEX_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// The coordinates of one `vertex` element.
#[derive(Default)]
pub(super) struct PlyVertex(pub(super) [f64; 3]);

impl PlyVertex {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.0[axis] = value;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// The index list of one `face` element: its length and its first three entries.
#[derive(Default)]
pub(super) struct PlyFace {
    len: usize,
    first: [i64; 3],
}

impl PlyFace {
    fn store<T: Copy + Into<i64>>(&mut self, name: &str, list: &[T]) -> PropertyAccessResult {
        if !INDEX_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        self.len = list.len();
        for (slot, &value) in self.first.iter_mut().zip(list) {
            *slot = value.into();
        }
        PropertyAccessResult::Set
    }

    /// The face as a triangle of valid vertex indices.
    pub(super) fn triangle(
        &self,
        location: &dyn Fn() -> Location,
        vertices: usize,
        name: &Path,
    ) -> Result<[u32; 3], IoError> {
        if self.len != 3 {
            return Err(IoError::NotTriangle {
                path: name.to_path_buf(),
                location: location(),
                vertices: self.len,
            });
        }
        let mut triangle = [0u32; 3];
        for (slot, &index) in triangle.iter_mut().zip(&self.first) {
            *slot = u32::try_from(index)
                .ok()
                .filter(|&i| (i as usize) < vertices)
                .ok_or_else(|| IoError::IndexOutOfRange {
                    path: name.to_path_buf(),
                    location: location(),
                    index,
                    vertices,
                })?;
        }
        Ok(triangle)
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        Self::default()
    }
    fn set_list_char(&mut self, name: &str, list: Vec<i8>) -> PropertyAccessResult {
        self.store(name, &list)
    }
    fn set_list_uchar(&mut self, name: &str, list: Vec<u8>) -> PropertyAccessResult {
        self.store(name, &list)
    }
    fn set_list_short(&mut self, name: &str, list: Vec<i16>) -> PropertyAccessResult {
        self.store(name, &list)
    }
    fn set_list_ushort(&mut self, name: &str, list: Vec<u16>) -> PropertyAccessResult {
        self.store(name, &list)
    }
    fn set_list_int(&mut self, name: &str, list: Vec<i32>) -> PropertyAccessResult {
        self.store(name, &list)
    }
    fn set_list_uint(&mut self, name: &str, list: Vec<u32>) -> PropertyAccessResult {
        self.store(name, &list)
    }
}

/// An element we do not need: every property is read and dropped.
pub(super) struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}
