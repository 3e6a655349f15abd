//! The servo side of the PiC900 `REGIST` function for one axis (spec `regist.md`, from the
//! Giddings & Lewis application note AN000031): fast-input edges classified as good, bad or ignored marks, the DIST+TOLR
//! status event, the correction `(distance since last good mark) mod LGTH`, its release to the
//! slave and master offsets through their filters, STATUSSV and servo variables 9–25.
//!
//! The module is self-contained: the caller feeds it edges (exact time and the registration
//! axis's continuous position), the axis position each update, and whether the correction may
//! move the slave; it reports marks, re-references and offset deltas for the caller to apply.
//!
//! Every input is checked: a bad value is a [`RegistError`] naming it, never a panic, which is
//! why [`Regist::new`], [`Regist::edge`] and [`Regist::passed`] return `Result`.
//!
//! Decisions the spec leaves open:
//! - Re-enabling with the same values changes nothing; enabling after [`Regist::disable`] or
//!   with different values re-arms: the next mark is the entrant good mark again, because the
//!   old ruler was measured against other DIST/TOLR/IGNR/LGTH and means nothing for the new ones.
//!   A refused enable leaves the running registration untouched and makes OK false.
//! - Corrections already queued survive disable and re-arm: they come from real marks and a
//!   half-released correction would leave the slave half corrected.
//! - The minimum time between marks (var 25) is measured from the previous *latched* mark (a
//!   rising edge that was seen). Falling edges are not latched: they only update the input
//!   state bit, so a short mark's falling edge never hides anything.
//! - The DIST+TOLR event fires when the axis *reaches* `ruler_start + DIST + TOLR` (>=), forward
//!   travel only, like the distances it guards.
//! - Sign: a positive correction `c` means the mark arrived `c` further along than one LGTH
//!   after the last good mark. The slave offset gets `+c` (the slave must travel `c` more to
//!   meet the product); the master offset gets `-c` (the master position the slave follows is
//!   set back by `c`, just as re-referencing the master to DIM at the mark would do). Both are
//!   offsets ADDED to the position they offset.

pub mod axes;
mod marks;
mod offsets;
mod servo_vars;

use offsets::Channel;
pub use servo_vars::{MIN_TIME_HIGHEST, MIN_TIME_LOWEST};

/// STATUSSV bit: a fast-input mark was latched (good, bad or ignored).
pub const FAST_IN_OCCURRED: u32 = 1 << 0;
/// STATUSSV bit: the fast input fired (set with FAST IN OCCURRED).
pub const FAST_INPUT: u32 = 1 << 1;
/// STATUSSV bit: the last mark was good.
pub const GOOD_MARK: u32 = 1 << 2;
/// STATUSSV bit: the last mark was bad.
pub const BAD_MARK: u32 = 1 << 3;
/// STATUSSV bit: the axis passed `ruler_start + DIST + TOLR` without a recognised mark.
pub const DIST_TOLR: u32 = 1 << 4;
/// STATUSSV bit: the state of the fast input (on after a rising edge, off after a falling one).
pub const FAST_IN_RISING: u32 = 1 << 5;

/// Servo variable 24 bit: the correction goes to the master offset.
pub const SWITCH_MASTER: u32 = 1;
/// Servo variable 24 bit: the correction goes to the slave offset.
pub const SWITCH_SLAVE: u32 = 2;
/// Servo variable 24 bit: a good mark re-references the axis to DIM.
pub const SWITCH_DIM: u32 = 4;
/// Servo variable 24 at start: slave correction and DIM at the mark, the usual slave
/// registration set-up (the spec's DIM is "the position assigned at a good mark", so it is on).
pub const SWITCH_DEFAULT: u32 = SWITCH_SLAVE | SWITCH_DIM;

/// Default minimum time between marks, in servo interrupts.
pub const DEFAULT_MIN_INTERRUPTS: f64 = 8.0;

/// Times closer than this (seconds) count as equal when testing the minimum time between marks:
/// edge times come from nanosecond clocks turned into seconds, so a mark exactly the minimum
/// time after the last one may come out a rounding error short and must still be seen.
pub const TIME_RESOLUTION: f64 = 1e-9;

/// A refused value, with a message naming it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct RegistError(pub String);

fn err<T>(message: impl Into<String>) -> Result<T, RegistError> {
    Err(RegistError(message.into()))
}

/// REGIST's inputs DIST, TOLR, IGNR, LGTH and DIM (axis units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegistParams {
    /// Expected distance between marks; 0 switches the distance test off.
    pub dist: f64,
    /// Allowed error around DIST.
    pub tolr: f64,
    /// Ignore zone after the last recognised mark; 0 = none.
    pub ignr: f64,
    /// Length the correction is taken modulo (the machine cycle); must be above 0.
    pub lgth: f64,
    /// Position assigned to the axis at a good mark.
    pub dim: f64,
}

impl RegistParams {
    fn validate(&self) -> Result<(), RegistError> {
        for (name, v) in [
            ("DIST", self.dist),
            ("TOLR", self.tolr),
            ("IGNR", self.ignr),
            ("LGTH", self.lgth),
            ("DIM", self.dim),
        ] {
            if !v.is_finite() {
                return err(format!("REGIST {name} must be a finite number, not {v}"));
            }
        }
        for (name, v) in [
            ("DIST", self.dist),
            ("TOLR", self.tolr),
            ("IGNR", self.ignr),
        ] {
            if v < 0.0 {
                return err(format!("REGIST {name} must be 0 or more, not {v}"));
            }
        }
        if self.lgth <= 0.0 {
            return err(format!(
                "REGIST LGTH must be above 0 (the correction is taken mod LGTH), not {}",
                self.lgth
            ));
        }
        Ok(())
    }
}

/// How a latched mark was classified.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkClass {
    /// Entrant mark or a distance within the window (or DIST 0): ruler and last good restart.
    Good,
    /// Outside the window: the ruler restarts here, no correction.
    Bad,
    /// Inside the ignore zone: as if it never happened (status bits only).
    Ignored,
}

/// A latched mark and what the caller must do about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mark {
    /// Its class.
    pub class: MarkClass,
    /// True for the first mark after (re-)arming, good by definition.
    pub entrant: bool,
    /// The continuous position it was latched at.
    pub position: f64,
    /// Distance from the ruler start; None for the entrant mark (there is no ruler yet).
    pub distance: Option<f64>,
    /// Good marks: the correction folded into (-LGTH/2, LGTH/2]; 0 for the entrant mark.
    pub correction: Option<f64>,
    /// Good marks with the DIM switch on: set the axis's actual and command position to this
    /// value at the mark. Classification keeps using continuous positions.
    pub rereference: Option<f64>,
}

/// Registration on one axis.
#[derive(Debug, Clone)]
pub struct Regist {
    servo_update: f64,
    /// The values handed to the servo side; None while registration is off.
    params: Option<RegistParams>,
    ok: bool,
    armed: bool,
    ruler_start: f64,
    last_good: f64,
    /// The DIST+TOLR event was already reported for the current ruler.
    window_passed: bool,
    bad_count: u32,
    status: u32,
    latch: f64,
    last_correction: f64,
    direction: f64,
    distance: f64,
    switches: u32,
    min_time: f64,
    /// Time of the last latched mark, for the minimum time between marks.
    last_mark_time: Option<f64>,
    /// Time and position of the last edge taken, for time order and direction.
    last_edge: Option<(f64, f64)>,
    slave: Channel,
    master: Channel,
}

impl Regist {
    /// Registration off, with the minimum time between marks at 8 interrupts of
    /// `servo_update` seconds. A non-finite or non-positive period is refused.
    pub fn new(servo_update: f64) -> Result<Regist, RegistError> {
        if !(servo_update.is_finite() && servo_update > 0.0) {
            return err(format!(
                "the servo update period must be above 0 seconds, not {servo_update}"
            ));
        }
        Ok(Regist {
            servo_update,
            params: None,
            ok: false,
            armed: false,
            ruler_start: 0.0,
            last_good: 0.0,
            window_passed: false,
            bad_count: 0,
            status: 0,
            latch: 0.0,
            last_correction: 0.0,
            direction: 0.0,
            distance: 0.0,
            switches: SWITCH_DEFAULT,
            min_time: DEFAULT_MIN_INTERRUPTS * servo_update,
            last_mark_time: None,
            last_edge: None,
            slave: Channel::new(),
            master: Channel::new(),
        })
    }

    /// The servo update period given to [`Regist::new`], seconds.
    pub fn servo_update(&self) -> f64 {
        self.servo_update
    }

    /// REGIST with EN true: hand the values to the servo side. The same values again change
    /// nothing; new values (or any after [`Regist::disable`]) re-arm, so the next mark is the
    /// entrant good mark. Refused values leave registration as it was and OK false.
    pub fn enable(&mut self, p: RegistParams) -> Result<(), RegistError> {
        if let Err(e) = p.validate() {
            self.ok = false;
            return Err(e);
        }
        self.ok = true;
        if self.params == Some(p) {
            return Ok(());
        }
        self.params = Some(p);
        self.armed = false;
        self.window_passed = false;
        self.bad_count = 0;
        Ok(())
    }

    /// Registration off (another fast-input move took the input, or the program turned it
    /// off): marks are no longer latched. Queued corrections are still released.
    pub fn disable(&mut self) {
        self.params = None;
        self.ok = false;
        self.armed = false;
        self.window_passed = false;
    }

    /// True while registration runs on the servo side.
    pub fn enabled(&self) -> bool {
        self.params.is_some()
    }

    /// REGIST's OK output: the last enable handed its values over and registration is on.
    pub fn ok(&self) -> bool {
        self.ok && self.params.is_some()
    }

    /// The values in force, if registration is on.
    pub fn params(&self) -> Option<RegistParams> {
        self.params
    }

    /// STATUSSV: the bits [`FAST_IN_OCCURRED`] … [`FAST_IN_RISING`].
    pub fn status(&self) -> u32 {
        self.status
    }
}
