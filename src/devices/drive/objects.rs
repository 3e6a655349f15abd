//! The drive's motion objects and switches as the registry holds them: each object's set-up
//! from `machine.toml` and the slots of its members, bound by name when pacer is compiled.

use super::motion::trapezoid::Phase;
use super::setup::{HomeConfig, IndexConfig, PlsConfig};
use crate::registry::catalog::{
    GEAR_TYPE, HOME_TYPE, INDEX_TYPE, JOG_TYPE, MOTION_TYPE, PLS_TYPE, PROFILE_TYPE,
};
use crate::registry::{Registry, SlotId};

crate::bind_slots! {
    /// The slots of one index's settings and status.
    pub struct IndexSlots for INDEX_TYPE {
        distance: "Distance",
        velocity: "Velocity",
        acceleration: "Acceleration",
        deceleration: "Deceleration",
        in_progress: "CommandInProgress",
        at_vel: "AtVel",
        decelerating: "Decelerating",
        complete: "CommandComplete",
        registration_offset: "RegistrationOffset",
        limit_hit: "LimitDistHit",
        sensor: "SensorTrigger",
        time: "Time",
        profile_limited: "ProfileLimited",
        pls_status: "PLSStatus",
        pls_on: "PLSOnPoint",
        pls_off: "PLSOffPoint",
        compound: "CompoundInitiate",
    }
}

crate::bind_slots! {
    /// The slots of one home's settings and status.
    pub struct HomeSlots for HOME_TYPE {
        velocity: "Velocity",
        acceleration: "Acceleration",
        deceleration: "Deceleration",
        offset: "Offset",
        in_progress: "CommandInProgress",
        at_vel: "AtVel",
        complete: "CommandComplete",
    }
}

crate::bind_slots! {
    /// The slots of one jog's settings and status.
    pub struct JogSlots for JOG_TYPE {
        velocity: "Velocity",
        acceleration: "Acceleration",
        deceleration: "Deceleration",
        in_progress: "CommandInProgress",
        minus_initiate: "MinusInitiate",
    }
}

crate::bind_slots! {
    /// The slots of one programmable limit switch.
    pub struct PlsSlots for PLS_TYPE {
        enable: "Enable",
        on: "OnPosn",
        off: "OffPosn",
        direction: "Direction",
        status: "Status",
    }
}

crate::bind_slots! {
    /// The slots of the gear's members.
    pub struct GearSlots for GEAR_TYPE {
        ratio: "Ratio",
        activate: "Activate",
        in_progress: "CommandInProgress",
    }
}

crate::bind_slots! {
    /// The slots of the drive-wide members (written bare in programs: `FeedRateOverride`).
    pub struct AxisSlots for MOTION_TYPE {
        command: "PosnCommand",
        feedback: "PosnFeedback",
        vel_feedback: "VelFeedback",
        following_error: "FollowingError",
        fe_limit: "FollowingErrorLimit",
        fe_enable: "FollowingErrorEnable",
        fault: "FollowingErrorFault",
        velocity: "VelCommand",
        revs: "MotorRevs",
        counts: "MotorCounts",
        master_counts: "MasterCounts",
        feed_rate: "FeedRateOverride",
        feed_rate_off: "FeedRateDeactivate",
        stop_decel: "StopDeceleration",
        free_run: "FreeRunTime",
    }
}

crate::bind_slots! {
    /// The slot of a profile's status.
    pub struct ProfileSlots for PROFILE_TYPE {
        busy: "Busy",
    }
}

/// The slots of the jog's own members (`Jog.Select`, `Jog.PlusActivate` …).
#[derive(Debug, Clone, Copy)]
pub struct JogGlobals {
    /// `Jog.Select`: which jog's settings `PlusActivate`/`MinusActivate` use.
    pub select: SlotId,
    /// `Jog.PlusActivate`.
    pub plus: SlotId,
    /// `Jog.MinusActivate`.
    pub minus: SlotId,
}

impl JogGlobals {
    /// The jog's own members.
    pub fn of(registry: &Registry) -> JogGlobals {
        JogGlobals {
            select: crate::global_slot!(registry, JOG_TYPE, "Select"),
            plus: crate::global_slot!(registry, JOG_TYPE, "PlusActivate"),
            minus: crate::global_slot!(registry, JOG_TYPE, "MinusActivate"),
        }
    }
}

/// The slot of `Index.ProfileLimited` (no instance): on while any index's is.
pub fn index_limited(registry: &Registry) -> SlotId {
    crate::global_slot!(registry, INDEX_TYPE, "ProfileLimited")
}

/// An index: its set-up and its slots.
#[derive(Debug, Clone)]
pub struct IndexObject {
    /// The set-up `machine.toml` gives.
    pub config: IndexConfig,
    /// Its members.
    pub s: IndexSlots,
}

impl IndexObject {
    /// Index `i` of the registry, set up as `config` says.
    pub fn new(registry: &Registry, i: u32, config: IndexConfig) -> IndexObject {
        IndexObject {
            config,
            s: IndexSlots::of(registry, i),
        }
    }

    /// The status members in `phase`.
    pub fn status(&self, v: &mut [f64], phase: Phase) {
        let running = phase != Phase::Done;
        v[self.s.in_progress as usize] = f64::from(running);
        v[self.s.at_vel as usize] = f64::from(phase == Phase::AtVelocity);
        v[self.s.decelerating as usize] = f64::from(phase == Phase::Decelerating);
        v[self.s.complete as usize] = f64::from(!running);
    }
}

/// A home: its set-up and its slots.
#[derive(Debug, Clone)]
pub struct HomeObject {
    /// The set-up `machine.toml` gives.
    pub config: HomeConfig,
    /// Its members.
    pub s: HomeSlots,
}

impl HomeObject {
    /// Home `i` of the registry, set up as `config` says.
    pub fn new(registry: &Registry, i: u32, config: HomeConfig) -> HomeObject {
        HomeObject {
            config,
            s: HomeSlots::of(registry, i),
        }
    }

    /// The status members in `phase`.
    pub fn status(&self, v: &mut [f64], phase: Phase) {
        let running = phase != Phase::Done;
        v[self.s.in_progress as usize] = f64::from(running);
        v[self.s.at_vel as usize] = f64::from(phase == Phase::AtVelocity);
        v[self.s.complete as usize] = f64::from(!running);
    }
}

/// A programmable limit switch: a window on a position.
#[derive(Debug, Clone)]
pub struct PlsObject {
    /// The set-up `machine.toml` gives.
    pub config: PlsConfig,
    /// Its members.
    pub s: PlsSlots,
}

impl PlsObject {
    /// PLS `i` of the registry, set up as `config` says.
    pub fn new(registry: &Registry, i: u32, config: PlsConfig) -> PlsObject {
        PlsObject {
            config,
            s: PlsSlots::of(registry, i),
        }
    }

    /// On while the position is in [On, Off) (with rollover, On > Off means outside [Off, On)),
    /// and the source moves in the PLS's direction.
    pub fn evaluate(&self, position: f64, velocity: f64, v: &mut [f64]) {
        // Most PLSs of a machine are off or empty: nothing to compute (rem_euclid is not cheap).
        let (on, off) = (v[self.s.on as usize], v[self.s.off as usize]);
        // Enabled is their default, but a window never set (On = Off) holds no position.
        if v[self.s.enable as usize] == 0.0 || on == off {
            v[self.s.status as usize] = 0.0;
            return;
        }
        let p = if self.config.rollover > 0.0 {
            position.rem_euclid(self.config.rollover)
        } else {
            position
        };
        let inside = if on <= off {
            on <= p && p < off
        } else {
            p >= on || p < off
        };
        let direction = v[self.s.direction as usize];
        let heading = direction == 0.0
            || (direction > 0.0 && velocity > 0.0)
            || (direction < 0.0 && velocity < 0.0);
        v[self.s.status as usize] = f64::from(inside && heading);
    }
}
