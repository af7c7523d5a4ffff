//! The faces of a file as the readers collect them: triangles kept as they are, polygons and
//! triangle strips split into triangles at the end (when every position is known), with the
//! map from triangles back to the faces of the file.

use super::polygon::{triangulate_polygon, PolygonSplit};
use super::{FaceOrigin, MeshNote};
use crate::alloc::{grow, try_collect, try_push, AllocError};

/// The index that restarts a triangle strip.
pub(super) const RESTART: u32 = u32::MAX;

/// A face recorded after the first polygon or strip: where its ids end in `FaceList::ids`.
#[derive(Clone, Copy)]
enum Record {
    Polygon(usize),
    Strip(usize),
}

/// The triangles and the face map (`None` if every face was a triangle) of
/// [`FaceList::finish`].
type FileTriangles = (Vec<[u32; 3]>, Option<Vec<FaceOrigin>>);

/// Collects the faces of a file in order. Every id handed in must already be checked against
/// the vertex count (except [`RESTART`] in strips).
#[derive(Default)]
pub(super) struct FaceList {
    /// The faces before the first polygon or strip: triangle `t` is face `t`.
    triangles: Vec<[u32; 3]>,
    /// From the first polygon or strip on, every face's ids, split in [`FaceList::finish`].
    ids: Vec<u32>,
    records: Vec<Record>,
}

impl FaceList {
    /// Adds a face with at least three corners.
    pub(super) fn polygon(&mut self, corners: &[u32]) -> Result<(), AllocError> {
        debug_assert!(corners.len() >= 3);
        if corners.len() == 3 && self.records.is_empty() {
            try_push(
                &mut self.triangles,
                [corners[0], corners[1], corners[2]],
                "triangles",
            )
        } else {
            self.record(corners, Record::Polygon)
        }
    }

    /// Adds a triangle strip record (ids, with [`RESTART`] between strips).
    pub(super) fn strip(&mut self, ids: &[u32]) -> Result<(), AllocError> {
        self.record(ids, Record::Strip)
    }

    fn record(&mut self, ids: &[u32], kind: fn(usize) -> Record) -> Result<(), AllocError> {
        grow(&mut self.ids, ids.len(), "face indices")?;
        self.ids.extend_from_slice(ids);
        try_push(&mut self.records, kind(self.ids.len()), "faces")
    }

    /// Splits the polygons and strips; returns the triangles, the face map (`None` if every
    /// face was a triangle) and a note for each kind of split that happened.
    pub(super) fn finish(
        self,
        positions: &[[f64; 3]],
        notes: &mut Vec<MeshNote>,
    ) -> Result<FileTriangles, AllocError> {
        let FaceList {
            mut triangles,
            ids,
            records,
        } = self;
        if records.is_empty() {
            return Ok((triangles, None));
        }
        let first_record = triangles.len();
        let mut origin: Vec<FaceOrigin> = try_collect(
            (0..first_record).map(|t| FaceOrigin {
                face: t as u32,
                sub: 0,
            }),
            "face map",
        )?;
        let mut split = Split::default();
        let mut start = 0;
        let mut scratch = Vec::new();
        for (r, record) in records.into_iter().enumerate() {
            let face = u32::try_from(first_record + r).unwrap_or(u32::MAX);
            scratch.clear();
            let end = match record {
                Record::Polygon(end) => {
                    split.polygon(
                        face,
                        triangulate_polygon(positions, &ids[start..end], &mut scratch),
                        scratch.len(),
                    );
                    end
                }
                Record::Strip(end) => {
                    split.strips += 1;
                    split.degenerate += decode_strip(&ids[start..end], &mut scratch)?;
                    split.strip_triangles += scratch.len();
                    end
                }
            };
            start = end;
            grow(&mut triangles, scratch.len(), "triangles")?;
            grow(&mut origin, scratch.len(), "face map")?;
            for (sub, &t) in scratch.iter().enumerate() {
                triangles.push(t);
                origin.push(FaceOrigin {
                    face,
                    sub: sub as u32,
                });
            }
        }
        split.notes(notes);
        Ok((triangles, Some(origin)))
    }
}

/// Counts of what [`FaceList::finish`] split.
#[derive(Default)]
struct Split {
    polygons: usize,
    non_convex: usize,
    irregular: usize,
    first_irregular: Option<u32>,
    polygon_triangles: usize,
    strips: usize,
    strip_triangles: usize,
    degenerate: usize,
}

impl Split {
    fn polygon(&mut self, face: u32, how: PolygonSplit, triangles: usize) {
        match how {
            PolygonSplit::Triangle => return,
            PolygonSplit::Fan => {}
            PolygonSplit::EarClipped => self.non_convex += 1,
            PolygonSplit::Irregular => {
                self.non_convex += 1;
                self.irregular += 1;
                self.first_irregular.get_or_insert(face);
            }
        }
        self.polygons += 1;
        self.polygon_triangles += triangles;
    }

    fn notes(self, notes: &mut Vec<MeshNote>) {
        if self.polygons > 0 {
            notes.push(MeshNote::Triangulated {
                polygons: self.polygons,
                non_convex: self.non_convex,
                irregular: self.irregular,
                first_irregular: self.first_irregular,
                triangles: self.polygon_triangles,
            });
        }
        if self.strips > 0 {
            notes.push(MeshNote::Strips {
                records: self.strips,
                triangles: self.strip_triangles,
                degenerate: self.degenerate,
            });
        }
    }
}

/// Decodes a triangle strip record: `[a, b, c, d, ...]` gives `(a, b, c)`, `(c, b, d)`, ...
/// (every other triangle reversed so that all keep one winding), [`RESTART`] starts a new
/// strip. Triangles with a repeated vertex (the stitches that join strips) are dropped; returns
/// how many.
fn decode_strip(ids: &[u32], out: &mut Vec<[u32; 3]>) -> Result<usize, AllocError> {
    let mut degenerate = 0;
    for strip in ids.split(|&i| i == RESTART) {
        for (k, w) in strip.windows(3).enumerate() {
            let t = if k % 2 == 0 {
                [w[0], w[1], w[2]]
            } else {
                [w[1], w[0], w[2]]
            };
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                degenerate += 1;
            } else {
                try_push(out, t, "triangles")?;
            }
        }
    }
    Ok(degenerate)
}
