//! MotionBASIC `PRINT` as a Microsoft BASIC user expects it (spec/basic-language.md, "PRINT";
//! the GW-BASIC User's Guide, PRINT: "1E-7 is output as .0000001 and 1E-8 is output as
//! 1E-08"): numbers with a sign position and a trailing space, `;` and `,` (zones of 14
//! columns), a trailing separator that keeps the line open; each line a `print` trace event
//! with its task and program, on standard output in `pacer run`, and shown by the REPL.

mod common;

use common::{load_error, load_memory, run_loaded, Run};
use pacer::repl::session::{Ran, Session};

/// `program` as `program0.mb` on the default machine, run to its end.
fn run_mb(name: &str, program: &str) -> Run {
    match load_memory(
        name,
        &[
            ("program0.mb", program),
            ("scenario.toml", "[run]\nduration = 0.05\n"),
        ],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// The `print` events' texts.
fn printed(r: &Run) -> Vec<String> {
    r.events
        .iter()
        .filter(|e| e["kind"] == "print")
        .map(|e| e["text"].as_str().unwrap_or_default().to_string())
        .collect()
}

#[test]
fn numbers_print_as_microsoft_basic_prints_them() {
    let r = run_mb(
        "numbers",
        "PRINT 5; -2.5\nPRINT .5\nPRINT -0.25\nPRINT 2.50\nPRINT 1/3\nX# = 1/3\nPRINT X#\n\
         PRINT 1234567\nPRINT 1E7\nX! = 12345678\nPRINT X!\nPRINT 1E-7\nPRINT 1E-8\nN& = 2147483647\n\
         PRINT N&\nPRINT N& - 1\nPRINT 3 > 2\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(
        printed(&r),
        [
            " 5 -2.5 ",
            " .5 ",
            "-.25 ",
            " 2.5 ",
            " .3333333 ",
            " .3333333333333333 ",
            " 1234567 ",
            " 1E+07 ",
            " 1.234568E+07 ",
            " .0000001 ",
            " 1E-08 ",
            " 2147483647 ",
            " 2147483646 ",
            "-1 ",
        ]
    );
}

#[test]
fn separators_zones_and_a_trailing_separator() {
    let r = run_mb(
        "zones",
        "CUTS& = 12\nPRINT \"cuts:\"; CUTS&\nPRINT \"a\", \"b\", 1\nPRINT\nPRINT \"x\";\n\
         PRINT \"y\",\nPRINT \"z\"\n? \"short\"\nPRINT \"end\";\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(
        printed(&r),
        [
            "cuts: 12 ".to_string(),
            format!("a{}b{} 1 ", " ".repeat(13), " ".repeat(13)),
            String::new(),
            format!("xy{}z", " ".repeat(12)),
            "short".to_string(),
            // A line left open is output when the program ends.
            "end".to_string(),
        ]
    );
    let first = r
        .events
        .iter()
        .find(|e| e["kind"] == "print")
        .expect("a print event");
    assert_eq!(first["task"], 0);
    assert_eq!(first["program"], 0);
}

/// GW-BASIC User's Guide, PRINT: items written side by side print as if `;` were between
/// them; a sign or a parenthesis after an item still continues its expression.
#[test]
fn items_side_by_side_print_as_if_a_semicolon_were_between_them() {
    let r = run_mb(
        "side-by-side",
        "C% = 12\nA$ = \"ab\"\nDIM V(3)\nV(1) = 7\nPRINT \"COUNT=\" C%\nPRINT A$ \"cd\" C% A$\n\
         PRINT V(1) \"x\"\nPRINT C% -2\nPRINT LEFT$(A$, 1) 5\nIF C% > 0 THEN PRINT \"p\" C% ELSE PRINT \"n\"\n\
         PRINT \"a\" : PRINT \"b\" C%\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(
        printed(&r),
        [
            "COUNT= 12 ",
            "abcd 12 ab",
            " 7 x",
            " 10 ",
            "a 5 ",
            "p 12 ",
            "a",
            "b 12 ",
        ]
    );
}

#[test]
fn an_axis_set_cannot_be_printed_and_powertools_has_no_print() {
    let d = load_error("axis", &[("program0.mb", "PRINT {1}\n")]);
    assert!(d.render_plain().contains("an axis set cannot be printed"));
    let d = load_error("pt", &[("program0.pt", "PRINT 5\n")]);
    assert!(!d.render_plain().is_empty());
}

#[test]
fn pacer_run_writes_printed_lines_to_standard_output_in_order() {
    let dir = common::scratch_in("print", "run");
    std::fs::write(
        dir.join("program0.mb"),
        "FOR I& = 1 TO 3\nPRINT \"line\"; I&\nNEXT I&\n",
    )
    .expect("write");
    let program = dir.join("program0.mb");
    let o = common::pacer(&["run", program.to_str().expect("utf-8 path")]);
    assert!(o.status.success(), "{}", common::text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    // Only the programs' output: the run's summary goes to standard error.
    assert_eq!(out, "line 1 \nline 2 \nline 3 \n");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("s simulated in"), "stderr: {err}");
}

#[test]
fn the_repl_shows_what_a_typed_print_prints() {
    let (mut s, _) =
        Session::open(None, Some(pacer::syntax::Dialect::MotionBasic), false).expect("opens");
    let mut out: Vec<String> = Vec::new();
    assert_eq!(s.enter("PRINT 2 + 3; \"mm\"", &mut out), Ran::Done);
    assert_eq!(out, [" 5 mm"]);
}

#[test]
fn disasm_shows_the_print_instructions() {
    let dir = common::scratch_in("print", "disasm");
    std::fs::write(dir.join("program0.mb"), "PRINT \"n =\"; 5,\n").expect("write");
    let program = dir.join("program0.mb");
    let o = common::pacer(&["disasm", program.to_str().expect("utf-8 path")]);
    assert!(o.status.success(), "{}", common::text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("print     ") && out.contains("as Text"),
        "{out}"
    );
    assert!(out.contains("as Integer"), "{out}");
    assert!(out.contains("print.zone"), "{out}");
    // A trailing `,` keeps the line open: no print.line.
    assert!(!out.contains("print.line"), "{out}");
}
