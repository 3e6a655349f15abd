//! Timing statistics of a paced run: how late each update started against its absolute
//! deadline (jitter), how long updates took, and how many overran their period. Lateness goes
//! into a histogram (3 significant figures), so a run of any length keeps constant memory.

use hdrhistogram::Histogram;

/// Collected per-update timings, nanoseconds.
#[derive(Debug, Clone)]
pub struct Timing {
    lateness: Histogram<u64>,
    work: Histogram<u64>,
    worst_update_ns: u64,
    overruns: u64,
    streak: u64,
    longest_streak: u64,
    skipped: u64,
}

impl Default for Timing {
    fn default() -> Self {
        Timing {
            // 1 ns to 1 hour at 3 significant figures; larger values saturate at the top.
            lateness: Histogram::new_with_bounds(1, 3_600_000_000_000, 3)
                .expect("constant histogram bounds are valid"),
            work: Histogram::new_with_bounds(1, 3_600_000_000_000, 3)
                .expect("constant histogram bounds are valid"),
            worst_update_ns: 0,
            overruns: 0,
            streak: 0,
            longest_streak: 0,
            skipped: 0,
        }
    }
}

/// The end-of-run summary of [`Timing`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimingSummary {
    /// Updates measured.
    pub updates: u64,
    /// Median start lateness, ns.
    pub p50_ns: u64,
    /// 99th percentile start lateness, ns.
    pub p99_ns: u64,
    /// Worst start lateness, ns.
    pub max_ns: u64,
    /// Median update time (I/O and computation), ns.
    pub update_p50_ns: u64,
    /// 99th percentile update time, ns.
    pub update_p99_ns: u64,
    /// Worst update time (I/O and computation), ns.
    pub worst_update_ns: u64,
    /// Updates whose work did not finish before the next deadline.
    pub overruns: u64,
    /// The longest run of consecutive overruns.
    pub longest_streak: u64,
    /// Deadlines dropped because the schedule had fallen a whole period or more behind.
    pub skipped: u64,
}

impl Timing {
    /// Record one update: it started `lateness_ns` after its deadline and took `work_ns`;
    /// `period_ns` is the update period (an update that ends after the next deadline is an
    /// overrun). Returns the overruns in a row so far, this one included (0: on time).
    pub fn record(&mut self, lateness_ns: u64, work_ns: u64, period_ns: u64) -> u64 {
        self.lateness.saturating_record(lateness_ns);
        self.work.saturating_record(work_ns);
        self.worst_update_ns = self.worst_update_ns.max(work_ns);
        if lateness_ns.saturating_add(work_ns) > period_ns {
            self.overruns += 1;
            self.streak += 1;
            self.longest_streak = self.longest_streak.max(self.streak);
        } else {
            self.streak = 0;
        }
        self.streak
    }

    /// `n` deadlines were dropped (the schedule fell behind by that many periods).
    pub fn skip(&mut self, n: u64) {
        self.skipped = self.skipped.saturating_add(n);
    }

    /// The summary; None before any update.
    pub fn summary(&self) -> Option<TimingSummary> {
        if self.lateness.is_empty() {
            return None;
        }
        let h = &self.lateness;
        Some(TimingSummary {
            updates: h.len(),
            p50_ns: h.value_at_quantile(0.50),
            p99_ns: h.value_at_quantile(0.99),
            max_ns: h.max(),
            update_p50_ns: self.work.value_at_quantile(0.50),
            update_p99_ns: self.work.value_at_quantile(0.99),
            worst_update_ns: self.worst_update_ns,
            overruns: self.overruns,
            longest_streak: self.longest_streak,
            skipped: self.skipped,
        })
    }
}

impl std::fmt::Display for TimingSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let us = |ns: u64| ns as f64 / 1e3;
        write!(
            f,
            "{} updates; start jitter p50 {:.1} µs, p99 {:.1} µs, max {:.1} µs; update time p50 {:.1} µs, p99 {:.1} µs, worst {:.1} µs; {} overrun(s) (longest run {}), {} deadline(s) dropped",
            self.updates,
            us(self.p50_ns),
            us(self.p99_ns),
            us(self.max_ns),
            us(self.update_p50_ns),
            us(self.update_p99_ns),
            us(self.worst_update_ns),
            self.overruns,
            self.longest_streak,
            self.skipped
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_overruns_and_streaks() {
        let mut t = Timing::default();
        assert_eq!(t.summary(), None);
        // Lateness 1..=200 µs in reverse order; updates 3 and 2 take longer than the 1 ms
        // period (two in a row), update 50 too.
        let mut streaks = Vec::new();
        for i in (1..=200u64).rev() {
            let work = if matches!(i, 2 | 3 | 50) {
                1_000_000
            } else {
                100_000
            };
            streaks.push(t.record(i * 1000, work, 1_000_000));
        }
        let s = t.summary().expect("updates");
        assert_eq!(s.updates, 200);
        // Three significant figures: within 0.1 %.
        assert!((s.p50_ns as f64 - 100_000.0).abs() <= 100.0, "{s:?}");
        assert!((s.p99_ns as f64 - 198_000.0).abs() <= 198.0, "{s:?}");
        assert!((s.max_ns as f64 - 200_000.0).abs() <= 200.0, "{s:?}");
        assert_eq!(s.worst_update_ns, 1_000_000);
        assert_eq!(s.overruns, 3);
        assert_eq!(s.longest_streak, 2);
        assert_eq!(streaks[200 - 50], 1);
        assert_eq!(streaks[200 - 2], 2);
        assert_eq!(streaks[200 - 1], 0);
        assert!(
            s.to_string().contains("3 overrun(s) (longest run 2)"),
            "{s}"
        );
    }

    #[test]
    fn one_update() {
        let mut t = Timing::default();
        t.record(7, 8, 1000);
        let s = t.summary().expect("one");
        assert_eq!((s.p50_ns, s.p99_ns, s.max_ns, s.overruns), (7, 7, 7, 0));
    }

    #[test]
    fn memory_does_not_grow_with_the_run() {
        let mut t = Timing::default();
        for i in 0..1_000_000u64 {
            t.record(i % 5000, 10, 1_000_000);
        }
        assert_eq!(t.summary().map(|s| s.updates), Some(1_000_000));
    }
}
