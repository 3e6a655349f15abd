//! Executing a poll plan against a [`Device`]: the part of the real backend that does not
//! depend on the transport. [`MemoryDevice`] is a device held in memory (for tests, and the
//! model the Modbus TCP client follows); [`PlanBackend`] runs the plan of an [`IoMap`] on any
//! device.

use super::map::{IoMap, Point, Table};
use super::plan::{plan, Op, PollPlan};
use super::IoFault;

/// The Modbus requests a device answers. Bits travel as `bool`, registers as `u16`.
pub trait Device {
    /// The device, for fault messages.
    fn device(&self) -> String;
    /// (Re)open the connection. A device without one (in memory) is always connected.
    fn connect(&mut self) -> Result<(), IoFault> {
        Ok(())
    }
    /// Functions 1 and 2.
    fn read_bits(&mut self, table: Table, start: u16, count: u16) -> Result<Vec<bool>, IoFault>;
    /// Functions 3 and 4.
    fn read_registers(&mut self, table: Table, start: u16, count: u16)
        -> Result<Vec<u16>, IoFault>;
    /// Function 15.
    fn write_coils(&mut self, start: u16, bits: &[bool]) -> Result<(), IoFault>;
    /// Function 16.
    fn write_registers(&mut self, start: u16, words: &[u16]) -> Result<(), IoFault>;
}

/// A Modbus device held in memory: 65536 points per table, and a count of requests served.
#[derive(Debug, Clone)]
pub struct MemoryDevice {
    /// Coils.
    pub coils: Vec<bool>,
    /// Discrete inputs.
    pub discrete_inputs: Vec<bool>,
    /// Holding registers.
    pub holding: Vec<u16>,
    /// Input registers.
    pub input_registers: Vec<u16>,
    /// Requests served since it was made.
    pub requests: usize,
    /// When set, every request and connection attempt fails with this fault (a device that
    /// went away, for tests).
    pub down: Option<IoFault>,
    /// Every write served, in order: (table, start, words), coils as 0/1.
    pub writes: Vec<(Table, u16, Vec<u16>)>,
    /// When set, reads (only) fail with this fault: a device that is there but refuses one
    /// request every time.
    pub refuse_reads: Option<IoFault>,
}

impl Default for MemoryDevice {
    fn default() -> Self {
        MemoryDevice {
            coils: vec![false; 65536],
            discrete_inputs: vec![false; 65536],
            holding: vec![0; 65536],
            input_registers: vec![0; 65536],
            requests: 0,
            down: None,
            writes: Vec::new(),
            refuse_reads: None,
        }
    }
}

fn range(start: u16, count: usize) -> std::ops::Range<usize> {
    usize::from(start)..usize::from(start) + count
}

impl MemoryDevice {
    fn check(&self, start: u16, count: usize) -> Result<(), IoFault> {
        if let Some(fault) = &self.down {
            return Err(fault.clone());
        }
        if usize::from(start) + count > 65536 {
            return Err(IoFault::Exception {
                device: self.device(),
                request: format!("{start}+{count}"),
                code: 2,
            });
        }
        Ok(())
    }
}

impl Device for MemoryDevice {
    fn device(&self) -> String {
        "memory".into()
    }

    fn connect(&mut self) -> Result<(), IoFault> {
        self.down.clone().map_or(Ok(()), Err)
    }

    fn read_bits(&mut self, table: Table, start: u16, count: u16) -> Result<Vec<bool>, IoFault> {
        self.requests += 1;
        self.check(start, count.into())?;
        if let Some(fault) = &self.refuse_reads {
            return Err(fault.clone());
        }
        let src = if table == Table::Coil {
            &self.coils
        } else {
            &self.discrete_inputs
        };
        Ok(src[range(start, count.into())].to_vec())
    }

    fn read_registers(
        &mut self,
        table: Table,
        start: u16,
        count: u16,
    ) -> Result<Vec<u16>, IoFault> {
        self.requests += 1;
        self.check(start, count.into())?;
        if let Some(fault) = &self.refuse_reads {
            return Err(fault.clone());
        }
        let src = if table == Table::HoldingRegister {
            &self.holding
        } else {
            &self.input_registers
        };
        Ok(src[range(start, count.into())].to_vec())
    }

    fn write_coils(&mut self, start: u16, bits: &[bool]) -> Result<(), IoFault> {
        self.requests += 1;
        self.check(start, bits.len())?;
        self.coils[range(start, bits.len())].copy_from_slice(bits);
        self.writes.push((
            Table::Coil,
            start,
            bits.iter().map(|&b| u16::from(b)).collect(),
        ));
        Ok(())
    }

    fn write_registers(&mut self, start: u16, words: &[u16]) -> Result<(), IoFault> {
        self.requests += 1;
        self.check(start, words.len())?;
        self.holding[range(start, words.len())].copy_from_slice(words);
        self.writes
            .push((Table::HoldingRegister, start, words.to_vec()));
        Ok(())
    }
}

/// The poll plan of a map, run on a device: one update's reads into the machine's values,
/// its writes from them.
#[derive(Debug, Clone)]
pub struct PlanBackend<D> {
    /// The map.
    pub map: IoMap,
    /// Its plan.
    pub plan: PollPlan,
    /// The device.
    pub device: D,
    /// Outputs whose value did not fit their register at the last write: (point index into
    /// the map, the value).
    pub saturated: Vec<(usize, f64)>,
    /// Requests sent (answered or not) since the backend was made.
    pub requests: u64,
    /// Inputs whose value did not fit their member at the last read: (point index into the
    /// map, the value read).
    pub clamped: Vec<(usize, f64)>,
}

impl<D: Device> PlanBackend<D> {
    /// A backend for `map` on `device`.
    pub fn new(map: IoMap, device: D) -> Self {
        let plan = plan(&map);
        PlanBackend {
            map,
            plan,
            device,
            saturated: Vec::new(),
            requests: 0,
            clamped: Vec::new(),
        }
    }

    /// Every write request of the plan, each point's value given by `value_of` (bits as 0/1).
    fn write_with(&mut self, value_of: impl Fn(&Point) -> f64) -> Result<(), IoFault> {
        self.saturated.clear();
        for r in &self.plan.writes {
            let mut words = vec![0u16; usize::from(r.count)];
            for &i in &r.points {
                let p = &self.map.points[i];
                let value = value_of(p);
                let (w, saturated) = p.encode(value);
                if saturated {
                    self.saturated.push((i, value));
                }
                let at = usize::from(p.address - r.start);
                words[at..at + w.len()].copy_from_slice(&w);
            }
            self.requests += 1;
            if r.table.is_bit() {
                let bits: Vec<bool> = words.iter().map(|&w| w != 0).collect();
                self.device.write_coils(r.start, &bits)?;
            } else {
                self.device.write_registers(r.start, &words)?;
            }
        }
        Ok(())
    }
}

impl<D: Device> PlanBackend<D> {
    /// The device, for messages.
    pub fn device_name(&self) -> String {
        self.device.device()
    }

    /// Read every input of the map into `values` (indexed by slot), scaled.
    pub fn read_inputs(&mut self, values: &mut [f64]) -> Result<(), IoFault> {
        self.clamped.clear();
        for r in &self.plan.reads {
            debug_assert_eq!(r.op, Op::Read);
            self.requests += 1;
            let words: Vec<u16> = if r.table.is_bit() {
                self.device
                    .read_bits(r.table, r.start, r.count)?
                    .into_iter()
                    .map(u16::from)
                    .collect()
            } else {
                self.device.read_registers(r.table, r.start, r.count)?
            };
            for &i in &r.points {
                let p = &self.map.points[i];
                let at = usize::from(p.address - r.start);
                let Some(w) = words.get(at..at + usize::from(p.width)) else {
                    continue;
                };
                let read = p.decode(w);
                let (x, fits) = p.store(read);
                if !fits {
                    self.clamped.push((i, read));
                }
                if let Some(v) = values.get_mut(p.slot as usize) {
                    *v = x;
                }
            }
        }
        Ok(())
    }

    /// Write every output of the map from `values` (indexed by slot), scaled.
    pub fn write_outputs(&mut self, values: &[f64]) -> Result<(), IoFault> {
        self.write_with(|p| values.get(p.slot as usize).copied().unwrap_or(0.0))
    }

    /// Write every output's configured safe value.
    pub fn safe_state(&mut self) -> Result<(), IoFault> {
        self.write_with(|p| p.safe)
    }
}
