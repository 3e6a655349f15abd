//! Values set from outside the machine's files: `pacer run --set NAME=VALUE` and each variant of
//! a sweep. A name is a path into the scenario (`master.speed`, `products.0.pitch`,
//! `master.change.1.speed`, `run.seed`), into the machine file (`machine.update`,
//! `queue.0.offset`), or a writable member (`Queue.0.QueueOffset`, `Var.Speed`). Files are
//! edited as TOML documents before the normal loader reads them, so every check and message of
//! a normal run applies to the values set; a member's value replaces its value at the start.

use crate::config::files::{Disk, Files};
use crate::load::{load_from, LoadOptions, LoadRequest, Loaded};
use crate::registry::{Access, ValueType};
use indexmap::IndexMap;
use std::path::{Path, PathBuf};

/// The top-level keys of `scenario.toml` (a name starting with one is a scenario path).
pub const SCENARIO_KEYS: &[&str] = &[
    "run",
    "master",
    "products",
    "input",
    "press",
    "pulses",
    "axis_marks",
    "marks",
    "belts",
    "workpieces",
];

/// The top-level keys of `machine.toml` (a name starting with one is a machine-file path).
pub const MACHINE_KEYS: &[&str] = &[
    "machine",
    "program",
    "io",
    "objects",
    "variables",
    "bits",
    "queue",
    "units",
    "index",
    "home",
    "jog",
    "pls",
    "assignment",
    "axis",
    "pickplace",
    "modbus",
];

/// Short names for the values swept most (`--seeds` varies `run.seed`).
const ALIASES: &[(&str, &str)] = &[
    ("seed", "run.seed"),
    ("duration", "run.duration"),
    ("update", "machine.update"),
];

/// Which file (or the members) a name sets.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A path into `scenario.toml`.
    Scenario(Vec<String>),
    /// A path into `machine.toml`.
    Machine(Vec<String>),
    /// A member's value at the start, by its name as programs write it.
    Member(String),
}

/// A value name, checked for form (whether it exists is known once the files are read).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Name {
    /// As written, aliases expanded (`seed` → `run.seed`).
    pub text: String,
    /// What it sets.
    pub target: Target,
}

impl Name {
    /// Parse a value name: an alias, a scenario or machine-file path, or a member.
    pub fn parse(text: &str) -> Result<Name, String> {
        let text = text.trim();
        let text = ALIASES
            .iter()
            .find(|(a, _)| *a == text)
            .map_or(text, |(_, full)| full);
        let parts: Vec<String> = text.split('.').map(str::to_string).collect();
        if text.is_empty() || parts.iter().any(String::is_empty) {
            return Err(format!("`{text}` is not a value name"));
        }
        let first = parts[0].as_str();
        let target = if first.starts_with(|c: char| c.is_ascii_uppercase()) {
            Target::Member(text.to_string())
        } else if SCENARIO_KEYS.contains(&first) {
            Target::Scenario(parts)
        } else if MACHINE_KEYS.contains(&first) {
            Target::Machine(parts)
        } else {
            let known = SCENARIO_KEYS
                .iter()
                .chain(MACHINE_KEYS)
                .chain(ALIASES.iter().map(|(a, _)| a));
            let hint = crate::diag::nearest(first, known.copied())
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "unknown value name `{text}`{hint}: a name is a path into scenario.toml \
                 (`master.speed`, `products.0.pitch`, `run.seed`), into machine.toml \
                 (`machine.update`, `queue.0.offset`), or a member (`Queue.0.QueueOffset`)"
            ));
        };
        Ok(Name {
            text: text.to_string(),
            target,
        })
    }
}

/// A value as text on a command line: TOML (`42`, `0.5`, `true`, `"50ms"`), else a bare string
/// (`50ms`, `ON`).
pub fn parse_value(text: &str) -> toml::Value {
    let t = text.trim();
    let doc = format!("v = {t}");
    match doc.parse::<toml::Table>() {
        Ok(mut table) => match table.remove("v") {
            Some(
                v @ (toml::Value::Integer(_) | toml::Value::Float(_) | toml::Value::Boolean(_)),
            ) => v,
            Some(toml::Value::String(s)) => toml::Value::String(s),
            _ => toml::Value::String(t.to_string()),
        },
        Err(_) => toml::Value::String(t.to_string()),
    }
}

/// A value as `--set` takes it back: numbers and booleans as TOML writes them, strings bare
/// when they read back as the same string, else quoted.
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => {
            if matches!(parse_value(s), toml::Value::String(ref back) if back == s)
                && !s.contains(['\'', '"', ' ', '\\'])
            {
                s.clone()
            } else {
                toml::Value::String(s.clone()).to_string()
            }
        }
        other => other.to_string(),
    }
}

/// `NAME=VALUE`, as `--set` and the re-run commands of a sweep give it.
pub fn parse_assignment(text: &str) -> Result<(Name, toml::Value), String> {
    let Some((name, value)) = text.split_once('=') else {
        return Err(format!("`{text}`: write NAME=VALUE, e.g. master.speed=40"));
    };
    if value.trim().is_empty() {
        return Err(format!("`{text}`: no value after `=`"));
    }
    Ok((Name::parse(name)?, parse_value(value)))
}

/// The machine project a sweep or a `--set` run starts from: its request, and the texts of its
/// machine file and scenario as read once.
#[derive(Debug, Clone)]
pub struct Base {
    /// What `pacer run` would load.
    pub req: LoadRequest,
    /// The machine file's path (where it would be, when there is none).
    pub machine_path: PathBuf,
    /// The scenario's path (where it would be, when there is none).
    pub scenario_path: PathBuf,
    /// The machine file's text, if there is one.
    pub machine_text: Option<String>,
    /// The scenario's text, if there is one.
    pub scenario_text: Option<String>,
}

impl Base {
    /// The project of `req`: the machine file and scenario the loader would read, read.
    pub fn open(req: LoadRequest) -> Base {
        // As the loader finds them: given, else beside the programs in the folder.
        let folder = req
            .paths
            .iter()
            .find(|p| p.is_dir())
            .cloned()
            .or_else(|| {
                req.paths
                    .first()
                    .and_then(|p| p.parent())
                    .map(Path::to_path_buf)
            })
            .unwrap_or_default();
        let machine_path = req
            .machine
            .clone()
            .unwrap_or_else(|| folder.join("machine.toml"));
        let scenario_path = req
            .scenario
            .clone()
            .unwrap_or_else(|| folder.join("scenario.toml"));
        Base {
            machine_text: std::fs::read_to_string(&machine_path).ok(),
            scenario_text: std::fs::read_to_string(&scenario_path).ok(),
            req,
            machine_path,
            scenario_path,
        }
    }

    /// Load the project with `values` set. A file that does not parse as TOML, or a name its
    /// file does not have, is an error message; problems the loader finds are its
    /// diagnostics.
    pub fn load(&self, values: &[(Name, toml::Value)]) -> Result<Loaded, SetError> {
        let mut overlay = Overlay::default();
        let scenario: Vec<_> = values
            .iter()
            .filter_map(|(n, v)| match &n.target {
                Target::Scenario(p) => Some((n, p, v)),
                _ => None,
            })
            .collect();
        if !scenario.is_empty() {
            let text = edit(
                self.scenario_text.as_deref(),
                &self.scenario_path,
                &scenario,
            )?;
            overlay.files.insert(as_set(&self.scenario_path), text);
        }
        let machine: Vec<_> = values
            .iter()
            .filter_map(|(n, v)| match &n.target {
                Target::Machine(p) => Some((n, p, v)),
                _ => None,
            })
            .collect();
        if !machine.is_empty() {
            let text = edit(self.machine_text.as_deref(), &self.machine_path, &machine)?;
            overlay.files.insert(as_set(&self.machine_path), text);
        }
        let mut req = self.req.clone();
        // An edited file is read under a name of its own, so a problem in it is not shown with
        // the line numbers of the file on the disk; beside it, so paths in it mean the same.
        if overlay.files.contains_key(&as_set(&self.scenario_path)) {
            req.scenario = Some(as_set(&self.scenario_path));
        }
        if overlay.files.contains_key(&as_set(&self.machine_path)) {
            req.machine = Some(as_set(&self.machine_path));
        }
        let mut loaded =
            load_from(&overlay, &req, &LoadOptions::default()).map_err(SetError::Load)?;
        for (name, value) in values {
            if let Target::Member(member) = &name.target {
                set_member(&mut loaded, member, value).map_err(SetError::Value)?;
            }
        }
        Ok(loaded)
    }
}

/// The name an edited file is read under: `scenario.toml (as set)`, beside the original.
fn as_set(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(" (as set)");
    path.with_file_name(name)
}

/// Why a project with values set did not load.
#[derive(Debug)]
pub enum SetError {
    /// A name or value that cannot be set (the message says which and why).
    Value(String),
    /// The loader's problems with the files as edited.
    Load(crate::diag::Diagnostics),
}

impl SetError {
    /// The problem as text.
    pub fn render(&self, color: bool) -> String {
        match self {
            SetError::Value(m) => format!("error: {m}\n"),
            SetError::Load(d) => d.render(color),
        }
    }

    /// Errors in it (at least one).
    pub fn error_count(&self) -> usize {
        match self {
            SetError::Value(_) => 1,
            SetError::Load(d) => d.error_count().max(1),
        }
    }
}

/// The disk, with some files' texts replaced.
#[derive(Default)]
struct Overlay {
    files: IndexMap<PathBuf, String>,
}

impl Files for Overlay {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        match self.files.get(path) {
            Some(t) => Ok(t.clone()),
            None => Disk.read(path),
        }
    }
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        match self.files.get(path) {
            Some(t) => Ok(t.clone().into_bytes()),
            None => Disk.read_bytes(path),
        }
    }
    fn is_dir(&self, path: &Path) -> bool {
        Disk.is_dir(path)
    }
    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(path) || Disk.exists(path)
    }
    fn list(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        Disk.list(dir)
    }
    fn folder_name(&self, dir: &Path) -> Option<String> {
        Disk.folder_name(dir)
    }
}

/// `text` (a TOML file at `path`, or none) with each path set to its value.
fn edit(
    text: Option<&str>,
    path: &Path,
    values: &[(&Name, &Vec<String>, &toml::Value)],
) -> Result<String, SetError> {
    let mut doc: toml::Table = match text {
        None => toml::Table::new(),
        // A file that does not parse is left to the loader, which reports it where it is.
        Some(t) => match t.parse() {
            Ok(d) => d,
            Err(_) => return Ok(t.to_string()),
        },
    };
    for (name, parts, value) in values {
        set_path(&mut doc, parts, (*value).clone())
            .map_err(|e| SetError::Value(format!("{}: {e} in {}", name.text, path.display())))?;
    }
    toml::to_string(&doc).map_err(|e| SetError::Value(format!("{}: {e}", path.display())))
}

/// Set `parts` in `doc`: every part but the last must exist (a number indexes an array of
/// tables, `products.0`); the last may be a key the table lacks (the loader checks it).
pub fn set_path(doc: &mut toml::Table, parts: &[String], value: toml::Value) -> Result<(), String> {
    let Some((last, walk)) = parts.split_last() else {
        return Err("an empty name".into());
    };
    let mut table = doc;
    let mut so_far = String::new();
    let mut iter = walk.iter().peekable();
    while let Some(part) = iter.next() {
        if !so_far.is_empty() {
            so_far.push('.');
        }
        so_far.push_str(part);
        // `[master]` may be absent from a scenario with no master: made here.
        if !table.contains_key(part.as_str())
            && iter.peek().is_none()
            && !part.chars().all(|c| c.is_ascii_digit())
        {
            table.insert(part.clone(), toml::Value::Table(toml::Table::new()));
        }
        let Some(next) = table.get_mut(part.as_str()) else {
            return Err(format!("there is no `{so_far}`"));
        };
        table = match next {
            toml::Value::Table(t) => t,
            toml::Value::Array(items) => {
                let Some(index) = iter.next() else {
                    return Err(format!(
                        "`{so_far}` is a list: give an entry's number (`{so_far}.0`)"
                    ));
                };
                let n: usize = index.parse().map_err(|_| {
                    format!("`{so_far}` is a list: `{index}` is not an entry number")
                })?;
                let count = items.len();
                match items.get_mut(n) {
                    Some(toml::Value::Table(t)) => {
                        so_far.push('.');
                        so_far.push_str(index);
                        t
                    }
                    Some(_) => return Err(format!("`{so_far}.{index}` is not a table")),
                    None => {
                        return Err(format!(
                            "there is no `{so_far}.{index}`: `{so_far}` has {count} entr{} (numbered from 0)",
                            if count == 1 { "y" } else { "ies" }
                        ))
                    }
                }
            }
            _ => return Err(format!("`{so_far}` is a value, not a table")),
        };
    }
    if matches!(
        table.get(last.as_str()),
        Some(toml::Value::Table(_) | toml::Value::Array(_))
    ) {
        return Err(format!(
            "`{}` is a table or list, not a value",
            parts.join(".")
        ));
    }
    table.insert(last.clone(), value);
    Ok(())
}

/// The member's value at the start of the run. Only settings and data a program may write
/// (not status, not actions), with a value of the member's type.
fn set_member(loaded: &mut Loaded, member: &str, value: &toml::Value) -> Result<(), String> {
    let registry = &loaded.image.registry;
    let name = crate::syntax::ast::Name::from_token(member, 0);
    let resolved = crate::check::motionbasic::resolve(registry, &name).map_err(|p| {
        let names: Vec<_> = registry.slots.iter().map(|s| s.name.text()).collect();
        let hint = crate::export::signals::nearest(member, names.iter().map(|n| n.as_ref()))
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
        format!("{member}: {}{hint}", p.message)
    })?;
    let slot = resolved.slot as usize;
    let Some(info) = registry.slots.get(slot) else {
        return Err(format!("{member}: not a member with a value"));
    };
    if info.member.access != Access::ReadWrite {
        return Err(format!(
            "{member}: only settings and data a program may write can be set (this one is {})",
            match info.member.access {
                Access::Read => "status the machine sets",
                Access::Action | Access::Input => "an action",
                Access::ReadWrite => "writable",
            }
        ));
    }
    let x = member_value(value, info.ty).map_err(|e| format!("{member}: {e}"))?;
    match loaded.image.initial.get_mut(slot) {
        Some(v) => *v = x,
        None => return Err(format!("{member}: not a member with a value")),
    }
    Ok(())
}

/// `value` as a member of type `ty` holds it.
fn member_value(value: &toml::Value, ty: ValueType) -> Result<f64, String> {
    let x = match value {
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(f) => *f,
        toml::Value::Boolean(b) => f64::from(u8::from(*b)),
        toml::Value::String(s) => match s.to_ascii_uppercase().as_str() {
            "ON" | "TRUE" => 1.0,
            "OFF" | "FALSE" => 0.0,
            _ => return Err(format!("`{s}` is not a number (or ON/OFF)")),
        },
        other => return Err(format!("`{other}` is not a number (or ON/OFF)")),
    };
    if !x.is_finite() {
        return Err(format!("{x} is not a finite number"));
    }
    match ty {
        ValueType::Bit if x == 0.0 || x == 1.0 => Ok(x),
        ValueType::Bit => Err(format!("{x}: a bit is ON or OFF")),
        ValueType::Integer => {
            if x.fract() != 0.0 || x < f64::from(i32::MIN) || x > f64::from(i32::MAX) {
                Err(format!("{x} is not a 32-bit integer"))
            } else {
                Ok(x)
            }
        }
        ValueType::Fixed(d) => crate::fixed::to_fixed(x, d)
            .ok_or_else(|| format!("{x} does not fit a 32-bit value with {d} decimals")),
        ValueType::Real => Ok(x),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_go_to_their_file() {
        let n = Name::parse("master.speed").expect("a scenario path");
        assert_eq!(
            n.target,
            Target::Scenario(vec!["master".into(), "speed".into()])
        );
        assert_eq!(Name::parse("seed").expect("alias").text, "run.seed");
        assert!(matches!(
            Name::parse("update").expect("alias").target,
            Target::Machine(_)
        ));
        assert!(matches!(
            Name::parse("Queue.0.QueueOffset").expect("member").target,
            Target::Member(_)
        ));
        let e = Name::parse("mastr.speed").expect_err("unknown");
        assert!(e.contains("did you mean `master`"), "{e}");
        assert!(Name::parse("master..speed").is_err());
    }

    #[test]
    fn values_read_as_toml_or_bare_text() {
        assert_eq!(parse_value("42"), toml::Value::Integer(42));
        assert_eq!(parse_value("0.5"), toml::Value::Float(0.5));
        assert_eq!(parse_value("50ms"), toml::Value::String("50ms".into()));
        assert_eq!(parse_value("\"50ms\""), toml::Value::String("50ms".into()));
        for v in ["42", "0.5", "50ms", "ON", "true"] {
            assert_eq!(parse_value(&value_text(&parse_value(v))), parse_value(v));
        }
        assert_eq!(value_text(&toml::Value::String("a b".into())), "\"a b\"");
    }

    #[test]
    fn paths_walk_tables_and_lists() {
        let mut doc: toml::Table =
            "[master]\nspeed = 1.0\n[[master.change]]\nat = 1.0\nspeed = 2.0\n"
                .parse()
                .expect("toml");
        let path = |s: &str| s.split('.').map(str::to_string).collect::<Vec<_>>();
        set_path(
            &mut doc,
            &path("master.change.0.speed"),
            toml::Value::Float(9.0),
        )
        .expect("set");
        assert_eq!(doc["master"]["change"][0]["speed"].as_float(), Some(9.0));
        let e = set_path(
            &mut doc,
            &path("master.change.3.speed"),
            toml::Value::Float(1.0),
        )
        .expect_err("no entry 3");
        assert!(e.contains("has 1 entry"), "{e}");
        let e = set_path(&mut doc, &path("master.change"), toml::Value::Float(1.0))
            .expect_err("a list");
        assert!(e.contains("not a value"), "{e}");
        set_path(&mut doc, &path("run.seed"), toml::Value::Integer(3)).expect("made");
        assert_eq!(doc["run"]["seed"].as_integer(), Some(3));
    }
}
