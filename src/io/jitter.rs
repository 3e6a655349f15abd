//! Timing statistics of a paced run: how late each update started against its absolute
//! deadline (jitter), how long updates took, and how many overran their period.

/// Collected per-update timings, nanoseconds.
#[derive(Debug, Clone, Default)]
pub struct Timing {
    lateness: Vec<u64>,
    work: Vec<u64>,
    overruns: u64,
}

/// The end-of-run summary of [`Timing`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimingSummary {
    /// Updates measured.
    pub updates: usize,
    /// Median start lateness, ns.
    pub p50_ns: u64,
    /// 99th percentile start lateness, ns.
    pub p99_ns: u64,
    /// Worst start lateness, ns.
    pub max_ns: u64,
    /// Worst update time (I/O and computation), ns.
    pub worst_update_ns: u64,
    /// Updates whose work did not finish before the next deadline.
    pub overruns: u64,
}

impl Timing {
    /// Record one update: it started `lateness_ns` after its deadline and took `work_ns`;
    /// `period_ns` is the update period (an update longer than that is an overrun).
    pub fn record(&mut self, lateness_ns: u64, work_ns: u64, period_ns: u64) {
        self.lateness.push(lateness_ns);
        self.work.push(work_ns);
        if lateness_ns.saturating_add(work_ns) > period_ns {
            self.overruns += 1;
        }
    }

    /// The summary; None before any update.
    pub fn summary(&self) -> Option<TimingSummary> {
        if self.lateness.is_empty() {
            return None;
        }
        let mut sorted = self.lateness.clone();
        sorted.sort_unstable();
        Some(TimingSummary {
            updates: sorted.len(),
            p50_ns: percentile(&sorted, 50),
            p99_ns: percentile(&sorted, 99),
            max_ns: sorted[sorted.len() - 1],
            worst_update_ns: self.work.iter().copied().max().unwrap_or(0),
            overruns: self.overruns,
        })
    }
}

/// The nearest-rank percentile `p` (1–100) of sorted, non-empty data.
fn percentile(sorted: &[u64], p: usize) -> u64 {
    let rank = (p * sorted.len()).div_ceil(100).max(1);
    sorted[rank.min(sorted.len()) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank_and_overruns() {
        let mut t = Timing::default();
        assert_eq!(t.summary(), None);
        // Lateness 1..=200 µs in reverse order; update 3 takes longer than the 1 ms period.
        for i in (1..=200u64).rev() {
            let work = if i == 3 { 1_000_000 } else { 100_000 };
            t.record(i * 1000, work, 1_000_000);
        }
        let s = t.summary().expect("updates");
        assert_eq!(s.updates, 200);
        assert_eq!(s.p50_ns, 100_000);
        assert_eq!(s.p99_ns, 198_000);
        assert_eq!(s.max_ns, 200_000);
        assert_eq!(s.worst_update_ns, 1_000_000);
        assert_eq!(s.overruns, 1);
    }

    #[test]
    fn one_update() {
        let mut t = Timing::default();
        t.record(7, 8, 1000);
        let s = t.summary().expect("one");
        assert_eq!((s.p50_ns, s.p99_ns, s.max_ns, s.overruns), (7, 7, 7, 0));
    }
}
