//! Delta3 kinematics (spec: pick-and-place.md conventions): round trips, the 120° and mirror
//! symmetries of the robot, and unreachable points as named errors, never NaN.

use pacer::devices::pickplace::kinematics::delta3::Delta3;
use pacer::devices::pickplace::kinematics::KinematicsError;
use proptest::prelude::*;

/// A common industrial size: base side 457.3, effector side 115, upper arm 112, forearm 232 mm.
fn robot() -> Delta3 {
    Delta3::new(457.3, 115.0, 112.0, 232.0).expect("a valid robot")
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() < tol)
}

#[test]
fn the_home_pose_is_below_the_base_on_the_axis() {
    let p = robot().forward([0.0; 3]).expect("home");
    assert!(p[0].abs() < 1e-9 && p[1].abs() < 1e-9, "{p:?}");
    assert!(p[2] < 0.0, "{p:?}");
    let back = robot().inverse(p).expect("reachable");
    assert!(close(back, [0.0; 3], 1e-9), "{back:?}");
}

#[test]
fn arm_1_lies_along_minus_y_and_lowering_it_pushes_the_tool_away_from_it() {
    // Lowering arm 1 alone swings its elbow in and down, pushing the effector toward +Y.
    let home = robot().forward([0.0; 3]).expect("home");
    let p = robot().forward([20.0, 0.0, 0.0]).expect("pose");
    assert!(p[1] > home[1] + 1.0, "{p:?} vs {home:?}");
    assert!(p[0].abs() < 1e-9, "arm 1 moves in the YZ plane: {p:?}");
    assert!(p[2] < home[2], "{p:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn forward_then_inverse_gives_the_angles_back(
        t1 in -20.0f64..80.0, t2 in -20.0f64..80.0, t3 in -20.0f64..80.0,
    ) {
        // Over the working range (arms from 20° up to 80° down, the effector well below the
        // base) the inverse gives the elbows-out branch the robot works in.
        let r = robot();
        if let Some(p) = r.forward([t1, t2, t3]).ok().filter(|p| p[2] < -150.0) {
            let back = r.inverse(p).expect("a pose the robot reached is reachable");
            prop_assert!(close(back, [t1, t2, t3], 1e-7), "{:?} → {:?} → {:?}", [t1, t2, t3], p, back);
        }
    }

    #[test]
    fn inverse_then_forward_gives_the_point_back(
        x in -150.0f64..150.0, y in -150.0f64..150.0, z in -350.0f64..-150.0,
    ) {
        let r = robot();
        if let Ok(t) = r.inverse([x, y, z]) {
            let p = r.forward(t).expect("angles from the inverse are a pose");
            prop_assert!(close(p, [x, y, z], 1e-7), "{:?} → {:?} → {:?}", [x, y, z], t, p);
        }
    }

    #[test]
    fn rotating_the_point_by_120_degrees_rotates_the_arms(
        x in -150.0f64..150.0, y in -150.0f64..150.0, z in -350.0f64..-150.0,
    ) {
        let r = robot();
        let (s, c) = (120f64.to_radians().sin(), 120f64.to_radians().cos());
        let rotated = [x * c - y * s, x * s + y * c, z];
        match (r.inverse([x, y, z]), r.inverse(rotated)) {
            (Ok(t), Ok(u)) => prop_assert!(close(u, [t[2], t[0], t[1]], 1e-7), "{t:?} vs {u:?}"),
            (Err(_), Err(_)) => {}
            (a, b) => prop_assert!(false, "symmetric points differ in reach: {a:?} / {b:?}"),
        }
    }

    #[test]
    fn mirroring_x_swaps_arms_2_and_3(
        x in -150.0f64..150.0, y in -150.0f64..150.0, z in -350.0f64..-150.0,
    ) {
        let r = robot();
        match (r.inverse([x, y, z]), r.inverse([-x, y, z])) {
            (Ok(t), Ok(u)) => prop_assert!(close(u, [t[0], t[2], t[1]], 1e-7), "{t:?} vs {u:?}"),
            (Err(_), Err(_)) => {}
            (a, b) => prop_assert!(false, "mirror points differ in reach: {a:?} / {b:?}"),
        }
    }

    #[test]
    fn any_point_is_reached_or_named_never_nan(
        x in -3000.0f64..3000.0, y in -3000.0f64..3000.0, z in -3000.0f64..3000.0,
    ) {
        match robot().inverse([x, y, z]) {
            Ok(t) => prop_assert!(t.iter().all(|a| a.is_finite()), "{t:?}"),
            Err(KinematicsError::Unreachable { x: ex, y: ey, z: ez }) => {
                prop_assert_eq!([ex, ey, ez], [x, y, z]);
            }
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
    }
}

#[test]
fn unreachable_points_are_named() {
    let r = robot();
    for p in [
        [0.0, 0.0, 10.0],
        [0.0, 0.0, 0.0],
        [2000.0, 0.0, -200.0],
        [0.0, 0.0, -5000.0],
        [f64::NAN, 0.0, -200.0],
        [f64::INFINITY, 0.0, -200.0],
    ] {
        let e = r.inverse(p).expect_err("out of reach");
        assert!(matches!(e, KinematicsError::Unreachable { .. }), "{e:?}");
        let text = e.to_string();
        assert!(text.contains("out of the robot's reach"), "{text}");
    }
    let text = r
        .inverse([2000.0, 0.0, -200.0])
        .expect_err("far")
        .to_string();
    assert!(text.contains("(2000.000, 0.000, -200.000)"), "{text}");
    assert!(matches!(
        r.forward([f64::NAN, 0.0, 0.0]),
        Err(KinematicsError::NoPose(..))
    ));
}

#[test]
fn dimensions_that_make_no_robot_are_refused() {
    for (f, e, rf, re) in [
        (-1.0, 115.0, 112.0, 232.0),
        (457.3, 0.0, 112.0, 232.0),
        (457.3, 115.0, f64::NAN, 232.0),
        (457.3, 115.0, 112.0, 10.0),
    ] {
        let err = Delta3::new(f, e, rf, re).expect_err("no robot");
        assert!(matches!(err, KinematicsError::Geometry(_)), "{err:?}");
    }
}
