//! The REPL's `:` commands: what each one is, its help, and parsing a typed command line into
//! a [`Command`] with a clear message for anything malformed.

use crate::config::values::{bool_word, parse_duration};
use crate::syntax::Dialect;
use std::path::PathBuf;

/// The prefix of every command.
pub const PREFIX: char = ':';

/// Every command: name, arguments, one line of help.
pub const COMMANDS: &[(&str, &str, &str)] = &[
    ("help", "[COMMAND]", "this list, or one command's help"),
    (
        "load",
        "FOLDER",
        "load a machine folder (programs, machine.toml, scenario.toml) and start at t = 0",
    ),
    (
        "dialect",
        "[pt|mb]",
        "show or set the language of typed lines (PowerTools or MotionBASIC)",
    ),
    (
        "run",
        "[DURATION]",
        "run the machine in real time (see :speed) until DURATION, :pause or Ctrl-C; the prompt stays",
    ),
    (
        "step",
        "[N | DURATION]",
        "compute N updates (default 1), or DURATION of simulated time (\"0.5s\", \"20ms\"), at full speed",
    ),
    ("pause", "", "stop a :run; the machine stays where it is"),
    (
        "speed",
        "[FACTOR | max]",
        "show or set how fast :run goes: 1 is real time, max as fast as it computes",
    ),
    (
        "set",
        "INPUT ON|OFF",
        "set an input (DriveInput.N, ModuleInput.N, DriveIO.N.In) from the next update on",
    ),
    (
        "watch",
        "[NAME…]",
        "print each change of these members or variables as the machine runs (no NAME: list)",
    ),
    ("unwatch", "[NAME…]", "stop watching these names (no NAME: all)"),
    (
        "tasks",
        "",
        "each task: its program, line, state and what it waits for",
    ),
    (
        "trace",
        "[FILE | off]",
        "write the JSON-lines trace to FILE from now on (off: stop and close it)",
    ),
    (
        "reset",
        "",
        "load the same machine again and start at t = 0",
    ),
    ("quit", "", "leave (also Ctrl-D)"),
];

/// How far `:step` goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepBy {
    /// This many updates.
    Updates(u64),
    /// This much simulated time, ns.
    Time(u64),
}

/// How fast `:run` goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    /// Simulated seconds per wall-clock second.
    Factor(f64),
    /// As fast as the machine computes.
    Max,
}

/// What `:trace` was asked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TraceArg {
    /// Show where the trace goes.
    Show,
    /// Stop writing it.
    Off,
    /// Write it to this file.
    To(PathBuf),
}

/// A parsed command.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `:help [COMMAND]`
    Help(Option<String>),
    /// `:load FOLDER`
    Load(PathBuf),
    /// `:dialect [pt|mb]`
    Dialect(Option<Dialect>),
    /// `:run [DURATION]` (ns)
    Run(Option<u64>),
    /// `:step [N | DURATION]`
    Step(StepBy),
    /// `:pause`
    Pause,
    /// `:speed [FACTOR | max]`
    Speed(Option<Speed>),
    /// `:set INPUT ON|OFF`
    Set {
        /// The input as typed.
        name: String,
        /// The level.
        on: bool,
    },
    /// `:watch [NAME…]`
    Watch(Vec<String>),
    /// `:unwatch [NAME…]`
    Unwatch(Vec<String>),
    /// `:tasks`
    Tasks,
    /// `:trace [FILE | off]`
    Trace(TraceArg),
    /// `:reset`
    Reset,
    /// `:quit`
    Quit,
}

/// Parse a line that starts with [`PREFIX`].
pub fn parse(line: &str) -> Result<Command, String> {
    let body = line.trim().strip_prefix(PREFIX).unwrap_or(line).trim();
    let (word, rest) = match body.find(char::is_whitespace) {
        Some(i) => (&body[..i], body[i..].trim()),
        None => (body, ""),
    };
    let args: Vec<&str> = rest.split_whitespace().collect();
    let name = resolve(word)?;
    let none = |c: Command| {
        if args.is_empty() {
            Ok(c)
        } else {
            Err(format!(":{name} takes no arguments"))
        }
    };
    match name {
        "help" => match args.as_slice() {
            [] => Ok(Command::Help(None)),
            [c] => Ok(Command::Help(Some(
                resolve(c.trim_start_matches(PREFIX))?.to_string(),
            ))),
            _ => Err("usage: :help [COMMAND]".into()),
        },
        "load" if rest.is_empty() => Err("usage: :load FOLDER (a machine folder such as programs/labeling)".into()),
        "load" => Ok(Command::Load(PathBuf::from(rest))),
        "dialect" => match args.as_slice() {
            [] => Ok(Command::Dialect(None)),
            [d] => dialect(d).map(|d| Command::Dialect(Some(d))),
            _ => Err("usage: :dialect [pt|mb]".into()),
        },
        "run" => match args.as_slice() {
            [] => Ok(Command::Run(None)),
            [d] => duration(d).map(|ns| Command::Run(Some(ns))),
            _ => Err("usage: :run [DURATION], e.g. :run 2s".into()),
        },
        "step" => match args.as_slice() {
            [] => Ok(Command::Step(StepBy::Updates(1))),
            [a] => step_by(a).map(Command::Step),
            _ => Err("usage: :step [N | DURATION], e.g. :step 500 or :step 0.5s".into()),
        },
        "pause" => none(Command::Pause),
        "speed" => match args.as_slice() {
            [] => Ok(Command::Speed(None)),
            [s] if s.eq_ignore_ascii_case("max") => Ok(Command::Speed(Some(Speed::Max))),
            [s] => match s.trim_end_matches(['x', 'X']).parse::<f64>() {
                Ok(f) if f.is_finite() && f > 0.0 && f <= 1e6 => {
                    Ok(Command::Speed(Some(Speed::Factor(f))))
                }
                _ => Err(format!(
                    "`{s}` is not a speed: give a factor above 0 (1 is real time, 10 ten times faster) or max"
                )),
            },
            _ => Err("usage: :speed [FACTOR | max]".into()),
        },
        "set" => match args.as_slice() {
            [n, v] => match level(v) {
                Some(on) => Ok(Command::Set {
                    name: n.to_string(),
                    on,
                }),
                None => Err(format!("`{v}` is not a level: use ON or OFF (or 1, 0, TRUE, FALSE)")),
            },
            _ => Err("usage: :set INPUT ON|OFF, e.g. :set DriveInput.4 ON".into()),
        },
        "watch" => Ok(Command::Watch(names(&args))),
        "unwatch" => Ok(Command::Unwatch(names(&args))),
        "tasks" => none(Command::Tasks),
        "trace" => match args.as_slice() {
            [] => Ok(Command::Trace(TraceArg::Show)),
            [a] if a.eq_ignore_ascii_case("off") => Ok(Command::Trace(TraceArg::Off)),
            _ => Ok(Command::Trace(TraceArg::To(PathBuf::from(rest)))),
        },
        "reset" => none(Command::Reset),
        _ => none(Command::Quit),
    }
}

/// The full name of a command written in full or by a unique prefix (`:st` is ambiguous,
/// `:q` is `:quit`).
fn resolve(word: &str) -> Result<&'static str, String> {
    if word.is_empty() {
        return Err("a command name must follow `:` (:help lists them)".into());
    }
    let lower = word.to_ascii_lowercase();
    if let Some((n, _, _)) = COMMANDS.iter().find(|(n, _, _)| *n == lower) {
        return Ok(n);
    }
    let matches: Vec<&str> = COMMANDS
        .iter()
        .map(|(n, _, _)| *n)
        .filter(|n| n.starts_with(&lower))
        .collect();
    match matches.as_slice() {
        [one] => Ok(one),
        [] => {
            let names = COMMANDS.iter().map(|(n, _, _)| *n);
            let hint = crate::diag::nearest(&lower, names)
                .map(|n| format!(" (did you mean :{n}?)"))
                .unwrap_or_default();
            Err(format!("unknown command :{word}{hint}; :help lists them"))
        }
        many => Err(format!(
            ":{word} is ambiguous: {}",
            many.iter()
                .map(|n| format!(":{n}"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

fn dialect(word: &str) -> Result<Dialect, String> {
    match word.to_ascii_lowercase().as_str() {
        "pt" | "powertools" => Ok(Dialect::PowerTools),
        "mb" | "motionbasic" | "basic" => Ok(Dialect::MotionBasic),
        _ => Err(format!(
            "unknown dialect `{word}`: pt (PowerTools) or mb (MotionBASIC)"
        )),
    }
}

fn level(word: &str) -> Option<bool> {
    match word {
        "1" => Some(true),
        "0" => Some(false),
        w => bool_word(w),
    }
}

/// A duration: seconds as a number, or with a unit (`0.5s`, `20ms`, `250us`).
fn duration(word: &str) -> Result<u64, String> {
    parse_duration(word)
}

fn step_by(word: &str) -> Result<StepBy, String> {
    if !word.is_empty() && word.bytes().all(|b| b.is_ascii_digit()) {
        return word
            .parse::<u64>()
            .map(StepBy::Updates)
            .map_err(|_| format!("`{word}` updates is too many"));
    }
    if word.ends_with(|c: char| c.is_ascii_alphabetic() || c == 'µ') {
        return duration(word).map(StepBy::Time);
    }
    Err(format!(
        "`{word}` is neither a number of updates (500) nor a duration with its unit (0.5s, 20ms)"
    ))
}

/// The help text: every command, or one.
pub fn help(command: Option<&str>) -> String {
    let line = |(n, a, h): &(&str, &str, &str)| {
        let head = if a.is_empty() {
            format!(":{n}")
        } else {
            format!(":{n} {a}")
        };
        format!("  {head:<24} {h}")
    };
    match command.and_then(|c| COMMANDS.iter().find(|(n, _, _)| *n == c)) {
        Some(c) => line(c),
        None => {
            let mut out = String::from(
                "Type a statement to run it now on its own task, or an expression to print its value.\n\
                 Blocks (If … Endif, Do While … Loop, IF … ENDIF, WHILE … WEND) go on over several lines.\n\
                 Tab completes objects, members, variables, keywords and commands; Ctrl-C stops the machine.\n\
                 Commands (any unique prefix will do, e.g. :q):\n",
            );
            for c in COMMANDS {
                out.push_str(&line(c));
                out.push('\n');
            }
            out.pop();
            out
        }
    }
}

/// The names among a command's arguments: an array element written with spaces between its
/// subscripts (`G(1, 2)`) is one name, its parts joined without the spaces.
fn names(args: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut open = 0i32;
    for a in args {
        if open > 0 {
            if let Some(last) = out.last_mut() {
                last.push_str(a);
            }
        } else {
            out.push((*a).to_string());
        }
        open += a.matches('(').count() as i32 - a.matches(')').count() as i32;
        open = open.max(0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_parse_with_their_arguments() {
        assert_eq!(parse(":step"), Ok(Command::Step(StepBy::Updates(1))));
        assert_eq!(parse(":step 500"), Ok(Command::Step(StepBy::Updates(500))));
        assert_eq!(
            parse(":step 0.5s"),
            Ok(Command::Step(StepBy::Time(500_000_000)))
        );
        assert_eq!(parse(":run 20ms"), Ok(Command::Run(Some(20_000_000))));
        assert_eq!(parse(":q"), Ok(Command::Quit));
        assert_eq!(
            parse(":set DriveInput.4 on"),
            Ok(Command::Set {
                name: "DriveInput.4".into(),
                on: true
            })
        );
        assert_eq!(
            parse(":dialect mb"),
            Ok(Command::Dialect(Some(Dialect::MotionBasic)))
        );
        assert_eq!(parse(":speed max"), Ok(Command::Speed(Some(Speed::Max))));
        assert_eq!(
            parse(":watch F&(5) G(1, 2) SPEED T(1, 0 ,3)"),
            Ok(Command::Watch(vec![
                "F&(5)".into(),
                "G(1,2)".into(),
                "SPEED".into(),
                "T(1,0,3)".into()
            ]))
        );
    }

    #[test]
    fn mistakes_get_clear_messages() {
        let e = parse(":stpe 5").unwrap_err();
        assert!(e.contains("did you mean :step"), "{e}");
        assert!(parse(":s").unwrap_err().contains("ambiguous"));
        assert!(parse(":step 1.5").unwrap_err().contains("neither"));
        assert!(parse(":step -3").is_err());
        assert!(parse(":run forever").is_err());
        assert!(parse(":set DriveInput.4 maybe")
            .unwrap_err()
            .contains("not a level"));
        assert!(parse(":speed 0").is_err());
        assert!(parse(":pause now").is_err());
        assert!(parse(":").is_err());
        assert!(parse(":load").unwrap_err().contains("usage"));
    }
}
