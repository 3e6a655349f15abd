//! Fault handling of a real I/O link: the first failed request puts the link down (the runner
//! stops motion and reports the fault with its device and cause); reconnection is retried with
//! a doubling back-off; on reconnection the safe output values are written before anything
//! else, and only then are inputs read and outputs written again.
//!
//! The back-off learns: a link that fails again less than [`Backoff::settle_ns`] after it came
//! back starts its next wait where the last one ended instead of at the first delay, so a
//! coupler that drops every connection after a few exchanges is retried ever more slowly, up
//! to the longest delay; a link that has served that long is trusted again.
//!
//! Time is passed in (nanoseconds since the start of the run), so the behaviour is a pure
//! function of the device's answers and the clock, and is tested without sockets or sleeps.

use super::memory::{Device, PlanBackend};
use super::{IoBackend, IoFault, IoStats};
use crate::registry::SlotId;
use crate::world::{InputActivity, World};

/// Retry delays: `initial_ns`, doubling after each failed attempt, never above `max_ns`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Backoff {
    /// The first delay.
    pub initial_ns: u64,
    /// The longest delay.
    pub max_ns: u64,
    /// How long a link must serve after coming back before a new fault starts again at the
    /// first delay.
    pub settle_ns: u64,
}

impl Default for Backoff {
    /// 100 ms, doubling up to 5 s; trusted again after 10 s of service.
    fn default() -> Self {
        Backoff {
            initial_ns: 100_000_000,
            max_ns: 5_000_000_000,
            settle_ns: 10_000_000_000,
        }
    }
}

impl Backoff {
    /// The delay after `failed` failed attempts (0: after the fault itself).
    pub fn delay(&self, failed: u32) -> u64 {
        let factor = 1u64.checked_shl(failed.min(63)).unwrap_or(u64::MAX);
        self.initial_ns.saturating_mul(factor).min(self.max_ns)
    }
}

/// The state of the link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Link {
    /// Requests are served.
    Up,
    /// Faulted; the next connection attempt is at `retry_at_ns`.
    Down {
        /// Connection attempts that failed since the fault.
        failed: u32,
        /// When to try next.
        retry_at_ns: u64,
    },
}

/// What an update reports to the runner (which traces it and stops motion on a fault).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkEvent {
    /// The link went down: the fault, with device and cause.
    Fault(IoFault),
    /// The link is back after `attempts` attempts; the safe values have been written.
    Reconnected {
        /// Attempts it took (1: the first retry).
        attempts: u32,
    },
    /// Something the operator should know that is not a fault (an output saturated in its
    /// register); said once per output.
    Warning(String),
}

/// A [`PlanBackend`] with fault handling.
#[derive(Debug, Clone)]
pub struct Supervisor<D> {
    /// The backend.
    pub backend: PlanBackend<D>,
    /// The link's state.
    pub link: Link,
    /// Retry delays.
    pub backoff: Backoff,
    /// Faults and reconnections so far.
    pub faults: u64,
    /// Reconnections so far.
    pub reconnections: u64,
    /// Updates whose I/O went to the device.
    pub updates: u64,
    /// The back-off level the next fault starts at: grows with each fault that comes before
    /// the link has settled.
    relapses: u32,
    /// When the link last came up (the start, or a reconnection).
    up_since_ns: u64,
    /// Outputs already reported as saturated (point indices).
    warned: Vec<usize>,
}

impl<D: Device> Supervisor<D> {
    /// Supervise `backend`; the link is taken as up (the runner connects before the first
    /// update and reports a refused connection as a fault at time 0).
    pub fn new(backend: PlanBackend<D>, backoff: Backoff) -> Self {
        Supervisor {
            backend,
            link: Link::Up,
            backoff,
            faults: 0,
            reconnections: 0,
            updates: 0,
            relapses: 0,
            up_since_ns: 0,
            warned: Vec::new(),
        }
    }

    /// Open the link before the run: connect, then drive every output to its safe value, so
    /// the outputs are defined before any program runs.
    pub fn open(&mut self) -> Result<(), IoFault> {
        self.backend.device.connect()?;
        self.backend.safe_state()
    }

    /// Take the link down at `now_ns` after `fault`; try once to drive the outputs safe (the
    /// device may still answer, e.g. after an exception).
    fn fail(&mut self, now_ns: u64, fault: IoFault) -> LinkEvent {
        let _ = self.backend.safe_state();
        self.faults += 1;
        // A link that fails again before it has settled (a device that refuses a request every
        // time, or drops each connection after a few exchanges) keeps backing off instead of
        // cycling at the first delay.
        if self.faults > 1 && now_ns.saturating_sub(self.up_since_ns) >= self.backoff.settle_ns {
            self.relapses = 0;
        }
        let level = self.relapses;
        self.relapses = self.relapses.saturating_add(1);
        self.link = Link::Down {
            failed: 0,
            retry_at_ns: now_ns.saturating_add(self.backoff.delay(level)),
        };
        LinkEvent::Fault(fault)
    }

    /// The input half of an update at `now_ns`: reconnect when it is time (writing the safe
    /// values first), then read the inputs into `values`. While the link is down the inputs
    /// keep their last values.
    ///
    /// A return followed at once by a failing read reports both events, in order.
    pub fn read(&mut self, now_ns: u64, values: &mut [f64]) -> Vec<LinkEvent> {
        let mut events = Vec::new();
        if let Link::Down {
            failed,
            retry_at_ns,
        } = self.link
        {
            if now_ns < retry_at_ns {
                return events;
            }
            let attempt = self
                .backend
                .device
                .connect()
                .and_then(|()| self.backend.safe_state());
            if attempt.is_err() {
                self.link = Link::Down {
                    failed: failed + 1,
                    retry_at_ns: now_ns
                        .saturating_add(self.backoff.delay(self.relapses.saturating_add(failed))),
                };
                return events;
            }
            self.link = Link::Up;
            self.up_since_ns = now_ns;
            self.reconnections += 1;
            events.push(LinkEvent::Reconnected {
                attempts: failed + 1,
            });
        }
        self.updates += 1;
        match self.backend.read_inputs(values) {
            Ok(()) => events.extend(self.clamp_warning()),
            Err(fault) => events.push(self.fail(now_ns, fault)),
        }
        events
    }

    /// The output half of an update: write the outputs (nothing while the link is down).
    pub fn write(&mut self, now_ns: u64, values: &[f64]) -> Option<LinkEvent> {
        if self.link != Link::Up {
            return None;
        }
        match self.backend.write_outputs(values) {
            Ok(()) => self.saturation_warning(),
            Err(fault) => Some(self.fail(now_ns, fault)),
        }
    }

    /// The output half of an update in which the machine holds its safe state (its inputs went
    /// stale): write every output's safe value (nothing while the link is down).
    pub fn write_safe(&mut self, now_ns: u64) -> Option<LinkEvent> {
        if self.link != Link::Up {
            return None;
        }
        match self.backend.safe_state() {
            Ok(()) => None,
            Err(fault) => Some(self.fail(now_ns, fault)),
        }
    }

    /// Whether the link is up (requests are being served).
    pub fn is_up(&self) -> bool {
        self.link == Link::Up
    }
}

impl<D: Device> Supervisor<D> {
    /// The first input of the last read that did not fit its member and was not reported yet.
    fn clamp_warning(&mut self) -> Option<LinkEvent> {
        let (i, value) = first_unreported(&self.backend.clamped, &mut self.warned)?;
        let p = &self.backend.map.points[i];
        let decimals = match p.ty {
            crate::registry::ValueType::Fixed(d) => d,
            _ => 0,
        };
        Some(LinkEvent::Warning(format!(
            "{} {} read {value}, which {} cannot hold (32-bit with {decimals} decimal places: {}): held at the nearest end (said once)",
            p.table.name(),
            p.address,
            p.member,
            crate::fixed::range_text(decimals)
        )))
    }

    /// The first output of the last write that saturated and was not reported yet.
    fn saturation_warning(&mut self) -> Option<LinkEvent> {
        let (i, value) = first_unreported(&self.backend.saturated, &mut self.warned)?;
        let p = &self.backend.map.points[i];
        Some(LinkEvent::Warning(format!(
            "{} = {value} does not fit {} {} ({}-bit{}, scale {}, offset {}): written as the nearest value it holds (said once)",
            p.member,
            p.table.name(),
            p.address,
            16 * p.width,
            if p.signed { " signed" } else { "" },
            p.scale,
            p.offset
        )))
    }
}

/// The first (point, value) of `found` not in `warned`, now marked as warned.
fn first_unreported(found: &[(usize, f64)], warned: &mut Vec<usize>) -> Option<(usize, f64)> {
    let &(i, value) = found.iter().find(|(i, _)| !warned.contains(i))?;
    warned.push(i);
    Some((i, value))
}

impl<D: Device> IoBackend for Supervisor<D> {
    fn device(&self) -> String {
        self.backend.device_name()
    }

    fn real_time(&self) -> bool {
        true
    }

    fn read_inputs(
        &mut self,
        t: f64,
        now_ns: u64,
        world: &mut World,
        values: &mut [f64],
        activity: &mut Vec<InputActivity>,
    ) -> Vec<LinkEvent> {
        // The world still gives the master axis and the inputs the device does not drive.
        world.advance(t, values, activity);
        self.read(now_ns, values)
    }

    fn write_outputs(&mut self, now_ns: u64, values: &[f64]) -> Option<LinkEvent> {
        self.write(now_ns, values)
    }

    fn safe_outputs(&self) -> Vec<(SlotId, f64)> {
        self.backend
            .map
            .points
            .iter()
            .filter(|p| p.table.is_output() && p.io_point)
            .map(|p| (p.slot, p.safe))
            .collect()
    }

    fn driven_inputs(&self) -> Vec<SlotId> {
        self.backend
            .map
            .points
            .iter()
            .filter(|p| !p.table.is_output())
            .map(|p| p.slot)
            .collect()
    }

    fn close(&mut self) -> Result<(), IoFault> {
        if self.link != Link::Up {
            // Written when the link went down; nothing answers now.
            return Ok(());
        }
        self.backend.safe_state()
    }

    fn stats(&self) -> IoStats {
        IoStats {
            per_update: self.backend.plan.requests_per_update() as u64,
            requests: self.backend.requests,
            updates: self.updates,
            faults: self.faults,
            reconnections: self.reconnections,
            exchange: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::map::{IoMap, Point, Table};
    use crate::io::memory::MemoryDevice;

    const MS: u64 = 1_000_000;

    fn point(table: Table, address: u16, slot: u32, safe: f64) -> Point {
        Point {
            table,
            address,
            width: 1,
            slot,
            member: format!("slot{slot}"),
            scale: 1.0,
            offset: 0.0,
            signed: false,
            safe,
            io_point: false,
            ty: if table.is_bit() {
                crate::registry::ValueType::Bit
            } else {
                crate::registry::ValueType::Real
            },
        }
    }

    /// Input 0 → slot 0; slot 1 → coil 0 (safe ON); slot 2 → holding 4 (safe 7).
    fn map(points: Vec<Point>) -> IoMap {
        IoMap {
            host: None,
            port: 502,
            unit: 1,
            timeout_ns: 20 * MS,
            max_gap: 0,
            enabled: false,
            overrun_limit: 10,
            period_ns: crate::io::map::DEFAULT_PERIOD_NS,
            max_age_ns: crate::io::map::DEFAULT_MAX_AGE_NS,
            points,
        }
    }

    fn supervisor() -> Supervisor<MemoryDevice> {
        let map = map(vec![
            point(Table::DiscreteInput, 0, 0, 0.0),
            point(Table::Coil, 0, 1, 1.0),
            point(Table::HoldingRegister, 4, 2, 7.0),
        ]);
        Supervisor::new(
            PlanBackend::new(map, MemoryDevice::default()),
            Backoff {
                initial_ns: 10 * MS,
                max_ns: 40 * MS,
                settle_ns: 100 * MS,
            },
        )
    }

    fn lost() -> IoFault {
        IoFault::Disconnected {
            device: "memory".into(),
            cause: "connection reset by peer".into(),
        }
    }

    #[test]
    fn backoff_doubles_up_to_its_limit() {
        let b = Backoff {
            initial_ns: 10,
            max_ns: 45,
            settle_ns: 1000,
        };
        let delays: Vec<u64> = (0..5).map(|n| b.delay(n)).collect();
        assert_eq!(delays, vec![10, 20, 40, 45, 45]);
        assert_eq!(b.delay(200), 45);
    }

    #[test]
    fn a_lost_device_faults_retries_with_backoff_and_writes_safe_values_first_on_return() {
        let mut s = supervisor();
        let mut values = vec![0.0, 0.0, 3.0];
        s.backend.device.discrete_inputs[0] = true;
        assert_eq!(s.read(0, &mut values), vec![]);
        assert_eq!(values[0], 1.0);
        assert_eq!(s.write(0, &values), None);
        assert_eq!(s.backend.device.holding[4], 3);

        // The device goes away: the next read is a fault, with its cause.
        s.backend.device.down = Some(lost());
        s.backend.device.discrete_inputs[0] = false;
        assert_eq!(s.read(MS, &mut values), vec![LinkEvent::Fault(lost())]);
        assert_eq!(
            s.link,
            Link::Down {
                failed: 0,
                retry_at_ns: 11 * MS
            }
        );
        // Inputs keep their last values; nothing is written while down.
        assert_eq!(values[0], 1.0);
        let served = s.backend.device.requests;
        assert_eq!(s.write(2 * MS, &values), None);
        assert_eq!(s.read(10 * MS, &mut values), vec![]);
        assert_eq!(
            s.backend.device.requests, served,
            "no request before the retry"
        );

        // Retry at 11 ms fails: the next is 20 ms later; then 40 (the limit), then 40.
        assert_eq!(s.read(11 * MS, &mut values), vec![]);
        assert_eq!(
            s.link,
            Link::Down {
                failed: 1,
                retry_at_ns: 31 * MS
            }
        );
        assert_eq!(s.read(31 * MS, &mut values), vec![]);
        assert_eq!(
            s.link,
            Link::Down {
                failed: 2,
                retry_at_ns: 71 * MS
            }
        );

        // Back: the safe values go out before the first read, then the update goes on.
        s.backend.device.down = None;
        s.backend.device.writes.clear();
        assert_eq!(
            s.read(71 * MS, &mut values),
            vec![LinkEvent::Reconnected { attempts: 3 }]
        );
        assert_eq!(
            s.backend.device.writes,
            vec![
                (Table::Coil, 0, vec![1]),
                (Table::HoldingRegister, 4, vec![7])
            ]
        );
        assert_eq!(
            values[0], 0.0,
            "inputs are read again after the safe values"
        );
        assert_eq!(s.link, Link::Up);
        values[1] = 0.0;
        assert_eq!(s.write(71 * MS, &values), None);
        assert_eq!(s.backend.device.holding[4], 3);
        assert!(!s.backend.device.coils[0]);
    }

    #[test]
    fn a_device_that_refuses_every_time_keeps_backing_off() {
        let mut s = supervisor();
        let refused = IoFault::Exception {
            device: "memory".into(),
            request: "read discrete_input 0..1".into(),
            code: 2,
        };
        s.backend.device.refuse_reads = Some(refused.clone());
        let mut values = vec![0.0; 3];
        let mut faults = Vec::new();
        let mut reconnects = Vec::new();
        for ms in 0..200 {
            for event in s.read(ms * MS, &mut values) {
                match event {
                    LinkEvent::Fault(f) => {
                        assert_eq!(f, refused);
                        faults.push(ms);
                    }
                    LinkEvent::Reconnected { attempts } => {
                        assert_eq!(attempts, 1);
                        reconnects.push(ms);
                    }
                    LinkEvent::Warning(w) => panic!("{w}"),
                }
            }
            assert_eq!(s.write(ms * MS, &values), None);
        }
        // Each return fails at once: 10, 20, 40, 40 ms apart, not every 10 ms.
        assert_eq!(faults, vec![0, 10, 30, 70, 110, 150, 190]);
        assert_eq!(reconnects, vec![10, 30, 70, 110, 150, 190]);
        // A link that has served for the settle time (100 ms since its return at 190 ms) is
        // trusted again: the next fault starts at 10 ms again.
        s.backend.device.refuse_reads = None;
        s.link = Link::Up;
        assert_eq!(s.read(300 * MS, &mut values), vec![]);
        assert_eq!(s.write(300 * MS, &values), None);
        s.backend.device.refuse_reads = Some(refused);
        assert!(matches!(
            s.read(301 * MS, &mut values).as_slice(),
            [LinkEvent::Fault(_)]
        ));
        assert!(matches!(s.link, Link::Down { retry_at_ns, .. } if retry_at_ns == 311 * MS));
    }

    /// A device that serves `good` requests after each connection, then resets it.
    #[derive(Debug)]
    struct Flaky {
        inner: MemoryDevice,
        good: u32,
        left: u32,
    }

    impl Flaky {
        fn take(&mut self) -> Result<(), IoFault> {
            if self.left == 0 {
                return Err(lost());
            }
            self.left -= 1;
            Ok(())
        }
    }

    impl Device for Flaky {
        fn device(&self) -> String {
            "memory".into()
        }
        fn connect(&mut self) -> Result<(), IoFault> {
            self.left = self.good;
            Ok(())
        }
        fn read_bits(&mut self, t: Table, a: u16, n: u16) -> Result<Vec<bool>, IoFault> {
            self.take()?;
            self.inner.read_bits(t, a, n)
        }
        fn read_registers(&mut self, t: Table, a: u16, n: u16) -> Result<Vec<u16>, IoFault> {
            self.take()?;
            self.inner.read_registers(t, a, n)
        }
        fn write_coils(&mut self, a: u16, bits: &[bool]) -> Result<(), IoFault> {
            self.take()?;
            self.inner.write_coils(a, bits)
        }
        fn write_registers(&mut self, a: u16, words: &[u16]) -> Result<(), IoFault> {
            self.take()?;
            self.inner.write_registers(a, words)
        }
    }

    #[test]
    fn a_coupler_that_drops_each_connection_soon_after_its_return_is_retried_ever_more_slowly() {
        // Three requests per update (a read, a coil write, a register write) and two for the
        // safe values on each return: 14 requests are four updates after a reconnection.
        let map = map(vec![
            point(Table::DiscreteInput, 0, 0, 0.0),
            point(Table::Coil, 0, 1, 1.0),
            point(Table::HoldingRegister, 4, 2, 7.0),
        ]);
        let flaky = Flaky {
            inner: MemoryDevice::default(),
            good: 14,
            left: 12,
        };
        let mut s = Supervisor::new(
            PlanBackend::new(map, flaky),
            Backoff {
                initial_ns: 10 * MS,
                max_ns: 80 * MS,
                settle_ns: 100 * MS,
            },
        );
        let mut values = vec![0.0; 3];
        let mut faults = Vec::new();
        for ms in 0..400 {
            for event in s.read(ms * MS, &mut values) {
                if let LinkEvent::Fault(_) = event {
                    faults.push(ms);
                }
            }
            if let Some(LinkEvent::Fault(_)) = s.write(ms * MS, &values) {
                faults.push(ms);
            }
        }
        // Four good updates, then the fault; the waits grow 10, 20, 40, 80, 80 ms instead of
        // restarting at 10 ms after each short return.
        let gaps: Vec<u64> = faults.windows(2).map(|w| w[1] - w[0]).collect();
        assert_eq!(faults[0], 4);
        assert_eq!(&gaps[..5], &[14, 24, 44, 84, 84]);
    }

    #[test]
    fn an_output_that_does_not_fit_its_register_is_said_once_and_saturated() {
        let mut s = supervisor();
        let mut values = vec![0.0, 0.0, 70_000.0];
        let warning = s.write(0, &values);
        assert_eq!(
            warning,
            Some(LinkEvent::Warning(
                "slot2 = 70000 does not fit holding_register 4 (16-bit, scale 1, offset 0): written as the nearest value it holds (said once)".into()
            ))
        );
        assert_eq!(s.backend.device.holding[4], 65535);
        assert_eq!(s.write(MS, &values), None, "said once");
        values[2] = -3.0;
        assert_eq!(s.write(2 * MS, &values), None);
        assert_eq!(s.backend.device.holding[4], 0);
        assert_eq!(s.link, Link::Up, "not a fault");
    }

    #[test]
    fn an_input_that_does_not_fit_its_member_is_said_once_and_held_at_the_end() {
        let mut count = point(Table::InputRegister, 0, 0, 0.0);
        count.width = 2;
        count.member = "Var.Count".into();
        count.ty = crate::registry::ValueType::Integer;
        let mut s = Supervisor::new(
            PlanBackend::new(map(vec![count]), MemoryDevice::default()),
            Backoff::default(),
        );
        s.backend.device.input_registers[0] = 0xFFFF;
        s.backend.device.input_registers[1] = 0xFFFF;
        let mut values = vec![0.0];
        assert_eq!(
            s.read(0, &mut values),
            vec![LinkEvent::Warning(
                "input_register 0 read 4294967295, which Var.Count cannot hold (32-bit with 0 decimal places: -2147483648 to 2147483647): held at the nearest end (said once)".into()
            )]
        );
        assert_eq!(values[0], f64::from(i32::MAX));
        assert_eq!(s.read(MS, &mut values), vec![], "said once");
        s.backend.device.input_registers[0] = 0;
        assert_eq!(s.read(2 * MS, &mut values), vec![]);
        assert_eq!(values[0], 65535.0);
    }

    #[test]
    fn an_exception_on_write_is_a_fault_with_its_code() {
        let mut s = supervisor();
        let exception = IoFault::Exception {
            device: "memory".into(),
            request: "write holding_register 4".into(),
            code: 2,
        };
        s.backend.device.down = Some(exception.clone());
        let values = vec![0.0; 3];
        assert_eq!(
            s.write(5 * MS, &values),
            Some(LinkEvent::Fault(exception.clone()))
        );
        assert_eq!(
            exception.to_string(),
            "memory: write holding_register 4 answered exception 2 (illegal data address)"
        );
    }
}
