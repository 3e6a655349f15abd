//! The master axis (an encoder on the conveyor) as the scenario drives it: a piecewise speed
//! profile of constant speeds and linear ramps. Position is exact at any instant (piecewise
//! quadratic), and so is the first instant the master reaches a position, which is how product
//! edges tied to master positions get their times.

/// One piece of the profile: from `t0`, position `p0 + v0·dt + a·dt²/2`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    t0: f64,
    p0: f64,
    v0: f64,
    a: f64,
}

/// A speed change: from `at`, ramp linearly to `speed` over `ramp` seconds (0: at once).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedChange {
    /// Start of the change, seconds.
    pub at: f64,
    /// Target speed, master units per second (never negative: a conveyor runs forward).
    pub speed: f64,
    /// Duration of the ramp, seconds.
    pub ramp: f64,
}

/// Why a speed profile cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileError {
    /// Index of the offending change.
    pub change: usize,
    /// What is wrong.
    pub message: String,
}

/// The master's motion over the whole run.
#[derive(Debug, Clone, PartialEq)]
pub struct MasterProfile {
    pieces: Vec<Piece>,
}

impl Default for MasterProfile {
    fn default() -> Self {
        MasterProfile {
            pieces: vec![Piece {
                t0: 0.0,
                p0: 0.0,
                v0: 0.0,
                a: 0.0,
            }],
        }
    }
}

impl MasterProfile {
    /// A profile starting at position 0 with speed `initial`, then the changes in time order.
    pub fn new(initial: f64, changes: &[SpeedChange]) -> Result<MasterProfile, ProfileError> {
        if !(initial.is_finite() && initial >= 0.0) {
            return Err(ProfileError {
                change: usize::MAX,
                message: format!("the initial speed must be 0 or more, not {initial}"),
            });
        }
        let mut pieces = vec![Piece {
            t0: 0.0,
            p0: 0.0,
            v0: initial,
            a: 0.0,
        }];
        let mut busy_until = 0.0f64;
        for (i, c) in changes.iter().enumerate() {
            let bad = |message: String| Err(ProfileError { change: i, message });
            if !(c.speed.is_finite() && c.speed >= 0.0) {
                return bad(format!("a speed must be 0 or more, not {}", c.speed));
            }
            if !(c.ramp.is_finite() && c.ramp >= 0.0) {
                return bad(format!("a ramp must take 0 s or more, not {}", c.ramp));
            }
            if !(c.at.is_finite() && c.at >= busy_until) || (i > 0 && c.at <= changes[i - 1].at) {
                return bad(format!(
                    "this change at {} s starts before the previous one has finished ({} s); changes must come in time order",
                    c.at, busy_until
                ));
            }
            let last = *pieces.last().unwrap_or(&Piece {
                t0: 0.0,
                p0: 0.0,
                v0: 0.0,
                a: 0.0,
            });
            let (p, v) = last.at(c.at);
            if c.ramp > 0.0 {
                pieces.push(Piece {
                    t0: c.at,
                    p0: p,
                    v0: v,
                    a: (c.speed - v) / c.ramp,
                });
                let (p2, _) = pieces[pieces.len() - 1].at(c.at + c.ramp);
                pieces.push(Piece {
                    t0: c.at + c.ramp,
                    p0: p2,
                    v0: c.speed,
                    a: 0.0,
                });
            } else {
                pieces.push(Piece {
                    t0: c.at,
                    p0: p,
                    v0: c.speed,
                    a: 0.0,
                });
            }
            busy_until = c.at + c.ramp;
        }
        Ok(MasterProfile { pieces })
    }

    fn piece(&self, t: f64) -> Piece {
        let i = self.pieces.partition_point(|p| p.t0 <= t).saturating_sub(1);
        self.pieces[i]
    }

    /// Position at `t` seconds.
    pub fn position(&self, t: f64) -> f64 {
        self.piece(t).at(t).0
    }

    /// Speed at `t` seconds.
    pub fn speed(&self, t: f64) -> f64 {
        self.piece(t).at(t).1
    }

    /// The master moves at `t` seconds or will move later (the scenario changes its speed).
    pub fn moves_from(&self, t: f64) -> bool {
        self.speed(t) != 0.0 || self.pieces.last().is_some_and(|p| p.t0 > t)
    }

    /// The first instant at which the master is at `p` or beyond, if it ever gets there.
    pub fn time_at(&self, p: f64) -> Option<f64> {
        if p <= 0.0 {
            return Some(0.0);
        }
        for (i, piece) in self.pieces.iter().enumerate() {
            let end = self.pieces.get(i + 1).map(|n| n.t0);
            let reach = match end {
                Some(t1) => piece.at(t1).0,
                None => f64::INFINITY,
            };
            if p > reach || (end.is_none() && piece.v0 <= 0.0 && piece.a <= 0.0) {
                // Not in this piece; the last piece never gets there.
                end?;
                continue;
            }
            let d = p - piece.p0;
            if d <= 0.0 {
                return Some(piece.t0);
            }
            // Solve a/2·dt² + v0·dt = d in a form that stays accurate when a is tiny.
            let root = (piece.v0 * piece.v0 + 2.0 * piece.a * d).max(0.0).sqrt();
            let denom = piece.v0 + root;
            if denom <= 0.0 {
                continue;
            }
            let t = piece.t0 + 2.0 * d / denom;
            return Some(match end {
                Some(t1) => t.min(t1),
                None => t,
            });
        }
        None
    }
}

impl Piece {
    fn at(self, t: f64) -> (f64, f64) {
        let dt = t - self.t0;
        (
            self.p0 + self.v0 * dt + 0.5 * self.a * dt * dt,
            self.v0 + self.a * dt,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn constant_speed() {
        let m = MasterProfile::new(100.0, &[]).expect("profile");
        assert!(close(m.position(2.5), 250.0));
        assert!(close(m.time_at(250.0).expect("reached"), 2.5));
    }

    #[test]
    fn ramp_stop_and_restart() {
        let changes = [
            SpeedChange {
                at: 1.0,
                speed: 0.0,
                ramp: 0.5,
            },
            SpeedChange {
                at: 2.0,
                speed: 200.0,
                ramp: 1.0,
            },
        ];
        let m = MasterProfile::new(100.0, &changes).expect("profile");
        // 100 units in the first second, 25 on the ramp down, still during the stop.
        assert!(close(m.position(1.5), 125.0));
        assert!(close(m.position(2.0), 125.0));
        assert_eq!(m.speed(1.75), 0.0);
        // Ramp up 0 → 200 over 1 s: 100 units; then 200/s.
        assert!(close(m.position(3.0), 225.0));
        assert!(close(m.position(4.0), 425.0));
        // A position reached during the stop is reached when the stop begins.
        assert!(close(m.time_at(125.0).expect("reached"), 1.5));
        for p in [10.0, 110.0, 124.9, 125.5, 180.0, 300.0] {
            let t = m.time_at(p).expect("reached");
            assert!(close(m.position(t), p), "{p}: t={t} pos={}", m.position(t));
        }
    }

    #[test]
    fn never_reached_when_stopped_for_good() {
        let m = MasterProfile::new(
            10.0,
            &[SpeedChange {
                at: 1.0,
                speed: 0.0,
                ramp: 0.0,
            }],
        )
        .expect("profile");
        assert_eq!(m.time_at(10.5), None);
        assert!(close(m.time_at(5.0).expect("reached"), 0.5));
    }

    #[test]
    fn bad_profiles_are_refused() {
        assert!(MasterProfile::new(-1.0, &[]).is_err());
        let overlapping = [
            SpeedChange {
                at: 1.0,
                speed: 5.0,
                ramp: 2.0,
            },
            SpeedChange {
                at: 2.0,
                speed: 1.0,
                ramp: 0.0,
            },
        ];
        assert_eq!(
            MasterProfile::new(1.0, &overlapping).map_err(|e| e.change),
            Err(1)
        );
    }
}
