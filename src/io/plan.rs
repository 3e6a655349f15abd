//! The poll plan: the fewest Modbus requests that read every mapped input and write every
//! mapped output in one update.
//!
//! Points of one table are sorted by address and merged into one request while they are
//! contiguous (reads may also bridge up to `max_gap` unmapped addresses; writes never do, as
//! that would overwrite points pacer does not own) and the request stays within the
//! protocol's limit ([`Table::max_read`], [`Table::max_write`]). Reads are issued in the
//! order coils, discrete inputs, holding registers, input registers; writes coils first, then
//! holding registers. The plan is a pure function of the map: the same map gives the same
//! requests.

use super::map::{IoMap, Table};

/// Read or write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// Function 1, 2, 3 or 4.
    Read,
    /// Function 15 or 16.
    Write,
}

/// One Modbus request of the plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    /// Read or write.
    pub op: Op,
    /// Its table.
    pub table: Table,
    /// First address.
    pub start: u16,
    /// Number of bits or registers.
    pub count: u16,
    /// The points it carries (indices into [`IoMap::points`]), by address.
    pub points: Vec<usize>,
}

impl Request {
    /// The Modbus function code of the request.
    pub fn function(&self) -> u8 {
        match (self.op, self.table) {
            (Op::Read, Table::Coil) => 1,
            (Op::Read, Table::DiscreteInput) => 2,
            (Op::Read, Table::HoldingRegister) => 3,
            (Op::Read, Table::InputRegister) => 4,
            (Op::Write, Table::Coil) => 15,
            (Op::Write, _) => 16,
        }
    }
}

/// Every request of one update.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PollPlan {
    /// Reads, issued at the start of the update (inputs).
    pub reads: Vec<Request>,
    /// Writes, issued at the end of the update (outputs).
    pub writes: Vec<Request>,
}

impl PollPlan {
    /// The requests one update costs.
    pub fn requests_per_update(&self) -> usize {
        self.reads.len() + self.writes.len()
    }
}

/// The plan of a map. Inputs (discrete inputs, input registers) are read; outputs (coils,
/// holding registers) are written. Outputs are not read back.
pub fn plan(map: &IoMap) -> PollPlan {
    let mut out = PollPlan::default();
    for table in Table::ALL {
        let (op, limit, gap) = if table.is_output() {
            (Op::Write, table.max_write(), 0)
        } else {
            (Op::Read, table.max_read(), map.max_gap)
        };
        let mut idx: Vec<usize> = (0..map.points.len())
            .filter(|&i| map.points[i].table == table)
            .collect();
        idx.sort_by_key(|&i| map.points[i].address);
        let list = if op == Op::Read {
            &mut out.reads
        } else {
            &mut out.writes
        };
        let mut current: Option<Request> = None;
        for i in idx {
            let p = &map.points[i];
            let start = u32::from(p.address);
            let end = p.end();
            if let Some(r) = current.as_mut() {
                let r_end = u32::from(r.start) + u32::from(r.count);
                let joins = start <= r_end + u32::from(gap)
                    && end.max(r_end) - u32::from(r.start) <= u32::from(limit);
                if joins {
                    r.count = (end.max(r_end) - u32::from(r.start)) as u16;
                    r.points.push(i);
                    continue;
                }
            }
            if let Some(r) = current.take() {
                list.push(r);
            }
            current = Some(Request {
                op,
                table,
                start: p.address,
                count: p.width,
                points: vec![i],
            });
        }
        if let Some(r) = current {
            list.push(r);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::map::Point;

    fn point(table: Table, address: u16, width: u16) -> Point {
        Point {
            table,
            address,
            width,
            slot: u32::from(address),
            member: format!("{}.{address}", table.name()),
            scale: 1.0,
            offset: 0.0,
            signed: false,
            safe: 0.0,
            io_point: false,
            ty: if table.is_bit() {
                crate::registry::ValueType::Bit
            } else {
                crate::registry::ValueType::Real
            },
        }
    }

    fn map(points: Vec<Point>, max_gap: u16) -> IoMap {
        IoMap {
            host: None,
            port: 502,
            unit: 1,
            timeout_ns: 100_000_000,
            max_gap,
            enabled: false,
            overrun_limit: 10,
            period_ns: crate::io::map::DEFAULT_PERIOD_NS,
            max_age_ns: crate::io::map::DEFAULT_MAX_AGE_NS,
            points,
        }
    }

    fn spans(rs: &[Request]) -> Vec<(u8, u16, u16)> {
        rs.iter()
            .map(|r| (r.function(), r.start, r.count))
            .collect()
    }

    #[test]
    fn contiguous_points_are_one_request_in_any_order() {
        let m = map(
            vec![
                point(Table::DiscreteInput, 2, 1),
                point(Table::DiscreteInput, 0, 1),
                point(Table::DiscreteInput, 1, 1),
                point(Table::Coil, 5, 1),
                point(Table::Coil, 4, 1),
            ],
            0,
        );
        let p = plan(&m);
        assert_eq!(spans(&p.reads), vec![(2, 0, 3)]);
        assert_eq!(spans(&p.writes), vec![(15, 4, 2)]);
        assert_eq!(p.reads[0].points, vec![1, 2, 0]);
        assert_eq!(p.requests_per_update(), 2);
    }

    #[test]
    fn a_gap_splits_reads_unless_max_gap_bridges_it_and_never_splits_writes_less() {
        let pts = vec![
            point(Table::InputRegister, 0, 1),
            point(Table::InputRegister, 3, 2),
            point(Table::HoldingRegister, 0, 1),
            point(Table::HoldingRegister, 2, 1),
        ];
        let p = plan(&map(pts.clone(), 0));
        assert_eq!(spans(&p.reads), vec![(4, 0, 1), (4, 3, 2)]);
        assert_eq!(spans(&p.writes), vec![(16, 0, 1), (16, 2, 1)]);
        let p = plan(&map(pts, 2));
        // The read spans the two unmapped registers 1 and 2; the writes stay apart.
        assert_eq!(spans(&p.reads), vec![(4, 0, 5)]);
        assert_eq!(spans(&p.writes), vec![(16, 0, 1), (16, 2, 1)]);
        assert_eq!(p.requests_per_update(), 3);
    }

    #[test]
    fn requests_respect_the_protocol_limits() {
        // 300 contiguous input registers: 125 + 125 + 50.
        let pts: Vec<Point> = (0..300)
            .map(|a| point(Table::InputRegister, a, 1))
            .collect();
        let p = plan(&map(pts, 0));
        assert_eq!(
            spans(&p.reads),
            vec![(4, 0, 125), (4, 125, 125), (4, 250, 50)]
        );
        // 124 holding registers: 123 + 1 (function 16 writes at most 123).
        let pts: Vec<Point> = (0..124)
            .map(|a| point(Table::HoldingRegister, a, 1))
            .collect();
        let p = plan(&map(pts, 0));
        assert_eq!(spans(&p.writes), vec![(16, 0, 123), (16, 123, 1)]);
        // A 32-bit value never straddles two requests: 62 of them fill 124 registers → 123
        // would cut the last one, so it starts the next request.
        let pts: Vec<Point> = (0..62)
            .map(|i| point(Table::HoldingRegister, i * 2, 2))
            .collect();
        let p = plan(&map(pts, 0));
        assert_eq!(spans(&p.writes), vec![(16, 0, 122), (16, 122, 2)]);
    }

    #[test]
    fn an_empty_map_costs_nothing() {
        assert_eq!(plan(&map(Vec::new(), 0)).requests_per_update(), 0);
    }
}
