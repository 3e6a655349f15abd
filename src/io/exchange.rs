//! The process image of a real I/O link, as a fieldbus master keeps it: a thread of its own
//! exchanges inputs and outputs with the device on the link's cycle (`[modbus] period`), with
//! the fault handling of [`Supervisor`] (reconnection included), so an update never waits on
//! the network. Each update takes the latest complete input image and leaves its outputs for
//! the next exchange.
//!
//! Staleness is measured on the update's side: when the latest input image is older than
//! `[modbus] max_age` while the link still counts as up (answers that come slowly, or an
//! exchange starved of processor time), the update reports an [`IoFault::Stale`] fault with the
//! same safe state as a failed request, and the exchange writes the safe values until a fresh
//! image arrives (reported as a return after 0 attempts) or the link fails outright.

use super::jitter::Timing;
use super::memory::Device;
use super::supervisor::{LinkEvent, Supervisor};
use super::{IoBackend, IoFault, IoStats};
use crate::registry::SlotId;
use crate::world::{InputActivity, World};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How the exchange runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExchangeOptions {
    /// The exchange cycle, nanoseconds: an exchange starts this long after the one before
    /// (at once when that one took longer).
    pub period_ns: u64,
    /// The oldest input image an update accepts, nanoseconds.
    pub max_age_ns: u64,
}

/// The exchange cycle's timing over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ExchangeSummary {
    /// Exchanges made (with the link up or down).
    pub exchanges: u64,
    /// The configured cycle, ns.
    pub period_ns: u64,
    /// Median time from one exchange's start to the next's, ns.
    pub cycle_p50_ns: u64,
    /// 99th percentile of it, ns.
    pub cycle_p99_ns: u64,
    /// The longest, ns.
    pub cycle_max_ns: u64,
    /// Median time one exchange took (its round trips), ns.
    pub exchange_p50_ns: u64,
    /// 99th percentile of it, ns.
    pub exchange_p99_ns: u64,
    /// The longest, ns.
    pub exchange_max_ns: u64,
    /// 99th percentile age of the input image an update used, ns.
    pub age_p99_ns: u64,
    /// The oldest input image an update used, ns.
    pub age_max_ns: u64,
}

impl std::fmt::Display for ExchangeSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let ms = |ns: u64| ns as f64 / 1e6;
        write!(
            f,
            "{} exchanges every {:.1} ms; cycle p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms; exchange time p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms; input age at the update p99 {:.2} ms, max {:.2} ms",
            self.exchanges,
            ms(self.period_ns),
            ms(self.cycle_p50_ns),
            ms(self.cycle_p99_ns),
            ms(self.cycle_max_ns),
            ms(self.exchange_p50_ns),
            ms(self.exchange_p99_ns),
            ms(self.exchange_max_ns),
            ms(self.age_p99_ns),
            ms(self.age_max_ns)
        )
    }
}

/// What the two threads share.
struct Image {
    /// The driven inputs' latest values, in [`Exchange::driven`] order.
    inputs: Vec<f64>,
    /// When the latest complete input image was asked for (ns on the link's clock); None
    /// before the first.
    read_at_ns: Option<u64>,
    /// The link is up (as the exchange last saw it).
    link_up: bool,
    /// Link events not yet taken by an update.
    events: Vec<LinkEvent>,
    /// The outputs' latest values, in [`Exchange::outputs`] order.
    outputs: Vec<f64>,
    /// The machine holds its safe state (stale inputs): write the safe values.
    safe: bool,
    /// The supervisor's counts after the latest exchange.
    stats: IoStats,
    /// The exchange cycle (lateness: time between starts beyond the period; work: the
    /// exchange's duration).
    cycle: Timing,
    /// Time between exchange starts.
    interval: Timing,
    /// Age of the input image at the updates that used it.
    age: Timing,
}

struct Shared {
    image: Mutex<Image>,
    stop: AtomicBool,
    start: Instant,
}

impl Shared {
    fn now_ns(&self) -> u64 {
        u64::try_from(self.start.elapsed().as_nanos()).unwrap_or(u64::MAX)
    }

    /// The image; a thread that panicked while holding it leaves plain data behind, still
    /// usable.
    fn image(&self) -> MutexGuard<'_, Image> {
        self.image.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A supervised link run as a process image on a thread of its own: the [`IoBackend`] of real
/// I/O.
pub struct Exchange<D: Device + Send + 'static> {
    shared: Arc<Shared>,
    worker: Option<JoinHandle<Supervisor<D>>>,
    /// The inputs the device drives.
    driven: Vec<SlotId>,
    /// The outputs the device is sent.
    outputs: Vec<SlotId>,
    safe_outputs: Vec<(SlotId, f64)>,
    period_ns: u64,
    staleness: Staleness,
}

/// The update's judgement of the input image's age.
#[derive(Debug)]
struct Staleness {
    /// The device, for the fault.
    device: String,
    /// The oldest image accepted, ns.
    max_age_ns: u64,
    /// The update reported the inputs stale and holds the safe state.
    stale: bool,
}

impl<D: Device + Send + 'static> std::fmt::Debug for Exchange<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Exchange")
            .field("device", &self.staleness.device)
            .field("stale", &self.staleness.stale)
            .finish()
    }
}

impl<D: Device + Send + 'static> Exchange<D> {
    /// Start exchanging on `supervisor`'s link (already open: connected, safe values
    /// written). Returns once the first exchange is done, so the first update has inputs.
    pub fn start(supervisor: Supervisor<D>, options: ExchangeOptions) -> std::io::Result<Self> {
        let driven = supervisor.driven_inputs();
        let safe_outputs = supervisor.safe_outputs();
        // Every output the device is sent, starting from its safe value.
        let (outputs, first): (Vec<SlotId>, Vec<f64>) = supervisor
            .backend
            .map
            .points
            .iter()
            .filter(|p| p.table.is_output())
            .map(|p| (p.slot, p.safe))
            .unzip();
        let device = supervisor.device();
        let image = Image {
            inputs: vec![0.0; driven.len()],
            read_at_ns: None,
            link_up: supervisor.is_up(),
            events: Vec::new(),
            outputs: first,
            safe: false,
            stats: supervisor.stats(),
            cycle: Timing::default(),
            interval: Timing::default(),
            age: Timing::default(),
        };
        let shared = Arc::new(Shared {
            image: Mutex::new(image),
            stop: AtomicBool::new(false),
            start: Instant::now(),
        });
        let worker = {
            let shared = shared.clone();
            let driven = driven.clone();
            let outputs = outputs.clone();
            std::thread::Builder::new()
                .name("pacer-exchange".into())
                .spawn(move || run(supervisor, &shared, &driven, &outputs, options))?
        };
        let exchange = Exchange {
            shared,
            worker: Some(worker),
            driven,
            outputs,
            safe_outputs,
            period_ns: options.period_ns,
            staleness: Staleness {
                device,
                max_age_ns: options.max_age_ns,
                stale: false,
            },
        };
        // The first image (or the fault that prevented it), bounded by the staleness limit.
        let deadline = exchange.shared.now_ns().saturating_add(options.max_age_ns);
        loop {
            {
                let image = exchange.shared.image();
                if image.read_at_ns.is_some() || !image.events.is_empty() {
                    break;
                }
            }
            if exchange.shared.now_ns() >= deadline {
                break;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        Ok(exchange)
    }

    /// Stop the exchange and hand back the supervisor; None when its thread panicked.
    fn stop(&mut self) -> Option<Supervisor<D>> {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.worker.take()?.join().ok()
    }
}

impl Staleness {
    /// The staleness of the image the update took: a stale fault when it passes the limit,
    /// a return when a fresh image arrives. While stale, the machine is already in its safe
    /// state: a failure the exchange meets then is said, not a second fault.
    fn judge(
        &mut self,
        now_ns: u64,
        image: &mut Image,
        events: &mut [LinkEvent],
    ) -> Option<LinkEvent> {
        if self.stale {
            for e in events.iter_mut() {
                if let LinkEvent::Fault(f) = e {
                    *e = LinkEvent::Warning(format!("while the inputs were stale: {f}"));
                }
            }
        }
        if !image.link_up {
            // The exchange saw the link fail: its own fault (already among the events) holds.
            self.stale = false;
            image.safe = false;
            return None;
        }
        // No image yet: as old as the link.
        let age = image
            .read_at_ns
            .map_or(now_ns, |at| now_ns.saturating_sub(at));
        image.age.record(age, 0, u64::MAX);
        if !self.stale && age > self.max_age_ns {
            self.stale = true;
            image.safe = true;
            Some(LinkEvent::Fault(IoFault::Stale {
                device: self.device.clone(),
                // Rounded up: an image 30.4 ms old against a 30 ms limit says 31.
                age_ms: age.div_ceil(1_000_000),
                max_age_ms: self.max_age_ns / 1_000_000,
            }))
        } else if self.stale && age <= self.max_age_ns {
            self.stale = false;
            image.safe = false;
            Some(LinkEvent::Reconnected { attempts: 0 })
        } else {
            None
        }
    }
}

/// The exchange thread: one exchange per period until told to stop.
fn run<D: Device>(
    mut supervisor: Supervisor<D>,
    shared: &Shared,
    driven: &[SlotId],
    outputs: &[SlotId],
    options: ExchangeOptions,
) -> Supervisor<D> {
    let size = driven
        .iter()
        .chain(outputs)
        .map(|&s| s as usize + 1)
        .max()
        .unwrap_or(0);
    let mut inputs = vec![0.0; size];
    let mut sent = vec![0.0; size];
    let mut next = shared.now_ns();
    let mut last_start: Option<u64> = None;
    while !shared.stop.load(Ordering::SeqCst) {
        let started = shared.now_ns();
        let safe = {
            let image = shared.image();
            for (&slot, &v) in outputs.iter().zip(&image.outputs) {
                sent[slot as usize] = v;
            }
            image.safe
        };
        let was_up = supervisor.is_up();
        let mut events = supervisor.read(started, &mut inputs);
        let read = supervisor.is_up()
            && !events.iter().any(|e| matches!(e, LinkEvent::Fault(_)))
            && (was_up
                || events
                    .iter()
                    .any(|e| matches!(e, LinkEvent::Reconnected { .. })));
        if supervisor.is_up() {
            let written = if safe {
                supervisor.write_safe(started)
            } else {
                supervisor.write(started, &sent)
            };
            events.extend(written);
        }
        let ended = shared.now_ns();
        {
            let mut image = shared.image();
            if read {
                for (i, &slot) in driven.iter().enumerate() {
                    image.inputs[i] = inputs[slot as usize];
                }
                image.read_at_ns = Some(started);
            }
            image.link_up = supervisor.is_up();
            image.events.extend(events);
            image.stats = supervisor.stats();
            let late = started.saturating_sub(next);
            image
                .cycle
                .record(late, ended.saturating_sub(started), options.period_ns);
            if let Some(before) = last_start {
                image
                    .interval
                    .record(started.saturating_sub(before), 0, u64::MAX);
            }
        }
        last_start = Some(started);
        next = next.saturating_add(options.period_ns);
        let now = shared.now_ns();
        if next < now {
            // Behind by a whole cycle or more: start again from now rather than rushing.
            next = now;
        } else {
            std::thread::sleep(Duration::from_nanos(next - now));
        }
    }
    supervisor
}

impl<D: Device + Send + 'static> IoBackend for Exchange<D> {
    fn device(&self) -> String {
        self.staleness.device.clone()
    }

    fn real_time(&self) -> bool {
        true
    }

    fn read_inputs(
        &mut self,
        t: f64,
        _now_ns: u64,
        world: &mut World,
        values: &mut [f64],
        activity: &mut Vec<InputActivity>,
    ) -> Vec<LinkEvent> {
        // The world still gives the master axis and the inputs the device does not drive.
        world.advance(t, values, activity);
        let now = self.shared.now_ns();
        let mut image = self.shared.image();
        let mut events = std::mem::take(&mut image.events);
        if image.read_at_ns.is_some() {
            for (&slot, &v) in self.driven.iter().zip(&image.inputs) {
                if let Some(x) = values.get_mut(slot as usize) {
                    *x = v;
                }
            }
        }
        let judged = self.staleness.judge(now, &mut image, &mut events);
        events.extend(judged);
        events
    }

    fn write_outputs(&mut self, _now_ns: u64, values: &[f64]) -> Option<LinkEvent> {
        let mut image = self.shared.image();
        for (i, &slot) in self.outputs.iter().enumerate() {
            if let (Some(out), Some(&v)) = (image.outputs.get_mut(i), values.get(slot as usize)) {
                *out = v;
            }
        }
        None
    }

    fn safe_outputs(&self) -> Vec<(SlotId, f64)> {
        self.safe_outputs.clone()
    }

    fn driven_inputs(&self) -> Vec<SlotId> {
        self.driven.clone()
    }

    fn close(&mut self) -> Result<(), IoFault> {
        match self.stop() {
            Some(mut supervisor) => {
                let result = supervisor.close();
                self.shared.image().stats = supervisor.stats();
                result
            }
            None => Err(IoFault::Disconnected {
                device: self.staleness.device.clone(),
                cause: "the exchange thread stopped unexpectedly".into(),
            }),
        }
    }

    fn stats(&self) -> IoStats {
        let image = self.shared.image();
        let mut stats = image.stats;
        let cycle = image.cycle.summary();
        let interval = image.interval.summary();
        let age = image.age.summary();
        stats.exchange = Some(ExchangeSummary {
            exchanges: cycle.map_or(0, |c| c.updates),
            period_ns: self.period_ns,
            cycle_p50_ns: interval.map_or(0, |i| i.p50_ns),
            cycle_p99_ns: interval.map_or(0, |i| i.p99_ns),
            cycle_max_ns: interval.map_or(0, |i| i.max_ns),
            exchange_p50_ns: cycle.map_or(0, |c| c.update_p50_ns),
            exchange_p99_ns: cycle.map_or(0, |c| c.update_p99_ns),
            exchange_max_ns: cycle.map_or(0, |c| c.worst_update_ns),
            age_p99_ns: age.map_or(0, |a| a.p99_ns),
            age_max_ns: age.map_or(0, |a| a.max_ns),
        });
        stats
    }
}

impl<D: Device + Send + 'static> Drop for Exchange<D> {
    fn drop(&mut self) {
        // A run that ends without `close` (an error) still stops its thread.
        let _ = self.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::map::{IoMap, Point, Table};
    use crate::io::memory::{MemoryDevice, PlanBackend};
    use crate::io::supervisor::Backoff;
    use std::sync::atomic::AtomicU64;

    const MS: u64 = 1_000_000;

    /// A memory device the test can reach while the exchange owns it, whose reads take
    /// `delay_ms` (answers that come slowly but within any timeout).
    #[derive(Debug, Clone, Default)]
    struct Reachable {
        device: Arc<Mutex<MemoryDevice>>,
        delay_ms: Arc<AtomicU64>,
    }

    impl Reachable {
        fn with<T>(&self, f: impl FnOnce(&mut MemoryDevice) -> T) -> T {
            f(&mut self.device.lock().unwrap_or_else(|e| e.into_inner()))
        }
    }

    impl Device for Reachable {
        fn device(&self) -> String {
            "memory".into()
        }
        fn read_bits(&mut self, t: Table, a: u16, n: u16) -> Result<Vec<bool>, IoFault> {
            let delay = self.delay_ms.load(Ordering::SeqCst);
            if delay > 0 {
                std::thread::sleep(Duration::from_millis(delay));
            }
            self.with(|d| d.read_bits(t, a, n))
        }
        fn read_registers(&mut self, t: Table, a: u16, n: u16) -> Result<Vec<u16>, IoFault> {
            self.with(|d| d.read_registers(t, a, n))
        }
        fn write_coils(&mut self, a: u16, bits: &[bool]) -> Result<(), IoFault> {
            self.with(|d| d.write_coils(a, bits))
        }
        fn write_registers(&mut self, a: u16, words: &[u16]) -> Result<(), IoFault> {
            self.with(|d| d.write_registers(a, words))
        }
    }

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
            io_point: true,
            ty: crate::registry::ValueType::Bit,
        }
    }

    /// Discrete input 0 → slot 0; slot 1 → coil 0 (safe OFF).
    fn exchange(device: Reachable, max_age_ns: u64) -> Exchange<Reachable> {
        let map = IoMap {
            host: None,
            port: 502,
            unit: 1,
            timeout_ns: 20 * MS,
            max_gap: 0,
            enabled: false,
            overrun_limit: 10,
            period_ns: 2 * MS,
            max_age_ns,
            points: vec![
                point(Table::DiscreteInput, 0, 0, 0.0),
                point(Table::Coil, 0, 1, 0.0),
            ],
        };
        let mut supervisor = Supervisor::new(PlanBackend::new(map, device), Backoff::default());
        assert_eq!(supervisor.open(), Ok(()));
        let options = ExchangeOptions {
            period_ns: 2 * MS,
            max_age_ns,
        };
        match Exchange::start(supervisor, options) {
            Ok(x) => x,
            Err(e) => panic!("the exchange thread starts: {e}"),
        }
    }

    /// Updates every millisecond until `done` holds of the values and the events so far (a
    /// limit keeps a broken exchange from hanging the test; it is no timing assertion).
    fn update_until(
        x: &mut Exchange<Reachable>,
        values: &mut [f64],
        events: &mut Vec<LinkEvent>,
        mut done: impl FnMut(&[f64], &[LinkEvent]) -> bool,
    ) {
        let mut world = World::default();
        let mut activity = Vec::new();
        for _ in 0..20_000 {
            events.extend(x.read_inputs(0.0, 0, &mut world, values, &mut activity));
            x.write_outputs(0, values);
            if done(values, events) {
                return;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        panic!("not reached in 20 s: {events:?}");
    }

    #[test]
    fn inputs_and_outputs_travel_through_the_image() {
        let device = Reachable::default();
        let mut x = exchange(device.clone(), 500 * MS);
        let mut values = vec![0.0, 1.0];
        let mut events = Vec::new();
        device.with(|d| d.discrete_inputs[0] = true);
        update_until(&mut x, &mut values, &mut events, |v, _| v[0] == 1.0);
        update_until(&mut x, &mut values, &mut events, |_, _| {
            device.with(|d| d.coils[0])
        });
        assert!(events.is_empty(), "{events:?}");
        assert_eq!(x.close(), Ok(()));
        assert!(!device.with(|d| d.coils[0]), "closed: the safe value");
        let stats = x.stats();
        let exchange = stats.exchange.unwrap_or_default();
        assert!(exchange.exchanges >= 2, "{exchange:?}");
        assert_eq!(exchange.period_ns, 2 * MS);
        assert_eq!(stats.faults, 0);
    }

    #[test]
    fn inputs_older_than_max_age_are_a_fault_with_the_safe_state_until_they_are_fresh() {
        let device = Reachable::default();
        let mut x = exchange(device.clone(), 30 * MS);
        let mut values = vec![0.0, 1.0];
        let mut events = Vec::new();
        update_until(&mut x, &mut values, &mut events, |_, _| {
            device.with(|d| d.coils[0])
        });
        // Answers slow down to 80 ms a read: no request fails, but the image ages past 30 ms.
        device.delay_ms.store(80, Ordering::SeqCst);
        update_until(&mut x, &mut values, &mut events, |_, e| !e.is_empty());
        match events.as_slice() {
            [LinkEvent::Fault(IoFault::Stale {
                device,
                age_ms,
                max_age_ms: 30,
            })] => {
                assert_eq!(device, "memory");
                assert!(*age_ms > 30, "{age_ms}");
            }
            other => panic!("{other:?}"),
        }
        // The exchange drives the outputs safe while the machine holds its safe state, whatever
        // the update hands it.
        update_until(&mut x, &mut values, &mut events, |_, _| {
            !device.with(|d| d.coils[0])
        });
        // Fresh answers again: the link is back without a reconnection.
        device.delay_ms.store(0, Ordering::SeqCst);
        update_until(&mut x, &mut values, &mut events, |_, e| e.len() >= 2);
        assert_eq!(events[1], LinkEvent::Reconnected { attempts: 0 });
        update_until(&mut x, &mut values, &mut events, |_, _| {
            device.with(|d| d.coils[0])
        });
        assert_eq!(x.close(), Ok(()));
    }
}
