//! Pacing updates by the wall clock: each update is due at an absolute deadline (start + n ×
//! period), so a late update does not shift the ones after it. The thread asks for the best
//! scheduling it may have (real-time FIFO priority, memory locked) and falls back with a
//! warning when the system refuses.

use super::jitter::Timing;
use std::time::{Duration, Instant};

/// What the pacing thread obtained from the operating system.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Realtime {
    /// Real-time FIFO scheduling is in force.
    pub fifo: bool,
    /// The process's memory is locked (no page faults in an update).
    pub locked: bool,
    /// Why something was refused, for the warning.
    pub warnings: Vec<String>,
}

/// Ask for real-time FIFO scheduling of the calling thread at `priority` (1–99) and locked
/// memory. Refusals (no CAP_SYS_NICE, RLIMIT_MEMLOCK, another OS) become warnings.
pub fn request_realtime(priority: i32) -> Realtime {
    let mut rt = Realtime::default();
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param {
            sched_priority: priority.clamp(1, 99),
        };
        // SAFETY: pthread_self is always valid for the calling thread, and `param` lives
        // across the call.
        let err =
            unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) };
        if err == 0 {
            rt.fifo = true;
        } else {
            rt.warnings.push(format!(
                "real-time scheduling refused ({}): updates run at normal priority",
                std::io::Error::from_raw_os_error(err)
            ));
        }
        // SAFETY: mlockall takes only flags and touches no memory of ours.
        if unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) } == 0 {
            rt.locked = true;
        } else {
            rt.warnings.push(format!(
                "memory could not be locked ({}): page faults may delay updates",
                std::io::Error::last_os_error()
            ));
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = priority;
        rt.warnings
            .push("real-time scheduling is only requested on Linux".to_string());
    }
    rt
}

/// Run `updates` updates of `period`, update `n` due at start + n × period; `update(n)` does
/// the work and returns false to stop early. Returns the timing of every update run.
pub fn run_paced(period: Duration, updates: u64, mut update: impl FnMut(u64) -> bool) -> Timing {
    let mut timing = Timing::default();
    let period_ns = u64::try_from(period.as_nanos()).unwrap_or(u64::MAX);
    let start = Instant::now();
    for n in 0..updates {
        let due = start + period.saturating_mul(u32::try_from(n).unwrap_or(u32::MAX));
        let now = Instant::now();
        if let Some(wait) = due.checked_duration_since(now) {
            std::thread::sleep(wait);
        }
        let began = Instant::now();
        let lateness = began.saturating_duration_since(due);
        let go_on = update(n);
        let work = began.elapsed();
        timing.record(
            u64::try_from(lateness.as_nanos()).unwrap_or(u64::MAX),
            u64::try_from(work.as_nanos()).unwrap_or(u64::MAX),
            period_ns,
        );
        if !go_on {
            break;
        }
    }
    timing
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn updates_follow_absolute_deadlines_and_a_slow_one_is_an_overrun() {
        let start = Instant::now();
        let mut seen = Vec::new();
        let timing = run_paced(Duration::from_millis(2), 20, |n| {
            seen.push(n);
            if n == 5 {
                // Longer than the period: an overrun; the next updates catch up, since their
                // deadlines do not move.
                std::thread::sleep(Duration::from_millis(5));
            }
            true
        });
        let elapsed = start.elapsed();
        assert_eq!(seen, (0..20).collect::<Vec<u64>>());
        let s = timing.summary().expect("updates");
        assert_eq!(s.updates, 20);
        assert!(s.overruns >= 1, "{s:?}");
        assert!(s.worst_update_ns >= 5_000_000, "{s:?}");
        // Update 19 is due at 38 ms: the run cannot end sooner, and the slow update did not
        // push the schedule by its 5 ms (generous bound for a loaded test machine).
        assert!(elapsed >= Duration::from_millis(38), "{elapsed:?}");
        assert!(elapsed < Duration::from_millis(400), "{elapsed:?}");
    }

    #[test]
    fn an_update_can_stop_the_run() {
        let timing = run_paced(Duration::from_micros(100), 1000, |n| n < 3);
        assert_eq!(timing.summary().map(|s| s.updates), Some(4));
    }

    #[test]
    fn realtime_is_granted_or_explained() {
        // On a thread of its own, so the priority ends with it; the memory lock is undone.
        let rt = std::thread::spawn(|| request_realtime(10))
            .join()
            .expect("the thread ends");
        #[cfg(target_os = "linux")]
        if rt.locked {
            // SAFETY: munlockall takes no arguments and only unlocks this process's pages.
            unsafe { libc::munlockall() };
        }
        // Either granted, or each refusal says why.
        assert_eq!(
            usize::from(!rt.fifo) + usize::from(!rt.locked),
            rt.warnings.len(),
            "{rt:?}"
        );
    }
}
