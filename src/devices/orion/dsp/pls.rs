//! Programmable limit switches (PLS.MOD@, PLSn.LOW@, PLSn.HIGH@) and POS.MOD@ rollover.

use super::{err, DspAxes, DspError};

/// The three PLS of an axis: on while the position within the cycle is in [LOW, HIGH).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Pls {
    /// Cycle length (0: the raw position).
    cycle: f64,
    low: [Option<f64>; 3],
    high: [Option<f64>; 3],
}

impl Pls {
    /// PLS `n` (1..=3) with the axis at `position`. LOW above HIGH wraps around the cycle; LOW
    /// equal to HIGH, or either unset, is never on.
    pub(super) fn active(&self, n: usize, position: f64) -> bool {
        let k = n.wrapping_sub(1);
        let (Some(&Some(low)), Some(&Some(high))) = (self.low.get(k), self.high.get(k)) else {
            return false;
        };
        let q = wrap(position, self.cycle);
        if low < high {
            low <= q && q < high
        } else if low > high {
            q >= low || q < high
        } else {
            false
        }
    }
}

/// `p` modulo `m` in [0, m) when m > 0, else `p` itself.
pub(super) fn wrap(p: f64, m: f64) -> f64 {
    if m > 0.0 {
        let q = p.rem_euclid(m);
        // rem_euclid can round up to m itself for a tiny negative p.
        if q >= m {
            0.0
        } else {
            q
        }
    } else {
        p
    }
}

fn pls_index(axis: u32, n: u32) -> Result<usize, DspError> {
    if (1..=3).contains(&n) {
        Ok(n as usize - 1)
    } else {
        err(format!("axis {axis} has PLS1 to PLS3, not PLS{n}"))
    }
}

fn finite(what: &str, axis: u32, value: f64) -> Result<f64, DspError> {
    if value.is_finite() {
        Ok(value)
    } else {
        err(format!(
            "{what} of axis {axis} must be a number, not {value}"
        ))
    }
}

fn cycle(what: &str, axis: u32, value: f64) -> Result<f64, DspError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        err(format!(
            "{what} of axis {axis} must be 0 (none) or above, not {value}"
        ))
    }
}

impl DspAxes {
    /// PLS.MOD@: the PLS cycle length (0: PLS compare the raw position).
    pub fn set_pls_mod(&mut self, axis: u32, cycle_len: f64) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        self.axes[i].pls.cycle = cycle("PLS.MOD@", axis, cycle_len)?;
        Ok(())
    }

    /// PLSn.LOW@: where PLS `n` turns on within the cycle.
    pub fn set_pls_low(&mut self, axis: u32, n: u32, pos: f64) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        let k = pls_index(axis, n)?;
        self.axes[i].pls.low[k] = Some(finite(&format!("PLS{n}.LOW@"), axis, pos)?);
        Ok(())
    }

    /// PLSn.HIGH@: where PLS `n` turns off within the cycle.
    pub fn set_pls_high(&mut self, axis: u32, n: u32, pos: f64) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        let k = pls_index(axis, n)?;
        self.axes[i].pls.high[k] = Some(finite(&format!("PLS{n}.HIGH@"), axis, pos)?);
        Ok(())
    }

    /// PLS.MOD@, PLSn.LOW@, PLSn.HIGH@ as set (LOW and HIGH 0 while unset).
    pub fn pls_settings(&self, axis: u32, n: u32) -> Result<(f64, f64, f64), DspError> {
        let a = &self.axes[self.axis(axis)?];
        let k = pls_index(axis, n)?;
        Ok((
            a.pls.cycle,
            a.pls.low[k].unwrap_or(0.0),
            a.pls.high[k].unwrap_or(0.0),
        ))
    }

    /// Whether PLS `n` of the axis is on at `t` (inside the last update).
    pub fn pls_active(&self, axis: u32, n: u32, t: f64) -> Result<bool, DspError> {
        let i = self.axis(axis)?;
        pls_index(axis, n)?;
        self.check_time(t)?;
        Ok(self.axes[i].pls.active(n as usize, self.pos_at(i, t)))
    }

    /// POS.MOD@: report positions modulo `m` (0: no rollover). The axis keeps its absolute
    /// position inside, so gearing and latches never see a jump.
    pub fn set_pos_mod(&mut self, axis: u32, m: f64) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        self.axes[i].pos_mod = cycle("POS.MOD@", axis, m)?;
        Ok(())
    }

    /// POS.MOD@ as set.
    pub fn pos_mod(&self, axis: u32) -> Result<f64, DspError> {
        Ok(self.axes[self.axis(axis)?].pos_mod)
    }

    /// The position now as the program sees it: modulo POS.MOD@ in [0, POS.MOD@).
    pub fn reported_position(&self, axis: u32) -> Result<f64, DspError> {
        let i = self.axis(axis)?;
        Ok(wrap(self.pos_at(i, self.t_now), self.axes[i].pos_mod))
    }
}
