//! Keyword options to the library's `Method` and `QueryOptions`, checked by the library.

use pyo3::prelude::*;
use topoccd::{ClusterGrowth, DopKind, Method, Mode, QueryOptions};

use crate::errors::options_error;

/// The keyword options of `Ccd.query`, as given from Python.
pub struct Keywords<'a> {
    pub method: &'a str,
    pub mode: &'a str,
    pub tolerance: f64,
    pub min_distance: f64,
    pub tmax: f64,
    pub max_iterations: i64,
    pub k: i64,
    pub growth: Option<&'a str>,
    pub geometry: bool,
    pub crack_filter: bool,
    pub max_contacts: Option<i64>,
    pub timeout: Option<f64>,
}

/// The method by name: `brute`, `bvh`, `cluster` or `auto`.
pub fn method(name: &str) -> PyResult<Method> {
    name.parse::<Method>().map_err(|_| {
        options_error(format!(
            "method must be 'bvh', 'cluster', 'brute' or 'auto', got {name:?}"
        ))
    })
}

/// The mode by name: `all` or `earliest`.
fn mode(name: &str) -> PyResult<Mode> {
    match name {
        "all" => Ok(Mode::All),
        "earliest" => Ok(Mode::Earliest),
        _ => Err(options_error(format!(
            "mode must be 'all' or 'earliest', got {name:?}"
        ))),
    }
}

/// The cluster growth by name: `paper` or `certificate`.
fn growth(name: &str) -> PyResult<ClusterGrowth> {
    match name {
        "paper" => Ok(ClusterGrowth::Paper),
        "certificate" => Ok(ClusterGrowth::Certificate),
        _ => Err(options_error(format!(
            "growth must be 'certificate' or 'paper', got {name:?}"
        ))),
    }
}

impl Keywords<'_> {
    /// The library's method and options, validated by [`QueryOptions::validate`].
    pub fn resolve(&self) -> PyResult<(Method, QueryOptions)> {
        let method = method(self.method)?;
        let kdop = usize::try_from(self.k)
            .ok()
            .and_then(DopKind::from_k)
            .ok_or_else(|| options_error(format!("k must be 6, 14, 18 or 26, got {}", self.k)))?;
        let max_iterations = u32::try_from(self.max_iterations).map_err(|_| {
            options_error(format!(
                "max_iterations must be in [1, {}], got {}",
                u32::MAX,
                self.max_iterations
            ))
        })?;
        let mut options = QueryOptions::default();
        options.narrow.tolerance = self.tolerance;
        options.narrow.min_distance = self.min_distance;
        options.narrow.tmax = self.tmax;
        options.narrow.max_iterations = max_iterations;
        options.kdop = kdop;
        options.mode = mode(self.mode)?;
        if let Some(g) = self.growth {
            options.growth = growth(g)?;
        }
        options.geometry = self.geometry;
        options.crack_filter = self.crack_filter;
        options.max_contacts = match self.max_contacts {
            None => None,
            Some(n) => Some(usize::try_from(n).map_err(|_| {
                options_error(format!("max_contacts must be None or >= 0, got {n}"))
            })?),
        };
        if let Some(t) = self.timeout {
            // (The deadline itself is set when the query starts.)
            if !(t > 0.0 && t < 1e9) {
                return Err(options_error(format!(
                    "timeout must be None or seconds in (0, 1e9), got {t}"
                )));
            }
        }
        options
            .validate()
            .map_err(|e| options_error(e.to_string()))?;
        Ok((method, options))
    }
}
