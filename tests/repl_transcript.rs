//! `pacer repl` as a machine builder uses it: the real binary driven through a pseudo-terminal
//! (rexpect), keys and all — Tab completion, a multi-line block, a syntax error and recovery,
//! Ctrl-C while the machine runs and while a typed line waits, and the history it leaves.
//!
//! Every step waits for the REPL's own answer before the next key is sent; nothing depends
//! on how fast this machine is.

use rexpect::reader::Options;
use rexpect::session::PtySession;
use std::path::PathBuf;
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-repl-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// `pacer repl ARGS` in a pseudo-terminal, with its data directory (history) in `data`.
fn spawn(args: &[&str], data: &std::path::Path) -> PtySession {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pacer"));
    c.arg("repl")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("XDG_DATA_HOME", data)
        .env("TERM", "xterm")
        .env("NO_COLOR", "1");
    // No timeout: each expectation is a line the REPL prints; a REPL that ended instead is an
    // end-of-file error, not a wait.
    rexpect::spawn_with_options(
        c,
        Options::new()
            .timeout_ms(None)
            .strip_ansi_escape_codes(true),
    )
    .expect("pacer repl starts in a pty")
}

/// Expect `needle` (what the REPL printed, or the prompt drawn after it); on failure say what
/// came instead.
fn expect(p: &mut PtySession, needle: &str) -> String {
    match p.exp_string(needle) {
        Ok(before) => before,
        Err(e) => panic!("expected {needle:?}: {e}"),
    }
}

/// The number printed on a line of its own after the text sent.
fn value_line(p: &mut PtySession) -> String {
    let (_, line) = p
        .exp_regex(r"[\r\n]-?[0-9][0-9.]*\r\n")
        .expect("a value on a line of its own");
    line.trim().to_string()
}

#[test]
fn a_commissioning_session_on_the_labeler() {
    let data = scratch("labeler");
    let mut p = spawn(&["programs/labeling"], &data);
    expect(&mut p, "pacer repl: labeling");
    expect(&mut p, "pt> ");

    // Step the line forward.
    p.send_line(":step 500").expect("type");
    expect(&mut p, "t=0.499 s (500 updates, 500 computed now)");
    expect(&mut p, "pt> ");

    // Watch the label queue.
    p.send_line(":watch Queue.0.QueueEmpty").expect("type");
    expect(&mut p, "watching Queue.0.QueueEmpty = ON");
    expect(&mut p, "pt> ");

    // Tab completes the member name (QueueOf… is only QueueOffset): the nudge below would be
    // an unknown member without it.
    p.send("Queue.0.QueueOf\t").expect("type");
    p.send_line(" = 12.5").expect("type");
    expect(&mut p, "pt> ");
    p.send_line("Queue.0.QueueOffset * 2").expect("type");
    assert_eq!(value_line(&mut p), "25");
    expect(&mut p, "pt> ");

    // Step on: the first product reaches the sensor and the watch reports the queue filling.
    p.send_line(":step 1.5s").expect("type");
    let seen = expect(&mut p, "t=1.999 s (2000 updates, 1500 computed now)");
    assert!(
        seen.contains("Queue.0.QueueEmpty = OFF"),
        "the watch reports the queue filling:\n{seen}"
    );
    expect(&mut p, "pt> ");

    // A block over several lines: the parser keeps it open until Endif.
    p.send_line("If Queue.0.QueueEmpty Then").expect("type");
    p.send_line("Bit.0 = ON").expect("type");
    p.send_line("Else").expect("type");
    p.send_line("Bit.1 = ON").expect("type");
    p.send_line("Endif").expect("type");
    expect(&mut p, "pt> ");
    p.send_line("Bit.1 And Not Bit.0").expect("type");
    expect(&mut p, "\r\nON\r\n");
    expect(&mut p, "pt> ");

    // A syntax error points into the typed line; the REPL goes on.
    p.send_line("Queue.0.QueueOffset = = 3").expect("type");
    expect(&mut p, "pacer::syntax");
    expect(&mut p, "Queue.0.QueueOffset = = 3");
    expect(&mut p, "not expected here");
    expect(&mut p, "pt> ");
    p.send_line("Queue.0.QueueOffset").expect("type");
    assert_eq!(value_line(&mut p), "12.5", "the bad line changed nothing");
    expect(&mut p, "pt> ");

    // :run goes on until Ctrl-C; the machine stays where it stopped.
    p.send_line(":speed 10").expect("type");
    expect(&mut p, ":run goes at 10x real time");
    expect(&mut p, "pt> ");
    p.send_line(":run").expect("type");
    expect(&mut p, "running from t=1.999 s at 10x real time");
    expect(&mut p, "pt> ");
    p.send_control('c').expect("Ctrl-C");
    let (_, stopped) = p
        .exp_regex(r"interrupted at t=[0-9.]+ s \([0-9]+ updates\)")
        .expect("Ctrl-C stops the run");
    expect(&mut p, "pt> ");
    p.send_line(":step 1").expect("type");
    let after = expect(&mut p, " computed now)");
    let updates: u64 = stopped
        .split('(')
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .expect("an update count");
    assert!(
        after.contains(&format!("({} updates, 1", updates + 1)),
        ":step goes on from where Ctrl-C stopped ({updates} updates): {after}"
    );
    expect(&mut p, "pt> ");

    // A typed Wait For blocks while the machine runs; Ctrl-C cancels it and stops the run.
    p.send_line(":run").expect("type");
    expect(&mut p, "running from t=");
    expect(&mut p, "pt> ");
    p.send_line("Wait For Bit.7").expect("type");
    expect(&mut p, "waiting from t=");
    p.send_control('c').expect("Ctrl-C");
    expect(&mut p, "the typed line was cancelled");
    expect(&mut p, "pt> ");
    p.send_line(":tasks").expect("type");
    expect(&mut p, "REPL    free");
    expect(&mut p, "pt> ");

    p.send_line(":quit").expect("type");
    p.exp_eof().expect("the REPL ends");
    let status = format!("{:?}", p.process().wait().expect("exit status"));
    assert!(
        status.starts_with("Exited(") && status.ends_with(", 0)"),
        "{status}"
    );

    // The history is kept in the data directory.
    let history = std::fs::read_to_string(data.join("pacer").join("history")).expect("history");
    assert!(history.contains(":watch Queue.0.QueueEmpty"), "{history}");
    assert!(history.contains("Queue.0.QueueOffset = 12.5"), "{history}");
}

#[test]
fn motionbasic_on_the_empty_machine() {
    let data = scratch("empty");
    let mut p = spawn(&["--dialect", "mb"], &data);
    expect(&mut p, "the empty default machine");
    expect(&mut p, "mb> ");
    p.send_line("COUNT& = 0").expect("type");
    expect(&mut p, "mb> ");
    // A WHILE block, closed by WEND.
    p.send_line("WHILE COUNT& < 7").expect("type");
    p.send_line("COUNT& = COUNT& + 2").expect("type");
    p.send_line("WEND").expect("type");
    expect(&mut p, "mb> ");
    p.send_line("COUNT& * 10").expect("type");
    assert_eq!(value_line(&mut p), "80");
    expect(&mut p, "mb> ");
    // Tab completes a variable the session declared.
    p.send("COU\t").expect("type");
    p.send_line("").expect("enter");
    assert_eq!(value_line(&mut p), "8");
    expect(&mut p, "mb> ");
    p.send_control('d').expect("Ctrl-D");
    p.exp_eof().expect("Ctrl-D leaves");
}
