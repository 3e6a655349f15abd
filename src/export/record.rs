//! What a plot is drawn from, gathered as the run (or a recorded trace) goes: the chosen
//! signals as bounded time series, and the events the pictures mark (motions, captures, mark
//! latches, picks and places). Trace lines come in as JSON, from the live run's trace or a file;
//! continuous members, which the trace does not carry, come in as samples (observed each update
//! of a live run, or read from a CSV).

use super::series::{Path2, Series};
use crate::trace::{Event, MotionPhase, Value};
use indexmap::{IndexMap, IndexSet};

/// The pictures a plot holds.
#[derive(Debug, Clone, PartialEq)]
pub enum Preset {
    /// A PowerTools drive: master and servo position, index activity, queue counts.
    Servo,
    /// Web registration on DSP axes: pitch and phase error per printed mark.
    Web,
    /// Pick & place: the tool's path in X/Y, and Z against time.
    PickPlace,
    /// The signals named on the command line, against time.
    Signals(Vec<String>),
}

/// What to gather for a plot.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The pictures.
    pub preset: Preset,
    /// Start of the time window, seconds.
    pub from: f64,
    /// End of the time window (`None`: the end of the run).
    pub to: Option<f64>,
}

/// The pick & place preset without a window end shows this many whole cycles.
pub const PP_CYCLES: usize = 3;

/// Names the servo preset draws against time.
pub const MASTER_POSITION: &str = "MasterPosnFeedback";
/// The servo axis's position.
pub const SERVO_POSITION: &str = "PosnFeedback";
/// The pick & place tool's X, Y and Z.
pub const TOOL_XYZ: [&str; 3] = [
    "PickPlace.alrActPos[1]",
    "PickPlace.alrActPos[2]",
    "PickPlace.alrActPos[3]",
];

impl Plan {
    /// The members this plan draws as series against time.
    pub fn wants_series(&self, name: &str) -> bool {
        match &self.preset {
            Preset::Servo => {
                name == MASTER_POSITION
                    || name == SERVO_POSITION
                    || ((name.starts_with("Index.") || name.starts_with("Home."))
                        && name.ends_with(".CommandInProgress"))
                    || (name.starts_with("Queue.") && name.ends_with(".QueueCount"))
            }
            Preset::Web => false,
            Preset::PickPlace => name == TOOL_XYZ[2],
            Preset::Signals(names) => names.iter().any(|n| n == name),
        }
    }
}

/// One printed mark: the positions every latching axis reported at its edge, and the program's
/// variables as they stood when the next mark came (after the program had dealt with this one).
#[derive(Debug, Clone, Default)]
pub struct Mark {
    /// Exact edge time.
    pub time: f64,
    /// (axis, latched position), in the order the trace gave them.
    pub positions: Vec<(u32, f64)>,
    /// Every member's value by then (only the members the web picture uses are kept).
    pub after: IndexMap<String, f64>,
}

/// Everything gathered.
#[derive(Debug, Clone)]
pub struct Recording {
    /// Machine name.
    pub machine: String,
    /// Servo axis unit.
    pub motor_unit: String,
    /// Master unit.
    pub master_unit: String,
    /// Update period, s.
    pub update: f64,
    /// The window drawn: from …
    pub from: f64,
    /// … to (the window's end, or the last time seen).
    pub to: f64,
    /// The chosen signals over time.
    pub series: IndexMap<String, Series>,
    /// Signals seen as booleans in the trace, or known bits.
    pub bits: IndexSet<String>,
    /// Continuous samples came in (a live run, or a CSV).
    pub sampled: bool,
    /// The series that came in as samples (drawn through their samples, not as steps).
    pub sampled_names: IndexSet<String>,
    /// Master position at captures (exact edge time) and at the end of motions (bounded like
    /// any series: an hour of products is hundreds of thousands of them).
    pub master_at_events: Series,
    /// Servo command position at captures and at the start and end of motions.
    pub servo_at_events: Series,
    /// Printed marks (latches grouped by edge time).
    pub marks: Vec<Mark>,
    /// Pick events: time, x, y, z.
    pub picks: Vec<[f64; 4]>,
    /// Place events: time, x, y, z.
    pub places: Vec<[f64; 4]>,
    /// The tool's X/Y path.
    pub path: Path2,
    /// The window ended after the first whole pick-and-place cycles (no end was given).
    pub auto_window: bool,
    /// The last value of every member seen in a change (the per-mark pictures read these).
    pub current: IndexMap<String, f64>,
}

/// Add a point to an event series, unless the value is not a number (null in the trace).
fn push_finite(series: &mut Series, t: f64, v: f64) {
    if v.is_finite() {
        series.push(t, v);
    }
}

/// Members whose values are kept with each mark for the web picture.
pub const MARK_VARIABLES: &[&str] = &["PLEN&", "PLEN.TMP&", "DIFF&", "CORR&"];

/// Gathers a [`Recording`] for a [`Plan`].
pub struct Recorder {
    plan: Plan,
    rec: Recording,
    to: Option<f64>,
    picks_in_window: usize,
    mark_open: bool,
    last_t: f64,
    /// Series drawn from samples only: their change events are not used.
    samples_only: IndexSet<String>,
}

impl Recorder {
    /// A recorder for `plan`; `update` is the update period (the series' finest bucket).
    pub fn new(plan: Plan, update: f64) -> Recorder {
        let to = plan.to;
        let from = plan.from;
        Recorder {
            rec: Recording {
                machine: String::new(),
                motor_unit: "units".into(),
                master_unit: "units".into(),
                update,
                from,
                to: from,
                series: IndexMap::new(),
                bits: IndexSet::new(),
                sampled: false,
                sampled_names: IndexSet::new(),
                master_at_events: Series::new(from, update),
                servo_at_events: Series::new(from, update),
                marks: Vec::new(),
                picks: Vec::new(),
                places: Vec::new(),
                // 0.05 mm between points keeps a path smooth at any plot size; the cap keeps a
                // long window from holding the whole run in memory.
                path: Path2::new(0.05, 200_000),
                auto_window: false,
                current: IndexMap::new(),
            },
            plan,
            to,
            picks_in_window: 0,
            mark_open: false,
            last_t: from,
            samples_only: IndexSet::new(),
        }
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Machine name and units, when known before the trace says them (a live run).
    pub fn set_machine(&mut self, name: &str, motor: &str, master: &str) {
        self.rec.machine = name.to_string();
        self.rec.motor_unit = motor.to_string();
        self.rec.master_unit = master.to_string();
    }

    /// Note a member as a bit (a live run knows its registry).
    pub fn mark_bit(&mut self, name: &str) {
        self.rec.bits.insert(name.to_string());
    }

    /// The value a series starts the run with (a live run knows it; a trace gives only
    /// changes).
    pub fn seed(&mut self, name: &str, v: f64) {
        if self.plan.wants_series(name) {
            self.series(name).before = Some(v);
        }
        // A member the programs only ever write with the value it has is never in the trace:
        // its value is known from the start.
        self.rec.current.entry(name.to_string()).or_insert(v);
    }

    /// Draw `name` from samples only (a CSV has it every row; its changes would repeat it out
    /// of time order).
    pub fn prefer_samples(&mut self, name: &str) {
        self.samples_only.insert(name.to_string());
    }

    /// True while `t` is inside the window.
    pub fn in_window(&self, t: f64) -> bool {
        t >= self.plan.from && self.to.is_none_or(|to| t <= to)
    }

    /// True once the window has closed (nothing later is drawn).
    pub fn closed(&self, t: f64) -> bool {
        self.to.is_some_and(|to| t > to)
    }

    fn series(&mut self, name: &str) -> &mut Series {
        let (from, update) = (self.plan.from, self.rec.update);
        self.rec
            .series
            .entry(name.to_string())
            .or_insert_with(|| Series::new(from, update))
    }

    /// Take one trace event, at time `t`.
    pub fn event(&mut self, t: f64, e: &Event<'_>) {
        match e {
            Event::Start { machine, units, .. } => {
                self.rec.machine = machine.to_string();
                self.rec.motor_unit = units.motor.to_string();
                self.rec.master_unit = units.master.to_string();
                return;
            }
            Event::End { .. } => {
                self.last_t = self.last_t.max(t);
                return;
            }
            Event::Change { name, value } => {
                // Kept whatever the window: a mark's variables are read when the next one comes.
                let v = value.number();
                match self.rec.current.get_mut(&**name) {
                    Some(c) => *c = v,
                    None => {
                        self.rec.current.insert(name.to_string(), v);
                    }
                }
            }
            _ => {}
        }
        if self.closed(t) {
            // Marks after the window still close the last one inside it.
            if matches!(e, Event::Latch { .. }) {
                self.close_mark();
            }
            return;
        }
        self.last_t = self.last_t.max(t);
        let inside = t >= self.plan.from;
        match e {
            Event::Change { name, value } => {
                let v = value.number();
                if matches!(value, Value::Bit(_)) && !self.rec.bits.contains(&**name) {
                    self.rec.bits.insert(name.to_string());
                }
                if self.plan.wants_series(name) && !self.samples_only.contains(&**name) {
                    if inside {
                        self.series(name).level(t, v);
                    } else {
                        let s = self.series(name);
                        s.before = Some(v);
                        s.changed = true;
                    }
                }
            }
            _ if !inside => {}
            // Non-finite positions (written as null) are not drawn.
            Event::Motion { phase, .. } => match *phase {
                MotionPhase::Start { position, .. } => {
                    push_finite(&mut self.rec.servo_at_events, t, position)
                }
                MotionPhase::Done {
                    master, position, ..
                } => {
                    push_finite(&mut self.rec.servo_at_events, t, position);
                    push_finite(&mut self.rec.master_at_events, t, master);
                }
            },
            Event::Capture {
                master, command, ..
            } => {
                // At the update's time: a series takes its values in time order, and the
                // exact edge time is within the update before.
                push_finite(&mut self.rec.master_at_events, t, *master);
                push_finite(&mut self.rec.servo_at_events, t, *command);
            }
            Event::Latch {
                axis,
                time,
                position,
                ..
            } => {
                let time = *time;
                let same = self.mark_open
                    && self
                        .rec
                        .marks
                        .last()
                        .is_some_and(|m| m.time.to_bits() == time.to_bits());
                if !same {
                    self.close_mark();
                    self.rec.marks.push(Mark {
                        time,
                        ..Mark::default()
                    });
                    self.mark_open = true;
                }
                if let Some(m) = self.rec.marks.last_mut() {
                    m.positions.push((*axis, *position));
                }
            }
            Event::Pick { x, y, z, .. } => {
                self.picks_in_window += 1;
                self.rec.picks.push([t, *x, *y, *z]);
                if self.plan.preset == Preset::PickPlace
                    && self.plan.to.is_none()
                    && self.picks_in_window > PP_CYCLES
                {
                    // The next pick after the last whole cycle closes the window.
                    self.to = Some(t);
                    self.rec.auto_window = true;
                }
            }
            Event::Place { x, y, z, .. } => self.rec.places.push([t, *x, *y, *z]),
            _ => {}
        }
    }

    /// Keep the variables as they stand with the mark before (the program has dealt with it).
    fn close_mark(&mut self) {
        if !self.mark_open {
            return;
        }
        self.mark_open = false;
        let current = &self.rec.current;
        if let Some(m) = self.rec.marks.last_mut() {
            for (k, v) in current {
                if MARK_VARIABLES.contains(&k.as_str()) {
                    m.after.insert(k.clone(), *v);
                }
            }
        }
    }

    /// Take a sample of a continuous member.
    pub fn sample(&mut self, t: f64, name: &str, v: f64) {
        if !self.in_window(t) {
            return;
        }
        self.rec.sampled = true;
        self.last_t = self.last_t.max(t);
        if self.plan.wants_series(name) {
            if !self.rec.sampled_names.contains(name) {
                self.rec.sampled_names.insert(name.to_string());
            }
            self.series(name).push(t, v);
        }
    }

    /// Take a sample of the tool's X and Y.
    pub fn sample_xy(&mut self, t: f64, x: f64, y: f64) {
        if !self.in_window(t) {
            return;
        }
        self.rec.sampled = true;
        self.rec.path.push(x, y);
    }

    /// Everything gathered.
    pub fn finish(mut self) -> Recording {
        self.close_mark();
        for s in self.rec.series.values_mut() {
            s.flush();
        }
        self.rec.to = match self.to {
            Some(to) => to.min(self.last_t).max(self.plan.from),
            None => self.last_t,
        };
        self.rec
    }
}
