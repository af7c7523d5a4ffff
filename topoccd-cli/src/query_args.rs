//! The query options every command that runs steps takes, declared once and checked by the
//! library ([`QueryOptions::validate`]), so every command refuses the same values with the same
//! message.

use anyhow::{bail, Result};

use crate::common::MemoryLimit;
use topoccd::{ClusterGrowth, DopKind, Method, Mode, NarrowOptions, QueryOptions};

/// The whole-step query's method, as named on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodArg {
    /// A k-DOP bounding volume hierarchy built anew for the step (the paper's baseline).
    Bvh,
    /// Every feature pair whose swept boxes overlap (the oracle).
    Brute,
    /// The paper's method: clusters proved free of self-contact, a hierarchy over them, lazy
    /// hierarchies over the leaf clusters' triangles.
    Cluster,
    /// bvh on steps below 100,000 triangles, cluster on larger ones (the method that ran is
    /// in the JSON's `stats.method`).
    Auto,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Bvh => Method::Bvh,
            MethodArg::Brute => Method::Brute,
            MethodArg::Cluster => Method::Cluster,
            MethodArg::Auto => Method::Auto,
        }
    }
}

/// How `--method cluster` grows its leaf clusters, as named on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrowthArg {
    /// The paper's criterion (every ring faces away from the observation point) and the disk
    /// certificate.
    Paper,
    /// The disk certificate alone: bigger clusters, equally sound.
    Certificate,
}

impl From<GrowthArg> for ClusterGrowth {
    fn from(g: GrowthArg) -> Self {
        match g {
            GrowthArg::Paper => ClusterGrowth::Paper,
            GrowthArg::Certificate => ClusterGrowth::Certificate,
        }
    }
}

impl GrowthArg {
    /// The library's default.
    pub fn default_growth() -> Self {
        match ClusterGrowth::default() {
            ClusterGrowth::Paper => GrowthArg::Paper,
            ClusterGrowth::Certificate => GrowthArg::Certificate,
        }
    }
}

/// The broad phase's method of `step` and `run`.
#[derive(clap::Args, Debug, Clone)]
pub struct MethodArgs {
    /// Method of the broad phase (every method reports the same pairs).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto)]
    pub method: MethodArg,
}

/// Options of the query shared by every command that runs steps.
#[derive(clap::Args, Debug, Clone)]
pub struct QueryArgs {
    /// Report only the earliest time of impact and the pairs attaining it (within the
    /// tolerance).
    #[arg(long)]
    pub earliest: bool,
    /// k of the k-DOP bounding volumes: 6, 14, 18 or 26.
    #[arg(long, default_value_t = 18, value_parser = parse_k)]
    pub k: usize,
    /// Distance at or below which features count as touching (coordinate units, >= 0).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub min_distance: f64,
    /// Time resolution of the elementary tests, in (0, 1).
    #[arg(long, default_value_t = NarrowOptions::default().tolerance, allow_negative_numbers = true)]
    pub tolerance: f64,
    /// End of the time interval searched, in (0, 1].
    #[arg(long, default_value_t = NarrowOptions::default().tmax, allow_negative_numbers = true)]
    pub tmax: f64,
    /// Most parameter boxes an elementary test may examine (>= 1) before it gives up
    /// conservatively (the contact is then reported as unresolved).
    #[arg(long, default_value_t = NarrowOptions::default().max_iterations)]
    pub max_iterations: u32,
    /// How `--method cluster` grows its leaf clusters (ignored by the other methods).
    #[arg(long, value_enum, default_value_t = GrowthArg::default_growth())]
    pub growth: GrowthArg,
    /// Compute each contact's geometry (barycentric coordinates, point, normal); shown in the
    /// JSON pairs.
    #[arg(long)]
    pub geometry: bool,
    /// Report contacts between the two sides of a fresh crack too (a new vertex and its parent
    /// are then different vertices).
    #[arg(long)]
    pub keep_crack_contacts: bool,
    /// Keep at most N contacts per step: once a step has more, its query stops and its output
    /// says TRUNCATED (the first N of the query's fixed order, the same for any thread count;
    /// with --earliest, once the earliest time is known to be 0). Default: as many as the
    /// memory allows (`step --max-memory`, else $TOPOCCD_MAX_MEMORY, else the memory
    /// available: a collapsed step has hundreds of millions of contacts at t=0); `off` for no
    /// cap.
    #[arg(long, value_name = "N", value_parser = parse_cap)]
    pub max_contacts: Option<Cap>,
    /// Stop a step's query after SECONDS (from when it starts) and exit with an error that
    /// says so. Default: no time limit.
    #[arg(long, value_name = "SECONDS", value_parser = parse_timeout)]
    pub timeout: Option<f64>,
    /// Deprecated alias of `--min-distance` (hidden; a note on stderr says so).
    #[arg(
        long,
        hide = true,
        allow_negative_numbers = true,
        conflicts_with = "min_distance"
    )]
    pub min_separation: Option<f64>,
    /// Deprecated alias of `--tmax` (hidden; a note on stderr says so).
    #[arg(
        long,
        hide = true,
        allow_negative_numbers = true,
        conflicts_with = "tmax"
    )]
    pub t_max: Option<f64>,
}

/// The deadline `--timeout SECONDS` sets for work starting now (none without it).
pub fn deadline_after(timeout: Option<f64>) -> Option<std::time::Instant> {
    timeout.map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s))
}

/// `--timeout`: a positive, finite number of seconds.
pub fn parse_timeout(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t > 0.0 && t.is_finite() && t < 1e9 => Ok(t),
        _ => Err(format!("{s:?} is not a positive number of seconds")),
    }
}

/// `--max-contacts`: a number, or no cap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cap {
    /// At most this many contacts.
    At(usize),
    /// No cap.
    Off,
}

pub fn parse_cap(s: &str) -> Result<Cap, String> {
    if s.trim().eq_ignore_ascii_case("off") {
        return Ok(Cap::Off);
    }
    s.trim()
        .parse()
        .map(Cap::At)
        .map_err(|_| format!("{s:?} is not a number of contacts (or 'off')"))
}

/// Bytes a contact may take while a query runs: the report's, and those the traversal's
/// tasks hold before they hand them over (a few per thread, see `QueryOptions::max_contacts`).
fn bytes_per_contact() -> u64 {
    let contact = std::mem::size_of::<topoccd::VfContact>()
        .max(std::mem::size_of::<topoccd::EeContact>()) as u64;
    contact * (rayon::current_num_threads() as u64 + 2)
}

/// The default cap: what the memory limit allows, `None` without one.
fn default_cap(limit: MemoryLimit) -> Option<usize> {
    match limit {
        MemoryLimit::Bytes(bytes, _) => {
            Some(usize::try_from(bytes / bytes_per_contact()).unwrap_or(usize::MAX))
        }
        MemoryLimit::Off => None,
    }
}

impl Default for QueryArgs {
    fn default() -> Self {
        let narrow = NarrowOptions::default();
        Self {
            earliest: false,
            k: 18,
            min_distance: narrow.min_distance,
            tolerance: narrow.tolerance,
            tmax: narrow.tmax,
            max_iterations: narrow.max_iterations,
            growth: GrowthArg::default_growth(),
            geometry: false,
            keep_crack_contacts: false,
            max_contacts: None,
            timeout: None,
            min_separation: None,
            t_max: None,
        }
    }
}

fn parse_k(s: &str) -> Result<usize, String> {
    let k: usize = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    DopKind::from_k(k)
        .map(|_| k)
        .ok_or_else(|| format!("k must be 6, 14, 18 or 26, got {k}"))
}

impl QueryArgs {
    /// One note on stderr per deprecated flag given (once per process, however many steps).
    fn deprecation_notes(&self) {
        static ONCE: std::sync::Once = std::sync::Once::new();
        let old = [
            (
                "--min-separation",
                "--min-distance",
                self.min_separation.is_some(),
            ),
            ("--t-max", "--tmax", self.t_max.is_some()),
        ];
        if old.iter().any(|(_, _, given)| *given) {
            ONCE.call_once(|| {
                for (old, new, given) in old {
                    if given {
                        eprintln!(
                            "note: {old} is deprecated, use {new} (the IPC toolkit's name; \
                             {old} goes in the next release)"
                        );
                    }
                }
            });
        }
    }

    /// The deadline of a query starting now: `--timeout` seconds from now, if given.
    pub fn deadline(&self) -> Option<std::time::Instant> {
        deadline_after(self.timeout)
    }

    /// An error when `report` stopped at its deadline (`--timeout`), saying what to do.
    pub fn check_deadline(&self, report: &topoccd::Report) -> Result<()> {
        match &report.truncated {
            Some(t) if t.reason == topoccd::StopReason::Deadline => bail!(
                "the query did not finish within --timeout {} s (stopped in its {} phase); \
                 raise --timeout, or lower --max-contacts on a step with very many contacts",
                self.timeout.unwrap_or(0.0),
                format!("{:?}", t.phase).to_lowercase()
            ),
            _ => Ok(()),
        }
    }

    /// The library's options, after checking the ranges; the default cap of `--max-contacts`
    /// follows the default memory limit ([`MemoryLimit::from_env`]).
    pub fn options(&self) -> Result<QueryOptions> {
        self.options_within(MemoryLimit::from_env()?)
    }

    /// [`QueryArgs::options`] with the default cap of `--max-contacts` following `limit`.
    pub fn options_within(&self, limit: MemoryLimit) -> Result<QueryOptions> {
        self.deprecation_notes();
        let options = QueryOptions {
            narrow: NarrowOptions {
                tolerance: self.tolerance,
                min_distance: self.min_separation.unwrap_or(self.min_distance),
                tmax: self.t_max.unwrap_or(self.tmax),
                max_iterations: self.max_iterations,
            },
            kdop: DopKind::from_k(self.k).unwrap_or_default(),
            mode: if self.earliest {
                Mode::Earliest
            } else {
                Mode::All
            },
            growth: self.growth.into(),
            geometry: self.geometry,
            crack_filter: !self.keep_crack_contacts,
            max_contacts: match self.max_contacts {
                Some(Cap::At(n)) => Some(n),
                Some(Cap::Off) => None,
                None => default_cap(limit),
            },
            deadline: None,
        };
        options.validate()?;
        Ok(options)
    }
}
