//! ORMEC ORION "DSP axes": the motion a MotionBASIC program commands with `MOVE … AT … IN`,
//! `GEAR … AT … TO … [IN …] [AFTER …]` and `GEAR … FOR … IN …`, the programmable limit switches,
//! POS.MOD rollover and the ZREF/ASEN/BSEN position latches of the two-axis DSP cards.
//!
//! Self-contained: the MotionBASIC VM drives it through this API and traces the returned events.
//! Every axis's commanded position is a base layer (the DSP motion queue: velocity ramps or a gear
//! ratio) plus a superimposed layer (`GEAR FOR` moves). Geared motion is stored as a function of
//! the pacer's position, so it is exact at any instant of an update whatever the pacer does.

mod command;
mod gear;
mod latch;
mod pls;
mod sim;
mod solve;
mod superimpose;

use gear::BaseLayer;
use latch::{Latch, Marks, SensMode};
use pls::Pls;
use superimpose::SuperLayer;

/// The queue depth of an axis unless its configuration says otherwise.
pub const DEFAULT_QUEUE_DEPTH: usize = 4;

/// The highest axis number an ORION addresses.
pub const MAX_AXIS: u32 = 16;

/// A refused command or configuration, with a message fit for the user.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct DspError(pub String);

fn err<T>(message: impl Into<String>) -> Result<T, DspError> {
    Err(DspError(message.into()))
}

/// One DSP axis as the machine set-up (MotionBASIC's `MP.CONFIG`) describes it.
#[derive(Debug, Clone, PartialEq)]
pub struct DspAxisConfig {
    /// The axis number the program uses (`{1}` … `{16}`).
    pub number: u32,
    /// The axis whose position drives this axis's GEAR statements (the MotionData link).
    pub pacer: Option<u32>,
    /// User units per motor revolution, to turn RPM speeds into units per second.
    pub units_per_rev: f64,
    /// How many segments (both layers together) the axis's DSP queue holds.
    pub queue_depth: usize,
}

impl DspAxisConfig {
    /// An axis with the default queue depth.
    pub fn new(number: u32, pacer: Option<u32>, units_per_rev: f64) -> DspAxisConfig {
        DspAxisConfig {
            number,
            pacer,
            units_per_rev,
            queue_depth: DEFAULT_QUEUE_DEPTH,
        }
    }
}

/// What became of a motion statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Queued {
    /// In the queue; it runs when the segments before it are done.
    Accepted,
    /// A `GEAR FOR … IN 0`: accepted, and its whole distance will be applied as a step when it
    /// starts (the caller should warn the user: a superimposed move over no pacer distance).
    AcceptedAsStep,
    /// The queue is full: nothing was queued, the statement should retry next update.
    Full,
}

/// The two motion layers of an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    /// MOVE AT and GEAR AT segments.
    Base,
    /// GEAR FOR segments.
    Superimposed,
}

/// The three sensor inputs of a DSP axis, each with its own latch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sensor {
    /// The encoder reference (never PLS-gated).
    Zref,
    /// Sensor A, gated by PLS1 when SENS.MODE says G.
    Asen,
    /// Sensor B, gated by PLS2 when SENS.MODE says G.
    Bsen,
}

impl Sensor {
    fn index(self) -> usize {
        match self {
            Sensor::Zref => 0,
            Sensor::Asen => 1,
            Sensor::Bsen => 2,
        }
    }

    /// The name MotionBASIC uses.
    pub fn name(self) -> &'static str {
        ["ZREF", "ASEN", "BSEN"][self.index()]
    }
}

/// What a queued `GEAR AT … AFTER` waits for at its queue head.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum After {
    /// A drive or module input (its slot): the caller reports its rising edges with `trigger`.
    Input(u32),
    /// An edge of this sensor of the axis's own DSP card, of the polarity its SENS.MODE@ letter
    /// latches on and not blinded by its PLS gate: found while advancing, at its exact instant.
    Sensor(Sensor),
}

/// An event a waiting segment can start on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Trigger {
    /// A rising edge of an `AFTER` input.
    Input(u32),
    /// An edge of `Sensor` for axis index `usize`; consumed by the segment it starts.
    Sensor(usize, Sensor),
}

impl Trigger {
    /// Whether this trigger is what `after`, waiting on axis `i`, waits for.
    fn starts(self, i: usize, after: After) -> bool {
        match (self, after) {
            (Trigger::Input(k), After::Input(m)) => k == m,
            (Trigger::Sensor(j, w), After::Sensor(s)) => j == i && w == s,
            _ => false,
        }
    }
}

/// Something that happened during an update, at an exact time inside it, for the trace.
#[derive(Debug, Clone, PartialEq)]
pub enum DspEvent {
    /// A segment left the queue head and began to run (for `AFTER`: when its input came).
    SegmentStarted { axis: u32, layer: Layer, time: f64 },
    /// A `GEAR … AFTER ZREF|ASEN|BSEN` started at its sensor's edge: the pacer and the axis
    /// positions (absolute) at that instant.
    StartedOnEdge {
        axis: u32,
        which: Sensor,
        time: f64,
        pacer: f64,
        position: f64,
    },
    /// A segment completed; the next queued one starts at this instant.
    SegmentDone { axis: u32, layer: Layer, time: f64 },
    /// A `GEAR FOR … IN 0` was applied as a step of `dist`.
    Stepped { axis: u32, dist: f64, time: f64 },
    /// An armed latch took the axis's position; `position` as reported (modulo POS.MOD),
    /// `absolute` without rollover.
    Latched {
        axis: u32,
        which: Sensor,
        time: f64,
        position: f64,
        absolute: f64,
    },
    /// A card input edge rejected by the PLS gate of one of the card's axes (only reported for
    /// edges of a polarity some axis of the card latches on).
    EdgeBlinded { card: u32, which: Sensor, time: f64 },
}

impl DspEvent {
    /// The instant the event happened.
    pub fn time(&self) -> f64 {
        match *self {
            DspEvent::SegmentStarted { time, .. }
            | DspEvent::StartedOnEdge { time, .. }
            | DspEvent::SegmentDone { time, .. }
            | DspEvent::Stepped { time, .. }
            | DspEvent::Latched { time, .. }
            | DspEvent::EdgeBlinded { time, .. } => time,
        }
    }
}

/// One axis's state.
#[derive(Debug, Clone)]
struct AxisState {
    number: u32,
    card: u32,
    pacer: Option<usize>,
    units_per_rev: f64,
    queue_depth: usize,
    base: BaseLayer,
    sup: SuperLayer,
    pls: Pls,
    pos_mod: f64,
    sens: SensMode,
    latches: [Latch; 3],
}

/// All DSP axes of a controller, advanced together through time.
#[derive(Debug, Clone)]
pub struct DspAxes {
    axes: Vec<AxisState>,
    /// Axis number → index into `axes` (a fixed table: lookups stay deterministic).
    index: [Option<usize>; MAX_AXIS as usize + 1],
    /// Pacers before their followers.
    order: Vec<usize>,
    t_prev: f64,
    t_now: f64,
    /// `AFTER` events not yet consumed: (time, trigger), in time order.
    triggers: Vec<(f64, Trigger)>,
    marks: Vec<Marks>,
}

/// The card of axis `number`: axes 1 and 2 are card 0, 3 and 4 card 1, …
pub fn card_of(number: u32) -> u32 {
    number.saturating_sub(1) / 2
}

impl DspAxes {
    /// The axes of `configs`, at time 0, standing still at position 0.
    pub fn new(configs: &[DspAxisConfig]) -> Result<DspAxes, DspError> {
        let mut index = [None; MAX_AXIS as usize + 1];
        for (i, c) in configs.iter().enumerate() {
            if c.number == 0 || c.number > MAX_AXIS {
                return err(format!(
                    "DSP axis {} does not exist: axes are numbered 1 to {MAX_AXIS}",
                    c.number
                ));
            }
            if index[c.number as usize].is_some() {
                return err(format!("DSP axis {} is configured twice", c.number));
            }
            if !(c.units_per_rev.is_finite() && c.units_per_rev > 0.0) {
                return err(format!(
                    "DSP axis {}: units per revolution must be above 0, not {}",
                    c.number, c.units_per_rev
                ));
            }
            if c.queue_depth == 0 {
                return err(format!(
                    "DSP axis {}: the queue depth must be at least 1",
                    c.number
                ));
            }
            index[c.number as usize] = Some(i);
        }
        let mut axes = Vec::with_capacity(configs.len());
        for c in configs {
            let pacer = match c.pacer {
                None => None,
                Some(p) if p == c.number => {
                    return err(format!("DSP axis {} cannot be its own pacer", c.number))
                }
                Some(p) => match index.get(p as usize).copied().flatten() {
                    Some(i) => Some(i),
                    None => {
                        return err(format!(
                            "DSP axis {}: its pacer, axis {p}, is not a configured DSP axis",
                            c.number
                        ))
                    }
                },
            };
            axes.push(AxisState {
                number: c.number,
                card: card_of(c.number),
                pacer,
                units_per_rev: c.units_per_rev,
                queue_depth: c.queue_depth,
                base: BaseLayer::new(),
                sup: SuperLayer::new(),
                pls: Pls::default(),
                pos_mod: 0.0,
                sens: SensMode::default(),
                latches: [Latch::default(); 3],
            });
        }
        let order = topological(&axes)?;
        Ok(DspAxes {
            axes,
            index,
            order,
            t_prev: 0.0,
            t_now: 0.0,
            triggers: Vec::new(),
            marks: Vec::new(),
        })
    }

    /// The time of the last `advance` (0 before the first).
    pub fn time(&self) -> f64 {
        self.t_now
    }

    /// The start of the last advanced interval: `position_at` answers for `[previous_time, time]`.
    pub fn previous_time(&self) -> f64 {
        self.t_prev
    }

    /// The index of axis `number`, or an error naming it.
    fn axis(&self, number: u32) -> Result<usize, DspError> {
        match self.index.get(number as usize).copied().flatten() {
            Some(i) => Ok(i),
            None => err(format!("axis {number} is not a configured DSP axis")),
        }
    }

    /// Commanded position (absolute, no rollover) at the current time.
    pub fn position(&self, axis: u32) -> Result<f64, DspError> {
        Ok(self.pos_at(self.axis(axis)?, self.t_now))
    }

    /// Commanded velocity, units/s, at the current time.
    pub fn velocity(&self, axis: u32) -> Result<f64, DspError> {
        Ok(self.vel_at(self.axis(axis)?, self.t_now))
    }

    fn check_time(&self, t: f64) -> Result<(), DspError> {
        if t.is_finite() && self.t_prev <= t && t <= self.t_now {
            Ok(())
        } else {
            err(format!(
                "time {t} s is outside the last update [{}, {}] s",
                self.t_prev, self.t_now
            ))
        }
    }

    /// Commanded position (absolute) at `t` in the last advanced interval, exact.
    pub fn position_at(&self, axis: u32, t: f64) -> Result<f64, DspError> {
        let i = self.axis(axis)?;
        self.check_time(t)?;
        Ok(self.pos_at(i, t))
    }

    /// The gear ratio (follower units per pacer unit) now, or None while time-based.
    pub fn ratio(&self, axis: u32) -> Result<Option<f64>, DspError> {
        let i = self.axis(axis)?;
        let x = self.axes[i]
            .pacer
            .map_or(0.0, |p| self.pos_at(p, self.t_now));
        Ok(self.axes[i].base.piece_at(self.t_now).ratio(x))
    }

    /// The first time in `[t0, t1]` (inside the last update) the axis reaches `pos` from the side
    /// it is on at `t0` (`t0` itself when it is there).
    pub fn time_at_position(
        &self,
        axis: u32,
        pos: f64,
        t0: f64,
        t1: f64,
    ) -> Result<Option<f64>, DspError> {
        let i = self.axis(axis)?;
        self.check_time(t0)?;
        self.check_time(t1)?;
        if !pos.is_finite() || t0 > t1 {
            return err(format!(
                "time_at_position needs a finite position and t0 <= t1, not {pos} in [{t0}, {t1}]"
            ));
        }
        let g0 = self.pos_at(i, t0) - pos;
        if g0 == 0.0 {
            return Ok(Some(t0));
        }
        Ok(self.first_reach(i, pos, -g0.signum(), t0, t1))
    }
}

/// Axis indexes with every pacer before its followers, or an error naming a pacer cycle.
fn topological(axes: &[AxisState]) -> Result<Vec<usize>, DspError> {
    let mut order = Vec::with_capacity(axes.len());
    let mut placed = vec![false; axes.len()];
    for start in 0..axes.len() {
        let mut chain = Vec::new();
        let mut at = Some(start);
        while let Some(i) = at {
            if placed[i] {
                break;
            }
            if chain.contains(&i) {
                let names: Vec<String> = chain
                    .iter()
                    .map(|&j: &usize| axes[j].number.to_string())
                    .collect();
                return err(format!(
                    "DSP pacer links form a cycle through axes {}",
                    names.join(", ")
                ));
            }
            chain.push(i);
            at = axes[i].pacer;
        }
        for &i in chain.iter().rev() {
            placed[i] = true;
            order.push(i);
        }
    }
    Ok(order)
}
