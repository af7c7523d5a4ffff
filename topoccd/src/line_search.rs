//! Line-search helpers for a simulator: how far along a step the mesh may move without a
//! contact ([`collision_free_stepsize`]), and whether a whole step is free of contact
//! ([`is_step_collision_free`]), as the IPC toolkit's `compute_collision_free_stepsize` and
//! `is_step_collision_free` are used. Both run one [`Mode::Earliest`] query.
//!
//! ```
//! use topoccd::line_search::{collision_free_stepsize, LineSearchOptions};
//! // A triangle falls from z=1 to z=-1 through a fixed one: first contact at t=0.5.
//! let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
//!           [0.2, 0.2, 1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
//! let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
//!           [0.2, 0.2, -1.0], [0.3, 0.2, -1.0], [0.2, 0.3, -1.0]];
//! let triangles = [[0u32, 1, 2], [3, 4, 5]];
//! let step = collision_free_stepsize(&x0, &x1, &triangles, &LineSearchOptions::default())?;
//! assert!((step.alpha - 0.8 * 0.5).abs() < 1e-6); // 0.8 times the earliest time of impact
//! assert!(step.earliest.is_some());
//! # Ok::<(), topoccd::line_search::LineSearchError>(())
//! ```
//!
//! Input range: inside it ([`range`](crate::range)) the earliest time is the query's, with
//! its guarantees; a pair outside it (a difference beyond `1e300`) is a contact at 0, so the
//! step size is 0 and the step is not collision-free: an answer that can only be too
//! cautious, never unsafe.
//!
//! In a simulation loop, keep a [`Ccd`] and call [`Ccd::collision_free_stepsize`] and
//! [`Ccd::is_step_collision_free`] on each [`Step`]: its buffers are reused, and a step can
//! carry parents (a cut) and groups.

use thiserror::Error;

use crate::check;
use crate::mesh::{Frame, Positions, Step, StepError, Triangles};
use crate::query::{Ccd, Contact, Method, Mode, OptionsError, QueryOptions, Report, StopReason};

/// Options of the line-search helpers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSearchOptions {
    /// The query's options. `query.narrow.min_distance` is the minimum separation: features
    /// closer than it count as touching. `query.mode` is ignored (the helpers run
    /// [`Mode::Earliest`]).
    pub query: QueryOptions,
    /// The broad phase. Default [`Method::Auto`].
    pub method: Method,
    /// The fraction of the earliest time of impact that [`collision_free_stepsize`] returns,
    /// in `(0, 1]`. Default `0.8`, the IPC toolkit's conservative rescaling: the step stops
    /// short of the contact, so the next step does not start touching.
    pub conservative_rescaling: f64,
    /// Run the exact static check ([`check::step_intersections`]) on the t=0 positions
    /// first, and refuse a start where triangles already intersect
    /// ([`LineSearchError::StartIntersects`]). Default `false`: the helpers then assume the
    /// paper's premise (nothing intersects at t=0) and do not look. A pair of triangles
    /// that passes through each other at t=0 and keeps moving apart has no contact in
    /// `(0, tmax]`, so without the check the step size can be `tmax`.
    pub check_start: bool,
}

impl Default for LineSearchOptions {
    fn default() -> Self {
        Self {
            query: QueryOptions::default(),
            method: Method::Auto,
            conservative_rescaling: 0.8,
            check_start: false,
        }
    }
}

impl LineSearchOptions {
    /// Checks every option against its documented range.
    ///
    /// ```
    /// use topoccd::line_search::LineSearchOptions;
    /// let bad = LineSearchOptions { conservative_rescaling: 1.5, ..LineSearchOptions::default() };
    /// assert_eq!(bad.validate().unwrap_err().to_string(), "conservative_rescaling must be in (0, 1], got 1.5");
    /// ```
    pub fn validate(&self) -> Result<(), LineSearchError> {
        self.query.validate()?;
        if !(self.conservative_rescaling > 0.0 && self.conservative_rescaling <= 1.0) {
            return Err(LineSearchError::ConservativeRescaling(
                self.conservative_rescaling,
            ));
        }
        Ok(())
    }

    /// With [`check_start`](Self::check_start), refuses a step whose t=0 triangles intersect.
    fn check(&self, step: &Step<'_>) -> Result<(), LineSearchError> {
        if self.check_start {
            let unbounded = check::CheckLimits {
                max_contacts: None,
                ..check::CheckLimits::default()
            };
            let pairs = match check::step_intersections_within(step, Frame::Start, &unbounded) {
                Ok(pairs) => pairs,
                Err(check::CheckError::OutOfMemory { what, bytes }) => {
                    return Err(OptionsError::OutOfMemory { what, bytes }.into())
                }
                Err(_) => unreachable!("no cap, no deadline, no cancel token"),
            };
            if let Some(&first) = pairs.first() {
                return Err(LineSearchError::StartIntersects {
                    triangles: first,
                    count: pairs.len(),
                });
            }
        }
        Ok(())
    }

    /// The query the helpers run: [`Mode::Earliest`], keeping one pair (only the earliest
    /// contact matters), so that it stops as soon as a contact at time 0 is proven and holds
    /// a bounded set of pairs otherwise. The deadline is the caller's.
    fn earliest(&self) -> QueryOptions {
        QueryOptions {
            mode: Mode::Earliest,
            max_contacts: Some(1),
            ..self.query
        }
    }
}

/// Why a line-search helper refused its input.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LineSearchError {
    /// The positions or triangles do not describe a valid step.
    #[error(transparent)]
    Step(#[from] StepError),
    /// A query option out of its range.
    #[error(transparent)]
    Options(#[from] OptionsError),
    /// [`LineSearchOptions::conservative_rescaling`] not in `(0, 1]`.
    #[error("conservative_rescaling must be in (0, 1], got {0}")]
    ConservativeRescaling(f64),
    /// The query stopped on its deadline ([`QueryOptions::deadline`]) or its
    /// [`CancelToken`](crate::CancelToken) before the earliest time of impact was known (a
    /// contact at time 0, found by then, is still an answer).
    #[error("the line search stopped ({0}) before the earliest time of impact was known: allow more time (a later deadline, a larger timeout) or reset the cancel token")]
    Stopped(StopReason),
    /// [`LineSearchOptions::check_start`] found triangles that intersect at t=0: no step size
    /// is safe from such a start.
    #[error(
        "triangles {} and {} intersect at t=0 ({count} intersecting pairs): the step \
         starts in contact",
        triangles[0],
        triangles[1]
    )]
    StartIntersects {
        /// The first intersecting pair `[a, b]` (`a < b`, in sorted order).
        triangles: [u32; 2],
        /// How many pairs intersect.
        count: usize,
    },
}

/// The earliest contact of an [`Mode::Earliest`] report of [`LineSearchOptions::earliest`],
/// and whether its time is the step's earliest time of impact, exactly (see
/// [`QueryOptions::max_contacts`]): a query truncated by its cap knows that time is 0; one
/// stopped by time knows it only if it found a contact at 0.
fn earliest_of(report: &Report) -> Result<(Option<Contact>, bool), LineSearchError> {
    match report.truncated.map(|t| t.reason) {
        None => Ok((report.earliest, false)),
        Some(StopReason::MaxContacts) => Ok((report.earliest, true)),
        Some(reason) => match report.earliest {
            Some(c) if c.toi() == 0.0 => Ok((Some(c), true)),
            _ => Err(LineSearchError::Stopped(reason)),
        },
    }
}

/// What [`collision_free_stepsize`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepSize {
    /// The fraction of the step the mesh may take: `conservative_rescaling` times the earliest time of
    /// impact, or `tmax` when no features come within `min_distance` over `[0, tmax]`.
    /// `0` when features already touch at the start: nothing can move. Triangles that pass
    /// through each other at the start without touching features are not seen: set
    /// [`LineSearchOptions::check_start`] to refuse such a start.
    pub alpha: f64,
    /// The earliest contact, or `None`. Its [`certainty`](Contact::certainty) says whether the
    /// search gave up on it: then its time is only a lower bound, and `alpha` stays safe.
    pub earliest: Option<Contact>,
}

/// What [`is_step_collision_free`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepStatus {
    /// No two features come within `min_distance` over `[0, tmax]`.
    CollisionFree,
    /// The earliest contact of the step. Its [`certainty`](Contact::certainty) is
    /// [`Certainty::Resolved`](crate::Certainty::Resolved), or says that the search gave up
    /// and reported the pair to stay safe.
    Collides(Contact),
}

impl StepStatus {
    /// `true` for [`StepStatus::CollisionFree`].
    pub fn is_collision_free(&self) -> bool {
        matches!(self, StepStatus::CollisionFree)
    }
}

/// The fraction of the step from `x0` to `x1` that the mesh may take without contact: the
/// earliest time of impact scaled by [`LineSearchOptions::conservative_rescaling`]. A fresh [`Ccd`] runs
/// the query; in a loop, use [`Ccd::collision_free_stepsize`].
pub fn collision_free_stepsize<'a>(
    x0: impl Into<Positions<'a>>,
    x1: impl Into<Positions<'a>>,
    triangles: impl Into<Triangles<'a>>,
    options: &LineSearchOptions,
) -> Result<StepSize, LineSearchError> {
    let step = Step::new(x0, x1, triangles)?;
    Ccd::new().collision_free_stepsize(&step, options)
}

/// Whether the whole step from `x0` to `x1` is free of contact, and if not, its earliest
/// contact. A fresh [`Ccd`] runs the query; in a loop, use [`Ccd::is_step_collision_free`].
///
/// ```
/// use topoccd::line_search::{is_step_collision_free, LineSearchOptions, StepStatus};
/// // Vertex 3 falls through triangle 0 at t=0.5.
/// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
/// let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
///           [0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
/// let triangles = [[0u32, 1, 2], [3, 4, 5]];
/// let status = is_step_collision_free(&x0, &x1, &triangles, &LineSearchOptions::default())?;
/// match status {
///     StepStatus::Collides(contact) => assert!((contact.toi() - 0.5).abs() < 1e-6),
///     StepStatus::CollisionFree => unreachable!("vertex 3 crosses triangle 0"),
/// }
/// # Ok::<(), topoccd::line_search::LineSearchError>(())
/// ```
pub fn is_step_collision_free<'a>(
    x0: impl Into<Positions<'a>>,
    x1: impl Into<Positions<'a>>,
    triangles: impl Into<Triangles<'a>>,
    options: &LineSearchOptions,
) -> Result<StepStatus, LineSearchError> {
    let step = Step::new(x0, x1, triangles)?;
    Ccd::new().is_step_collision_free(&step, options)
}

impl Ccd {
    /// [`collision_free_stepsize`] on a step, with this query object's buffers.
    ///
    /// ```
    /// use topoccd::line_search::LineSearchOptions;
    /// use topoccd::{Ccd, Step};
    /// // A vertex 1 above a triangle moves down by 2; with a minimum separation of 0.5 it
    /// // comes that close at t=0.25.
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
    /// let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
    /// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    /// let mut options = LineSearchOptions::default();
    /// options.query.narrow.min_distance = 0.5;
    /// let mut ccd = Ccd::new();
    /// let size = ccd.collision_free_stepsize(&step, &options)?;
    /// assert!(size.alpha <= 0.8 * 0.25 && size.alpha > 0.8 * 0.25 - 1e-6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn collision_free_stepsize(
        &mut self,
        step: &Step<'_>,
        options: &LineSearchOptions,
    ) -> Result<StepSize, LineSearchError> {
        options.validate()?;
        options.check(step)?;
        let report = self.query(step, options.method, &options.earliest())?;
        let (earliest, at_zero) = earliest_of(&report)?;
        let alpha = match earliest {
            _ if at_zero => 0.0,
            Some(contact) => options.conservative_rescaling * contact.toi(),
            None => options.query.narrow.tmax,
        };
        Ok(StepSize { alpha, earliest })
    }

    /// [`is_step_collision_free`] on a step, with this query object's buffers.
    ///
    /// ```
    /// use topoccd::line_search::{LineSearchOptions, StepStatus};
    /// use topoccd::{Ccd, Step};
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// let step = Step::new(&x, &x, &[[0u32, 1, 2]])?;
    /// let status = Ccd::new().is_step_collision_free(&step, &LineSearchOptions::default())?;
    /// assert_eq!(status, StepStatus::CollisionFree);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn is_step_collision_free(
        &mut self,
        step: &Step<'_>,
        options: &LineSearchOptions,
    ) -> Result<StepStatus, LineSearchError> {
        options.validate()?;
        options.check(step)?;
        let report = self.query(step, options.method, &options.earliest())?;
        Ok(match earliest_of(&report)?.0 {
            Some(contact) => StepStatus::Collides(contact),
            None => StepStatus::CollisionFree,
        })
    }
}
