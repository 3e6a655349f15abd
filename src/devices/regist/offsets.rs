//! One offset channel (slave or master) of registration: the corrections owed to it, released
//! through its filter only while the correction may move the slave.

/// A slave or master offset: corrections waiting, the filter that spreads them, and what was
/// released (servo variables 13/14 incremental, 15/16 absolute, 17/18 filter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Channel {
    /// Updates a correction is spread over (0 and 1: at once).
    pub filter: u32,
    /// Correction queued but not yet released.
    pending: f64,
    /// Releasing updates left for `pending`; 0 when nothing is owed.
    remaining: u32,
    /// Released at the last update (servo variable 13 or 14).
    pub incremental: f64,
    /// Sum of everything released (servo variable 15 or 16).
    pub absolute: f64,
}

impl Channel {
    /// A channel that owes nothing and releases at once.
    pub fn new() -> Channel {
        Channel {
            filter: 0,
            pending: 0.0,
            remaining: 0,
            incremental: 0.0,
            absolute: 0.0,
        }
    }

    /// Owe `amount` more. A correction arriving while an earlier one is still being spread
    /// joins its remainder and the sum is spread over a fresh `filter` updates: one running
    /// total keeps the state bounded however many marks arrive while the master stands, and the
    /// released amounts still sum to exactly what was queued. A zero amount changes nothing (it
    /// must not restart a spread in progress).
    pub fn queue(&mut self, amount: f64) {
        if amount == 0.0 {
            return;
        }
        self.pending += amount;
        self.remaining = self.filter.max(1);
    }

    /// The amount released at this update: nothing unless `running` (registration never moves
    /// the slave by itself), else an even share of what is owed; the last share is the exact
    /// remainder, so the shares sum to the queued correction.
    pub fn release(&mut self, running: bool) -> f64 {
        let step = if !running || self.remaining == 0 {
            0.0
        } else if self.remaining == 1 {
            self.pending
        } else {
            self.pending / f64::from(self.remaining)
        };
        if running && self.remaining > 0 {
            self.remaining -= 1;
            self.pending = if self.remaining == 0 {
                0.0
            } else {
                self.pending - step
            };
        }
        self.incremental = step;
        self.absolute += step;
        step
    }
}
