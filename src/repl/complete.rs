//! Tab completion and hints: objects, instances and members from the machine's registry,
//! variables, keywords, functions and commands. Pure functions over a [`Vocabulary`], so the
//! line editor's thread can use it while the machine runs on the main thread.

use super::commands::{COMMANDS, PREFIX};
use crate::check::functions::{FUNCTIONS, KERNEL_FUNCTIONS};
use crate::check::motionbasic::CONTROLLERS;
use crate::registry::catalog::BARE_GLOBAL_TYPE;
use crate::registry::{Instances, Kind, Registry};
use crate::syntax::Dialect;

/// PowerTools keywords, as the manual writes them.
const PT_KEYWORDS: &[&str] = &[
    "If", "Then", "Else", "Endif", "Do", "While", "Loop", "Wait", "For", "Time", "Dwell", "Master",
    "Dist", "Using", "Last", "On", "To", "Step", "Next", "Goto", "Jump", "Call", "End", "And",
    "Or", "Xor", "Not", "Mod", "ON", "OFF", "TRUE", "FALSE",
];

/// MotionBASIC keywords.
const MB_KEYWORDS: &[&str] = &[
    "IF",
    "THEN",
    "ELSE",
    "ELSEIF",
    "ENDIF",
    "WHILE",
    "WHILETRUE",
    "WEND",
    "DO",
    "LOOP",
    "UNTIL",
    "EXIT",
    "SELECT",
    "CASE",
    "IS",
    "FOR",
    "TO",
    "STEP",
    "NEXT",
    "GOSUB",
    "GOTO",
    "RETURN",
    "END",
    "GEAR",
    "MOVE",
    "PRINT",
    "AT",
    "IN",
    "AFTER",
    "TRUE",
    "FALSE",
    "NOT",
    "AND",
    "OR",
    "XOR",
    "MOD",
    "REM",
    "ON",
    "DIM",
    "DATA",
    "READ",
    "RESTORE",
    "SWAP",
    "LET",
    "CONST",
    "RANDOMIZE",
    "DEFINT",
    "DEFLNG",
    "DEFSNG",
    "DEFDBL",
    "DEFSTR",
    "RND",
    "TIMER",
];

/// The objects of one type, as completion offers them.
#[derive(Debug, Clone)]
struct TypeWords {
    name: &'static str,
    global: bool,
    /// A name may stop at the instance (`DriveInput.4`, `Var.Count`).
    has_default: bool,
    instances: Vec<String>,
    members: Vec<&'static str>,
    global_members: Vec<&'static str>,
}

/// Everything completion knows about the current machine and dialect.
#[derive(Debug, Clone, Default)]
pub struct Vocabulary {
    /// The language of typed lines.
    pub dialect: Dialect,
    types: Vec<TypeWords>,
    bare: Vec<&'static str>,
    variables: Vec<String>,
}

/// What to complete at the cursor.
#[derive(Debug, Clone, PartialEq)]
pub enum Completion {
    /// Replace from byte `start` with one of these: (shown, replacement).
    Words(usize, Vec<(String, String)>),
    /// A file name (`:load`, `:trace`): the editor's file name completer does it.
    Path,
}

impl Vocabulary {
    /// The vocabulary of a machine's registry for `dialect`.
    pub fn new(registry: &Registry, dialect: Dialect) -> Vocabulary {
        let mut types = Vec::new();
        let mut bare = Vec::new();
        let mut variables = Vec::new();
        for t in &registry.types {
            let def = t.def;
            if def.kind == Kind::BasicVar {
                variables.extend(
                    t.display
                        .iter()
                        .filter(|d| !d.starts_with(crate::vm::live::SPARE_VARIABLE))
                        .map(ToString::to_string),
                );
                continue;
            }
            if def.name == BARE_GLOBAL_TYPE {
                bare.extend(def.members.iter().map(|m| m.name));
            }
            let global = def.instances == Instances::Global;
            if t.count == 0 && !global {
                continue;
            }
            if global && matches!(def.kind, Kind::PickPlace) && t.count == 0 {
                continue;
            }
            types.push(TypeWords {
                name: def.name,
                global,
                has_default: def.default_member.is_some(),
                instances: if global {
                    Vec::new()
                } else {
                    t.display.iter().map(ToString::to_string).collect()
                },
                members: def.members.iter().map(|m| m.name).collect(),
                global_members: def.global_members.iter().map(|m| m.name).collect(),
            });
        }
        Vocabulary {
            dialect,
            types,
            bare,
            variables,
        }
    }

    fn find_type(&self, name: &str) -> Option<&TypeWords> {
        self.types
            .iter()
            .find(|t| t.name.eq_ignore_ascii_case(name))
    }

    fn keywords(&self) -> &'static [&'static str] {
        match self.dialect {
            Dialect::PowerTools => PT_KEYWORDS,
            Dialect::MotionBasic => MB_KEYWORDS,
        }
    }

    /// Candidates for a name being typed (`Queue.0.Q`), replacing all of it.
    fn names(&self, word: &str) -> Vec<(String, String)> {
        let segs: Vec<&str> = word.split('.').collect();
        let mut out: Vec<(String, String)> = Vec::new();
        let starts = |cand: &str, partial: &str| {
            cand.len() >= partial.len()
                && cand.is_char_boundary(partial.len())
                && cand[..partial.len()].eq_ignore_ascii_case(partial)
        };
        match segs.as_slice() {
            [partial] => {
                for t in &self.types {
                    if starts(t.name, partial) {
                        out.push((t.name.to_string(), format!("{}.", t.name)));
                    }
                }
                let words = self
                    .bare
                    .iter()
                    .copied()
                    .chain(self.keywords().iter().copied())
                    .chain(FUNCTIONS.iter().map(|f| f.0))
                    .chain(KERNEL_FUNCTIONS.iter().map(|f| f.0));
                for w in words {
                    if starts(w, partial) {
                        out.push((w.to_string(), w.to_string()));
                    }
                }
                for v in &self.variables {
                    if starts(v, partial) {
                        out.push((v.clone(), v.clone()));
                    }
                }
                if self.dialect == Dialect::MotionBasic {
                    for c in CONTROLLERS {
                        let w = format!("{}@", c.name);
                        if starts(&w, partial) {
                            out.push((w.clone(), w));
                        }
                    }
                }
            }
            [ty, partial] => {
                let Some(t) = self.find_type(ty) else {
                    return self.variable_names(word);
                };
                if t.global {
                    for m in &t.members {
                        if starts(m, partial) {
                            out.push((m.to_string(), format!("{}.{m}", t.name)));
                        }
                    }
                } else {
                    for i in &t.instances {
                        if starts(i, partial) {
                            let dot = if t.has_default { "" } else { "." };
                            out.push((i.clone(), format!("{}.{i}{dot}", t.name)));
                        }
                    }
                    for m in &t.global_members {
                        if starts(m, partial) {
                            out.push((m.to_string(), format!("{}.{m}", t.name)));
                        }
                    }
                }
            }
            [ty, inst, partial] => {
                let Some(t) = self.find_type(ty) else {
                    return self.variable_names(word);
                };
                let Some(i) = t.instances.iter().find(|i| i.eq_ignore_ascii_case(inst)) else {
                    return Vec::new();
                };
                for m in &t.members {
                    if starts(m, partial) {
                        out.push((m.to_string(), format!("{}.{i}.{m}", t.name)));
                    }
                }
            }
            _ => return self.variable_names(word),
        }
        out.sort_by_key(|c| c.1.to_ascii_lowercase());
        out.dedup_by(|a, b| a.1 == b.1);
        out
    }

    /// MotionBASIC variables and controller variables may hold dots (`BELT.SPEED`,
    /// `POS.ASEN@`).
    fn variable_names(&self, word: &str) -> Vec<(String, String)> {
        let controllers = CONTROLLERS
            .iter()
            .filter(|_| self.dialect == Dialect::MotionBasic)
            .map(|c| format!("{}@", c.name));
        self.variables
            .iter()
            .cloned()
            .chain(controllers)
            .filter(|v| {
                v.len() >= word.len()
                    && v.is_char_boundary(word.len())
                    && v[..word.len()].eq_ignore_ascii_case(word)
            })
            .map(|v| (v.clone(), v))
            .collect()
    }

    /// What Tab offers at byte `pos` of `line`.
    pub fn complete(&self, line: &str, pos: usize) -> Completion {
        let pos = floor_boundary(line, pos);
        let before = &line[..pos];
        let lead = before.len() - before.trim_start().len();
        if before[lead..].starts_with(PREFIX) {
            let body = &before[lead + 1..];
            return match body.find(char::is_whitespace) {
                None => {
                    let words = COMMANDS
                        .iter()
                        .filter(|(n, _, _)| n.starts_with(&body.to_ascii_lowercase()))
                        .map(|(n, _, _)| (format!(":{n}"), n.to_string()))
                        .collect();
                    Completion::Words(lead + 1, words)
                }
                Some(i) => self.argument(&body[..i], before),
            };
        }
        let start = word_start(before);
        Completion::Words(start, self.names(&before[start..]))
    }

    fn argument(&self, command: &str, before: &str) -> Completion {
        let command = command.to_ascii_lowercase();
        let matches: Vec<&str> = COMMANDS
            .iter()
            .map(|(n, _, _)| *n)
            .filter(|n| n.starts_with(&command))
            .collect();
        let start = word_start(before);
        let word = &before[start..];
        let fixed = |choices: &[&str]| {
            let words = choices
                .iter()
                .filter(|c| c.starts_with(&word.to_ascii_lowercase()))
                .map(|c| (c.to_string(), c.to_string()))
                .collect();
            Completion::Words(start, words)
        };
        match matches.as_slice() {
            ["load"] | ["trace"] => Completion::Path,
            ["watch"] | ["unwatch"] | ["set"] => Completion::Words(start, self.names(word)),
            ["dialect"] => fixed(&["pt", "mb"]),
            ["speed"] => fixed(&["max", "1", "10", "100"]),
            ["help"] => {
                let names: Vec<&str> = COMMANDS.iter().map(|(n, _, _)| *n).collect();
                fixed(&names)
            }
            _ => Completion::Words(start, Vec::new()),
        }
    }

    /// The grey text shown after the cursor: the rest of the only completion, or a command's
    /// arguments.
    pub fn hint(&self, line: &str, pos: usize) -> Option<String> {
        if pos < line.len() || line.trim().is_empty() {
            return None;
        }
        let trimmed = line.trim_start();
        if let Some(body) = trimmed.strip_prefix(PREFIX) {
            if body.contains(char::is_whitespace) {
                return None;
            }
            let lower = body.to_ascii_lowercase();
            let matches: Vec<&(&str, &str, &str)> = COMMANDS
                .iter()
                .filter(|(n, _, _)| n.starts_with(&lower))
                .collect();
            return match matches.as_slice() {
                [(n, args, _)] if *n == lower => (!args.is_empty()).then(|| format!(" {args}")),
                [(n, args, _)] => Some(format!(
                    "{}{}",
                    &n[lower.len()..],
                    if args.is_empty() {
                        String::new()
                    } else {
                        format!(" {args}")
                    }
                )),
                _ => None,
            };
        }
        let Completion::Words(start, words) = self.complete(line, pos) else {
            return None;
        };
        let typed = &line[start..];
        if typed.is_empty() {
            return None;
        }
        match words.as_slice() {
            [(_, one)]
                if one.len() > typed.len() && one[..typed.len()].eq_ignore_ascii_case(typed) =>
            {
                Some(one[typed.len()..].to_string())
            }
            _ => None,
        }
    }
}

/// The start of the name being typed before the cursor.
fn word_start(before: &str) -> usize {
    before
        .char_indices()
        .rev()
        .take_while(|(_, c)| c.is_ascii_alphanumeric() || "_.&~@%!#$[]".contains(*c))
        .last()
        .map_or(before.len(), |(i, _)| i)
}

fn floor_boundary(s: &str, mut pos: usize) -> usize {
    pos = pos.min(s.len());
    while !s.is_char_boundary(pos) {
        pos -= 1;
    }
    pos
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::machine::MachineFile;

    fn vocab(dialect: Dialect) -> Vocabulary {
        let (registry, problems) = crate::config::registry(
            &MachineFile::default(),
            &[0, 1],
            &[crate::registry::BasicVar::Scalar(
                "SPEED&".into(),
                crate::registry::ValueType::Fixed(0),
            )],
        );
        assert!(problems.is_empty());
        Vocabulary::new(&registry, dialect)
    }

    fn replacements(c: Completion) -> Vec<String> {
        match c {
            Completion::Words(_, w) => w.into_iter().map(|(_, r)| r).collect(),
            Completion::Path => vec!["<path>".into()],
        }
    }

    #[test]
    fn members_complete_from_the_registry() {
        let v = vocab(Dialect::PowerTools);
        let got = replacements(v.complete("Queue.0.QueueE", 14));
        assert_eq!(got, vec!["Queue.0.QueueEmpty", "Queue.0.QueueExit"]);
        let got = replacements(v.complete("x = queue.1.queueo", 18));
        assert_eq!(got, vec!["Queue.1.QueueOffset", "Queue.1.QueueOverflow"]);
        assert_eq!(v.hint("Queue.0.QueueOf", 15), Some("fset".to_string()));
        let got = replacements(v.complete("Que", 3));
        assert_eq!(got, vec!["Queue."]);
        let got = replacements(v.complete("DriveInput.", 11));
        assert!(got.contains(&"DriveInput.4".to_string()), "{got:?}");
        let got = replacements(v.complete("Wai", 3));
        assert_eq!(got, vec!["Wait"]);
    }

    #[test]
    fn commands_and_their_arguments_complete() {
        let v = vocab(Dialect::MotionBasic);
        assert_eq!(
            replacements(v.complete(":wa", 3)),
            vec!["watch".to_string()]
        );
        assert_eq!(
            replacements(v.complete(":watch Queue.0.QueueEm", 22)),
            vec!["Queue.0.QueueEmpty".to_string()]
        );
        assert_eq!(
            replacements(v.complete(":dialect p", 10)),
            vec!["pt".to_string()]
        );
        assert_eq!(v.complete(":load pro", 9), Completion::Path);
        assert_eq!(v.hint(":step", 5), Some(" [N | DURATION]".to_string()));
        assert_eq!(replacements(v.complete("SPE", 3)), vec!["SPEED&"]);
        assert!(replacements(v.complete("POS.A", 5)).contains(&"POS.ASEN@".to_string()));
    }

    #[test]
    fn odd_cursor_positions_do_not_panic() {
        let v = vocab(Dialect::PowerTools);
        for line in [
            "",
            "é",
            "Queue.é.",
            ":",
            ": ",
            "....",
            "Queue.0.QueueEmpty.x.y",
        ] {
            for pos in 0..=line.len() + 2 {
                let _ = v.complete(line, pos);
                let _ = v.hint(line, pos);
            }
        }
    }
}
