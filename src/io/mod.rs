//! I/O backends: where a machine's inputs come from and its outputs go.
//!
//! The machine talks to one [`IoBackend`] per run. The simulated world (scenario edges, the
//! master profile) is the default backend, [`Simulator`]; the real backend (Modbus TCP against a remote-I/O coupler) is described
//! by [`map`] (what is wired where, validated from `machine.toml`) and [`plan`] (the requests
//! one update costs). [`memory`] executes a plan against an in-memory device, the model the
//! Modbus TCP client follows; [`supervisor`] adds the fault handling (safe state, reconnection
//! with back-off, safe values first); [`exchange`] runs a supervised link on a thread of its
//! own as a process image, so updates never wait on the network; [`modbus`] is the Modbus TCP client. [`target`] parses `--io`; [`jitter`] keeps the timing statistics
//! of a run paced by the wall clock.

pub mod exchange;
pub mod jitter;
pub mod map;
pub mod memory;
pub mod modbus;
pub mod pace;
pub mod plan;
pub mod supervisor;
pub mod target;

use crate::registry::SlotId;
use crate::world::{InputActivity, World};

/// Why an I/O update failed: the device and the cause, for the fault report.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum IoFault {
    /// The connection was refused, lost or never opened.
    #[error("{device}: not connected ({cause})")]
    Disconnected {
        /// The device (`modbus://HOST:PORT unit N`).
        device: String,
        /// What the operating system said.
        cause: String,
    },
    /// A request took longer than the timeout.
    #[error("{device}: {request} timed out after {timeout_ms} ms")]
    Timeout {
        /// The device.
        device: String,
        /// The request (`read discrete_input 0..8`).
        request: String,
        /// The timeout.
        timeout_ms: u64,
    },
    /// The latest input image is older than the link allows: the exchange with the device has
    /// stalled (slow answers, or the exchange starved of processor time).
    #[error("{device}: inputs {age_ms} ms old, more than max_age {max_age_ms} ms: the exchange with the device has stalled")]
    Stale {
        /// The device.
        device: String,
        /// The age of the latest input image at the update, milliseconds.
        age_ms: u64,
        /// The limit.
        max_age_ms: u64,
    },
    /// The device answered with a Modbus exception.
    #[error("{device}: {request} answered exception {code} ({})", exception_name(*.code))]
    Exception {
        /// The device.
        device: String,
        /// The request.
        request: String,
        /// The exception code.
        code: u8,
    },
}

/// The name of a Modbus exception code.
pub fn exception_name(code: u8) -> &'static str {
    match code {
        1 => "illegal function",
        2 => "illegal data address",
        3 => "illegal data value",
        4 => "server device failure",
        5 => "acknowledge",
        6 => "server device busy",
        8 => "memory parity error",
        10 => "gateway path unavailable",
        11 => "gateway target device failed to respond",
        _ => "unknown exception",
    }
}

impl IoFault {
    /// The device the fault is about.
    pub fn device(&self) -> &str {
        match self {
            IoFault::Disconnected { device, .. }
            | IoFault::Timeout { device, .. }
            | IoFault::Stale { device, .. }
            | IoFault::Exception { device, .. } => device,
        }
    }

    /// The cause, without the device (for the trace's `cause` field).
    pub fn cause(&self) -> String {
        match self {
            IoFault::Disconnected { cause, .. } => format!("not connected ({cause})"),
            IoFault::Timeout {
                request,
                timeout_ms,
                ..
            } => format!("{request} timed out after {timeout_ms} ms"),
            IoFault::Stale {
                age_ms, max_age_ms, ..
            } => format!(
                "inputs {age_ms} ms old, more than max_age {max_age_ms} ms: the exchange with the device has stalled"
            ),
            IoFault::Exception { request, code, .. } => format!(
                "{request} answered exception {code} ({})",
                exception_name(*code)
            ),
        }
    }
}

/// Requests, faults and reconnections of a run, for the end-of-run summary.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IoStats {
    /// The exchange cycle's timing, when a process image ran the link ([`exchange`]).
    pub exchange: Option<exchange::ExchangeSummary>,
    /// Requests one update costs (the poll plan's reads and writes).
    pub per_update: u64,
    /// Requests sent to the device (updates, safe values and reconnections).
    pub requests: u64,
    /// Updates whose I/O was exchanged with the device (link up).
    pub updates: u64,
    /// Faults (the link went down).
    pub faults: u64,
    /// Reconnections (the link came back).
    pub reconnections: u64,
}

/// Where a machine's inputs come from and its outputs go: what `vm::Machine::step` talks to,
/// once per update. [`Simulator`] is the scenario's world; [`supervisor::Supervisor`] a real
/// device (over the simulated world, which still gives the master axis and every input the
/// device does not drive).
pub trait IoBackend {
    /// The device, for messages (`simulator`, `modbus://10.0.0.5:502 unit 1`).
    fn device(&self) -> String;
    /// Whether updates must be paced by the wall clock (a real device is).
    fn real_time(&self) -> bool;
    /// The input half of the update ending at `t` seconds (`now_ns` nanoseconds): advance the
    /// world and bring the inputs into `values`. A link going down or coming back is reported.
    fn read_inputs(
        &mut self,
        t: f64,
        now_ns: u64,
        world: &mut World,
        values: &mut [f64],
        activity: &mut Vec<InputActivity>,
    ) -> Vec<supervisor::LinkEvent>;
    /// The output half: send the outputs in `values` (nothing while the link is down).
    fn write_outputs(&mut self, now_ns: u64, values: &[f64]) -> Option<supervisor::LinkEvent>;
    /// The digital outputs' slots and safe values: the machine takes them on a fault, so its
    /// image and the trace show what the device was sent (variables fed to registers keep
    /// theirs: they are the programs' data).
    fn safe_outputs(&self) -> Vec<(SlotId, f64)>;
    /// The slots the device drives (scenario edges on them are dropped).
    fn driven_inputs(&self) -> Vec<SlotId>;
    /// End of the run: drive the outputs to their safe values.
    fn close(&mut self) -> Result<(), IoFault>;
    /// What the link did so far.
    fn stats(&self) -> IoStats;
}

/// The simulated world as the I/O backend: inputs are the scenario's edges, outputs go nowhere
/// (the trace shows them).
#[derive(Debug, Clone, Copy, Default)]
pub struct Simulator;

impl IoBackend for Simulator {
    fn device(&self) -> String {
        "simulator".into()
    }

    fn real_time(&self) -> bool {
        false
    }

    fn read_inputs(
        &mut self,
        t: f64,
        _now_ns: u64,
        world: &mut World,
        values: &mut [f64],
        activity: &mut Vec<InputActivity>,
    ) -> Vec<supervisor::LinkEvent> {
        world.advance(t, values, activity);
        Vec::new()
    }

    fn write_outputs(&mut self, _now_ns: u64, _values: &[f64]) -> Option<supervisor::LinkEvent> {
        None
    }

    fn safe_outputs(&self) -> Vec<(SlotId, f64)> {
        Vec::new()
    }

    fn driven_inputs(&self) -> Vec<SlotId> {
        Vec::new()
    }

    fn close(&mut self) -> Result<(), IoFault> {
        Ok(())
    }

    fn stats(&self) -> IoStats {
        IoStats::default()
    }
}
