//! The narrow-phase query files of the Sample-Queries data set.
//!
//! Each query is 8 rows `xnum,xden,ynum,yden,znum,zden,gt`: the coordinates as exact rationals
//! and the ground truth (1 if the features touch during `[0, 1]`, the same on all 8 rows).
//! Vertex-face rows are `v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1`; edge-edge rows are
//! `ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1`.

use std::fs;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::math::DVec3;

/// Which elementary test a query file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum QueryKind {
    /// Vertex against triangle (files under a `vertex-face` folder).
    VertexFace,
    /// Edge against edge (files under an `edge-edge` folder).
    EdgeEdge,
}

impl QueryKind {
    /// Short name: `vf` or `ee`.
    pub fn short_name(self) -> &'static str {
        match self {
            QueryKind::VertexFace => "vf",
            QueryKind::EdgeEdge => "ee",
        }
    }
}

/// One query: eight points in file order and the exact answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QueryRecord {
    /// The eight points, in the order of the file.
    pub points: [DVec3; 8],
    /// `true` if the features touch during `[0, 1]` (exact ground truth).
    pub touching: bool,
    /// Line (1-based) of the query's first row.
    pub line: usize,
}

/// Why a query file could not be read.
#[derive(Debug, Error)]
pub enum QueryFileError {
    /// The file or folder could not be read.
    #[error("{path}: cannot read")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A row is malformed.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// Line number, 1-based.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// Reads one query file.
pub fn read_query_file(path: &Path) -> Result<Vec<QueryRecord>, QueryFileError> {
    let text = fs::read_to_string(path).map_err(|source| QueryFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_queries(&text, path)
}

/// Parses the text of a query file; `path` only names the file in errors.
pub fn parse_queries(text: &str, path: &Path) -> Result<Vec<QueryRecord>, QueryFileError> {
    let err = |line: usize, message: String| QueryFileError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let rows: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty())
        .collect();
    if !rows.len().is_multiple_of(8) {
        let last = rows.last().map_or(1, |r| r.0);
        return Err(err(
            last,
            format!(
                "{} rows is not a whole number of 8-row queries (the last query is cut short)",
                rows.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(rows.len() / 8);
    for chunk in rows.chunks(8) {
        let mut points = [DVec3::ZERO; 8];
        let mut truth = None;
        for (k, &(line, row)) in chunk.iter().enumerate() {
            let (p, gt) = parse_row(row).map_err(|m| err(line, m))?;
            points[k] = p;
            match truth {
                None => truth = Some(gt),
                Some(t) if t != gt => {
                    return Err(err(
                        line,
                        "ground truth differs from the query's first row".into(),
                    ))
                }
                Some(_) => {}
            }
        }
        out.push(QueryRecord {
            points,
            touching: truth.unwrap_or(false),
            line: chunk[0].0,
        });
    }
    Ok(out)
}

fn parse_row(row: &str) -> Result<(DVec3, bool), String> {
    let fields: Vec<&str> = row.split(',').map(str::trim).collect();
    if fields.len() != 7 {
        return Err(format!(
            "expected 7 comma-separated fields, found {}",
            fields.len()
        ));
    }
    let mut xyz = [0.0; 3];
    for (k, c) in xyz.iter_mut().enumerate() {
        *c = rational(fields[2 * k], fields[2 * k + 1])?;
    }
    let gt = match fields[6] {
        "0" => false,
        "1" => true,
        other => return Err(format!("ground truth must be 0 or 1, found {other:?}")),
    };
    Ok((DVec3::from_array(xyz), gt))
}

/// `num / den` as an `f64`, refused unless exact.
fn rational(num: &str, den: &str) -> Result<f64, String> {
    let n: i128 = num
        .parse()
        .map_err(|_| format!("numerator {num:?} is not an integer"))?;
    let d: i128 = den
        .parse()
        .map_err(|_| format!("denominator {den:?} is not an integer"))?;
    if d <= 0 {
        return Err(format!("denominator {d} is not positive"));
    }
    let (nf, df) = (n as f64, d as f64);
    let value = nf / df;
    // Exact iff both convert exactly and the quotient is exact (d a power of two suffices).
    let exact = nf as i128 == n && df as i128 == d && (d as u128).is_power_of_two();
    if !exact || !value.is_finite() {
        return Err(format!("{n}/{d} is not exactly representable as an f64"));
    }
    Ok(value)
}

/// Every `*.csv` file in a `vertex-face` or `edge-edge` folder below `dir`, sorted by path.
pub fn find_query_files(dir: &Path) -> Result<Vec<(QueryKind, PathBuf)>, QueryFileError> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let entries = fs::read_dir(&d).map_err(|source| QueryFileError::Io {
            path: d.clone(),
            source,
        })?;
        for entry in entries {
            let entry = entry.map_err(|source| QueryFileError::Io {
                path: d.clone(),
                source,
            })?;
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let is_csv = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
            let folder = d.file_name().and_then(|f| f.to_str());
            let kind = match folder {
                Some("vertex-face") => QueryKind::VertexFace,
                Some("edge-edge") => QueryKind::EdgeEdge,
                _ => continue,
            };
            if is_csv {
                out.push((kind, path));
            }
        }
    }
    out.sort_by(|a, b| a.1.cmp(&b.1));
    Ok(out)
}
