//! The one configuration stage: `machine.toml`, `scenario.toml` and the Modbus map are parsed and
//! checked here, every problem located in its file, into a typed description of the machine
//! and its world ([`desc`]). The registry and the devices are built from that description and
//! cannot fail afterwards.
//!
//! [`machine`] checks the machine file (in two passes: values first, then the names it writes
//! as text, resolved against the registry it builds); [`scenario`] checks the world against the
//! machine. The files come from the disk or from memory ([`files`]).

pub mod belts;
pub mod desc;
pub mod files;
pub mod limits;
pub mod links;
pub mod machine;
pub mod marks;
pub mod messages;
pub mod modbus;
pub mod objects;
pub mod pickplace;
pub mod scenario;
pub mod servo;
pub mod values;
pub mod world;

use crate::diag::Problem;
use crate::registry::{BasicVar, Registry, DEFAULT_UPDATE_NS};
use crate::span::Span;
use desc::{MachineDesc, ProgramDesc, ScenarioDesc};
use machine::MachineFile;
use scenario::ScenarioFile;

/// Tasks unless `[machine] tasks` says otherwise.
pub const DEFAULT_TASKS: u32 = 4;

/// Instructions a task may run in one update unless `[machine] budget` says otherwise.
pub const DEFAULT_BUDGET: u64 = 10_000;

/// Parse a TOML document into `T`, turning a syntax or shape error into a located problem in
/// the user's words ([`messages`]).
pub fn parse_toml<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> Result<T, Problem> {
    toml::from_str::<T>(text).map_err(|e| messages::toml_problem(text, what, &e))
}

/// The span of a spanned TOML value.
pub fn span_of<T>(v: &toml::Spanned<T>) -> Span {
    let r = v.span();
    Span::new(r.start, r.end)
}

/// The programs `[[program]]` lists, each number once.
pub fn programs(file: &MachineFile, problems: &mut Vec<Problem>) -> Vec<ProgramDesc> {
    let mut out: Vec<ProgramDesc> = Vec::new();
    for e in &file.programs {
        let number = *e.number.get_ref();
        // Every number below the highest gets its Program object: memory and time.
        if number >= objects::MAX_INSTANCES {
            problems.push(Problem::error(
                "pacer::machine::program",
                span_of(&e.number),
                format!(
                    "Program.{} cannot be: programs are numbered 0 to {}",
                    limits::thousands(u64::from(number)),
                    limits::thousands(u64::from(objects::MAX_INSTANCES - 1))
                ),
                "too high",
            ));
            continue;
        }
        if out.iter().any(|p| p.number == number) {
            problems.push(Problem::error(
                "pacer::machine::program",
                span_of(&e.number),
                format!("Program.{number} is listed twice"),
                "duplicate",
            ));
            continue;
        }
        out.push(ProgramDesc {
            number,
            file: e.file.get_ref().clone(),
            autostart: e.autostart,
            span: span_of(&e.file),
        });
    }
    out
}

/// Check the machine file of a machine whose programs are numbered `programs` and use the
/// MotionBASIC variables `basic_vars` (name as first written, and type): its description and
/// the registry of its objects. Values in error are left at their defaults and reported, so the
/// rest of the file (and the programs) can still be checked against the result.
pub fn machine(
    file: &MachineFile,
    programs: &[u32],
    basic_vars: &[BasicVar],
    problems: &mut Vec<Problem>,
) -> (MachineDesc, Registry) {
    let (objects, mut drive) = objects::objects(file, programs, problems);
    let registry = Registry::new(&objects, basic_vars);
    links::home_references(file, &registry, &mut drive, problems);
    let m = &file.machine;
    if let Some(u) = &m.update {
        if !(1_000..=1_000_000_000).contains(&u.get_ref().0) {
            problems.push(Problem::error(
                "pacer::machine::update",
                span_of(u),
                "the update period must be between 1 µs and 1 s",
                "out of range",
            ));
        }
    }
    if let Some(b) = &m.budget {
        let n = *b.get_ref();
        if n == 0 {
            problems.push(Problem::error(
                "pacer::machine::budget",
                span_of(b),
                "a budget of 0 instructions lets no program run",
                "must be at least 1",
            ));
        } else if n > limits::MAX_BUDGET {
            problems.push(
                Problem::error(
                    "pacer::machine::budget",
                    span_of(b),
                    format!(
                        "a budget of {} instructions per update is too many: at most {}",
                        limits::thousands(n),
                        limits::thousands(limits::MAX_BUDGET)
                    ),
                    "too many",
                )
                .with_help("a loop that never waits spends the whole budget every update, so a larger one could hold an update for minutes"),
            );
        }
    }
    if let Some(t) = &m.tasks {
        if !(1..=64).contains(t.get_ref()) {
            problems.push(Problem::error(
                "pacer::machine::tasks",
                span_of(t),
                "tasks must be 1 to 64",
                "out of range",
            ));
        }
    }
    let assignments = links::assignments(file, &registry, programs, problems);
    let pickplace = pickplace::setup(file, problems);
    let mut dsp = objects::dsp_axes(file);
    let update_s = m
        .update
        .as_ref()
        .map_or(DEFAULT_UPDATE_NS, |u| u.get_ref().0) as f64
        / 1e9;
    servo::dsp_servos(file, update_s, &mut dsp, problems);
    if !dsp.is_empty() {
        let configs: Vec<_> = dsp.iter().map(|a| a.config.clone()).collect();
        if let Err(e) = crate::devices::orion::dsp::DspAxes::new(&configs) {
            let span = file.axis.values().next().map(span_of).unwrap_or_default();
            problems.push(Problem::error("pacer::machine::axis", span, e.0, "here"));
        }
    }
    links::fast_inputs(file, &registry, &mut dsp, problems);
    let io_map = modbus::validate(file, &registry, problems);
    let desc = MachineDesc {
        name: m.name.clone(),
        update_ns: m
            .update
            .as_ref()
            .map_or(DEFAULT_UPDATE_NS, |u| u.get_ref().0),
        budget: m.budget.as_ref().map_or(DEFAULT_BUDGET, |b| *b.get_ref()),
        tasks: m.tasks.as_ref().map_or(DEFAULT_TASKS, |t| *t.get_ref()) as usize,
        objects,
        drive,
        dsp,
        pickplace,
        assignments,
        io_map,
    };
    (desc, registry)
}

/// The registry of a machine file alone, for tools and tests: the registry built from its valid
/// values, and every problem of the file.
pub fn registry(
    file: &MachineFile,
    programs: &[u32],
    basic_vars: &[BasicVar],
) -> (Registry, Vec<Problem>) {
    let mut problems = Vec::new();
    let (_, registry) = machine(file, programs, basic_vars, &mut problems);
    (registry, problems)
}

/// Check the scenario file against the machine it drives: the world's description.
pub fn scenario(
    sc: &ScenarioFile,
    registry: &Registry,
    machine: &MachineDesc,
    problems: &mut Vec<Problem>,
) -> ScenarioDesc {
    // A scenario that would lay out too much is checked without its streams, so nothing is
    // allocated for them.
    let trimmed;
    let sc = if limits::world_size(sc, problems) {
        sc
    } else {
        trimmed = ScenarioFile {
            run: sc.run.clone(),
            master: sc.master.clone(),
            belts: sc.belts.clone(),
            ..ScenarioFile::default()
        };
        &trimmed
    };
    if let Some(d) = &sc.run.duration {
        let updates = d.get_ref().0 / machine.update_ns.max(1);
        if updates > limits::MAX_UPDATES {
            problems.push(
                Problem::error(
                    "pacer::scenario::duration",
                    span_of(d),
                    format!(
                        "a run of {} updates is too long: at most {}",
                        limits::thousands(updates),
                        limits::thousands(limits::MAX_UPDATES)
                    ),
                    "too long",
                )
                .with_help("every update takes time even when nothing moves: run shorter, or with a longer [machine] update"),
            );
        }
    }
    let w = world::world(sc, registry, problems);
    let axes: Vec<u32> = machine.dsp.iter().map(|a| a.config.number).collect();
    let mark_tracks = marks::tracks(&sc.marks, &axes, problems);
    let setups = machine.pickplace.as_ref().map_or(&[][..], |p| &p.belts[..]);
    let belts = belts::belts(sc, setups, problems);
    ScenarioDesc {
        edges: w.edges,
        master: w.master,
        axis_marks: w.marks,
        products: w.products,
        mark_tracks,
        belt_profiles: belts.profiles,
        feeds: belts.feeds,
        duration_ns: sc.run.duration.as_ref().map(|d| d.get_ref().0),
        seed: sc.run.seed,
    }
}
