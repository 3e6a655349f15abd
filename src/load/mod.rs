//! Loading a machine project (a folder, or program files) into a runnable image: every file
//! read, parsed, checked and compiled, and every problem of every file reported together.

use crate::check::{check_program, CheckEnv};
use crate::compile::{compile, Layout};
use crate::config::machine::MachineFile;
use crate::config::scenario::ScenarioFile;
use crate::config::{parse_toml, span_of};
use crate::diag::{Diagnostics, Problem, SourceFile};
use crate::registry::{Access, Kind, Registry, DEFAULT_UPDATE_NS};
use crate::syntax::span::Span;
use crate::syntax::Dialect;
use crate::vm::{Assignment, MachineImage};
use indexmap::IndexMap;

pub mod belts;
mod marks;
pub mod pickplace;
mod scenario;
use std::path::{Path, PathBuf};

/// What to load.
#[derive(Debug, Clone, Default)]
pub struct LoadRequest {
    /// A folder, or program files.
    pub paths: Vec<PathBuf>,
    /// Machine file (default: `machine.toml` in the folder, if any).
    pub machine: Option<PathBuf>,
    /// Scenario file (default: `scenario.toml` in the folder, if any).
    pub scenario: Option<PathBuf>,
}

/// A loaded project: the image, plus the warnings found on the way.
pub struct Loaded {
    /// Ready to run.
    pub image: MachineImage,
    /// Warnings (no errors).
    pub warnings: Diagnostics,
    /// The program sources, by program number.
    pub sources: IndexMap<u32, SourceFile>,
    /// Compilation layout (for the disassembler).
    pub layout: Layout,
    /// The validated Modbus map (`[modbus]`), if the machine file has one.
    pub io_map: Option<crate::io::map::IoMap>,
}

struct ProgramFile {
    number: u32,
    path: PathBuf,
    autostart: bool,
    span: Option<Span>,
}

/// Default update period, nanoseconds.
pub const UPDATE_NS: u64 = DEFAULT_UPDATE_NS;

/// Options of a load beyond its files (the REPL needs them).
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// A machine with no programs is no error (the REPL's empty default machine).
    pub allow_no_programs: bool,
    /// Spare MotionBASIC variable slots to reserve for variables first used in typed lines
    /// (named [`crate::vm::live::SPARE_VARIABLE`]`N` until then).
    pub spare_basic_vars: usize,
}

/// Load, check and compile. On any error, every problem found is returned.
pub fn load(req: &LoadRequest) -> Result<Loaded, Diagnostics> {
    load_with(req, &LoadOptions::default())
}

/// [`load`] with options.
pub fn load_with(req: &LoadRequest, options: &LoadOptions) -> Result<Loaded, Diagnostics> {
    let mut diags = Diagnostics::new();
    let (folder, files) = split_paths(&req.paths, &mut diags)?;
    let machine_path = req.machine.clone().or_else(|| {
        folder
            .as_ref()
            .map(|f| f.join("machine.toml"))
            .filter(|p| p.exists())
    });
    let scenario_path = req.scenario.clone().or_else(|| {
        folder
            .as_ref()
            .map(|f| f.join("scenario.toml"))
            .filter(|p| p.exists())
    });

    let (machine, machine_src) = match &machine_path {
        Some(p) => {
            let src = read(p, &mut diags)?;
            match parse_toml::<MachineFile>(&src.text, "machine file") {
                Ok(m) => (m, Some(src)),
                Err(problem) => {
                    diags.extend_file(&src, vec![problem]);
                    return Err(diags);
                }
            }
        }
        None => (MachineFile::default(), None),
    };
    let machine_file = machine_src
        .clone()
        .unwrap_or_else(|| SourceFile::new("machine.toml (defaults)", ""));
    let base_dir = machine_path
        .as_ref()
        .and_then(|p| p.parent().map(Path::to_path_buf))
        .or(folder.clone())
        .unwrap_or_default();

    // Which programs, with which numbers.
    let mut programs: Vec<ProgramFile> = Vec::new();
    let mut machine_problems: Vec<Problem> = Vec::new();
    if !machine.programs.is_empty() && files.is_empty() {
        for e in &machine.programs {
            let number = *e.number.get_ref();
            if programs.iter().any(|p| p.number == number) {
                machine_problems.push(Problem::error(
                    "pacer::machine::program",
                    span_of(&e.number),
                    format!("Program.{number} is listed twice"),
                    "duplicate",
                ));
                continue;
            }
            programs.push(ProgramFile {
                number,
                path: base_dir.join(e.file.get_ref()),
                autostart: e.autostart,
                span: Some(span_of(&e.file)),
            });
        }
    } else {
        let list = if files.is_empty() {
            folder
                .as_ref()
                .map(|f| program_files_in(f, &mut diags))
                .unwrap_or_default()
        } else {
            files
        };
        let mut used: Vec<u32> = list.iter().filter_map(|p| number_in_name(p)).collect();
        for path in list {
            let number = match number_in_name(&path) {
                Some(n) if programs.iter().all(|p| p.number != n) => n,
                _ => {
                    let n = (0..).find(|n| !used.contains(n)).unwrap_or(0);
                    used.push(n);
                    n
                }
            };
            programs.push(ProgramFile {
                number,
                path,
                autostart: false,
                span: None,
            });
        }
        programs.sort_by_key(|p| p.number);
    }
    if programs.is_empty() && !options.allow_no_programs {
        diags.extend_file(
            &machine_file,
            vec![Problem::error(
                "pacer::load::no_programs",
                Span::new(0, 0),
                "no programs to run",
                "nothing here",
            )
            .with_help(
                "give .pt or .mb files, a folder holding them, or [[program]] entries in machine.toml",
            )],
        );
        return Err(diags);
    }
    let numbers: Vec<u32> = programs.iter().map(|p| p.number).collect();

    // Read and parse every program first: MotionBASIC variables are declared by use, and the
    // registry needs them.
    let mut sources: IndexMap<u32, SourceFile> = IndexMap::new();
    let mut parsed = Vec::new();
    let mut basic_vars = crate::check::basic::Variables::default();
    for p in &programs {
        let text = match std::fs::read_to_string(&p.path) {
            Ok(t) => t,
            Err(e) => {
                let span = p.span.unwrap_or_default();
                machine_problems.push(Problem::error(
                    "pacer::load::read",
                    span,
                    format!("cannot read {}: {e}", p.path.display()),
                    "this program file",
                ));
                continue;
            }
        };
        let dialect = Dialect::of_path(&p.path).unwrap_or_default();
        let file = SourceFile::new(p.path.display().to_string(), text.as_str());
        let mut problems = Vec::new();
        let ast = crate::syntax::parse_program_as(&text, dialect, &mut problems);
        if dialect == Dialect::MotionBasic {
            basic_vars.collect(&ast);
        }
        sources.insert(p.number, file);
        parsed.push((p.number, dialect, ast, problems));
    }
    // Problems in the machine file do not stop the checks of the rest of it, nor of the
    // programs: everything wrong is reported at once.
    let mut variables = basic_vars.list();
    variables.extend((0..options.spare_basic_vars).map(|i| {
        (
            format!("{}{i}", crate::vm::live::SPARE_VARIABLE),
            crate::registry::ValueType::Real,
        )
    }));
    let (registry, registry_problems) = Registry::build_with_basic(&machine, &numbers, &variables);
    machine_problems.extend(registry_problems);
    let registry = Some(registry);

    let mut asts = Vec::new();
    for (number, dialect, ast, mut problems) in parsed {
        if let Some(reg) = &registry {
            match dialect {
                Dialect::PowerTools => {
                    let env = CheckEnv {
                        registry: reg,
                        loaded_programs: &numbers,
                    };
                    problems.extend(check_program(&ast, &env));
                }
                Dialect::MotionBasic => {
                    problems.extend(crate::check::basic::check(&ast, reg, &basic_vars));
                }
            }
        }
        if let Some(file) = sources.get(&number) {
            diags.extend_file(file, problems);
        }
        asts.push((number, dialect, ast));
    }

    let update_ns = machine
        .machine
        .update
        .as_ref()
        .map_or(UPDATE_NS, |u| u.get_ref().0);
    if let Some(u) = &machine.machine.update {
        if !(1_000..=1_000_000_000).contains(&u.get_ref().0) {
            machine_problems.push(Problem::error(
                "pacer::machine::update",
                span_of(u),
                "the update period must be between 1 µs and 1 s",
                "out of range",
            ));
        }
    }
    let budget = machine
        .machine
        .budget
        .as_ref()
        .map_or(crate::vm::DEFAULT_BUDGET, |b| *b.get_ref());
    if let Some(b) = &machine.machine.budget {
        if *b.get_ref() == 0 {
            machine_problems.push(Problem::error(
                "pacer::machine::budget",
                span_of(b),
                "a budget of 0 instructions lets no program run",
                "must be at least 1",
            ));
        }
    }
    let tasks = machine.machine.tasks.as_ref().map_or(4, |t| *t.get_ref()) as usize;
    if let Some(t) = &machine.machine.tasks {
        if !(1..=64).contains(t.get_ref()) {
            machine_problems.push(Problem::error(
                "pacer::machine::tasks",
                span_of(t),
                "tasks must be 1 to 64",
                "out of range",
            ));
        }
    }

    let mut assignments = Vec::new();
    if let Some(reg) = &registry {
        for a in &machine.assignments {
            let src = resolve_text(reg, &a.source, &mut machine_problems);
            let dst = resolve_text(reg, &a.destination, &mut machine_problems);
            let active_off = match &a.polarity {
                None => false,
                Some(p) => match p
                    .get_ref()
                    .to_ascii_lowercase()
                    .replace([' ', '_'], "")
                    .as_str()
                {
                    "activeon" => false,
                    "activeoff" => true,
                    _ => {
                        machine_problems.push(Problem::error(
                            "pacer::machine::assignment",
                            span_of(p),
                            format!("unknown polarity `{}`", p.get_ref()),
                            "ActiveOn or ActiveOff",
                        ));
                        false
                    }
                },
            };
            if let (Some(s), Some(d)) = (src, dst) {
                if !s.ty.is_bit() || matches!(s.access, Access::Action | Access::Input) {
                    machine_problems.push(
                        Problem::error(
                            "pacer::machine::assignment",
                            span_of(&a.source),
                            format!("{} cannot be an assignment source", s.name),
                            "not a readable bit",
                        )
                        .with_help("sources are bits: inputs, status bits, user bits"),
                    );
                } else if !d.ty.is_bit() || d.access == Access::Read || d.access == Access::Input {
                    machine_problems.push(Problem::error("pacer::machine::assignment", span_of(&a.destination), format!("{} cannot be an assignment destination", d.name), "not a writable bit or action")
                        .with_help("destinations are actions (Program.1.Initiate) or writable bits (DriveIO.1.Out, Capture.0.CaptureActivate)"));
                } else {
                    if d.hook == crate::registry::Hook::ProgramInitiate
                        && !numbers.contains(&d.instance)
                    {
                        machine_problems.push(Problem::error(
                            "pacer::machine::assignment",
                            span_of(&a.destination),
                            format!("Program.{} is not loaded", d.instance),
                            "no such program",
                        ));
                    }
                    // Sources assigned to the same destination are ORed.
                    let latched = s.kind == crate::registry::Kind::ModuleInput;
                    match assignments
                        .iter_mut()
                        .find(|x: &&mut Assignment| x.dest.slot == d.slot)
                    {
                        Some(existing) => {
                            existing.sources.push((s.slot, active_off));
                            existing.latched |= latched;
                        }
                        None => assignments.push(Assignment {
                            sources: vec![(s.slot, active_off)],
                            dest: d,
                            latched,
                        }),
                    }
                }
            }
        }
    }
    let mut autostart: Vec<u32> = programs
        .iter()
        .filter(|p| p.autostart)
        .map(|p| p.number)
        .collect();
    let started_by_assignment = assignments
        .iter()
        .any(|a| a.dest.hook == crate::registry::Hook::ProgramInitiate);
    if autostart.is_empty() && !started_by_assignment {
        autostart.extend(programs.first().map(|p| p.number));
    }
    let pp_setup = pickplace::setup(&machine, &mut machine_problems);
    let io_map = registry
        .as_ref()
        .and_then(|reg| crate::io::map::validate(&machine, reg, &mut machine_problems));
    diags.extend_file(&machine_file, machine_problems);

    // The scenario.
    let mut edges = Vec::new();
    let mut master = crate::world::master::MasterProfile::default();
    let mut axis_marks = Vec::new();
    let mut products = Vec::new();
    let mut mark_tracks = Vec::new();
    let mut duration_ns = None;
    let mut belt_world: Option<belts::BeltWorld> = None;
    let dsp_numbers: Vec<u32> = machine
        .axis
        .keys()
        .filter_map(|k| k.parse::<u32>().ok())
        .collect();
    if let Some(p) = &scenario_path {
        let src = read(p, &mut diags)?;
        match parse_toml::<ScenarioFile>(&src.text, "scenario") {
            Err(problem) => diags.extend_file(&src, vec![problem]),
            Ok(sc) => {
                let mut problems = Vec::new();
                if let Some(reg) = &registry {
                    let world = scenario::world(&sc, reg, &mut problems);
                    edges = world.edges;
                    master = world.master;
                    axis_marks = world.marks;
                    products = world.products;
                }
                mark_tracks = marks::tracks(&sc.marks, &dsp_numbers, &mut problems);
                let setups = pp_setup.as_ref().map_or(&[][..], |p| &p.belts[..]);
                belt_world = Some(belts::belts(&sc, setups, &mut problems));
                duration_ns = sc.run.duration.as_ref().map(|d| d.get_ref().0);
                diags.extend_file(&src, problems);
            }
        }
    }

    if diags.has_errors() {
        return Err(diags);
    }
    let Some(registry) = registry else {
        return Err(diags);
    };

    let mut layout = Layout::new(&registry);
    let mut chunks = Vec::new();
    let mut program_chunks = IndexMap::new();
    for (number, dialect, ast) in &asts {
        let Some(file) = sources.get(number) else {
            continue;
        };
        match compile(
            ast,
            &file.text,
            &file.name,
            *number,
            &registry,
            &mut layout,
            *dialect,
        ) {
            Ok(chunk) => {
                program_chunks.insert(*number, chunks.len());
                chunks.push(chunk);
            }
            Err(problems) => diags.extend_file(file, problems),
        }
    }
    if diags.has_errors() {
        return Err(diags);
    }
    let orion = if machine.axis.is_empty() {
        None
    } else {
        let configs = dsp_configs(&machine);
        match crate::devices::orion::Orion::new(
            &registry,
            configs,
            &mark_tracks,
            layout.strings.clone(),
            update_ns as f64 / 1e9,
        ) {
            Ok(mut o) => {
                let wiring = wire_fast_inputs(&machine, &registry, &mut o);
                if !wiring.is_empty() {
                    diags.extend_file(&machine_file, wiring);
                    return Err(diags);
                }
                Some(o)
            }
            Err(message) => {
                let span = machine
                    .axis
                    .values()
                    .next()
                    .map(span_of)
                    .unwrap_or_default();
                diags.extend_file(
                    &machine_file,
                    vec![Problem::error(
                        "pacer::machine::axis",
                        span,
                        message,
                        "here",
                    )],
                );
                return Err(diags);
            }
        }
    };
    let pickplace = match &pp_setup {
        None => None,
        Some(setup) => {
            let (profiles, feeds) = match belt_world {
                Some(w) => {
                    let profiles = setup
                        .belts
                        .iter()
                        .map(|b| w.profiles.get(&b.number).cloned().unwrap_or_default())
                        .collect();
                    (profiles, w.feeds)
                }
                None => (Vec::new(), Vec::new()),
            };
            Some(crate::devices::pickplace::cell::PickPlaceCell::new(
                &registry,
                setup,
                profiles,
                feeds,
                update_ns as f64 / 1e9,
            ))
        }
    };
    // The devices, in the order they update: the drive, the DSP axes, pick & place.
    let mut devices: Vec<Box<dyn crate::devices::Device>> = vec![Box::new(
        crate::devices::drive::Drive::new(&registry, axis_marks),
    )];
    if let Some(o) = orion {
        devices.push(Box::new(o));
    }
    if let Some(pp) = pickplace {
        devices.push(Box::new(pp));
    }
    let initial = layout.initial_values(&registry);
    let name = machine.machine.name.clone().unwrap_or_else(|| {
        folder
            .as_ref()
            .and_then(|f| f.canonicalize().ok())
            .and_then(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| "machine".into())
    });
    let image = MachineImage {
        name,
        tick_ns: update_ns,
        budget,
        tasks,
        registry,
        initial,
        chunks,
        programs: program_chunks,
        autostart,
        assignments,
        edges,
        master,
        products,
        duration_ns,
        devices,
    };
    Ok(Loaded {
        image,
        warnings: diags,
        sources,
        layout,
        io_map,
    })
}

fn read(path: &Path, diags: &mut Diagnostics) -> Result<SourceFile, Diagnostics> {
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(SourceFile::new(path.display().to_string(), t)),
        Err(e) => {
            let f = SourceFile::new(path.display().to_string(), "");
            diags.extend_file(
                &f,
                vec![Problem::error(
                    "pacer::load::read",
                    Span::new(0, 0),
                    format!("cannot read {}: {e}", path.display()),
                    "missing or unreadable",
                )],
            );
            Err(std::mem::take(diags))
        }
    }
}

fn split_paths(
    paths: &[PathBuf],
    diags: &mut Diagnostics,
) -> Result<(Option<PathBuf>, Vec<PathBuf>), Diagnostics> {
    let mut folder = None;
    let mut files = Vec::new();
    for p in paths {
        if p.is_dir() {
            if folder.is_some() {
                let f = SourceFile::new(p.display().to_string(), "");
                diags.extend_file(
                    &f,
                    vec![Problem::error(
                        "pacer::load::paths",
                        Span::new(0, 0),
                        "give one machine folder at a time",
                        "second folder",
                    )],
                );
                return Err(std::mem::take(diags));
            }
            folder = Some(p.clone());
        } else {
            files.push(p.clone());
        }
    }
    if folder.is_none() {
        // Files in one folder that has a machine.toml use it.
        if let Some(parent) = files.first().and_then(|f| f.parent()) {
            if parent.join("machine.toml").exists()
                && files.iter().all(|f| f.parent() == Some(parent))
            {
                folder = Some(parent.to_path_buf());
            }
        }
    }
    Ok((folder, files))
}

/// Wire the inputs `[axis.N] fast_input` names to the axes' fast inputs.
fn wire_fast_inputs(
    machine: &MachineFile,
    registry: &Registry,
    orion: &mut crate::devices::orion::Orion,
) -> Vec<Problem> {
    let mut problems = Vec::new();
    for (key, setup) in &machine.axis {
        let (Ok(n), Some(input)) = (key.parse::<u32>(), &setup.get_ref().fast_input) else {
            continue;
        };
        match resolve_text(registry, input, &mut problems) {
            Some(r)
                if r.ty.is_bit()
                    && r.access == Access::Read
                    && matches!(r.kind, Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO) =>
            {
                if let Err(message) = orion.wire_fast_input(n, r.slot) {
                    problems.push(Problem::error(
                        "pacer::machine::axis",
                        span_of(input),
                        message,
                        "here",
                    ));
                }
            }
            Some(r) => problems.push(
                Problem::error(
                    "pacer::machine::axis",
                    span_of(input),
                    format!("{} is not an input", r.name),
                    "not an input",
                )
                .with_help("wire a DriveInput, ModuleInput or DriveIO point"),
            ),
            None => {}
        }
    }
    problems
}

/// The DSP axes of `[axis.N]` (already checked by the registry).
fn dsp_configs(
    machine: &MachineFile,
) -> Vec<(
    crate::devices::orion::dsp::DspAxisConfig,
    crate::devices::orion::MoveDefaults,
)> {
    machine
        .axis
        .iter()
        .filter_map(|(k, setup)| {
            let n = k.parse::<u32>().ok()?;
            let s = setup.get_ref();
            let mut c = crate::devices::orion::dsp::DspAxisConfig::new(
                n,
                s.pacer.as_ref().map(|p| *p.get_ref()),
                s.units_per_rev.as_ref().map_or(1.0, |u| *u.get_ref()),
            );
            if let Some(q) = &s.queue {
                c.queue_depth = *q.get_ref() as usize;
            }
            let defaults = crate::devices::orion::MoveDefaults {
                accel: s
                    .accel
                    .as_ref()
                    .map_or(10.0 * c.units_per_rev, |a| *a.get_ref()),
                speed_rpm: s.speed.as_ref().map_or(100.0, |v| *v.get_ref()),
            };
            Some((c, defaults))
        })
        .collect()
}

fn program_files_in(folder: &Path, diags: &mut Diagnostics) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = match std::fs::read_dir(folder) {
        Ok(rd) => rd
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| Dialect::of_path(p).is_some())
            .collect(),
        Err(e) => {
            let f = SourceFile::new(folder.display().to_string(), "");
            diags.extend_file(
                &f,
                vec![Problem::error(
                    "pacer::load::read",
                    Span::new(0, 0),
                    format!("cannot list {}: {e}", folder.display()),
                    "here",
                )],
            );
            Vec::new()
        }
    };
    files.sort();
    files
}

/// `program2.pt` → 2.
fn number_in_name(p: &Path) -> Option<u32> {
    let stem = p.file_stem()?.to_string_lossy();
    let digits: String = stem
        .chars()
        .rev()
        .take_while(char::is_ascii_digit)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    if digits.is_empty() {
        None
    } else {
        digits.parse().ok()
    }
}

/// Resolve a member name written as a TOML string, reporting a problem in place.
fn resolve_text(
    reg: &Registry,
    text: &toml::Spanned<String>,
    problems: &mut Vec<Problem>,
) -> Option<crate::registry::Resolved> {
    reg.resolve_text(text).map_err(|p| problems.push(p)).ok()
}
