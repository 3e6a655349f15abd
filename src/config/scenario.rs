//! `scenario.toml`: the simulated world: how long to run, the master axis, product streams and
//! the digital inputs (levels, presses, pulse trains) in time.

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
    /// The master axis (conveyor encoder).
    #[serde(default)]
    pub master: MasterSection,
    /// Product streams passing sensors.
    #[serde(default)]
    pub products: Vec<ProductsEntry>,
    /// Sensors tied to the servo axis (home reference, label-edge marks).
    #[serde(default)]
    pub axis_marks: Vec<AxisMarksEntry>,
    /// Marks printed on the material a DSP axis moves, seen by a sensor on a DSP card input.
    #[serde(default)]
    pub marks: Vec<PrintedMarks>,
    /// Conveying belts of the pick & place module: each belt's speed over time.
    #[serde(default)]
    pub belts: Vec<BeltEntry>,
    /// Workpiece streams reported by detectors on the pick & place belts.
    #[serde(default)]
    pub workpieces: Vec<WorkpiecesEntry>,
}

/// `[[belts]]`: one conveying belt's speed profile (mm/s), jerk-limited S-ramps between speeds.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeltEntry {
    /// Belt number, 1–16 (CV1 … CV16); must be a belt of the machine's `[pickplace]`.
    pub belt: Spanned<u32>,
    /// Speed at the start, mm/s (default 0).
    pub speed: Option<Spanned<f64>>,
    /// Speed changes in time order.
    #[serde(default)]
    pub changes: Vec<Spanned<BeltChangeEntry>>,
}

/// `{ at = "20 s", speed = 220.0, ramp = "1 s" }`: a jerk-limited change of a belt's speed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeltChangeEntry {
    /// When the change starts.
    pub at: Spanned<Duration>,
    /// The new speed, mm/s (0 stops the belt).
    pub speed: Spanned<f64>,
    /// How long the S-ramp to it takes (default 0: a step, only for a belt without an
    /// acceleration limit).
    pub ramp: Option<Spanned<Duration>>,
}

/// `[[workpieces]]`: workpieces a detector reports on a belt, at belt travels given either as
/// `first`/`pitch`/`count` or as an explicit `at` list.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkpiecesEntry {
    /// The belt the workpieces ride on.
    pub belt: Spanned<u32>,
    /// Belt travel (mm) at the first detection (default 0).
    pub first: Option<Spanned<f64>>,
    /// Belt travel between detections, mm.
    pub pitch: Option<Spanned<f64>>,
    /// Number of detections (missing ones included).
    pub count: Option<Spanned<u32>>,
    /// Explicit belt travels of the detections, ascending (instead of first/pitch/count).
    pub at: Option<Spanned<Vec<Spanned<f64>>>>,
    /// 0-based indices of detections left out (gaps in the stream).
    #[serde(default)]
    pub missing: Vec<Spanned<u32>>,
    /// Nominal X, Y, Z (mm) in belt coordinates at detection (default 0, 0, 0).
    pub detect: Option<Spanned<[f64; 3]>>,
    /// Nominal C (degrees) at detection (default 0).
    pub c: Option<Spanned<f64>>,
    /// Seeded uniform jitter of the reported X, Y (mm) and C (degrees).
    pub jitter: Option<WorkpieceJitter>,
    /// Seed of the jitter (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Time from the receive edge to `xValidPos` (default 0).
    pub delay: Option<Spanned<Duration>>,
}

/// `jitter = { x = 4.0, y = 25.0, c = 10.0 }`: ± amplitudes, each default 0.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkpieceJitter {
    /// ± mm on X.
    pub x: Option<Spanned<f64>>,
    /// ± mm on Y.
    pub y: Option<Spanned<f64>>,
    /// ± degrees on C.
    pub c: Option<Spanned<f64>>,
}

/// `[[marks]]`: printed registration marks on a DSP axis's material (a web), with pitch drift,
/// steps, print jitter and spurious marks.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrintedMarks {
    /// The DSP axis that moves the material.
    pub axis: Spanned<u32>,
    /// The input the mark sensor is wired to: "ASEN" (default), "BSEN" or "ZREF" of the DSP
    /// card, or "FAST", the axis's fast input (REGIST).
    pub sensor: Option<Spanned<String>>,
    /// For a fast input: how long the sensor stays on at each mark (default 1 ms).
    pub on_time: Option<Spanned<Duration>>,
    /// Marks at these axis positions (instead of first/pitch/count).
    pub at: Option<Spanned<Vec<f64>>>,
    /// Axis position of the first mark.
    #[serde(default)]
    pub first: f64,
    /// Printed pitch at the first mark, axis units.
    pub pitch: Option<Spanned<f64>>,
    /// Number of marks.
    pub count: Option<Spanned<u32>>,
    /// Length of a mark along the material (default 50 units).
    pub width: Option<Spanned<f64>>,
    /// Change of the pitch per mark (stretch, humidity), units.
    #[serde(default)]
    pub drift: f64,
    /// Print jitter: each mark is displaced uniformly within ± this many units.
    pub jitter: Option<Spanned<f64>>,
    /// Seed of the jitter.
    #[serde(default)]
    pub seed: u64,
    /// Pitch steps: from mark `at` on, the pitch is `pitch` (drift continues from there).
    #[serde(default)]
    pub steps: Vec<PitchStep>,
    /// Spurious marks (print defects): one `offset` units after every `every`-th mark.
    pub spurious: Option<Spurious>,
}

/// A step of the printed pitch.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PitchStep {
    /// First mark (0-based) printed at the new pitch.
    pub at: u32,
    /// The new pitch.
    pub pitch: f64,
}

/// Spurious marks between the real ones.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spurious {
    /// After every this-many marks.
    pub every: Spanned<u32>,
    /// Distance after the real mark.
    pub offset: Spanned<f64>,
}

/// `[[axis_marks]]`: a sensor that is on while the servo axis is over a mark.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisMarksEntry {
    /// The sensor input.
    pub sensor: Spanned<String>,
    /// Axis position of the first mark.
    pub first: f64,
    /// Distance between marks (default 0: a single mark).
    #[serde(default)]
    pub pitch: f64,
    /// Number of marks (default 1).
    #[serde(default = "one")]
    pub count: u32,
    /// Width of each mark, axis units.
    pub width: f64,
}

fn one() -> u32 {
    1
}

/// `[master]`: the conveyor's speed over time.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MasterSection {
    /// Speed at the start, master units per second (default 0).
    pub speed: Option<Spanned<f64>>,
    /// Speed changes in time order.
    #[serde(default, rename = "change")]
    pub changes: Vec<Spanned<SpeedChangeEntry>>,
}

/// `[[master.change]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedChangeEntry {
    /// When the change starts.
    pub at: Duration,
    /// The new speed, master units per second (0 stops the conveyor).
    pub speed: f64,
    /// How long the ramp to it takes (default 0: at once).
    #[serde(default)]
    pub ramp: Option<Duration>,
}

/// `[[products]]`: products passing a sensor, tied to master positions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProductsEntry {
    /// The sensor input, e.g. `ModuleInput.2`.
    pub sensor: Spanned<String>,
    /// Master position of the first leading edge.
    pub first: f64,
    /// Master distance between leading edges.
    pub pitch: f64,
    /// Product length, master units.
    pub length: f64,
    /// Each leading edge moves by a seeded uniform amount within ±jitter (default 0).
    #[serde(default)]
    pub jitter: f64,
    /// Number of products.
    pub count: u32,
    /// Indices (from 0) of missing products.
    #[serde(default)]
    pub missing: Vec<u32>,
    /// Contact bounce on the edges.
    pub bounce: Option<BounceEntry>,
}

/// `bounce = { count = 3, width = "50us", gap = "100us", trailing = true }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BounceEntry {
    /// Bounces after each edge (at most [`super::limits::MAX_BOUNCES`]).
    pub count: Spanned<u32>,
    /// How long each bounce lasts.
    pub width: Duration,
    /// Time between bounces.
    pub gap: Duration,
    /// Bounce on trailing edges too (default: leading edges only).
    #[serde(default)]
    pub trailing: bool,
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
