//! A project's files: the folder and program files given, the machine file and scenario that go
//! with them, and the programs with their numbers (from `[[program]]` entries, else from the
//! digits that end a file name, else in order).

use super::LoadRequest;
use crate::config::desc::ProgramDesc;
use crate::config::files::Files;
use crate::diag::{Diagnostics, Problem, SourceFile};
use crate::span::Span;
use crate::syntax::Dialect;
use std::path::{Path, PathBuf};

/// Where a project's files are.
pub struct Located {
    /// The folder, if one was given (or the program files' folder has a machine file).
    pub folder: Option<PathBuf>,
    /// Program files given one by one.
    pub files: Vec<PathBuf>,
    /// The machine file, if there is one.
    pub machine: Option<PathBuf>,
    /// The scenario, if there is one.
    pub scenario: Option<PathBuf>,
}

/// A program to load.
pub struct ProgramFile {
    /// `Program.N`.
    pub number: u32,
    /// Its file.
    pub path: PathBuf,
    /// It starts with the run.
    pub autostart: bool,
    /// The `[[program]]` entry naming it, if one does.
    pub span: Option<Span>,
}

/// The folder, files, machine file and scenario of `req`.
pub fn locate(
    files: &dyn Files,
    req: &LoadRequest,
    diags: &mut Diagnostics,
) -> Result<Located, Diagnostics> {
    let mut folder = None;
    let mut given = Vec::new();
    for p in &req.paths {
        if files.is_dir(p) {
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
            given.push(p.clone());
        }
    }
    if folder.is_none() {
        // Files in one folder that has a machine.toml use it.
        if let Some(parent) = given.first().and_then(|f| f.parent()) {
            if files.exists(&parent.join("machine.toml"))
                && given.iter().all(|f| f.parent() == Some(parent))
            {
                folder = Some(parent.to_path_buf());
            }
        }
    }
    let beside = |name: &str| {
        folder
            .as_ref()
            .map(|f| f.join(name))
            .filter(|p| files.exists(p))
    };
    Ok(Located {
        machine: req.machine.clone().or_else(|| beside("machine.toml")),
        scenario: req.scenario.clone().or_else(|| beside("scenario.toml")),
        folder,
        files: given,
    })
}

/// The text of the file at `path`, or every problem so far and this one.
pub fn read(
    files: &dyn Files,
    path: &Path,
    diags: &mut Diagnostics,
) -> Result<SourceFile, Diagnostics> {
    match files.read(path) {
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

/// The programs of the project, by number: the machine file's `[[program]]` entries (`listed`)
/// when no files are given, else the files (or the folder's program files) numbered from their
/// names.
pub fn programs(
    files: &dyn Files,
    p: &Located,
    listed: &[ProgramDesc],
    diags: &mut Diagnostics,
) -> Vec<ProgramFile> {
    let base_dir = p
        .machine
        .as_ref()
        .and_then(|m| m.parent().map(Path::to_path_buf))
        .or(p.folder.clone())
        .unwrap_or_default();
    if !listed.is_empty() && p.files.is_empty() {
        return listed
            .iter()
            .map(|e| ProgramFile {
                number: e.number,
                path: base_dir.join(&e.file),
                autostart: e.autostart,
                span: Some(e.span),
            })
            .collect();
    }
    let list = if p.files.is_empty() {
        p.folder
            .as_ref()
            .map(|f| program_files_in(files, f, diags))
            .unwrap_or_default()
    } else {
        p.files.clone()
    };
    let mut programs: Vec<ProgramFile> = Vec::new();
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
    programs
}

fn program_files_in(files: &dyn Files, folder: &Path, diags: &mut Diagnostics) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = match files.list(folder) {
        Ok(entries) => entries
            .into_iter()
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
    found.sort();
    found
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
    // A number past the most programs a machine may have (`program99999999.pt`) is no program
    // number: the file is numbered in order.
    digits
        .parse()
        .ok()
        .filter(|n| *n < crate::config::objects::MAX_INSTANCES)
}
