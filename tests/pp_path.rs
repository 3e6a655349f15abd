//! Path geometry of the Track Pick & Place module: polylines with tangent blends, the
//! half-ellipse mode, and the arc-length parametrisation.

use pacer::devices::pickplace::path::*;
use std::f64::consts::PI;

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: P3, k: f64) -> P3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}
fn dist(a: P3, b: P3) -> f64 {
    norm(sub(a, b))
}
fn unit(a: P3) -> P3 {
    scale(a, 1.0 / norm(a))
}

#[track_caller]
fn close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (diff {:e})", a - b);
}
#[track_caller]
fn close3(a: P3, b: P3, tol: f64) {
    assert!(dist(a, b) <= tol, "{a:?} vs {b:?} (dist {:e})", dist(a, b));
}

/// Half-ellipse arc length by the AGM (Gauss) formula: exact to rounding, independent of the
/// quadrature under test.
fn half_ellipse_len(a: f64, b: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    let (mut an, mut bn) = (a, b);
    let mut s = 0.5 * (a * a - b * b);
    let mut p = 0.5;
    for _ in 0..60 {
        let cn = 0.5 * (an - bn);
        let (na, nb) = (0.5 * (an + bn), (an * bn).sqrt());
        an = na;
        bn = nb;
        p *= 2.0;
        s += p * cn * cn;
        if cn == 0.0 {
            break;
        }
    }
    PI / an * (a * a - s)
}

/// Marks must be non-decreasing and inside the path.
#[track_caller]
fn marks_in_order(p: &Path) {
    let m = p.marks();
    for w in m.windows(2) {
        assert!(w[0] <= w[1], "marks out of order: {m:?}");
    }
    for &x in m {
        assert!((0.0..=p.length()).contains(&x), "mark {x} outside path");
    }
}

/// Joins between pieces: positions meet and (except at reported corners) tangents agree.
#[track_caller]
fn joins_are_smooth(p: &Path) {
    let pcs = p.pieces();
    for i in 1..pcs.len() {
        let s = p.piece_starts()[i];
        close3(pcs[i - 1].end(), pcs[i].start(), 1e-9);
        close3(p.point(s - 1e-12), p.point(s), 1e-9);
        if p.corners().contains(&s) {
            continue;
        }
        let (t0, t1) = (pcs[i - 1].end_tangent(), pcs[i].start_tangent());
        close3(t0, t1, 1e-9);
        // One-sided second-order finite differences of point() on both sides.
        let h = 1e-5;
        let left = scale(
            add(
                sub(scale(p.point(s), 3.0), scale(p.point(s - h), 4.0)),
                p.point(s - 2.0 * h),
            ),
            1.0 / (2.0 * h),
        );
        let right = scale(
            add(
                sub(scale(p.point(s + h), 4.0), scale(p.point(s), 3.0)),
                scale(p.point(s + 2.0 * h), -1.0),
            ),
            1.0 / (2.0 * h),
        );
        close3(unit(left), unit(right), 1e-6);
        close3(unit(left), t1, 1e-6);
    }
}

/// Unit speed and derivative consistency, sampled densely, away from corners (kinks) and,
/// for the derivative comparisons, away from piece joins (curvature may jump there, which
/// makes central differences straddling a join only first-order accurate). The step shrinks
/// with the curvature so the finite differences' own truncation error stays below 1e-8.
#[track_caller]
fn check_parametrisation(p: &Path, samples: usize) {
    let len = p.length();
    let h0 = 1e-4;
    let near = |s: f64, list: &[f64], d: f64| list.iter().any(|&c| (s - c).abs() < d);
    for i in 0..=samples {
        let s = len * i as f64 / samples as f64;
        let d = p.derivatives(s);
        for v in d.iter().flatten() {
            assert!(v.is_finite(), "non-finite derivative at {s}");
        }
        close3(d[0], p.point(s), 1e-12);
        close(norm(d[1]), 1.0, 1e-12);
        // The curvature vector is perpendicular to the tangent.
        close(dot(d[1], d[2]), 0.0, 1e-9 * (1.0 + norm(d[2])));
        if s < 2.0 * h0 || s > len - 2.0 * h0 || near(s, p.corners(), 2.0 * h0) {
            continue;
        }
        let kmax = [s - h0, s, s + h0]
            .iter()
            .map(|&x| norm(p.derivatives(x)[2]))
            .fold(0.0, f64::max);
        let h = h0 / (1.0 + 10.0 * kmax);
        let fd = scale(sub(p.point(s + h), p.point(s - h)), 0.5 / h);
        close(norm(fd), 1.0, 1e-7);
        if near(s, p.piece_starts(), 2.0 * h0) {
            continue;
        }
        close3(fd, d[1], 1e-7);
        let (a, b) = (p.derivatives(s + h), p.derivatives(s - h));
        let k = norm(d[2]);
        let j = norm(d[3]);
        close3(scale(sub(a[1], b[1]), 0.5 / h), d[2], 1e-6 * (1.0 + k));
        close3(
            scale(sub(a[2], b[2]), 0.5 / h),
            d[3],
            1e-5 * (1.0 + j + k * k),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Lines and blends

#[test]
fn single_line_length_and_exact_endpoints() {
    let (a, b) = ([0.1, 0.2, 0.3], [3.1, 4.2, 0.3]);
    let p = blended(&[a, b], 5.0).unwrap();
    close(p.length(), 5.0, 1e-12);
    assert_eq!(p.point(0.0), a);
    assert_eq!(p.point(p.length()), b);
    assert_eq!(p.point(-1.0), a);
    assert_eq!(p.point(1e9), b);
    assert_eq!(p.point(f64::NAN), a);
    close3(p.point(2.5), [1.6, 2.2, 0.3], 1e-12);
    assert_eq!(p.pieces().len(), 1);
    assert!(p.marks().is_empty());
    let d = p.derivatives(1.0);
    close3(d[1], [0.6, 0.8, 0.0], 1e-15);
    assert_eq!(d[2], [0.0; 3]);
    assert_eq!(d[3], [0.0; 3]);
}

#[test]
fn polyline_with_sharp_corners() {
    let pts = [
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 10.0, 0.0],
        [20.0, 10.0, 5.0],
    ];
    let p = blended(&pts, 0.0).unwrap();
    let l3 = (125.0f64).sqrt();
    close(p.length(), 20.0 + l3, 1e-12);
    assert_eq!(p.marks(), &[10.0, 10.0, 20.0, 20.0]);
    assert_eq!(p.corners(), &[10.0, 20.0]);
    for (i, &m) in [0.0, 10.0, 20.0, 20.0 + l3].iter().enumerate() {
        close3(p.point(m), pts[i], 1e-12);
    }
    assert!(p.pieces().iter().all(|x| matches!(x, Piece::Line { .. })));
    check_parametrisation(&p, 500);
}

#[test]
fn right_angle_blend() {
    let p = blended(
        &[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0]],
        10.0,
    )
    .unwrap();
    assert_eq!(p.pieces().len(), 3);
    match p.pieces()[1] {
        Piece::Arc {
            center,
            radius,
            angle,
            ..
        } => {
            // Tangent points at 10 from the corner of a right angle: radius 10.
            close(radius, 10.0, 1e-12);
            close(angle, PI / 2.0, 1e-15);
            close3(center, [90.0, 10.0, 0.0], 1e-12);
        }
        ref other => panic!("expected an arc, got {other:?}"),
    }
    let m = p.marks();
    close(m[0], 90.0, 1e-12);
    close(m[1], 90.0 + 5.0 * PI, 1e-12);
    close3(p.point(m[0]), [90.0, 0.0, 0.0], 1e-12);
    close3(p.point(m[1]), [100.0, 10.0, 0.0], 1e-12);
    close(p.length(), 180.0 + 5.0 * PI, 1e-12);
    assert!(p.corners().is_empty());
    joins_are_smooth(&p);
    check_parametrisation(&p, 1000);
}

/// With deflection angle θ between the two segment directions, the tangent points at distance
/// r from the corner give a circle of radius r / tan(θ/2) (= r·tan(α/2), α = π − θ the interior
/// angle) sweeping θ: the tangent length of a circle of radius R for a turn θ is R·tan(θ/2).
#[test]
fn blend_radius_for_general_angles() {
    // A skew plane, so nothing relies on axis alignment.
    let ex = unit([1.0, 2.0, 2.0]);
    let ey = unit([2.0, 1.0, -2.0]);
    assert!(dot(ex, ey).abs() < 1e-15);
    let corner = [10.0, -20.0, 30.0];
    let r = 7.0;
    for deg in [0.5, 10.0, 30.0, 60.0, 90.0, 120.0, 150.0, 170.0, 179.0] {
        let th = f64::to_radians(deg);
        let d1 = ex;
        let d2 = add(scale(ex, th.cos()), scale(ey, th.sin()));
        let a = add(corner, scale(d1, -50.0));
        let b = add(corner, scale(d2, 60.0));
        let p = blended(&[a, corner, b], r).unwrap();
        let expect_radius = r / (th / 2.0).tan();
        let Piece::Arc {
            center,
            radius,
            angle,
            u,
            w,
        } = p.pieces()[1]
        else {
            panic!("no arc at {deg}°");
        };
        close(radius / expect_radius, 1.0, 1e-12);
        close(angle, th, 1e-12);
        close(norm(u), 1.0, 1e-12);
        close(norm(w), 1.0, 1e-12);
        close(dot(u, w), 0.0, 1e-12);
        let m = p.marks();
        // The blend starts and ends at distance r from the corner, on the segments.
        close3(p.point(m[0]), add(corner, scale(d1, -r)), 1e-9);
        close3(p.point(m[1]), add(corner, scale(d2, r)), 1e-9);
        close(m[1] - m[0], radius * angle, 1e-9);
        close(p.length(), 110.0 - 2.0 * r + radius * th, 1e-9);
        // Every arc point lies on the circle; its midpoint R(sec(θ/2) − 1) from the corner.
        for i in 0..=20 {
            let s = m[0] + (m[1] - m[0]) * i as f64 / 20.0;
            close(dist(p.point(s), center), radius, 1e-9 * (1.0 + radius));
        }
        let mid = p.point(0.5 * (m[0] + m[1]));
        close(
            dist(mid, corner),
            radius * (1.0 / (th / 2.0).cos() - 1.0),
            1e-9,
        );
        assert!(p.corners().is_empty(), "{deg}°");
        joins_are_smooth(&p);
        check_parametrisation(&p, 400);
    }
}

#[test]
fn blend_radius_is_clamped_to_half_the_shorter_segment() {
    let p = blended(
        &[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 100.0, 0.0]],
        20.0,
    )
    .unwrap();
    let m = p.marks();
    close3(p.point(m[0]), [5.0, 0.0, 0.0], 1e-12);
    close3(p.point(m[1]), [10.0, 5.0, 0.0], 1e-12);
    let Piece::Arc { radius, .. } = p.pieces()[1] else {
        panic!("no arc");
    };
    close(radius, 5.0, 1e-12);

    // Two neighbouring blends on a short middle segment meet in its middle, no overlap.
    let p = blended(
        &[
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [20.0, 10.0, 0.0],
        ],
        100.0,
    )
    .unwrap();
    let kinds: Vec<_> = p
        .pieces()
        .iter()
        .map(|x| matches!(x, Piece::Arc { .. }))
        .collect();
    assert_eq!(kinds, [false, true, true, false]);
    let m = p.marks();
    close(m[1], m[2], 1e-12);
    close3(p.point(m[1]), [10.0, 5.0, 0.0], 1e-9);
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 500);
}

#[test]
fn collinear_points_get_no_arc_and_duplicates_are_dropped() {
    let a = [0.0, 0.0, 0.0];
    let b = [10.0, 10.0, 10.0];
    let c = [20.0, 20.0, 20.0];
    let d = [20.0, 20.0, 40.0];
    let p = blended(&[a, a, b, b, c, d, d], 3.0).unwrap();
    // 7 input points: 5 interior ones, 2 marks each.
    assert_eq!(p.marks().len(), 10);
    let m = p.marks();
    assert_eq!(&m[0..2], &[0.0, 0.0]); // the duplicate of the start
    let lb = 300f64.sqrt();
    close(m[2], lb, 1e-12); // b: collinear, no blend
    assert_eq!(m[2], m[3]);
    assert_eq!(&m[2..4], &m[4..6]); // duplicate of b
    assert!(m[7] > m[6]); // c: a real corner
    close(m[8], p.length(), 0.0); // duplicate of the end
    assert_eq!(
        p.pieces()
            .iter()
            .filter(|x| matches!(x, Piece::Arc { .. }))
            .count(),
        1
    );
    assert_eq!(p.end_point(), d);
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 500);
}

#[test]
fn reversal_stays_a_corner() {
    let p = blended(&[[0.0, 0.0, 0.0], [0.0, 0.0, 50.0], [0.0, 0.0, 10.0]], 5.0).unwrap();
    close(p.length(), 90.0, 1e-12);
    assert_eq!(p.corners(), &[50.0]);
    assert_eq!(p.marks(), &[50.0, 50.0]);
    check_parametrisation(&p, 300);
}

#[test]
fn typical_pick_place_polyline() {
    let p = blended(
        &[
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 50.0],
            [300.0, 0.0, 50.0],
            [300.0, 0.0, 0.0],
        ],
        20.0,
    )
    .unwrap();
    // Each right-angle blend replaces 2·20 of corner by a quarter circle of radius 20.
    let q = PI / 2.0 * 20.0;
    close(p.length(), 400.0 - 2.0 * (40.0 - q), 1e-9);
    close(p.length(), 320.0 + 20.0 * PI, 1e-9);
    let m = p.marks();
    let expect = [30.0, 30.0 + q, 30.0 + q + 260.0, 30.0 + 2.0 * q + 260.0];
    for (x, e) in m.iter().zip(expect) {
        close(*x, e, 1e-9);
    }
    close3(p.point(m[0]), [0.0, 0.0, 30.0], 1e-12);
    close3(p.point(m[1]), [20.0, 0.0, 50.0], 1e-12);
    close3(p.point(m[2]), [280.0, 0.0, 50.0], 1e-9);
    close3(p.point(m[3]), [300.0, 0.0, 30.0], 1e-9);
    assert_eq!(p.point(p.length()), [300.0, 0.0, 0.0]);
    assert!(p.corners().is_empty());
    joins_are_smooth(&p);
    check_parametrisation(&p, 2000);
}

#[test]
fn random_3d_polylines_are_unit_speed_and_smooth() {
    // A small deterministic generator: no dependency on rand for a geometry test.
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0
    };
    for case in 0..20 {
        let pts: Vec<P3> = (0..6).map(|_| [next(), next(), next()]).collect();
        let r = [0.0, 1.0, 15.0, 1e3][case % 4];
        let p = blended(&pts, r).unwrap();
        assert_eq!(p.marks().len(), 8);
        marks_in_order(&p);
        joins_are_smooth(&p);
        check_parametrisation(&p, 600);
        if r > 0.0 {
            assert!(p.corners().is_empty());
        } else {
            assert_eq!(p.corners().len(), 4);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Elliptical mode

#[test]
fn ellipse_equal_heights() {
    let (start, ip1, ip2, end) = (
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 50.0],
        [300.0, 0.0, 50.0],
        [300.0, 0.0, 0.0],
    );
    let p = elliptical(start, ip1, ip2, end, 80.0, 0.0).unwrap();
    let lh = half_ellipse_len(150.0, 80.0);
    assert_eq!(p.pieces().len(), 3);
    let Piece::HalfEllipse {
        from, to, height, ..
    } = p.pieces()[1]
    else {
        panic!("no ellipse");
    };
    assert_eq!((from, to, height), (ip1, ip2, 80.0));
    close(p.pieces()[1].length(), lh, 1e-9);
    close(p.length(), 100.0 + lh, 1e-9);
    let m = p.marks();
    close(m[0], 50.0, 1e-12);
    close(m[1], 50.0 + lh, 1e-9);
    assert_eq!(p.point(0.0), start);
    assert_eq!(p.point(p.length()), end);
    close3(p.point(m[0]), ip1, 1e-12);
    close3(p.point(m[1]), ip2, 1e-9);
    // The apex is 80 above, in the middle; nothing is higher; the path is symmetric.
    let mid = 0.5 * p.length();
    close3(p.point(mid), [150.0, 0.0, 130.0], 1e-9);
    for i in 0..=1000 {
        let x = mid * i as f64 / 1000.0;
        let (l, r) = (p.point(mid - x), p.point(mid + x));
        assert!(l[2] <= 130.0 + 1e-9 && r[2] <= 130.0 + 1e-9);
        close3(l, [300.0 - r[0], r[1], r[2]], 1e-9);
        assert_eq!(l[1], 0.0);
    }
    // Curvature: a/b² at the ends (toward the middle), b/a² at the apex (downward).
    let d = p.derivatives(m[0]);
    close3(d[1], [0.0, 0.0, 1.0], 1e-12);
    close3(d[2], [150.0 / 6400.0, 0.0, 0.0], 1e-12);
    let d = p.derivatives(mid);
    close3(d[1], [1.0, 0.0, 0.0], 1e-9);
    close3(d[2], [0.0, 0.0, -80.0 / 22500.0], 1e-12);
    assert!(p.corners().is_empty());
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 3000);

    // Vertical lines meet the ellipse tangentially already: blending adds no arc.
    let q = elliptical(start, ip1, ip2, end, 80.0, 20.0).unwrap();
    assert_eq!(q, p);
}

#[test]
fn ellipse_lengths_against_reference() {
    for (w, h) in [
        (300.0, 80.0),
        (300.0, 150.0),
        (10.0, 300.0),
        (1000.0, 0.01),
        (0.02, 500.0),
        (1.0, 1e-4),
        (3.0, 1.0),
    ] {
        let piece = Piece::half_ellipse([w, 5.0, -3.0], [0.0, 5.0, -3.0], h).unwrap();
        let reference = half_ellipse_len(w / 2.0, h);
        close(piece.length() / reference, 1.0, 1e-12);
        // A small fixed table, even for the most eccentric ellipses, keeps paths cheap to copy.
        let Piece::HalfEllipse { table, .. } = piece else {
            panic!("not an ellipse");
        };
        assert!(table.intervals() <= ELLIPSE_TABLE_MAX);
        assert!(std::mem::size_of::<Piece>() <= 1024);
        let p = elliptical(
            [w, 5.0, -10.0],
            [w, 5.0, -3.0],
            [0.0, 5.0, -3.0],
            [0.0, 5.0, -10.0],
            h,
            0.0,
        )
        .unwrap();
        close(
            p.marks()[1] - p.marks()[0],
            reference,
            1e-9 * reference.max(1.0),
        );
        close3(
            p.point(p.marks()[0] + 0.5 * reference),
            [w / 2.0, 5.0, -3.0 + h],
            1e-9,
        );
        // Unit speed everywhere except across the needle tip of a very narrow ellipse (radius
        // of curvature (w/2)²/h there, far below the finite-difference step).
        let len = p.length();
        let tip = 0.5 * len;
        for i in 1..2000 {
            let s = len * i as f64 / 2000.0;
            let d = p.derivatives(s);
            close(norm(d[1]), 1.0, 1e-12);
            let hh = 1e-4;
            if (s - tip).abs() < 10.0 * hh || (s - p.marks()[0]).abs() < 2.0 * hh {
                continue;
            }
            if (s - p.marks()[1]).abs() < 2.0 * hh {
                continue;
            }
            let fd = scale(sub(p.point(s + hh), p.point(s - hh)), 0.5 / hh);
            close(norm(fd), 1.0, 1e-7);
        }
    }
}

#[test]
fn ellipse_with_lower_ip1_inserts_vertical_at_start() {
    let p = elliptical(
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 30.0],
        [300.0, 0.0, 50.0],
        [300.0, 0.0, 0.0],
        80.0,
        0.0,
    )
    .unwrap();
    let lh = half_ellipse_len(150.0, 80.0);
    let pcs = p.pieces();
    assert_eq!(pcs.len(), 4);
    assert_eq!(
        pcs[1],
        Piece::Line {
            from: [0.0, 0.0, 30.0],
            to: [0.0, 0.0, 50.0]
        }
    );
    assert!(matches!(pcs[2], Piece::HalfEllipse { from, to, .. }
        if from == [0.0, 0.0, 50.0] && to == [300.0, 0.0, 50.0]));
    close(p.marks()[0], 50.0, 1e-12);
    close(p.marks()[1], 50.0 + lh, 1e-9);
    close(p.length(), 100.0 + lh, 1e-9);
    // Apex 80 above the higher point.
    close(p.point(50.0 + lh / 2.0)[2], 130.0, 1e-9);
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 2000);
}

#[test]
fn ellipse_with_lower_ip2_inserts_vertical_at_end() {
    let p = elliptical(
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 50.0],
        [300.0, 0.0, 20.0],
        [300.0, 0.0, 0.0],
        80.0,
        0.0,
    )
    .unwrap();
    let lh = half_ellipse_len(150.0, 80.0);
    let pcs = p.pieces();
    assert_eq!(pcs.len(), 4);
    assert!(matches!(pcs[1], Piece::HalfEllipse { from, to, .. }
        if from == [0.0, 0.0, 50.0] && to == [300.0, 0.0, 50.0]));
    assert_eq!(
        pcs[2],
        Piece::Line {
            from: [300.0, 0.0, 50.0],
            to: [300.0, 0.0, 20.0]
        }
    );
    close(p.marks()[0], 50.0, 1e-12);
    close(p.marks()[1], 50.0 + lh, 1e-9);
    close(p.length(), 50.0 + lh + 50.0, 1e-9);
    assert_eq!(p.end_point(), [300.0, 0.0, 0.0]);
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 2000);
}

#[test]
fn ellipse_omits_empty_lines_and_works_in_any_vertical_plane() {
    let ip1 = [10.0, 20.0, 5.0];
    let ip2 = [10.0 + 120.0, 20.0 - 90.0, 5.0]; // 150 apart, diagonal in x-y
    let p = elliptical(ip1, ip1, ip2, ip2, 40.0, 10.0).unwrap();
    assert_eq!(p.pieces().len(), 1);
    assert_eq!(p.marks(), &[0.0, p.length()]);
    close(p.length(), half_ellipse_len(75.0, 40.0), 1e-9);
    let apex = p.point(p.length() / 2.0);
    close3(apex, [70.0, -25.0, 45.0], 1e-9);
    check_parametrisation(&p, 1000);
}

#[test]
fn elliptical_blending_choices() {
    // Slanted approach to a lower ip1: the line–line corner with the vertical insert is
    // blended (r clamped to half the 20 mm insert).
    let p = elliptical(
        [-50.0, 0.0, 0.0],
        [0.0, 0.0, 30.0],
        [300.0, 0.0, 50.0],
        [300.0, 0.0, 0.0],
        80.0,
        25.0,
    )
    .unwrap();
    let arcs: Vec<_> = p
        .pieces()
        .iter()
        .filter_map(|x| match x {
            Piece::Arc { radius, angle, .. } => Some((*radius, *angle)),
            _ => None,
        })
        .collect();
    assert_eq!(arcs.len(), 1);
    let th = f64::atan2(50.0, 30.0); // deflection from the slanted line to vertical
    close(arcs[0].1, th, 1e-12);
    close(arcs[0].0, 10.0 / (th / 2.0).tan(), 1e-9);
    assert!(p.corners().is_empty());
    // The ellipse still starts at the top of the insert.
    let s0 = p.marks()[0];
    close3(p.point(s0), [0.0, 0.0, 50.0], 1e-9);
    marks_in_order(&p);
    joins_are_smooth(&p);
    check_parametrisation(&p, 2000);

    // A slanted line straight into the ellipse has no tangent circle: a reported corner.
    let p = elliptical(
        [-50.0, 0.0, 0.0],
        [0.0, 0.0, 50.0],
        [300.0, 0.0, 50.0],
        [300.0, 0.0, 0.0],
        80.0,
        25.0,
    )
    .unwrap();
    assert_eq!(p.corners().len(), 1);
    close(p.corners()[0], p.marks()[0], 0.0);
    check_parametrisation(&p, 2000);
}

#[test]
fn degenerate_ellipses_become_lines() {
    // Height 0: a straight line between ip1 and ip2; its corners with the vertical lines are
    // blended like a polyline.
    let flat = elliptical(
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 50.0],
        [300.0, 0.0, 50.0],
        [300.0, 0.0, 0.0],
        0.0,
        20.0,
    )
    .unwrap();
    let poly = blended(
        &[
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 50.0],
            [300.0, 0.0, 50.0],
            [300.0, 0.0, 0.0],
        ],
        20.0,
    )
    .unwrap();
    close(flat.length(), poly.length(), 1e-12);
    close(flat.marks()[0], poly.marks()[1], 1e-12);
    close(flat.marks()[1], poly.marks()[2], 1e-12);
    check_parametrisation(&flat, 1000);

    // ip1 and ip2 vertically aligned: up by the height and back down, a reversal.
    let narrow = elliptical(
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 50.0],
        [0.0, 0.0, 50.0],
        [0.0, 0.0, 10.0],
        30.0,
        5.0,
    )
    .unwrap();
    close(narrow.length(), 50.0 + 60.0 + 40.0, 1e-12);
    assert_eq!(narrow.marks(), &[50.0, 110.0]);
    close3(narrow.point(80.0), [0.0, 0.0, 80.0], 1e-12);
    assert_eq!(narrow.corners(), &[80.0]);
    check_parametrisation(&narrow, 1000);
}

// ---------------------------------------------------------------------------------------------
// Degenerate input and errors

#[test]
fn all_points_equal_is_a_zero_length_path() {
    let a = [1.0, 2.0, 3.0];
    let p = blended(&[a, a, a], 10.0).unwrap();
    assert_eq!(p.length(), 0.0);
    assert_eq!(p.point(0.0), a);
    assert_eq!(p.point(5.0), a);
    assert_eq!(p.derivatives(0.0), [a, [0.0; 3], [0.0; 3], [0.0; 3]]);
    assert_eq!(p.marks(), &[0.0, 0.0]);
    assert!(p.pieces().is_empty());

    let q = elliptical(a, a, a, a, 0.0, 5.0).unwrap();
    assert_eq!(q.length(), 0.0);
    assert_eq!(q.point(1.0), a);
    assert_eq!(q.marks(), &[0.0, 0.0]);
}

#[test]
fn invalid_input_is_an_error() {
    let ok = [0.0, 0.0, 0.0];
    let nan = [1.0, f64::NAN, 0.0];
    let e = blended(&[ok, nan], 1.0).unwrap_err();
    assert!(matches!(e, PathError::NonFinitePoint { .. }));
    assert!(e.to_string().contains("point 1") && e.to_string().contains("NaN"));
    let e = blended(&[ok, [1.0, 0.0, 0.0]], -2.5).unwrap_err();
    assert_eq!(e, PathError::InvalidRadius(-2.5));
    assert!(e.to_string().contains("-2.5"));
    assert!(blended(&[ok, [1.0, 0.0, 0.0]], f64::NAN).is_err());
    assert!(blended(&[ok, [1.0, 0.0, 0.0]], f64::INFINITY).is_err());
    assert_eq!(blended(&[ok], 0.0).unwrap_err(), PathError::TooFewPoints(1));
    assert!(blended(&[ok, [f64::INFINITY, 0.0, 0.0]], 0.0).is_err());
    assert!(matches!(
        blended(&[ok, [1e300, 0.0, 0.0]], 0.0),
        Err(PathError::PointOutOfRange { .. })
    ));

    let up = [0.0, 0.0, 10.0];
    let e = elliptical(ok, up, [100.0, 0.0, 10.0], ok, -1.0, 0.0).unwrap_err();
    assert_eq!(e, PathError::InvalidHeight(-1.0));
    assert!(e.to_string().contains("-1"));
    let e = elliptical(ok, nan, up, ok, 10.0, 0.0).unwrap_err();
    assert!(e.to_string().contains("ip1"));
    assert!(elliptical(ok, up, up, ok, 10.0, -1.0).is_err());
    assert!(Piece::half_ellipse(ok, up, 10.0).is_err());
    assert!(matches!(
        Piece::half_ellipse(ok, [1.0, 0.0, 0.0], 1e-9),
        Err(PathError::DegenerateEllipse { .. })
    ));
}
