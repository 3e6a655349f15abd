//! The limits of what `machine.toml` and `scenario.toml` may ask for, and why: nothing a file
//! says may make pacer allocate without bound or spin without bound. Each limit is documented in
//! docs/machine-toml.md or docs/scenario-toml.md, and the rule in docs/decisions.md.
//!
//! Per-value limits are checked where each value is (a located problem on it); the one limit
//! over a whole scenario, the number of things the world lays out before the run starts, is
//! [`world_size`] here.

use super::scenario::ScenarioFile;
use super::span_of;
use crate::diag::Problem;
use crate::span::Span;

/// The longest time either file may give (an `at`, a `duration`, a `period`), in nanoseconds:
/// 1,000,000 s, about 11.6 days. Longer runs are not simulated in one go, and every sum of
/// times (a pulse train's end) stays far inside 64 bits.
pub const MAX_TIME_NS: u64 = 1_000_000 * 1_000_000_000;

/// The most updates one run may take (its duration over the update period): 100,000,000, about
/// 28 hours at 1 ms. Each update costs time whatever the programs do, so this bounds a run's
/// time.
pub const MAX_UPDATES: u64 = 100_000_000;

/// The most instructions a task may run in one update (`[machine] budget`): 1,000,000, some
/// 10 ms of work, so a loop that never waits cannot stretch one update without bound.
pub const MAX_BUDGET: u64 = 1_000_000;

/// The most bounces after one edge (`bounce = { count = … }`): contact bounce is a handful of
/// excursions; each is two input edges held in memory for the run.
pub const MAX_BOUNCES: u32 = 1_000;

/// The most pulses in one train and products in one stream.
pub const MAX_STREAM: u32 = 10_000_000;

/// The most things a scenario may lay out before the run starts, all entries together: input
/// edges (presses, levels, pulses, products and their bounces), products, printed marks and
/// workpieces. Each is held in memory for the whole run (some 16 to 48 bytes), so 5,000,000 keep
/// a scenario within a few hundred megabytes.
pub const MAX_WORLD_ITEMS: u64 = 5_000_000;

/// `n` with a comma every three digits: `5,000,000`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// What one scenario entry lays out, and where it is written.
struct Entry {
    items: u64,
    span: Span,
    what: &'static str,
}

/// The entries of `sc` that lay things out, with an upper bound of what each makes.
fn entries(sc: &ScenarioFile) -> Vec<Entry> {
    let mut out = Vec::new();
    for c in &sc.inputs {
        out.push(Entry {
            items: 1,
            span: span_of(&c.name),
            what: "level change",
        });
    }
    for p in &sc.presses {
        out.push(Entry {
            items: 2,
            span: span_of(&p.name),
            what: "press",
        });
    }
    for p in &sc.pulses {
        out.push(Entry {
            items: 2 * u64::from((*p.count.get_ref()).min(MAX_STREAM)),
            span: span_of(&p.count),
            what: "pulse train",
        });
    }
    for p in &sc.products {
        // Each count at most its own limit here, so a count past it is reported at the count.
        let bounces = p
            .bounce
            .as_ref()
            .map_or(0, |b| u64::from((*b.count.get_ref()).min(MAX_BOUNCES)));
        // The product, its two edges, and two edges for each bounce of each of them.
        out.push(Entry {
            items: u64::from(p.count.min(MAX_STREAM)).saturating_mul(3 + 4 * bounces),
            span: span_of(&p.sensor),
            what: "product stream",
        });
    }
    for m in &sc.marks {
        let count = m.count.as_ref().map_or(0, |c| {
            u64::from((*c.get_ref()).min(super::marks::MAX_MARKS))
        });
        let listed = m.at.as_ref().map_or(0, |a| a.get_ref().len() as u64);
        let spurious = m
            .spurious
            .as_ref()
            .map_or(0, |s| count / u64::from((*s.every.get_ref()).max(1)));
        out.push(Entry {
            items: count + listed + spurious,
            span: span_of(&m.axis),
            what: "mark track",
        });
    }
    for w in &sc.workpieces {
        let count = w.count.as_ref().map_or(0, |c| {
            u64::from((*c.get_ref()).min(super::belts::MAX_WORKPIECES))
        });
        let listed = w.at.as_ref().map_or(0, |a| a.get_ref().len() as u64);
        out.push(Entry {
            items: count + listed,
            span: span_of(&w.belt),
            what: "workpiece stream",
        });
    }
    out
}

/// Check that the scenario lays out at most [`MAX_WORLD_ITEMS`] things, before any is made:
/// false (with a problem on the entry that passes the limit) when it would lay out more.
pub fn world_size(sc: &ScenarioFile, problems: &mut Vec<Problem>) -> bool {
    let mut total: u64 = 0;
    for e in entries(sc) {
        total = total.saturating_add(e.items);
        if total > MAX_WORLD_ITEMS {
            problems.push(
                Problem::error(
                    "pacer::scenario::size",
                    e.span,
                    format!(
                        "this {} takes the scenario past {} things laid out before the run (input edges, products, marks, workpieces)",
                        e.what,
                        thousands(MAX_WORLD_ITEMS)
                    ),
                    "too many",
                )
                .with_help("each is held in memory for the whole run: make the counts smaller, or split the run in two"),
            );
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_groups_digits() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(5_000_000), "5,000,000");
        assert_eq!(thousands(u64::MAX), "18,446,744,073,709,551,615");
    }
}
