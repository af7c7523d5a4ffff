//! What bounds the static check: a cap on the pairs it reports and a deadline (or a
//! [`CancelToken`]), as for the CCD query ([`QueryOptions`](crate::QueryOptions)).

use std::time::Instant;

use thiserror::Error;

use crate::mesh::StepError;
use crate::query::{CancelToken, StopReason, DEFAULT_MAX_CONTACTS};

/// Limits of [`step_intersections_within`](super::step_intersections_within) and
/// [`frame_intersections_within`](super::frame_intersections_within).
///
/// ```
/// use topoccd::check::CheckLimits;
/// let limits = CheckLimits::default();
/// assert_eq!(limits.max_contacts, Some(topoccd::DEFAULT_MAX_CONTACTS));
/// assert!(limits.deadline.is_none());
/// ```
#[derive(Clone, Debug)]
pub struct CheckLimits {
    /// The most intersecting pairs the check reports: with more, it stops and answers
    /// [`CheckError::MaxContacts`] (whatever the thread count: it is the step's count that
    /// decides). Default [`DEFAULT_MAX_CONTACTS`]; `None` for no cap.
    pub max_contacts: Option<usize>,
    /// Past this instant the check stops (within about a millisecond of work per thread) and
    /// answers [`CheckError::Stopped`]. Default `None`.
    pub deadline: Option<Instant>,
    /// Cancelling it (from any thread) stops the check the same way. Default `None`.
    pub cancel: Option<CancelToken>,
}

impl Default for CheckLimits {
    fn default() -> Self {
        Self {
            max_contacts: Some(DEFAULT_MAX_CONTACTS),
            deadline: None,
            cancel: None,
        }
    }
}

/// Why a bounded static check gave no answer.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum CheckError {
    /// The positions or triangles do not describe a valid configuration.
    #[error(transparent)]
    Step(#[from] StepError),
    /// More pairs intersect than the cap allows.
    #[error("more than {max_contacts} pairs of triangles intersect (a collapsed mesh, or positions cast to integers?): raise max_contacts, or pass None for no cap")]
    MaxContacts {
        /// The cap.
        max_contacts: usize,
    },
    /// The deadline passed, or the check was cancelled.
    #[error("the static check stopped ({0}) before its end: allow more time (a later deadline, a larger timeout)")]
    Stopped(StopReason),
    /// An allocation failed (the system refused the memory): the check gave up.
    #[error("out of memory: could not allocate {bytes} bytes for the {what}: set max_contacts (a cap bounds the pairs)")]
    OutOfMemory {
        /// The buffer that could not grow.
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
}

impl From<crate::alloc::AllocError> for CheckError {
    fn from(e: crate::alloc::AllocError) -> Self {
        Self::OutOfMemory {
            what: e.what,
            bytes: e.bytes,
        }
    }
}
