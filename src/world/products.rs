//! Product streams: products on the conveyor pass a sensor at master positions (pitch, product
//! length, seeded jitter, missing products); each edge may bounce.

use super::master::MasterProfile;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Contact bounce: after an edge the contact opens and closes `count` times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounce {
    /// Number of bounces after each edge.
    pub count: u32,
    /// How long each bounce holds the opposite level, seconds.
    pub width: f64,
    /// Time between bounces (and from the edge to the first bounce), seconds.
    pub gap: f64,
    /// Bounce on the trailing edge too.
    pub trailing: bool,
}

/// A stream of products passing one sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct ProductStream {
    /// Master position of the first product's leading edge.
    pub first: f64,
    /// Master distance between leading edges.
    pub pitch: f64,
    /// Product length along the conveyor, master units.
    pub length: f64,
    /// Each leading edge is moved by a uniform amount in ±jitter.
    pub jitter: f64,
    /// Number of products (missing ones included).
    pub count: u32,
    /// Indices (from 0) of products that are missing: gaps in the stream.
    pub missing: Vec<u32>,
    /// Contact bounce, if any.
    pub bounce: Option<Bounce>,
}

/// One product as it passes the sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Product {
    /// Index in the stream.
    pub index: u32,
    /// Master position of its leading edge.
    pub lead: f64,
    /// Time the leading edge reaches the sensor, seconds.
    pub on_at: f64,
    /// Time the trailing edge leaves it, if the master gets there.
    pub off_at: Option<f64>,
}

/// A sensor level change at an exact time (seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedEdge {
    /// Seconds.
    pub at: f64,
    /// New level.
    pub on: bool,
}

/// A uniform draw in [-1, 1) from 53 random bits: the same on every platform and version.
pub fn unit(rng: &mut ChaCha8Rng) -> f64 {
    let bits = rng.next_u64() >> 11;
    (bits as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

impl ProductStream {
    /// Check the stream makes physical sense; the message says what to change.
    pub fn validate(&self) -> Result<(), String> {
        let finite = [self.first, self.pitch, self.length, self.jitter]
            .iter()
            .all(|x| x.is_finite());
        if !finite
            || self.pitch <= 0.0
            || self.length <= 0.0
            || self.jitter < 0.0
            || self.first < 0.0
        {
            return Err("first ≥ 0, pitch > 0, length > 0 and jitter ≥ 0 are needed".into());
        }
        if self.length + 2.0 * self.jitter >= self.pitch {
            return Err(format!(
                "products would touch or overlap: length + 2 × jitter ({}) must stay below the pitch ({})",
                self.length + 2.0 * self.jitter,
                self.pitch
            ));
        }
        if let Some(b) = self.bounce {
            if !(b.width > 0.0 && b.gap > 0.0 && b.width.is_finite() && b.gap.is_finite()) {
                return Err("bounce width and gap must be above 0".into());
            }
        }
        Ok(())
    }

    /// The products, in order, with their edge times on `master`. `seed` makes the jitter.
    pub fn products(&self, master: &MasterProfile, seed: u64) -> Vec<Product> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut out = Vec::with_capacity(self.count as usize);
        // Sorted once: a long `missing` list must not cost its length for every product.
        let mut missing = self.missing.clone();
        missing.sort_unstable();
        for i in 0..self.count {
            // Draw for every index, missing ones too, so removing a product moves no other.
            let shift = unit(&mut rng) * self.jitter;
            if missing.binary_search(&i).is_ok() {
                continue;
            }
            let lead = self.first + f64::from(i) * self.pitch + shift;
            let Some(on_at) = master.time_at(lead) else {
                break;
            };
            out.push(Product {
                index: i,
                lead,
                on_at,
                off_at: master.time_at(lead + self.length),
            });
        }
        out
    }

    /// The sensor's level changes for these products, bounces included, in time order.
    pub fn edges(&self, products: &[Product]) -> Vec<TimedEdge> {
        let mut edges = Vec::with_capacity(products.len() * 2);
        for p in products {
            edges.push(TimedEdge {
                at: p.on_at,
                on: true,
            });
            let end = p.off_at.unwrap_or(f64::INFINITY);
            if let Some(b) = self.bounce {
                bounce(&mut edges, p.on_at, true, b, end);
            }
            if let Some(off) = p.off_at {
                edges.push(TimedEdge { at: off, on: false });
                if let Some(b) = self.bounce.filter(|b| b.trailing) {
                    bounce(&mut edges, off, false, b, f64::INFINITY);
                }
            }
        }
        edges.sort_by(|a, b| a.at.total_cmp(&b.at));
        edges
    }
}

/// After an edge to `level` at `t`, the contact leaves `level` for `width`, `count` times, `gap`
/// apart; bounces that would reach `until` (the next edge) are dropped.
fn bounce(edges: &mut Vec<TimedEdge>, t: f64, level: bool, b: Bounce, until: f64) {
    for k in 0..b.count {
        let start = t + b.gap * f64::from(k + 1) + b.width * f64::from(k);
        let end = start + b.width;
        if end >= until {
            break;
        }
        edges.push(TimedEdge {
            at: start,
            on: !level,
        });
        edges.push(TimedEdge { at: end, on: level });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stream() -> ProductStream {
        ProductStream {
            first: 1.0,
            pitch: 1.0,
            length: 0.2,
            jitter: 0.1,
            count: 50,
            missing: vec![3],
            bounce: None,
        }
    }

    #[test]
    fn edges_sit_at_their_master_positions() {
        let m = MasterProfile::new(10.0, &[]).expect("profile");
        let ps = stream().products(&m, 7);
        assert_eq!(ps.len(), 49);
        assert!(ps.iter().all(|p| p.index != 3));
        for p in &ps {
            let expected = 1.0 + f64::from(p.index);
            assert!((p.lead - expected).abs() <= 0.1);
            assert!((m.position(p.on_at) - p.lead).abs() < 1e-9);
        }
    }

    #[test]
    fn the_same_seed_gives_the_same_stream_and_another_does_not() {
        let m = MasterProfile::new(10.0, &[]).expect("profile");
        assert_eq!(stream().products(&m, 1), stream().products(&m, 1));
        assert_ne!(stream().products(&m, 1), stream().products(&m, 2));
    }

    #[test]
    fn bounce_follows_the_leading_edge_and_ends_on() {
        let m = MasterProfile::new(1.0, &[]).expect("profile");
        let mut s = stream();
        s.jitter = 0.0;
        s.bounce = Some(Bounce {
            count: 2,
            width: 0.001,
            gap: 0.002,
            trailing: true,
        });
        let ps = s.products(&m, 1);
        let e = s.edges(&ps[..1]);
        let levels: Vec<bool> = e.iter().map(|x| x.on).collect();
        assert_eq!(
            levels,
            [true, false, true, false, true, false, true, false, true, false]
        );
        assert!((e[1].at - e[0].at - 0.002).abs() < 1e-12);
        assert!((e[3].at - e[0].at - 0.005).abs() < 1e-12);
    }

    #[test]
    fn overlapping_products_are_refused() {
        let mut s = stream();
        s.jitter = 0.45;
        assert!(s.validate().is_err());
        assert!(stream().validate().is_ok());
    }
}
