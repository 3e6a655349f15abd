//! Path preparation: from where the tool is to a goal (a static position, a workpiece on a
//! belt, a parking position), the geometry through the intermediate points, the motion law
//! along it, and the interception of a moving workpiece; then the move is checked at every
//! servo update it will take, and slowed (uniformly in time) until no axis — Cartesian or
//! real — exceeds its velocity, acceleration or jerk, with the followed belts' own limits
//! kept in reserve so a belt changing speed mid-move cannot push an axis over.
//!
//! [`PlanJob`] prepares a move in steps of bounded work (so a caller can spread it over
//! updates); [`Planner::plan`] runs one to its end.

use super::law::{DoubleS, Limits};
use super::path::{self, Path, P3};
use super::robot::{Pose, Robot, AXES, AXIS_NAMES};
use super::setup::AxisLimit;
use super::track::Belt;
use super::trajectory::{Follow, Leg, Trajectory};
use crate::devices::pickplace::kinematics::KinematicsError;

/// How the path is shaped and how fast it may go (the module's parameters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathParams {
    /// lrPathVel, lrPathAcc, lrPathDec, lrPathJerk.
    pub law: Limits,
    /// lrBlendingRadius.
    pub radius: f64,
    /// ePathMode = 1.
    pub elliptical: bool,
    /// lrZDistElliptical.
    pub ellipse_height: f64,
}

/// Where a move goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal {
    /// A static position; the approach comes from `approach` above it (lrZTargetDist).
    Point {
        /// The target pose.
        pose: Pose,
        /// Height of Intermediate Point 2 above it.
        approach: f64,
    },
    /// A workpiece on a belt, met where the belt will have carried it.
    Workpiece {
        /// Index of the belt in the module's list.
        belt: usize,
        /// The workpiece's id.
        id: u32,
        /// Height of Intermediate Point 2 above it (the belt's lrZDistBelt).
        approach: f64,
        /// Aux1 at the target (the belt input's lrAux1TargetPos).
        aux: f64,
        /// The operating range's end (lrUpperSyncLimit) and how far the belt carries the
        /// workpiece during the synchronous travel: a workpiece met so far downstream that
        /// `x + carry > upper` cannot be taken, so a move to it that fails its check is given
        /// back unchecked instead of an error (the caller drops the workpiece as missed; a path
        /// it will never run cannot fail a limit).
        upper: f64,
        /// See `upper`.
        carry: f64,
    },
    /// A parking position, reached by two blended lines.
    Park {
        /// The parking pose.
        pose: Pose,
    },
}

/// A move to prepare.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Request {
    /// The tool's pose now.
    pub start: Pose,
    /// The belt the tool moves with now, if any.
    pub src: Option<Follow>,
    /// Height of Intermediate Point 1 above the start.
    pub lift: f64,
    /// Where to.
    pub goal: Goal,
}

/// The longest move the planner checks, seconds (see `CheckRun`).
pub const MAX_MOVE_SECONDS: f64 = 3600.0;

/// Why a move cannot be prepared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// A point of the path is out of the robot's reach.
    #[error("no kinematic solution on the planned path: {0}")]
    NoSolution(KinematicsError),
    /// The path crosses a software limit position.
    #[error(
        "the planned path takes axis {axis} to {value:.3}, beyond its software limit {limit:.3}"
    )]
    SwLimit {
        /// Manual axis name.
        axis: &'static str,
        /// Where the path would take it.
        value: f64,
        /// The limit.
        limit: f64,
        /// True for the upper limit.
        upper: bool,
    },
    /// An axis cannot keep up even with the path slowed down.
    #[error("axis {axis} cannot keep within its {what} limit on this path ({detail})")]
    Limits {
        /// Manual axis name.
        axis: &'static str,
        /// "velocity", "acceleration" or "jerk".
        what: &'static str,
        /// Why.
        detail: String,
    },
    /// A parameter makes no path.
    #[error("{0}")]
    Param(String),
    /// The workpiece is no longer tracked, or its position is unknown.
    #[error("workpiece {0} is not tracked")]
    Gone(u32),
}

/// A prepared move.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    /// The move.
    pub traj: Trajectory,
    /// For a workpiece: its X on the belt when the tool arrives.
    pub arrival_x: Option<f64>,
    /// The time scale the limits imposed (1: none).
    pub scale: f64,
    /// Limit checks run (planning iterations).
    pub iterations: u32,
}

/// The planner: the robot, its limits, and the servo update the moves are checked at.
#[derive(Debug, Clone)]
pub struct Planner {
    /// Robot and axis limits (Cartesian from the parameters, real axes from the machine).
    pub robot: Robot,
    /// Software limits in force, per manual axis.
    pub sw: [Option<(f64, f64)>; AXES],
    /// Servo update, s.
    pub dt: f64,
    /// The belts' own limits, per belt index.
    pub belt_limits: Vec<AxisLimit>,
}

/// Share of each limit the plan may use; the rest absorbs what the plan cannot predict (the
/// second-order effect of a belt's speed change on a Delta3's joints).
const MARGIN: f64 = 0.97;
/// Finite-difference step for a joint's sensitivity to belt travel, mm.
const EPS: f64 = 1e-3;

fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn up(h: f64) -> P3 {
    [0.0, 0.0, h]
}

/// Peak use of each kind of limit, relative to what is allowed (≤ 1: within).
#[derive(Debug, Clone, Copy, Default)]
struct Use {
    ratio: [f64; 3],
    axis: [usize; 3],
}

/// Work units a [`PlanJob`] step counts (a path preparation's cost in updates computed, so a
/// budget of them splits it the same way on every run): one update of the source belt's
/// predicted share, one move built from its geometry and law, one update of the limit check.
pub mod cost {
    /// One update summed for the source belt's predicted share.
    pub const SRC_UPDATE: u64 = 1;
    /// One interception round's move: geometry, motion law, legs.
    pub const ROUND: u64 = 20;
    /// One update of the limit check: the pose, the kinematics, every axis.
    pub const CHECK_UPDATE: u64 = 8;
}

/// A path preparation done in steps of bounded work: the same plan as [`Planner::plan`], which
/// runs one to its end, step by step, so that a caller can spread it over updates. Every step
/// must be given the same belts (as they were, or are predicted to be, for the move's start).
#[derive(Debug, Clone)]
pub struct PlanJob {
    req: Request,
    params: PathParams,
    scale: f64,
    iterations: u32,
    stage: Stage,
}

#[derive(Debug, Clone)]
enum Stage {
    /// Solving the interception at the present scale.
    Shape(Box<Shape>),
    /// Checking the move against every limit at every update.
    Check(Box<CheckRun>),
    /// The result has been given.
    Ended,
}

/// The interception solve in progress: arrival time, belt travel and the source belt's
/// predicted share (P) iterated until they agree (at most eight rounds).
#[derive(Debug, Clone)]
struct Shape {
    law: Limits,
    src_speed: f64,
    round: u32,
    t_arrive: f64,
    secant: Option<(f64, f64)>,
    shift: [f64; 3],
    out: Option<(Trajectory, Option<f64>)>,
    /// The round's move, and its source share summed so far: next update `k` of `n`, `sum`.
    cur: Option<(Trajectory, Option<f64>, i64, i64, f64)>,
}

impl Shape {
    fn new(law: Limits, src_speed: f64) -> Shape {
        Shape {
            law,
            src_speed,
            round: 0,
            t_arrive: 0.0,
            secant: None,
            shift: [0.0; 3],
            out: None,
            cur: None,
        }
    }
}

impl PlanJob {
    /// A preparation of `req`, not started.
    pub fn new(req: &Request, params: &PathParams, belts: &[Belt]) -> PlanJob {
        let mut job = PlanJob {
            req: *req,
            params: *params,
            scale: 1.0,
            iterations: 1,
            stage: Stage::Ended,
        };
        job.stage = Stage::Shape(Box::new(Shape::new(job.law(), job.src_speed(belts))));
        job
    }

    /// The request being prepared.
    pub fn request(&self) -> &Request {
        &self.req
    }

    fn law(&self) -> Limits {
        let (p, scale) = (self.params.law, self.scale);
        Limits {
            vel: p.vel * scale,
            acc: p.acc * scale * scale,
            dec: p.dec * scale * scale,
            jerk: p.jerk * scale * scale * scale,
        }
    }

    /// The error a move's check ended in — unless the move meets its workpiece beyond the
    /// operating range: the caller drops such a workpiece as missed, and a path that will
    /// never run raises no error. The move is given back as it is, unchecked.
    fn unless_beyond(&self, e: PlanError, run: CheckRun) -> Result<Planned, PlanError> {
        match (self.req.goal, run.arrival_x) {
            (Goal::Workpiece { upper, carry, .. }, Some(x)) if x + carry > upper => Ok(Planned {
                traj: run.traj,
                arrival_x: run.arrival_x,
                scale: self.scale,
                iterations: self.iterations,
            }),
            _ => Err(e),
        }
    }

    fn src_speed(&self, belts: &[Belt]) -> f64 {
        self.req
            .src
            .map_or(0.0, |f| belts.get(f.belt).map_or(0.0, |b| b.velocity))
    }

    /// Go on with at most about `budget` work units ([`cost`]); the result once it is there
    /// (`None`: not yet). Asked again after the result, it is an error.
    pub fn step(
        &mut self,
        planner: &Planner,
        belts: &[Belt],
        budget: u64,
    ) -> Option<Result<Planned, PlanError>> {
        let mut left = budget;
        self.step_within(planner, belts, &mut left)
    }

    /// [`PlanJob::step`] with the units still `left` in a budget shared with other work: what
    /// the step did not use stays in it (a step may overrun by one piece of work, less than
    /// [`cost::ROUND`]; `left` is then 0).
    pub fn step_within(
        &mut self,
        planner: &Planner,
        belts: &[Belt],
        left: &mut u64,
    ) -> Option<Result<Planned, PlanError>> {
        loop {
            let stage = std::mem::replace(&mut self.stage, Stage::Ended);
            match stage {
                Stage::Ended => {
                    return Some(Err(PlanError::Param(
                        "the path preparation has already ended".into(),
                    )))
                }
                Stage::Shape(mut sh) => {
                    let (traj, arrival_x) =
                        match planner.shape_step(&self.req, &self.params, &mut sh, belts, left) {
                            Err(e) => return Some(Err(e)),
                            Ok(None) => {
                                self.stage = Stage::Shape(sh);
                                return None;
                            }
                            Ok(Some(done)) => done,
                        };
                    // The check runs through every update of the move: a move longer than
                    // this (a path of a million kilometres) is refused rather than checked
                    // for hours.
                    if traj.duration.is_nan() || traj.duration > MAX_MOVE_SECONDS {
                        return Some(Err(PlanError::Param(format!(
                            "the path would take {} s; a move may take at most {MAX_MOVE_SECONDS} s",
                            crate::diag::number(traj.duration)
                        ))));
                    }
                    let run = CheckRun::new(planner, traj, arrival_x, belts);
                    self.stage = Stage::Check(Box::new(run));
                }
                Stage::Check(mut run) => {
                    let used = match run.step(planner, left) {
                        None => {
                            self.stage = Stage::Check(run);
                            return None;
                        }
                        Some(Err(e)) => return Some(self.unless_beyond(e, *run)),
                        Some(Ok(used)) => used,
                    };
                    let worst = used.ratio.iter().cloned().fold(0.0, f64::max);
                    if worst <= 1.0 {
                        return Some(Ok(Planned {
                            traj: run.traj,
                            arrival_x: run.arrival_x,
                            scale: self.scale,
                            iterations: self.iterations,
                        }));
                    }
                    if self.iterations >= 12 {
                        let k = (0..3)
                            .max_by(|&a, &b| used.ratio[a].total_cmp(&used.ratio[b]))
                            .unwrap_or(0);
                        let e = PlanError::Limits {
                            axis: AXIS_NAMES[used.axis[k]],
                            what: ["velocity", "acceleration", "jerk"][k],
                            detail: format!(
                                "still {:.0} % of the limit with the path slowed to {:.4} of its speed",
                                used.ratio[k] * 100.0,
                                self.scale
                            ),
                        };
                        return Some(self.unless_beyond(e, *run));
                    }
                    // Time scaling by λ scales velocity by λ, acceleration by λ², jerk by λ³.
                    let f = [used.ratio[0], used.ratio[1].sqrt(), used.ratio[2].cbrt()]
                        .into_iter()
                        .fold(1.0, f64::max);
                    self.scale *= 0.995 / f;
                    self.iterations += 1;
                    self.stage =
                        Stage::Shape(Box::new(Shape::new(self.law(), self.src_speed(belts))));
                }
            }
        }
    }
}

impl Planner {
    /// Prepare a move. `belts` as the module tracks them now.
    pub fn plan(
        &self,
        req: &Request,
        params: &PathParams,
        belts: &[Belt],
    ) -> Result<Planned, PlanError> {
        let mut job = PlanJob::new(req, params, belts);
        loop {
            // An unbounded budget ends the job in one step.
            if let Some(done) = job.step(self, belts, u64::MAX) {
                return done;
            }
        }
    }

    /// The interception solve of `sh`, with `left` work units; the move once the arrival
    /// time, the place the belt carries a workpiece to, and the source belt's predicted share
    /// (P) agree (or eight rounds are done).
    fn shape_step(
        &self,
        req: &Request,
        params: &PathParams,
        sh: &mut Shape,
        belts: &[Belt],
        left: &mut u64,
    ) -> Result<Option<(Trajectory, Option<f64>)>, PlanError> {
        loop {
            let (traj, x, k, n, sum) = match sh.cur.take() {
                Some(cur) => cur,
                None => {
                    if sh.round >= 8 {
                        return sh
                            .out
                            .take()
                            .map(Some)
                            .ok_or_else(|| PlanError::Param("no path".into()));
                    }
                    if *left == 0 {
                        return Ok(None);
                    }
                    *left = left.saturating_sub(cost::ROUND);
                    let (traj, x) =
                        self.round(req, params, sh.law, belts, sh.t_arrive, sh.shift)?;
                    let n = match traj.src {
                        Some(_) => (traj.duration / self.dt).ceil() as i64,
                        None => 0,
                    };
                    (traj, x, 1, n, 0.0)
                }
            };
            // What the source belt adds over the move at its present speed, summed update by
            // update as the interpolator does.
            let (mut k, mut sum) = (k, sum);
            while k <= n {
                if *left == 0 {
                    sh.cur = Some((traj, x, k, n, sum));
                    return Ok(None);
                }
                *left = left.saturating_sub(cost::SRC_UPDATE);
                let s = traj.state(k as f64 * self.dt).s;
                sum += 1.0 - traj.weight(s);
                k += 1;
            }
            let p = match traj.src {
                Some(f) => {
                    let d = sh.src_speed * self.dt * sum;
                    [f.dir[0] * d, f.dir[1] * d, f.dir[2] * d]
                }
                None => [0.0; 3],
            };
            // Nothing below depends on these agreeing exactly (the end is exact anyway): they
            // only make the prediction good, to well under a micrometre of belt travel.
            let f = traj.duration - sh.t_arrive;
            let settled = f.abs() < 1e-7 && (0..3).all(|k| (p[k] - sh.shift[k]).abs() < 1e-6);
            // Secant steps on arrival time = duration: the fixed point converges only as fast
            // as the belt is slow against the path.
            let next = match sh.secant {
                Some((t0, f0)) if (f - f0).abs() > 1e-15 => {
                    sh.t_arrive - f * (sh.t_arrive - t0) / (f - f0)
                }
                _ => traj.duration,
            };
            sh.secant = Some((sh.t_arrive, f));
            sh.t_arrive = if next.is_finite() && next >= 0.0 {
                next
            } else {
                traj.duration
            };
            sh.shift = p;
            sh.round += 1;
            if settled {
                return Ok(Some((traj, x)));
            }
            sh.out = Some((traj, x));
        }
    }

    /// One interception round's move: the geometry and law for limits `law`, the goal met
    /// where the belt will be at `t_arrive`, the end shifted back by the source's share `shift`.
    fn round(
        &self,
        req: &Request,
        params: &PathParams,
        law: Limits,
        belts: &[Belt],
        t_arrive: f64,
        shift: P3,
    ) -> Result<(Trajectory, Option<f64>), PlanError> {
        let start = req.start.p;
        let minus = |p: P3| [p[0] - shift[0], p[1] - shift[1], p[2] - shift[2]];
        Ok(match req.goal {
            Goal::Point { pose, approach } => {
                let ip1 = add(start, up(req.lift));
                let ip2 = minus(add(pose.p, up(approach)));
                let path = self.geometry(start, ip1, ip2, minus(pose.p), params)?;
                let t = self.finish(path, req, params, law, None, pose.c, pose.aux, shift)?;
                (t, None)
            }
            Goal::Park { pose } => {
                let ip1 = add(start, up(req.lift + params.ellipse_height));
                let r = params.ellipse_height + params.radius;
                let path = path::blended(&[start, ip1, minus(pose.p)], r)
                    .map_err(|e| PlanError::Param(e.to_string()))?;
                let p = PathParams {
                    elliptical: false,
                    radius: r,
                    ..*params
                };
                let t = self.finish(path, req, &p, law, None, pose.c, pose.aux, shift)?;
                (t, None)
            }
            Goal::Workpiece {
                belt,
                id,
                approach,
                aux,
                ..
            } => {
                let b = belts.get(belt).ok_or(PlanError::Gone(id))?;
                let w = b
                    .pieces
                    .iter()
                    .find(|w| w.id == id && w.pos0.is_some())
                    .ok_or(PlanError::Gone(id))?;
                let base = b.travel + b.velocity * t_arrive;
                let end = b.position_of(w, base).ok_or(PlanError::Gone(id))?;
                let ip1 = add(start, up(req.lift));
                let ip2 = minus(add(end, b.frame.rotate(up(approach))));
                let path = self.geometry(start, ip1, ip2, minus(end), params)?;
                let follow = Follow {
                    belt,
                    dir: b.direction(),
                    base,
                };
                let t = self.finish(path, req, params, law, Some(follow), b.c_of(w), aux, shift)?;
                // Where the workpiece really is when this move ends: the arrival the range
                // is checked with, whether or not the arrival time settled.
                let x = w.belt_x(b.travel + b.velocity * t.duration);
                (t, x)
            }
        })
    }

    fn geometry(
        &self,
        start: P3,
        ip1: P3,
        ip2: P3,
        end: P3,
        params: &PathParams,
    ) -> Result<Path, PlanError> {
        let r = if params.elliptical {
            path::elliptical(start, ip1, ip2, end, params.ellipse_height, params.radius)
        } else {
            path::blended(&[start, ip1, ip2, end], params.radius)
        };
        r.map_err(|e| PlanError::Param(e.to_string()))
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        path: Path,
        req: &Request,
        params: &PathParams,
        law: Limits,
        dst: Option<Follow>,
        c: f64,
        aux: f64,
        src_final: P3,
    ) -> Result<Trajectory, PlanError> {
        let length = path.length();
        let marks: Vec<f64> = path.marks().to_vec();
        let (first, last) = match (marks.first(), marks.last()) {
            (Some(&a), Some(&b)) if b > a => (a, b),
            _ => (0.0, length),
        };
        // Blended: one rest-to-rest law over the whole path. Not blended: the tool stops at
        // each intermediate point (path speed 0 there), so each stretch has its own law.
        // Wherever the direction still jumps (a corner no arc could round), the tool must stop
        // too.
        let mut stops: Vec<f64> = path.corners().to_vec();
        if params.radius <= 0.0 {
            stops.extend_from_slice(&marks);
        }
        stops.sort_by(f64::total_cmp);
        let mut cuts = vec![0.0];
        for m in stops {
            if m > cuts[cuts.len() - 1] + 1e-9 && m < length - 1e-9 {
                cuts.push(m);
            }
        }
        cuts.push(length);
        let mut legs = Vec::with_capacity(cuts.len());
        let mut t0 = 0.0;
        for k in 0..cuts.len() - 1 {
            let law = DoubleS::plan(cuts[k + 1] - cuts[k], law)
                .map_err(|e| PlanError::Param(e.to_string()))?;
            legs.push(Leg {
                s0: cuts[k],
                t0,
                law,
            });
            t0 += law.duration();
        }
        let mut points = marks;
        points.push(length);
        Ok(Trajectory {
            path,
            legs,
            src: req.src,
            dst,
            window: (first, last),
            c: (req.start.c, c),
            aux: (req.start.aux, aux),
            ab: req.start.ab,
            duration: t0,
            points,
            src_final,
            law,
        })
    }
}

/// The limit check in progress: the move run at the servo update with the belts at their
/// present speeds, measuring per axis the discrete velocity, acceleration and jerk the drives
/// will see.
#[derive(Debug, Clone)]
struct CheckRun {
    traj: Trajectory,
    arrival_x: Option<f64>,
    follows: Vec<Follow>,
    /// What the followed belts may still add, per axis: velocity, acceleration, jerk.
    reserve: [[f64; 3]; AXES],
    travel_now: Vec<f64>,
    speed: Vec<f64>,
    travel: Vec<f64>,
    /// The next update to check (from −3: the tool's last updates before the move).
    n: i64,
    n_end: i64,
    hist: [[f64; AXES]; 4],
    used: Use,
    src_speed: f64,
    src_off: [f64; 3],
    sens: [f64; 3],
}

/// Each belt's travel `t` seconds from now at its present speed, into `travel`. Zipped rather
/// than indexed: the compiler then needs no bounds check per belt and vectorises the loop, which
/// runs at every update the limit check looks at (indexing the three vectors through the
/// check's state made the whole preparation about 5 % slower).
fn belts_at(travel: &mut [f64], now: &[f64], speed: &[f64], t: f64) {
    for ((x, x0), v) in travel.iter_mut().zip(now).zip(speed) {
        *x = x0 + v * t;
    }
}

impl CheckRun {
    fn new(
        planner: &Planner,
        traj: Trajectory,
        arrival_x: Option<f64>,
        belts: &[Belt],
    ) -> CheckRun {
        let follows: Vec<Follow> = traj.src.iter().chain(traj.dst.iter()).copied().collect();
        // What the followed belts may still add: the rest of their speed range, all of their
        // acceleration and jerk, along each Cartesian axis.
        let mut reserve = [[0.0; 3]; AXES];
        for f in &follows {
            let lim = planner.belt_limits.get(f.belt).copied().unwrap_or_default();
            let v_now = belts.get(f.belt).map_or(0.0, |b| b.velocity);
            for (i, r) in reserve.iter_mut().enumerate().take(3) {
                let comp = f.dir[i].abs();
                r[0] = f64::max(r[0], comp * (lim.max_vel - v_now).max(0.0));
                r[1] = f64::max(r[1], comp * lim.max_acc);
                r[2] = f64::max(r[2], comp * lim.max_jerk);
            }
        }
        let travel_now: Vec<f64> = belts.iter().map(|b| b.travel).collect();
        let speed: Vec<f64> = belts.iter().map(|b| b.velocity).collect();
        let travel = travel_now.clone();
        let n_end = (traj.duration / planner.dt).ceil() as i64 + 3;
        let src_speed = traj
            .src
            .map_or(0.0, |f| speed.get(f.belt).copied().unwrap_or(0.0));
        CheckRun {
            traj,
            arrival_x,
            follows,
            reserve,
            travel_now,
            speed,
            travel,
            n: -3,
            n_end,
            hist: [[0.0; AXES]; 4],
            used: Use::default(),
            src_speed,
            src_off: [0.0; 3],
            sens: [0.0; 3],
        }
    }

    /// Go on with `left` work units: the peak use of each kind of limit once every update is
    /// checked (`None`: not yet).
    fn step(&mut self, planner: &Planner, left: &mut u64) -> Option<Result<Use, PlanError>> {
        let dt = planner.dt;
        let robot = &planner.robot;
        while self.n <= self.n_end {
            if *left == 0 {
                return None;
            }
            *left = left.saturating_sub(cost::CHECK_UPDATE);
            let n = self.n;
            let k = (n + 3) as usize;
            self.n += 1;
            let t = n as f64 * dt;
            belts_at(&mut self.travel, &self.travel_now, &self.speed, t);
            let traj = &self.traj;
            let st = traj.state(t.max(0.0));
            if n <= 0 {
                // Before the move the tool rides the source belt.
                let src_speed = self.src_speed;
                self.src_off = traj.src.map_or([0.0; 3], |f| {
                    let d = src_speed * t;
                    [f.dir[0] * d, f.dir[1] * d, f.dir[2] * d]
                });
            } else {
                let step = traj.src_step(st.s, self.src_speed * dt);
                for (o, x) in self.src_off.iter_mut().zip(step) {
                    *o += x;
                }
            }
            let pose = traj.pose_at(st.s, self.src_off, &self.travel);
            let q = match robot.axes(&pose) {
                Ok(q) => q,
                Err(e) => return Some(Err(PlanError::NoSolution(e))),
            };
            for (i, lim) in planner.sw.iter().enumerate() {
                if let Some((lo, hi)) = lim {
                    if robot.has_axis(i) && (q[i] < *lo || q[i] > *hi) {
                        let upper = q[i] > *hi;
                        return Some(Err(PlanError::SwLimit {
                            axis: AXIS_NAMES[i],
                            value: q[i],
                            limit: if upper { *hi } else { *lo },
                            upper,
                        }));
                    }
                }
            }
            let hist = &mut self.hist;
            hist.rotate_right(1);
            hist[0] = q;
            if k < 3 {
                continue;
            }
            // Joints: how much a millimetre of belt travel moves each, here. It changes
            // slowly along the path (and the reserve it sizes is a small share of the limit):
            // every eighth update is enough.
            if k % 8 == 3 && matches!(robot.kinematics, super::setup::Kinematics::Delta3(_)) {
                self.sens = [0.0; 3];
                for f in &self.follows {
                    let mut p2 = pose;
                    for (x, d) in p2.p.iter_mut().zip(f.dir) {
                        *x += d * EPS;
                    }
                    let q2 = match robot.axes(&p2) {
                        Ok(q) => q,
                        Err(e) => return Some(Err(PlanError::NoSolution(e))),
                    };
                    for j in 0..3 {
                        self.sens[j] = self.sens[j].max((q2[6 + j] - q[6 + j]).abs() / EPS);
                    }
                }
            }
            for i in 0..AXES {
                let lim = robot.limits[i];
                if !robot.has_axis(i) {
                    continue;
                }
                let mut r = self.reserve[i];
                if (6..9).contains(&i) {
                    let bl = self
                        .follows
                        .iter()
                        .map(|f| planner.belt_limits.get(f.belt).copied().unwrap_or_default())
                        .fold(AxisLimit::default(), |a, b| AxisLimit {
                            max_vel: a.max_vel.max(b.max_vel),
                            max_acc: a.max_acc.max(b.max_acc),
                            max_jerk: a.max_jerk.max(b.max_jerk),
                        });
                    let s = self.sens[i - 6];
                    r = [s * bl.max_vel, s * bl.max_acc, s * bl.max_jerk];
                }
                let h = |m: usize| self.hist[m][i];
                let v = (h(0) - h(1)) / dt;
                let a = (h(0) - 2.0 * h(1) + h(2)) / (dt * dt);
                let j = (h(0) - 3.0 * h(1) + 3.0 * h(2) - h(3)) / (dt * dt * dt);
                for (kind, (x, l)) in [(v, lim.max_vel), (a, lim.max_acc), (j, lim.max_jerk)]
                    .into_iter()
                    .enumerate()
                {
                    if l <= 0.0 {
                        continue;
                    }
                    let allowed = (l - r[kind]) * MARGIN;
                    let ratio = if allowed > 0.0 {
                        x.abs() / allowed
                    } else {
                        f64::INFINITY
                    };
                    if ratio > self.used.ratio[kind] {
                        self.used.ratio[kind] = ratio;
                        self.used.axis[kind] = i;
                    }
                }
            }
        }
        let used = self.used;
        if used.ratio.iter().any(|r| r.is_infinite()) {
            let k = used.ratio.iter().position(|r| r.is_infinite()).unwrap_or(0);
            return Some(Err(PlanError::Limits {
                axis: AXIS_NAMES[used.axis[k]],
                what: ["velocity", "acceleration", "jerk"][k],
                detail: "the followed belt's own limit leaves nothing for the path".into(),
            }));
        }
        Some(Ok(used))
    }
}
