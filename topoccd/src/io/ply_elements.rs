//! The elements of a PLY mesh as `ply-rs-bw` fills them: a vertex's coordinates, a face's or a
//! triangle strip's index list, and a sink for elements we skip.

use super::faces::RESTART;
use super::{IoError, Location};
use crate::alloc::{grow, try_collect, AllocError};
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

/// The index list of one `face` or `tristrips` element.
#[derive(Default)]
pub(super) struct PlyFace {
    len: usize,
    /// The first three entries, so that a triangle needs no allocation of its own.
    first: [i64; 3],
    /// All entries when there are more than three.
    all: Vec<i64>,
    /// The allocation for `all` that failed, if one did (reported by the readers of the face).
    failed: Option<AllocError>,
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
        if list.len() > 3 {
            match try_collect(list.iter().map(|&v| v.into()), "face indices") {
                Ok(all) => self.all = all,
                Err(e) => self.failed = Some(e),
            }
        }
        PropertyAccessResult::Set
    }

    /// The entries, in `out` cleared and grown to hold them.
    fn entries(&self, name: &Path, out: &mut Vec<u32>) -> Result<&[i64], IoError> {
        out.clear();
        let failed = self
            .failed
            .map_or_else(|| grow(out, self.len, "face indices"), Err);
        failed.map_err(|e| IoError::memory(name, e))?;
        Ok(if self.len > 3 {
            &self.all
        } else {
            &self.first[..self.len]
        })
    }

    /// The face's corners (at least three), checked against the vertex count, into `out`.
    pub(super) fn corners(
        &self,
        location: &dyn Fn() -> Location,
        vertices: usize,
        name: &Path,
        out: &mut Vec<u32>,
    ) -> Result<(), IoError> {
        if self.len < 3 {
            return Err(IoError::NotTriangle {
                path: name.to_path_buf(),
                location: location(),
                vertices: self.len,
            });
        }
        for &index in self.entries(name, out)? {
            out.push(check_index(index, location, vertices, name)?);
        }
        Ok(())
    }

    /// The strip's ids checked against the vertex count, a negative id (-1, or the largest
    /// value of an unsigned list) becoming [`RESTART`], into `out`.
    pub(super) fn strip(
        &self,
        location: &dyn Fn() -> Location,
        vertices: usize,
        name: &Path,
        out: &mut Vec<u32>,
    ) -> Result<(), IoError> {
        for &index in self.entries(name, out)? {
            out.push(match index {
                -1 | 0xFFFF_FFFF => RESTART,
                _ => check_index(index, location, vertices, name)?,
            });
        }
        Ok(())
    }
}

fn check_index(
    index: i64,
    location: &dyn Fn() -> Location,
    vertices: usize,
    name: &Path,
) -> Result<u32, IoError> {
    u32::try_from(index)
        .ok()
        .filter(|&i| (i as usize) < vertices)
        .ok_or_else(|| IoError::IndexOutOfRange {
            path: name.to_path_buf(),
            location: location(),
            index,
            vertices,
        })
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

/// The two vertex indices of one `edge` element (`vertex1`, `vertex2`: any integer type).
#[derive(Default)]
pub(super) struct PlyEdge([Option<i64>; 2]);

impl PlyEdge {
    fn set(&mut self, name: &str, value: i64) -> PropertyAccessResult {
        let end = match name {
            "vertex1" => 0,
            "vertex2" => 1,
            _ => return PropertyAccessResult::Ignored,
        };
        self.0[end] = Some(value);
        PropertyAccessResult::Set
    }

    /// The edge's two vertices, checked against the vertex count.
    pub(super) fn ends(
        &self,
        location: &dyn Fn() -> Location,
        vertices: usize,
        name: &Path,
    ) -> Result<[u32; 2], IoError> {
        let [Some(a), Some(b)] = self.0 else {
            return Err(IoError::PlyElement {
                path: name.to_path_buf(),
                location: location(),
                message: "an edge needs the integer properties 'vertex1' and 'vertex2'".into(),
            });
        };
        Ok([
            check_index(a, location, vertices, name)?,
            check_index(b, location, vertices, name)?,
        ])
    }
}

impl PropertyAccess for PlyEdge {
    fn new() -> Self {
        Self::default()
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
}

/// An element we do not need: every property is read and dropped.
pub(super) struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}
