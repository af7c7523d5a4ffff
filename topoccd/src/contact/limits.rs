//! What stops a query before its end: a cap on the contacts it keeps
//! ([`QueryOptions::max_contacts`]), a deadline ([`QueryOptions::deadline`]) and a
//! [`CancelToken`]. One [`Limits`] per query carries them to every place that loops for long:
//! the traversal tasks (one check as each task starts, and every few thousand triangle pairs),
//! the narrow phase's candidate batches (every few dozen pairs), the brute-force sweep and the
//! cluster method's leaf growth. A stop is recorded once, with its reason, and every loop that
//! sees it winds down; the query then returns what it has, with [`Report::truncated`] saying
//! why and how far it got.
//!
//! [`QueryOptions::max_contacts`]: super::QueryOptions::max_contacts
//! [`QueryOptions::deadline`]: super::QueryOptions::deadline
//! [`Report::truncated`]: super::Report::truncated

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// A flag that stops the queries of a [`Ccd`](crate::Ccd) from another thread (a Ctrl-C
/// handler, a user's cancel button). Clones share the flag. A cancelled token stays cancelled
/// until [`CancelToken::reset`]: every query on the `Ccd` returns at once, truncated, with
/// [`StopReason::Cancelled`].
///
/// ```
/// use topoccd::{Ccd, Method, QueryOptions, StopReason, Step};
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let step = Step::new(&x, &x, &[[0u32, 1, 2]])?;
/// let mut ccd = Ccd::new();
/// let token = ccd.cancel_token(); // hand a clone to another thread
/// token.cancel();
/// let report = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
/// assert_eq!(report.truncated.map(|t| t.reason), Some(StopReason::Cancelled));
/// token.reset();
/// assert!(ccd.query(&step, Method::Bvh, &QueryOptions::default())?.truncated.is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A token not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Stops the query running with this token (within about a millisecond of work on each
    /// thread), and every later one until [`CancelToken::reset`].
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Release);
    }

    /// Whether [`CancelToken::cancel`] was called since the last reset.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }

    /// Lets queries run again.
    pub fn reset(&self) {
        self.0.store(false, Ordering::Release);
    }
}

/// Why a query stopped before its end ([`Truncation::reason`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum StopReason {
    /// The report holds [`QueryOptions::max_contacts`](super::QueryOptions::max_contacts)
    /// contacts and the step has more.
    MaxContacts,
    /// [`QueryOptions::deadline`](super::QueryOptions::deadline) passed.
    Deadline,
    /// The [`CancelToken`] was cancelled.
    Cancelled,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopReason::MaxContacts => "max_contacts",
            StopReason::Deadline => "deadline",
            StopReason::Cancelled => "cancelled",
        })
    }
}

/// Where a query stopped, in [`Truncation::phase`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Phase {
    /// Before the candidate pairs: the topology, the volumes, the hierarchy, the clusters.
    Build,
    /// Among the candidate pairs: the traversal and the elementary tests.
    Candidates,
}

/// How a truncated query ended ([`Report::truncated`](super::Report::truncated)).
///
/// With [`StopReason::MaxContacts`] the report is the same for any thread count: its contacts
/// are the first `max_contacts` the query finds in its fixed order of work (the traversal's
/// tasks in their order, and within a task its candidate pairs in order, a buffer's
/// vertex-face pairs before its edge-edge pairs; for [`Method::Brute`](super::Method::Brute),
/// the sweep's candidates in order), sorted as usual, and `tasks` and the statistics count
/// only the work those contacts came from. In [`Mode::Earliest`](super::Mode::Earliest) they
/// are the first `max_contacts` of that order within the tolerance of the earliest time, which
/// is then 0 (the query truncates only once it knows that).
///
/// After a deadline or a cancellation, what was found depends on timing: the report holds no
/// contacts, only the earliest found by then (`earliest`, an upper bound of the step's earliest
/// time of impact), so that the query ends at once, whatever it had found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Truncation {
    /// Why the query stopped.
    pub reason: StopReason,
    /// In which phase.
    pub phase: Phase,
    /// Units of work whose contacts the report holds, in the fixed order: traversal tasks of
    /// [`Method::Bvh`](super::Method::Bvh) and [`Method::Cluster`](super::Method::Cluster)
    /// (the last one possibly in part; the per-step hierarchy splits a step into about 512),
    /// or buffers of candidates of [`Method::Brute`](super::Method::Brute).
    pub tasks: u64,
}

/// How many pairs [`Limits::poll`] may be called for between two reads of the clock.
const POLLS_PER_CLOCK: u64 = 64;

/// The limits of one query, shared by all its threads.
#[derive(Debug)]
pub(crate) struct Limits {
    /// Most contacts the report keeps (`usize::MAX`: no cap).
    pub max_contacts: usize,
    deadline: Option<Instant>,
    cancel: Option<CancelToken>,
    /// `0` while the query runs, else `1 + ` the [`StopReason`] index.
    state: AtomicU8,
    /// Calls of [`Limits::poll`] since the clock was last read (approximate across threads).
    polls: AtomicU64,
    /// The first allocation that failed ([`Limits::fail`]): the query returns it as its error.
    failure: std::sync::OnceLock<crate::alloc::AllocError>,
}

impl Default for Limits {
    fn default() -> Self {
        Self::new(None, None, None)
    }
}

impl Limits {
    /// The limits of a query.
    pub fn new(
        max_contacts: Option<usize>,
        deadline: Option<Instant>,
        cancel: Option<CancelToken>,
    ) -> Self {
        Self {
            max_contacts: max_contacts.unwrap_or(usize::MAX),
            deadline,
            cancel,
            state: AtomicU8::new(0),
            polls: AtomicU64::new(0),
            failure: std::sync::OnceLock::new(),
        }
    }

    /// Whether the report keeps at most some number of contacts.
    pub fn capped(&self) -> bool {
        self.max_contacts != usize::MAX
    }

    /// Why the query stopped, if it has (a relaxed load: call it as often as needed).
    #[inline]
    pub fn stopped(&self) -> Option<StopReason> {
        match self.state.load(Ordering::Relaxed) {
            0 => None,
            1 => Some(StopReason::MaxContacts),
            2 => Some(StopReason::Deadline),
            // 3: cancelled; 4: an allocation failed, which winds the query down as a
            // cancellation does (it then returns the failure, [`Limits::failure`]).
            _ => Some(StopReason::Cancelled),
        }
    }

    /// Records a stop; the first reason recorded stays.
    pub fn stop(&self, reason: StopReason) {
        let code = match reason {
            StopReason::MaxContacts => 1,
            StopReason::Deadline => 2,
            StopReason::Cancelled => 3,
        };
        let _ = self
            .state
            .compare_exchange(0, code, Ordering::Relaxed, Ordering::Relaxed);
    }

    /// Records that an allocation failed: every loop winds down (as after a cancellation)
    /// and the query returns the first failure recorded as its error.
    #[cold]
    pub fn fail(&self, failure: crate::alloc::AllocError) {
        let _ = self.failure.set(failure);
        self.state.store(4, Ordering::Relaxed);
    }

    /// The allocation that failed, if one did.
    pub fn failure(&self) -> Option<crate::alloc::AllocError> {
        self.failure.get().copied()
    }

    /// Records `result`'s failure, if any ([`Limits::fail`]); whether it succeeded.
    #[inline]
    pub fn check(&self, result: Result<(), crate::alloc::AllocError>) -> bool {
        match result {
            Ok(()) => true,
            Err(e) => {
                self.fail(e);
                false
            }
        }
    }

    /// Whether the query must stop: a stop already recorded, the cancel token, or (every
    /// [`POLLS_PER_CLOCK`] calls, or at once with `now`) the deadline. Cheap enough to call
    /// every few pairs.
    #[inline]
    pub fn poll(&self, now: bool) -> bool {
        if self.stopped().is_some() {
            return true;
        }
        if self.cancel.as_ref().is_some_and(CancelToken::is_cancelled) {
            self.stop(StopReason::Cancelled);
            return true;
        }
        if let Some(deadline) = self.deadline {
            let due = now
                || (self.polls.fetch_add(1, Ordering::Relaxed)).is_multiple_of(POLLS_PER_CLOCK);
            if due && Instant::now() >= deadline {
                self.stop(StopReason::Deadline);
                return true;
            }
        }
        false
    }
}
