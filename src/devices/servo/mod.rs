//! The servo loop behind an axis: what the motor actually does with the command position the
//! trajectory generator hands it. One job: turn a command into feedback — a digital cascaded
//! position / velocity loop driving a motor and its load, read through an encoder — so that
//! `PosnFeedback`, `VelFeedback` and `FollowingError` are what a real drive would report.
//!
//! `model.rs` is the pure, deterministic loop (no members, no trace); the PowerTools drive
//! steps it once per update and owns the fault that follows from it. The ideal servo (feedback
//! equals command) is not a model here: it is the absence of one.

pub mod model;

pub use model::{Servo, ServoParams};
