//! The programs through the front end: read and parsed (before the registry exists, since
//! MotionBASIC programs declare their variables by use), then checked against the registry and
//! compiled to bytecode.

use super::project::ProgramFile;
use crate::check::typed::Program;
use crate::check::{CheckEnv, Variables};
use crate::compile::{compile as compile_program, Chunk, Layout};
use crate::config::files::Files;
use crate::diag::{Diagnostics, Problem, SourceFile};
use crate::registry::Registry;
use crate::span::Span;
use crate::syntax::ast::ProgramAst;
use crate::syntax::Dialect;
use indexmap::IndexMap;

/// The programs parsed.
pub struct Parsed {
    /// Each program's source, by number.
    pub sources: IndexMap<u32, SourceFile>,
    /// Each program: number, dialect, tree and its syntax problems.
    pub programs: Vec<(u32, Dialect, ProgramAst, Vec<Problem>)>,
    /// The MotionBASIC variables of every MotionBASIC program.
    pub variables: Variables,
}

/// Read and parse every program; a file that cannot be read is a problem of the machine file
/// (`problems`), at its `[[program]]` entry.
pub fn parse(files: &dyn Files, programs: &[ProgramFile], problems: &mut Vec<Problem>) -> Parsed {
    let mut out = Parsed {
        sources: IndexMap::new(),
        programs: Vec::new(),
        variables: Variables::default(),
    };
    for p in programs {
        let (text, not_utf8) = match files.read_bytes(&p.path) {
            Ok(bytes) => decode(bytes),
            Err(e) => {
                problems.push(Problem::error(
                    "pacer::load::read",
                    p.span.unwrap_or_default(),
                    format!("cannot read {}: {e}", p.path.display()),
                    "this program file",
                ));
                continue;
            }
        };
        let dialect = Dialect::of_path(&p.path).unwrap_or_default();
        let file = SourceFile::new(p.path.display().to_string(), text.as_str());
        let mut syntax = Vec::new();
        if let Some((at, byte, ch)) = not_utf8 {
            let (line, column) = file.line_col(Span::new(at, at));
            syntax.push(
                Problem::warning(
                    "pacer::load::encoding",
                    Span::new(at, at + ch.len_utf8()),
                    format!(
                        "{} is not UTF-8: read as Windows-1252 (its first such byte, 0x{byte:02X}, \
                         is `{ch}` at line {line}, column {column})",
                        p.path.display()
                    ),
                    "not UTF-8",
                )
                .with_help("save the file as UTF-8 to silence this warning"),
            );
        }
        let ast = crate::syntax::parse_program_as(&text, dialect, &mut syntax);
        if dialect == Dialect::MotionBasic {
            out.variables.collect(&ast);
        }
        out.sources.insert(p.number, file);
        out.programs.push((p.number, dialect, ast, syntax));
    }
    out
}

/// A program's text: UTF-8 as it is, anything else read as Windows-1252 (the encoding of the
/// Windows editors such programs were written with), with the first byte that is not UTF-8:
/// its offset in the text, its value and the character it stands for.
fn decode(bytes: Vec<u8>) -> (String, Option<(usize, u8, char)>) {
    let bad = match String::from_utf8(bytes) {
        Ok(text) => return (text, None),
        Err(e) => e,
    };
    let at = bad.utf8_error().valid_up_to();
    let bytes = bad.into_bytes();
    let (text, _, _) = encoding_rs::WINDOWS_1252.decode(&bytes);
    let (prefix, _, _) = encoding_rs::WINDOWS_1252.decode(&bytes[..at]);
    let offset = prefix.len();
    let ch = text[offset..].chars().next().unwrap_or('\u{FFFD}');
    (text.into_owned(), Some((offset, bytes[at], ch)))
}

/// What the checks against the machine need from the machine file.
pub struct MachineCheck<'a> {
    /// The DSP axes it defines, by number.
    pub dsp_axes: &'a [u32],
    /// A machine file was given (else the machine is the defaults).
    pub described: bool,
    /// The set-up of each index.
    pub indexes: &'a [crate::devices::drive::setup::IndexConfig],
}

/// Check every program against the registry; each program's problems go with its file. The
/// checked programs, by number.
pub fn check(
    parsed: &Parsed,
    registry: &Registry,
    numbers: &[u32],
    all_programs: bool,
    machine: Option<&MachineCheck<'_>>,
    diags: &mut Diagnostics,
) -> Vec<(u32, Program)> {
    let env = CheckEnv {
        registry,
        loaded_programs: numbers,
        all_programs,
    };
    let mut checked = Vec::new();
    // Programs with an error hold placeholders: checked against the machine they would cascade.
    let mut clean = Vec::new();
    for (number, dialect, ast, syntax) in &parsed.programs {
        let mut problems = syntax.clone();
        let (program, found) = crate::check::check(ast, *dialect, &env, &parsed.variables);
        problems.extend(found);
        if !problems
            .iter()
            .any(|p| p.level == crate::diag::Level::Error)
        {
            clean.push(*number);
        }
        if let Some(file) = parsed.sources.get(number) {
            diags.extend_file(file, problems);
        }
        checked.push((*number, program));
    }
    // Against the machine, with what every program writes known (not when the machine file
    // has errors: what it would have set up is unknown).
    let Some(machine) = machine else {
        return checked;
    };
    let mut written = Vec::new();
    for (_, program) in &checked {
        crate::check::machine::written_slots(program, &mut written);
    }
    let facts = crate::check::machine::MachineFacts {
        registry,
        dsp_axes: machine.dsp_axes,
        written: &written,
        described: machine.described,
        indexes: machine.indexes,
    };
    for (number, program) in checked.iter().filter(|(n, _)| clean.contains(n)) {
        let problems = crate::check::machine::against_machine(program, &facts);
        if let Some(file) = parsed.sources.get(number) {
            diags.extend_file(file, problems);
        }
    }
    checked
}

/// Compile every checked program (they checked without errors): each program's chunk, and the
/// value array's layout.
pub fn compile(
    parsed: &Parsed,
    checked: &[(u32, Program)],
    registry: &Registry,
    diags: &mut Diagnostics,
) -> (Vec<(u32, Chunk)>, Layout) {
    let mut layout = Layout::new(registry);
    let mut chunks = Vec::new();
    for (number, program) in checked {
        let Some(file) = parsed.sources.get(number) else {
            continue;
        };
        match compile_program(program, &file.text, &file.name, *number, &mut layout) {
            Ok(chunk) => chunks.push((*number, chunk)),
            Err(problems) => diags.extend_file(file, problems),
        }
    }
    (chunks, layout)
}
