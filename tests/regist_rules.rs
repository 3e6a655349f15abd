//! REGIST's servo side (`pacer::devices::regist`) against the spec `regist.md`: its worked
//! cases, the three cases the note has but does not print, a reference model under random
//! marks, and the edges of the interface (minimum time, falling edges, release of corrections,
//! filters, switches, refused values).

use pacer::devices::regist::{
    Mark, MarkClass, Regist, RegistParams, BAD_MARK, DIST_TOLR, FAST_INPUT, FAST_IN_OCCURRED,
    FAST_IN_RISING, GOOD_MARK, SWITCH_DEFAULT, SWITCH_DIM, SWITCH_MASTER, SWITCH_SLAVE,
};
use proptest::prelude::*;

/// 1 ms servo update: the default minimum time between marks is 8 ms.
const SERVO: f64 = 0.001;

const GOOD: u32 = FAST_IN_OCCURRED | FAST_INPUT | GOOD_MARK | FAST_IN_RISING;
const BAD: u32 = FAST_IN_OCCURRED | FAST_INPUT | BAD_MARK | FAST_IN_RISING;
const IGNORED: u32 = FAST_IN_OCCURRED | FAST_INPUT | FAST_IN_RISING;

fn params(dist: f64, tolr: f64, ignr: f64, lgth: f64) -> RegistParams {
    RegistParams {
        dist,
        tolr,
        ignr,
        lgth,
        dim: 0.0,
    }
}

fn enabled(p: RegistParams) -> Regist {
    let mut r = Regist::new(SERVO).unwrap();
    r.enable(p).unwrap();
    assert!(r.ok() && r.enabled());
    r
}

/// An axis travelling forward through marks: between marks the position is fed to `passed`
/// in steps of 10 units; time is 1 ms per unit, so no mark falls inside the minimum time.
struct Walk {
    r: Regist,
    at: f64,
    /// (position, STATUSSV) of each DIST+TOLR event.
    passes: Vec<(f64, u32)>,
}

impl Walk {
    fn new(p: RegistParams) -> Walk {
        Walk {
            r: enabled(p),
            at: f64::NEG_INFINITY,
            passes: Vec::new(),
        }
    }

    fn mark(&mut self, position: f64) -> Mark {
        if self.at.is_finite() {
            let mut x = (self.at / 10.0).floor() * 10.0 + 10.0;
            while x < position {
                if self.r.passed(x).unwrap() {
                    self.passes.push((x, self.r.status()));
                }
                x += 10.0;
            }
        }
        let m = self
            .r
            .edge(position * 0.001, position, true)
            .unwrap()
            .expect("the mark is outside the minimum time, so it is seen");
        // The mark restarted or kept the ruler: reaching the mark itself never passes it.
        if m.class != MarkClass::Ignored {
            assert!(!self.r.passed(position).unwrap());
        }
        self.at = position;
        m
    }

    /// A mark expected with `class` and `correction`; checks the status bits per the table and
    /// the servo variables that follow from it.
    fn expect(&mut self, position: f64, class: MarkClass, correction: Option<f64>) {
        let m = self.mark(position);
        assert_eq!(m.class, class, "class of the mark at {position}");
        assert_eq!(
            m.correction, correction,
            "correction of the mark at {position}"
        );
        assert_eq!(m.position, position);
        let status = match class {
            MarkClass::Good => GOOD,
            MarkClass::Bad => BAD,
            MarkClass::Ignored => IGNORED,
        };
        assert_eq!(
            self.r.status(),
            status,
            "STATUSSV after the mark at {position}"
        );
        assert_eq!(self.r.read_sv(9).unwrap(), position);
        assert_eq!(self.r.read_sv(22).unwrap(), position);
        assert_eq!(self.r.read_sv(23).unwrap(), position);
        if let Some(c) = correction {
            assert_eq!(self.r.read_sv(10).unwrap(), c);
            // DIM switch is on by default: a good mark re-references the axis to DIM (0).
            assert_eq!(m.rereference, Some(0.0));
        } else {
            assert_eq!(m.rereference, None);
        }
    }
}

use MarkClass::{Bad as B, Good as G, Ignored as X};

#[test]
fn case_1_dist_0_every_mark_good() {
    let mut w = Walk::new(params(0.0, 100.0, 0.0, 900.0));
    w.expect(0.0, G, Some(0.0));
    assert!(w.r.edge(0.0, 0.0, true).unwrap().is_none()); // same instant: not seen
    w.expect(900.0, G, Some(0.0));
    w.expect(1050.0, G, Some(150.0));
    w.expect(1950.0, G, Some(0.0));
    assert!(w.passes.is_empty(), "DIST 0 has no window to pass");
}

#[test]
fn case_2_mark_in_the_ignore_zone() {
    let mut w = Walk::new(params(1000.0, 100.0, 200.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(1000.0, G, Some(0.0));
    w.expect(1150.0, X, None);
    assert_eq!(w.r.read_sv(20).unwrap(), 150.0);
    w.expect(2090.0, G, Some(90.0));
    assert_eq!(w.r.read_sv(20).unwrap(), 1090.0);
    assert!(w.passes.is_empty());
}

#[test]
fn case_3_window_passes_then_a_bad_mark() {
    let mut w = Walk::new(params(1000.0, 80.0, 200.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(1000.0, G, Some(0.0));
    w.expect(1150.0, X, None);
    assert!(w.passes.is_empty());
    w.expect(2090.0, B, None);
    assert_eq!(w.passes, vec![(2080.0, DIST_TOLR)]);
    assert_eq!(w.r.read_sv(11).unwrap(), 1.0);
    w.expect(3090.0, G, Some(90.0));
    assert_eq!(w.r.read_sv(20).unwrap(), 1000.0);
    assert_eq!(w.r.read_sv(11).unwrap(), 0.0);
    assert_eq!(
        w.passes.len(),
        1,
        "once per ruler, and the new rulers were met"
    );
}

#[test]
fn case_4_bad_mark_resets_the_ruler() {
    let mut w = Walk::new(params(1000.0, 50.0, 50.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(1000.0, G, Some(0.0));
    w.expect(1090.0, B, None);
    w.expect(2090.0, G, Some(90.0));
    assert!(w.passes.is_empty());
}

#[test]
fn case_6_ignore_zone_hides_a_splice() {
    let mut w = Walk::new(params(1000.0, 100.0, 900.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(1000.0, G, Some(0.0));
    w.expect(1500.0, X, None);
    w.expect(2050.0, G, Some(50.0));
    assert!(w.passes.is_empty());
}

#[test]
fn unprinted_two_consecutive_bad_marks() {
    let mut w = Walk::new(params(1000.0, 50.0, 50.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(1000.0, G, Some(0.0));
    w.expect(1090.0, B, None); // 90 from G2
    assert_eq!(w.r.read_sv(11).unwrap(), 1.0);
    w.expect(1200.0, B, None); // 110 from B1
    assert_eq!(w.r.read_sv(11).unwrap(), 2.0);
    w.expect(1230.0, X, None); // 30 from B2: ignored, count stays
    assert_eq!(w.r.read_sv(11).unwrap(), 2.0);
    w.expect(2200.0, G, Some(200.0)); // 1000 from B2; 1200 since G2
    assert_eq!(w.r.read_sv(11).unwrap(), 0.0);
    // The ruler after B1 (1090) would be passed at 2140, after B2 (1200) at 2250.
    assert!(w.passes.is_empty());
}

#[test]
fn unprinted_several_marks_per_cycle_register_point_shifts() {
    // Three print marks per 1000-unit cycle at +0, +300, +600; IGNR 900 hides the other two.
    let mut w = Walk::new(params(1000.0, 100.0, 900.0, 1000.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(300.0, X, None);
    w.expect(600.0, X, None);
    w.expect(1000.0, G, Some(0.0));
    w.expect(1300.0, X, None);
    w.expect(1600.0, X, None);
    // The mark at 2000 is missed: 2300 is 1300 from the ruler, bad; the ruler moves to it.
    w.expect(2300.0, B, None);
    assert_eq!(w.passes, vec![(2100.0, DIST_TOLR)]);
    w.expect(2600.0, X, None);
    w.expect(3000.0, X, None);
    // Registration now locks on the +300 marks: a correction of 300 shifts the register.
    w.expect(3300.0, G, Some(300.0));
    w.expect(3600.0, X, None);
    w.expect(4000.0, X, None);
    w.expect(4300.0, G, Some(0.0));
    assert_eq!(w.passes.len(), 1);
}

#[test]
fn unprinted_print_registration_dist_100_tolr_10() {
    let mut w = Walk::new(params(100.0, 10.0, 0.0, 100.0));
    w.expect(0.0, G, Some(0.0));
    w.expect(100.0, G, Some(0.0));
    w.expect(205.0, G, Some(5.0));
    w.expect(300.0, G, Some(-5.0)); // 95 folds to -5
    w.expect(450.0, B, None); // 150 from 300
    assert_eq!(w.passes, vec![(410.0, DIST_TOLR)]);
    w.expect(550.0, G, Some(50.0)); // 250 since 300: mod 100 = 50, LGTH/2 stays
    w.expect(652.0, G, Some(2.0));
    w.expect(700.0, B, None); // 48 from 652, IGNR 0 ignores nothing
    w.expect(800.0, G, Some(48.0)); // 148 since 652
    assert_eq!(w.passes.len(), 1);
}

// ---- a reference model under random marks ----

#[derive(Debug, Clone, Copy, PartialEq)]
enum RefClass {
    Good(i64),
    Bad,
    Ignored,
}

/// What the spec says, mark by mark, in integers: (class, distance, consecutive bad marks).
fn reference(
    dist: i64,
    tolr: i64,
    ignr: i64,
    lgth: i64,
    marks: &[i64],
) -> Vec<(RefClass, i64, i64)> {
    let mut out = Vec::new();
    let mut state: Option<(i64, i64)> = None; // (ruler, last good)
    let mut bad = 0;
    for &p in marks {
        let Some((ruler, good)) = state else {
            state = Some((p, p));
            out.push((RefClass::Good(0), 0, 0));
            continue;
        };
        let d = p - ruler;
        let class = if ignr > 0 && d < ignr {
            RefClass::Ignored
        } else if dist == 0 || (d >= dist - tolr && d <= dist + tolr) {
            let mut c = (p - good) % lgth;
            if c < 0 {
                c += lgth;
            }
            if 2 * c > lgth {
                c -= lgth;
            }
            state = Some((p, p));
            bad = 0;
            RefClass::Good(c)
        } else {
            state = Some((p, good));
            bad += 1;
            RefClass::Bad
        };
        out.push((class, d, bad));
    }
    out
}

fn marks_strategy() -> impl Strategy<Value = (i64, i64, i64, i64, i64, Vec<i64>)> {
    (
        prop_oneof![1 => Just(0i64), 3 => 1..2000i64],
        0..300i64,
        prop_oneof![1 => Just(0i64), 3 => 1..1500i64],
        1..3000i64,
        -5000..5000i64,
        prop::collection::vec((0..3u8, 0..1000i64), 1..40),
    )
        .prop_map(|(dist, tolr, ignr, lgth, start, gaps)| {
            let mut p = start;
            let mut marks = Vec::new();
            for (kind, f) in gaps {
                let gap = match kind {
                    0 if ignr > 0 => f % ignr,
                    1 => (dist - tolr + f % (2 * tolr + 1)).max(0),
                    _ => f * 5,
                };
                marks.push(p);
                p += gap;
            }
            (dist, tolr, ignr, lgth, start, marks)
        })
}

proptest! {
    #[test]
    fn classification_matches_the_reference_model(
        (dist, tolr, ignr, lgth, dim, marks) in marks_strategy()
    ) {
        let p = RegistParams {
            dist: dist as f64,
            tolr: tolr as f64,
            ignr: ignr as f64,
            lgth: lgth as f64,
            dim: dim as f64,
        };
        let mut r = Regist::new(SERVO).unwrap();
        r.enable(p).unwrap();
        r.write_sv(24, f64::from(SWITCH_MASTER | SWITCH_SLAVE | SWITCH_DIM)).unwrap();
        let expected = reference(dist, tolr, ignr, lgth, &marks);
        let mut ruler: Option<i64> = None;
        let mut window_passed = false;
        for (i, (&pos, &(class, d, bad))) in marks.iter().zip(&expected).enumerate() {
            // Just before the mark: the DIST+TOLR event, once per ruler.
            let before = pos as f64 - 0.5;
            let fires = match ruler {
                Some(s) if dist > 0 && !window_passed => before >= (s + dist + tolr) as f64,
                _ => false,
            };
            prop_assert_eq!(r.passed(before).unwrap(), fires);
            window_passed |= fires;
            let m = r.edge(i as f64 * 0.01, pos as f64, true).unwrap();
            let m = m.expect("10 ms apart: every mark is seen");
            prop_assert_eq!(m.entrant, i == 0);
            prop_assert_eq!(m.distance, if i == 0 { None } else { Some(d as f64) });
            prop_assert_eq!(r.read_sv(20).unwrap(), d as f64);
            prop_assert_eq!(r.read_sv(11).unwrap(), bad as f64);
            let (slave, master) = r.take_correction(true, true);
            match class {
                RefClass::Good(c) => {
                    prop_assert_eq!(m.class, MarkClass::Good);
                    prop_assert_eq!(m.correction, Some(c as f64));
                    prop_assert_eq!(m.rereference, Some(dim as f64));
                    prop_assert_eq!(r.status(), GOOD);
                    prop_assert_eq!((slave, master), (c as f64, -(c as f64)));
                    ruler = Some(pos);
                    window_passed = false;
                }
                RefClass::Bad => {
                    prop_assert_eq!(m.class, MarkClass::Bad);
                    prop_assert_eq!(m.correction, None);
                    prop_assert_eq!(r.status(), BAD);
                    prop_assert_eq!((slave, master), (0.0, 0.0));
                    ruler = Some(pos);
                    window_passed = false;
                }
                RefClass::Ignored => {
                    prop_assert_eq!(m.class, MarkClass::Ignored);
                    prop_assert_eq!(m.correction, None);
                    prop_assert_eq!(r.status(), IGNORED);
                    prop_assert_eq!((slave, master), (0.0, 0.0));
                }
            }
        }
    }
}

// ---- the interface's edges ----

#[test]
fn minimum_time_between_marks() {
    let mut r = enabled(params(0.0, 0.0, 0.0, 1000.0));
    assert_eq!(r.read_sv(25).unwrap(), 0.008); // 8 interrupts of 1 ms
    assert!(r.edge(0.0, 0.0, true).unwrap().is_some());
    // A falling edge 0.1 ms later is never latched, so it hides nothing.
    assert!(r.edge(0.0001, 0.1, false).unwrap().is_none());
    assert_eq!(r.status() & FAST_IN_RISING, 0);
    // 5 ms after the last mark: not seen at all.
    let before = (r.status(), r.read_sv(9).unwrap(), r.read_sv(20).unwrap());
    assert!(r.edge(0.005, 50.0, true).unwrap().is_none());
    assert_eq!(
        before,
        (r.status(), r.read_sv(9).unwrap(), r.read_sv(20).unwrap())
    );
    // 9 ms after the last latched mark (4 ms after the unseen one): seen.
    let m = r.edge(0.009, 90.0, true).unwrap().unwrap();
    assert_eq!(
        (m.class, m.distance, m.correction),
        (G, Some(90.0), Some(90.0))
    );
    // Exactly the minimum time later is seen.
    assert!(r.edge(0.017, 100.0, true).unwrap().is_some());
    // Reduced to 2 ms.
    r.write_sv(25, 0.002).unwrap();
    assert!(r.edge(0.0185, 110.0, true).unwrap().is_none());
    assert!(r.edge(0.019, 120.0, true).unwrap().is_some());
}

#[test]
fn falling_edges_only_set_the_input_state_and_direction_follows_travel() {
    let mut r = enabled(params(1000.0, 100.0, 0.0, 1000.0));
    let m = r.edge(0.0, 0.0, true).unwrap().unwrap();
    assert!(m.entrant);
    assert_eq!(r.read_sv(19).unwrap(), 0.0); // no earlier edge: direction unknown
    assert_eq!(r.status(), GOOD);
    assert!(r.edge(0.001, 5.0, false).unwrap().is_none());
    assert_eq!(r.status(), GOOD & !FAST_IN_RISING);
    assert_eq!(r.read_sv(9).unwrap(), 0.0, "a falling edge latches nothing");
    // The ruler still starts at 0: 1000 is good.
    let m = r.edge(1.0, 1000.0, true).unwrap().unwrap();
    assert_eq!((m.class, m.distance), (G, Some(1000.0)));
    assert_eq!(r.read_sv(19).unwrap(), 1.0);
    assert!(r.edge(1.1, 1005.0, false).unwrap().is_none());
    // Travelling back: a mark behind the last edge.
    let m = r.edge(2.0, 990.0, true).unwrap().unwrap();
    assert_eq!(m.class, B);
    assert_eq!(r.read_sv(19).unwrap(), -1.0);
    assert_eq!(r.read_sv(20).unwrap(), -10.0);
}

#[test]
fn correction_released_only_while_master_moves_and_slave_ratio_moves() {
    let mut r = enabled(params(1000.0, 100.0, 0.0, 1000.0));
    r.edge(0.0, 0.0, true).unwrap();
    r.edge(1.0, 1060.0, true).unwrap();
    assert_eq!(r.read_sv(10).unwrap(), 60.0);
    for (master, ratio) in [(false, false), (false, true), (true, false)] {
        assert_eq!(r.take_correction(master, ratio), (0.0, 0.0));
        assert_eq!(r.read_sv(13).unwrap(), 0.0);
        assert_eq!(r.read_sv(15).unwrap(), 0.0);
    }
    // Default switches: slave only, at once (filter 0).
    assert_eq!(r.take_correction(true, true), (60.0, 0.0));
    assert_eq!(r.read_sv(13).unwrap(), 60.0);
    assert_eq!(r.read_sv(15).unwrap(), 60.0);
    assert_eq!(r.take_correction(true, true), (0.0, 0.0));
    assert_eq!(r.read_sv(13).unwrap(), 0.0);
    assert_eq!(r.read_sv(15).unwrap(), 60.0);
    // A negative correction: the absolute offset runs down again.
    r.edge(2.0, 2030.0, true).unwrap(); // 970 since 1060: -30
    assert_eq!(r.take_correction(true, true), (-30.0, 0.0));
    assert_eq!(r.read_sv(15).unwrap(), 30.0);
}

#[test]
fn filters_spread_a_correction_evenly_and_sum_to_it() {
    let mut r = enabled(params(0.0, 0.0, 0.0, 1000.0));
    r.write_sv(24, f64::from(SWITCH_MASTER | SWITCH_SLAVE))
        .unwrap();
    r.write_sv(17, 7.0).unwrap();
    r.write_sv(18, 3.0).unwrap();
    assert_eq!((r.read_sv(17).unwrap(), r.read_sv(18).unwrap()), (7.0, 3.0));
    r.edge(0.0, 0.0, true).unwrap();
    r.edge(1.0, 1090.0, true).unwrap();
    let (mut slave, mut master) = (Vec::new(), Vec::new());
    for k in 0..12 {
        // Pauses (the master standing) do not use up the filter's updates.
        let (s, m) = r.take_correction(k % 3 != 2, true);
        if k % 3 != 2 {
            slave.push(s);
            master.push(m);
            assert_eq!(r.read_sv(13).unwrap(), s);
            assert_eq!(r.read_sv(14).unwrap(), m);
        } else {
            assert_eq!((s, m), (0.0, 0.0));
        }
    }
    assert_eq!(slave.len(), 8);
    for s in &slave[..7] {
        assert!((s - 90.0 / 7.0).abs() < 1e-9, "slave share {s}");
    }
    assert_eq!(slave[7], 0.0);
    assert!((slave.iter().sum::<f64>() - 90.0).abs() < 1e-9);
    assert!((r.read_sv(15).unwrap() - 90.0).abs() < 1e-9);
    for m in &master[..3] {
        assert!((m + 30.0).abs() < 1e-9, "master share {m}");
    }
    assert!(master[3..].iter().all(|&m| m == 0.0));
    assert!((r.read_sv(16).unwrap() + 90.0).abs() < 1e-9);

    // A correction arriving mid-spread joins the remainder, spread over a fresh 4 updates.
    let mut r = enabled(params(0.0, 0.0, 0.0, 1000.0));
    r.write_sv(17, 4.0).unwrap();
    r.edge(0.0, 0.0, true).unwrap();
    r.edge(1.0, 1100.0, true).unwrap(); // +100
    let first = r.take_correction(true, true).0 + r.take_correction(true, true).0;
    assert!((first - 50.0).abs() < 1e-9);
    r.edge(2.0, 2070.0, true).unwrap(); // 970 since 1100: -30
    let rest: Vec<f64> = (0..5).map(|_| r.take_correction(true, true).0).collect();
    for s in &rest[..4] {
        assert!((s - 5.0).abs() < 1e-9, "share {s} of the 20 left"); // (50 - 30) / 4
    }
    assert_eq!(rest[4], 0.0);
    assert!((r.read_sv(15).unwrap() - 70.0).abs() < 1e-9);

    // Filter 1 is at once, like 0.
    let mut r = enabled(params(0.0, 0.0, 0.0, 1000.0));
    r.write_sv(17, 1.0).unwrap();
    r.edge(0.0, 0.0, true).unwrap();
    r.edge(1.0, 1010.0, true).unwrap();
    assert_eq!(r.take_correction(true, true), (10.0, 0.0));
}

#[test]
fn switches_route_the_correction_and_the_dim() {
    assert_eq!(SWITCH_DEFAULT, SWITCH_SLAVE | SWITCH_DIM);
    for sw in 0..8u32 {
        let mut r = Regist::new(SERVO).unwrap();
        assert_eq!(r.read_sv(24).unwrap(), f64::from(SWITCH_DEFAULT));
        r.enable(RegistParams {
            dist: 0.0,
            tolr: 0.0,
            ignr: 0.0,
            lgth: 1000.0,
            dim: 25.0,
        })
        .unwrap();
        r.write_sv(24, f64::from(sw)).unwrap();
        let dim = if sw & SWITCH_DIM != 0 {
            Some(25.0)
        } else {
            None
        };
        assert_eq!(r.edge(0.0, 0.0, true).unwrap().unwrap().rereference, dim);
        let m = r.edge(1.0, 1040.0, true).unwrap().unwrap();
        assert_eq!((m.correction, m.rereference), (Some(40.0), dim));
        let slave = if sw & SWITCH_SLAVE != 0 { 40.0 } else { 0.0 };
        let master = if sw & SWITCH_MASTER != 0 { -40.0 } else { 0.0 };
        assert_eq!(
            r.take_correction(true, true),
            (slave, master),
            "switches {sw}"
        );
        assert_eq!(r.read_sv(24).unwrap(), f64::from(sw));
    }
}

#[test]
fn writing_var_10_queues_an_alignment_correction() {
    let mut r = enabled(params(1000.0, 100.0, 0.0, 1000.0));
    r.edge(0.0, 0.0, true).unwrap();
    r.edge(1.0, 1040.0, true).unwrap();
    assert_eq!(r.take_correction(true, true), (40.0, 0.0));
    // The start-up idiom: negate the correction and write it back.
    r.write_sv(10, -40.0).unwrap();
    assert_eq!(r.read_sv(10).unwrap(), -40.0);
    assert_eq!(r.take_correction(false, true), (0.0, 0.0));
    assert_eq!(r.take_correction(true, true), (-40.0, 0.0));
    assert_eq!(r.read_sv(15).unwrap(), 0.0);
    // Var 11 resets the bad count.
    r.edge(2.0, 1500.0, true).unwrap();
    assert_eq!(r.read_sv(11).unwrap(), 1.0);
    r.write_sv(11, 0.0).unwrap();
    assert_eq!(r.read_sv(11).unwrap(), 0.0);
}

#[test]
fn enable_same_values_keeps_the_ruler_new_values_rearm() {
    let p = params(1000.0, 100.0, 0.0, 1000.0);
    let mut r = enabled(p);
    r.edge(0.0, 0.0, true).unwrap();
    r.enable(p).unwrap();
    let m = r.edge(1.0, 1050.0, true).unwrap().unwrap();
    assert!(!m.entrant);
    assert_eq!(m.correction, Some(50.0));
    // New values: the next mark is the entrant again.
    r.enable(params(500.0, 10.0, 0.0, 500.0)).unwrap();
    let m = r.edge(2.0, 1700.0, true).unwrap().unwrap();
    assert!(m.entrant);
    assert_eq!((m.class, m.correction, m.distance), (G, Some(0.0), None));
    // Off: marks are not latched, only the input state follows.
    r.disable();
    assert!(!r.enabled() && !r.ok());
    assert!(r.edge(3.0, 2200.0, true).unwrap().is_none());
    assert_eq!(r.read_sv(9).unwrap(), 1700.0);
    assert_ne!(r.status() & FAST_IN_RISING, 0);
    assert!(!r.passed(1e6).unwrap());
    // On again with the same values: re-armed, since registration was off.
    r.enable(params(500.0, 10.0, 0.0, 500.0)).unwrap();
    assert!(r.edge(4.0, 2300.0, true).unwrap().unwrap().entrant);
}

#[test]
fn refused_params_name_the_value_and_leave_registration_running() {
    let p = params(1000.0, 100.0, 0.0, 1000.0);
    let mut r = enabled(p);
    r.edge(0.0, 0.0, true).unwrap();
    for (bad, what) in [
        (
            params(f64::NAN, 0.0, 0.0, 1.0),
            "DIST must be a finite number, not NaN",
        ),
        (
            params(-1.0, 0.0, 0.0, 1.0),
            "DIST must be 0 or more, not -1",
        ),
        (
            params(0.0, -2.0, 0.0, 1.0),
            "TOLR must be 0 or more, not -2",
        ),
        (
            params(0.0, 0.0, -3.0, 1.0),
            "IGNR must be 0 or more, not -3",
        ),
        (params(0.0, 0.0, 0.0, 0.0), "LGTH must be above 0"),
        (params(0.0, 0.0, 0.0, -5.0), "not -5"),
        (
            params(0.0, 0.0, f64::INFINITY, 1.0),
            "IGNR must be a finite number, not inf",
        ),
        (
            RegistParams { dim: f64::NAN, ..p },
            "DIM must be a finite number",
        ),
    ] {
        let e = r.enable(bad).unwrap_err();
        assert!(e.0.contains(what), "{e} should say {what}");
        assert!(!r.ok());
        assert!(r.enabled());
    }
    // The old registration still runs with its ruler.
    let m = r.edge(1.0, 1000.0, true).unwrap().unwrap();
    assert!(!m.entrant);
    r.enable(p).unwrap();
    assert!(r.ok());
    assert!(Regist::new(0.0).unwrap_err().0.contains("not 0"));
    assert!(Regist::new(f64::NAN).is_err());
}

#[test]
fn refused_edges_and_positions() {
    let mut r = enabled(params(1000.0, 100.0, 0.0, 1000.0));
    assert!(r.edge(f64::NAN, 0.0, true).unwrap_err().0.contains("NaN"));
    assert!(r
        .edge(0.0, f64::INFINITY, true)
        .unwrap_err()
        .0
        .contains("inf"));
    r.edge(1.0, -1e308, true).unwrap();
    let e = r.edge(0.5, 10.0, false).unwrap_err();
    assert!(e.0.contains("0.5") && e.0.contains("earlier"), "{e}");
    assert!(r.passed(f64::NAN).unwrap_err().0.contains("NaN"));
    // 2e308 from the ruler: the distance overflows.
    let e = r.edge(2.0, 1e308, true).unwrap_err();
    assert!(e.0.contains("too far"), "{e}");
    // Nothing changed: the ruler is still at -1e308 and the lockout did not restart.
    let m = r.edge(2.0, -9e307, true).unwrap().unwrap();
    assert_eq!((m.class, m.distance), (B, Some(-9e307 - -1e308)));
}

#[test]
fn servo_variable_numbers_and_values() {
    let mut r = enabled(params(1000.0, 100.0, 0.0, 1000.0));
    for var in [9, 10, 11, 13, 14, 15, 16, 17, 18, 19, 20, 22, 23, 24, 25] {
        assert!(r.read_sv(var).is_ok(), "var {var}");
    }
    for var in [0, 8, 12, 21, 26, 1000] {
        let e = r.read_sv(var).unwrap_err();
        assert!(
            e.0.contains(&format!("servo variable {var} ")) && e.0.contains("13 to 20"),
            "{e}"
        );
        assert!(r.write_sv(var, 0.0).is_err());
    }
    for var in [9, 13, 14, 15, 16, 19, 20, 22, 23] {
        let e = r.write_sv(var, 0.0).unwrap_err();
        assert!(
            e.0.contains("read-only") && e.0.contains(&var.to_string()),
            "{e}"
        );
    }
    for (var, value) in [
        (17, 1.5),
        (17, -1.0),
        (18, f64::NAN),
        (11, -1.0),
        (24, 8.0),
        (24, 2.5),
        (25, 0.001),
        (25, 1.5),
        (25, f64::INFINITY),
        (10, f64::NAN),
    ] {
        let e = r.write_sv(var, value).unwrap_err();
        assert!(
            e.0.contains(&format!("servo variable {var}")) && e.0.contains(&format!("{value}")),
            "{e}"
        );
    }
    r.write_sv(25, 1.0).unwrap();
    assert_eq!(r.read_sv(25).unwrap(), 1.0);
    r.write_sv(24, 0.0).unwrap();
    assert_eq!(r.read_sv(24).unwrap(), 0.0);
}
