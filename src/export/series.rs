//! Time series kept for plots in bounded memory, however long the run: values fall into time
//! buckets that double in width whenever there are too many, each bucket keeping its first,
//! least, greatest and last value. A plot is at most a few thousand pixels wide, so this is all it
//! can show, and a signal that toggles faster than a pixel still draws as the band it fills.

/// Buckets kept per series before they are merged in pairs.
const CAP: usize = 4096;

#[derive(Debug, Clone, Copy)]
struct Bucket {
    index: i64,
    t0: f64,
    t1: f64,
    first: f64,
    min: f64,
    max: f64,
    last: f64,
}

/// One signal over time.
#[derive(Debug, Clone)]
pub struct Series {
    origin: f64,
    width: f64,
    buckets: Vec<Bucket>,
    /// The value in force when the window opened (the last change before it).
    pub before: Option<f64>,
    /// It changed during the run (not just held the value it started with).
    pub changed: bool,
    /// A level not yet added: later changes at the same time replace it.
    pending: Option<(f64, f64)>,
}

impl Series {
    /// An empty series whose buckets start at `origin`, at first `width` seconds wide.
    pub fn new(origin: f64, width: f64) -> Series {
        Series {
            origin,
            width: width.max(1e-9),
            buckets: Vec::new(),
            before: None,
            changed: false,
            pending: None,
        }
    }

    /// Add a value at time `t` (times never decrease).
    pub fn push(&mut self, t: f64, v: f64) {
        if !v.is_finite() {
            return;
        }
        self.changed = true;
        let index = ((t - self.origin) / self.width).floor() as i64;
        match self.buckets.last_mut() {
            Some(b) if b.index == index => {
                b.t1 = t;
                b.last = v;
                b.min = b.min.min(v);
                b.max = b.max.max(v);
            }
            _ => {
                self.buckets.push(Bucket {
                    index,
                    t0: t,
                    t1: t,
                    first: v,
                    min: v,
                    max: v,
                    last: v,
                });
                if self.buckets.len() > CAP {
                    self.coarsen();
                }
            }
        }
    }

    /// Set the level at time `t`: of several values written at one time (a program's writes
    /// within one update) only the last is the level it had, as a VCD shows it.
    pub fn level(&mut self, t: f64, v: f64) {
        match self.pending {
            Some((pt, _)) if pt.to_bits() == t.to_bits() => self.pending = Some((t, v)),
            _ => {
                self.flush();
                self.pending = Some((t, v));
            }
        }
    }

    /// Add the pending level, if any.
    pub fn flush(&mut self) {
        if let Some((t, v)) = self.pending.take() {
            self.push(t, v);
        }
    }

    /// Double the bucket width, merging buckets in pairs.
    fn coarsen(&mut self) {
        self.width *= 2.0;
        let mut merged: Vec<Bucket> = Vec::with_capacity(self.buckets.len() / 2 + 1);
        for b in self.buckets.drain(..) {
            let index = b.index.div_euclid(2);
            match merged.last_mut() {
                Some(m) if m.index == index => {
                    m.t1 = b.t1;
                    m.last = b.last;
                    m.min = m.min.min(b.min);
                    m.max = m.max.max(b.max);
                }
                _ => merged.push(Bucket { index, ..b }),
            }
        }
        self.buckets = merged;
    }

    /// No value at all, not even one held from before the window.
    pub fn is_empty(&self) -> bool {
        self.buckets.is_empty() && self.before.is_none()
    }

    /// Least and greatest value, the held one included.
    pub fn range(&self) -> Option<(f64, f64)> {
        let mut r: Option<(f64, f64)> = self.before.map(|v| (v, v));
        for b in &self.buckets {
            r = Some(match r {
                None => (b.min, b.max),
                Some((lo, hi)) => (lo.min(b.min), hi.max(b.max)),
            });
        }
        r
    }

    /// Buckets so far (for tests of the bound).
    pub fn len(&self) -> usize {
        self.buckets.len()
    }

    /// A value that holds between changes, as a polyline from `from` to `to`: flat, then
    /// straight up or down at each change.
    pub fn step_points(&self, from: f64, to: f64) -> Vec<(f64, f64)> {
        let mut pts = Vec::with_capacity(self.buckets.len() * 4 + 2);
        let mut held = self.before;
        if let Some(v) = held {
            pts.push((from, v));
        }
        for b in &self.buckets {
            if let Some(v) = held {
                pts.push((b.t0, v));
            }
            pts.push((b.t0, b.first));
            if b.min < b.max {
                pts.push((b.t0, b.min));
                pts.push((b.t0, b.max));
            }
            pts.push((b.t1, b.last));
            held = Some(b.last);
        }
        if let Some(v) = held {
            pts.push((to, v));
        }
        pts
    }

    /// A sampled value as a polyline through its samples (each bucket's extremes kept).
    pub fn line_points(&self) -> Vec<(f64, f64)> {
        let mut pts = Vec::with_capacity(self.buckets.len() * 4);
        for b in &self.buckets {
            pts.push((b.t0, b.first));
            if b.min < b.max {
                let mid = 0.5 * (b.t0 + b.t1);
                // Through the extremes in the order a rising or falling stretch meets them.
                if b.last >= b.first {
                    pts.push((mid, b.min));
                    pts.push((mid, b.max));
                } else {
                    pts.push((mid, b.max));
                    pts.push((mid, b.min));
                }
            }
            if b.t1 > b.t0 {
                pts.push((b.t1, b.last));
            }
        }
        pts
    }
}

/// A path in a plane (the tool's X/Y), thinned so consecutive points are at least `step` apart,
/// and capped: past `cap` points the rest of the path is left out and counted.
#[derive(Debug, Clone, Default)]
pub struct Path2 {
    /// The points kept.
    pub points: Vec<(f64, f64)>,
    /// Points left out once the cap was reached.
    pub dropped: u64,
    step: f64,
    cap: usize,
}

impl Path2 {
    /// An empty path.
    pub fn new(step: f64, cap: usize) -> Path2 {
        Path2 {
            points: Vec::new(),
            dropped: 0,
            step,
            cap,
        }
    }

    /// Add a point.
    pub fn push(&mut self, x: f64, y: f64) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        if let Some(&(px, py)) = self.points.last() {
            if (x - px).hypot(y - py) < self.step {
                return;
            }
        }
        if self.points.len() >= self.cap {
            self.dropped += 1;
            return;
        }
        self.points.push((x, y));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_series_stays_bounded_and_keeps_its_extremes() {
        let mut s = Series::new(0.0, 0.001);
        for i in 0..1_000_000u32 {
            let t = f64::from(i) * 0.001;
            // A spike at one sample only: it must survive the merging.
            let v = if i == 777_777 { 50.0 } else { (t * 0.1).sin() };
            s.push(t, v);
        }
        assert!(s.len() <= CAP, "{}", s.len());
        let (lo, hi) = s.range().expect("values");
        assert_eq!(hi, 50.0);
        assert!(lo < -0.99);
        assert!(s.line_points().iter().any(|&(_, v)| v == 50.0));
    }

    #[test]
    fn steps_hold_their_value_between_changes() {
        let mut s = Series::new(0.0, 0.001);
        s.before = Some(0.0);
        s.push(1.0, 1.0);
        s.push(2.0, 0.0);
        assert_eq!(
            s.step_points(0.5, 3.0),
            vec![
                (0.5, 0.0),
                (1.0, 0.0),
                (1.0, 1.0),
                (1.0, 1.0),
                (2.0, 1.0),
                (2.0, 0.0),
                (2.0, 0.0),
                (3.0, 0.0)
            ]
        );
    }

    #[test]
    fn writes_at_one_time_leave_their_last_as_the_level() {
        let mut s = Series::new(0.0, 0.001);
        s.level(1.0, -3600.0);
        s.level(1.0, -300.0);
        s.level(2.0, 5.0);
        s.flush();
        assert_eq!(s.range(), Some((-300.0, 5.0)));
    }

    #[test]
    fn a_path_is_thinned_and_capped() {
        let mut p = Path2::new(1.0, 3);
        for i in 0..10 {
            p.push(f64::from(i) * 0.6, 0.0);
        }
        assert_eq!(p.points, vec![(0.0, 0.0), (1.2, 0.0), (2.4, 0.0)]);
        assert_eq!(p.dropped, 4);
    }
}
