//! A planned move as the interpolator runs it: a path in Cartesian space, the motion law along
//! it, and the belts it follows. The setpoint at virtual time τ and real belt travel is
//!
//! `path(σ(τ)) + S + w(σ)·(P − S) + w(σ)·Δdst`,  with  `S = Σ (1 − w(σ))·δsrc`
//!
//! where w is the clutch: 0 while the tool still moves with the source belt (the lift), 1 once
//! it moves with the destination (the approach), blended smoothly in between. Leaving the
//! source, the tool takes on each update's belt travel δsrc weighted by 1 − w (S): a velocity
//! clutch, so however long the move takes, no offset piles up to be unwound. P is the S the
//! plan predicts at the end, and the path's end is shifted back by it, so the end is exact
//! whatever the source belt really did. Joining the destination, Δdst is how far the belt is
//! from the travel predicted for the arrival, along its direction: at the end w = 1 exactly,
//! and the setpoint is the workpiece's own position whatever the belt did on the way.

use super::law::DoubleS;
use super::path::Path;
use super::robot::Pose;

/// A belt the tool moves with: `dir · (travel − base)` is added to the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Follow {
    /// Index of the belt in the module's belt list.
    pub belt: usize,
    /// The belt's direction of travel in the machine's coordinates.
    pub dir: [f64; 3],
    /// The travel at which the offset is zero.
    pub base: f64,
}

impl Follow {
    /// The offset at belt travels `travel` (indexed like the module's belts).
    pub fn offset(&self, travel: &[f64]) -> [f64; 3] {
        self.offset_at(travel.get(self.belt).copied().unwrap_or(self.base))
    }

    /// The offset when the followed belt has travelled `travel`.
    pub fn offset_at(&self, travel: f64) -> [f64; 3] {
        let d = travel - self.base;
        [self.dir[0] * d, self.dir[1] * d, self.dir[2] * d]
    }
}

/// One rest-to-rest stretch of the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leg {
    /// Arc length where it starts.
    pub s0: f64,
    /// Virtual time where it starts.
    pub t0: f64,
    /// The motion law over its length.
    pub law: DoubleS,
}

/// Where the path parameter is.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PathState {
    /// Arc length.
    pub s: f64,
    /// Path speed, per virtual second.
    pub v: f64,
    /// Path acceleration.
    pub a: f64,
}

/// A planned move.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// The geometry, in the machine's coordinates as of the plan.
    pub path: Path,
    /// The motion law, leg by leg (one leg when the intermediate points are blended).
    pub legs: Vec<Leg>,
    /// The belt the tool moves with when the move starts.
    pub src: Option<Follow>,
    /// The belt the tool moves with when the move ends.
    pub dst: Option<Follow>,
    /// Arc lengths between which the clutch blends from source to destination, and the
    /// orientation and Aux1 move.
    pub window: (f64, f64),
    /// C at the start and at the end.
    pub c: (f64, f64),
    /// Aux1 at the start and at the end.
    pub aux: (f64, f64),
    /// A and B, held.
    pub ab: [f64; 2],
    /// Total virtual duration.
    pub duration: f64,
    /// Arc lengths of the profile points passed (for iProfilePointPassed).
    pub points: Vec<f64>,
    /// P: what the source belt is predicted to have added by the end of the move.
    pub src_final: [f64; 3],
    /// The path limits the plan settled on (after any slowing for the axes); a resumed
    /// stretch uses them again.
    pub law: super::law::Limits,
}

/// 0 → 1 with zero first and second derivatives at both ends, so a blend that starts while
/// the path is moving adds no step in acceleration.
pub fn smooth5(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    (x * x * x * (10.0 + x * (6.0 * x - 15.0))).clamp(0.0, 1.0)
}

impl Trajectory {
    /// The path state at virtual time `tau` (clamped to the move).
    pub fn state(&self, tau: f64) -> PathState {
        let Some(last) = self.legs.last() else {
            return PathState::default();
        };
        let leg = self
            .legs
            .iter()
            .rev()
            .find(|l| tau >= l.t0)
            .unwrap_or(&self.legs[0]);
        if tau >= self.duration {
            return PathState {
                s: last.s0 + last.law.length(),
                ..PathState::default()
            };
        }
        let st = leg.law.sample(tau - leg.t0);
        PathState {
            s: leg.s0 + st.s,
            v: st.v,
            a: st.a,
        }
    }

    /// The clutch weight at arc length `s`.
    pub fn weight(&self, s: f64) -> f64 {
        let (a, b) = self.window;
        if b > a {
            smooth5((s - a) / (b - a))
        } else if s >= b {
            1.0
        } else {
            0.0
        }
    }

    /// What the source belt adds to the setpoint while it travels `d` with the tool at arc
    /// length `s`.
    pub fn src_step(&self, s: f64, d: f64) -> [f64; 3] {
        match &self.src {
            Some(f) => {
                let k = (1.0 - self.weight(s)) * d;
                [f.dir[0] * k, f.dir[1] * k, f.dir[2] * k]
            }
            None => [0.0; 3],
        }
    }

    /// The setpoint at arc length `s` with the source's contribution so far `src` and the
    /// belts at `travel`.
    pub fn pose_at(&self, s: f64, src: [f64; 3], travel: &[f64]) -> Pose {
        let w = self.weight(s);
        let mut p = self.path.point(s);
        for k in 0..3 {
            p[k] += src[k] + w * (self.src_final[k] - src[k]);
        }
        if let Some(f) = &self.dst {
            let o = f.offset(travel);
            for k in 0..3 {
                p[k] += w * o[k];
            }
        }
        Pose {
            p,
            ab: self.ab,
            c: self.c.0 + w * (self.c.1 - self.c.0),
            aux: self.aux.0 + w * (self.aux.1 - self.aux.0),
        }
    }

    /// The arc length at the end.
    pub fn length(&self) -> f64 {
        self.path.length()
    }

    /// How many profile points lie at or before arc length `s`.
    pub fn points_passed(&self, s: f64) -> usize {
        self.points.iter().filter(|&&p| p <= s + 1e-9).count()
    }
}
