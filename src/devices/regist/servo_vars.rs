//! READ_SV / WRITE_SV of registration's servo variables 9–25.

use super::{err, Regist, RegistError};

/// The numbers READ_SV accepts, for messages.
const READABLE: &str = "9, 10, 11, 13 to 20, 22, 23, 24 and 25";
/// The numbers WRITE_SV accepts, for messages.
const WRITABLE: &str = "10, 11, 17, 18, 24 and 25";

/// Shortest minimum time between marks (var 25), seconds: the note's 2 ms.
pub const MIN_TIME_LOWEST: f64 = 0.002;
/// Longest minimum time between marks (var 25), seconds: longer would hide marks for no reason
/// any machine has, so it is taken as a mistake.
pub const MIN_TIME_HIGHEST: f64 = 1.0;

/// `value` as a whole number in `0..=max`, or why not.
fn whole(var: u32, value: f64, max: u32) -> Result<u32, RegistError> {
    if value.is_finite() && value >= 0.0 && value <= f64::from(max) && value.fract() == 0.0 {
        // In range and whole, so the conversion is exact.
        Ok(value as u32)
    } else {
        err(format!(
            "servo variable {var} takes a whole number from 0 to {max}, not {value}"
        ))
    }
}

impl Regist {
    /// READ_SV: 9 and 22 the latched fast-input position, 10 the last correction (or the
    /// value last written), 11 consecutive bad marks, 13/14 slave/master offset released at
    /// the last update, 15/16 their running sums, 17/18 the filters, 19 the direction of travel
    /// at the last mark (+1, -1, 0 unknown), 20 its distance from the ruler (0 for an entrant
    /// mark), 23 the position of the last mark (with a single axis there is no "axis 1 with
    /// fast input on axis 2"; the mark's own position is the nearest meaning), 24 the switches,
    /// 25 the minimum time between marks in seconds.
    pub fn read_sv(&self, var: u32) -> Result<f64, RegistError> {
        Ok(match var {
            9 | 22 | 23 => self.latch,
            10 => self.last_correction,
            11 => f64::from(self.bad_count),
            13 => self.slave.incremental,
            14 => self.master.incremental,
            15 => self.slave.absolute,
            16 => self.master.absolute,
            17 => f64::from(self.slave.filter),
            18 => f64::from(self.master.filter),
            19 => self.direction,
            20 => self.distance,
            24 => f64::from(self.switches),
            25 => self.min_time,
            _ => {
                return err(format!(
                    "servo variable {var} is not a registration variable (READ_SV takes {READABLE})"
                ))
            }
        })
    }

    /// WRITE_SV: 10 queues `value` as an extra correction through the same switches, filters
    /// and release conditions as a mark's, and becomes var 10 (the note's start-up idiom:
    /// negate the first correction and write it back to align); 11 sets the bad-mark count
    /// (normally 0 to reset it); 17/18 filters (whole updates, 0 or 1 = at once; a spread in
    /// progress keeps its count, the new value applies from the next correction); 24 switches
    /// 0..=7; 25 seconds in [0.002, 1]. Others are read-only or not registration variables.
    pub fn write_sv(&mut self, var: u32, value: f64) -> Result<(), RegistError> {
        match var {
            10 => {
                if !value.is_finite() {
                    return err(format!("servo variable 10 must be finite, not {value}"));
                }
                self.last_correction = value;
                self.apply_correction(value);
            }
            11 => self.bad_count = whole(var, value, u32::MAX)?,
            17 => self.slave.filter = whole(var, value, u32::MAX)?,
            18 => self.master.filter = whole(var, value, u32::MAX)?,
            24 => self.switches = whole(var, value, 7)?,
            25 => {
                if !(value.is_finite() && (MIN_TIME_LOWEST..=MIN_TIME_HIGHEST).contains(&value)) {
                    return err(format!(
                        "servo variable 25 (minimum time between marks) takes {MIN_TIME_LOWEST} to {MIN_TIME_HIGHEST} seconds, not {value}"
                    ));
                }
                self.min_time = value;
            }
            9 | 13..=16 | 19 | 20 | 22 | 23 => {
                return err(format!(
                    "servo variable {var} is read-only (WRITE_SV takes {WRITABLE})"
                ))
            }
            _ => {
                return err(format!(
                "servo variable {var} is not a registration variable (WRITE_SV takes {WRITABLE})"
            ))
            }
        }
        Ok(())
    }
}
