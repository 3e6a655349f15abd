//! Pacing updates by the wall clock: each update is due at an absolute deadline (start + n ×
//! period), so a late update does not shift the ones after it. The thread asks for the best
//! scheduling it may have (real-time FIFO priority, memory locked) and falls back with a
//! warning when the system refuses.

use super::jitter::Timing;
use std::time::Duration;

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

/// The monotonic clock, nanoseconds from an arbitrary origin.
#[cfg(target_os = "linux")]
fn mono_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    (ts.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(ts.tv_nsec as u64)
}

#[cfg(not(target_os = "linux"))]
fn mono_ns() -> u64 {
    use std::sync::OnceLock;
    static ORIGIN: OnceLock<std::time::Instant> = OnceLock::new();
    let origin = *ORIGIN.get_or_init(std::time::Instant::now);
    u64::try_from(origin.elapsed().as_nanos()).unwrap_or(u64::MAX)
}

/// Sleep until the monotonic clock reads `deadline_ns`: an absolute sleep, so the time spent
/// computing the sleep cannot add to it.
#[cfg(target_os = "linux")]
fn sleep_until(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    // Interrupted by a signal (EINTR): sleep again until the deadline.
    // SAFETY: `ts` is a valid timespec; the remainder pointer may be null with TIMER_ABSTIME.
    while unsafe {
        libc::clock_nanosleep(
            libc::CLOCK_MONOTONIC,
            libc::TIMER_ABSTIME,
            &ts,
            std::ptr::null_mut(),
        )
    } == libc::EINTR
    {}
}

#[cfg(not(target_os = "linux"))]
fn sleep_until(deadline_ns: u64) {
    let now = mono_ns();
    if deadline_ns > now {
        std::thread::sleep(Duration::from_nanos(deadline_ns - now));
    }
}

/// Paces updates by absolute deadlines: update `n` is due at start + n × period, whatever the
/// updates before it took, and each one's lateness and work go into a [`Timing`].
#[derive(Debug, Clone)]
pub struct Pacer {
    period_ns: u64,
    start_ns: u64,
    n: u64,
    began_ns: u64,
    lateness_ns: u64,
    timing: Timing,
}

impl Pacer {
    /// Start pacing: update 0 is due now.
    pub fn start(period: Duration) -> Pacer {
        let now = mono_ns();
        Pacer {
            period_ns: u64::try_from(period.as_nanos()).unwrap_or(u64::MAX).max(1),
            start_ns: now,
            n: 0,
            began_ns: now,
            lateness_ns: 0,
            timing: Timing::default(),
        }
    }

    /// The current update has done its work: record it. Returns whether it overran (ended
    /// after the next update was due).
    pub fn end_update(&mut self) -> bool {
        let work = mono_ns().saturating_sub(self.began_ns);
        self.timing.record(self.lateness_ns, work, self.period_ns) > 0
    }

    /// Wait for the next update's deadline (at once when it has passed) and start it. When
    /// the schedule is a whole period or more behind (an update blocked on a device's
    /// timeout), the deadlines passed are dropped rather than run back to back.
    pub fn wait_next(&mut self) {
        self.n += 1;
        let mut due = self
            .start_ns
            .saturating_add(self.n.saturating_mul(self.period_ns));
        let now = mono_ns();
        if now >= due.saturating_add(self.period_ns) {
            let behind = (now - due) / self.period_ns;
            self.n += behind;
            self.timing.skip(behind);
            due = self
                .start_ns
                .saturating_add(self.n.saturating_mul(self.period_ns));
        }
        if now < due {
            sleep_until(due);
        }
        self.began_ns = mono_ns();
        self.lateness_ns = self.began_ns.saturating_sub(due);
    }

    /// The timings so far.
    pub fn timing(&self) -> &Timing {
        &self.timing
    }
}

/// Run `updates` updates of `period`, update `n` due at start + n × period; `update(n)` does
/// the work and returns false to stop early. Returns the timing of every update run.
pub fn run_paced(period: Duration, updates: u64, mut update: impl FnMut(u64) -> bool) -> Timing {
    let mut pacer = Pacer::start(period);
    for n in 0..updates {
        if n > 0 {
            pacer.wait_next();
        }
        let go_on = update(n);
        pacer.end_update();
        if !go_on {
            break;
        }
    }
    pacer.timing
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

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
