//! Pick & place belts and workpiece streams: the jerk-limited belt profile (exact travel, speed,
//! acceleration and jerk, and its inverse), the workpiece feeds a detector makes from it, and the
//! `[[belts]]` / `[[workpieces]]` scenario entries with errors pointing at the offending value.

use pacer::config::belts::{belts, BeltWorld};
use pacer::config::parse_toml;
use pacer::config::scenario::ScenarioFile;
use pacer::devices::pickplace::setup::{AxisLimit, BeltSetup};
use pacer::diag::Problem;
use pacer::world::belt::{BeltChange, BeltProfile};
use pacer::world::workpieces::{feeds, Stream};

fn change(at: f64, speed: f64, ramp: f64) -> BeltChange {
    BeltChange { at, speed, ramp }
}

/// Speed-ups, a stop with a standstill, a restart and a slow-down; all ramps are S-ramps.
fn stop_and_restart() -> BeltProfile {
    BeltProfile::new(
        150.0,
        &[
            change(2.0, 220.0, 1.0),
            change(5.0, 0.0, 0.8),
            change(7.0, 100.0, 1.5),
            change(10.0, 60.0, 0.5),
        ],
    )
    .expect("a valid profile")
}

/// Every boundary between pieces of `stop_and_restart`.
const BOUNDARIES: [f64; 12] = [
    2.0, 2.5, 3.0, 5.0, 5.4, 5.8, 7.0, 7.75, 8.5, 10.0, 10.25, 10.5,
];

/// Composite two-point Gauss–Legendre rule of `f` over [a, b] with `n` parts: exact for cubics
/// and never sampling the ends, where the jerk jumps.
fn gauss(f: &impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let off = 0.5 * h / 3f64.sqrt();
    (0..n)
        .map(|i| {
            let mid = a + h * (i as f64 + 0.5);
            0.5 * h * (f(mid - off) + f(mid + off))
        })
        .sum()
}

/// The integral of `f` from 0 to `t`, split at the profile's piece boundaries so each part is
/// smooth (the jerk jumps at them) and integrated finely.
fn integral(f: impl Fn(f64) -> f64, t: f64) -> f64 {
    let mut cuts = vec![0.0];
    cuts.extend(BOUNDARIES.iter().copied().filter(|b| *b < t));
    cuts.push(t);
    cuts.windows(2).map(|w| gauss(&f, w[0], w[1], 1_000)).sum()
}

#[test]
fn position_is_the_integral_of_velocity_and_so_on_down() {
    let b = stop_and_restart();
    for &t in &[0.7, 2.3, 2.9, 4.0, 5.5, 6.5, 7.3, 8.0, 9.9, 10.4, 12.0] {
        let travel = integral(|x| b.velocity(x), t);
        assert!(
            (travel - b.position(t)).abs() < 1e-9,
            "t={t}: integral {travel} vs position {}",
            b.position(t)
        );
        let speed = b.velocity(0.0) + integral(|x| b.acceleration(x), t);
        assert!(
            (speed - b.velocity(t)).abs() < 1e-9,
            "t={t}: integral {speed} vs velocity {}",
            b.velocity(t)
        );
        let acc = integral(|x| b.jerk(x), t);
        assert!(
            (acc - b.acceleration(t)).abs() < 1e-9,
            "t={t}: integral {acc} vs acceleration {}",
            b.acceleration(t)
        );
    }
    // Exact values: 150 mm/s for 2 s, then 1 s at an average of 185 mm/s.
    assert!((b.position(3.0) - 485.0).abs() < 1e-9);
    assert_eq!(b.velocity(4.0), 220.0);
    assert_eq!(b.position(-1.0), 0.0);
}

#[test]
fn jerk_is_plus_minus_four_dv_over_t_squared() {
    let b = stop_and_restart();
    let expect = [
        // (inside the first half, inside the second half, Δv, T)
        (2.2, 2.8, 70.0, 1.0),
        (5.1, 5.6, -220.0, 0.8),
        (7.2, 8.0, 100.0, 1.5),
        (10.1, 10.4, -40.0, 0.5),
    ];
    for (first, second, dv, t) in expect {
        let j = 4.0 * dv / (t * t);
        assert!((b.jerk(first) - j).abs() < 1e-9 * j.abs(), "{first}");
        assert!((b.jerk(second) + j).abs() < 1e-9 * j.abs(), "{second}");
    }
    // Peak acceleration 2Δv/T in the middle of each ramp, none outside ramps.
    assert!((b.acceleration(2.5) - 140.0).abs() < 1e-9);
    assert!((b.acceleration(5.4) + 550.0).abs() < 1e-9);
    assert_eq!(b.acceleration(4.0), 0.0);
    assert_eq!(b.jerk(4.0), 0.0);
    assert_eq!(b.velocity(6.5), 0.0);
}

#[test]
fn position_velocity_and_acceleration_are_continuous() {
    let b = stop_and_restart();
    for &t in &BOUNDARIES {
        // The float just below the boundary: the left limit as closely as f64 can get.
        let (l, r) = (f64::from_bits(t.to_bits() - 1), t);
        assert!(
            (b.position(l) - b.position(r)).abs() < 1e-9,
            "position at {t}"
        );
        assert!(
            (b.velocity(l) - b.velocity(r)).abs() < 1e-9,
            "velocity at {t}"
        );
        assert!(
            (b.acceleration(l) - b.acceleration(r)).abs() < 1e-9,
            "acceleration at {t}: {} vs {}",
            b.acceleration(l),
            b.acceleration(r)
        );
    }
}

#[test]
fn time_at_inverts_position() {
    let b = stop_and_restart();
    let mut t = 0.013;
    while t < 14.0 {
        let p = b.position(t);
        let back = b.time_at(p).expect("reached");
        assert!(
            (b.position(back) - p).abs() < 1e-9,
            "t={t}: position {p}, back at {back}"
        );
        // Where the belt moves briskly, the time itself comes back to well under 1e-12 s.
        if b.velocity(t) > 1.0 {
            assert!((back - t).abs() < 1e-12, "t={t}: back at {back}");
        }
        t += 0.0173;
    }
    // Samples right at the piece boundaries, during ramps included.
    for &t in &BOUNDARIES {
        if b.velocity(t) > 1.0 {
            let back = b.time_at(b.position(t)).expect("reached");
            assert!((back - t).abs() < 1e-12, "boundary {t}: back at {back}");
        }
    }
    // The travel of the standstill is first reached when the stop ends (5.8 s), not later.
    let rest = b.position(6.5);
    let first = b.time_at(rest).expect("reached");
    assert!(first <= 5.8 + 1e-12 && first > 5.79, "{first}");
    // A little further is only reached after the restart.
    let after = b.time_at(rest + 1e-3).expect("reached");
    assert!(after > 7.0 && after < 7.75);
    assert_eq!(b.time_at(0.0), Some(0.0));
}

#[test]
fn time_at_is_none_after_a_final_stop() {
    let b = BeltProfile::new(100.0, &[change(1.0, 0.0, 0.5)]).expect("a valid profile");
    let end = b.position(10.0);
    assert!((end - 125.0).abs() < 1e-9);
    assert_eq!(b.time_at(end + 0.01), None);
    assert_eq!(b.time_at(f64::INFINITY), None);
    let near = b.time_at(124.0).expect("reached");
    assert!((b.position(near) - 124.0).abs() < 1e-9);
    assert!(near > 1.0 && near < 1.5);
    assert_eq!(BeltProfile::stopped().time_at(1.0), None);
    assert_eq!(BeltProfile::stopped().position(5.0), 0.0);
}

#[test]
fn peaks_and_steps() {
    let (v, a, j) = stop_and_restart().peaks();
    assert_eq!(v, 220.0);
    assert!((a - 550.0).abs() < 1e-9);
    assert!((j - 1375.0).abs() < 1e-9);
    // A step in speed needs an infinite acceleration for an instant.
    let step = BeltProfile::new(50.0, &[change(1.0, 80.0, 0.0)]).expect("a valid profile");
    assert_eq!(step.peaks(), (80.0, f64::INFINITY, f64::INFINITY));
    assert_eq!(step.velocity(1.0), 80.0);
    assert!((step.position(2.0) - 130.0).abs() < 1e-12);
    assert_eq!(BeltProfile::stopped().peaks(), (0.0, 0.0, 0.0));
}

#[test]
fn bad_profiles_are_refused() {
    let err = BeltProfile::new(-1.0, &[]).expect_err("negative speed");
    assert_eq!(err.change, usize::MAX);
    let err = BeltProfile::new(f64::NAN, &[]).expect_err("not a number");
    assert_eq!(err.change, usize::MAX);
    let overlapping = [change(1.0, 5.0, 2.0), change(2.0, 1.0, 0.0)];
    assert_eq!(
        BeltProfile::new(1.0, &overlapping).map_err(|e| e.change),
        Err(1)
    );
    let backwards = [change(3.0, 5.0, 0.0), change(2.0, 1.0, 0.0)];
    assert_eq!(
        BeltProfile::new(1.0, &backwards).map_err(|e| e.change),
        Err(1)
    );
    let negative = [change(1.0, -5.0, 0.0)];
    assert_eq!(
        BeltProfile::new(1.0, &negative).map_err(|e| e.change),
        Err(0)
    );
    // Touching the previous ramp's end is fine.
    assert!(BeltProfile::new(1.0, &[change(1.0, 5.0, 2.0), change(3.0, 1.0, 1.0)]).is_ok());
}

fn stream(seed: u64) -> Stream {
    Stream {
        belt: 1,
        travel: (0..200).map(|k| 40.0 + 37.5 * f64::from(k)).collect(),
        detect: [10.0, -20.0, 5.0],
        jitter: [4.0, 25.0, 10.0],
        c: 30.0,
        delay: 0.02,
        seed,
    }
}

#[test]
fn feeds_follow_the_belt_exactly() {
    let b = stop_and_restart();
    let s = stream(7);
    let f = feeds(&s, &b);
    // 150·2 + 185 + 220·2 + 88 + 75 + 100·1.5 + 40 + 60·t: the stream of 200 reaches far beyond
    // the end of the changes, but every detection is reached eventually.
    assert_eq!(f.len(), 200);
    for (k, w) in f.iter().enumerate() {
        assert_eq!(w.id as usize, k);
        assert_eq!(w.belt, 1);
        assert_eq!(Some(w.receive), b.time_at(s.travel[k]));
        assert_eq!(w.valid, w.receive + 0.02);
        let [x, y, z, a, bb, c] = w.position;
        assert!((x - 10.0).abs() <= 4.0);
        assert!((y + 20.0).abs() <= 25.0);
        assert_eq!(z, 5.0);
        assert_eq!((a, bb), (0.0, 0.0));
        assert!((c - 30.0).abs() <= 10.0);
    }
    assert!(f.windows(2).all(|w| w[0].receive < w[1].receive));
    // The jitter is really used.
    assert!(f.iter().any(|w| (w.position[1] + 20.0).abs() > 12.5));
}

#[test]
fn same_seed_same_feeds_other_seed_other_feeds() {
    let b = stop_and_restart();
    let bits = |f: &[pacer::world::workpieces::WorkpieceFeed]| -> Vec<u64> {
        f.iter()
            .flat_map(|w| {
                [w.receive, w.valid]
                    .into_iter()
                    .chain(w.position)
                    .map(f64::to_bits)
            })
            .collect()
    };
    let a = feeds(&stream(7), &b);
    let again = feeds(&stream(7), &b);
    assert_eq!(bits(&a), bits(&again));
    let other = feeds(&stream(8), &b);
    assert_ne!(bits(&a), bits(&other));
    // Only positions differ: times do not depend on the seed.
    assert!(a.iter().zip(&other).all(|(x, y)| x.receive == y.receive));
}

#[test]
fn unreached_detections_are_left_out() {
    let b = BeltProfile::new(100.0, &[change(1.0, 0.0, 0.5)]).expect("a valid profile");
    let f = feeds(&stream(1), &b);
    // Travels 40, 77.5, 115 are reached before the belt stops at 125; 152.5 never is.
    assert_eq!(f.len(), 3);
}

// --- the scenario side ---------------------------------------------------------------------

fn machine() -> Vec<BeltSetup> {
    vec![
        BeltSetup {
            number: 1,
            limit: AxisLimit {
                max_vel: 300.0,
                max_acc: 400.0,
                max_jerk: 2000.0,
            },
        },
        BeltSetup {
            number: 2,
            limit: AxisLimit::default(),
        },
    ]
}

fn load(text: &str, setups: &[BeltSetup]) -> (BeltWorld, Vec<Problem>) {
    let sc: ScenarioFile = parse_toml(text, "scenario").expect("the scenario parses");
    let mut problems = Vec::new();
    let world = belts(&sc, setups, &mut problems);
    (world, problems)
}

/// The one problem `text` makes, and the text its span covers.
fn one_problem<'a>(text: &'a str, setups: &[BeltSetup]) -> (Problem, &'a str) {
    let (_, problems) = load(text, setups);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = problems.into_iter().next().expect("one problem");
    let spanned = &text[p.span.start..p.span.end];
    (p, spanned)
}

const EXAMPLE: &str = r#"
[[belts]]
belt = 1
speed = 150.0
changes = [ { at = "20 s", speed = 220.0, ramp = "1 s" }, { at = "40 s", speed = 0.0, ramp = "0.8 s" } ]

[[workpieces]]
belt = 1
first = 100.0
pitch = 120.0
count = 1200
missing = [17, 40]
detect = [0.0, 0.0, 0.0]
c = 0.0
jitter = { x = 4.0, y = 25.0, c = 10.0 }
seed = 7
delay = "20 ms"
"#;

#[test]
fn the_example_scenario_loads() {
    // The example stops at 550 mm/s² with a jerk of 1375 mm/s³.
    let setups = [
        BeltSetup {
            number: 1,
            limit: AxisLimit {
                max_vel: 250.0,
                max_acc: 600.0,
                max_jerk: 1500.0,
            },
        },
        BeltSetup {
            number: 2,
            limit: AxisLimit::default(),
        },
    ];
    let (world, problems) = load(EXAMPLE, &setups);
    assert!(problems.is_empty(), "{problems:#?}");
    assert_eq!(world.profiles.keys().copied().collect::<Vec<_>>(), [1, 2]);
    let b = &world.profiles[&1];
    // 150·20 + 185·1 + 220·19 + 110·0.8 = 7453 mm, then the belt stands.
    assert!((b.position(100.0) - 7453.0).abs() < 1e-9);
    assert_eq!(world.profiles[&2], BeltProfile::stopped());
    // Detections at 100 + 120·k up to 7453 mm: k = 0 … 61, less the two missing ones.
    assert_eq!(world.feeds.len(), 60);
    let ids: Vec<u32> = world.feeds.iter().map(|f| f.id).collect();
    assert!(ids.windows(2).all(|w| w[0] < w[1]));
    let travels: Vec<f64> = (0..62u32)
        .filter(|k| *k != 17 && *k != 40)
        .map(|k| 100.0 + 120.0 * f64::from(k))
        .collect();
    for (f, travel) in world.feeds.iter().zip(&travels) {
        assert_eq!(Some(f.receive), b.time_at(*travel));
        assert_eq!(f.valid, f.receive + 0.02);
    }
}

#[test]
fn two_streams_on_one_belt_keep_ids_unique_and_merge_in_time() {
    let text = r#"
[[belts]]
belt = 2
speed = 100.0

[[workpieces]]
belt = 2
at = [50.0, 250.0]

[[workpieces]]
belt = 2
first = 150.0
pitch = 200.0
count = 2
"#;
    let (world, problems) = load(text, &machine());
    assert!(problems.is_empty(), "{problems:#?}");
    let got: Vec<(u32, f64)> = world.feeds.iter().map(|f| (f.id, f.receive)).collect();
    assert_eq!(got, [(0, 0.5), (2, 1.5), (1, 2.5), (3, 3.5)]);
}

#[test]
fn unknown_belts_are_named() {
    let (p, at) = one_problem("[[belts]]\nbelt = 3\nspeed = 10.0\n", &machine());
    assert_eq!(at, "3");
    assert!(p.message.contains("belt 3"), "{}", p.message);
    assert!(p.help.as_deref().unwrap_or("").contains("belts 1, 2"));
    let (p, at) = one_problem("[[workpieces]]\nbelt = 9\nat = [1.0]\n", &[]);
    assert_eq!(at, "9");
    assert!(p.help.as_deref().unwrap_or("").contains("no belts"));
}

#[test]
fn a_belt_given_twice() {
    let text = "[[belts]]\nbelt = 1\n\n[[belts]]\nbelt = 1\nspeed = 5.0\n";
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "1");
    assert!(p.span.start > text.find("speed").expect("second entry") - 5);
    assert!(p.message.contains("already"), "{}", p.message);
}

#[test]
fn bad_speeds() {
    let (_, at) = one_problem("[[belts]]\nbelt = 2\nspeed = -5.0\n", &machine());
    assert_eq!(at, "-5.0");
    let (_, at) = one_problem("[[belts]]\nbelt = 2\nspeed = nan\n", &machine());
    assert_eq!(at, "nan");
    let text = "[[belts]]\nbelt = 2\nchanges = [ { at = \"1 s\", speed = -1.5 } ]\n";
    let (_, at) = one_problem(text, &machine());
    assert_eq!(at, "-1.5");
    let text = "[[belts]]\nbelt = 2\nchanges = [ { at = \"1 s\", speed = inf } ]\n";
    let (_, at) = one_problem(text, &machine());
    assert_eq!(at, "inf");
}

#[test]
fn overlapping_and_out_of_order_changes() {
    let text = r#"[[belts]]
belt = 2
changes = [ { at = "1 s", speed = 10.0, ramp = "2 s" }, { at = "2.5 s", speed = 20.0 } ]
"#;
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "\"2.5 s\"");
    assert!(p.message.contains("3 s"), "{}", p.message);
    let text = r#"[[belts]]
belt = 2
changes = [ { at = "5 s", speed = 10.0 }, { at = "4 s", speed = 20.0 } ]
"#;
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "\"4 s\"");
    assert!(p.message.contains("before"), "{}", p.message);
    // Touching the end of the previous ramp is fine.
    let text = r#"[[belts]]
belt = 2
changes = [ { at = "1 s", speed = 10.0, ramp = "2 s" }, { at = "3 s", speed = 20.0 } ]
"#;
    assert!(load(text, &machine()).1.is_empty());
}

#[test]
fn limits_of_the_belt_drive() {
    // 0 → 220 mm/s in 1 s peaks at 440 mm/s².
    let text = r#"[[belts]]
belt = 1
changes = [ { at = "2 s", speed = 220.0, ramp = "1.0 s" } ]
"#;
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "\"1.0 s\"");
    assert_eq!(
        p.message,
        "this ramp accelerates at 440 mm/s² but belt 1 allows 400 (max_acc)"
    );
    assert!(p.label.contains("change 1"), "{}", p.label);
    assert!(
        p.help.as_deref().unwrap_or("").contains("1.1 s"),
        "{:?}",
        p.help
    );
    // 0 → 50 mm/s in 0.3 s: 333 mm/s² is fine, 2222 mm/s³ is not.
    let text = r#"[[belts]]
belt = 1
changes = [ { at = "2 s", speed = 50.0, ramp = "0.3 s" } ]
"#;
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "\"0.3 s\"");
    assert!(p.message.contains("max_jerk"), "{}", p.message);
    assert!(p.message.contains("2222.222 mm/s³"), "{}", p.message);
    // Too fast, at the start and in a change.
    let (p, at) = one_problem("[[belts]]\nbelt = 1\nspeed = 350.0\n", &machine());
    assert_eq!(at, "350.0");
    assert!(p.message.contains("max_vel"), "{}", p.message);
    let text = r#"[[belts]]
belt = 1
speed = 250.0
changes = [ { at = "2 s", speed = 310.0, ramp = "1 s" } ]
"#;
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "310.0");
    assert!(p.message.contains("310 mm/s"), "{}", p.message);
    // A step in speed on a belt with an acceleration limit: the change has no ramp.
    let text = "[[belts]]\nbelt = 1\nchanges = [ { at = \"1 s\", speed = 100.0 } ]\n";
    let (p, at) = one_problem(text, &machine());
    assert_eq!(at, "{ at = \"1 s\", speed = 100.0 }");
    assert!(p.message.contains("max_acc"), "{}", p.message);
    let text =
        "[[belts]]\nbelt = 1\nchanges = [ { at = \"1 s\", speed = 100.0, ramp = \"0 s\" } ]\n";
    let (_, at) = one_problem(text, &machine());
    assert_eq!(at, "\"0 s\"");
    // Belt 2 has no limits: steps are allowed; ramps at exactly the limit are too.
    let text = "[[belts]]\nbelt = 2\nchanges = [ { at = \"1 s\", speed = 1000.0 } ]\n";
    assert!(load(text, &machine()).1.is_empty());
    let text = r#"[[belts]]
belt = 1
changes = [ { at = "2 s", speed = 200.0, ramp = "1 s" } ]
"#;
    assert!(load(text, &machine()).1.is_empty());
}

#[test]
fn workpiece_errors_point_at_the_value() {
    let m = machine();
    let cases: &[(&str, &str, &str)] = &[
        (
            "[[workpieces]]\nbelt = 1\nat = [100.0, 200.0]\npitch = 5.0\ncount = 3\n",
            "[100.0, 200.0]",
            "given twice",
        ),
        ("[[workpieces]]\nbelt = 1\nseed = 3\n", "1", "say where"),
        (
            "[[workpieces]]\nbelt = 1\nfirst = 0.0\npitch = 0.0\ncount = 3\n",
            "0.0",
            "pitch",
        ),
        (
            "[[workpieces]]\nbelt = 1\npitch = -5.0\ncount = 3\n",
            "-5.0",
            "pitch",
        ),
        (
            "[[workpieces]]\nbelt = 1\npitch = 5.0\ncount = 0\n",
            "0",
            "0 workpieces",
        ),
        (
            "[[workpieces]]\nbelt = 1\npitch = 5.0\n",
            "1",
            "`count` is missing",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [100.0, 180.0, 170.0]\n",
            "170.0",
            "increasing",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [100.0, 100.0]\n",
            "100.0",
            "increasing",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [10.0, inf]\n",
            "inf",
            "finite",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [-10.0, 5.0]\n",
            "-10.0",
            "0 mm or more",
        ),
        (
            "[[workpieces]]\nbelt = 1\nfirst = nan\npitch = 5.0\ncount = 3\n",
            "nan",
            "finite",
        ),
        (
            "[[workpieces]]\nbelt = 1\npitch = 5.0\ncount = 5\nmissing = [1, 7]\n",
            "7",
            "workpiece 7",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [1.0]\ndetect = [0.0, nan, 0.0]\n",
            "[0.0, nan, 0.0]",
            "finite",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [1.0]\nc = -inf\n",
            "-inf",
            "C must",
        ),
        (
            "[[workpieces]]\nbelt = 1\nat = [1.0]\njitter = { x = 1.0, y = -2.5 }\n",
            "-2.5",
            "Y jitter",
        ),
    ];
    for (text, spanned, says) in cases {
        let (p, at) = one_problem(text, &m);
        assert_eq!(at, *spanned, "{text}");
        assert!(p.message.contains(says), "{text}: {}", p.message);
        assert_eq!(p.code, "pacer::scenario::workpieces");
        // The span is the value of the key the error is about, not an accidental match.
        if *spanned == "0.0" {
            assert_eq!(&text[p.span.start - 8..p.span.start], "pitch = ");
        }
        if *spanned == "100.0" {
            assert_eq!(p.span.start, text.rfind("100.0").unwrap_or(0));
        }
    }
}

#[test]
fn a_negative_delay_is_refused_where_it_is_written() {
    let text = "[[workpieces]]\nbelt = 1\nat = [1.0]\ndelay = \"-20 ms\"\n";
    let err = parse_toml::<ScenarioFile>(text, "scenario").expect_err("refused");
    assert_eq!(&text[err.span.start..err.span.end], "\"-20 ms\"");
    assert!(err.message.contains("at least 0"), "{}", err.message);
}

#[test]
fn missing_workpieces_are_removed() {
    let text = r#"
[[belts]]
belt = 2
speed = 10.0

[[workpieces]]
belt = 2
first = 5.0
pitch = 10.0
count = 6
missing = [0, 3]
"#;
    let (world, problems) = load(text, &machine());
    assert!(problems.is_empty(), "{problems:#?}");
    let receive: Vec<f64> = world.feeds.iter().map(|f| f.receive).collect();
    assert_eq!(receive, [1.5, 2.5, 4.5, 5.5]);
}

mod random_profiles {
    use super::*;
    use proptest::prelude::*;

    /// Changes from (gap before, speed, ramp) triples, each starting after the previous ended.
    fn profile(initial: f64, raw: &[(f64, f64, f64)]) -> BeltProfile {
        let mut at = 0.0;
        let changes: Vec<BeltChange> = raw
            .iter()
            .map(|&(gap, speed, ramp)| {
                at += gap;
                let c = change(at, speed, ramp);
                at += ramp;
                c
            })
            .collect();
        BeltProfile::new(initial, &changes).expect("a valid profile")
    }

    proptest! {
        #[test]
        fn time_at_is_the_first_time_the_travel_is_reached(
            initial in prop_oneof![Just(0.0), 0.0..500.0f64],
            raw in prop::collection::vec(
                (0.001..3.0f64, prop_oneof![Just(0.0), 0.0..500.0f64], prop_oneof![Just(0.0), 0.001..2.0f64]),
                0..6,
            ),
            fractions in prop::collection::vec(0.0..1.0f64, 1..20),
        ) {
            let b = profile(initial, &raw);
            let horizon = raw.iter().map(|r| r.0 + r.2).sum::<f64>() + 2.0;
            let reach = b.position(horizon);
            for f in fractions {
                let p = reach * f;
                let Some(t) = b.time_at(p) else {
                    // Only a belt that stands still at the end may fail to get there.
                    prop_assert!(b.velocity(horizon) == 0.0 && p >= reach);
                    continue;
                };
                prop_assert!((b.position(t) - p).abs() <= 1e-9 * (1.0 + p));
                // No earlier instant reaches it (up to rounding of the travel).
                prop_assert!(b.position(t - 1e-6) <= p + 1e-9 * (1.0 + p));
            }
            let (v, a, j) = b.peaks();
            let mut t = 0.0;
            while t < horizon {
                prop_assert!(b.velocity(t) <= v * (1.0 + 1e-12) + 1e-12);
                prop_assert!(b.velocity(t) >= -1e-9);
                prop_assert!(b.acceleration(t).abs() <= a * (1.0 + 1e-9) + 1e-9);
                prop_assert!(b.jerk(t).abs() <= j * (1.0 + 1e-9) + 1e-9);
                t += horizon / 997.0;
            }
        }
    }
}
