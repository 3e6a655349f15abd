//! The machine at run time: the value array, the devices, the world, the tasks and the
//! per-update schedule.
//!
//! Each update, in this fixed order: the world advances (master position, inputs sampled, edges
//! timed) → assignments (captures latch at the exact edge) → the control loop: every device
//! moves to this update in the machine's order (the drive's profiles, the DSP axes, pick &
//! place), then every device derives its status (queue compares, PLS windows, timers) → blocked
//! tasks re-examined (`Wait For` conditions evaluated every update, timed waits, motion waits) → one
//! task runs, round robin over the tasks that are not blocked, until it blocks, ends or spends
//! its instruction budget → the changes of the update are traced. The spec puts the task after
//! the control loop ("each update, after the control loop, one task runs").

pub mod body;
pub mod error;
pub mod exec;
pub mod live;
pub mod print;
pub mod realtime;
pub mod rnd;
pub mod stop;
pub mod stuck;
pub mod task;
pub mod tight;
pub mod using;

use crate::compile::bytecode::Op;
use crate::compile::Chunk;
use crate::devices::command::StartRef;
use crate::devices::{ActOutcome, Device, Devices, Now, Target, When};
use crate::io::supervisor::LinkEvent;
use crate::io::{IoBackend, IoFault, IoStats, Simulator};
use crate::registry::{Access, Hook, Registry, SlotId};
use crate::trace::{Event, Origin, ProgramEvent, Trace, Value};
use crate::world::{Edge, InputActivity, World};
pub use error::RunError;
use exec::{Ctx, Exit};
use indexmap::IndexMap;
use std::cmp::Ordering;
pub use stop::StopReason;
use task::{Frame, Task, TaskState};

/// Instructions a task may run in one update unless machine.toml says otherwise.
pub const DEFAULT_BUDGET: u64 = crate::config::DEFAULT_BUDGET;

/// Deepest nesting of `Call Program.N`.
pub const MAX_CALL_DEPTH: usize = 16;

/// The fewest iterations per entry, on average over its first [`TRIAL`] entries, for which a
/// `WHILE` stays handed over to the machine (`Machine::run_body`).
const FEWEST_ROUNDS: u64 = 16;

/// How many entries of a `WHILE` or a `FOR` the machine counts before it decides whether to
/// keep running it (`Machine::run_body`, `Machine::judge_for`).
const TRIAL: u32 = 64;

/// The fewest of the interpreter's instructions per entry, on average over its first [`TRIAL`]
/// entries, that the machine must run for a `FOR` (or a `WHILE`) to stay handed over
/// (`Machine::judge_for`, `Machine::run_body`). Handing a loop over and back costs some 900
/// machine instructions an entry; a body saves between 1 and 7 of them per instruction of the
/// interpreter's (a long's `MOD` and sum, which the interpreter does in integers too: 1; a
/// SINGLE's count and remainder: 7). A short loop inside a loop the interpreter runs
/// (`probe/inner`: 5 iterations of 7 instructions) took twice as long handed over; past 256
/// instructions an entry the loss is at most some 12 %, and the gain up to some 20 %.
const FEWEST_COUNTED: u64 = 256;

/// How many of the machine's instructions after a trial gives a loop back to the interpreter
/// it is tried again (doubled at each trial that fails again, to [`RETRY_LAST`] doublings): a
/// loop's first entries are not always its others (Collatz lengths of 1 to 64, short, then of
/// larger numbers), and a trial costs less than some 64 × 900 machine instructions.
const RETRY_AFTER: u64 = 1 << 20;

/// The most doublings of [`RETRY_AFTER`].
const RETRY_LAST: u32 = 16;

/// How many of the interpreter's budget tests a turn starting inside an iteration of a body
/// that runs subroutines stops at, at most, to hand the loop back (`Machine::run_task`): an
/// iteration holds a few (each `GOSUB`, each `RETURN`, the `for.next`); past them the loop
/// has ended, or is one the machine does not take back.
const REJOIN_TESTS: u32 = 8;

/// Upper bound on a run with no duration whose programs never end (simulated seconds).
pub const DEFAULT_MAX_SECONDS: u64 = 3600;

/// The program number of chunks typed at the REPL (no program has it: numbers come from files).
pub const REPL_PROGRAM: u32 = u32::MAX;

pub use crate::config::desc::Assignment;

/// Everything a run needs, loaded and compiled.
pub struct MachineImage {
    /// Machine name.
    pub name: String,
    /// Update period, ns.
    pub tick_ns: u64,
    /// Instructions per task turn.
    pub budget: u64,
    /// Number of tasks.
    pub tasks: usize,
    /// The user units of the drive's axis and the master.
    pub units: crate::devices::drive::setup::Units,
    /// The objects.
    pub registry: Registry,
    /// Initial values of the whole value array.
    pub initial: Vec<f64>,
    /// Compiled programs.
    pub chunks: Vec<Chunk>,
    /// The programs' strings: a string value is an index into it.
    pub strings: Vec<String>,
    /// Program number → chunk.
    pub programs: IndexMap<u32, usize>,
    /// Programs started at the beginning, in order.
    pub autostart: Vec<u32>,
    /// Assignments in machine-file order.
    pub assignments: Vec<Assignment>,
    /// Scenario input edges.
    pub edges: Vec<Edge>,
    /// The master axis.
    pub master: crate::world::master::MasterProfile,
    /// The scenario's products, per stream: the sensor slot and the products (for reports and
    /// tests).
    pub products: Vec<(SlotId, Vec<crate::world::products::Product>)>,
    /// Scenario duration, if set.
    pub duration_ns: Option<u64>,
    /// The scenario's seed, if set: MotionBASIC's RND starts from it.
    pub seed: Option<u64>,
    /// The devices, in the order they update: the drive, then the DSP axes and the pick &
    /// place module when the machine has them.
    pub devices: Vec<Box<dyn Device>>,
}

crate::bind_slots! {
    /// The members the scheduler keeps for each program.
    struct ProgramSlots for crate::registry::catalog::PROGRAM_TYPE {
        running: "Running",
        task: "Task",
    }
}

crate::bind_slots! {
    /// The master's members, which the world sets every update.
    struct MasterSlots for crate::registry::catalog::MOTION_TYPE {
        position: "MasterPosnFeedback",
        velocity: "MasterVelFeedback",
    }
}

/// The devices' view of the moment: the machine's update, its master, its inputs' edges and
/// its trace (borrowed field by field, so the devices and values can be borrowed beside it).
macro_rules! now {
    ($m:expr) => {
        Now {
            tick: $m.tick,
            time_ns: $m.tick * $m.image.tick_ns,
            tick_ns: $m.image.tick_ns,
            master: $m.master_now,
            master_profile: &$m.world.master,
            activity: &$m.activity,
            trace: &mut $m.trace,
        }
    };
}

/// How a run went.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Updates computed.
    pub ticks: u64,
    /// Simulated seconds.
    pub seconds: f64,
    /// Instructions executed.
    pub instructions: u64,
    /// Trace events by kind.
    pub events: Vec<(String, u64)>,
    /// The error that ended the run, if any.
    pub error: Option<RunError>,
    /// Why the run stopped.
    pub stop_reason: StopReason,
    /// The objects whose motion still ran when it stopped (`Index.1`, `Axis.2`, `Gear`).
    pub moving: Vec<String>,
    /// The tasks still blocked when it stopped, with what on and where.
    pub waiting: Vec<stuck::Waiting>,
}

/// A machine running.
pub struct Machine {
    image: MachineImage,
    values: Vec<f64>,
    snapshot: Vec<f64>,
    devices: Devices,
    world: World,
    tasks: Vec<Task>,
    trace: Trace,
    tick: u64,
    rr: usize,
    activity: Vec<InputActivity>,
    assign_last: Vec<Option<bool>>,
    instructions: u64,
    error: Option<RunError>,
    running_slots: Vec<ProgramSlots>,
    /// Master position at the current update.
    master_now: f64,
    /// Slots of the master's position and velocity.
    master_slots: MasterSlots,
    /// The run has begun: `start` traced, autostart programs started.
    begun: bool,
    /// An update has been computed (`tick` is the last one computed, not the next).
    stepped: bool,
    /// The REPL's own task, after the machine's tasks, once a typed line has run.
    repl_task: Option<usize>,
    /// Where inputs come from and outputs go: the simulated world unless a real device is
    /// attached.
    io: Box<dyn IoBackend>,
    /// The I/O link is down: motion was stopped, outputs are at their safe values and the
    /// programs are held until it comes back.
    io_down: bool,
    /// The tasks' `PRINT` lines and where they go.
    printer: print::Printer,
    /// A string being built (see [`exec::Ctx::scratch`]).
    scratch: String,
    /// MotionBASIC's random-number generator.
    rnd: rnd::Rnd,
    /// The `DATA` place of a probe or a task that has none (never read: probes run no READ).
    no_data: u32,
    /// How many runs of loops the machine ran outside the interpreter (`vm::tight`).
    tight_runs: u64,
    /// How many of those runs of translated bodies left an iteration to the interpreter.
    slow_runs: u64,
    /// The registers of a loop run on typed registers (`vm::body`), kept from one run to the
    /// next: a short loop entered often would otherwise clear them at each entry.
    body_regs: Box<body::Registers>,
    /// Per `WHILE` handed over (chunk, its `loop`) and per `FOR` (chunk, its `for.check`), over
    /// their first [`TRIAL`] entries: how many there were and the interpreter's instructions
    /// the machine ran in them (`Machine::run_body`, `Machine::judge_for`).
    /// Indexed by chunk, then instruction (grown when first needed): a lookup at every entry
    /// of a short loop must cost little.
    trials: Vec<Vec<(u32, u64)>>,
    /// The task whose last turn ended in a body that runs subroutines inside, its budget
    /// spent at a `GOSUB` or `RETURN` there: its next turn hands the loop back to the machine
    /// as soon as the interpreter has run the rest of that iteration (`Machine::run_task`).
    rejoin: Option<usize>,
    /// The loops their trial gave back to the interpreter, to be tried again
    /// (`Machine::retry_loops`), in the order they were given back.
    retries: Vec<Retry>,
    /// The machine's instruction count at which the earliest of [`Machine::retries`] is due.
    next_retry: u64,
}

/// A loop a trial gave back to the interpreter ([`Machine::judge_for`], [`Machine::run_body`]).
#[derive(Debug, Clone, Copy)]
struct Retry {
    /// Its chunk.
    chunk: usize,
    /// Its `for.check` or `loop`.
    pc: u32,
    /// The machine's instruction count at which it is tried again; `None` while it is.
    due: Option<u64>,
    /// How many of its trials have failed.
    failed: u32,
}

/// The trial of the loop whose `for.check` or `loop` is instruction `pc` of `chunk`
/// (`Machine::trials`).
fn trial_of(trials: &mut Vec<Vec<(u32, u64)>>, chunk: usize, pc: u32) -> &mut (u32, u64) {
    if trials.len() <= chunk {
        trials.resize_with(chunk + 1, Vec::new);
    }
    let of_chunk = &mut trials[chunk];
    let pc = pc as usize;
    if of_chunk.len() <= pc {
        of_chunk.resize(pc + 1, (0, 0));
    }
    &mut of_chunk[pc]
}

/// Trace every registry slot whose value differs from the snapshot, in slot order.
pub(crate) fn trace_changes(
    registry: &Registry,
    v: &[f64],
    snapshot: &mut [f64],
    trace: &mut Trace,
    tick: u64,
) {
    for (i, info) in registry.slots.iter().enumerate() {
        let x = v[i];
        if x.to_bits() != snapshot[i].to_bits() {
            snapshot[i] = x;
            if !info.member.continuous
                && !info.member.derived
                && !matches!(info.member.access, Access::Action | Access::Input)
            {
                trace.emit(
                    tick,
                    &Event::Change {
                        name: info.name.text(),
                        value: Value::of(info.ty, x),
                    },
                );
            }
        }
    }
}

impl Machine {
    /// A machine ready to run, writing its trace to `trace`.
    pub fn new(mut image: MachineImage, trace: Trace) -> Machine {
        let values = image.initial.clone();
        let devices = Devices::new(std::mem::take(&mut image.devices));
        let world = World::new(image.edges.clone(), image.master.clone());
        let tasks = (0..image.tasks).map(|_| Task::free()).collect();
        let slot_count = image.registry.slot_count();
        let running_slots = (0..image.registry.of(crate::registry::Kind::Program).count)
            .map(|i| ProgramSlots::of(&image.registry, i))
            .collect();
        let assign_last = vec![None; image.assignments.len()];
        let mut m = Machine {
            snapshot: Vec::new(),
            values,
            devices,
            world,
            tasks,
            trace,
            tick: 0,
            rr: 0,
            activity: Vec::new(),
            assign_last,
            instructions: 0,
            error: None,
            running_slots,
            master_now: 0.0,
            master_slots: MasterSlots::of(&image.registry, 0),
            begun: false,
            stepped: false,
            repl_task: None,
            io: Box::new(Simulator),
            io_down: false,
            printer: print::Printer::default(),
            scratch: String::new(),
            rnd: rnd::Rnd::new(image.seed),
            no_data: 0,
            tight_runs: 0,
            slow_runs: 0,
            body_regs: Box::default(),
            rejoin: None,
            trials: Vec::new(),
            retries: Vec::new(),
            next_retry: u64::MAX,
            image,
        };
        m.devices.start(&mut m.values);
        m.snapshot = m.values[..slot_count].to_vec();
        m
    }

    /// The value array (registry slots first).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The string table as the run left it (a string value is an index into it).
    pub fn strings(&self) -> &[String] {
        &self.image.strings
    }

    /// The registry.
    pub fn registry(&self) -> &Registry {
        &self.image.registry
    }

    /// The state of task `task` (exporters draw it; `None` past the last task).
    pub fn task_state(&self, task: usize) -> Option<TaskState> {
        self.tasks.get(task).map(|t| t.state)
    }

    /// How many runs of loops of one instruction (an empty `FOR`, a fill) the machine has run
    /// outside the interpreter (`vm::tight`): what tests read to see that it did.
    pub fn tight_runs(&self) -> u64 {
        self.tight_runs
    }

    /// How many runs of translated loop bodies (`vm::body`) stopped at an iteration they could
    /// not finish as the interpreter would (a value out of their range, a -0 they cannot
    /// carry, a fault), leaving it to the interpreter: what tests read to see that a body
    /// keeps running where it should.
    pub fn slow_runs(&self) -> u64 {
        self.slow_runs
    }

    /// Current value of a member by name, e.g. `Queue.0.QueueOffset` (for tests and tools).
    pub fn value_of(&self, name: &str) -> Option<f64> {
        let n = crate::syntax::ast::Name::from_token(name, 0);
        let r = crate::check::motionbasic::resolve(&self.image.registry, &n).ok()?;
        self.values.get(r.slot as usize).copied()
    }

    /// Run until the duration, the end of all programs, or an error.
    pub fn run(&mut self, duration_ns: Option<u64>) -> RunSummary {
        self.run_observed(duration_ns, &mut |_| {})
    }

    /// The device of type `T`, when the machine has one (tools and tests look inside).
    pub fn device<T: std::any::Any>(&self) -> Option<&T> {
        self.devices.get::<T>()
    }

    /// The time of the current update, seconds.
    pub fn time(&self) -> f64 {
        self.seconds()
    }

    /// Like [`Machine::run`], calling `observe` after every update (tests and tools watch the
    /// machine this way).
    pub fn run_observed(
        &mut self,
        duration_ns: Option<u64>,
        observe: &mut dyn FnMut(&Machine),
    ) -> RunSummary {
        self.run_controlled(duration_ns, &mut |m| {
            observe(m);
            None
        })
    }

    /// Like [`Machine::run_observed`], but `control` may end the run after any update by
    /// returning the reason (the real-time runner does on Ctrl-C or too many overruns; it
    /// also paces the run by waiting in it).
    pub fn run_controlled(
        &mut self,
        duration_ns: Option<u64>,
        control: &mut dyn FnMut(&Machine) -> Option<StopReason>,
    ) -> RunSummary {
        let tick_ns = self.image.tick_ns;
        let limit_ns = duration_ns.or(self.image.duration_ns);
        let last_tick = limit_ns.map(|d| d / tick_ns);
        let max_tick = DEFAULT_MAX_SECONDS * 1_000_000_000 / tick_ns;
        self.begin();
        let stop_reason;
        loop {
            let mut stop = None;
            if self.error.is_none() {
                self.step();
                stop = control(self);
            }
            if self.error.is_some() {
                stop_reason = StopReason::RunTimeError;
                break;
            }
            if self.trace.failed() {
                stop_reason = StopReason::TraceFailed;
                break;
            }
            if self.trace.full() {
                stop_reason = StopReason::TraceLimit {
                    bytes: self.trace.size_limit().unwrap_or_default(),
                };
                break;
            }
            if let Some(reason) = stop {
                stop_reason = reason;
                break;
            }
            if let Some(last) = last_tick {
                if self.tick >= last {
                    stop_reason = StopReason::Duration;
                    break;
                }
            } else {
                let idle = self.tasks.iter().all(|t| !t.busy());
                let world_done = self.world.last_edge().is_none_or(|t| t <= self.seconds());
                // Motion that comes to rest by itself holds the run open: the trace shows it
                // end (a gear or a jog would run forever, so it does not).
                if idle && world_done && !self.moving().iter().any(|m| m.settles) {
                    stop_reason = StopReason::ProgramsEnded;
                    break;
                }
                // A machine on real I/O runs until it is stopped (Ctrl-C, its duration).
                if self.tick >= max_tick && !self.io.real_time() {
                    stop_reason = StopReason::Cap {
                        seconds: DEFAULT_MAX_SECONDS,
                    };
                    self.trace
                        .machine_warning(self.tick, stop_reason.to_string());
                    let waiting = self.waiting();
                    self.trace_waiting(&waiting, "at the cap on simulated time");
                    break;
                }
            }
            self.tick += 1;
        }
        let moving: Vec<String> = self.moving().into_iter().map(|m| m.name).collect();
        self.trace.emit(
            self.tick,
            &Event::End {
                reason: stop_reason.to_string().into(),
                instructions: self.instructions,
                moving: moving.iter().map(|m| m.as_str().into()).collect(),
            },
        );
        RunSummary {
            moving,
            waiting: self.waiting(),
            ticks: self.tick + 1,
            seconds: self.tick as f64 * tick_ns as f64 / 1e9,
            instructions: self.instructions,
            events: self
                .trace
                .counts
                .iter()
                .map(|(k, v)| (k.to_string(), *v))
                .collect(),
            error: self.error.clone(),
            stop_reason,
        }
    }

    /// Flush the trace.
    pub fn finish(&mut self) -> std::io::Result<()> {
        self.trace.finish()
    }

    /// Begin the run, once: trace `start` and start the autostart programs. [`Machine::run`]
    /// does it; tools that drive the machine update by update ([`Machine::advance`], the REPL)
    /// get it at their first update or typed statement.
    pub fn begin(&mut self) {
        if self.begun {
            return;
        }
        self.begun = true;
        self.trace_start(0);
        let autostart = self.image.autostart.clone();
        for p in autostart {
            if let Err(message) = self.start_program(p) {
                self.error = Some(RunError {
                    program: p,
                    ..RunError::machine("", message, 0.0)
                });
            }
        }
    }

    fn trace_start(&mut self, tick: u64) {
        let tick_ns = self.image.tick_ns;
        let units = &self.image.units;
        self.trace.emit(
            tick,
            &Event::Start {
                machine: self.image.name.as_str().into(),
                update: tick_ns as f64 / 1e9,
                tasks: self.image.tasks,
                units: crate::trace::Units {
                    master: units.master.as_str().into(),
                    motor: units.motor.as_str().into(),
                },
            },
        );
    }

    /// The objects whose motion still runs now.
    pub fn moving(&self) -> Vec<crate::devices::Moving> {
        let t = self.seconds();
        let master_moves = self.world.master.moves_from(t);
        self.devices.moving(master_moves)
    }

    /// Time of the current update, seconds.
    fn seconds(&self) -> f64 {
        (self.tick as f64 * self.image.tick_ns as f64) / 1e9
    }

    /// Wire the machine to a real device instead of the simulator, before the run. The
    /// scenario's edges on inputs the device drives are dropped; returns how many.
    pub fn attach_io(&mut self, io: Box<dyn IoBackend>) -> usize {
        let dropped = self.world.drop_inputs(&io.driven_inputs());
        self.io = io;
        dropped
    }

    /// The I/O backend's device (`simulator` unless one is attached).
    pub fn io_device(&self) -> String {
        self.io.device()
    }

    /// Whether the attached I/O must be paced by the wall clock.
    pub fn io_real_time(&self) -> bool {
        self.io.real_time()
    }

    /// What the I/O link did so far.
    pub fn io_stats(&self) -> IoStats {
        self.io.stats()
    }

    /// Lines programs print (`PRINT`) are also written to `output`, as they happen.
    pub fn set_output(&mut self, output: Box<dyn std::io::Write>) {
        self.printer.set_output(output);
    }

    /// Keep the lines programs print for [`Machine::take_printed`] (the REPL shows them).
    pub fn keep_printed(&mut self) {
        self.printer.keep();
    }

    /// The lines printed since the last call, when [`Machine::keep_printed`] asked for them.
    pub fn take_printed(&mut self) -> Vec<String> {
        self.printer.take()
    }

    /// The I/O link is down (the machine is in its safe state).
    pub fn io_down(&self) -> bool {
        self.io_down
    }

    /// End of a run on real I/O: drive every output to its safe value.
    pub fn close_io(&mut self) -> Result<(), IoFault> {
        self.io.close()
    }

    /// Every device brings its motion to rest (`Stop`, an I/O fault).
    fn stop_all_motion(&mut self) {
        self.devices.stop_all(&mut self.values, &mut now!(self));
    }

    /// A link going down puts the machine in its safe state: the fault is traced with its
    /// device and cause, the outputs take their safe values, every motion stops with its stop
    /// deceleration and the programs are held. Its return is traced and releases them.
    fn link_event(&mut self, event: LinkEvent) {
        match event {
            LinkEvent::Fault(fault) => {
                self.trace.emit(
                    self.tick,
                    &Event::IoFault {
                        device: fault.device().into(),
                        cause: fault.cause().into(),
                    },
                );
                self.io_down = true;
                for (slot, safe) in self.io.safe_outputs() {
                    if let Some(v) = self.values.get_mut(slot as usize) {
                        *v = safe;
                    }
                }
                self.stop_all_motion();
                self.devices.hold(true);
            }
            LinkEvent::Warning(message) => {
                self.trace.machine_warning(self.tick, message);
            }
            LinkEvent::Reconnected { attempts } => {
                self.trace.emit(
                    self.tick,
                    &Event::IoReconnect {
                        device: self.io.device().into(),
                        attempts,
                    },
                );
                self.io_down = false;
                self.devices.hold(false);
            }
        }
    }

    /// Compute one update.
    pub fn step(&mut self) {
        let t = self.seconds();
        let now_ns = self.tick.saturating_mul(self.image.tick_ns);
        let mut activity = std::mem::take(&mut self.activity);
        let events =
            self.io
                .read_inputs(t, now_ns, &mut self.world, &mut self.values, &mut activity);
        self.activity = activity;
        self.master_now = self.world.master.position(t);
        self.values[self.master_slots.position as usize] = self.master_now;
        self.values[self.master_slots.velocity as usize] = self.world.master.speed(t);
        for event in events {
            self.link_event(event);
        }
        self.assignments();
        if self.error.is_some() {
            return;
        }
        // The control loop: every device moves to this update, then derives its status (queue
        // compares on the new positions, PLS windows, timers). The task runs after it, as on
        // the drive.
        let updated = self.devices.update(&mut self.values, &mut now!(self));
        if let Err(e) = updated {
            self.trace.machine_error(self.tick, e.message.clone());
            self.error = Some(RunError::machine(
                e.device,
                e.message,
                self.tick as f64 * self.image.tick_ns as f64 / 1e9,
            ));
            return;
        }
        self.devices.derive(&mut self.values, &mut now!(self));
        let mut made = Vec::new();
        self.devices.take_edges(&mut made);
        self.world.inject(made);
        // While the I/O link is down the programs are held: their inputs are stale.
        if !self.io_down {
            self.unblock();
            if self.error.is_none() {
                self.run_one_task();
            }
        }
        if let Some(event) = self.io.write_outputs(now_ns, &self.values) {
            self.link_event(event);
        }
        if self.trace.enabled() {
            trace_changes(
                &self.image.registry,
                &self.values,
                &mut self.snapshot,
                &mut self.trace,
                self.tick,
            );
        }
    }

    fn assignments(&mut self) {
        // Moved out for the loop, so the kernel and tasks can be borrowed beside it.
        let assignments = std::mem::take(&mut self.image.assignments);
        for (i, a) in assignments.iter().enumerate() {
            let on = a
                .sources
                .iter()
                .any(|(src, off)| (self.values[*src as usize] != 0.0) != *off);
            let last = self.assign_last[i];
            self.assign_last[i] = Some(on);
            if last == Some(on) {
                continue;
            }
            // The earliest source edge that makes the destination go on, at its exact time.
            let edge_at = a
                .sources
                .iter()
                .filter_map(|(src, off)| {
                    let x = self.activity.iter().find(|x| x.slot == *src)?;
                    if *off {
                        x.first_fall
                    } else {
                        x.first_rise
                    }
                })
                .reduce(f64::min);
            let edge = if on {
                edge_at.unwrap_or(self.seconds())
            } else {
                self.seconds()
            };
            let target = Target {
                hook: a.dest.hook,
                slot: a.dest.slot,
                instance: a.dest.instance,
            };
            let result = match (a.dest.access, a.dest.hook) {
                (Access::Action, _) if !on => Ok(()),
                // A module input (it latches in hardware) initiating a motion starts it at its
                // exact edge, as `Using Capture` would.
                (Access::Action, Hook::MotionStart) if a.latched && edge_at.is_some() => {
                    match self.devices.act(
                        target,
                        StartRef::Now,
                        0,
                        When::Edge(edge),
                        &mut self.values,
                        &mut now!(self),
                    ) {
                        Ok(ActOutcome::ProfileBusy) => {
                            let message = format!("{} from an assignment: a motion is running on its profile; ignored", a.dest.name);
                            self.trace.machine_warning(self.tick, message);
                            Ok(())
                        }
                        other => other.map(|_| ()),
                    }
                }
                (Access::Action, _) => self.control_or_act(target),
                // From an input: the edge at its exact time (a capture latches there, a
                // registration index's sensor acts there).
                _ => self.devices.write(
                    target,
                    f64::from(on),
                    When::Edge(edge),
                    &mut self.values,
                    &mut now!(self),
                ),
            };
            if let Err(message) = result {
                self.fail_assignment(a, message);
                break;
            }
        }
        self.image.assignments = assignments;
    }

    fn fail_assignment(&mut self, a: &Assignment, message: String) {
        let time = self.trace.seconds(self.tick);
        let message = format!("assignment to {}: {message}", a.dest.name);
        self.trace.machine_error(self.tick, message.clone());
        self.error = Some(RunError::machine("machine.toml", message, time));
    }

    /// Run an action: program control here, the rest on the devices.
    fn control_or_act(&mut self, target: Target) -> Result<(), String> {
        match target.hook {
            Hook::ProgramInitiate => self.start_program(target.instance),
            Hook::ProgramStop => {
                self.stop_program(target.instance);
                Ok(())
            }
            Hook::StopAll => {
                self.stop_all();
                self.stop_all_motion();
                Ok(())
            }
            _ => self
                .devices
                .act(
                    target,
                    StartRef::Now,
                    0,
                    When::Now,
                    &mut self.values,
                    &mut now!(self),
                )
                .map(|_| ()),
        }
    }

    /// Start a program on a free task (no effect, with a warning, when it already runs).
    fn start_program(&mut self, program: u32) -> Result<(), String> {
        let Some(&chunk) = self.image.programs.get(&program) else {
            return Err(format!("Program.{program} is not loaded"));
        };
        if self.tasks.iter().any(|t| {
            t.busy()
                && t.frames
                    .iter()
                    .any(|f| self.image.chunks[f.chunk].program == program)
        }) {
            self.trace.machine_warning(
                self.tick,
                format!("Program.{program}.Initiate: the program is already running"),
            );
            return Ok(());
        }
        // Programs run on the machine's own tasks, never on the REPL's.
        let Some(ti) = self.tasks[..self.image.tasks]
            .iter()
            .position(|t| !t.busy())
        else {
            return Err(format!(
                "Program.{program}.Initiate: all {} tasks are busy",
                self.tasks.len()
            ));
        };
        self.tasks[ti] = Task::starting(chunk, program);
        self.set_running(program, Some(ti));
        self.trace.emit(
            self.tick,
            &Event::Program {
                program,
                task: ti,
                event: ProgramEvent::Start,
            },
        );
        Ok(())
    }

    fn set_running(&mut self, program: u32, task: Option<usize>) {
        if let Some(&ProgramSlots {
            running,
            task: task_slot,
        }) = self.running_slots.get(program as usize)
        {
            self.values[running as usize] = f64::from(task.is_some());
            self.values[task_slot as usize] = task.map_or(-1.0, |t| t as f64);
        }
    }

    fn end_task(&mut self, ti: usize, event: ProgramEvent) {
        let program = self.tasks[ti].program;
        // A line left open by a trailing `;` or `,` is output when its task ends.
        if let Some(text) = self.printer.pending(ti) {
            let number = (program != REPL_PROGRAM).then_some(program);
            self.printer
                .emit(&mut self.trace, self.tick, ti, number, text);
        }
        self.tasks[ti] = Task::free();
        self.set_running(program, None);
        // A typed line is no program: its start and end are not program events.
        if program == REPL_PROGRAM {
            return;
        }
        self.trace.emit(
            self.tick,
            &Event::Program {
                program,
                task: ti,
                event,
            },
        );
    }

    fn stop_program(&mut self, program: u32) {
        let found: Vec<usize> = (0..self.tasks.len())
            .filter(|&i| {
                self.tasks[i].busy()
                    && self.tasks[i]
                        .frames
                        .iter()
                        .any(|f| self.image.chunks[f.chunk].program == program)
            })
            .collect();
        for ti in found {
            self.end_task(ti, ProgramEvent::Stop);
        }
    }

    fn stop_all(&mut self) {
        for ti in 0..self.tasks.len() {
            if self.tasks[ti].busy() {
                self.end_task(ti, ProgramEvent::Stop);
            }
        }
    }

    /// Re-examine blocked tasks: timed waits, motion waits, and `Wait For` conditions.
    fn unblock(&mut self) {
        for ti in 0..self.tasks.len() {
            match self.tasks[ti].state {
                TaskState::Sleeping { until } if self.tick >= until => {
                    self.tasks[ti].state = TaskState::Ready
                }
                TaskState::MotionWait { profile }
                    if !self.devices.profile_busy(profile as usize) =>
                {
                    self.tasks[ti].state = TaskState::Ready
                }
                TaskState::Waiting { retry, resume } => {
                    let Some(frame) = self.tasks[ti].frames.last().copied() else {
                        continue;
                    };
                    match self.exec(ti, frame.chunk, retry, true, u64::MAX) {
                        Exit::Probed { value: true, .. } => {
                            self.tasks[ti].state = TaskState::Ready;
                            if let Some(f) = self.tasks[ti].frames.last_mut() {
                                f.pc = resume;
                            }
                        }
                        Exit::Probed { value: false, .. } => {}
                        Exit::Fault { message, pc } => {
                            self.fault(ti, frame.chunk, pc, message);
                            return;
                        }
                        other => {
                            self.fault(
                                ti,
                                frame.chunk,
                                retry,
                                format!("internal: a Wait For condition ended with {other:?}"),
                            );
                            return;
                        }
                    }
                }
                _ => {}
            }
        }
    }

    fn exec(&mut self, task: usize, chunk: usize, pc: u32, probe: bool, budget: u64) -> Exit {
        // The other tasks, read by a `Call Program` to learn whether the program it calls is
        // running on one (no other task runs while this one does).
        let at = task.min(self.tasks.len());
        let (before, rest) = self.tasks.split_at_mut(at);
        let (frames, data_at, after) = match rest.split_first_mut() {
            Some((t, after)) => (Some(&mut t.frames), &mut t.data_at, &*after),
            None => (None, &mut self.no_data, &[][..]),
        };
        let slot_count = self.image.registry.slot_count() as u32;
        let mut ctx = Ctx {
            task,
            devices: &mut self.devices,
            registry: &self.image.registry,
            snapshot: &mut self.snapshot,
            now: now!(self),
            slot_count,
            printer: &mut self.printer,
            strings: &mut self.image.strings,
            scratch: &mut self.scratch,
            rnd: &mut self.rnd,
            seed: self.image.seed,
            data_at,
            chunks: &self.image.chunks,
            programs: &self.image.programs,
            other_tasks: [&*before, after],
            elsewhere: None,
        };
        let mut executed = self.instructions;
        let exit = exec::run(
            &self.image.chunks[chunk],
            pc,
            &mut self.values,
            &mut ctx,
            budget,
            &mut executed,
            probe,
            // A task's turn runs GOSUB and RETURN in the interpreter, on the task's frames; a
            // probe of a `Wait For` condition runs no subroutine.
            frames.filter(|_| !probe),
        );
        self.instructions = executed;
        exit
    }

    /// Do the `for.check` of the [`Op::ForTight`] at `pc` of `chunk` (the interpreter left
    /// it, its dispatch not counted), then run its loop here when [`Machine::run_loop`] can.
    /// Where the task goes on, and whether its budget is spent; or the `for.check`'s fault.
    fn enter_loop(
        &mut self,
        ti: usize,
        chunk: usize,
        pc: u32,
        budget_end: u64,
    ) -> Result<(u32, bool), String> {
        self.instructions += 1;
        let internal = || "internal error: a loop left to the machine that is not one".to_string();
        let c = self.image.chunks.get(chunk).ok_or_else(internal)?;
        let Some(&Op::ForTight {
            var,
            limit,
            exit,
            kept,
        }) = c.ops.get(pc as usize)
        else {
            return Err(internal());
        };
        let get = |r: u32| self.values.get(r as usize).copied();
        let (Some(x), Some(l), Some(s)) = (get(var), get(limit), get(limit + 1)) else {
            return Err(internal());
        };
        // As the interpreter's `for.check`.
        if s == 0.0 {
            return Err(exec::STEP_ZERO.into());
        }
        if (s > 0.0 && x > l) || (s < 0.0 && x < l) {
            return Ok((exit, false));
        }
        let before = self.instructions;
        let ran = self.run_loop(ti, chunk, pc + 1, budget_end);
        if !kept {
            self.judge_for(chunk, pc, self.instructions.saturating_sub(before));
        }
        Ok(ran.unwrap_or((pc + 1, false)))
    }

    /// Count an entry of the `FOR` whose `for.check` is the [`Op::ForTight`] at `pc` of
    /// `chunk`, in which the machine ran `counted` of the interpreter's instructions (0 when
    /// the loop was left to the interpreter). A `FOR` that, over its first [`TRIAL`] entries,
    /// runs fewer than [`FEWEST_COUNTED`] instructions per entry on average costs more to hand
    /// over (some 900 machine instructions an entry, `probe/inner`) than it gains: its
    /// `for.check` becomes a plain one for the rest of the run; one that does is marked kept,
    /// and no longer counted. Only the speed changes.
    fn judge_for(&mut self, chunk: usize, pc: u32, counted: u64) {
        let trial = trial_of(&mut self.trials, chunk, pc);
        *trial = (trial.0 + 1, trial.1 + counted);
        if trial.0 < TRIAL {
            return;
        }
        let pays = trial.1 >= u64::from(TRIAL) * FEWEST_COUNTED;
        let op = self
            .image
            .chunks
            .get_mut(chunk)
            .and_then(|c| c.ops.get_mut(pc as usize));
        if let Some(op) = op {
            if let Op::ForTight {
                var, limit, exit, ..
            } = *op
            {
                *op = if pays {
                    Op::ForTight {
                        var,
                        limit,
                        exit,
                        kept: true,
                    }
                } else {
                    Op::ForCheck { var, limit, exit }
                };
                if !pays {
                    self.retry_later(chunk, pc);
                }
            }
        }
    }

    /// Run here (`tight::run_plan`) the loop of one instruction starting at `start` of `chunk`,
    /// about to run an iteration, when it has at least [`tight::FEWEST`] more and writes
    /// nothing traced (`tight::plan`). Where the task goes on, and whether its budget is spent;
    /// `None` when the interpreter is to run it.
    fn run_loop(
        &mut self,
        ti: usize,
        chunk: usize,
        start: u32,
        budget_end: u64,
    ) -> Option<(u32, bool)> {
        let traced_below = self.traced_below();
        let c = self.image.chunks.get(chunk)?;
        let Some(plan) = tight::plan(&c.ops, &c.sure, start, traced_below) else {
            return self.run_body(ti, chunk, start.checked_sub(1)?, 0, budget_end);
        };
        let get = |r: u32| self.values.get(r as usize).copied();
        let (x, l, s) = (get(plan.var)?, get(plan.limit)?, get(plan.limit + 1)?);
        // NaN (a step of 0, an infinite one) is not long.
        let long = ((l - x) / s).partial_cmp(&(tight::FEWEST - 1.0));
        if !matches!(long, Some(Ordering::Greater | Ordering::Equal)) {
            return None;
        }
        // The next iteration's dispatch counted first, as the interpreter counts it.
        let mut n = self.instructions + 1;
        let (end, next) = tight::run_plan(&mut self.values, plan, start, &mut n, budget_end);
        self.tight_runs += 1;
        self.instructions = match end {
            // The interpreter runs that iteration (and counts its dispatch).
            tight::End::Slow => n - 1,
            tight::End::Done | tight::End::Budget => n,
        };
        Some((next, end == tight::End::Budget))
    }

    /// Run here (`vm::body`) the loop that instruction `entry` of `chunk` enters (its
    /// `for.check` or its `loop`), about to run its body's instruction `from` (0: an iteration
    /// from its start; else the start of a loop inside, where a run stopped), when its body is
    /// translated and writes nothing traced, on task `ti`'s top frame. Where the task goes
    /// on, and whether its budget is spent; `None` when the interpreter is to run it. A run
    /// left inside a subroutine the body runs inside leaves the task there, in the frame its
    /// `GOSUB` would have pushed.
    fn run_body(
        &mut self,
        ti: usize,
        chunk: usize,
        entry: u32,
        from: u16,
        budget_end: u64,
    ) -> Option<(u32, bool)> {
        let traced_below = self.traced_below();
        let b = self.image.chunks.get(chunk)?.bodies.get(&entry)?;
        // Its `GOSUB`s would fault here, or a program it calls is running (the interpreter's
        // to report). No other task runs while it does.
        if !b.subs.is_empty() {
            let tasks = &self.tasks;
            if tasks.get(ti)?.frames.len() >= MAX_CALL_DEPTH {
                return None;
            }
            let running = |c: usize| {
                tasks
                    .iter()
                    .any(|t| t.busy() && t.frames.iter().any(|f| f.chunk == c))
            };
            if b.subs
                .iter()
                .any(|s| s.call.is_some_and(|(_, c)| running(c)))
            {
                return None;
            }
        }
        if b.lowest_write < traced_below {
            // A variable it writes is traced: a `WHILE`'s `loop` goes back to a plain one
            // rather than leave the interpreter at every iteration for nothing.
            if b.counter.is_none() {
                self.plain_loop(chunk, entry);
            }
            return None;
        }
        let mut n = self.instructions;
        let mut ran = body::run(
            &mut self.values,
            &mut self.body_regs,
            b,
            &mut self.image.strings,
            from,
            &mut n,
            budget_end,
        );
        // A real variable it keeps as an `Int` holds a fraction (or whatever else kept it
        // from starting): the body with every real variable a real may start.
        if let (None, Some(plain)) = (&ran, &b.fallback) {
            ran = body::run(
                &mut self.values,
                &mut self.body_regs,
                plain,
                &mut self.image.strings,
                from,
                &mut n,
                budget_end,
            );
        }
        let Some((end, at)) = ran else {
            // A `FOR` too short this time is entered once; a `WHILE` that could not start
            // would come back at every iteration.
            if b.counter.is_none() {
                self.plain_loop(chunk, entry);
            }
            return None;
        };
        let counted = n - self.instructions;
        self.tight_runs += 1;
        self.slow_runs += u64::from(end == tight::End::Slow);
        self.instructions = n;
        // The interpreter goes on after the loop, or where the run was left.
        let has_subs = !b.subs.is_empty();
        let (next, sub) = match end {
            tight::End::Done => (b.after, None),
            tight::End::Budget | tight::End::Slow => b.place(u16::try_from(at).ok()?),
        };
        // A `WHILE` is handed over at every entry whatever it does then: one that goes round
        // only a few times each (Euclid's algorithm inside two `FOR`s) costs more to hand over
        // than it gains, and its `loop` goes back to being a plain one. Only the speed
        // changes: values and counts are the same either way.
        if b.counter.is_none() {
            let per_round = b.count;
            let trial = trial_of(&mut self.trials, chunk, entry);
            if trial.0 < TRIAL {
                *trial = (trial.0 + 1, trial.1 + counted);
                let fewest = (FEWEST_ROUNDS * per_round).max(FEWEST_COUNTED);
                if trial.0 == TRIAL && trial.1 < u64::from(TRIAL) * fewest {
                    self.plain_loop(chunk, entry);
                    self.retry_later(chunk, entry);
                }
            }
        }
        let spent = end == tight::End::Budget;
        if spent && has_subs {
            self.rejoin = Some(ti);
        }
        let Some((pc, callee)) = sub else {
            return Some((next, spent));
        };
        // Left in a subroutine (or a program called): the loop's frame goes on after the
        // `GOSUB` (or the call), the subroutine's is the task's top frame (whose instruction
        // the caller sets).
        let frames = &mut self.tasks.get_mut(ti)?.frames;
        let top = frames.last_mut()?;
        top.pc = next;
        frames.push(Frame {
            chunk: callee.unwrap_or(chunk),
            pc,
            gosub: callee.is_none(),
        });
        Some((pc, spent))
    }

    /// The loop whose `for.check` or `loop` is instruction `pc` of `chunk`, which its trial
    /// just gave back to the interpreter, tried again later: after [`RETRY_AFTER`] of the
    /// machine's instructions, doubled at each trial of it that failed before.
    fn retry_later(&mut self, chunk: usize, pc: u32) {
        let at = match self
            .retries
            .iter()
            .position(|r| r.chunk == chunk && r.pc == pc)
        {
            Some(at) => at,
            None => {
                self.retries.push(Retry {
                    chunk,
                    pc,
                    due: None,
                    failed: 0,
                });
                self.retries.len() - 1
            }
        };
        let retry = &mut self.retries[at];
        let wait = RETRY_AFTER << retry.failed.min(RETRY_LAST);
        retry.failed += 1;
        let due = self.instructions.saturating_add(wait);
        retry.due = Some(due);
        self.next_retry = self.next_retry.min(due);
    }

    /// Hand over again the loops whose retry is due ([`Machine::retry_later`]): a `for.check`
    /// made plain by its trial becomes the one that hands its loop over, a `loop` too, and
    /// each starts a new trial. Only the speed changes.
    fn retry_loops(&mut self) {
        let now = self.instructions;
        let mut next = u64::MAX;
        for retry in &mut self.retries {
            let Some(due) = retry.due else {
                continue;
            };
            if due > now {
                next = next.min(due);
                continue;
            }
            retry.due = None;
            let op = self
                .image
                .chunks
                .get_mut(retry.chunk)
                .and_then(|c| c.ops.get_mut(retry.pc as usize));
            let Some(op) = op else {
                continue;
            };
            *op = match *op {
                Op::ForCheck { var, limit, exit } => Op::ForTight {
                    var,
                    limit,
                    exit,
                    kept: false,
                },
                Op::Loop { target } => Op::LoopTight { target },
                _ => continue,
            };
            *trial_of(&mut self.trials, retry.chunk, retry.pc) = (0, 0);
        }
        self.next_retry = next;
    }

    /// The `loop` at `entry` of `chunk` that hands its loop over (`Op::LoopTight`) made a plain
    /// one for the rest of the run.
    fn plain_loop(&mut self, chunk: usize, entry: u32) {
        let op = self
            .image
            .chunks
            .get_mut(chunk)
            .and_then(|c| c.ops.get_mut(entry as usize));
        if let Some(op) = op {
            if let Op::LoopTight { target } = *op {
                *op = Op::Loop { target };
            }
        }
    }

    /// The loop at the top frame of task `ti`, whose last turn ended in it (its budget spent),
    /// goes on here when [`Machine::run_loop`] or [`Machine::run_body`] can: a `FOR` about to
    /// start an iteration, or a loop whose body starts there or holds a loop starting there
    /// (`Chunk::heads`). Whether the turn is over.
    fn resume_loop(&mut self, ti: usize, budget_end: u64) -> bool {
        let Some(frame) = self.tasks[ti].frames.last().copied() else {
            return false;
        };
        let Some(c) = self.image.chunks.get(frame.chunk) else {
            return false;
        };
        let op = |p: u32| c.ops.get(p as usize);
        let entered = frame
            .pc
            .checked_sub(1)
            .is_some_and(|p| matches!(op(p), Some(Op::ForTight { .. })));
        // A loop handed over still (a `WHILE` may have been given its plain `loop` back).
        let head = c.heads.get(&frame.pc).copied().filter(|&(entry, _)| {
            matches!(op(entry), Some(Op::ForTight { .. } | Op::LoopTight { .. }))
        });
        // The outermost loop first: a `FOR` inside one, run alone, would leave the rest of the
        // outer loop's iterations to the interpreter.
        let ran = head
            .and_then(|(entry, from)| self.run_body(ti, frame.chunk, entry, from, budget_end))
            .or_else(|| {
                entered
                    .then(|| self.run_loop(ti, frame.chunk, frame.pc, budget_end))
                    .flatten()
            });
        let Some((next, spent)) = ran else {
            return false;
        };
        if let Some(f) = self.tasks[ti].frames.last_mut() {
            f.pc = next;
        }
        spent
    }

    /// The slots a program's write to which is traced: those below this (the interpreter's
    /// `trace_below`).
    fn traced_below(&self) -> u32 {
        exec::traced_below(
            self.trace.enabled(),
            self.image.registry.slot_count() as u32,
        )
    }

    /// A run-time error of task `ti` at instruction `pc` of `chunk`: traced and kept with the
    /// place in the program (the expression or statement the instruction evaluates).
    fn fault(&mut self, ti: usize, chunk: usize, pc: u32, message: String) {
        let c = &self.image.chunks[chunk];
        let program = c.program;
        let file = c.file.clone();
        let time = self.trace.seconds(self.tick);
        let place = c.spans.get(pc as usize).map(|s| (c.source.clone(), *s));
        let (line, column) = match &place {
            Some((source, span)) => {
                let (l, col) = source.line_col(*span);
                (l as u32, col as u32)
            }
            None => (c.lines.get(pc as usize).copied().unwrap_or(0), 0),
        };
        let program_number = (program != REPL_PROGRAM).then_some(program);
        self.trace.emit(
            self.tick,
            &Event::Error {
                origin: Origin::At {
                    task: ti,
                    program: program_number,
                    file: file.as_str().into(),
                    line,
                    column,
                },
                message: message.as_str().into(),
            },
        );
        self.error = Some(RunError {
            task: ti,
            program,
            file,
            line,
            column,
            place,
            message,
            time,
        });
        self.end_task(ti, ProgramEvent::Error);
    }

    /// Pick the next ready task after the last one run, and run it for this update.
    fn run_one_task(&mut self) {
        let n = self.tasks.len();
        let Some(ti) = (0..n)
            .map(|k| (self.rr + k) % n)
            .find(|&i| self.tasks[i].state == TaskState::Ready)
        else {
            return;
        };
        self.rr = (ti + 1) % n;
        self.run_task(ti);
    }

    /// Run task `ti` for one turn: until it blocks, ends, or spends its instruction budget.
    fn run_task(&mut self, ti: usize) {
        if self.instructions >= self.next_retry {
            self.retry_loops();
        }
        let budget_end = self.instructions.saturating_add(self.image.budget);
        if self.resume_loop(ti, budget_end) {
            return;
        }
        // A turn starting inside an iteration of a body that runs subroutines (where its
        // budget was spent, at a `GOSUB` or a `RETURN`): the interpreter, which would run the
        // loop to the end of this turn, stops at each of its budget tests (a `GOSUB`, a
        // `RETURN`, a `for.next`, a `loop`) until the machine takes the loop back. A test
        // passed so is one the interpreter passes: only the speed changes.
        let mut rejoin = if self.rejoin == Some(ti) {
            self.rejoin = None;
            REJOIN_TESTS
        } else {
            0
        };
        loop {
            let Some(frame) = self.tasks[ti].frames.last().copied() else {
                self.end_task(ti, ProgramEvent::End);
                return;
            };
            let end = if rejoin > 0 {
                budget_end.min(self.instructions.saturating_add(1))
            } else {
                budget_end
            };
            let exit = self.exec(ti, frame.chunk, frame.pc, false, end);
            // The frame running when the interpreter stopped, which a `Call Program` or the
            // end of a called program may have changed: its program is the one faults name.
            let frame = self.tasks[ti].frames.last().copied().unwrap_or(frame);
            let set_pc = |m: &mut Machine, pc: u32| {
                if let Some(f) = m.tasks[ti].frames.last_mut() {
                    f.pc = pc;
                }
            };
            match exit {
                Exit::Yield(pc) if self.instructions < budget_end => {
                    set_pc(self, pc);
                    rejoin = rejoin.saturating_sub(1);
                    if self.resume_loop(ti, budget_end) {
                        return;
                    }
                }
                Exit::Yield(pc) => {
                    set_pc(self, pc);
                    return;
                }
                Exit::Wait { retry, resume } => {
                    set_pc(self, retry);
                    self.tasks[ti].state = TaskState::Waiting { retry, resume };
                    return;
                }
                Exit::Sleep { ticks, pc } => {
                    set_pc(self, pc);
                    self.tasks[ti].state = TaskState::Sleeping {
                        until: self.tick + ticks,
                    };
                    return;
                }
                Exit::MotionBusy { profile, pc } => {
                    set_pc(self, pc);
                    self.tasks[ti].state = TaskState::MotionWait { profile };
                    return;
                }
                Exit::Gosub { target, ret } => {
                    set_pc(self, ret);
                    if self.tasks[ti].frames.len() >= MAX_CALL_DEPTH {
                        self.fault(
                            ti,
                            frame.chunk,
                            ret.saturating_sub(1),
                            format!("GOSUB nested deeper than {MAX_CALL_DEPTH}"),
                        );
                        return;
                    }
                    self.tasks[ti].frames.push(Frame {
                        chunk: frame.chunk,
                        pc: target,
                        gosub: true,
                    });
                    if self.instructions >= budget_end {
                        return;
                    }
                }
                Exit::Return { pc } => {
                    // The frame running now (the interpreter may have entered and left
                    // subroutines since `frame` was read).
                    let in_subroutine = self.tasks[ti].frames.last().is_some_and(|f| f.gosub);
                    if !in_subroutine {
                        self.fault(ti, frame.chunk, pc, "RETURN without GOSUB".into());
                        return;
                    }
                    self.tasks[ti].frames.pop();
                    if self.instructions >= budget_end {
                        return;
                    }
                }
                Exit::End => {
                    // END in a subroutine ends its program, not just the subroutine.
                    while self.tasks[ti].frames.last().is_some_and(|f| f.gosub) {
                        self.tasks[ti].frames.pop();
                    }
                    self.tasks[ti].frames.pop();
                    if self.tasks[ti].frames.is_empty() {
                        self.end_task(ti, ProgramEvent::End);
                        return;
                    }
                }
                Exit::Call { program, pc } => {
                    set_pc(self, pc);
                    // A machine has few programs: comparing their numbers is quicker than
                    // hashing one (a program may call another every few instructions).
                    let found = self.image.programs.iter().find(|(&p, _)| p == program);
                    let Some((_, &chunk)) = found else {
                        self.fault(
                            ti,
                            frame.chunk,
                            pc.saturating_sub(1),
                            format!("Program.{program} is not loaded"),
                        );
                        return;
                    };
                    let running_elsewhere = self
                        .tasks
                        .iter()
                        .any(|t| t.busy() && t.frames.iter().any(|f| f.chunk == chunk));
                    if running_elsewhere {
                        self.fault(
                            ti,
                            frame.chunk,
                            pc.saturating_sub(1),
                            format!("Call Program.{program}: the program is already running"),
                        );
                        return;
                    }
                    if self.tasks[ti].frames.len() >= MAX_CALL_DEPTH {
                        self.fault(
                            ti,
                            frame.chunk,
                            pc.saturating_sub(1),
                            format!("calls nested deeper than {MAX_CALL_DEPTH}"),
                        );
                        return;
                    }
                    self.tasks[ti].frames.push(Frame {
                        chunk,
                        pc: 0,
                        gosub: false,
                    });
                    if self.instructions >= budget_end {
                        return;
                    }
                }
                Exit::Control { hook, instance, pc } => {
                    set_pc(self, pc);
                    // Only program control leaves the interpreter: its slot is not needed.
                    let r = self.control_or_act(Target {
                        hook,
                        slot: 0,
                        instance,
                    });
                    if let Err(message) = r {
                        self.fault(ti, frame.chunk, pc.saturating_sub(1), message);
                        return;
                    }
                    if !self.tasks[ti].busy() {
                        return;
                    }
                }
                Exit::Fault { message, pc } => {
                    self.fault(ti, frame.chunk, pc, message);
                    return;
                }
                Exit::Probed { .. } => return,
                Exit::Back { pc, start } => {
                    let (next, spent) = self
                        .run_body(ti, frame.chunk, pc, 0, budget_end)
                        .unwrap_or((start, false));
                    set_pc(self, next);
                    if spent {
                        return;
                    }
                }
                Exit::Loop { pc } => match self.enter_loop(ti, frame.chunk, pc, budget_end) {
                    Ok((next, spent)) => {
                        set_pc(self, next);
                        if spent {
                            return;
                        }
                    }
                    Err(message) => {
                        self.fault(ti, frame.chunk, pc, message);
                        return;
                    }
                },
            }
        }
    }
}
