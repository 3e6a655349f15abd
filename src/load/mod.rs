//! Loading a machine project (a folder, or program files; on the disk or in memory) into a
//! runnable image: the files read ([`project`]), the programs parsed, the configuration stage
//! run ([`crate::config`]), the programs checked and compiled ([`front`]), and the image
//! built ([`build`], which cannot fail). Every problem of every file is reported together.

mod build;
mod front;
mod project;

use crate::compile::Layout;
use crate::config::files::{Disk, Files};
use crate::config::machine::MachineFile;
use crate::config::parse_toml;
use crate::config::scenario::ScenarioFile;
use crate::diag::{Diagnostics, Problem, SourceFile};
use crate::span::Span;
use crate::vm::MachineImage;
use indexmap::IndexMap;
use std::path::PathBuf;

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
    /// The lowest subscript of each MotionBASIC array that does not start at 0 (`OPTION
    /// BASE 1`), by upper-case name: the registry holds every element from 0, so a line typed
    /// at the REPL learns the base here.
    pub array_lower: IndexMap<String, u32>,
}

/// Default update period, nanoseconds.
pub const UPDATE_NS: u64 = crate::registry::DEFAULT_UPDATE_NS;

/// Options of a load beyond its files (the REPL needs them).
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// A machine with no programs is no error (the REPL's empty default machine).
    pub allow_no_programs: bool,
    /// Spare MotionBASIC variable slots to reserve for variables first used in typed lines
    /// (named [`crate::vm::live::SPARE_VARIABLE`]`N` until then).
    pub spare_basic_vars: usize,
}

/// Load, check and compile from the disk. On any error, every problem found is returned.
pub fn load(req: &LoadRequest) -> Result<Loaded, Diagnostics> {
    load_with(req, &LoadOptions::default())
}

/// [`load`] with options.
pub fn load_with(req: &LoadRequest, options: &LoadOptions) -> Result<Loaded, Diagnostics> {
    load_from(&Disk, req, options)
}

/// Load, check and compile from `files` (the disk, or [`crate::config::files::Memory`]).
pub fn load_from(
    files: &dyn Files,
    req: &LoadRequest,
    options: &LoadOptions,
) -> Result<Loaded, Diagnostics> {
    let mut diags = Diagnostics::new();
    let p = project::locate(files, req, &mut diags)?;
    let (machine, machine_src) = match &p.machine {
        Some(path) => {
            let src = project::read(files, path, &mut diags)?;
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

    // Which programs, with which numbers.
    let mut machine_problems: Vec<Problem> = Vec::new();
    let listed = crate::config::programs(&machine, &mut machine_problems);
    let programs = project::programs(files, &p, &listed, &mut diags);
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

    // Every program read and parsed first: MotionBASIC variables are declared by use, and the
    // registry needs them.
    let parsed = front::parse(files, &programs, &mut machine_problems);
    let mut variables = parsed.variables.list();
    variables.extend((0..options.spare_basic_vars).map(|i| {
        crate::registry::BasicVar::Scalar(
            format!("{}{i}", crate::vm::live::SPARE_VARIABLE),
            crate::registry::ValueType::Real,
        )
    }));
    // Problems in the machine file do not stop the checks of the rest of it, nor of the
    // programs: everything wrong is reported at once.
    let (desc, registry) =
        crate::config::machine(&machine, &numbers, &variables, &mut machine_problems);
    // Loose files without a machine file may be only some of the machine's programs.
    let all_programs = p.machine.is_some() || p.folder.is_some();
    let dsp_axes: Vec<u32> = desc.dsp.iter().map(|a| a.config.number).collect();
    let machine_ok = !machine_problems
        .iter()
        .any(|p| p.level == crate::diag::Level::Error);
    let machine_check = front::MachineCheck {
        dsp_axes: &dsp_axes,
        described: p.machine.is_some(),
        indexes: &desc.drive.indexes,
    };
    let checked = front::check(
        &parsed,
        &registry,
        &numbers,
        all_programs,
        machine_ok.then_some(&machine_check),
        &mut diags,
    );
    diags.extend_file(&machine_file, machine_problems);

    let scenario = match &p.scenario {
        None => crate::config::desc::ScenarioDesc::default(),
        Some(path) => {
            let src = project::read(files, path, &mut diags)?;
            match parse_toml::<ScenarioFile>(&src.text, "scenario") {
                Err(problem) => {
                    diags.extend_file(&src, vec![problem]);
                    crate::config::desc::ScenarioDesc::default()
                }
                Ok(sc) => {
                    let mut problems = Vec::new();
                    let world = crate::config::scenario(&sc, &registry, &desc, &mut problems);
                    diags.extend_file(&src, problems);
                    world
                }
            }
        }
    };
    if diags.has_errors() {
        return Err(diags);
    }
    let (chunks, layout) = front::compile(&parsed, &checked, &registry, &mut diags);
    if diags.has_errors() {
        return Err(diags);
    }
    let name = desc
        .name
        .clone()
        .or_else(|| p.folder.as_ref().and_then(|f| files.folder_name(f)))
        .unwrap_or_else(|| "machine".into());
    let io_map = desc.io_map.clone();
    let image = match build::image(name, desc, registry, scenario, &programs, chunks, &layout) {
        Ok(image) => image,
        Err(message) => {
            let span = machine
                .axis
                .values()
                .next()
                .map(crate::config::span_of)
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
    };
    let array_lower = parsed
        .variables
        .arrays
        .iter()
        .filter(|(_, a)| a.lower != 0)
        .map(|(name, a)| (name.clone(), a.lower))
        .collect();
    Ok(Loaded {
        image,
        warnings: diags,
        sources: parsed.sources,
        layout,
        io_map,
        array_lower,
    })
}
