//! SENS.MODE@, the ZREF/ASEN/BSEN position latches, card input edges with their PLS gate, and
//! sensor marks tied to an axis position (the simulated world's printed marks).

use super::pls::wrap;
use super::{err, DspAxes, DspError, DspEvent, Sensor, Trigger};

/// A parsed SENS.MODE@ string.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct SensMode {
    /// Latch on the rising edge (else falling) of ZREF, ASEN, BSEN.
    rising: [bool; 3],
    /// ASEN gated by PLS1, BSEN gated by PLS2.
    gated: [bool; 2],
}

impl Default for SensMode {
    /// "RRRNN": every input latches on its rising edge, none is gated.
    fn default() -> SensMode {
        SensMode {
            rising: [true; 3],
            gated: [false; 2],
        }
    }
}

const INPUTS: [&str; 3] = ["ZREF", "ASEN", "BSEN"];

impl SensMode {
    /// Parse five characters, case-insensitive: three edges (R/F) then two gates (G/N).
    fn parse(text: &str) -> Result<SensMode, String> {
        let chars: Vec<char> = text.chars().collect();
        if chars.len() != 5 {
            return Err(format!(
                "SENS.MODE@ needs exactly 5 characters (ZREF, ASEN, BSEN edge: R or F; ASEN, BSEN gate: G or N), not \"{text}\" ({} characters)",
                chars.len()
            ));
        }
        let mut mode = SensMode::default();
        for (k, c) in chars.iter().enumerate() {
            let up = c.to_ascii_uppercase();
            let (ok, what) = if k < 3 {
                mode.rising[k] = up == 'R';
                (
                    up == 'R' || up == 'F',
                    format!("R (rising) or F (falling) for the {} edge", INPUTS[k]),
                )
            } else {
                mode.gated[k - 3] = up == 'G';
                let pls = k - 2;
                (
                    up == 'G' || up == 'N',
                    format!(
                        "G (gated by PLS{pls}) or N (not gated) for {}",
                        INPUTS[k - 2]
                    ),
                )
            };
            if !ok {
                return Err(format!(
                    "SENS.MODE@ \"{text}\": character {} is '{c}', it must be {what}",
                    k + 1
                ));
            }
        }
        Ok(mode)
    }

    fn text(&self) -> String {
        let edges = self.rising.iter().map(|&r| if r { 'R' } else { 'F' });
        let gates = self.gated.iter().map(|&g| if g { 'G' } else { 'N' });
        edges.chain(gates).collect()
    }

    /// The PLS (1 or 2) gating `which`, if SENS.MODE gates it.
    fn gate(&self, which: Sensor) -> Option<usize> {
        match which {
            Sensor::Zref => None,
            Sensor::Asen => self.gated[0].then_some(1),
            Sensor::Bsen => self.gated[1].then_some(2),
        }
    }
}

/// One position latch.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Latch {
    latched: bool,
    /// Absolute position taken (0 until the first latch).
    position: f64,
}

/// Marks on the path of an axis, seen by a sensor wired to a card input.
#[derive(Debug, Clone)]
pub(super) struct Marks {
    axis: usize,
    card: u32,
    which: Sensor,
    /// Mark starts and ends, ascending: even indexes start a mark (the sensor turns on when the
    /// axis passes upwards), odd ones end it.
    bounds: Vec<f64>,
}

impl DspAxes {
    /// SENS.MODE@: e.g. "RRRGN". A bad string is refused, naming the character.
    pub fn set_sens_mode(&mut self, axis: u32, mode: &str) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        self.axes[i].sens = SensMode::parse(mode).map_err(DspError)?;
        Ok(())
    }

    /// The SENS.MODE@ string in force, upper case.
    pub fn sens_mode(&self, axis: u32) -> Result<String, DspError> {
        Ok(self.axes[self.axis(axis)?].sens.text())
    }

    /// `ASEN@(axis) = 0` and the like: re-arm the latch.
    pub fn clear_latch(&mut self, axis: u32, which: Sensor) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        self.axes[i].latches[which.index()].latched = false;
        Ok(())
    }

    /// `ASEN(axis)`: true once the armed latch took a position.
    pub fn latched(&self, axis: u32, which: Sensor) -> Result<bool, DspError> {
        Ok(self.axes[self.axis(axis)?].latches[which.index()].latched)
    }

    /// `POS.ASEN@(axis)`: the latched position modulo POS.MOD (0 before any latch).
    pub fn latched_position(&self, axis: u32, which: Sensor) -> Result<f64, DspError> {
        let a = &self.axes[self.axis(axis)?];
        Ok(wrap(a.latches[which.index()].position, a.pos_mod))
    }

    /// An edge of input `which` of DSP card `card` at `t` (inside the last update): unless a
    /// gating axis's PLS is off, every armed axis of the card whose polarity matches latches its
    /// exact position at `t`.
    pub fn card_edge(
        &mut self,
        card: u32,
        which: Sensor,
        rising: bool,
        t: f64,
    ) -> Result<Vec<DspEvent>, DspError> {
        self.check_time(t)?;
        if !self.axes.iter().any(|a| a.card == card) {
            return err(format!("DSP card {card} has no configured axis"));
        }
        let mut events = Vec::new();
        self.edge(card, which, rising, t, &mut events);
        Ok(events)
    }

    /// Apply an edge to the latches of the card's axes; false when a PLS gate blinded it.
    fn edge(
        &mut self,
        card: u32,
        which: Sensor,
        rising: bool,
        t: f64,
        events: &mut Vec<DspEvent>,
    ) -> bool {
        let on_card: Vec<usize> = (0..self.axes.len())
            .filter(|&i| self.axes[i].card == card)
            .collect();
        let k = which.index();
        let blind = on_card.iter().any(|&i| {
            let a = &self.axes[i];
            a.sens
                .gate(which)
                .is_some_and(|n| !a.pls.active(n, self.pos_at(i, t)))
        });
        if blind {
            if on_card
                .iter()
                .any(|&i| self.axes[i].sens.rising[k] == rising)
            {
                events.push(DspEvent::EdgeBlinded {
                    card,
                    which,
                    time: t,
                });
            }
            return false;
        }
        for i in on_card {
            let absolute = self.pos_at(i, t);
            let a = &mut self.axes[i];
            if a.sens.rising[k] != rising || a.latches[k].latched {
                continue;
            }
            a.latches[k] = Latch {
                latched: true,
                position: absolute,
            };
            let position = wrap(absolute, a.pos_mod);
            events.push(DspEvent::Latched {
                axis: a.number,
                which,
                time: t,
                position,
                absolute,
            });
        }
        true
    }

    /// A sensor wired to input `which` of `card`, on while axis `axis` is within
    /// `[mark, mark + width)` of a mark. Marks ascending, not touching one another.
    pub fn add_marks(
        &mut self,
        axis: u32,
        card: u32,
        which: Sensor,
        positions: Vec<f64>,
        width: f64,
    ) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        if !self.axes.iter().any(|a| a.card == card) {
            return err(format!(
                "marks on axis {axis}: DSP card {card} has no configured axis"
            ));
        }
        if !(width.is_finite() && width > 0.0) {
            return err(format!(
                "marks on axis {axis}: the width must be above 0, not {width}"
            ));
        }
        let mut bounds = Vec::with_capacity(positions.len() * 2);
        for &p in &positions {
            if !p.is_finite() {
                return err(format!(
                    "marks on axis {axis}: position {p} is not a number"
                ));
            }
            if let Some(&end) = bounds.last() {
                if p <= end {
                    return err(format!("marks on axis {axis}: the mark at {p} is not after the end of the previous one ({end}): marks must ascend and not touch"));
                }
            }
            bounds.push(p);
            bounds.push(p + width);
        }
        self.marks.push(Marks {
            axis: i,
            card,
            which,
            bounds,
        });
        Ok(())
    }

    /// The card edges made by the marks the axes crossed in [ta, tb], applied in time order,
    /// up to the first that starts a gear `waiting` (per axis: the sensor and since when) that
    /// is not one of the edges `found` already: that edge is returned, the rest not applied.
    pub(super) fn mark_edges(
        &mut self,
        before: &[f64],
        ta: f64,
        tb: f64,
        waiting: &[Option<(Sensor, f64)>],
        found: &[(f64, Trigger)],
        events: &mut Vec<DspEvent>,
    ) -> Option<(f64, Trigger)> {
        // (time, card, which, rising), in the order found; the sort below is stable.
        let mut edges: Vec<(f64, u32, Sensor, bool)> = Vec::new();
        for m in &self.marks {
            if m.bounds.is_empty() {
                continue;
            }
            let mut prev = (ta, before[m.axis]);
            for s in self.samples(m.axis, ta, tb) {
                let p = self.pos_at(m.axis, s);
                let up = p > prev.1;
                let (lo, hi) = if up { (prev.1, p) } else { (p, prev.1) };
                // Bounds b with lo < b <= hi: where "position >= b" changed.
                let first = m.bounds.partition_point(|&b| b <= lo);
                let last = m.bounds.partition_point(|&b| b <= hi);
                let crossed: Vec<usize> = if up {
                    (first..last).collect()
                } else {
                    (first..last).rev().collect()
                };
                for k in crossed {
                    let b = m.bounds[k];
                    let dir = if up { 1.0 } else { -1.0 };
                    // A jump (a step at the start of the update) has no time inside.
                    let t = if prev.0 == s {
                        s
                    } else {
                        self.first_reach(m.axis, b, dir, prev.0, s).unwrap_or(s)
                    };
                    // Upwards a mark's start turns the sensor on; downwards its end does.
                    let rising = (k % 2 == 0) == up;
                    edges.push((t, m.card, m.which, rising));
                }
                prev = (s, p);
            }
        }
        edges.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (t, card, which, rising) in edges {
            if !self.edge(card, which, rising, t, events) {
                continue;
            }
            // The edge a latch of the same axis would take: its SENS.MODE@ polarity, through
            // the same gate (checked above), from the instant the gear began to wait.
            let starts = (0..self.axes.len()).find(|&i| {
                let a = &self.axes[i];
                a.card == card
                    && a.sens.rising[which.index()] == rising
                    && waiting
                        .get(i)
                        .copied()
                        .flatten()
                        .is_some_and(|(w, since)| w == which && since <= t)
                    && !found.contains(&(t, Trigger::Sensor(i, which)))
            });
            if let Some(i) = starts {
                return Some((t, Trigger::Sensor(i, which)));
            }
        }
        None
    }
}
