//! I/O backends: where a machine's inputs come from and its outputs go.
//!
//! The kernel talks to one [`IoBackend`] per run. The simulated world (scenario edges, the
//! master profile) is the default backend and today is still called directly by
//! `vm::Machine::step`; the real backend (Modbus TCP against a remote-I/O coupler) is described
//! by [`map`] (what is wired where, validated from `machine.toml`) and [`plan`] (the requests
//! one update costs). [`memory`] executes a plan against an in-memory device, the model the
//! Modbus TCP client follows; [`supervisor`] adds the fault handling (safe state, reconnection
//! with back-off, safe values first). [`target`] parses `--io`; [`jitter`] keeps the timing statistics
//! of a run paced by the wall clock.

pub mod jitter;
pub mod map;
pub mod memory;
pub mod pace;
pub mod plan;
pub mod supervisor;
pub mod target;

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

/// What the kernel needs of an I/O backend, once per update.
///
/// An update calls [`IoBackend::read_inputs`] before the assignments and tasks run and
/// [`IoBackend::write_outputs`] after the kernel has updated the outputs; both work on the
/// machine's value table (indexed by slot). On a fault the runner calls
/// [`IoBackend::safe_state`], stops motion and reports the fault; the backend reconnects on
/// later updates and writes the safe values first.
pub trait IoBackend {
    /// The device, for messages (`simulator`, `modbus://10.0.0.5:502 unit 1`).
    fn device(&self) -> String;
    /// Bring the inputs of the update ending at `t` seconds into `values`.
    fn read_inputs(&mut self, t: f64, values: &mut [f64]) -> Result<(), IoFault>;
    /// Send the outputs in `values` to the device.
    fn write_outputs(&mut self, values: &[f64]) -> Result<(), IoFault>;
    /// Drive every output to its configured safe value.
    fn safe_state(&mut self) -> Result<(), IoFault>;
}
