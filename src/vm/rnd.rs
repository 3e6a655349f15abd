//! MotionBASIC's `RND` and `RANDOMIZE`: Microsoft QuickBASIC's generator, a 24-bit linear
//! congruential sequence, so a program gives the numbers it gives on a QuickBASIC-derived
//! BASIC. The run starts from QuickBASIC's own seed, or — when the scenario says `[run] seed`
//! — from `RANDOMIZE seed`: deterministic either way, as every simulated run is.

/// The generator's state.
#[derive(Debug, Clone, PartialEq)]
pub struct Rnd {
    seed: u32,
    last: f64,
}

/// QuickBASIC's seed before any `RANDOMIZE`.
const START: u32 = 0x0005_0000;
const MASK: u32 = 0x00FF_FFFF;

impl Rnd {
    /// The generator at the start of a run.
    pub fn new(scenario_seed: Option<u64>) -> Rnd {
        let mut r = Rnd {
            seed: START,
            last: 0.0,
        };
        if let Some(s) = scenario_seed {
            r.randomize(s as f64);
        }
        r
    }

    /// The next number, in [0, 1).
    fn next(&mut self) -> f64 {
        self.seed = self
            .seed
            .wrapping_mul(0x43FD_43FD)
            .wrapping_add(0x00C3_9EC3)
            & MASK;
        self.last = f64::from(self.seed) / f64::from(MASK + 1);
        self.last
    }

    /// `RND` (no argument or a positive one: the next number), `RND(0)` (the last again) or
    /// `RND(x)` with x < 0 (a sequence started from x: the same x gives the same numbers).
    pub fn call(&mut self, arg: Option<f64>) -> f64 {
        match arg {
            Some(0.0) => self.last,
            Some(x) if x < 0.0 => {
                let bits = (x as f32).to_bits();
                self.seed = bits.wrapping_add(bits >> 24) & MASK;
                self.next()
            }
            _ => self.next(),
        }
    }

    /// `RANDOMIZE n`: the seed's middle bytes from the high words of `n` as a double.
    pub fn randomize(&mut self, n: f64) {
        let hi = (n.to_bits() >> 32) as u32;
        let word = (hi ^ (hi >> 16)) & 0xFFFF;
        self.seed = ((self.seed & 0xFF) | (word << 8)) & MASK;
    }
}

#[cfg(test)]
mod tests {
    use super::Rnd;

    /// QuickBASIC 4.5 prints .7055475, .533424, .5795186 for its first three `PRINT RND`.
    #[test]
    fn first_numbers_are_quickbasics() {
        let mut r = Rnd::new(None);
        let got: Vec<f32> = (0..3).map(|_| r.call(None) as f32).collect();
        assert_eq!(got, vec![0.705_547_5, 0.533_424, 0.579_518_6]);
    }

    #[test]
    fn zero_repeats_and_negative_restarts() {
        let mut r = Rnd::new(None);
        let a = r.call(None);
        assert_eq!(r.call(Some(0.0)), a);
        let x = r.call(Some(-3.0));
        r.call(None);
        assert_eq!(r.call(Some(-3.0)), x);
    }

    #[test]
    fn a_seed_gives_its_own_sequence() {
        let mut a = Rnd::new(Some(7));
        let mut b = Rnd::new(Some(7));
        let mut c = Rnd::new(Some(8));
        let sa: Vec<f64> = (0..5).map(|_| a.call(None)).collect();
        let sb: Vec<f64> = (0..5).map(|_| b.call(None)).collect();
        let sc: Vec<f64> = (0..5).map(|_| c.call(None)).collect();
        assert_eq!(sa, sb);
        assert_ne!(sa, sc);
    }
}
