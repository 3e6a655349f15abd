//! `scenario.toml`: the simulated world. For now: how long to run and the digital inputs
//! (levels, presses, pulse trains) in time.

use super::values::{Duration, Level};
use serde::Deserialize;
use toml::Spanned;

/// The whole scenario file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Run settings.
    #[serde(default)]
    pub run: RunSection,
    /// Level changes: `name` goes to `value` at `at`.
    #[serde(default, rename = "input")]
    pub inputs: Vec<LevelChange>,
    /// Presses: `name` is on from `at` for `length`.
    #[serde(default, rename = "press")]
    pub presses: Vec<Press>,
    /// Pulse trains.
    #[serde(default)]
    pub pulses: Vec<PulseTrain>,
}

/// `[run]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Simulated time to run.
    pub duration: Option<Spanned<Duration>>,
    /// Seed for everything random in the world (default 1).
    pub seed: Option<u64>,
}

/// `[[input]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelChange {
    /// An input, e.g. `DriveInput.6`.
    pub name: Spanned<String>,
    /// When.
    pub at: Spanned<Duration>,
    /// The new level.
    pub value: Spanned<Level>,
}

/// `[[press]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Press {
    /// An input.
    pub name: Spanned<String>,
    /// When it goes on.
    pub at: Spanned<Duration>,
    /// How long it stays on (may be shorter than one update).
    pub length: Spanned<Duration>,
}

/// `[[pulses]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PulseTrain {
    /// An input.
    pub name: Spanned<String>,
    /// First rising edge.
    pub start: Spanned<Duration>,
    /// Rising edge to rising edge.
    pub period: Spanned<Duration>,
    /// On-time of each pulse.
    pub width: Spanned<Duration>,
    /// Number of pulses.
    pub count: Spanned<u32>,
}
