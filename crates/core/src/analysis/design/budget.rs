//! A time limit on a search: the command line's `--budget` and Python's `budget=`, checked and
//! kept in one place. When the time is up the search's stop flag is raised, as Ctrl+C raises
//! it, and the search ends with the best body so far (`Ended::Stopped`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::{DesignError, bad};

/// The longest budget allowed, in seconds (about four months).
pub const MAX_BUDGET_S: f64 = 1e7;

/// How often the timer looks whether the work has finished: a finished search does not wait
/// out its budget.
const POLL: Duration = Duration::from_millis(20);

/// Refuses a budget that is not a positive, finite number of seconds up to [`MAX_BUDGET_S`].
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::check_budget;
/// assert!(check_budget(Some(60.0)).is_ok() && check_budget(None).is_ok());
/// let e = check_budget(Some(0.0)).unwrap_err().to_string();
/// assert_eq!(e, "budget = 0 is not allowed (needs 0 < seconds ≤ 1e7)");
/// assert!(check_budget(Some(f64::NAN)).is_err());
/// // A huge value reads as one, not as 301 digits.
/// assert!(check_budget(Some(1e300)).unwrap_err().to_string().starts_with("budget = 1e300 "));
/// ```
pub fn check_budget(seconds: Option<f64>) -> Result<(), DesignError> {
    match seconds {
        Some(s) if !(s.is_finite() && s > 0.0 && s <= MAX_BUDGET_S) => Err(bad(
            "budget",
            crate::integrate::readable(s),
            format!("0 < seconds ≤ {MAX_BUDGET_S:e}"),
        )),
        _ => Ok(()),
    }
}

/// Runs `work`, raising `stop` once `seconds` have passed (never, for `None`); returns as soon
/// as `work` does.
///
/// # Example
/// ```
/// use std::sync::atomic::{AtomicBool, Ordering};
/// use rollphase_core::analysis::design::with_budget;
/// let stop = AtomicBool::new(false);
/// let waited = with_budget(&stop, Some(0.05), || {
///     while !stop.load(Ordering::Relaxed) {
///         std::thread::sleep(std::time::Duration::from_millis(1));
///     }
///     "stopped"
/// });
/// assert_eq!(waited, "stopped");
/// ```
pub fn with_budget<T>(stop: &AtomicBool, seconds: Option<f64>, work: impl FnOnce() -> T) -> T {
    let Some(seconds) = seconds else {
        return work();
    };
    let deadline = Instant::now() + Duration::from_secs_f64(seconds.clamp(0.0, MAX_BUDGET_S));
    let finished = AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            while !finished.load(Ordering::Relaxed) {
                let left = deadline.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    stop.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::sleep(left.min(POLL));
            }
        });
        // Raised on return and on a panic alike, so the timer never outlives the work.
        let _done = Finished(&finished);
        work()
    })
}

/// Marks the work finished when dropped.
struct Finished<'a>(&'a AtomicBool);

impl Drop for Finished<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}
