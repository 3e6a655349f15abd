//! Workpiece streams on belts: a detector (camera, light barrier) reports each workpiece when the
//! belt's travel reaches its detection position. The receive edge comes at that exact instant;
//! the position, in the belt's coordinates at the receive instant, is valid `delay` later.

use super::belt::BeltProfile;
use super::products::unit;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// One workpiece as the module is told about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkpieceFeed {
    /// The belt it rides on, 1–16.
    pub belt: u32,
    /// 0-based, in stream order; unique per belt.
    pub id: u32,
    /// Exact time `xWorkpieceOnBeltReceive` rises, seconds.
    pub receive: f64,
    /// Exact time `xValidPos` rises: `receive + delay`, seconds.
    pub valid: f64,
    /// X, Y, Z, A, B, C (mm and degrees) in belt coordinates at the receive instant
    /// (`ascInitialObjectPosition[1..6]`).
    pub position: [f64; 6],
}

/// A stream of workpieces a detector reports on one belt.
#[derive(Debug, Clone, PartialEq)]
pub struct Stream {
    /// The belt, 1–16.
    pub belt: u32,
    /// Belt travel (mm) at each detection, ascending (already expanded from first/pitch/count or
    /// an explicit list, with `missing` removed).
    pub travel: Vec<f64>,
    /// Nominal X, Y, Z (mm) in belt coordinates at detection.
    pub detect: [f64; 3],
    /// ± uniform amplitude of X, Y (mm) and C (degrees).
    pub jitter: [f64; 3],
    /// Nominal C, degrees.
    pub c: f64,
    /// Time from the receive edge to `xValidPos`, seconds (0 or more).
    pub delay: f64,
    /// Seed of the jitter.
    pub seed: u64,
}

/// The feeds of one stream on one belt profile, in time order; detections the belt never reaches
/// are left out.
///
/// Every workpiece draws its jitter (x, y, c, in that order) whether or not the belt reaches it
/// and whatever the amplitudes, so one workpiece's jitter depends only on the seed and its place
/// in the stream, the same on every machine.
pub fn feeds(stream: &Stream, profile: &BeltProfile) -> Vec<WorkpieceFeed> {
    let mut rng = ChaCha8Rng::seed_from_u64(stream.seed);
    let mut out = Vec::with_capacity(stream.travel.len());
    for (i, &travel) in stream.travel.iter().enumerate() {
        let jx = stream.jitter[0] * unit(&mut rng);
        let jy = stream.jitter[1] * unit(&mut rng);
        let jc = stream.jitter[2] * unit(&mut rng);
        let Ok(id) = u32::try_from(i) else {
            break;
        };
        let Some(receive) = profile.time_at(travel) else {
            continue;
        };
        out.push(WorkpieceFeed {
            belt: stream.belt,
            id,
            receive,
            valid: receive + stream.delay,
            position: [
                stream.detect[0] + jx,
                stream.detect[1] + jy,
                stream.detect[2],
                0.0,
                0.0,
                stream.c + jc,
            ],
        });
    }
    // Ascending travels give ascending times already; a stable sort keeps a hand-made stream
    // with travels out of order in time order too.
    out.sort_by(|a, b| a.receive.total_cmp(&b.receive));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unreached_detections_are_left_out() {
        let profile = BeltProfile::new(
            100.0,
            &[crate::world::belt::BeltChange {
                at: 1.0,
                speed: 0.0,
                ramp: 0.0,
            }],
        )
        .expect("profile");
        let stream = Stream {
            belt: 1,
            travel: vec![50.0, 90.0, 150.0],
            detect: [0.0; 3],
            jitter: [0.0; 3],
            c: 0.0,
            delay: 0.01,
            seed: 0,
        };
        let f = feeds(&stream, &profile);
        assert_eq!(f.len(), 2);
        assert_eq!(f[1].id, 1);
        assert!((f[1].receive - 0.9).abs() < 1e-12);
    }
}
