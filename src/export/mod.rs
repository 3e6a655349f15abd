//! Pictures of the machine: a Value Change Dump for timing-diagram viewers (GTKWave, Surfer),
//! sampled numeric signals as CSV, and SVG plots, from a live run or (plots) a recorded trace.
//!
//! A live run is watched after every update through [`Machine::run_observed`]: positions and
//! velocities move every update and are not in the JSON trace, so the exporters read them from
//! the machine's values. Plots take the trace's events too: when a plot is asked for, the
//! trace's lines also go to the plot's recorder (see [`Export::trace_sink`]). Nothing here runs
//! unless asked for: without `--vcd`, `--csv` or `--plot` a run is exactly what it was.

pub mod csv;
pub mod figure;
pub mod input;
pub mod plot;
pub mod record;
pub mod series;
pub mod signals;
pub mod vcd;

use crate::registry::{Kind, SlotId};
use crate::vm::{Machine, MachineImage};
use record::{Plan, Preset, Recorder, TOOL_XYZ};
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// What went wrong in an export.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Options that do not fit together, or name what does not exist.
    #[error("{0}")]
    Usage(String),
    /// A file to read that is not what pacer writes.
    #[error("{}: {message}", path.display())]
    Input {
        /// The file.
        path: PathBuf,
        /// What is wrong, with the line.
        message: String,
    },
    /// A file that cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

impl ExportError {
    /// The exit code of `pacer`: 1 for problems in what was given, 3 for a file not written.
    pub fn exit_code(&self) -> u8 {
        match self {
            ExportError::Usage(_) | ExportError::Input { .. } => 1,
            ExportError::Io { .. } => 3,
        }
    }
}

/// Export options of `pacer run`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ExportArgs {
    /// Write a Value Change Dump (GTKWave, Surfer) of every signal that changes
    #[arg(long, value_name = "FILE.vcd")]
    pub vcd: Option<PathBuf>,
    /// Write sampled numeric signals as CSV (--signals, else every position and velocity)
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Draw plots to an SVG file (--signals, else the machine's own pictures)
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Signals for --csv and --plot, comma-separated (e.g. PosnFeedback,Queue.0.QueueCount)
    #[arg(long, value_name = "NAMES")]
    pub signals: Vec<String>,
    /// CSV sample period (default: every update), e.g. 10ms
    #[arg(long, value_name = "PERIOD")]
    pub sample: Option<String>,
    /// Time window of the plot, seconds: FROM:TO (either may be left out)
    #[arg(long, value_name = "FROM:TO")]
    pub window: Option<String>,
}

/// Options of `pacer plot`.
#[derive(clap::Args, Debug, Clone)]
pub struct PlotArgs {
    /// A recorded trace (FILE.jsonl), and optionally the CSV the same run wrote with --csv
    #[arg(required = true, value_name = "TRACE.jsonl [DATA.csv]")]
    pub files: Vec<PathBuf>,
    /// The SVG to write (default: the trace's name with .svg)
    #[arg(long, short, value_name = "FILE.svg")]
    pub output: Option<PathBuf>,
    /// Signals to draw against time, comma-separated (default: the machine's own pictures)
    #[arg(long, value_name = "NAMES")]
    pub signals: Vec<String>,
    /// Time window, seconds: FROM:TO (either may be left out)
    #[arg(long, value_name = "FROM:TO")]
    pub window: Option<String>,
}

/// `FROM:TO` in seconds (or with a unit: `500ms`); either side may be empty.
pub fn parse_window(text: &str) -> Result<(f64, Option<f64>), ExportError> {
    let bad = |why: String| ExportError::Usage(format!("--window {text}: {why}"));
    let (a, b) = text
        .split_once(':')
        .ok_or_else(|| bad("write FROM:TO in seconds, e.g. 38:46 or 10: or :5".into()))?;
    let side = |s: &str| -> Result<Option<f64>, ExportError> {
        let s = s.trim();
        if s.is_empty() {
            return Ok(None);
        }
        crate::config::values::parse_duration(s)
            .map(|ns| Some(ns as f64 / 1e9))
            .map_err(bad)
    };
    let from = side(a)?.unwrap_or(0.0);
    let to = side(b)?;
    if let Some(to) = to {
        if to <= from {
            return Err(bad("the end must come after the start".into()));
        }
    }
    Ok((from, to))
}

/// The exports of one run.
pub struct Export {
    vcd: Option<vcd::VcdWriter>,
    csv: Option<csv::CsvWriter>,
    plot: Option<LivePlot>,
    tick_ns: u64,
    tasks: usize,
}

struct LivePlot {
    path: PathBuf,
    file: std::fs::File,
    recorder: Rc<RefCell<Option<Recorder>>>,
    /// Continuous members sampled every update: slot and name.
    samples: Vec<(SlotId, String)>,
    /// The tool's X and Y (pick & place).
    xy: Option<(SlotId, SlotId)>,
}

impl Export {
    /// Check the options against the machine and create the files (so an unwritable path or an
    /// unknown signal stops the run before it starts).
    pub fn open(args: &ExportArgs, image: &MachineImage) -> Result<Export, ExportError> {
        let registry = &image.registry;
        if args.csv.is_none() && args.plot.is_none() && !args.signals.is_empty() {
            return Err(ExportError::Usage(
                "--signals chooses what --csv and --plot write: give one of them".into(),
            ));
        }
        if args.csv.is_none() && args.sample.is_some() {
            return Err(ExportError::Usage(
                "--sample is the period of --csv rows: give --csv".into(),
            ));
        }
        if args.plot.is_none() && args.window.is_some() {
            return Err(ExportError::Usage(
                "--window is the time window of --plot: give --plot".into(),
            ));
        }
        let outputs: Vec<&PathBuf> = [&args.vcd, &args.csv, &args.plot]
            .into_iter()
            .flatten()
            .collect();
        for (i, p) in outputs.iter().enumerate() {
            if outputs[..i].contains(p) {
                return Err(ExportError::Usage(format!(
                    "{} is given for two exports: each needs its own file",
                    p.display()
                )));
            }
        }
        let chosen = if args.signals.is_empty() {
            None
        } else {
            Some(signals::resolve_list(registry, &args.signals)?)
        };
        let period = match &args.sample {
            None => None,
            Some(p) => {
                let ns = crate::config::values::parse_duration(p)
                    .map_err(|e| ExportError::Usage(format!("--sample {p}: {e}")))?;
                if ns < image.tick_ns {
                    return Err(ExportError::Usage(format!(
                        "--sample {p}: shorter than the update ({} s): rows come at most once \
                         per update",
                        image.tick_ns as f64 / 1e9
                    )));
                }
                Some(ns)
            }
        };
        let window = match &args.window {
            None => (0.0, None),
            Some(w) => parse_window(w)?,
        };
        let csv = match &args.csv {
            None => None,
            Some(p) => Some(csv::CsvWriter::create(
                p,
                chosen
                    .clone()
                    .unwrap_or_else(|| signals::positions_and_velocities(registry)),
                image.tick_ns,
                period,
            )?),
        };
        let plot = match &args.plot {
            None => None,
            Some(p) => {
                if let Some(s) = chosen.iter().flatten().find(|s| s.text) {
                    return Err(ExportError::Usage(format!(
                        "--signals: {} holds text, and --plot draws numbers (--csv writes text)",
                        s.name
                    )));
                }
                Some(LivePlot::open(p, image, chosen.as_deref(), window)?)
            }
        };
        let vcd = match &args.vcd {
            None => None,
            Some(p) => Some(vcd::VcdWriter::create(p, image)?),
        };
        Ok(Export {
            vcd,
            csv,
            plot,
            tick_ns: image.tick_ns,
            tasks: image.tasks,
        })
    }

    /// Something is exported (otherwise the run need not be observed at all).
    pub fn is_active(&self) -> bool {
        self.vcd.is_some() || self.csv.is_some() || self.plot.is_some()
    }

    /// What watches the trace's events: the plot's recorder, when a plot is drawn (the plot
    /// then needs the trace's events even without `--trace`).
    pub fn trace_observer(&self) -> Option<crate::trace::Observer> {
        let recorder = Rc::clone(&self.plot.as_ref()?.recorder);
        Some(Box::new(move |t, event| {
            if let Some(r) = recorder.borrow_mut().as_mut() {
                r.event(t, event);
            }
        }))
    }

    /// Note the machine as it is before the run.
    pub fn start(&mut self, m: &Machine) {
        if let Some(v) = &mut self.vcd {
            v.start(m, self.tasks);
        }
        if let Some(p) = &mut self.plot {
            if let Some(r) = p.recorder.borrow_mut().as_mut() {
                // A live run knows where every series starts; a trace only has changes.
                for (i, info) in m.registry().slots.iter().enumerate() {
                    r.seed(&info.name.text(), m.values()[i]);
                }
            }
        }
    }

    /// Take the update just computed.
    pub fn observe(&mut self, m: &Machine) {
        let t = m.time();
        let tick = (t * 1e9 / self.tick_ns as f64).round() as u64;
        if let Some(v) = &mut self.vcd {
            v.observe(m, tick);
        }
        if let Some(c) = &mut self.csv {
            c.observe(m, tick);
        }
        if let Some(p) = &mut self.plot {
            let mut guard = p.recorder.borrow_mut();
            let Some(r) = guard.as_mut() else { return };
            if !r.in_window(t) {
                return;
            }
            let v = m.values();
            for (slot, name) in &p.samples {
                r.sample(t, name, v[*slot as usize]);
            }
            if let Some((x, y)) = p.xy {
                r.sample_xy(t, v[x as usize], v[y as usize]);
            }
        }
    }

    /// Finish every file; the paths written, by kind.
    pub fn finish(
        self,
        registry: &crate::registry::Registry,
    ) -> Result<Vec<(&'static str, PathBuf)>, ExportError> {
        let mut written = Vec::new();
        if let Some(v) = self.vcd {
            written.push(("vcd", v.finish(registry)?));
        }
        if let Some(c) = self.csv {
            written.push(("csv", c.finish()?));
        }
        if let Some(p) = self.plot {
            let recorder = p.recorder.borrow_mut().take();
            if let Some(r) = recorder {
                let preset = r.plan().preset.clone();
                let rec = r.finish();
                write_svg(&p.path, &p.file, &figure::figure(&preset, &rec))?;
                written.push(("plot", p.path));
            }
        }
        Ok(written)
    }
}

impl LivePlot {
    fn open(
        path: &Path,
        image: &MachineImage,
        chosen: Option<&[signals::Signal]>,
        (from, to): (f64, Option<f64>),
    ) -> Result<LivePlot, ExportError> {
        let registry = &image.registry;
        let preset = match chosen {
            Some(s) => Preset::Signals(s.iter().map(|s| s.name.clone()).collect()),
            None if registry.of(Kind::PickPlace).count > 0 => Preset::PickPlace,
            None if registry.of(Kind::Axis).count > 0 => Preset::Web,
            None => Preset::Servo,
        };
        let file = std::fs::File::create(path).map_err(|source| ExportError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let plan = Plan { preset, from, to };
        let mut recorder = Recorder::new(plan, image.tick_ns as f64 / 1e9);
        recorder.set_machine(&image.name, &image.units.motor, &image.units.master);
        let mut samples = Vec::new();
        for (i, info) in registry.slots.iter().enumerate() {
            if info.ty.is_bit() {
                recorder.mark_bit(&info.name.text());
            }
            // Continuous members are not in the trace: the plot samples the ones it draws.
            if info.member.continuous && recorder.plan().wants_series(&info.name.text()) {
                samples.push((i as SlotId, info.name.to_string()));
            }
        }
        let xy = if recorder.plan().preset == Preset::PickPlace {
            let slot = |n: &str| registry.slots.iter().position(|s| s.name == *n);
            match (slot(TOOL_XYZ[0]), slot(TOOL_XYZ[1])) {
                (Some(x), Some(y)) => Some((x as SlotId, y as SlotId)),
                _ => None,
            }
        } else {
            None
        };
        Ok(LivePlot {
            path: path.to_path_buf(),
            file,
            recorder: Rc::new(RefCell::new(Some(recorder))),
            samples,
            xy,
        })
    }
}

fn write_svg(path: &Path, file: &std::fs::File, fig: &figure::Figure) -> Result<(), ExportError> {
    let svg = plot::render(fig).map_err(ExportError::Usage)?;
    let mut out = std::io::BufWriter::new(file);
    out.write_all(svg.as_bytes())
        .and_then(|_| out.flush())
        .map_err(|source| ExportError::Io {
            path: path.to_path_buf(),
            source,
        })
}

/// `pacer plot`: draw from a recorded trace (and the run's CSV, if given). Returns the SVG's
/// path.
pub fn plot_command(args: &PlotArgs) -> Result<PathBuf, ExportError> {
    let mut trace: Option<&PathBuf> = None;
    let mut data: Option<&PathBuf> = None;
    for f in &args.files {
        let is_csv = f.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let slot = if is_csv { &mut data } else { &mut trace };
        if slot.is_some() {
            return Err(ExportError::Usage(format!(
                "pacer plot takes one trace and at most one CSV; {} is one {} too many",
                f.display(),
                if is_csv { "CSV" } else { "trace" }
            )));
        }
        *slot = Some(f);
    }
    let Some(trace) = trace else {
        return Err(ExportError::Usage(
            "pacer plot needs the trace of a run (FILE.jsonl, from pacer run --trace)".into(),
        ));
    };
    let (from, to) = match &args.window {
        None => (0.0, None),
        Some(w) => parse_window(w)?,
    };
    let survey = input::survey(trace)?;
    let columns = match data {
        Some(d) => input::csv_columns(d)?,
        None => Vec::new(),
    };
    let preset = if !args.signals.is_empty() {
        let known: Vec<&str> = survey
            .names
            .iter()
            .map(|s| s.as_str())
            .chain(columns.iter().map(|s| s.as_str()))
            .collect();
        let mut names = Vec::new();
        for n in signals::split_names(&args.signals) {
            let found = known.iter().find(|k| k.eq_ignore_ascii_case(&n));
            match found {
                Some(k) => {
                    if !names.iter().any(|x: &String| x == k) {
                        names.push(k.to_string());
                    }
                }
                None => {
                    return Err(ExportError::Usage(format!(
                        "--signals: `{n}` is not in {}{}{}",
                        trace.display(),
                        if data.is_some() {
                            " nor in the CSV"
                        } else {
                            " (members that move every update, such as positions, are in the \
                             run's --csv, not in the trace)"
                        },
                        signals::nearest(&n, known.iter().copied())
                            .map(|k| format!("; did you mean `{k}`?"))
                            .unwrap_or_default()
                    )))
                }
            }
        }
        if names.is_empty() {
            return Err(ExportError::Usage(
                "--signals: no signal names given".into(),
            ));
        }
        Preset::Signals(names)
    } else if ["pick", "place", "pp_state"]
        .iter()
        .any(|k| survey.kinds.contains(*k))
    {
        Preset::PickPlace
    } else if survey.kinds.contains("latch") {
        Preset::Web
    } else {
        Preset::Servo
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| trace.with_extension("svg"));
    if output == *trace || data.is_some_and(|d| *d == output) {
        return Err(ExportError::Usage(format!(
            "the plot would overwrite {}: give another --output",
            output.display()
        )));
    }
    let plan = Plan { preset, from, to };
    let mut recorder = Recorder::new(plan, survey.update.unwrap_or(0.001));
    // Signals in the CSV are drawn from it: it has them every row, the trace only when they
    // change (and never, for the moving ones).
    for c in &columns {
        recorder.prefer_samples(c);
    }
    input::read_trace(trace, |l| recorder.event(l.t, &l.event))?;
    if let Some(d) = data {
        let x = columns.iter().position(|c| c == TOOL_XYZ[0]);
        let y = columns.iter().position(|c| c == TOOL_XYZ[1]);
        let text = input::read_csv(d, |t, values| {
            for (c, v) in columns.iter().zip(values) {
                if !v.is_nan() {
                    recorder.sample(t, c, *v);
                }
            }
            if let (Some(x), Some(y)) = (x, y) {
                recorder.sample_xy(t, values[x], values[y]);
            }
        })?;
        if let Preset::Signals(names) = &recorder.plan().preset {
            if let Some(n) = names.iter().find(|n| text.contains(n)) {
                return Err(ExportError::Usage(format!(
                    "--signals: {n} holds text in {}, and a plot draws numbers",
                    d.display()
                )));
            }
        }
    }
    let preset = recorder.plan().preset.clone();
    let rec = recorder.finish();
    let file = std::fs::File::create(&output).map_err(|source| ExportError::Io {
        path: output.clone(),
        source,
    })?;
    write_svg(&output, &file, &figure::figure(&preset, &rec))?;
    Ok(output)
}
