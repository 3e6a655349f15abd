//! Cartesian path geometry of the Track Pick & Place module: polylines through intermediate
//! points with tangent circular blends ([`blended`]), the half-ellipse mode ([`elliptical`]), and
//! an exact arc-length parametrisation of both.
//!
//! Everything is parametrised by arc length `s` (mm) so that the motion law (a jerk-limited
//! profile in `s`) maps one-to-one onto Cartesian speed, acceleration and jerk: `point(s)` has
//! unit speed everywhere, and [`Path::derivatives`] gives the unit tangent, the curvature vector
//! and its derivative, from which the planner bounds the axis accelerations and jerks.
//!
//! Numerical choices, and why:
//! - Arcs are evaluated relative to their start point with `1 − cos φ = 2·sin²(φ/2)`, not from
//!   their center: a blend of a nearly straight corner has a huge radius and a far-away center,
//!   and `center + R·u` would lose the start point to rounding.
//! - The half ellipse has no closed-form arc length. Its quarter `[0, π/2]` gets an adaptively
//!   graded table of `s(φ)` (10-point Gauss–Legendre per interval, refined where the integrand
//!   `|dP/dφ|` is nearly singular: the ends of a very flat ellipse, the apex of a very narrow
//!   one); `φ(s)` is then found by Newton iteration on the same quadrature, started from a
//!   quintic Hermite guess. The result is the exact root to rounding, so it is C∞ in `s` (no
//!   kinks from table interpolation that would show up as jerk spikes), and costs a couple of
//!   quadratures without allocating. The second quarter follows by symmetry.

use std::f64::consts::{FRAC_PI_2, PI};

/// A point or vector in mm: x, y, z (z up).
pub type P3 = [f64; 3];

/// Points closer than this (mm) are the same point: consecutive duplicates are dropped and
/// lines shorter than this are omitted, because a zero-length segment has no direction.
pub const DUP_TOL: f64 = 1e-9;

/// Direction changes smaller than this (rad) count as collinear (no blend arc, no corner): the
/// arc would deviate from the polyline by under `r·MIN_TURN/4`, far below any axis resolution.
pub const MIN_TURN: f64 = 1e-9;

/// Largest accepted coordinate magnitude (mm). Far beyond any workspace; it only guarantees
/// that no intermediate square or sum overflows to infinity (and from there to NaN).
pub const MAX_COORD: f64 = 1e12;

/// A half ellipse whose smaller semi-axis is below this fraction of the larger one is replaced
/// by lines (see [`elliptical`]): it deviates from them by less than that fraction of its size,
/// while its quadrature table would need ever finer grading near the nearly singular ends.
pub const ELLIPSE_MIN_RATIO: f64 = 1e-6;

/// Maximum number of table intervals on the quarter `[0, π/2]` of a half ellipse. Axis ratios
/// down to [`ELLIPSE_MIN_RATIO`] need about 18 (one per halving toward the flat end); the
/// bound keeps [`Piece`] small enough to copy freely.
pub const ELLIPSE_TABLE_MAX: usize = 24;

/// Positive Gauss–Legendre nodes (10 points on [−1, 1]; the others are their negatives).
const GL_X: [f64; 5] = [
    0.14887433898163122,
    0.4333953941292472,
    0.6794095682990244,
    0.8650633666889845,
    0.9739065285171717,
];
/// Weights of [`GL_X`].
const GL_W: [f64; 5] = [
    0.29552422471475287,
    0.26926671930999635,
    0.21908636251598204,
    0.1494513491505806,
    0.06667134430868814,
];

/// Why a path could not be built. Every message names the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// A point has a NaN or infinite coordinate.
    #[error("{what} has a non-finite coordinate: {point:?}")]
    NonFinitePoint {
        /// Which point (e.g. "point 3", "ip1").
        what: String,
        /// Its coordinates.
        point: P3,
    },
    /// A point has a coordinate beyond [`MAX_COORD`].
    #[error("{what} is out of range (|coordinate| > 1e12 mm): {point:?}")]
    PointOutOfRange {
        /// Which point.
        what: String,
        /// Its coordinates.
        point: P3,
    },
    /// The blend radius is negative, NaN or infinite.
    #[error("blend radius must be finite and >= 0 mm, got {0}")]
    InvalidRadius(f64),
    /// The ellipse height is negative, NaN or infinite (or beyond [`MAX_COORD`]).
    #[error("ellipse height must be finite and >= 0 mm, got {0}")]
    InvalidHeight(f64),
    /// Fewer than two points were given.
    #[error("a path needs at least 2 points, got {0}")]
    TooFewPoints(usize),
    /// [`Piece::half_ellipse`] was given ends at different heights.
    #[error("half-ellipse ends must be at the same height: from z = {from_z}, to z = {to_z}")]
    EllipseNotLevel {
        /// z of the start.
        from_z: f64,
        /// z of the end.
        to_z: f64,
    },
    /// [`Piece::half_ellipse`] was given a (nearly) flat or (nearly) zero-width ellipse.
    #[error(
        "half ellipse of width {width} mm and height {height} mm is degenerate \
         (one semi-axis below 1e-6 of the other)"
    )]
    DegenerateEllipse {
        /// Horizontal distance of the ends.
        width: f64,
        /// Height.
        height: f64,
    },
}

// ---------------------------------------------------------------------------------------------
// Small vector helpers (kept local so the module is self-contained).

fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: P3, k: f64) -> P3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}
fn dist(a: P3, b: P3) -> f64 {
    norm(sub(b, a))
}
/// `a·x + b·y`, the building block of every in-plane evaluation.
fn comb(x: P3, a: f64, y: P3, b: f64) -> P3 {
    [
        a * x[0] + b * y[0],
        a * x[1] + b * y[1],
        a * x[2] + b * y[2],
    ]
}
/// Angle between two unit vectors, accurate also near 0 and π (unlike `acos`).
fn angle_between(a: P3, b: P3) -> f64 {
    norm(cross(a, b)).atan2(dot(a, b))
}

const UP: P3 = [0.0, 0.0, 1.0];
const ZERO: P3 = [0.0; 3];

// ---------------------------------------------------------------------------------------------
// Pieces

/// The arc-length table of a half ellipse (see the module docs). Built only by
/// [`Piece::half_ellipse`], so its invariants (non-degenerate axes, consistent table) hold.
///
/// The ellipse is `P(φ) = c + a·cos φ·e + h·sin φ·z`, φ ∈ [0, π], with `c` the midpoint of its
/// ends, `e` the horizontal unit vector toward `from` and `z` up; the table covers φ ∈ [0, π/2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipseTable {
    /// Horizontal semi-axis (half the distance of the ends).
    a: f64,
    /// Vertical semi-axis (the height).
    b: f64,
    /// Unit horizontal vector from the midpoint toward `from`.
    e: P3,
    /// Number of table intervals used.
    n: usize,
    /// Interval bounds in φ: `phi[0] = 0`, `phi[n] = π/2`.
    phi: [f64; ELLIPSE_TABLE_MAX + 1],
    /// Arc length from φ = 0 to `phi[k]`, by the same quadrature [`Self::phi_of`] uses, so that
    /// `s(φ)` is continuous across table bounds.
    s: [f64; ELLIPSE_TABLE_MAX + 1],
}

impl EllipseTable {
    /// Number of table intervals on the quarter `[0, π/2]` (at most [`ELLIPSE_TABLE_MAX`]).
    pub fn intervals(&self) -> usize {
        self.n
    }

    /// Total arc length of the half ellipse.
    pub fn length(&self) -> f64 {
        2.0 * self.quarter()
    }

    fn new(a: f64, b: f64, e: P3) -> EllipseTable {
        let mut t = EllipseTable {
            a,
            b,
            e,
            n: 0,
            phi: [0.0; ELLIPSE_TABLE_MAX + 1],
            s: [0.0; ELLIPSE_TABLE_MAX + 1],
        };
        // Start from a few uniform intervals (good Hermite guesses everywhere), then bisect
        // the interval with the largest quadrature error estimate until all are below tol.
        // The error of 10-point Gauss–Legendre falls geometrically with the distance of the
        // integrand's complex singularity, so this yields a dyadic grading toward the flat end
        // of a very eccentric ellipse.
        let tol = 1e-15 * (a + b);
        let mut bounds: Vec<f64> = (0..=4).map(|i| FRAC_PI_2 * i as f64 / 4.0).collect();
        while bounds.len() <= ELLIPSE_TABLE_MAX {
            let mut worst = (0.0, 0);
            for k in 0..bounds.len() - 1 {
                let (p0, p1) = (bounds[k], bounds[k + 1]);
                let m = 0.5 * (p0 + p1);
                let err = (t.gl(p0, p1) - t.gl(p0, m) - t.gl(m, p1)).abs();
                if err > worst.0 {
                    worst = (err, k);
                }
            }
            if worst.0 <= tol {
                break;
            }
            let k = worst.1;
            bounds.insert(k + 1, 0.5 * (bounds[k] + bounds[k + 1]));
        }
        t.n = bounds.len() - 1;
        for (k, &p) in bounds.iter().enumerate() {
            t.phi[k] = p;
        }
        for k in 0..t.n {
            t.s[k + 1] = t.s[k] + t.gl(t.phi[k], t.phi[k + 1]);
        }
        t
    }

    /// `|dP/dφ|`.
    fn speed(&self, phi: f64) -> f64 {
        let (sn, cs) = phi.sin_cos();
        let (x, z) = (self.a * sn, self.b * cs);
        (x * x + z * z).sqrt()
    }

    /// Arc length from `p0` to `p1` by one 10-point Gauss–Legendre rule.
    fn gl(&self, p0: f64, p1: f64) -> f64 {
        let half = 0.5 * (p1 - p0);
        let mid = 0.5 * (p1 + p0);
        let mut sum = 0.0;
        for (x, w) in GL_X.iter().zip(GL_W.iter()) {
            sum += w * (self.speed(mid - half * x) + self.speed(mid + half * x));
        }
        sum * half
    }

    /// Length of the quarter ellipse φ ∈ [0, π/2].
    fn quarter(&self) -> f64 {
        self.s[self.n]
    }

    /// For arc length `s` ∈ [0, 2·quarter] from `from`: the angle ψ ∈ [0, π/2] measured from
    /// the nearer end, and whether that end is `to` (then φ = π − ψ). Measuring the second
    /// half from `to` makes the end point exact and reuses the quarter table by symmetry.
    fn angle_at(&self, s: f64) -> (f64, bool) {
        let q = self.quarter();
        if s <= q {
            (self.phi_of(s), false)
        } else {
            (self.phi_of(2.0 * q - s), true)
        }
    }

    /// Position at angle ψ from the nearer end (see [`Self::angle_at`]), relative to that end
    /// with `1 − cos ψ = 2·sin²(ψ/2)` so the ends are reproduced exactly.
    fn position(&self, from: P3, to: P3, psi: f64, mirrored: bool) -> P3 {
        let h = (0.5 * psi).sin();
        let back = 2.0 * self.a * h * h;
        let up = self.b * psi.sin();
        if mirrored {
            add(to, comb(self.e, back, UP, up))
        } else {
            add(from, comb(self.e, -back, UP, up))
        }
    }

    /// `|dP/dφ|` and `dP/dφ · d²P/dφ²` (= speed · d speed/dφ).
    fn speed_g(&self, phi: f64) -> (f64, f64) {
        let (sn, cs) = phi.sin_cos();
        let (x, z) = (self.a * sn, self.b * cs);
        let v = (x * x + z * z).sqrt();
        (v, (self.a * self.a - self.b * self.b) * sn * cs)
    }

    /// Arc length over a short step (within 1 % of a table interval) by 3-point
    /// Gauss–Legendre: the step is so much shorter than the interval that its error is ~1e-12
    /// of the step's length, while costing a third of [`Self::gl`].
    fn gl3(&self, p0: f64, p1: f64) -> f64 {
        let half = 0.5 * (p1 - p0);
        let mid = 0.5 * (p1 + p0);
        let x = (0.6f64).sqrt() * half;
        (5.0 * (self.speed(mid - x) + self.speed(mid + x)) + 8.0 * self.speed(mid)) * half / 9.0
    }

    /// The φ ∈ [0, π/2] at which the arc length from φ = 0 is `sigma`.
    fn phi_of(&self, sigma: f64) -> f64 {
        let sigma = sigma.clamp(0.0, self.quarter());
        let k = self.s[1..self.n].partition_point(|&x| x <= sigma);
        let (p0, p1, s0, s1) = (self.phi[k], self.phi[k + 1], self.s[k], self.s[k + 1]);
        let ds = s1 - s0;
        if ds <= 0.0 {
            return p0;
        }
        // Quintic Hermite guess for φ(s) from the end values, slopes dφ/ds = 1/v and
        // curvatures d²φ/ds² = −v'/v³ (v = |dP/dφ|): error O(h⁶), so Newton starts close.
        // The basis is exact at t = 0 and t = 1, so table bounds are hit exactly.
        let t = (sigma - s0) / ds;
        let ((v0, g0), (v1, g1)) = (self.speed_g(p0), self.speed_g(p1));
        let (m0, m1) = (ds / v0, ds / v1);
        let (c0, c1) = (-g0 / (v0 * v0 * v0 * v0), -g1 / (v1 * v1 * v1 * v1));
        let ds2 = ds * ds;
        let (t2, t3) = (t * t, t * t * t);
        let (t4, t5) = (t3 * t, t3 * t2);
        let mut phi = (1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5) * p0
            + (t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5) * m0
            + 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5) * c0 * ds2
            + 0.5 * (t3 - 2.0 * t4 + t5) * c1 * ds2
            + (-4.0 * t3 + 7.0 * t4 - 3.0 * t5) * m1
            + (10.0 * t3 - 15.0 * t4 + 6.0 * t5) * p1;
        let (mut lo, mut hi) = (p0, p1);
        phi = phi.clamp(lo, hi);
        // Safeguarded Newton on f(φ) = s0 + ∫_{p0}^{φ} v − σ, which is increasing. The
        // integral is evaluated once by the table's own rule (so s(φ) is continuous across table
        // bounds) and then updated by the short steps Newton takes.
        let mut s_phi = s0 + self.gl(p0, phi);
        let small = 0.01 * (p1 - p0);
        for _ in 0..16 {
            let f = s_phi - sigma;
            if f > 0.0 {
                hi = phi;
            } else {
                lo = phi;
            }
            let mut next = phi - f / self.speed(phi);
            if !(next >= lo && next <= hi) {
                next = 0.5 * (lo + hi);
            }
            let moved = (next - phi).abs();
            if moved <= 1e-15 {
                // Converged: this last step is below any effect on s.
                return next;
            }
            s_phi += if moved <= small {
                self.gl3(phi, next)
            } else {
                // A bisection fallback or a large first step: integrate afresh.
                s0 + self.gl(p0, next) - s_phi
            };
            phi = next;
        }
        phi
    }
}

/// One geometric piece, parametrised by its own arc length.
// The ellipse variant carries its fixed-size table inline: pieces are `Copy` (so no Box), and
// a path has only a handful of pieces, so the size difference costs little.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Piece {
    /// A straight line.
    Line {
        /// Start point.
        from: P3,
        /// End point.
        to: P3,
    },
    /// A circular arc (any plane): center, radius, unit vectors u (center→start) and w
    /// (in-plane, perpendicular to u, toward the direction of travel), swept angle (rad).
    /// The point at arc length s is `center + radius·(cos φ·u + sin φ·w)`, φ = s / radius.
    Arc {
        /// Center.
        center: P3,
        /// Radius (mm, > 0).
        radius: f64,
        /// Unit vector from the center to the start point.
        u: P3,
        /// Unit vector perpendicular to `u` in the arc's plane: the start tangent.
        w: P3,
        /// Swept angle (rad, > 0).
        angle: f64,
    },
    /// Half an ellipse in a vertical plane: from `from` to `to` (same z), rising to `height`
    /// above them. It leaves `from` straight up and arrives at `to` straight down.
    HalfEllipse {
        /// Start point.
        from: P3,
        /// End point (same z as `from`).
        to: P3,
        /// Height of the apex above the ends (mm, > 0).
        height: f64,
        /// Arc-length table; build the piece with [`Piece::half_ellipse`].
        table: EllipseTable,
    },
}

impl Piece {
    /// A half ellipse from `from` to `to` (same z, exactly) of the given height. Rejects
    /// non-finite input and ellipses whose smaller semi-axis is below
    /// [`ELLIPSE_MIN_RATIO`] times the larger (they are lines, see [`elliptical`]).
    pub fn half_ellipse(from: P3, to: P3, height: f64) -> Result<Piece, PathError> {
        check_point("ellipse start", from)?;
        check_point("ellipse end", to)?;
        check_height(height)?;
        if from[2] != to[2] {
            return Err(PathError::EllipseNotLevel {
                from_z: from[2],
                to_z: to[2],
            });
        }
        let d = sub(from, to);
        let width = norm(d);
        let a = 0.5 * width;
        if a <= ELLIPSE_MIN_RATIO * height || height <= ELLIPSE_MIN_RATIO * a {
            return Err(PathError::DegenerateEllipse { width, height });
        }
        let e = scale(d, 1.0 / width);
        Ok(Piece::HalfEllipse {
            from,
            to,
            height,
            table: EllipseTable::new(a, height, e),
        })
    }

    /// Arc length of the piece.
    pub fn length(&self) -> f64 {
        match *self {
            Piece::Line { from, to } => dist(from, to),
            Piece::Arc { radius, angle, .. } => radius * angle,
            Piece::HalfEllipse { table, .. } => table.length(),
        }
    }

    /// Start point.
    pub fn start(&self) -> P3 {
        match *self {
            Piece::Line { from, .. } | Piece::HalfEllipse { from, .. } => from,
            Piece::Arc {
                center, radius, u, ..
            } => add(center, scale(u, radius)),
        }
    }

    /// End point.
    pub fn end(&self) -> P3 {
        match *self {
            Piece::Line { to, .. } | Piece::HalfEllipse { to, .. } => to,
            Piece::Arc { .. } => self.point(self.length()),
        }
    }

    /// Unit tangent at the start.
    pub fn start_tangent(&self) -> P3 {
        self.derivatives(0.0)[1]
    }

    /// Unit tangent at the end.
    pub fn end_tangent(&self) -> P3 {
        self.derivatives(self.length())[1]
    }

    /// Position at arc length `s` from the start (clamped to the piece; NaN counts as 0).
    pub fn point(&self, s: f64) -> P3 {
        self.point_from(self.start(), s)
    }

    /// Position and its first three derivatives with respect to arc length at `s` (clamped).
    pub fn derivatives(&self, s: f64) -> [P3; 4] {
        self.derivatives_from(self.start(), s)
    }

    /// [`Self::point`] with the start point given: the path stores the exact start of each
    /// arc, which `center + radius·u` only reproduces to `radius·ε`.
    fn point_from(&self, start: P3, s: f64) -> P3 {
        let len = self.length();
        let s = clamp_s(s, len);
        match *self {
            Piece::Line { from, to } => {
                if len <= 0.0 {
                    from
                } else if s >= len {
                    // Exact end point: from + (to − from) need not round to `to`.
                    to
                } else {
                    add(from, scale(sub(to, from), s / len))
                }
            }
            Piece::Arc { radius, .. } if radius.is_nan() || radius <= 0.0 => start,
            Piece::Arc { radius, u, w, .. } => {
                let phi = s / radius;
                let h = (0.5 * phi).sin();
                add(start, comb(u, -2.0 * radius * h * h, w, radius * phi.sin()))
            }
            Piece::HalfEllipse {
                from, to, table, ..
            } => {
                let (psi, mirrored) = table.angle_at(s);
                table.position(from, to, psi, mirrored)
            }
        }
    }

    fn derivatives_from(&self, start: P3, s: f64) -> [P3; 4] {
        let len = self.length();
        let s = clamp_s(s, len);
        match *self {
            Piece::Line { from, to } => {
                let p = self.point_from(start, s);
                let t = if len > 0.0 {
                    scale(sub(to, from), 1.0 / len)
                } else {
                    ZERO
                };
                [p, t, ZERO, ZERO]
            }
            // Only a hand-built piece can have no radius; it is a point, not a NaN.
            Piece::Arc { radius, .. } if radius.is_nan() || radius <= 0.0 => {
                [start, ZERO, ZERO, ZERO]
            }
            Piece::Arc { radius, u, w, .. } => {
                let (sn, cs) = (s / radius).sin_cos();
                [
                    self.point_from(start, s),
                    comb(u, -sn, w, cs),
                    comb(u, -cs / radius, w, -sn / radius),
                    comb(u, sn / (radius * radius), w, -cs / (radius * radius)),
                ]
            }
            Piece::HalfEllipse {
                from, to, table, ..
            } => {
                let (psi, mirrored) = table.angle_at(s);
                let p = table.position(from, to, psi, mirrored);
                // sin and cos of φ ∈ [0, π]; the mirrored half has φ = π − ψ.
                let (sn, cs) = psi.sin_cos();
                let cs = if mirrored { -cs } else { cs };
                let (a, b, e) = (table.a, table.b, table.e);
                // Derivatives in φ: P' = −a sin·e + b cos·z, P'' = −(P − c), P''' = −P'.
                let d1 = comb(e, -a * sn, UP, b * cs);
                let d2 = comb(e, -a * cs, UP, -b * sn);
                let d3 = scale(d1, -1.0);
                let v2 = dot(d1, d1);
                let v = v2.sqrt();
                let g = dot(d1, d2); // = v·dv/dφ
                let v4 = v2 * v2;
                // Chain rule with dφ/ds = 1/v:
                // T = P'/v, K = P''/v² − P'·g/v⁴,
                // dK/dφ = P'''/v² − 3P''·g/v⁴ − P'(|P''|² + P'·P''')/v⁴ + 4P'·g²/v⁶, J = (dK/dφ)/v.
                let t = scale(d1, 1.0 / v);
                let k = comb(d2, 1.0 / v2, d1, -g / v4);
                let h = dot(d2, d2) + dot(d1, d3);
                let dk = add(
                    comb(d3, 1.0 / v2, d2, -3.0 * g / v4),
                    scale(d1, (-h + 4.0 * g * g / v2) / v4),
                );
                [p, t, k, scale(dk, 1.0 / v)]
            }
        }
    }
}

/// Clamp an arc length into `[0, len]`, mapping NaN to 0 so no NaN can leak into positions.
fn clamp_s(s: f64, len: f64) -> f64 {
    if s >= 0.0 {
        s.min(len)
    } else {
        0.0
    }
}

// ---------------------------------------------------------------------------------------------
// Path

/// A path: pieces joined end to start, with its cumulative length.
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    pieces: Vec<Piece>,
    /// Exact start point of each piece (see [`Piece::point_from`]).
    origins: Vec<P3>,
    /// Arc length at which each piece starts.
    starts: Vec<f64>,
    length: f64,
    first: P3,
    last: P3,
    marks: Vec<f64>,
    corners: Vec<f64>,
}

impl Path {
    /// Total arc length (mm).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Position at arc length s (clamped to [0, length]; NaN counts as 0).
    pub fn point(&self, s: f64) -> P3 {
        if self.pieces.is_empty() || s.is_nan() || s <= 0.0 {
            return self.first;
        }
        if s >= self.length {
            return self.last;
        }
        let i = self.index(s);
        self.pieces[i].point_from(self.origins[i], s - self.starts[i])
    }

    /// Position and its first three derivatives with respect to s (unit tangent, curvature
    /// vector, its derivative) — used to check axis limits. At a join the piece that starts
    /// there is used (the last piece at the very end); a zero-length path has zero derivatives.
    pub fn derivatives(&self, s: f64) -> [P3; 4] {
        if self.pieces.is_empty() {
            return [self.first, ZERO, ZERO, ZERO];
        }
        let s = clamp_s(s, self.length);
        let i = self.index(s);
        let mut d = self.pieces[i].derivatives_from(self.origins[i], s - self.starts[i]);
        // Same exact end points as `point`.
        if s <= 0.0 {
            d[0] = self.first;
        } else if s >= self.length {
            d[0] = self.last;
        }
        d
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }

    /// Arc length at which each piece starts (same order as [`Self::pieces`]).
    pub fn piece_starts(&self) -> &[f64] {
        &self.starts
    }

    /// Arc length at which each intermediate "mark" lies (see [`blended`], [`elliptical`]).
    pub fn marks(&self) -> &[f64] {
        &self.marks
    }

    /// Arc lengths of the remaining sharp corners (tangent direction jumps by ≥ [`MIN_TURN`]):
    /// every interior point when r = 0, reversals, and a non-vertical line meeting the
    /// ellipse. The motion law must come to a stop there.
    pub fn corners(&self) -> &[f64] {
        &self.corners
    }

    /// First point.
    pub fn start_point(&self) -> P3 {
        self.first
    }

    /// Last point.
    pub fn end_point(&self) -> P3 {
        self.last
    }

    /// Index of the piece containing `s` ∈ [0, length]: the one starting at or before it.
    fn index(&self, s: f64) -> usize {
        self.starts
            .partition_point(|&x| x <= s)
            .saturating_sub(1)
            .min(self.pieces.len() - 1)
    }
}

// ---------------------------------------------------------------------------------------------
// Validation

fn check_point(what: &str, p: P3) -> Result<(), PathError> {
    if p.iter().any(|c| !c.is_finite()) {
        return Err(PathError::NonFinitePoint {
            what: what.to_string(),
            point: p,
        });
    }
    if p.iter().any(|c| c.abs() > MAX_COORD) {
        return Err(PathError::PointOutOfRange {
            what: what.to_string(),
            point: p,
        });
    }
    Ok(())
}

fn check_radius(r: f64) -> Result<(), PathError> {
    if r.is_finite() && r >= 0.0 {
        Ok(())
    } else {
        Err(PathError::InvalidRadius(r))
    }
}

fn check_height(h: f64) -> Result<(), PathError> {
    if h.is_finite() && (0.0..=MAX_COORD).contains(&h) {
        Ok(())
    } else {
        Err(PathError::InvalidHeight(h))
    }
}

// ---------------------------------------------------------------------------------------------
// Assembly: segments joined at corners, line–line corners blended.

/// An unblended segment of a path under construction.
enum Seg {
    Line(P3, P3),
    /// A curved piece that is never trimmed (the half ellipse).
    Fixed(Box<Piece>),
}

impl Seg {
    fn end(&self) -> P3 {
        match self {
            Seg::Line(_, b) => *b,
            Seg::Fixed(p) => p.end(),
        }
    }
}

/// A blend at a corner: how far it trims both lines, the arc, and the arc's exact start.
struct Blend {
    trim: f64,
    arc: Piece,
    start: P3,
}

/// The trim point at distance `t` from `a` toward `b` — one function for both the line end and
/// the arc start, so they agree to the last bit.
fn toward(a: P3, dir: P3, t: f64) -> P3 {
    add(a, scale(dir, t))
}

fn unit(a: P3, b: P3) -> P3 {
    let d = sub(b, a);
    scale(d, 1.0 / norm(d))
}

/// The tangent arc at corner `c` between lines `a→c` and `c→b` (both longer than
/// [`DUP_TOL`]), with tangent points at distance `r` (clamped to half the shorter line) from
/// the corner. With deflection angle θ between the two directions, the arc sweeps θ and its
/// radius is `r / tan(θ/2)` (= `r·tan(α/2)` with α = π − θ the interior angle at the corner).
/// None for r = 0, collinear corners and reversals (θ = π has no tangent circle).
fn corner_blend(a: P3, c: P3, b: P3, r: f64) -> Option<Blend> {
    let rr = r.min(0.5 * dist(a, c)).min(0.5 * dist(c, b));
    if rr <= 0.0 {
        return None;
    }
    let d1 = unit(a, c);
    let d2 = unit(c, b);
    let theta = angle_between(d1, d2);
    if theta < MIN_TURN || PI - theta < MIN_TURN {
        return None;
    }
    let radius = rr / (0.5 * theta).tan();
    // Inward normal at the first tangent point: the part of d2 perpendicular to d1.
    let nv = comb(d2, 1.0, d1, -dot(d1, d2));
    let nn = norm(nv);
    if nn <= 0.0 || !radius.is_finite() {
        return None;
    }
    let n = scale(nv, 1.0 / nn);
    let start = toward(c, d1, -rr);
    Some(Blend {
        trim: rr,
        arc: Piece::Arc {
            center: toward(start, n, radius),
            radius,
            u: scale(n, -1.0),
            w: d1,
            angle: theta,
        },
        start,
    })
}

/// Builds the path from segments (each starting where the previous ends), blending every
/// line–line corner with `r`. Returns the path (marks empty) and, per corner j (between
/// segment j and j+1), the arc lengths where its blend starts and ends.
fn assemble(first: P3, segs: &[Seg], r: f64) -> (Path, Vec<(f64, f64)>) {
    let nj = segs.len().saturating_sub(1);
    let blends: Vec<Option<Blend>> = (0..nj)
        .map(|j| match (&segs[j], &segs[j + 1]) {
            (Seg::Line(a, c), Seg::Line(_, b)) => corner_blend(*a, *c, *b, r),
            _ => None,
        })
        .collect();
    let trim = |j: usize| blends[j].as_ref().map_or(0.0, |b| b.trim);

    let mut path = Path {
        pieces: Vec::new(),
        origins: Vec::new(),
        starts: Vec::new(),
        length: 0.0,
        first,
        last: segs.last().map_or(first, Seg::end),
        marks: Vec::new(),
        corners: Vec::new(),
    };
    let push = |path: &mut Path, piece: Piece, origin: P3| {
        path.starts.push(path.length);
        path.length += piece.length();
        path.pieces.push(piece);
        path.origins.push(origin);
    };
    let mut junctions = Vec::with_capacity(nj);
    for (j, seg) in segs.iter().enumerate() {
        match seg {
            Seg::Line(a, b) => {
                let len = dist(*a, *b);
                let t0 = if j > 0 { trim(j - 1) } else { 0.0 };
                let t1 = if j < nj { trim(j) } else { 0.0 };
                if len - t0 - t1 > 1e-12 {
                    let from = if t0 > 0.0 {
                        toward(*a, unit(*a, *b), t0)
                    } else {
                        *a
                    };
                    let to = if t1 > 0.0 {
                        toward(*b, unit(*a, *b), -t1)
                    } else {
                        *b
                    };
                    push(&mut path, Piece::Line { from, to }, from);
                }
            }
            Seg::Fixed(p) => push(&mut path, **p, p.start()),
        }
        if j < nj {
            let s0 = path.length;
            if let Some(b) = &blends[j] {
                push(&mut path, b.arc, b.start);
            }
            junctions.push((s0, path.length));
        }
    }
    for i in 1..path.pieces.len() {
        let t0 = path.pieces[i - 1].end_tangent();
        let t1 = path.pieces[i].start_tangent();
        if angle_between(t0, t1) >= MIN_TURN {
            path.corners.push(path.starts[i]);
        }
    }
    (path, junctions)
}

/// Straight lines through `points` (≥ 2; consecutive duplicates — closer than [`DUP_TOL`] —
/// are dropped) with each interior corner replaced by a tangent-continuous circular arc whose
/// tangent points lie `r` before and after the corner along the two segments; r is clamped to
/// half of the shorter adjacent segment (so two neighbouring blends can meet but never
/// overlap). The arc sweeps the deflection angle θ between the segment directions and has
/// radius `r / tan(θ/2)` (r for a right angle). r = 0: sharp corners (plain polyline).
/// Collinear corners (θ < [`MIN_TURN`]) and reversals (θ = π) get no arc.
///
/// marks(): for each interior point i (1..n-1) of the input, the arc length where its blend
/// starts and where it ends (equal for r = 0 or no arc) — so marks has 2·(n−2) entries, in
/// order. A dropped duplicate gets the marks of the point it duplicates (0 or the length if
/// that is an end point). All points equal: a zero-length path at that point.
pub fn blended(points: &[P3], r: f64) -> Result<Path, PathError> {
    if points.len() < 2 {
        return Err(PathError::TooFewPoints(points.len()));
    }
    for (i, p) in points.iter().enumerate() {
        check_point(&format!("point {i}"), *p)?;
    }
    check_radius(r)?;
    // Deduplicate, remembering which kept point each input point maps to.
    let mut kept: Vec<P3> = Vec::with_capacity(points.len());
    let mut map = Vec::with_capacity(points.len());
    for p in points {
        match kept.last() {
            Some(&q) if dist(q, *p) <= DUP_TOL => {}
            _ => kept.push(*p),
        }
        map.push(kept.len() - 1);
    }
    // Keep the path's end exactly at the last input point.
    let n_kept = kept.len();
    if n_kept > 1 {
        kept[n_kept - 1] = points[points.len() - 1];
    }
    let segs: Vec<Seg> = kept.windows(2).map(|w| Seg::Line(w[0], w[1])).collect();
    let (mut path, junctions) = assemble(kept[0], &segs, r);
    for &k in &map[1..map.len() - 1] {
        let (m0, m1) = if k == 0 {
            (0.0, 0.0)
        } else if k == n_kept - 1 {
            (path.length, path.length)
        } else {
            junctions[k - 1]
        };
        path.marks.push(m0);
        path.marks.push(m1);
    }
    Ok(path)
}

/// Elliptical mode between intermediate points ip1 and ip2: a line from `start` to ip1, then
/// a half ellipse of height `height` (above the higher of ip1/ip2) in the vertical plane
/// through ip1 and ip2, then a line down to `end`. When ip1 and ip2 differ in height, a
/// vertical line is inserted at the LOWER one (up from ip1 before the ellipse if ip1 is lower,
/// down to ip2 after it if ip2 is lower) so the ellipse's two ends are at the same height.
/// Points closer than [`DUP_TOL`] (start == ip1, ip2 == end, equal heights) omit that line.
///
/// Blending (r > 0, clamped to half the shorter adjacent line as in [`blended`]): only corners
/// between two lines get a tangent arc — e.g. a slanted start→ip1 line meeting the vertical
/// insert above a lower ip1. The ellipse itself is never trimmed: it leaves its start straight
/// up and arrives at its end straight down (x = a·cos φ, z = h·sin φ), so a vertical line
/// (the normal case, start below ip1 and end below ip2) is already tangent to it and needs no
/// arc. A non-vertical line meeting the ellipse stays a sharp corner (a circle tangent to both
/// exists only in their common plane, generally not at all), reported by [`Path::corners`].
///
/// Degenerate ellipses (one semi-axis below [`ELLIPSE_MIN_RATIO`] of the other) become lines:
/// a flat one (height ≈ 0) the straight line between its ends (whose corners with vertical
/// lines are then blended), a narrow one (ip1, ip2 vertically aligned) a line up by `height`
/// and back down (a reversal, i.e. a corner).
///
/// marks(): [arc length where the ellipse starts, where it ends] — for the lines replacing a
/// degenerate ellipse, where they start after and end before any adjacent blend.
pub fn elliptical(
    start: P3,
    ip1: P3,
    ip2: P3,
    end: P3,
    height: f64,
    r: f64,
) -> Result<Path, PathError> {
    check_point("start", start)?;
    check_point("ip1", ip1)?;
    check_point("ip2", ip2)?;
    check_point("end", end)?;
    check_height(height)?;
    check_radius(r)?;

    let mut segs = Vec::new();
    let mut cur = start;
    // Appends a line from the current point unless it would be shorter than DUP_TOL; the next
    // segment always starts where the previous one ended, so the path is continuous.
    let line_to = |segs: &mut Vec<Seg>, cur: &mut P3, to: P3| {
        if dist(*cur, to) > DUP_TOL {
            segs.push(Seg::Line(*cur, to));
            *cur = to;
        }
    };
    line_to(&mut segs, &mut cur, ip1);
    let top_z = ip1[2].max(ip2[2]);
    let above_ip1 = [cur[0], cur[1], top_z];
    line_to(&mut segs, &mut cur, above_ip1);
    let a_pt = cur;
    let b_pt = [ip2[0], ip2[1], a_pt[2]];

    let mid_begin = segs.len();
    let half_width = 0.5 * dist(a_pt, b_pt);
    if half_width <= DUP_TOL && height <= DUP_TOL {
        // Nothing between the two lines.
    } else if height <= ELLIPSE_MIN_RATIO * half_width {
        line_to(&mut segs, &mut cur, b_pt);
    } else if half_width <= ELLIPSE_MIN_RATIO * height {
        line_to(&mut segs, &mut cur, add(a_pt, scale(UP, height)));
        line_to(&mut segs, &mut cur, b_pt);
    } else {
        segs.push(Seg::Fixed(Box::new(Piece::half_ellipse(
            a_pt, b_pt, height,
        )?)));
        cur = b_pt;
    }
    let mid_end = segs.len();

    line_to(&mut segs, &mut cur, ip2);
    line_to(&mut segs, &mut cur, end);

    let (mut path, junctions) = assemble(start, &segs, r);
    let len = path.length;
    let marks = if mid_begin < mid_end {
        [
            if mid_begin == 0 {
                0.0
            } else {
                junctions[mid_begin - 1].1
            },
            if mid_end == segs.len() {
                len
            } else {
                junctions[mid_end - 1].0
            },
        ]
    } else if mid_begin == 0 {
        [0.0, 0.0]
    } else if mid_begin == segs.len() {
        [len, len]
    } else {
        let (m0, m1) = junctions[mid_begin - 1];
        [m0, m1]
    };
    path.marks = marks.to_vec();
    Ok(path)
}
