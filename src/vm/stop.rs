//! Why a run (or a REPL's trace) ended: the `reason` of the trace's `end` event and of the run's
//! summary line.

/// Why a run stopped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StopReason {
    /// A run-time error in a program, an assignment or a device ended it.
    RunTimeError,
    /// `--for` or the scenario's duration was reached.
    Duration,
    /// Every program ended and the scenario had nothing more to do.
    ProgramsEnded,
    /// No duration was set and the programs never ended: the cap on simulated time.
    Cap {
        /// The cap, simulated seconds.
        seconds: u64,
    },
    /// The trace reached its size limit (`--trace-limit`).
    TraceLimit {
        /// The limit, bytes.
        bytes: u64,
    },
    /// Writing the trace failed (disk full, a closed pipe): the run stops at once, since
    /// nothing after it could be recorded.
    TraceFailed,
    /// Ctrl-C (or SIGTERM) on a real-time run.
    Interrupted,
    /// Too many updates in a row finished late on a real-time run.
    RealTimeFault {
        /// Late updates in a row.
        streak: u64,
        /// The machine's `overrun_limit`.
        limit: u64,
    },
    /// The REPL's trace was closed by `:trace off`.
    TraceOff,
    /// The REPL's trace was moved to another file by `:trace FILE`.
    TraceMoved,
    /// The REPL loaded another machine (`:load`, `:reset`).
    Reloaded,
    /// The REPL ended.
    ReplEnded,
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopReason::RunTimeError => f.write_str("run-time error"),
            StopReason::Duration => f.write_str("duration reached"),
            StopReason::ProgramsEnded => f.write_str("all programs ended"),
            StopReason::Cap { seconds } => write!(
                f,
                "stopped after {seconds} s simulated (no duration set and programs still running)"
            ),
            StopReason::TraceLimit { bytes } => write!(
                f,
                "the trace reached its size limit of {bytes} bytes (--trace-limit)"
            ),
            StopReason::TraceFailed => f.write_str("the trace could not be written"),
            StopReason::Interrupted => f.write_str("interrupted (Ctrl-C)"),
            StopReason::RealTimeFault { streak, limit } => write!(
                f,
                "real-time fault: {streak} updates in a row finished after the next one was due (overrun_limit = {limit})"
            ),
            StopReason::TraceOff => f.write_str("trace off"),
            StopReason::TraceMoved => f.write_str("trace moved"),
            StopReason::Reloaded => f.write_str("machine reloaded"),
            StopReason::ReplEnded => f.write_str("repl ended"),
        }
    }
}
