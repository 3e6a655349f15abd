//! Path preparation in steps (`PlanJob`, issue 19): stepped with any budget, down to one work
//! unit at a time, it gives exactly the plan `Planner::plan` gives in one go — the move, the
//! arrival, the scale and the iterations, and the same errors.

use pacer::devices::pickplace::frame::Frame;
use pacer::devices::pickplace::kinematics::delta3::Delta3;
use pacer::devices::pickplace::law::Limits;
use pacer::devices::pickplace::plan::{
    Goal, PathParams, PlanError, PlanJob, Planned, Planner, Request,
};
use pacer::devices::pickplace::robot::{Pose, Robot, AXES};
use pacer::devices::pickplace::setup::{AxisLimit, Kinematics};
use pacer::devices::pickplace::track::Belt;
use pacer::devices::pickplace::trajectory::Follow;

const DT: f64 = 0.001;

/// The bench's Delta3 with its Cartesian and joint limits; belts with their own limits.
fn planner(sw: [Option<(f64, f64)>; AXES]) -> Planner {
    let delta = Delta3::new(400.0, 100.0, 250.0, 600.0).expect("a Delta3");
    let mut limits = [AxisLimit::default(); AXES];
    for i in 0..3 {
        limits[i] = AxisLimit {
            max_vel: 3000.0,
            max_acc: 50000.0,
            max_jerk: 6e6,
        };
        limits[6 + i] = AxisLimit {
            max_vel: 600.0,
            max_acc: 12000.0,
            max_jerk: 1.5e6,
        };
    }
    limits[5] = AxisLimit {
        max_vel: 720.0,
        max_acc: 20000.0,
        max_jerk: 2e6,
    };
    Planner {
        robot: Robot {
            kinematics: Kinematics::Delta3(delta),
            limits,
        },
        sw,
        dt: DT,
        belt_limits: vec![
            AxisLimit {
                max_vel: 400.0,
                max_acc: 800.0,
                max_jerk: 8000.0,
            };
            2
        ],
    }
}

/// Belt 1 (products, Y −150) with workpiece 7 at belt X 300, belt 2 (trays, Y +150); both at
/// 250 mm/s, as the mode-3 cell.
fn belts() -> Vec<Belt> {
    [(1, -150.0), (2, 150.0)]
        .into_iter()
        .map(|(number, y)| {
            let mut b = Belt::new(number);
            b.origin = [-500.0, y, -670.0, 0.0, 0.0, 0.0];
            b.frame = Frame::from_pose(b.origin);
            b.travel = 1000.0;
            b.velocity = 250.0;
            b
        })
        .enumerate()
        .map(|(i, mut b)| {
            if i == 0 {
                assert!(b.receive(7, 700.0));
                assert!(b.validate([0.0, 10.0, 20.0, 0.0, 0.0, 5.0]));
            }
            b
        })
        .collect()
}

fn params(elliptical: bool) -> PathParams {
    PathParams {
        law: Limits {
            vel: 3000.0,
            acc: 40000.0,
            dec: 40000.0,
            jerk: 4e6,
        },
        radius: 0.0,
        elliptical,
        ellipse_height: 40.0,
    }
}

/// Requests of every kind: a workpiece on belt 1 from the tray belt (the tool riding it), a
/// static point, a park position; `upper` ends belt 1's operating range.
fn requests(belts: &[Belt], upper: f64) -> Vec<Request> {
    let on_belt2 = Pose {
        p: [-100.0, 150.0, -645.0],
        ..Pose::default()
    };
    let src = Some(Follow {
        belt: 1,
        dir: belts[1].direction(),
        base: belts[1].travel,
    });
    vec![
        Request {
            start: on_belt2,
            src,
            lift: 30.0,
            goal: Goal::Workpiece {
                belt: 0,
                id: 7,
                approach: 30.0,
                aux: 0.0,
                upper,
                carry: 250.0 * 0.04,
            },
        },
        Request {
            start: on_belt2,
            src,
            lift: 30.0,
            goal: Goal::Point {
                pose: Pose {
                    p: [0.0, 0.0, -620.0],
                    c: 30.0,
                    ..Pose::default()
                },
                approach: 30.0,
            },
        },
        Request {
            start: Pose {
                p: [0.0, 0.0, -620.0],
                ..Pose::default()
            },
            src: None,
            lift: 30.0,
            goal: Goal::Park {
                pose: Pose {
                    p: [-180.0, -150.0, -600.0],
                    ..Pose::default()
                },
            },
        },
    ]
}

/// The job run with `budget` units a step; the result and how many steps it took.
fn stepped(
    planner: &Planner,
    req: &Request,
    params: &PathParams,
    belts: &[Belt],
    budget: u64,
) -> (Result<Planned, PlanError>, u64) {
    let mut job = PlanJob::new(req, params, belts);
    assert_eq!(job.request(), req);
    for steps in 1..=10_000_000u64 {
        if let Some(done) = job.step(planner, belts, budget) {
            // Asked again, it has nothing more to give.
            assert!(job.step(planner, belts, budget).is_some_and(|r| r.is_err()));
            return (done, steps);
        }
    }
    panic!("the job did not end");
}

#[test]
fn stepped_preparation_gives_exactly_the_plan_of_one_go() {
    let planner = planner([None; AXES]);
    let belts = belts();
    let mut slowed = 0;
    for elliptical in [false, true] {
        let params = params(elliptical);
        for req in requests(&belts, 700.0) {
            let whole = planner.plan(&req, &params, &belts);
            let plan = whole.as_ref().expect("each request makes a path");
            assert!(plan.traj.duration > 0.1, "{plan:?}");
            slowed += usize::from(plan.iterations > 1);
            for budget in [1, 7, 60, 333, 5000] {
                let (r, steps) = stepped(&planner, &req, &params, &belts, budget);
                assert_eq!(r, whole, "budget {budget}, {req:?}");
                if budget <= 60 {
                    // A move of over 100 updates checked cannot fit into a few small steps.
                    assert!(steps > 20, "budget {budget}: {steps} steps");
                }
            }
        }
    }
    // The jerk-limited joints slow some of these paths: the job has re-planned as well.
    assert!(slowed > 0, "no request needed slowing");
}

#[test]
fn stepped_preparation_gives_the_same_errors_and_early_misses() {
    let belts = belts();
    let params = params(false);
    // Z may not go above −630: every path lifts to −615 or higher.
    let mut sw = [None; AXES];
    sw[2] = Some((-700.0, -630.0));
    let planner = planner(sw);
    for req in requests(&belts, 700.0) {
        let whole = planner.plan(&req, &params, &belts);
        assert!(
            matches!(
                whole,
                Err(PlanError::SwLimit {
                    axis: "Z",
                    upper: true,
                    ..
                })
            ),
            "{whole:?}"
        );
        assert_eq!(stepped(&planner, &req, &params, &belts, 13).0, whole);
    }
    // A workpiece met only beyond the range: the check's error gives way to the move, unchecked,
    // with its arrival (the module drops the workpiece as missed).
    let req = requests(&belts, 100.0).remove(0);
    let whole = planner.plan(&req, &params, &belts);
    let plan = whole.as_ref().expect("an early miss is not an error");
    assert!(plan.arrival_x.is_some_and(|x| x > 100.0), "{plan:?}");
    assert_eq!(stepped(&planner, &req, &params, &belts, 13).0, whole);
}

/// A job stepped within a budget shared with other work (`PlanJob::step_within`, what a caller
/// spreading the preparation over updates uses): it gives the same plan, a spent budget moves
/// it no further, and what the last step did not use is left for the caller.
#[test]
fn a_shared_budget_gives_the_same_plan_and_keeps_what_is_left() {
    let planner = planner([None; AXES]);
    let belts = belts();
    let params = params(false);
    let budget = 300;
    for req in requests(&belts, 700.0) {
        let whole = planner.plan(&req, &params, &belts);
        let mut job = PlanJob::new(&req, &params, &belts);
        // Nothing left: no work done, no result, and the job still gives the same plan later.
        let mut none = 0;
        assert!(job.step_within(&planner, &belts, &mut none).is_none());
        let mut steps = 0u64;
        let (done, left) = loop {
            steps += 1;
            assert!(steps < 1_000_000, "the job did not end");
            let mut left = budget;
            if let Some(done) = job.step_within(&planner, &belts, &mut left) {
                break (done, left);
            }
            // A step that gives nothing has used its whole budget.
            assert_eq!(left, 0, "step {steps}");
        };
        assert_eq!(done, whole, "{req:?}");
        assert!(left < budget, "the last step did some work");
        // The same plan as the job stepped with the same budget each time (`step`).
        let (r, n) = stepped(&planner, &req, &params, &belts, budget);
        assert_eq!((r, n), (whole, steps));
    }
}
