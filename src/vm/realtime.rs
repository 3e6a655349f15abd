//! Running a machine in real time: each update is due at an absolute deadline on the wall
//! clock, on the calling thread (the command gives the run a thread of its own), with the best
//! scheduling the system grants. Late updates are counted; a configured number of them in a
//! row is a fault that ends the run, and Ctrl-C ends it cleanly. Either way the outputs are
//! driven to their safe values at the end.

use super::StopReason;
use super::{Machine, RunSummary};
use crate::io::jitter::TimingSummary;
use crate::io::pace::{request_realtime, Pacer, Realtime};
use crate::io::{IoFault, IoStats};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The real-time priority asked for (SCHED_FIFO, 1–99): above ordinary real-time helpers,
/// below the kernel's own threads.
pub const PRIORITY: i32 = 80;

/// How a real-time run is paced and ended.
#[derive(Debug, Clone, Copy)]
pub struct RealTimeOptions<'a> {
    /// Consecutive overruns that make a fault (0: never).
    pub overrun_limit: u64,
    /// Set (by a signal handler) to end the run after the current update.
    pub interrupt: &'a AtomicBool,
}

/// What a real-time run did, beyond its [`RunSummary`].
#[derive(Debug, Clone)]
pub struct RealTimeReport {
    /// The run.
    pub summary: RunSummary,
    /// Jitter, worst update and overruns.
    pub timing: Option<TimingSummary>,
    /// The scheduling obtained, and why anything was refused.
    pub realtime: Realtime,
    /// Requests, faults and reconnections of the I/O link.
    pub io: IoStats,
    /// Too many overruns in a row ended the run.
    pub overrun_fault: Option<String>,
    /// Driving the outputs safe at the end failed.
    pub close_error: Option<IoFault>,
}

/// Run `machine` paced by the wall clock for `duration_ns` (None: until its programs end or
/// Ctrl-C), calling `observe` after every update (the exporters).
pub fn run_real_time(
    machine: &mut Machine,
    duration_ns: Option<u64>,
    options: RealTimeOptions<'_>,
    observe: &mut dyn FnMut(&Machine),
) -> RealTimeReport {
    let realtime = request_realtime(PRIORITY);
    let mut pacer = Pacer::start(Duration::from_nanos(machine.tick_ns()));
    let mut overrun_fault = None;
    let limit = options.overrun_limit;
    // Overruns in a row while the link was up before and after the update: an update that
    // waited on a failing device is the I/O fault's business, not a slow machine's.
    let mut streak = 0u64;
    // A link that goes down leaves `io_down` set at the end of that update; one that comes back
    // was down at the end of the one before.
    let mut was_down = machine.io_down();
    let summary = machine.run_controlled(duration_ns, &mut |m| {
        observe(m);
        let overran = pacer.end_update();
        let link_trouble = was_down || m.io_down();
        was_down = m.io_down();
        streak = if overran && !link_trouble {
            streak + 1
        } else {
            0
        };
        if limit > 0 && streak >= limit {
            let reason = StopReason::RealTimeFault { streak, limit };
            overrun_fault = Some(reason.to_string());
            return Some(reason);
        }
        if options.interrupt.load(Ordering::SeqCst) {
            return Some(StopReason::Interrupted);
        }
        pacer.wait_next();
        None
    });
    let close_error = machine.close_io().err();
    RealTimeReport {
        summary,
        timing: pacer.timing().summary(),
        realtime,
        io: machine.io_stats(),
        overrun_fault,
        close_error,
    }
}
