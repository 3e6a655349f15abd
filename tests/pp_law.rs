//! The jerk-limited path motion law of the pick & place planner: hand-computed profiles, the
//! limits and exactness on random profiles, time scaling, servo-rate sampling and stops.

use pacer::devices::pickplace::law::*;
use proptest::prelude::*;

fn lim(vel: f64, acc: f64, dec: f64, jerk: f64) -> Limits {
    Limits {
        vel,
        acc,
        dec,
        jerk,
    }
}

fn plan(length: f64, l: Limits) -> DoubleS {
    match DoubleS::plan(length, l) {
        Ok(p) => p,
        Err(e) => panic!("plan({length}, {l:?}) failed: {e}"),
    }
}

fn stop(v0: f64, a0: f64, dec: f64, jerk: f64) -> Stop {
    match Stop::plan(v0, a0, dec, jerk) {
        Ok(s) => s,
        Err(e) => panic!("Stop::plan({v0}, {a0}, {dec}, {jerk}) failed: {e}"),
    }
}

fn assert_close(what: &str, got: f64, want: f64, rel: f64) {
    let tol = rel * want.abs().max(1e-300);
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (diff {})",
        got - want
    );
}

const EPS: f64 = f64::EPSILON;
const SERVO: f64 = 1e-3;

/// Sample instants: a uniform grid plus every phase switch and points just either side of it.
fn grid(duration: f64, switches: &[f64]) -> Vec<f64> {
    let n = 2000;
    let mut ts: Vec<f64> = (0..=n).map(|i| duration * i as f64 / n as f64).collect();
    for &b in switches {
        for t in [
            b,
            b * (1.0 - 1e-12),
            b * (1.0 + 1e-12),
            b - 1e-9 * duration,
            b + 1e-9 * duration,
        ] {
            if (0.0..=duration).contains(&t) {
                ts.push(t);
            }
        }
    }
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    ts
}

/// Checks a profile over a fine grid: the bounds `[-dec_max, acc_max]` on a, `|j| ≤ jerk_max`,
/// `0 ≤ v ≤ v_max`, monotone s, and that s, v, a are consistent derivatives of each other.
/// `err_s` is the rounding a position sample may carry, which swamps finite differences over
/// the tiny intervals around phase switches.
struct Bounds {
    v_max: f64,
    acc_max: f64,
    dec_max: f64,
    jerk_max: f64,
}

fn check_samples(sample: &dyn Fn(f64) -> State, duration: f64, switches: &[f64], b: &Bounds) {
    let ts = grid(duration, switches);
    let states: Vec<State> = ts.iter().map(|&t| sample(t)).collect();
    let s_max = states.iter().fold(0.0f64, |m, st| m.max(st.s.abs()));
    let err_s = 8.0 * EPS * (s_max + b.v_max * duration) + 1e-300;
    let err_v = 8.0 * EPS * (b.v_max + b.acc_max.max(b.dec_max) * duration) + 1e-300;
    // The instants themselves carry rounding of order EPS·duration, which shifts a sample's
    // v and a by up to acc·δt and jerk·δt.
    let a_bound = b.acc_max.max(b.dec_max);
    let err_vt = 4.0 * EPS * duration * a_bound;
    let err_at = 4.0 * EPS * duration * b.jerk_max;
    let rel = 1.0 + 1e-9;
    for (t, st) in ts.iter().zip(&states) {
        assert!(
            st.s.is_finite() && st.v.is_finite() && st.a.is_finite() && st.j.is_finite(),
            "non-finite state {st:?} at t = {t}"
        );
        assert!(st.v >= 0.0, "v < 0 at t = {t}: {st:?}");
        assert!(
            st.v <= b.v_max * rel,
            "v above the limit at t = {t}: {st:?}"
        );
        assert!(st.a <= b.acc_max * rel, "a above acc at t = {t}: {st:?}");
        assert!(st.a >= -b.dec_max * rel, "a below -dec at t = {t}: {st:?}");
        assert!(
            st.j.abs() <= b.jerk_max * rel,
            "jerk beyond limit at t = {t}: {st:?}"
        );
    }
    for i in 1..ts.len() {
        let (t0, t1) = (ts[i - 1], ts[i]);
        let (x0, x1) = (states[i - 1], states[i]);
        assert!(
            x1.s >= x0.s,
            "s decreases between t = {t0} and {t1}: {x0:?} {x1:?}"
        );
        let h = t1 - t0;
        if h <= 0.0 {
            continue;
        }
        // Within one phase s is a cubic, so Simpson's rule on v is exact and the trapezoid rule
        // on a is exact for v; the grid holds every switch, so each interval is inside a phase.
        let mid = sample(t0 + h / 2.0);
        let simpson = (x0.v + 4.0 * mid.v + x1.v) / 6.0;
        let ds = (x1.s - x0.s) / h;
        assert!(
            (ds - simpson).abs() <= 1e-9 * b.v_max + 4.0 * err_s / h + err_vt,
            "ds/dt {ds} vs v {simpson} on [{t0}, {t1}]"
        );
        let dv = (x1.v - x0.v) / h;
        let trap = (x0.a + x1.a) / 2.0;
        assert!(
            (dv - trap).abs() <= 1e-9 * a_bound + 4.0 * err_v / h + err_at,
            "dv/dt {dv} vs a {trap} on [{t0}, {t1}]"
        );
    }
}

fn check_double_s(p: &DoubleS, l: &Limits) {
    let length = p.length();
    let t_end = p.duration();
    assert!(t_end.is_finite() && t_end >= 0.0);
    let end = p.sample(t_end);
    assert_eq!(
        end,
        State {
            s: length,
            v: 0.0,
            a: 0.0,
            j: 0.0
        }
    );
    assert_eq!(p.sample(t_end * 2.0 + 1.0), end);
    let start = p.sample(0.0);
    assert_eq!((start.s, start.v, start.a), (0.0, 0.0, 0.0));
    assert_eq!(p.sample(-1.0), start);
    // The approach to the end is continuous: in the last jerk phase, r before the end, the
    // profile is a mirrored jerk-up (s = L − J r³/6, v = J r²/2, a = −J r).
    let last = t_end - p.phase_times()[6];
    for frac in [1e-3, 1e-6, 1e-9, 1e-12] {
        let r = t_end * frac;
        if r > last {
            continue;
        }
        let st = p.sample(t_end - r);
        let r = t_end - (t_end - r);
        let tol = 1e-9 * length.max(1.0);
        assert!(
            (length - st.s - l.jerk * r * r * r / 6.0).abs() <= tol,
            "{st:?} at r = {r}"
        );
        assert!(
            (st.v - l.jerk * r * r / 2.0).abs() <= 1e-9 * l.vel,
            "{st:?} at r = {r}"
        );
        assert!(
            (st.a + l.jerk * r).abs() <= 1e-9 * l.dec,
            "{st:?} at r = {r}"
        );
    }
    assert!(p.peak_velocity() <= l.vel * (1.0 + 1e-9));
    assert!(p.peak_acceleration() <= l.acc * (1.0 + 1e-9));
    assert!(p.peak_deceleration() <= l.dec * (1.0 + 1e-9));
    let times = p.phase_times();
    for w in times.windows(2) {
        assert!(
            w[1] >= w[0] - 1e-12 * t_end,
            "phase times out of order: {times:?}"
        );
    }
    let bounds = Bounds {
        v_max: l.vel,
        acc_max: l.acc,
        dec_max: l.dec,
        jerk_max: l.jerk,
    };
    check_samples(&|t| p.sample(t), t_end, &times, &bounds);
}

/// Samples at the servo period (all of the motion if short, else windows around every phase
/// switch and the ends) and checks the backward differences against the limits. A divided
/// difference is a B-spline average of the derivative it approximates, so it can never exceed
/// the derivative's bound; only the rounding of s (amplified by 1/h^k) is allowed on top.
fn check_servo(p: &DoubleS, l: &Limits) {
    let h = SERVO;
    let t_end = p.duration();
    let last = (t_end / h).ceil() as i64 + 3;
    let mut ranges: Vec<(i64, i64)> = Vec::new();
    if last <= 100_000 {
        ranges.push((0, last));
    } else {
        for b in p.phase_times() {
            let k = (b / h).round() as i64;
            ranges.push(((k - 300).max(0), (k + 300).min(last)));
        }
    }
    let err_s = 4.0 * EPS * (p.length() + l.vel * t_end) + 1e-300;
    let tol = 1.0 + 1e-6;
    let d_bound = l.acc.max(l.dec);
    for (k0, k1) in ranges {
        let s: Vec<f64> = ((k0 - 3)..=k1).map(|k| p.sample(k as f64 * h).s).collect();
        for i in 3..s.len() {
            let d1 = (s[i] - s[i - 1]) / h;
            let d2 = (s[i] - 2.0 * s[i - 1] + s[i - 2]) / (h * h);
            let d3 = (s[i] - 3.0 * s[i - 1] + 3.0 * s[i - 2] - s[i - 3]) / (h * h * h);
            let k = k0 - 3 + i as i64;
            assert!(d1 >= -2.0 * err_s / h, "backward step at k = {k}: {d1}");
            assert!(
                d1 <= l.vel * tol + 2.0 * err_s / h,
                "1st difference {d1} > vel {} at k = {k}",
                l.vel
            );
            assert!(
                d2.abs() <= d_bound * tol + 4.0 * err_s / (h * h),
                "2nd difference {d2} beyond {d_bound} at k = {k}"
            );
            assert!(
                d3.abs() <= l.jerk * tol + 8.0 * err_s / (h * h * h),
                "3rd difference {d3} beyond jerk {} at k = {k}",
                l.jerk
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Hand-computed profiles
// ---------------------------------------------------------------------------------------------

#[test]
fn symmetric_profile_with_cruise() {
    // vel 10, acc 100, jerk 1000: vel·jerk = 1e4 = acc², so the acceleration just reaches 100
    // with no constant phase: Tj = acc/jerk = 0.1 s, Ta = vel/acc + acc/jerk = 0.2 s. The ramps
    // cover vel·Ta/2 = 1 each, the cruise the remaining 98 at 10: 9.8 s. T = 0.2+9.8+0.2 = 10.2 s.
    let l = lim(10.0, 100.0, 100.0, 1000.0);
    let p = plan(100.0, l);
    assert_close("duration", p.duration(), 10.2, 1e-12);
    assert_close("peak v", p.peak_velocity(), 10.0, 1e-15);
    assert_close("peak a", p.peak_acceleration(), 100.0, 1e-15);
    // End of the jerk-up phase: s = J t³/6 = 1000·0.001/6, v = J t²/2 = 5, a = 100.
    let st = p.sample(0.1);
    assert_close("s(0.1)", st.s, 1.0 / 6.0, 1e-12);
    assert_close("v(0.1)", st.v, 5.0, 1e-12);
    assert_close("a(0.1)", st.a, 100.0, 1e-12);
    // Halfway the profile cruises at s = 1 + 10·(5.1 − 0.2) = 50 by symmetry.
    let mid = p.sample(5.1);
    assert_close("s(5.1)", mid.s, 50.0, 1e-12);
    assert_eq!((mid.v, mid.a, mid.j), (10.0, 0.0, 0.0));
    check_double_s(&p, &l);
    check_servo(&p, &l);
}

#[test]
fn asymmetric_acceleration_and_deceleration() {
    // acc 100: Tj = 0.1, no hold, Ta = 0.2. dec 50: Tj = 0.05, hold 10/50 − 0.05 = 0.15,
    // Td = 0.25. Ramps cover 10·(0.2 + 0.25)/2 = 2.25, cruise 97.75/10 = 9.775 s.
    // T = 0.2 + 9.775 + 0.25 = 10.225 s.
    let l = lim(10.0, 100.0, 50.0, 1000.0);
    let p = plan(100.0, l);
    assert_close("duration", p.duration(), 10.225, 1e-12);
    let want = [0.0, 0.1, 0.1, 0.2, 9.975, 10.025, 10.175, 10.225];
    for (got, want) in p.phase_times().iter().zip(want) {
        assert!((got - want).abs() < 1e-12, "{:?}", p.phase_times());
    }
    assert_close("peak dec", p.peak_deceleration(), 50.0, 1e-15);
    // During the deceleration hold a = −50 exactly.
    let st = p.sample(10.1);
    assert_eq!((st.a, st.j), (-50.0, 0.0));
    // The last jerk phase mirrors a jerk-up: 0.01 s before the end s = L − J·0.01³/6.
    let st = p.sample(10.215);
    assert_close("s near end", st.s, 100.0 - 1000.0 * 1e-6 / 6.0, 1e-13);
    assert_close("v near end", st.v, 1000.0 * 1e-4 / 2.0, 1e-9);
    check_double_s(&p, &l);
    check_servo(&p, &l);

    // Swapping acc and dec mirrors the profile in time: same duration, s(t) = L − s'(T − t).
    let m = plan(100.0, lim(10.0, 50.0, 100.0, 1000.0));
    assert_close("mirrored duration", m.duration(), 10.225, 1e-12);
    for i in 0..=100 {
        let t = p.duration() * i as f64 / 100.0;
        let a = p.sample(t).s;
        let b = 100.0 - m.sample(m.duration() - t).s;
        assert!((a - b).abs() < 1e-9, "mirror at t = {t}: {a} vs {b}");
    }
}

#[test]
fn short_move_reaches_acc_but_not_vel() {
    // acc = dec = 100, jerk 1e4: the acceleration limit is reached above vp = acc²/J = 1.
    // With both limits reached L = ½(1/acc + 1/dec)vp² + (acc + dec)/(2J)·vp
    //                            = 0.01 vp² + 0.01 vp, so vp = 5 gives L = 0.3 (< vel 10).
    // Ta = Td = 5/100 + 100/1e4 = 0.06 s, T = 0.12 s.
    let l = lim(10.0, 100.0, 100.0, 1e4);
    let p = plan(0.3, l);
    assert_close("peak v", p.peak_velocity(), 5.0, 1e-12);
    assert_close("peak a", p.peak_acceleration(), 100.0, 1e-15);
    assert_close("duration", p.duration(), 0.12, 1e-12);
    let times = p.phase_times();
    assert!((times[4] - times[3]).abs() < 1e-15, "no cruise: {times:?}");
    check_double_s(&p, &l);
    check_servo(&p, &l);
}

#[test]
fn short_move_reaches_neither_acc_nor_vel() {
    // jerk 100, acc = dec = 100: acc would need vp ≥ acc²/J = 100 > vel. Triangular ramps:
    // L = 2 vp^(3/2)/√J, so vp = 1 gives L = 0.2. Tj = √(vp/J) = 0.1, T = 4 Tj = 0.4 s,
    // peak acceleration √(vp·J) = 10.
    let l = lim(10.0, 100.0, 100.0, 100.0);
    let p = plan(0.2, l);
    assert_close("peak v", p.peak_velocity(), 1.0, 1e-12);
    assert_close("peak a", p.peak_acceleration(), 10.0, 1e-12);
    assert_close("peak dec", p.peak_deceleration(), 10.0, 1e-12);
    assert_close("duration", p.duration(), 0.4, 1e-12);
    assert_close("s at midpoint", p.sample(0.2).s, 0.1, 1e-12);
    check_double_s(&p, &l);
    check_servo(&p, &l);
}

#[test]
fn short_move_reaches_acc_but_not_dec() {
    // jerk 1e4, acc 100 (reached above vp = 1), dec 1000 (reached above vp = 100), vel 50.
    // With vp = 4: Ta = 4/100 + 100/1e4 = 0.05, Td = 2√(4/1e4) = 0.04, L = 4·0.09/2 = 0.18,
    // T = 0.09 s, peak deceleration √(4·1e4) = 200.
    let l = lim(50.0, 100.0, 1000.0, 1e4);
    let p = plan(0.18, l);
    assert_close("peak v", p.peak_velocity(), 4.0, 1e-12);
    assert_close("peak a", p.peak_acceleration(), 100.0, 1e-15);
    assert_close("peak dec", p.peak_deceleration(), 200.0, 1e-12);
    assert_close("duration", p.duration(), 0.09, 1e-12);
    check_double_s(&p, &l);
    check_servo(&p, &l);
    // And the other way round.
    let l = lim(50.0, 1000.0, 100.0, 1e4);
    let p = plan(0.18, l);
    assert_close("peak v", p.peak_velocity(), 4.0, 1e-12);
    assert_close("peak a", p.peak_acceleration(), 200.0, 1e-12);
    assert_close("peak dec", p.peak_deceleration(), 100.0, 1e-15);
    assert_close("duration", p.duration(), 0.09, 1e-12);
    check_double_s(&p, &l);
}

#[test]
fn vel_reached_without_reaching_acc() {
    // vel 1, acc 100, jerk 1000: vel < acc²/J = 10, so the ramps are triangular with
    // Tj = √(vel/J) = 1/√1000 and Ta = Td = 2Tj; T = L/vel + Ta = 10 + 2/√1000.
    let l = lim(1.0, 100.0, 100.0, 1000.0);
    let p = plan(10.0, l);
    assert_close("duration", p.duration(), 10.0 + 2.0 / 1000f64.sqrt(), 1e-12);
    assert_close("peak a", p.peak_acceleration(), 1000f64.sqrt(), 1e-12);
    check_double_s(&p, &l);
    check_servo(&p, &l);
}

#[test]
fn zero_tiny_and_huge_lengths() {
    let l = lim(500.0, 2000.0, 3000.0, 1e5);
    let p = plan(0.0, l);
    assert_eq!(p.duration(), 0.0);
    assert_eq!(p.sample(0.0), State::default());
    assert_eq!(p.sample(1.0), State::default());
    assert_eq!(p.peak_velocity(), 0.0);
    let p = plan(-0.0, l);
    assert_eq!(p.duration(), 0.0);

    for length in [1e-12, 1e-200, 1e-300, 1e-310, 5e-324, 1e-6, 1e3, 1e6] {
        let p = plan(length, l);
        assert!(p.duration() > 0.0, "length {length}");
        assert!(p.duration().is_finite(), "length {length}");
        assert_eq!(p.sample(p.duration()).s, length);
        for i in 0..=1000 {
            let st = p.sample(p.duration() * i as f64 / 1000.0);
            assert!(st.s.is_finite() && st.v.is_finite() && st.a.is_finite());
            assert!(st.v >= 0.0 && st.s >= 0.0 && st.s <= length);
        }
        check_double_s(&p, &l);
    }
    // 1e6 at vel 500 cruises for almost the whole 2000 s.
    let p = plan(1e6, l);
    assert!(
        (p.duration()
            - (2000.0 + (500.0 / 2000.0 + 2000.0 / 1e5 + 500.0 / 3000.0 + 3000.0 / 1e5) / 2.0))
            .abs()
            < 1e-9
    );
    check_servo(&p, &l);
}

#[test]
fn bad_inputs_are_refused_by_name() {
    let good = lim(1.0, 2.0, 3.0, 4.0);
    let cases = [
        (lim(0.0, 2.0, 3.0, 4.0), "vel", "0"),
        (lim(1.0, -2.0, 3.0, 4.0), "acc", "-2"),
        (lim(1.0, 2.0, f64::NAN, 4.0), "dec", "NaN"),
        (lim(1.0, 2.0, 3.0, f64::INFINITY), "jerk", "inf"),
    ];
    for (l, name, value) in cases {
        match DoubleS::plan(1.0, l) {
            Err(LawError::BadLimit(msg)) => {
                assert!(msg.contains(name) && msg.contains(value), "{msg}");
                let text = LawError::BadLimit(msg).to_string();
                assert!(text.contains(name) && text.contains(value), "{text}");
            }
            other => panic!("{l:?} gave {other:?}"),
        }
    }
    for length in [-1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1e-300] {
        match DoubleS::plan(length, good) {
            Err(LawError::BadLength(x)) => {
                assert!(x.is_nan() == length.is_nan());
                assert!(LawError::BadLength(x)
                    .to_string()
                    .contains(&format!("{length}")));
            }
            other => panic!("length {length} gave {other:?}"),
        }
    }
    assert!(matches!(
        Stop::plan(1.0, 0.0, 0.0, 1.0),
        Err(LawError::BadLimit(m)) if m.contains("dec")
    ));
    assert!(matches!(
        Stop::plan(1.0, 0.0, 1.0, -1.0),
        Err(LawError::BadLimit(m)) if m.contains("jerk")
    ));
    assert!(matches!(
        Stop::plan(-1.0, 0.0, 1.0, 1.0),
        Err(LawError::BadStart(_))
    ));
    assert!(matches!(
        Stop::plan(f64::NAN, 0.0, 1.0, 1.0),
        Err(LawError::BadStart(_))
    ));
    assert!(matches!(
        Stop::plan(1.0, f64::INFINITY, 1.0, 1.0),
        Err(LawError::BadStart(_))
    ));
}

#[test]
fn nan_time_samples_the_start() {
    let p = plan(1.0, lim(1.0, 10.0, 10.0, 100.0));
    assert_eq!(p.sample(f64::NAN), p.sample(0.0));
    let s = stop(1.0, 0.0, 10.0, 100.0);
    assert_eq!(s.sample(f64::NAN), s.sample(0.0));
}

// ---------------------------------------------------------------------------------------------
// Stops
// ---------------------------------------------------------------------------------------------

fn check_stop(st: &Stop, v0: f64, a0: f64, dec: f64, jerk: f64) {
    let t_end = st.duration();
    assert!(t_end.is_finite() && t_end >= 0.0);
    let end = st.sample(t_end);
    assert_eq!(
        end,
        State {
            s: st.distance(),
            v: 0.0,
            a: 0.0,
            j: 0.0
        }
    );
    assert_eq!(st.sample(t_end + 1.0), end);
    if t_end > 0.0 {
        let s0 = st.sample(0.0);
        assert_eq!(s0.s, 0.0);
        assert_close("v at start", s0.v, v0, 1e-12);
        assert_close("a at start", s0.a, a0, 1e-12);
        // The last phase, r before the end: s = d − j r³/6, v = j r²/2, a = −j r.
        let j = st.jerk();
        let last = st.phase_durations()[2];
        for frac in [1e-3, 1e-6, 1e-9, 1e-12] {
            let r = t_end * frac;
            if r > last {
                continue;
            }
            let x = st.sample(t_end - r);
            let r = t_end - (t_end - r);
            let d = st.distance();
            assert!(
                (d - x.s - j * r * r * r / 6.0).abs() <= 1e-9 * d.max(1.0),
                "{x:?}"
            );
            assert!((x.v - j * r * r / 2.0).abs() <= 1e-9 * v0.max(1.0), "{x:?}");
            assert!((x.a + j * r).abs() <= 1e-9 * dec.max(a0.abs()), "{x:?}");
        }
    }
    // Unless the start was already past saving within the jerk limit, the limit holds.
    let worst_drop = if a0 < 0.0 {
        a0 * a0 / (2.0 * jerk)
    } else {
        0.0
    };
    if v0 >= worst_drop * (1.0 + 1e-9) {
        assert!(
            st.jerk() <= jerk * (1.0 + 1e-12),
            "jerk {} > {jerk}",
            st.jerk()
        );
    } else {
        assert!(st.jerk() >= jerk || t_end == 0.0);
    }
    let v_top = v0
        + if a0 > 0.0 {
            a0 * a0 / (2.0 * jerk)
        } else {
            0.0
        };
    let bounds = Bounds {
        v_max: v_top.max(1e-300),
        acc_max: a0.max(0.0).max(1e-300),
        dec_max: dec.max(-a0),
        jerk_max: st.jerk().max(1e-300),
    };
    let p = st.phase_durations();
    let switches = [0.0, p[0], p[0] + p[1], t_end];
    if t_end > 0.0 {
        check_samples(&|t| st.sample(t), t_end, &switches, &bounds);
    }
}

#[test]
fn stop_from_cruise_matches_the_double_s_ramp() {
    // v0 10, dec 100, jerk 1000: v0·J = dec², so jerk down 0.1 s to −100 and straight back up
    // 0.1 s. T = 0.2 s; the velocity is point-symmetric, so the distance is v0·T/2 = 1.
    let s = stop(10.0, 0.0, 100.0, 1000.0);
    assert_close("duration", s.duration(), 0.2, 1e-12);
    assert_close("distance", s.distance(), 1.0, 1e-12);
    check_stop(&s, 10.0, 0.0, 100.0, 1000.0);
    // It is the deceleration half of a double-S cruising at 10.
    let p = plan(100.0, lim(10.0, 100.0, 100.0, 1000.0));
    let t0 = p.phase_times()[4];
    for i in 0..=50 {
        let t = 0.2 * i as f64 / 50.0;
        let a = s.sample(t);
        let b = p.sample(t0 + t);
        assert!((a.s - (b.s - p.sample(t0).s)).abs() < 1e-9, "t = {t}");
        assert!(
            (a.v - b.v).abs() < 1e-9 && (a.a - b.a).abs() < 1e-9,
            "t = {t}"
        );
    }
}

#[test]
fn stop_while_still_accelerating() {
    // v0 10, a0 +50, dec 100, jerk 1000: the velocity still grows by a0²/(2J) = 1.25 to 11.25
    // while the jerk brings a to 0. spare = v0 + a0²/(2J) − dec²/J = 1.25 ≥ 0, so dec is held
    // for 1.25/100 = 0.0125 s: T = (50 + 100)/1000 + 0.0125 + 0.1 = 0.2625 s.
    let s = stop(10.0, 50.0, 100.0, 1000.0);
    assert_close("duration", s.duration(), 0.2625, 1e-12);
    assert_close("peak dec", s.peak_deceleration(), 100.0, 1e-15);
    let top = s.sample(0.05);
    assert_close("top speed", top.v, 11.25, 1e-12);
    assert!(top.a.abs() < 1e-12);
    check_stop(&s, 10.0, 50.0, 100.0, 1000.0);
}

#[test]
fn stop_while_braking_harder_than_dec() {
    // v0 10, a0 −200, dec 100, jerk 1e4: jerk up to −100 in 0.01 s (v 10 → 8.5,
    // s = 0.1 − 0.01 + 1/600), hold −100 for (10 − 200²/2e4)/100 = 0.08 s (v 8.5 → 0.5,
    // s = 0.68 − 0.32), jerk to 0 in 0.01 s (s = 1/600). T = 0.1 s, distance 0.45 + 1/300.
    let s = stop(10.0, -200.0, 100.0, 1e4);
    assert_close("duration", s.duration(), 0.1, 1e-12);
    assert_close("distance", s.distance(), 0.45 + 1.0 / 300.0, 1e-12);
    assert_close("jerk", s.jerk(), 1e4, 1e-15);
    let hold = s.sample(0.05);
    assert_eq!(hold.a, -100.0);
    check_stop(&s, 10.0, -200.0, 100.0, 1e4);
}

#[test]
fn stop_too_slow_to_reach_dec() {
    // v0 1, dec 100, jerk 1000: v0·J = 1000 < dec², so the peak deceleration is √(J·v0):
    // T = 2√1000/1000 s, distance v0·T/2 by symmetry.
    let s = stop(1.0, 0.0, 100.0, 1000.0);
    let t = 2.0 * 1000f64.sqrt() / 1000.0;
    assert_close("duration", s.duration(), t, 1e-12);
    assert_close("distance", s.distance(), t / 2.0, 1e-12);
    assert_close("peak dec", s.peak_deceleration(), 1000f64.sqrt(), 1e-12);
    check_stop(&s, 1.0, 0.0, 100.0, 1000.0);
}

#[test]
fn stop_that_cannot_respect_the_jerk() {
    // v0 1, a0 −100, jerk 1000: even jerking straight back to 0 loses 100²/2000 = 5 > 1 of
    // velocity, so the jerk is raised to a0²/(2v0) = 5000: T = 2v0/|a0| = 0.02 s, and the
    // distance of v = v0(1 − t/T)² is v0·T/3.
    let s = stop(1.0, -100.0, 100.0, 1000.0);
    assert_close("jerk", s.jerk(), 5000.0, 1e-12);
    assert_close("duration", s.duration(), 0.02, 1e-12);
    assert_close("distance", s.distance(), 0.02 / 3.0, 1e-12);
    check_stop(&s, 1.0, -100.0, 100.0, 1000.0);
}

#[test]
fn degenerate_stops() {
    let s = stop(0.0, 0.0, 10.0, 100.0);
    assert_eq!(s.duration(), 0.0);
    assert_eq!(s.distance(), 0.0);
    assert_eq!(s.sample(0.0), State::default());
    // At rest but braking: nothing left to stop.
    let s = stop(0.0, -5.0, 10.0, 100.0);
    assert_eq!(s.duration(), 0.0);
    assert_eq!(s.sample(0.0), State::default());
    // At rest but accelerating: it moves a little before it settles.
    let s = stop(0.0, 10.0, 10.0, 100.0);
    assert!(s.duration() > 0.0 && s.distance() > 0.0);
    check_stop(&s, 0.0, 10.0, 10.0, 100.0);
    // Subnormal velocity with a hard brake: immediate, no NaN.
    let s = stop(1e-310, -1e10, 10.0, 100.0);
    assert!(s.duration().is_finite() && s.distance().is_finite());
    assert_eq!(s.sample(s.duration()).v, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Random profiles
// ---------------------------------------------------------------------------------------------

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.ln()..=hi.ln()).prop_map(f64::exp)
}

fn limits() -> impl Strategy<Value = Limits> {
    (
        log_uniform(1.0, 5000.0),
        log_uniform(10.0, 1e5),
        log_uniform(10.0, 1e5),
        log_uniform(100.0, 1e8),
    )
        .prop_map(|(vel, acc, dec, jerk)| lim(vel, acc, dec, jerk))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_profiles_are_exact_and_within_limits(
        length in log_uniform(1e-6, 1e4),
        l in limits(),
    ) {
        let p = plan(length, l);
        check_double_s(&p, &l);
        // Time-optimality: the profile always saturates a velocity or acceleration limit or
        // is the triangular all-jerk profile.
        let tv = p.phase_times()[4] - p.phase_times()[3];
        let saturated = (p.peak_velocity() - l.vel).abs() <= 1e-9 * l.vel
            || (p.peak_acceleration() - l.acc).abs() <= 1e-9 * l.acc
            || (p.peak_deceleration() - l.dec).abs() <= 1e-9 * l.dec
            || tv <= 1e-12 * p.duration();
        prop_assert!(saturated);
    }

    #[test]
    fn servo_rate_differences_stay_within_limits(
        length in log_uniform(1e-6, 1e4),
        l in limits(),
    ) {
        let p = plan(length, l);
        check_servo(&p, &l);
    }

    #[test]
    fn time_scaling_is_exact(
        length in log_uniform(1e-6, 1e4),
        l in limits(),
        lambda in log_uniform(0.1, 10.0),
    ) {
        let p = plan(length, l);
        let q = plan(length, lim(
            lambda * l.vel,
            lambda * lambda * l.acc,
            lambda * lambda * l.dec,
            lambda * lambda * lambda * l.jerk,
        ));
        prop_assert!(
            (q.duration() * lambda - p.duration()).abs() <= 1e-9 * p.duration(),
            "{} vs {}", q.duration() * lambda, p.duration()
        );
        for i in 0..=500 {
            let t = q.duration() * i as f64 / 500.0;
            let a = q.sample(t).s;
            let b = p.sample(lambda * t).s;
            prop_assert!(
                (a - b).abs() <= 1e-9 * length.max(1.0),
                "s_λ({t}) = {a} vs s({}) = {b}", lambda * t
            );
        }
    }

    #[test]
    fn random_stops_end_at_rest(
        v0 in prop_oneof![Just(0.0), 0.0..5000.0, log_uniform(1e-9, 1.0)],
        frac in prop_oneof![Just(0.0), Just(-1.0), Just(1.0), -2.0..1.0f64],
        acc in log_uniform(10.0, 1e5),
        dec in log_uniform(10.0, 1e5),
        jerk in log_uniform(100.0, 1e8),
    ) {
        let a0 = if frac < 0.0 { frac * dec } else { frac * acc };
        let st = stop(v0, a0, dec, jerk);
        check_stop(&st, v0, a0, dec, jerk);
        // With room to stop the deceleration limit holds from the moment a0 is within it.
        if a0 >= -dec {
            prop_assert!(st.peak_deceleration() <= dec * (1.0 + 1e-9));
        }
    }
}
