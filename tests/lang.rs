//! Language goldens, in the style of EndBASIC's tests: every `tests/lang/*.md` file holds cases,
//! each a program (and optionally its machine file, scenario and trace filter) written by hand,
//! followed by what pacer makes of it, generated: the diagnostics of a project it refuses, or the
//! warnings, the disassembly of program 0, the run-time error and the trace of a run.
//!
//! ````text
//! # Test: division by a variable that is zero
//!
//! ## Source            (```pt or ```mb: the dialect; the file is program0.pt / program0.mb)
//! ## Machine           (optional, ```toml: machine.toml; default: empty)
//! ## Scenario          (optional, ```toml: scenario.toml; default: 1 s)
//! ## Trace filter      (optional, one line: the trace kinds to keep, e.g. `motion, program`)
//!
//! ## Diagnostics       (generated: the project was refused)
//! ## Warnings          (generated: it loaded with warnings)
//! ## Disassembly       (generated: program 0's bytecode, as `pacer disasm` prints it)
//! ## Runtime errors    (generated: the error that ended the run)
//! ## Trace             (generated: the trace lines, without `start`)
//! ````
//!
//! A difference fails the test, naming the file and the case. Rewrite the generated sections
//! (and nothing else) with `PACER_BLESS=1 cargo test --test lang`, then read the diff.

mod common;

use pacer::trace::EventKind;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Sections written by hand: blessing keeps them verbatim.
const HAND_WRITTEN: &[&str] = &["Source", "Machine", "Scenario", "Trace filter"];

/// Sections pacer's output fills, in the order blessing writes them.
const GENERATED: &[&str] = &[
    "Diagnostics",
    "Warnings",
    "Disassembly",
    "Runtime errors",
    "Trace",
];

/// The scenario of a case that has none.
const DEFAULT_SCENARIO: &str = "[run]\nduration = 1.0\n";

/// The project folder every case is loaded as (held in memory): the file names of the
/// diagnostics and run-time errors start with it.
const FOLDER: &str = "lang";

// ---------------------------------------------------------------------------------------------
// The Markdown of a case file

/// A case file: text before the first case, then the cases.
#[derive(Debug, Clone, PartialEq)]
struct Doc {
    preamble: String,
    cases: Vec<Case>,
}

/// One `# Test:` case: its heading line, the text before its first section, its sections.
#[derive(Debug, Clone, PartialEq)]
struct Case {
    heading: String,
    intro: String,
    sections: Vec<Section>,
}

/// One `## Name` section: its heading line, and everything up to the next heading.
#[derive(Debug, Clone, PartialEq)]
struct Section {
    heading: String,
    name: String,
    body: String,
}

impl Case {
    /// The title after `# Test:`.
    fn title(&self) -> &str {
        self.heading
            .trim_end()
            .strip_prefix("# Test:")
            .unwrap_or(&self.heading)
            .trim()
    }

    fn section(&self, name: &str) -> Option<&Section> {
        self.sections.iter().find(|s| s.name == name)
    }
}

/// The backtick run opening a fenced code block on `line` (three or more), if any.
fn fence(line: &str) -> Option<usize> {
    let n = line.trim_start().bytes().take_while(|&b| b == b'`').count();
    (n >= 3).then_some(n)
}

/// Split a case file into cases and sections. Headings inside fenced code blocks are text;
/// nothing is lost, so [`render`] gives back the very same text.
fn parse(text: &str) -> Result<Doc, String> {
    let mut doc = Doc {
        preamble: String::new(),
        cases: Vec::new(),
    };
    let mut open: Option<(usize, usize)> = None;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let number = i + 1;
        if let Some((ticks, _)) = open {
            if line.trim().len() >= ticks && line.trim().bytes().all(|b| b == b'`') {
                open = None;
            }
        } else if let Some(ticks) = fence(line) {
            open = Some((ticks, number));
        } else if line.starts_with("# Test:") {
            doc.cases.push(Case {
                heading: line.to_string(),
                intro: String::new(),
                sections: Vec::new(),
            });
            continue;
        } else if let (Some(name), Some(case)) = (line.strip_prefix("## "), doc.cases.last_mut()) {
            let name = name.trim().to_string();
            if !HAND_WRITTEN.contains(&name.as_str()) && !GENERATED.contains(&name.as_str()) {
                return Err(format!(
                    "line {number}: unknown section `## {name}` (known: {}, {})",
                    HAND_WRITTEN.join(", "),
                    GENERATED.join(", ")
                ));
            }
            if case.section(&name).is_some() {
                return Err(format!("line {number}: a second `## {name}` in this case"));
            }
            case.sections.push(Section {
                heading: line.to_string(),
                name,
                body: String::new(),
            });
            continue;
        }
        let tail = match doc.cases.last_mut() {
            None => &mut doc.preamble,
            Some(case) => match case.sections.last_mut() {
                None => &mut case.intro,
                Some(s) => &mut s.body,
            },
        };
        tail.push_str(line);
    }
    match open {
        Some((_, line)) => Err(format!("line {line}: a code block that is never closed")),
        None => Ok(doc),
    }
}

/// The text of a case file, as [`parse`] found it.
fn render(doc: &Doc) -> String {
    let mut out = doc.preamble.clone();
    for case in &doc.cases {
        out.push_str(&render_case(case));
    }
    out
}

fn render_case(case: &Case) -> String {
    let mut out = format!("{}{}", case.heading, case.intro);
    for s in &case.sections {
        out.push_str(&s.heading);
        out.push_str(&s.body);
    }
    out
}

/// The info string and the text of the first fenced code block of a section.
fn code_block(body: &str) -> Option<(String, String)> {
    let mut lines = body.split_inclusive('\n');
    let (ticks, info) = lines
        .by_ref()
        .find_map(|l| fence(l).map(|n| (n, l.trim_start()[n..].trim().to_string())))?;
    let mut text = String::new();
    for line in lines {
        if line.trim().len() >= ticks && line.trim().bytes().all(|b| b == b'`') {
            return Some((info, text));
        }
        text.push_str(line);
    }
    None
}

/// A generated section: its name, the info string of its code block, its text.
#[derive(Debug, Clone, PartialEq)]
struct Output {
    name: &'static str,
    info: &'static str,
    text: String,
}

/// Text ending in a newline (or empty).
fn terminated(text: &str) -> String {
    if text.is_empty() || text.ends_with('\n') {
        text.to_string()
    } else {
        format!("{text}\n")
    }
}

/// A generated section as Markdown: heading, blank line, code block, blank line.
fn render_output(o: &Output) -> String {
    let text = terminated(&o.text);
    // A fence longer than any backtick run in the text.
    let longest = text.lines().filter_map(fence).max().unwrap_or(0);
    let ticks = "`".repeat(longest.max(2) + 1);
    format!("## {}\n\n{ticks}{}\n{text}{ticks}\n\n", o.name, o.info)
}

/// The case with its generated sections replaced by `outputs`: the heading, the intro and the
/// hand-written sections stay exactly as they were; the generated ones follow them.
fn rebless(case: &Case, outputs: &[Output]) -> String {
    let mut out = case.heading.clone();
    out.push_str(&case.intro);
    for s in case
        .sections
        .iter()
        .filter(|s| HAND_WRITTEN.contains(&s.name.as_str()))
    {
        out.push_str(&s.heading);
        out.push_str(&s.body);
    }
    for o in outputs {
        if !out.ends_with("\n\n") {
            out.push('\n');
        }
        out.push_str(&render_output(o));
    }
    out
}

/// A whole file with every case reblessed; it ends with a single newline.
fn rebless_doc(doc: &Doc, outputs: &[Vec<Output>]) -> String {
    let mut out = doc.preamble.clone();
    for (case, o) in doc.cases.iter().zip(outputs) {
        out.push_str(&rebless(case, o));
    }
    let trimmed = out.trim_end_matches('\n').len();
    out.truncate(trimmed);
    out.push('\n');
    out
}

// ---------------------------------------------------------------------------------------------
// Running a case

/// What pacer makes of a case: its generated sections, in [`GENERATED`] order.
fn generate(case: &Case) -> Result<Vec<Output>, String> {
    let source = case.section("Source").ok_or("no `## Source` section")?;
    let (info, program) = code_block(&source.body).ok_or("`## Source` has no code block")?;
    let file = match info.split_whitespace().next() {
        Some("pt") => "program0.pt",
        Some("mb") => "program0.mb",
        _ => {
            return Err(format!(
                "the source block says `{info}`: write ```pt or ```mb"
            ))
        }
    };
    let block = |name: &str| -> Result<Option<String>, String> {
        match case.section(name) {
            None => Ok(None),
            Some(s) => code_block(&s.body)
                .map(|(_, text)| Some(text))
                .ok_or(format!("`## {name}` has no code block")),
        }
    };
    let machine = block("Machine")?.unwrap_or_default();
    let scenario = block("Scenario")?.unwrap_or_else(|| DEFAULT_SCENARIO.to_string());
    let filter: Option<Vec<String>> = case.section("Trace filter").map(|s| {
        s.body
            .split(|c: char| c == ',' || c.is_whitespace())
            .map(|k| k.trim_matches('`'))
            .filter(|k| !k.is_empty())
            .map(str::to_string)
            .collect()
    });
    if let Some(kinds) = &filter {
        let known: Vec<&str> = EventKind::ALL.iter().map(|k| k.as_str()).collect();
        if kinds.is_empty() {
            return Err("`## Trace filter` lists no trace kind".into());
        }
        if let Some(k) = kinds.iter().find(|k| !known.contains(&k.as_str())) {
            return Err(format!(
                "`## Trace filter`: `{k}` is not a trace kind (kinds: {})",
                known.join(", ")
            ));
        }
    }

    let files = [
        (file, program.as_str()),
        ("machine.toml", machine.as_str()),
        ("scenario.toml", scenario.as_str()),
    ];
    let loaded = match common::load_memory(FOLDER, &files) {
        Ok(l) => l,
        Err(d) => {
            return Ok(vec![Output {
                name: "Diagnostics",
                info: "",
                text: d.render_plain(),
            }])
        }
    };
    let mut out = Vec::new();
    if !loaded.warnings.items.is_empty() {
        out.push(Output {
            name: "Warnings",
            info: "",
            text: loaded.warnings.render_plain(),
        });
    }
    let chunk = loaded
        .image
        .programs
        .get(&0)
        .and_then(|&i| loaded.image.chunks.get(i))
        .ok_or("the project has no program 0")?;
    out.push(Output {
        name: "Disassembly",
        info: "",
        text: pacer::compile::disasm::disassemble(chunk, &loaded.layout, &loaded.image.registry),
    });
    let run = common::run_loaded(loaded);
    if let Some(e) = &run.summary.error {
        out.push(Output {
            name: "Runtime errors",
            info: "",
            text: e.render(false),
        });
    }
    let mut trace = String::new();
    for (line, event) in run.text.lines().zip(&run.events) {
        let kind = event["kind"].as_str().unwrap_or("");
        let kept = match &filter {
            Some(kinds) => kinds.iter().any(|k| k == kind),
            None => kind != "start",
        };
        if kept {
            trace.push_str(line);
            trace.push('\n');
        }
    }
    out.push(Output {
        name: "Trace",
        info: "json",
        text: trace,
    });
    Ok(out)
}

/// Every difference between the generated sections in the file and `outputs`.
fn compare(case: &Case, outputs: &[Output]) -> Vec<String> {
    let mut problems = Vec::new();
    for o in outputs {
        match case.section(o.name) {
            None => problems.push(format!(
                "no `## {}` section; pacer gives:\n{}",
                o.name, o.text
            )),
            Some(s) => match code_block(&s.body) {
                None => problems.push(format!("`## {}` has no code block", o.name)),
                Some((_, text)) if text != terminated(&o.text) => problems.push(format!(
                    "`## {}` differs (- in the file, + what pacer gives):\n{}",
                    o.name,
                    diff(&text, &terminated(&o.text))
                )),
                Some(_) => {}
            },
        }
    }
    for s in &case.sections {
        if GENERATED.contains(&s.name.as_str()) && !outputs.iter().any(|o| o.name == s.name) {
            problems.push(format!(
                "`## {}` is in the file, but pacer gives none",
                s.name
            ));
        }
    }
    problems
}

/// A line diff of two texts: `  ` same, `- ` only in `old`, `+ ` only in `new`.
fn diff(old: &str, new: &str) -> String {
    let a: Vec<&str> = old.lines().collect();
    let b: Vec<&str> = new.lines().collect();
    // Longest common subsequence, from the ends.
    let mut lcs = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in (0..a.len()).rev() {
        for j in (0..b.len()).rev() {
            lcs[i][j] = if a[i] == b[j] {
                lcs[i + 1][j + 1] + 1
            } else {
                lcs[i + 1][j].max(lcs[i][j + 1])
            };
        }
    }
    let mut out = String::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        if i < a.len() && j < b.len() && a[i] == b[j] {
            let _ = writeln!(out, "  {}", a[i]);
            i += 1;
            j += 1;
        } else if i < a.len() && (j == b.len() || lcs[i + 1][j] >= lcs[i][j + 1]) {
            let _ = writeln!(out, "- {}", a[i]);
            i += 1;
        } else {
            let _ = writeln!(out, "+ {}", b[j]);
            j += 1;
        }
    }
    out
}

/// The case files, in sorted order.
fn case_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/lang");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a folder entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    files.sort();
    files
}

/// The name a failure gives a file: relative to the crate.
fn shown(path: &Path) -> String {
    path.strip_prefix(env!("CARGO_MANIFEST_DIR"))
        .unwrap_or(path)
        .display()
        .to_string()
}

#[test]
fn language_goldens() {
    let bless = std::env::var_os("PACER_BLESS").is_some();
    let files = case_files();
    assert!(!files.is_empty(), "no tests/lang/*.md");
    let mut failures = Vec::new();
    let mut cases = 0;
    for path in &files {
        let name = shown(path);
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let doc = match parse(&text) {
            Ok(d) => d,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        if doc.cases.is_empty() {
            failures.push(format!("{name}: no `# Test:` case"));
        }
        for (i, case) in doc.cases.iter().enumerate() {
            if doc.cases[..i].iter().any(|c| c.title() == case.title()) {
                failures.push(format!("{name}: two cases are called `{}`", case.title()));
            }
        }
        let mut outputs = Vec::new();
        for case in &doc.cases {
            cases += 1;
            match generate(case) {
                Ok(o) => {
                    if !bless {
                        for p in compare(case, &o) {
                            failures.push(format!("{name}: case `{}`: {p}", case.title()));
                        }
                    }
                    outputs.push(o);
                }
                Err(e) => failures.push(format!("{name}: case `{}`: {e}", case.title())),
            }
        }
        if bless && outputs.len() == doc.cases.len() {
            let new = rebless_doc(&doc, &outputs);
            if new != text {
                std::fs::write(path, new).unwrap_or_else(|e| panic!("{name}: {e}"));
                eprintln!("blessed {name}");
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {cases} language golden case(s) differ:\n\n{}\n\n\
         If the change is intended: PACER_BLESS=1 cargo test --test lang, and read the diff",
        failures.len(),
        failures.join("\n\n")
    );
}

// ---------------------------------------------------------------------------------------------
// The Markdown handling itself

/// A case file with everything the parser must keep: a preamble, an intro, headings and `# `
/// lines inside code blocks, a longer fence, no blank line before a heading, and a file that
/// does not end in a newline.
const SAMPLE: &str = "Some words before the cases.\n\n## Not a section: no case yet\n\n\
# Test: first case\n\nWhy this case exists.\n\n## Source\n\n```pt\nVar.X = 1 ' # Test: not a case\n```\n\
## Machine\n\n```toml\n# a TOML comment\n## Trace\n[variables.X]\n```\n\n\
## Trace filter\n\nmotion, program\n\n## Disassembly\n\n````\n```\ninside\n```\n````\n\n\
## Trace\n\n```json\n{\"kind\":\"end\"}\n```\n\n\
# Test: second case\n## Source\n```mb\nX& = 1\n```\n## Diagnostics\n```\n```";

#[test]
fn the_markdown_parser_round_trips() {
    let doc = parse(SAMPLE).expect("the sample parses");
    assert_eq!(render(&doc), SAMPLE);
    assert_eq!(doc.cases.len(), 2);
    assert_eq!(doc.cases[0].title(), "first case");
    assert_eq!(doc.cases[0].intro, "\nWhy this case exists.\n\n");
    let names: Vec<&str> = doc.cases[0]
        .sections
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        names,
        ["Source", "Machine", "Trace filter", "Disassembly", "Trace"]
    );
    let machine = doc.cases[0].section("Machine").expect("machine");
    assert_eq!(
        code_block(&machine.body),
        Some((
            "toml".into(),
            "# a TOML comment\n## Trace\n[variables.X]\n".into()
        ))
    );
    let disasm = doc.cases[0].section("Disassembly").expect("disassembly");
    assert_eq!(
        code_block(&disasm.body),
        Some((String::new(), "```\ninside\n```\n".into()))
    );
    assert_eq!(
        code_block(&doc.cases[1].section("Diagnostics").expect("d").body),
        Some((String::new(), String::new()))
    );

    // Every real case file too.
    for path in case_files() {
        let text = std::fs::read_to_string(&path).expect("a case file");
        let doc = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", shown(&path)));
        assert_eq!(render(&doc), text, "{}", shown(&path));
    }
}

#[test]
fn blessing_keeps_the_hand_written_parts() {
    let doc = parse(SAMPLE).expect("the sample parses");
    let outputs = vec![
        vec![
            Output {
                name: "Disassembly",
                info: "",
                text: "a\n```\nb".into(),
            },
            Output {
                name: "Trace",
                info: "json",
                text: String::new(),
            },
        ],
        vec![Output {
            name: "Diagnostics",
            info: "",
            text: "an error\n".into(),
        }],
    ];
    let blessed = rebless_doc(&doc, &outputs);
    let again = parse(&blessed).expect("the blessed text parses");
    assert_eq!(again.preamble, doc.preamble);
    for (old, new) in doc.cases.iter().zip(&again.cases) {
        assert_eq!(old.heading, new.heading);
        assert_eq!(old.intro, new.intro);
        for name in HAND_WRITTEN {
            let (a, b) = (old.section(name), new.section(name));
            assert_eq!(a.map(|s| &s.heading), b.map(|s| &s.heading));
            // Only blank lines may be added, before the first generated section.
            assert_eq!(
                a.map(|s| s.body.trim_end()),
                b.map(|s| s.body.trim_end()),
                "{name}"
            );
        }
    }
    // What was blessed compares equal, and blessing it again changes nothing.
    for (case, o) in again.cases.iter().zip(&outputs) {
        assert_eq!(compare(case, o), Vec::<String>::new());
    }
    assert_eq!(rebless_doc(&again, &outputs), blessed);
    // A changed output is reported with the case's section and a diff.
    let mut changed = outputs[1].clone();
    changed[0].text = "another error\n".into();
    let problems = compare(&again.cases[1], &changed);
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(
        problems[0].contains("`## Diagnostics` differs")
            && problems[0].contains("- an error")
            && problems[0].contains("+ another error"),
        "{}",
        problems[0]
    );
}
