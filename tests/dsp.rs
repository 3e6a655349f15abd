//! ORION DSP axes: MOVE AT, GEAR AT, GEAR FOR on top of a gear, the queue, PLS, POS.MOD and the
//! card latches, checked against closed-form values.

use pacer::devices::orion::dsp::{
    After, DspAxes, DspAxisConfig, DspEvent, Layer, Queued, Sensor, DEFAULT_QUEUE_DEPTH,
};
use proptest::prelude::*;

/// The DSP axes stepped at a fixed update period, every event kept.
struct Sim {
    d: DspAxes,
    tick: u64,
    dt: f64,
    events: Vec<DspEvent>,
    /// Positions of axes 1, 2, 3 (NaN: not configured) at each event's time.
    at_events: Vec<[f64; 3]>,
}

impl Sim {
    fn new(configs: &[DspAxisConfig], dt: f64) -> Sim {
        let d = DspAxes::new(configs).expect("valid configuration");
        Sim {
            d,
            tick: 0,
            dt,
            events: Vec::new(),
            at_events: Vec::new(),
        }
    }

    fn step(&mut self) -> Vec<DspEvent> {
        self.tick += 1;
        let e = self.d.advance(self.tick as f64 * self.dt).expect("advance");
        for ev in &e {
            let t = ev.time();
            let p = |a: u32| self.d.position_at(a, t).unwrap_or(f64::NAN);
            self.at_events.push([p(1), p(2), p(3)]);
        }
        self.events.extend(e.clone());
        e
    }

    /// Positions of axes 1..=3 at the first event `pick` accepts.
    fn at(&self, pick: impl Fn(&DspEvent) -> bool) -> [f64; 3] {
        let k = self.events.iter().position(pick).expect("no such event");
        self.at_events[k]
    }

    fn run_to(&mut self, t: f64) {
        while (self.tick as f64 * self.dt) < t - 1e-12 {
            self.step();
        }
    }

    fn pos(&self, axis: u32) -> f64 {
        self.d.position(axis).expect("axis")
    }

    fn done_times(&self, axis: u32, layer: Layer) -> Vec<f64> {
        let f = |e: &DspEvent| match *e {
            DspEvent::SegmentDone {
                axis: a,
                layer: l,
                time,
            } if a == axis && l == layer => Some(time),
            _ => None,
        };
        self.events.iter().filter_map(f).collect()
    }

    fn latches(&self) -> Vec<(u32, Sensor, f64, f64)> {
        let f = |e: &DspEvent| match *e {
            DspEvent::Latched {
                axis,
                which,
                time,
                position,
                ..
            } => Some((axis, which, time, position)),
            _ => None,
        };
        self.events.iter().filter_map(f).collect()
    }
}

/// Web axis 1 (user units per rev as given), knife axis 2 (3600 per turn) paced by the web, and
/// axis 3, a twin of the knife that never gets a GEAR FOR.
fn web_knife(web_units: f64, dt: f64) -> Sim {
    let mut web = DspAxisConfig::new(1, None, web_units);
    web.queue_depth = 8;
    Sim::new(
        &[
            web,
            DspAxisConfig::new(2, Some(1), 3600.0),
            DspAxisConfig::new(3, Some(1), 3600.0),
        ],
        dt,
    )
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn move_at_ramps_to_the_rpm_speed_exactly_at_the_ramp_end() {
    // An update period that does not divide the ramp: it ends inside an update.
    let mut s = web_knife(1000.0, 0.0007);
    assert_eq!(s.d.move_at(1, 1000.0, 1000.0), Ok(Queued::Accepted));
    let v = 1000.0 * 1000.0 / 60.0;
    let a = v / 1.0;
    s.run_to(0.5);
    let t = s.d.time();
    assert!(
        close(s.pos(1), 0.5 * a * t * t, 1e-9),
        "{} vs {}",
        s.pos(1),
        0.5 * a * t * t
    );
    assert!(close(s.d.velocity(1).unwrap(), a * t, 1e-9));
    assert!(!s.d.done(1).unwrap());
    s.run_to(1.0);
    assert_eq!(
        s.done_times(1, Layer::Base),
        vec![1.0],
        "the ramp ends at exactly 1 s"
    );
    assert_eq!(s.d.velocity(1).unwrap(), v);
    assert!(s.d.done(1).unwrap(), "a steady velocity is done");
    let t = s.d.time();
    assert!(t > 1.0 && s.d.previous_time() < 1.0);
    assert!(close(s.d.position_at(1, 1.0).unwrap(), 0.5 * a, 1e-9));
    assert!(close(s.pos(1), 0.5 * a + v * (t - 1.0), 1e-9));
    // A ramp back to rest over 333 ms, quadratic in time.
    s.d.move_at(1, 0.0, 333.0).unwrap();
    let (t0, p0) = (s.d.time(), s.pos(1));
    s.run_to(t0 + 0.2);
    let tau = s.d.time() - t0;
    let decel = v / 0.333;
    assert!(close(
        s.pos(1),
        p0 + v * tau - 0.5 * decel * tau * tau,
        1e-9
    ));
    s.run_to(t0 + 0.5);
    assert!(close(
        *s.done_times(1, Layer::Base).last().unwrap(),
        t0 + 0.333,
        1e-12
    ));
    assert!(close(s.pos(1), p0 + v * 0.333 / 2.0, 1e-9));
    assert_eq!(s.d.velocity(1).unwrap(), 0.0);
    // Analytic crossing time on the time-based ramp.
    let mut s = web_knife(60.0, 0.01);
    s.d.move_at(1, 60.0, 1000.0).unwrap(); // 60 units/s reached in 1 s: a = 60
    s.step();
    let hit = s.d.time_at_position(1, 0.0012, 0.0, 0.01).unwrap().unwrap();
    assert!(close(hit, (2.0 * 0.0012 / 60.0_f64).sqrt(), 1e-15));
}

#[test]
fn gear_at_at_once_and_ramped_over_pacer_distance() {
    let mut s = web_knife(100.0, 0.001); // 600 RPM = 1000 units/s
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.d.gear_at(2, 3600.0, 15000.0, None, None).unwrap();
    s.step();
    assert_eq!(s.d.ratio(2).unwrap(), Some(0.24));
    assert_eq!(s.d.ratio(1).unwrap(), None, "time-based");
    assert!(s.d.done(2).unwrap(), "a steady gear is done");
    s.run_to(0.3);
    assert!(close(s.pos(2), 0.24 * s.pos(1), 1e-9));
    // Ramp to 3600:12000 over 500 units of web: (0.24 + 0.3)/2 · 500 = 135.
    s.d.gear_at(2, 3600.0, 12000.0, Some(500.0), None).unwrap();
    let (w0, k0) = (s.pos(1), s.pos(2));
    s.run_to(0.65);
    assert!(!s.d.done(2).unwrap());
    s.run_to(1.0);
    let end = s.done_times(2, Layer::Base)[1];
    assert!(close(end, 0.3 + 0.5, 1e-9), "{end}");
    let ramp_end =
        s.at(|e| matches!(e, DspEvent::SegmentDone { axis: 2, time, .. } if *time == end));
    assert!(close(ramp_end[0] - w0, 500.0, 1e-9) && close(ramp_end[1] - k0, 135.0, 1e-9));
    assert_eq!(s.d.ratio(2).unwrap(), Some(0.3));
    assert!(close(
        s.pos(2) - k0,
        135.0 + 0.3 * (s.pos(1) - w0 - 500.0),
        1e-9
    ));
    // From time-based motion the ramp starts at the ratio the axis moves at: 0.36 → 0.24.
    s.d.move_at(3, 6.0, 0.0).unwrap(); // 360 units/s against 1000 units/s of web
    s.run_to(1.1);
    s.d.gear_at(3, 3600.0, 15000.0, Some(1000.0), None).unwrap();
    let (w0, k0) = (s.pos(1), s.pos(3));
    s.run_to(2.5);
    assert!(close(
        s.pos(3) - k0,
        0.30 * 1000.0 + 0.24 * (s.pos(1) - w0 - 1000.0),
        1e-9
    ));
    // Refused: no pacer, a zero divisor, a negative distance, NaN.
    assert!(s
        .d
        .gear_at(1, 1.0, 1.0, None, None)
        .unwrap_err()
        .0
        .contains("pacer"));
    assert!(s.d.gear_at(2, 1.0, 0.0, None, None).is_err());
    assert!(s.d.gear_at(2, 1.0, 1.0, Some(-1.0), None).is_err());
    assert!(s.d.gear_at(2, f64::NAN, 1.0, None, None).is_err());
    assert!(s.d.move_at(9, 1.0, 1.0).is_err());
}

#[test]
fn gear_after_an_input_starts_at_the_input_instant() {
    let mut s = web_knife(100.0, 0.01);
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.d.gear_at(2, 1.0, 10.0, None, None).unwrap();
    s.run_to(0.1);
    s.d.gear_at(2, 1.0, 2.0, None, Some(After::Input(7)))
        .unwrap();
    s.run_to(0.2);
    assert!(!s.d.done(2).unwrap(), "waiting for its input");
    assert_eq!(s.d.ratio(2).unwrap(), Some(0.1));
    assert!(s.d.trigger(7, 0.1).is_err(), "in the past");
    s.d.trigger(7, 0.2037).unwrap();
    s.step();
    assert!(s.d.done(2).unwrap());
    assert_eq!(s.d.ratio(2).unwrap(), Some(0.5));
    let w = |t: f64| s.d.position_at(1, t).unwrap();
    let k = |t: f64| s.d.position_at(2, t).unwrap();
    assert!(close(k(0.2037), 0.1 * w(0.2037), 1e-9));
    assert!(close(
        k(0.21),
        0.1 * w(0.2037) + 0.5 * (w(0.21) - w(0.2037)),
        1e-9
    ));
}

/// Follower 2 gets GEAR FOR dist IN pacer_dist on top of 0.24; follower 3 is its twin without it.
/// The pacer runs `profile`: (rpm, ramp ms, then hold s) each, holding the last speed. Returns
/// the largest |difference| seen (it must never exceed |dist|) after checking the end.
fn superimposed(profile: &[(f64, f64, f64)], dist: f64, pacer_dist: f64, dt: f64) -> f64 {
    let mut s = web_knife(100.0, dt);
    s.d.gear_at(2, 3600.0, 15000.0, None, None).unwrap();
    s.d.gear_at(3, 3600.0, 15000.0, None, None).unwrap();
    s.d.gear_for(2, dist, pacer_dist).unwrap();
    let mut next = profile.iter();
    let mut ready = 0.0;
    let mut most: f64 = 0.0;
    while !s.d.done(2).unwrap() {
        assert!(s.d.time() < 600.0, "GEAR FOR never completed");
        if s.d.done(1).unwrap() && s.d.time() >= ready {
            if let Some(&(rpm, ms, hold)) = next.next() {
                assert_eq!(s.d.move_at(1, rpm, ms), Ok(Queued::Accepted));
                ready = s.d.time() + ms / 1000.0 + hold;
            }
        }
        s.step();
        let diff = s.pos(2) - s.pos(3);
        assert!(
            diff.abs() <= dist.abs() + 1e-9 && diff * dist >= -1e-9,
            "{diff} outside 0..{dist}"
        );
        most = most.max(diff.abs());
    }
    let layer = Layer::Superimposed;
    let start =
        s.at(|e| matches!(e, DspEvent::SegmentStarted { axis: 2, layer: l, .. } if *l == layer));
    let end = s.at(|e| matches!(e, DspEvent::SegmentDone { axis: 2, layer: l, .. } if *l == layer));
    assert!(
        close(end[0] - start[0], pacer_dist, 1e-9),
        "{end:?} {start:?}"
    );
    for _ in 0..3 {
        s.step();
        assert!(
            (s.pos(2) - s.pos(3) - dist).abs() < 1e-9,
            "{} vs {dist}",
            s.pos(2) - s.pos(3)
        );
    }
    most
}

#[test]
fn gear_for_ends_exactly_dist_ahead_at_constant_pacer_speed() {
    superimposed(&[(600.0, 0.0, 0.0)], 77.7, 500.0, 0.001);
    superimposed(&[(600.0, 0.0, 0.0)], -33.3, 123.4, 0.0007);
}

#[test]
fn gear_for_ends_exactly_dist_ahead_with_the_pacer_speeding_up_and_slowing_down() {
    let profile = [
        (600.0, 0.0, 0.1),
        (1500.0, 37.0, 0.0),
        (200.0, 123.0, 0.05),
        (900.0, 50.0, 0.0),
    ];
    superimposed(&profile, 77.7, 500.0, 0.001);
}

#[test]
fn gear_for_holds_while_the_pacer_stops_and_finishes_after_it_restarts() {
    let mut s = web_knife(100.0, 0.001);
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.d.gear_at(2, 3600.0, 15000.0, None, None).unwrap();
    s.d.gear_at(3, 3600.0, 15000.0, None, None).unwrap();
    s.d.gear_for(2, 50.0, 400.0).unwrap();
    s.run_to(0.2);
    s.d.move_at(1, 0.0, 50.0).unwrap();
    s.run_to(0.5);
    let held = s.pos(2) - s.pos(3);
    assert!(held > 0.0 && held < 50.0, "{held}");
    s.run_to(0.9);
    assert_eq!(
        s.pos(2) - s.pos(3),
        held,
        "the pacer stands still: so does the FOR"
    );
    assert!(!s.d.done(2).unwrap());
    s.d.move_at(1, 600.0, 100.0).unwrap();
    s.run_to(1.5);
    assert!(s.d.done(2).unwrap());
    assert!((s.pos(2) - s.pos(3) - 50.0).abs() < 1e-9);
}

#[test]
fn gear_for_in_zero_is_a_reported_step_and_negative_pacer_distance_runs_backwards() {
    let mut s = web_knife(100.0, 0.001);
    s.d.move_at(1, -600.0, 0.0).unwrap();
    s.d.gear_at(2, 1.0, 4.0, None, None).unwrap();
    s.d.gear_at(3, 1.0, 4.0, None, None).unwrap();
    s.step();
    assert_eq!(s.d.gear_for(2, 12.5, 0.0), Ok(Queued::AcceptedAsStep));
    let e = s.step();
    assert!(
        e.contains(&DspEvent::Stepped {
            axis: 2,
            dist: 12.5,
            time: 0.001
        }),
        "{e:?}"
    );
    assert_eq!(s.pos(2) - s.pos(3), 12.5);
    assert!(s.d.done(2).unwrap());
    assert_eq!(s.d.gear_for(2, 10.0, -200.0), Ok(Queued::Accepted));
    s.run_to(0.1);
    let mid = s.pos(2) - s.pos(3) - 12.5;
    assert!(mid > 0.0 && mid < 10.0, "{mid}");
    s.run_to(0.3);
    assert!(s.d.done(2).unwrap());
    assert!((s.pos(2) - s.pos(3) - 22.5).abs() < 1e-9);
    assert!(s.d.gear_for(1, 1.0, 1.0).is_err(), "no pacer");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn gear_for_ends_exactly_dist_ahead_whatever_the_pacer_does(
        middle in proptest::collection::vec(
            (prop_oneof![Just(0.0), -400.0f64..2000.0], 0.0f64..400.0, 0.0f64..0.3),
            0..4,
        ),
        last in (50.0f64..1500.0, 0.0f64..300.0),
        dist in -500.0f64..500.0,
        pacer_dist in 5.0f64..800.0,
        dt in 0.0005f64..0.02,
    ) {
        let mut profile = middle;
        profile.push((last.0, last.1, 0.0));
        let most = superimposed(&profile, dist, pacer_dist, dt);
        prop_assert!(most <= dist.abs() + 1e-9);
    }
}

#[test]
fn the_queue_holds_queue_depth_segments_of_both_layers_and_done_follows_it() {
    let mut s = web_knife(100.0, 0.001);
    assert!(s.d.done(2).unwrap(), "standing still is done");
    assert_eq!(DEFAULT_QUEUE_DEPTH, 4);
    s.d.gear_at(2, 1.0, 1.0, Some(100.0), None).unwrap();
    s.d.gear_at(2, 1.0, 2.0, Some(100.0), None).unwrap();
    s.d.gear_for(2, 1.0, 10.0).unwrap();
    assert_eq!(s.d.gear_for(2, 1.0, 10.0), Ok(Queued::Accepted));
    assert_eq!(s.d.gear_for(2, 1.0, 10.0), Ok(Queued::Full));
    assert_eq!(s.d.move_at(2, 1.0, 10.0), Ok(Queued::Full));
    assert_eq!(s.d.queued(2), Ok(4));
    assert!(!s.d.done(2).unwrap());
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.run_to(0.1); // 100 units of web: the first ramp is done, the FORs too
    assert_eq!(s.d.queued(2), Ok(1));
    assert_eq!(s.d.gear_for(2, 1.0, 10.0), Ok(Queued::Accepted));
    s.run_to(0.3);
    assert!(s.d.done(2).unwrap());
    assert_eq!(s.d.ratio(2).unwrap(), Some(0.5));
}

/// Web 1 at 1000 units/s² from rest (MOVE AT 600 IN 1000, 100 units/rev), knife 2 geared
/// 3600:15000 from position 0, marks on the web seen by ASEN of card 0.
fn marked(marks: Vec<f64>, width: f64) -> Sim {
    let mut s = web_knife(100.0, 0.001);
    s.d.gear_at(2, 3600.0, 15000.0, None, None).unwrap();
    s.d.move_at(1, 600.0, 1000.0).unwrap();
    s.d.add_marks(1, 0, Sensor::Asen, marks, width).unwrap();
    s
}

#[test]
fn both_axes_of_a_card_latch_the_same_instant_inside_the_update() {
    let mut s = marked(vec![123.4567, 200.0, 300.0], 5.0);
    s.run_to(0.7);
    let l = s.latches();
    assert_eq!(l.len(), 2, "first edge only until cleared: {l:?}");
    let t = (2.0 * 123.4567 / 1000.0_f64).sqrt();
    let (web, knife) = (l[0], l[1]);
    assert_eq!((web.0, web.1, knife.0), (1, Sensor::Asen, 2));
    assert!(
        close(web.2, t, 1e-12) && web.2 == knife.2,
        "{web:?} {knife:?} vs {t}"
    );
    assert!(close(web.3, 123.4567, 1e-9));
    assert!(close(knife.3, 0.24 * web.3, 1e-9));
    assert_eq!(s.d.latched_position(2, Sensor::Asen).unwrap(), knife.3);
    assert!(s.d.latched(1, Sensor::Asen).unwrap() && !s.d.latched(1, Sensor::Bsen).unwrap());
    s.d.clear_latch(1, Sensor::Asen).unwrap();
    s.d.clear_latch(2, Sensor::Asen).unwrap();
    s.d.set_sens_mode(1, "rfrnn").unwrap();
    s.d.set_sens_mode(2, "RFRNN").unwrap();
    assert_eq!(s.d.sens_mode(1).unwrap(), "RFRNN");
    s.run_to(0.9);
    // The falling edge of the next mark: its end, 305.
    let l = s.latches();
    assert_eq!(l.len(), 4);
    assert!(close(l[2].3, 305.0, 1e-9) && close(l[2].2, (2.0 * 305.0 / 1000.0_f64).sqrt(), 1e-12));
    // A direct card edge at a time inside the update, on axis 2 re-armed only.
    s.d.clear_latch(2, Sensor::Asen).unwrap();
    let t = s.d.time() - 0.0003;
    let e = s.d.card_edge(0, Sensor::Asen, false, t).unwrap();
    let expected = s.d.position_at(2, t).unwrap();
    assert!(matches!(e[..], [DspEvent::Latched { axis: 2, position, .. }] if position == expected));
    assert!(s
        .d
        .card_edge(0, Sensor::Asen, false, s.d.time() + 1.0)
        .is_err());
    assert!(s.d.card_edge(5, Sensor::Asen, false, t).is_err());
}

#[test]
fn marks_crossed_backwards_rise_at_their_end() {
    let mut s = web_knife(100.0, 0.01);
    s.d.move_at(1, -600.0, 0.0).unwrap();
    s.d.add_marks(1, 0, Sensor::Bsen, vec![-520.0, -310.0], 7.0)
        .unwrap();
    s.run_to(0.6);
    // Both axes of card 0 latch (the knife stands at 0); the web enters the mark at its end.
    let l = s.latches();
    assert_eq!(l.len(), 2, "{l:?}");
    assert!(
        close(l[0].3, -303.0, 1e-9) && close(l[0].2, 0.303, 1e-12),
        "{l:?}"
    );
    assert_eq!((l[1].0, l[1].2, l[1].3), (2, l[0].2, 0.0));
}

#[test]
fn pls_gate_blinds_marks_outside_the_window_and_pos_mod_reports_modulo() {
    // Knife = 0.24·web; PLS1 on for knife in [2000, 2400) of 3600 ⇔ web in [8333.3, 10000).
    let mut s = marked(vec![5000.0, 9000.0, 24000.0], 10.0);
    s.d.set_pls_mod(2, 3600.0).unwrap();
    s.d.set_pls_low(2, 1, 2000.0).unwrap();
    s.d.set_pls_high(2, 1, 2400.0).unwrap();
    s.d.set_sens_mode(2, "RRRGN").unwrap();
    s.d.set_pos_mod(2, 3600.0).unwrap();
    s.d.move_at(1, 6000.0, 0.0).unwrap(); // then 10000 units/s
    s.run_to(3.0);
    let blinded: Vec<f64> = s
        .events
        .iter()
        .filter_map(|e| match *e {
            DspEvent::EdgeBlinded {
                card: 0,
                which: Sensor::Asen,
                time,
            } => Some(time),
            _ => None,
        })
        .collect();
    assert_eq!(
        blinded.len(),
        1,
        "the rising edge at 5000 only: {blinded:?}"
    );
    let l = s.latches();
    assert_eq!(l.len(), 2, "{l:?}");
    assert!(close(l[0].3, 9000.0, 1e-9) && close(l[1].3, 2160.0, 1e-9));
    let knife = s.pos(2);
    let reported = s.d.reported_position(2).unwrap();
    assert!(knife > 3600.0 && (0.0..3600.0).contains(&reported));
    assert!(close(reported, knife.rem_euclid(3600.0), 1e-9));
    // Wrap-around window: on from 3400 through 3600 to 200.
    s.d.set_pls_low(2, 1, 3400.0).unwrap();
    s.d.set_pls_high(2, 1, 200.0).unwrap();
    let t = s.d.time();
    let inside = !(200.0..3400.0).contains(&reported);
    assert_eq!(s.d.pls_active(2, 1, t).unwrap(), inside);
    assert!(!s.d.pls_active(2, 2, t).unwrap(), "unset: never on");
    s.d.set_pls_low(2, 3, 100.0).unwrap();
    s.d.set_pls_high(2, 3, 100.0).unwrap();
    assert!(!s.d.pls_active(2, 3, t).unwrap(), "LOW = HIGH: never on");
    assert!(s.d.set_pls_low(2, 4, 1.0).is_err() && s.d.set_pos_mod(2, -1.0).is_err());
}

#[test]
fn the_wrap_around_window_latches_across_the_cycle_end_only() {
    // Knife at the marks: 3480 (on), 3720 → 120 (on), 3960 → 360 (blind).
    let mut s = marked(vec![14500.0, 15500.0, 16500.0], 10.0);
    s.d.set_pls_mod(2, 3600.0).unwrap();
    s.d.set_pls_low(2, 1, 3400.0).unwrap();
    s.d.set_pls_high(2, 1, 200.0).unwrap();
    s.d.set_sens_mode(2, "RRRGN").unwrap();
    s.d.set_pos_mod(2, 3600.0).unwrap();
    s.d.move_at(1, 6000.0, 0.0).unwrap();
    let mut seen = Vec::new();
    while s.d.time() < 2.5 {
        for e in s.step() {
            if let DspEvent::Latched {
                axis: 2, position, ..
            } = e
            {
                seen.push(position);
                s.d.clear_latch(2, Sensor::Asen).unwrap();
            }
        }
    }
    assert_eq!(seen.len(), 2, "{seen:?}");
    assert!(
        close(seen[0], 3480.0, 1e-9) && close(seen[1], 120.0, 1e-9),
        "{seen:?}"
    );
}

#[test]
fn a_geared_follower_crossing_is_found_on_a_pacer_that_turns_back_inside_the_update() {
    let mut s = web_knife(100.0, 0.2);
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.d.gear_at(2, 1.0, 2.0, None, None).unwrap();
    s.step(); // web at 200, knife at 100
              // Up 25 more, then down: a peak of 225 at 0.25 s, 100 at the end of the update.
    s.d.move_at(1, -600.0, 100.0).unwrap();
    s.step();
    let (t0, t1) = (s.d.previous_time(), s.d.time());
    assert!(close(s.pos(1), 100.0, 1e-9), "{}", s.pos(1));
    let up = s.d.time_at_position(2, 110.0, t0, t1).unwrap().unwrap();
    assert!(
        close(s.d.position_at(1, up).unwrap(), 220.0, 1e-9) && up < 0.25,
        "{up}"
    );
    let web = s.d.time_at_position(1, 220.0, t0, t1).unwrap().unwrap();
    assert!(close(up, web, 1e-12), "{up} {web}");
    // From above: the first time at or below 80 is on the way down.
    let down = s.d.time_at_position(2, 80.0, 0.25, t1).unwrap().unwrap();
    assert!(
        close(s.d.position_at(2, down).unwrap(), 80.0, 1e-9) && down > 0.3,
        "{down}"
    );
    assert_eq!(s.d.time_at_position(2, 200.0, t0, t1).unwrap(), None);
}

#[test]
fn bad_configurations_and_inputs_are_refused_with_a_message() {
    let c = |n: u32, p: Option<u32>| DspAxisConfig::new(n, p, 1.0);
    for (configs, says) in [
        (vec![c(1, None), c(1, None)], "twice"),
        (vec![c(0, None)], "numbered 1 to 16"),
        (vec![c(17, None)], "numbered 1 to 16"),
        (vec![c(1, Some(1))], "own pacer"),
        (vec![c(1, Some(3))], "not a configured"),
        (vec![c(1, Some(2)), c(2, Some(3)), c(3, Some(1))], "cycle"),
        (vec![DspAxisConfig::new(1, None, 0.0)], "above 0"),
        (vec![DspAxisConfig::new(1, None, f64::NAN)], "above 0"),
        (
            vec![DspAxisConfig {
                queue_depth: 0,
                ..c(1, None)
            }],
            "queue depth",
        ),
    ] {
        let e = DspAxes::new(&configs).expect_err(says);
        assert!(e.0.contains(says), "{e}");
    }
    let mut s = web_knife(100.0, 0.01);
    for (mode, says) in [
        ("RRRN", "exactly 5 characters"),
        ("RRXNN", "character 3 is 'X'"),
        ("RRRRN", "character 4 is 'R', it must be G"),
        ("RRRNÑ", "character 5 is 'Ñ'"),
    ] {
        let e = s.d.set_sens_mode(1, mode).unwrap_err();
        assert!(e.0.contains(says), "{e}");
    }
    assert_eq!(
        s.d.sens_mode(1).unwrap(),
        "RRRNN",
        "unchanged by a refused string"
    );
    s.step();
    assert!(s.d.advance(0.005).is_err() && s.d.advance(f64::NAN).is_err());
    assert!(s.d.position_at(1, 0.5).is_err());
    assert!(s.d.move_at(1, 1.0, -1.0).is_err());
    let overlapping = s.d.add_marks(1, 0, Sensor::Asen, vec![0.0, 5.0], 10.0);
    assert!(overlapping.unwrap_err().0.contains("not touch"));
    assert!(s.d.add_marks(1, 0, Sensor::Asen, vec![0.0], 0.0).is_err());
}

#[test]
fn a_step_at_the_start_of_an_update_crosses_marks_at_that_instant() {
    let mut s = web_knife(100.0, 0.01);
    s.d.gear_at(2, 1.0, 1.0, None, None).unwrap();
    s.d.add_marks(2, 0, Sensor::Asen, vec![5.0], 100.0).unwrap();
    s.step();
    s.d.gear_for(2, 12.5, 0.0).unwrap();
    s.step();
    // The knife jumped from 0 to 12.5 at 0.01 s, into the mark: a rising edge then.
    let l = s.latches();
    assert_eq!(l.len(), 2, "{l:?}");
    assert_eq!((l[1].0, l[1].2, l[1].3), (2, 0.01, 12.5));
}

#[test]
fn a_stop_ramps_the_web_to_rest_and_the_geared_knife_with_it() {
    // Web at 600 RPM = 1000 units/s, knife geared at 0.24 with a queued ratio change and a
    // queued correction: the stop drops what is queued, ramps the web down at 2000 units/s²
    // (0.5 s, 250 units) and the knife follows it, still in step.
    let mut s = web_knife(100.0, 0.0007);
    s.d.move_at(1, 600.0, 0.0).unwrap();
    s.d.gear_at(2, 3600.0, 15000.0, None, None).unwrap();
    s.run_to(0.3);
    s.d.gear_at(2, 3600.0, 12000.0, Some(5000.0), Some(After::Input(1)))
        .unwrap();
    s.d.move_at(3, 6.0, 0.0).unwrap();
    let (t0, w0, k0) = (s.d.time(), s.pos(1), s.pos(2));
    s.d.stop(1, 2000.0).unwrap();
    s.d.stop(2, 2000.0).unwrap();
    s.d.stop(3, 100.0).unwrap();
    assert!(s.d.stop(1, 0.0).is_err());
    s.run_to(t0 + 0.25);
    let tau = s.d.time() - t0;
    assert!(close(
        s.pos(1),
        w0 + 1000.0 * tau - 1000.0 * tau * tau,
        1e-9
    ));
    s.run_to(t0 + 1.0);
    assert_eq!(s.d.velocity(1).unwrap(), 0.0);
    assert!(close(s.pos(1) - w0, 250.0, 1e-9), "{}", s.pos(1) - w0);
    assert!(
        close(s.pos(2) - k0, 0.24 * 250.0, 1e-9),
        "{}",
        s.pos(2) - k0
    );
    assert_eq!(
        s.d.ratio(2).unwrap(),
        Some(0.24),
        "the queued ratio change is dropped"
    );
    assert_eq!(s.d.motion_state(1).unwrap(), None);
    assert_eq!(s.d.motion_state(2).unwrap(), None);
    // Axis 3 had a MOVE queued, not yet started at the stop: it never moved.
    assert_eq!(s.pos(3), 0.0);
}
