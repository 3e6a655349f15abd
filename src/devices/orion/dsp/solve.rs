//! When does an axis reach a position inside the last update? Analytic on time-based pieces;
//! on geared ones, the interval is first cut at every instant the motion may turn back (piece
//! starts, the pacer's own turning points) and at uniform samples, then the first bracketing
//! sub-interval is bisected to full f64 precision.

use super::gear::BasePiece;
use super::DspAxes;

/// Uniform samples per interval on pacer-driven motion: the follower can turn back between the
/// pacer's turning points (a ratio changing sign, a GEAR FOR against the gear), and a crossing
/// and return inside one sample is the only one that can be missed.
const SAMPLES: usize = 16;

impl DspAxes {
    /// Instants in [t0, t1] (both included, ascending, no duplicates) between which axis `i`
    /// moves one way only, except for the turns uniform sampling can miss.
    pub(super) fn samples(&self, i: usize, t0: f64, t1: f64) -> Vec<f64> {
        let mut out = vec![t0, t1];
        self.collect_samples(i, t0, t1, &mut out);
        out.retain(|t| t0 <= *t && *t <= t1);
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    fn collect_samples(&self, i: usize, t0: f64, t1: f64, out: &mut Vec<f64>) {
        let a = &self.axes[i];
        let mut paced = false;
        for &(s, piece) in &a.base.hist {
            out.push(s);
            if let Some(v) = piece.vertex() {
                out.push(v);
            }
            paced |= piece.geared() && s <= t1;
        }
        for &(s, piece) in &a.sup.hist {
            out.push(s);
            paced |= piece.moving.is_some() && s <= t1;
        }
        if let (true, Some(p)) = (paced, a.pacer) {
            self.collect_samples(p, t0, t1, out);
            for k in 1..SAMPLES {
                out.push(t0 + (t1 - t0) * k as f64 / SAMPLES as f64);
            }
        }
    }

    /// The first time in [t0, t1] axis `i` is at or beyond `target` in direction `dir` (+1: at or
    /// above, −1: at or below).
    pub(super) fn first_reach(
        &self,
        i: usize,
        target: f64,
        dir: f64,
        t0: f64,
        t1: f64,
    ) -> Option<f64> {
        let reached = |t: f64| (self.pos_at(i, t) - target) * dir >= 0.0;
        if reached(t0) {
            return Some(t0);
        }
        let samples = self.samples(i, t0, t1);
        for w in samples.windows(2) {
            let (s0, s1) = (w[0], w[1]);
            if !reached(s1) {
                continue;
            }
            if let Some(t) = self.analytic(i, target, s0, s1) {
                return Some(t);
            }
            // Bisection: `lo` never reached, `hi` reached, until no float lies between them.
            let (mut lo, mut hi) = (s0, s1);
            loop {
                let mid = lo + (hi - lo) * 0.5;
                if mid <= lo || mid >= hi {
                    return Some(hi);
                }
                if reached(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
        }
        None
    }

    /// The crossing of `target` in [s0, s1] when axis `i` is purely time-based there (one
    /// quadratic piece and a constant offset): the first root of the quadratic in range.
    fn analytic(&self, i: usize, target: f64, s0: f64, s1: f64) -> Option<f64> {
        let a = &self.axes[i];
        let sup = a.sup.piece_at(s0);
        let BasePiece::Time { t0, p0, v0, a: acc } = a.base.piece_at(s0) else {
            return None;
        };
        if sup.moving.is_some() {
            return None;
        }
        // ½·acc·τ² + v0·τ + c = 0, τ from the piece's own start.
        let c = p0 + sup.acc - target;
        let roots: [Option<f64>; 2] = if acc == 0.0 {
            [(v0 != 0.0).then(|| -c / v0), None]
        } else {
            let disc = v0 * v0 - 2.0 * acc * c;
            if disc < 0.0 {
                return None;
            }
            // The numerically stable pair: no cancellation between v0 and the root.
            let sign = if v0 < 0.0 { -1.0 } else { 1.0 };
            let q = -0.5 * (v0 + sign * disc.sqrt());
            [Some(q / (0.5 * acc)), (q != 0.0).then(|| c / q)]
        };
        roots
            .into_iter()
            .flatten()
            .map(|tau| t0 + tau)
            .filter(|t| t.is_finite() && s0 <= *t && *t <= s1)
            .min_by(f64::total_cmp)
    }
}
