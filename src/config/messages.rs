//! The reader's errors in the user's words. When a file does not fit its shape, serde and the
//! TOML reader say so in Rust's terms ("invalid type: map, expected u32", "expected struct
//! MachineSection"); [`toml_problem`] turns every such message into the key at fault, what it
//! takes in words ("a whole number from 1 to 64") and what was found, with the numbers short
//! and invisible characters escaped. No Rust type name reaches the user (the configuration
//! fuzz target asserts it).

use super::machine::{TomlTable, TomlValue};
use crate::diag::{escaped, number, Problem};
use crate::span::Span;

/// What each key takes, in words, by its path: `*` stands for any one key (an instance number,
/// a variable's name). Arrays of tables (`[[program]]`) take no index in the path.
const FIELDS: &[(&str, &str)] = &[
    // machine.toml
    ("machine", "a table: write `[machine]` once"),
    ("machine.name", "text (the machine's name)"),
    (
        "machine.update",
        "a duration from 1 µs to 1 s: seconds, or text with a unit (\"1ms\")",
    ),
    ("machine.budget", "a whole number from 1 to 1,000,000"),
    ("machine.tasks", "a whole number from 1 to 64"),
    ("machine.rollover", "a number (0: no rollover)"),
    ("program", "`[[program]]` tables, one for each program"),
    (
        "program.number",
        "a whole number from 0 to 4,095 (the program's number)",
    ),
    ("program.file", "text (the program's file)"),
    ("program.autostart", "true or false"),
    ("io", "a table of counts (`DriveInput = 6`)"),
    ("io.*", "a whole number from 0 to 4,096"),
    ("objects", "a table of counts (`Capture = 4`)"),
    ("objects.*", "a whole number from 0 to 4,096"),
    ("variables", "a table of variables (`[variables.Count]`)"),
    ("variables.*", "a table (`decimals`, `initial`)"),
    ("variables.*.decimals", "a whole number from 0 to 9"),
    ("variables.*.initial", "a number"),
    ("bits", "a table: write `[bits]` once"),
    ("bits.count", "a whole number from 0 to 4,096"),
    ("bits.names", "a table of bit names (`Ready = 3`)"),
    ("bits.names.*", "a bit number (a whole number from 0)"),
    (
        "bits.initially_on",
        "an array of bit numbers or names, as text (`[\"3\", \"Ready\"]`)",
    ),
    ("queue.*", "a table (`[queue.0]`)"),
    ("queue.*.name", "text"),
    ("queue.*.size", "a whole number from 1 to 10,000"),
    ("queue.*.offset", "a number"),
    (
        "queue.*.full_level",
        "a whole number from 1 to the queue's size",
    ),
    (
        "queue.*.source",
        "text: MasterPosn, FeedbackPosn or CommandPosn",
    ),
    ("units", "a table: write `[units]` once"),
    ("units.motor", "text (the unit's name)"),
    ("units.master", "text (the unit's name)"),
    ("units.*", "a number above 0"),
    ("servo", "a table: write `[servo]` once"),
    ("servo.model", "text: ideal or cascade"),
    (
        "servo.latch_delay",
        "a duration from 0 to 1 ms: seconds, or text with a unit (\"1us\")",
    ),
    ("servo.*", "a number"),
    (
        "axis.*.servo",
        "a table (`[axis.1.servo]`, the keys of `[servo]`)",
    ),
    ("axis.*.servo.model", "text: ideal or cascade"),
    (
        "axis.*.servo.latch_delay",
        "a duration from 0 to 1 ms: seconds, or text with a unit (\"1us\")",
    ),
    ("axis.*.servo.*", "a number"),
    ("index.*", "a table (`[index.0]`)"),
    (
        "index.*.type",
        "text: Incremental, Absolute, Registration, RotaryPlus or RotaryMinus",
    ),
    ("index.*.time_base", "text: Realtime or Synchronized"),
    ("index.*.*", "a number"),
    ("home.*", "a table (`[home.0]`)"),
    ("home.*.reference", "text: an input (\"DriveInput.1\")"),
    ("home.*.*", "a number"),
    ("jog.*", "a table (`[jog.0]`)"),
    ("jog.*.*", "a number"),
    ("pls.*", "a table (`[pls.0]`)"),
    (
        "pls.*.source",
        "text: MasterPosn, FeedbackPosn or CommandPosn",
    ),
    ("pls.*.direction", "text: Both, Plus or Minus"),
    ("pls.*.*", "a number"),
    (
        "assignment",
        "`[[assignment]]` tables, one for each assignment",
    ),
    ("assignment.*", "text (a member: \"ModuleInput.1\")"),
    ("axis.*", "a table (`[axis.1]`)"),
    ("axis.*.name", "text"),
    ("axis.*.pacer", "an axis number from 1 to 16"),
    ("axis.*.queue", "a whole number from 1 to 64"),
    ("axis.*.fast_input", "text: an input (\"ModuleInput.1\")"),
    ("axis.*.*", "a number above 0"),
    ("pickplace", "a table: write `[pickplace]` once"),
    ("modbus", "a table: write `[modbus]` once"),
    ("modbus.host", "text: a host name or IP address"),
    ("modbus.port", "a whole number from 1 to 65,535"),
    ("modbus.unit", "a whole number from 0 to 255"),
    ("modbus.timeout", "a duration above 0 and at most 60 s"),
    ("modbus.max_gap", "a whole number from 0 to 125"),
    ("modbus.enabled", "true or false"),
    ("modbus.overrun_limit", "a whole number from 0 to 1,000,000"),
    (
        "modbus.map",
        "`[[modbus.map]]` tables, one for each run of points",
    ),
    (
        "modbus.map.kind",
        "text: coil, discrete_input, holding_register or input_register",
    ),
    ("modbus.map.address", "a whole number from 0 to 65,535"),
    ("modbus.map.count", "a whole number from 1 to 2,000"),
    ("modbus.map.member", "text: a member (\"DriveInput.1\")"),
    ("modbus.map.signed", "true or false"),
    ("modbus.map.*", "a number"),
    // scenario.toml
    ("run", "a table: write `[run]` once"),
    (
        "run.duration",
        "a duration from 0 to 1,000,000 s: seconds, or text with a unit (\"3s\")",
    ),
    ("run.seed", "a whole number, 0 or more"),
    ("input", "`[[input]]` tables, one for each level change"),
    ("input.name", "text: an input (\"DriveInput.1\")"),
    ("input.value", "ON or OFF (or true/false)"),
    (
        "input.at",
        "a time: seconds, or text with a unit (\"300ms\")",
    ),
    ("press", "`[[press]]` tables, one for each press"),
    ("press.name", "text: an input (\"DriveInput.1\")"),
    ("press.*", "a time: seconds, or text with a unit (\"50ms\")"),
    ("pulses", "`[[pulses]]` tables, one for each pulse train"),
    ("pulses.name", "text: an input (\"ModuleInput.2\")"),
    ("pulses.count", "a whole number from 0 to 10,000,000"),
    (
        "pulses.*",
        "a time: seconds, or text with a unit (\"10ms\")",
    ),
    ("master", "a table: write `[master]` once"),
    ("master.speed", "a number (master units per second)"),
    (
        "master.change",
        "`[[master.change]]` tables, one for each speed change",
    ),
    ("master.change.speed", "a number (master units per second)"),
    (
        "master.change.*",
        "a time: seconds, or text with a unit (\"1s\")",
    ),
    ("products", "`[[products]]` tables, one for each stream"),
    ("products.sensor", "text: an input (\"ModuleInput.2\")"),
    ("products.count", "a whole number from 0 to 10,000,000"),
    (
        "products.missing",
        "an array of product numbers (whole numbers from 0)",
    ),
    (
        "products.bounce",
        "a table (`{ count = 3, width = \"40us\", gap = \"60us\" }`)",
    ),
    ("products.bounce.count", "a whole number from 0 to 1,000"),
    ("products.bounce.trailing", "true or false"),
    (
        "products.bounce.*",
        "a time: seconds, or text with a unit (\"40us\")",
    ),
    ("products.*", "a number"),
    ("axis_marks", "`[[axis_marks]]` tables, one for each sensor"),
    ("axis_marks.sensor", "text: an input (\"DriveInput.1\")"),
    ("axis_marks.count", "a whole number, 1 or more"),
    ("axis_marks.*", "a number"),
    ("marks", "`[[marks]]` tables, one for each track of marks"),
    ("marks.axis", "a DSP axis number from 1 to 16"),
    ("marks.sensor", "text: ASEN, BSEN, ZREF or FAST"),
    (
        "marks.on_time",
        "a time: seconds, or text with a unit (\"1ms\")",
    ),
    (
        "marks.at",
        "an array of numbers (axis positions, increasing)",
    ),
    ("marks.count", "a whole number from 1 to 1,000,000"),
    ("marks.seed", "a whole number, 0 or more"),
    (
        "marks.steps",
        "an array of steps (`[{ at = 30, pitch = 15300 }]`)",
    ),
    ("marks.steps.at", "a mark number (a whole number from 0)"),
    ("marks.steps.pitch", "a number"),
    (
        "marks.spurious",
        "a table (`{ every = 40, offset = 6000 }`)",
    ),
    ("marks.spurious.every", "a whole number, 1 or more"),
    ("marks.spurious.offset", "a number"),
    ("marks.*", "a number"),
    ("belts", "`[[belts]]` tables, one for each belt"),
    ("belts.belt", "a belt number from 1 to 16"),
    ("belts.speed", "a number (mm/s)"),
    (
        "belts.changes",
        "an array of changes (`[{ at = \"20 s\", speed = 220.0, ramp = \"1 s\" }]`)",
    ),
    ("belts.changes.speed", "a number (mm/s)"),
    (
        "belts.changes.*",
        "a time: seconds, or text with a unit (\"1 s\")",
    ),
    (
        "workpieces",
        "`[[workpieces]]` tables, one for each detector",
    ),
    ("workpieces.belt", "a belt number from 1 to 16"),
    ("workpieces.count", "a whole number from 1 to 1,000,000"),
    (
        "workpieces.at",
        "an array of numbers (belt travels, mm, increasing)",
    ),
    (
        "workpieces.missing",
        "an array of workpiece numbers (whole numbers from 0)",
    ),
    (
        "workpieces.detect",
        "an array of three numbers (X, Y, Z in mm)",
    ),
    (
        "workpieces.jitter",
        "a table (`{ x = 4.0, y = 25.0, c = 10.0 }`)",
    ),
    ("workpieces.jitter.*", "a number"),
    ("workpieces.seed", "a whole number, 0 or more"),
    (
        "workpieces.delay",
        "a time: seconds, or text with a unit (\"20 ms\")",
    ),
    ("workpieces.*", "a number"),
];

/// One step of the way to a key: its name, and whether its value is an array (of tables).
#[derive(Debug, Clone, PartialEq)]
struct Step {
    key: String,
    array: bool,
}

/// A problem for a TOML document `text` (the `what` file) that the reader refused with `error`.
pub fn toml_problem(text: &str, what: &str, error: &toml::de::Error) -> Problem {
    let span = error
        .span()
        .map_or(Span::new(0, 0), |r| Span::new(r.start, r.end));
    let path = locate(text, span);
    let message = translate(error.message().trim(), text, span, &path);
    Problem::error(
        "pacer::config",
        span,
        format!("{what}: {}", escaped(&scrub(&message))),
        "here",
    )
}

/// The keys leading to the value at `span` (the deepest one that holds it), when the document
/// reads as TOML at all.
fn locate(text: &str, span: Span) -> Vec<Step> {
    let Ok(table) = toml::from_str::<TomlTable>(text) else {
        return locate_by_text(text, span);
    };
    let mut best = Vec::new();
    walk_table(&table, span.start, &mut Vec::new(), &mut best);
    best
}

/// The keys leading to `span` read from the text around it, for a document that does not read
/// as TOML values (a whole number past 64 bits): the key before `=` on its line, below the
/// nearest table header.
fn locate_by_text(text: &str, span: Span) -> Vec<Step> {
    let at = span.start.min(text.len());
    let Some(before) = text.get(..at) else {
        return Vec::new();
    };
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let mut path = Vec::new();
    for line in before[..line_start].lines().rev() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix("[[") {
            let name = h.split("]]").next().unwrap_or("");
            path = keys(name, true);
            break;
        }
        if let Some(h) = l.strip_prefix('[') {
            let name = h.split(']').next().unwrap_or("");
            path = keys(name, false);
            break;
        }
    }
    if let Some((key, _)) = before[line_start..].split_once('=') {
        path.extend(keys(key, false));
    }
    path
}

/// The steps of a dotted key as written (`queue.0`, `"a b".c`).
fn keys(dotted: &str, array: bool) -> Vec<Step> {
    let parts: Vec<&str> = dotted
        .split('.')
        .map(|k| k.trim().trim_matches('"'))
        .collect();
    let n = parts.len();
    parts
        .into_iter()
        .enumerate()
        .filter(|(_, k)| !k.is_empty())
        .map(|(i, k)| Step {
            key: k.to_string(),
            array: array && i + 1 == n,
        })
        .collect()
}

fn contains(r: std::ops::Range<usize>, at: usize) -> bool {
    r.start <= at && at < r.end.max(r.start + 1)
}

// A table opened by a header spans only its header, not the keys below it, so every entry is
// searched: the deepest key or value that holds `at` wins.
fn walk_table(table: &TomlTable, at: usize, path: &mut Vec<Step>, best: &mut Vec<Step>) {
    for (k, v) in &table.entries {
        path.push(Step {
            key: k.get_ref().clone(),
            array: matches!(v.get_ref(), TomlValue::Array(_)),
        });
        if (contains(k.span(), at) || contains(v.span(), at)) && path.len() > best.len() {
            *best = path.clone();
        }
        walk_value(v.get_ref(), at, path, best);
        path.pop();
    }
}

fn walk_value(v: &TomlValue, at: usize, path: &mut Vec<Step>, best: &mut Vec<Step>) {
    match v {
        TomlValue::Table(t) => walk_table(t, at, path, best),
        TomlValue::Array(items) => {
            for item in items {
                walk_value(item.get_ref(), at, path, best);
            }
        }
        _ => {}
    }
}

/// What the key at `path` takes, in words, when [`FIELDS`] knows it.
fn field_words(path: &[Step]) -> Option<&'static str> {
    FIELDS.iter().find_map(|(pattern, words)| {
        let parts: Vec<&str> = pattern.split('.').collect();
        (parts.len() == path.len()
            && parts
                .iter()
                .zip(path)
                .all(|(p, s)| *p == "*" || *p == s.key))
        .then_some(*words)
    })
}

/// The key at `path` as the user wrote it: `tasks` in `[machine]`, `count` in `[[products]]`
/// `bounce`.
fn key_name(path: &[Step]) -> String {
    let Some((last, parents)) = path.split_last() else {
        return "the file".into();
    };
    if parents.is_empty() {
        return if last.array {
            format!("`[[{}]]`", last.key)
        } else {
            format!("`{}`", last.key)
        };
    }
    // The header is everything up to the last array of tables, or every parent.
    let cut = parents
        .iter()
        .rposition(|s| s.array)
        .map_or(parents.len(), |i| i + 1);
    let header: Vec<&str> = parents[..cut].iter().map(|s| s.key.as_str()).collect();
    let header = if parents[..cut].last().is_some_and(|s| s.array) {
        format!("[[{}]]", header.join("."))
    } else {
        format!("[{}]", header.join("."))
    };
    let mut rest: Vec<&str> = parents[cut..].iter().map(|s| s.key.as_str()).collect();
    rest.push(&last.key);
    format!("`{}` in `{header}`", rest.join("."))
}

/// The table at `path` as its header is written: `[queue.0]`, `[[modbus.map]]`.
fn header(path: &[Step]) -> String {
    let name = path
        .iter()
        .map(|s| s.key.as_str())
        .collect::<Vec<_>>()
        .join(".");
    if path.last().is_some_and(|s| s.array) {
        format!("`[[{name}]]`")
    } else {
        format!("`[{name}]`")
    }
}

/// The reader's message in words.
fn translate(message: &str, text: &str, span: Span, path: &[Step]) -> String {
    let written = text.get(span.start..span.end).unwrap_or("");
    let place = path.iter().map(|s| s.key.as_str()).collect::<Vec<_>>();
    // A table written as an array of tables, or the other way round.
    if written.trim_start().starts_with("[[") && !path.is_empty() {
        let name = place.join(".");
        // A key that takes a list of tables (`[[program]]`) is not one table.
        let takes_list = FIELDS.iter().any(|(p, w)| *p == name && w.starts_with('`'));
        let takes_table =
            field_words(path).is_some_and(|w| w.starts_with("a table")) || path.len() == 1;
        if takes_table && !takes_list {
            return format!("`[{name}]` is one table; write `[{name}]`, not `[[{name}]]`");
        }
    }
    if let Some(rest) = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "))
    {
        let (found, expected) = rest.rsplit_once(", expected ").unwrap_or((rest, ""));
        let found = found_words(found);
        if let Some(words) = field_words(path) {
            if words.starts_with('`') && found == "a table" {
                let name = place.join(".");
                return format!(
                    "`{name}` is a list of tables: write each one as `[[{name}]]`, not `[{name}]`"
                );
            }
            return format!("{} takes {words}, not {found}", key_name(path));
        }
        return format!(
            "{} takes {}, not {found}",
            key_name(path),
            expected_words(expected)
        );
    }
    if let Some(field) = message
        .strip_prefix("missing field `")
        .and_then(|r| r.strip_suffix('`'))
    {
        let table = if path.is_empty() {
            "the file".to_string()
        } else {
            header(path)
        };
        let mut full: Vec<Step> = path.to_vec();
        full.push(Step {
            key: field.to_string(),
            array: false,
        });
        return match field_words(&full) {
            Some(words) => format!("{table} needs `{field}`: {words}"),
            None => format!("{table} needs `{field}`"),
        };
    }
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let (field, known) = rest.split_once('`').unwrap_or((rest, ""));
        let known = known
            .trim_start_matches(',')
            .trim()
            .trim_start_matches("expected one of ")
            .trim_start_matches("expected ");
        let within = match path.split_last() {
            Some((_, parents)) if !parents.is_empty() => format!(" in {}", header(parents)),
            _ => String::new(),
        };
        return if known.is_empty() || known.starts_with("there are no fields") {
            format!("unknown key `{field}`{within}")
        } else {
            format!("unknown key `{field}`{within}; the keys are {known}")
        };
    }
    if message.starts_with("floating-point number overflowed") {
        return "a number larger than any pacer can hold (about 1.8e308)".into();
    }
    message.to_string()
}

/// What serde found, in words: `integer \`3\`` is 3, `map` is a table.
fn found_words(found: &str) -> String {
    let inner = |s: &str| -> String {
        let s = s.trim();
        let s = s.split(" as ").next().unwrap_or(s);
        s.trim_matches('`').to_string()
    };
    if let Some(n) = found.strip_prefix("integer ") {
        let n = inner(n);
        return match n.parse::<f64>() {
            Ok(x) if n.len() > 16 => number(x),
            _ => n,
        };
    }
    if let Some(x) = found.strip_prefix("floating point ") {
        let x = inner(x);
        return x.parse::<f64>().map_or(x, number);
    }
    if let Some(s) = found.strip_prefix("string ") {
        return format!("the text {s}");
    }
    if let Some(b) = found.strip_prefix("boolean ") {
        return inner(b);
    }
    match found {
        "map" => "a table".into(),
        "sequence" => "an array".into(),
        other => other.into(),
    }
}

/// serde's "expected …" in words, for a key [`FIELDS`] does not know.
fn expected_words(expected: &str) -> String {
    let e = expected.trim();
    if e.starts_with("struct ") || e == "a map" {
        return "a table".into();
    }
    match e {
        "u8" => "a whole number from 0 to 255".into(),
        "u16" => "a whole number from 0 to 65,535".into(),
        "u32" => "a whole number from 0 to 4,294,967,295".into(),
        "u64" | "usize" => "a whole number, 0 or more".into(),
        "i8" | "i16" | "i32" | "i64" | "i128" | "isize" => "a whole number".into(),
        "f32" | "f64" => "a number".into(),
        "a string" => "text in quotes".into(),
        "a boolean" => "true or false".into(),
        "a sequence" => "an array".into(),
        "" => "something else".into(),
        other => other.into(),
    }
}

/// The last guard: any Rust type name left in a message (from a message this module does not
/// know) is put in words.
fn scrub(message: &str) -> String {
    let mut out = message.replace(" as i128", "");
    for (rust, words) in [("struct ", "a table"), ("enum ", "a choice")] {
        while let Some(i) = out.find(rust) {
            let name_end = out[i + rust.len()..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .map_or(out.len(), |n| i + rust.len() + n);
            out.replace_range(i..name_end, words);
        }
    }
    for (rust, words) in [
        ("Option<", "optional <"),
        ("Vec<", "array <"),
        ("invalid type: map", "a table"),
    ] {
        out = out.replace(rust, words);
    }
    let words: Vec<String> = out
        .split(' ')
        .map(|w| {
            let core = w.trim_matches(|c: char| !c.is_ascii_alphanumeric());
            match core {
                "u8" | "u16" | "u32" | "u64" | "usize" => w.replace(core, "a whole number"),
                "i8" | "i16" | "i32" | "i64" | "i128" | "isize" => {
                    w.replace(core, "a whole number")
                }
                "f32" | "f64" => w.replace(core, "a number"),
                _ => w.to_string(),
            }
        })
        .collect();
    words.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message_of<T: serde::de::DeserializeOwned + std::fmt::Debug>(text: &str) -> String {
        match toml::from_str::<T>(text) {
            Ok(v) => panic!("{text:?} read as {v:?}"),
            Err(e) => toml_problem(text, "machine file", &e).message,
        }
    }

    #[test]
    fn messages_name_the_key_and_what_it_takes() {
        use crate::config::machine::MachineFile;
        assert_eq!(
            message_of::<MachineFile>("[machine]\ntasks = -1\n"),
            "machine file: `tasks` in `[machine]` takes a whole number from 1 to 64, not -1"
        );
        assert_eq!(
            message_of::<MachineFile>("[[machine]]\nname = \"x\"\n"),
            "machine file: `[machine]` is one table; write `[machine]`, not `[[machine]]`"
        );
        assert_eq!(
            message_of::<MachineFile>("[program]\nnumber = 1\n"),
            "machine file: `program` is a list of tables: write each one as `[[program]]`, not `[program]`"
        );
        assert_eq!(
            message_of::<MachineFile>("[queue.0]\nsize = 1e300\n"),
            "machine file: `size` in `[queue.0]` takes a whole number from 1 to 10,000, not 1e300"
        );
        assert_eq!(
            message_of::<MachineFile>("[[program]]\nnumber = 1\n"),
            "machine file: `[[program]]` needs `file`: text (the program's file)"
        );
    }

    #[test]
    fn no_rust_type_is_left() {
        assert_eq!(
            scrub("expected u32, found i64"),
            "expected a whole number, found a whole number"
        );
        assert_eq!(
            scrub("expected struct Foo, or enum Bar"),
            "expected a table, or a choice"
        );
    }
}
