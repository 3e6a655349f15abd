//! pacer on real I/O: the `pacer` binary runs the checkweigher (`programs/checkweigher`) in real
//! time against an independent Modbus TCP server, pymodbus (`tests/peers/modbus_server.py`,
//! installed by `bash tests/run.sh` into `target/pytools`), on 127.0.0.1. The test plays the
//! machine's side: it sets the server's inputs and reads back what pacer wrote. Then the same
//! server is killed, restarted, stalled and asked for addresses it does not have.
//!
//! Waits poll the server until a condition holds; their limits only keep a broken run from
//! hanging the suite, they are not timing assertions.

mod common;

use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Longest wait for anything a run should do within milliseconds.
const PATIENCE: Duration = Duration::from_secs(20);

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Where `tests/run.sh` installs pymodbus (beside the build, not into the system's Python).
fn pytools() -> PathBuf {
    std::env::var_os("PACER_PYTOOLS")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target/pytools"))
}

/// The pymodbus server, driven over its stdin/stdout.
struct Peer {
    child: Child,
    stdin: ChildStdin,
    out: BufReader<ChildStdout>,
    port: u16,
}

impl Peer {
    /// Start a server on `port` (0: any free port) with addresses 0..`size` in each table.
    fn start(port: u16, size: u32) -> Peer {
        let mut child = Command::new("python3")
            .arg(root().join("tests/peers/modbus_server.py"))
            .args(["--port", &port.to_string(), "--size", &size.to_string()])
            .env("PYTHONPATH", pytools())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("python3 runs");
        let stdin = child.stdin.take().expect("piped stdin");
        let mut out = BufReader::new(child.stdout.take().expect("piped stdout"));
        let mut line = String::new();
        out.read_line(&mut line).expect("the server's first line");
        let ready: Value = serde_json::from_str(&line).unwrap_or_else(|_| {
            panic!(
                "the Modbus server did not start (pymodbus is installed by `bash tests/run.sh` into {}): {line:?}",
                pytools().display()
            )
        });
        let port = ready["ready"].as_u64().expect("ready line names the port") as u16;
        Peer {
            child,
            stdin,
            out,
            port,
        }
    }

    fn cmd(&mut self, line: &str) -> Value {
        writeln!(self.stdin, "{line}").expect("the server reads commands");
        self.stdin.flush().expect("flush");
        let mut answer = String::new();
        self.out.read_line(&mut answer).expect("the server answers");
        let v: Value = serde_json::from_str(&answer).expect("a JSON answer");
        assert!(v.get("error").is_none(), "{line}: {v}");
        v
    }

    fn get(&mut self, table: &str, start: u16, count: u16) -> Vec<u64> {
        let v = self.cmd(&format!("get {table} {start} {count}"));
        v[table]
            .as_array()
            .expect("values")
            .iter()
            .map(|x| x.as_u64().expect("a number"))
            .collect()
    }

    fn set(&mut self, table: &str, start: u16, values: &[u64]) {
        let values: Vec<String> = values.iter().map(u64::to_string).collect();
        self.cmd(&format!("set {table} {start} {}", values.join(" ")));
    }

    fn log(&mut self) -> Vec<Value> {
        self.cmd("log")["log"].as_array().expect("log").clone()
    }

    /// Gone at once, as a coupler whose power is cut.
    fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `pacer run FOLDER --io modbus://127.0.0.1:PORT --trace TRACE …`, running.
struct Run {
    child: Child,
    trace: PathBuf,
}

impl Run {
    fn start(folder: &Path, port: u16, trace: PathBuf) -> Run {
        let child = Command::new(env!("CARGO_BIN_EXE_pacer"))
            .arg("run")
            .arg(folder)
            .args(["--io", &format!("modbus://127.0.0.1:{port}")])
            .arg("--trace")
            .arg(&trace)
            // Longer than any test: each one ends its run with Ctrl-C (the checkweigher's
            // scenario would end it after 1 s, which a loaded machine can take to start a
            // Python server).
            .args(["--for", "600"])
            .current_dir(root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("pacer runs");
        Run { child, trace }
    }

    /// Poll until `ok` holds. When it does not within [`PATIENCE`], or pacer has ended, stop
    /// pacer and fail with what it printed and the end of its trace.
    fn wait_until(&mut self, what: &str, mut ok: impl FnMut() -> bool) {
        let start = Instant::now();
        while !ok() {
            let ended = matches!(self.child.try_wait(), Ok(Some(_)));
            if ended || start.elapsed() >= PATIENCE {
                // SAFETY: kill only sends a signal to our own child process.
                unsafe { libc::kill(self.child.id() as libc::pid_t, libc::SIGINT) };
                let _ = self.child.wait();
                let mut out = String::new();
                if let Some(mut o) = self.child.stdout.take() {
                    let _ = std::io::Read::read_to_string(&mut o, &mut out);
                }
                if let Some(mut e) = self.child.stderr.take() {
                    let _ = std::io::Read::read_to_string(&mut e, &mut out);
                }
                let trace = std::fs::read_to_string(&self.trace).unwrap_or_default();
                let tail: Vec<&str> = trace
                    .lines()
                    .filter(|l| !l.contains("\"kind\":\"change\""))
                    .rev()
                    .take(20)
                    .collect();
                panic!(
                    "waited {:?} for {what} (pacer {}):\n{out}\nlast trace events, newest first:\n{}",
                    start.elapsed(),
                    if ended { "had ended" } else { "still running" },
                    tail.join("\n")
                );
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Ctrl-C, then the run's output.
    fn interrupt(self) -> (Output, Vec<Value>) {
        // SAFETY: kill only sends a signal to our own child process.
        unsafe { libc::kill(self.child.id() as libc::pid_t, libc::SIGINT) };
        self.finish()
    }

    fn finish(self) -> (Output, Vec<Value>) {
        let out = self.child.wait_with_output().expect("pacer ends");
        let text = std::fs::read_to_string(&self.trace).expect("the trace was written");
        let events = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
            .collect();
        (out, events)
    }
}

/// The events of `kind`.
fn of_kind<'a>(events: &'a [Value], kind: &str) -> Vec<&'a Value> {
    events.iter().filter(|e| e["kind"] == kind).collect()
}

/// The values a member took, in order.
fn changes(events: &[Value], name: &str) -> Vec<Value> {
    events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == name)
        .map(|e| e["value"].clone())
        .collect()
}

/// A trace is whole: every line parsed (done by `finish`), ticks never go back, and it ends
/// with `end`.
fn assert_whole(events: &[Value]) {
    let ticks: Vec<u64> = events
        .iter()
        .map(|e| e["tick"].as_u64().expect("tick"))
        .collect();
    assert!(ticks.windows(2).all(|w| w[0] <= w[1]), "ticks go back");
    assert_eq!(
        events.first().map(|e| e["kind"].clone()),
        Some("start".into())
    );
    assert_eq!(events.last().map(|e| e["kind"].clone()), Some("end".into()));
}

/// `programs/checkweigher` as it is but for `overrun_limit = 0`, in a scratch folder `name`: the
/// real-time fault is not what these tests are about, and a loaded test machine with a Python
/// server can make ten late updates in a row (`tests/io_fault.rs` tests that fault).
fn checkweigher(name: &str) -> PathBuf {
    variant(
        name,
        &root().join("programs/checkweigher"),
        "timeout = \"50ms\"\n",
        "timeout = \"50ms\"\noverrun_limit = 0\n",
    )
}

/// A copy of the machine folder `from` (its programs and scenario) in a scratch folder named
/// `name`, with `from`'s machine.toml text replaced: `old` → `new` (which must be there).
fn variant(name: &str, from: &Path, old: &str, new: &str) -> PathBuf {
    let folder = common::scratch_in("io-modbus", name);
    for entry in std::fs::read_dir(from).expect("the machine folder") {
        let path = entry.expect("an entry").path();
        if let Some(file) = path.file_name() {
            std::fs::copy(&path, folder.join(file)).expect("copy");
        }
    }
    let machine = std::fs::read_to_string(from.join("machine.toml")).expect("machine.toml");
    assert!(
        machine.contains(old),
        "{old:?} is not in {}",
        from.display()
    );
    std::fs::write(folder.join("machine.toml"), machine.replace(old, new)).expect("write");
    folder
}

/// `pacer run ARGS…` must end with exit `code`, saying `says`.
fn refused(args: &[&str], code: i32, says: &str) {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    let o = common::pacer(&all);
    let printed = common::text(&o);
    assert_eq!(o.status.code(), Some(code), "{printed}");
    assert!(printed.contains(says), "{printed}");
}

/// The checkweigher's safe state as the server sees it, served: both lanes closed, count and
/// deviation registers 0.
fn safe_writes(log: &[Value]) -> bool {
    log.len() >= 2
        && log[..2].iter().all(|e| e.get("exception").is_none())
        && log[0]["op"] == "write"
        && log[0]["table"] == "co"
        && log[0]["start"] == 0
        && log[0]["values"] == serde_json::json!([0, 0])
        && log[1]["op"] == "write"
        && log[1]["table"] == "hr"
        && log[1]["start"] == 0
        && log[1]["values"] == serde_json::json!([0, 0, 0])
}

#[test]
fn a_program_reads_inputs_computes_and_writes_coils_and_registers() {
    let dir = common::scratch_in("io-modbus", "weigh");
    let mut server = Peer::start(0, 100);
    server.set("ir", 0, &[2475]); // 247.5 g on the scale
    let mut run = Run::start(
        &checkweigher("weigh-machine"),
        server.port,
        dir.join("t.jsonl"),
    );

    // Connected: the safe values went out before anything else, then the update's requests.
    let mut log = Vec::new();
    run.wait_until("pacer's first requests", || {
        log.extend(server.log());
        log.len() >= 6
    });
    assert!(safe_writes(&log), "{log:#?}");
    let reads: Vec<&Value> = log[2..].iter().filter(|e| e["op"] == "read").collect();
    assert!(
        reads
            .iter()
            .any(|e| e["table"] == "di" && e["start"] == 0 && e["count"] == 2),
        "{log:#?}"
    );
    assert!(
        reads
            .iter()
            .any(|e| e["table"] == "ir" && e["start"] == 0 && e["count"] == 1),
        "{log:#?}"
    );

    // A product within tolerance (−2.5 g): counted, accept lane, deviation −250 (0.01 g).
    server.set("di", 0, &[1]);
    run.wait_until("the accept lane", || server.get("co", 0, 2) == [1, 0]);
    // The registers go in the same exchange as the coils, one request after them.
    run.wait_until("the count and the deviation", || {
        server.get("hr", 0, 3) == [1, 0xFFFF, 0x10000 - 250]
    });
    server.set("di", 0, &[0]);
    run.wait_until("the lanes to close", || server.get("co", 0, 2) == [0, 0]);

    // 253.0 g: +3.0 g is out of tolerance: the reject lane.
    server.set("ir", 0, &[2530]);
    server.set("di", 0, &[1]);
    run.wait_until("the reject lane", || server.get("co", 0, 2) == [0, 1]);
    // As above: the registers' request follows the coils' (read at once, they may be the
    // last exchange's).
    run.wait_until("the count and the deviation", || {
        server.get("hr", 0, 3) == [2, 0, 300]
    });
    server.set("di", 0, &[0]);
    run.wait_until("the lanes to close", || server.get("co", 0, 2) == [0, 0]);

    // The reset button clears the count.
    server.set("di", 1, &[1]);
    run.wait_until("the count to clear", || server.get("hr", 0, 1) == [0]);
    server.set("di", 1, &[0]);

    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    assert!(
        printed.contains("stopped: interrupted (Ctrl-C)"),
        "{printed}"
    );
    assert!(
        printed.contains("0 fault(s), 0 reconnection(s)"),
        "{printed}"
    );
    assert!(printed.contains("timing: "), "{printed}");
    assert!(printed.contains(": 4 requests per exchange;"), "{printed}");
    assert_whole(&events);
    // The program's first `Var.Count = 0` leaves the value as it was: no change to trace.
    assert_eq!(
        changes(&events, "Var.Count"),
        [1, 2, 0].map(Value::from).to_vec()
    );
    assert_eq!(
        changes(&events, "Var.Deviation"),
        [-2.5, 3.0].map(Value::from).to_vec()
    );
    assert!(of_kind(&events, "io_fault").is_empty());
    // Ended: the outputs were driven safe.
    assert_eq!(server.get("co", 0, 2), [0, 0]);
    assert_eq!(server.get("hr", 1, 2), [0, 0]);
}

#[test]
fn a_killed_server_puts_the_machine_in_its_safe_state_and_its_return_gets_the_safe_values_first() {
    let dir = common::scratch_in("io-modbus", "kill");
    let mut server = Peer::start(0, 100);
    let port = server.port;
    server.set("ir", 0, &[2475]);
    let mut run = Run::start(&checkweigher("kill-machine"), port, dir.join("t.jsonl"));
    server.set("di", 0, &[1]);
    run.wait_until("the accept lane", || server.get("co", 0, 2) == [1, 0]);

    // The coupler loses power with the accept lane open.
    server.kill();
    std::thread::sleep(Duration::from_millis(300));
    // It comes back (fresh: every point 0, as after a power cycle).
    let mut server = Peer::start(port, 100);
    let mut log = Vec::new();
    run.wait_until("pacer to reconnect", || {
        log.extend(server.log());
        log.len() >= 4
    });
    assert!(safe_writes(&log), "the safe values come first: {log:#?}");
    // Then the inputs are read; the program, released, sees the product gone and closes the
    // lane; the count it kept is written again.
    run.wait_until("the count written again", || server.get("hr", 0, 1) == [1]);
    assert_eq!(server.get("co", 0, 2), [0, 0]);

    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    assert!(
        printed.contains("1 fault(s), 1 reconnection(s)"),
        "{printed}"
    );
    assert_whole(&events);
    let faults = of_kind(&events, "io_fault");
    assert_eq!(faults.len(), 1, "{faults:?}");
    let device = format!("modbus://127.0.0.1:{port} unit 1");
    assert_eq!(faults[0]["device"], device.as_str());
    let cause = faults[0]["cause"].as_str().expect("cause");
    assert!(cause.starts_with("not connected ("), "{cause}");
    let reconnects = of_kind(&events, "io_reconnect");
    assert_eq!(reconnects.len(), 1);
    assert_eq!(reconnects[0]["device"], device.as_str());
    assert!(reconnects[0]["attempts"].as_u64().expect("attempts") >= 1);
    // The safe state is in the trace at the fault's update: the accept lane closed.
    let fault_tick = faults[0]["tick"].as_u64().expect("tick");
    assert!(
        events.iter().any(|e| e["kind"] == "change"
            && e["name"] == "DriveIO.1.Out"
            && e["value"] == false
            && e["tick"] == fault_tick),
        "DriveIO.1.Out goes OFF at the fault (tick {fault_tick})"
    );
    // The count survived: the program's data is not a safe value.
    assert_eq!(changes(&events, "Var.Count"), [1].map(Value::from).to_vec());
}

#[test]
fn a_stalled_server_is_a_timeout_fault_and_a_missing_address_an_exception() {
    let dir = common::scratch_in("io-modbus", "stall");
    let mut server = Peer::start(0, 100);
    let mut run = Run::start(
        &checkweigher("stall-machine"),
        server.port,
        dir.join("t.jsonl"),
    );
    run.wait_until("pacer's first requests", || {
        server.cmd("requests")["requests"].as_u64() > Some(4)
    });
    // Longer than the machine's 50 ms timeout.
    server.cmd("stall 0.5");
    std::thread::sleep(Duration::from_millis(400));
    server.cmd("stall 0");
    let mut log = Vec::new();
    run.wait_until("pacer to reconnect", || {
        log.extend(server.log());
        log.windows(2).any(safe_writes)
    });
    // Requests flowing again after the safe writes: the link is back (on a loaded machine the
    // reconnect may come a while after them).
    let before = server.cmd("requests")["requests"].as_u64().unwrap_or(0);
    run.wait_until("requests after the reconnect", || {
        server.cmd("requests")["requests"].as_u64() > Some(before + 8)
    });
    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    let faults = of_kind(&events, "io_fault");
    assert!(!faults.is_empty());
    let cause = faults[0]["cause"].as_str().expect("cause");
    // Whichever of the update's four requests met the stall first.
    assert!(
        cause.ends_with(" timed out after 50 ms")
            && [
                "read discrete_input 0..2",
                "read input_register 0..1",
                "write coil 0..2",
                "write holding_register 0..3"
            ]
            .iter()
            .any(|r| cause.starts_with(r)),
        "{cause}"
    );
    assert!(!of_kind(&events, "io_reconnect").is_empty());

    // A map naming an address the coupler does not have: the first read is answered with
    // exception 2, which is the fault, with the request in it.
    let folder = variant(
        "exception",
        &checkweigher("exception-base"),
        "kind = \"input_register\"\naddress = 0\n",
        "kind = \"input_register\"\naddress = 150\n",
    );
    let mut server = Peer::start(0, 100);
    let mut run = Run::start(&folder, server.port, folder.join("t.jsonl"));
    run.wait_until("the failing read", || {
        server.log().iter().any(|e| e["exception"] == 2)
    });
    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    let faults = of_kind(&events, "io_fault");
    assert!(!faults.is_empty(), "{printed}");
    assert_eq!(
        faults[0]["cause"],
        "read input_register 150..151 answered exception 2 (illegal data address)"
    );
    // The link never completed an update, so the program never ran: it is held while the
    // link is down.
    assert!(changes(&events, "Var.Count").is_empty());
}

/// Wait until the server has seen the safe values written again (a reconnection), then
/// requests flowing after them; returns the log read meanwhile.
fn wait_for_return(run: &mut Run, server: &mut Peer, what: &str) -> Vec<Value> {
    let mut log = Vec::new();
    run.wait_until(what, || {
        log.extend(server.log());
        log.windows(2).any(safe_writes)
    });
    let before = server.cmd("requests")["requests"].as_u64().unwrap_or(0);
    run.wait_until("requests after the return", || {
        server.cmd("requests")["requests"].as_u64() > Some(before + 8)
    });
    log.extend(server.log());
    log
}

/// Issue 22: the checkweigher exactly as `programs/checkweigher` has it (its overrun limit of
/// 10 included) rides through a 2 s stall, a coupler answering "busy" and a coupler that is
/// killed and restarted: each is an I/O fault with its cause in words and the safe state, each
/// return is traced, and no update is late ten times in a row (the exchange with the coupler
/// runs on its own thread, so an update never waits on the network).
#[test]
fn the_checkweigher_as_it_is_rides_through_a_stall_busy_answers_and_a_restart() {
    let dir = common::scratch_in("io-modbus", "ride");
    let mut server = Peer::start(0, 100);
    let port = server.port;
    server.set("ir", 0, &[2475]);
    let mut run = Run::start(
        &root().join("programs/checkweigher"),
        port,
        dir.join("t.jsonl"),
    );
    server.set("di", 0, &[1]);
    run.wait_until("the accept lane", || server.get("co", 0, 2) == [1, 0]);

    // 1. Answers stop for 2 s (the machine's timeout is 50 ms).
    server.cmd("stall 2");
    std::thread::sleep(Duration::from_secs(2));
    server.cmd("stall 0");
    wait_for_return(&mut run, &mut server, "the return after the stall");
    assert_eq!(server.get("co", 0, 2), [0, 0], "the lane stays safe");

    // 2. The coupler answers every request with exception 6 for half a second.
    server.cmd("busy on");
    std::thread::sleep(Duration::from_millis(500));
    server.cmd("busy off");
    wait_for_return(&mut run, &mut server, "the return after the busy answers");

    // 3. Power cut and back.
    server.kill();
    std::thread::sleep(Duration::from_millis(300));
    let mut server = Peer::start(port, 100);
    server.set("ir", 0, &[2475]);
    server.set("di", 0, &[1]);
    wait_for_return(&mut run, &mut server, "the return after the restart");

    // The machine works on: the next product is weighed and counted.
    server.set("di", 0, &[0]);
    std::thread::sleep(Duration::from_millis(50));
    server.set("di", 0, &[1]);
    run.wait_until("the next product counted", || server.get("hr", 0, 1) == [2]);

    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    assert!(!printed.contains("real-time fault"), "{printed}");
    assert!(printed.contains("exchange: "), "{printed}");
    assert_whole(&events);
    let faults = of_kind(&events, "io_fault");
    // A fault met while the inputs were already stale (an exchange starved of processor time
    // on a loaded machine) is said as a warning of the link: its cause is there.
    let causes: Vec<&str> = faults
        .iter()
        .map(|f| f["cause"].as_str().expect("cause"))
        .chain(of_kind(&events, "warning").iter().filter_map(|w| {
            w["message"]
                .as_str()
                .filter(|m| m.starts_with("while the inputs were stale"))
        }))
        .collect();
    assert!(
        causes.iter().any(|c| c.ends_with(" timed out after 50 ms")),
        "{causes:?}"
    );
    assert!(
        causes
            .iter()
            .any(|c| c.ends_with("answered exception 6 (server device busy)")),
        "{causes:?}"
    );
    // The kill: the coupler's socket closes, or (on a loaded machine, the request sent as it
    // died) the request is left unanswered; either is said in words.
    assert!(
        causes.len() >= 3
            && causes.iter().any(|c| {
                c.contains("the coupler closed the connection")
                    || c.starts_with("not connected (") && c.ends_with(": no answer within 50 ms)")
            }),
        "{causes:?}"
    );
    assert!(causes.iter().all(|c| !c.contains("os error")), "{causes:?}");
    let reconnects = of_kind(&events, "io_reconnect");
    assert_eq!(reconnects.len(), faults.len(), "each fault has its return");
    // At each fault's update the lanes are closed in the machine.
    for f in &faults {
        let tick = f["tick"].as_u64().expect("tick");
        for lane in ["DriveIO.1.Out", "DriveIO.2.Out"] {
            let last = events
                .iter()
                .rev()
                .find(|e| {
                    e["kind"] == "change"
                        && e["name"] == lane
                        && e["tick"].as_u64().is_some_and(|t| t <= tick)
                })
                .map(|e| e["value"].clone());
            assert!(
                matches!(last, None | Some(Value::Bool(false))),
                "{lane} at the fault of tick {tick}: {last:?}"
            );
        }
    }
    assert_eq!(
        changes(&events, "Var.Count"),
        [1, 2].map(Value::from).to_vec()
    );
}

#[test]
fn a_refused_connection_is_a_clear_error_before_the_run() {
    // A port nobody listens on: bind one, learn its number, close it.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let out = common::pacer(&[
        "run",
        "programs/checkweigher",
        "--io",
        &format!("modbus://127.0.0.1:{port}"),
        "--for",
        "1",
    ]);
    let printed = common::text(&out);
    assert_eq!(out.status.code(), Some(3), "{printed}");
    assert!(
        printed.contains(&format!(
            "error: modbus://127.0.0.1:{port} unit 1: not connected (connect: "
        )),
        "{printed}"
    );
}

#[test]
fn a_bad_map_never_opens_a_connection() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("listen");
    listener.set_nonblocking(true).expect("non-blocking");
    let port = listener.local_addr().expect("address").port();
    let folder = variant(
        "bad-map",
        &checkweigher("bad-map-base"),
        "kind = \"coil\"",
        "kind = \"coils\"",
    );
    let out = common::pacer(&[
        "run",
        folder.to_str().expect("utf-8 path"),
        "--io",
        &format!("modbus://127.0.0.1:{port}"),
        "--for",
        "1",
    ]);
    let printed = common::text(&out);
    assert_eq!(out.status.code(), Some(1), "{printed}");
    assert!(
        printed.contains("unknown Modbus table `coils`"),
        "{printed}"
    );
    assert!(printed.contains("did you mean `coil`"), "{printed}");
    match listener.accept() {
        Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
        Ok((_, peer)) => panic!("pacer connected from {peer} with a bad map"),
        Err(e) => panic!("accept: {e}"),
    }
}

#[test]
fn io_options_that_cannot_work_are_errors() {
    let labeling = ["programs/labeling", "--for", "1", "--io"];
    // The flag's own syntax is a usage error; a setting the machine cannot take, an input
    // error.
    refused(
        &[&labeling[..], &["modbus://h:0"]].concat(),
        64,
        "`0` is not a TCP port",
    );
    refused(&[&labeling[..], &["serial"]].concat(), 64, "is not an I/O");
    refused(
        &["programs/operator-offset", "--io", "modbus"],
        1,
        "machine.toml has no [modbus] section",
    );
    let closed = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    // A MotionBASIC machine with DSP axes is no longer refused (its axes ramp to rest on an
    // I/O fault): here it goes on to connect, and nothing listens.
    let dsp = variant(
        "dsp",
        &root().join("programs/regist/case1"),
        "[machine]",
        &format!("[modbus]\nhost = \"127.0.0.1\"\nport = {closed}\n\n[machine]"),
    );
    let dsp = dsp.to_str().expect("utf-8 path");
    refused(
        &[dsp, "--io", "modbus", "--for", "1"],
        3,
        &format!("modbus://127.0.0.1:{closed} unit 1: not connected"),
    );
    // `[modbus] enabled = true` makes the coupler the default (here nothing listens: the run
    // stops before it starts); `--io sim` still simulates.
    let enabled = variant(
        "enabled",
        &checkweigher("enabled-base"),
        "port = 5020\n",
        &format!("port = {closed}\nenabled = true\n"),
    );
    let enabled = enabled.to_str().expect("utf-8 path");
    refused(
        &[enabled, "--for", "1"],
        3,
        &format!("modbus://127.0.0.1:{closed} unit 1: not connected"),
    );
    let o = common::pacer(&["run", enabled, "--io", "sim", "--for", "1", "--quiet"]);
    assert!(o.status.success(), "{}", common::text(&o));
    // The simulator is still the default, and `--io sim` names it.
    let o = common::pacer(&["run", "programs/checkweigher", "--io", "sim", "--quiet"]);
    assert!(o.status.success(), "{}", common::text(&o));
}

#[test]
fn the_web_registration_machine_survives_a_killed_server_with_its_dsp_axes_ramped_to_rest() {
    let dir = common::scratch_in("io-modbus", "web-kill");
    let mut server = Peer::start(0, 100);
    let port = server.port;
    // The web's velocity (units/s) and the knife's position in holding registers 0–3, a spare
    // input: the programs do no I/O of their own, the map is how the coupler sees the axes.
    let map = "[modbus]\nhost = \"127.0.0.1\"\ntimeout = \"50ms\"\noverrun_limit = 0\n\n\
        [[modbus.map]]\nkind = \"discrete_input\"\naddress = 0\nmember = \"DriveInput.1\"\n\n\
        [[modbus.map]]\nkind = \"holding_register\"\naddress = 0\ncount = 2\n\
        member = \"Axis.1.Velocity\"\nsigned = true\n\n\
        [[modbus.map]]\nkind = \"holding_register\"\naddress = 2\ncount = 2\n\
        member = \"Axis.2.Position\"\nsigned = true\n\n[machine]";
    let machine = variant(
        "web-kill-machine",
        &root().join("programs/web-registration"),
        "[machine]",
        map,
    );
    let velocity = |server: &mut Peer| {
        let w = server.get("hr", 0, 2);
        (((w[0] << 16) | w[1]) as u32) as i32
    };
    let mut run = Run::start(&machine, port, dir.join("t.jsonl"));
    // MOVE web~ AT 1000 IN 1000: 1000 RPM of 6000 units per revolution.
    run.wait_until("the web at 1000 RPM", || velocity(&mut server) == 100_000);

    server.kill();
    std::thread::sleep(Duration::from_millis(300));
    let mut server = Peer::start(port, 100);
    // Back: the safe values first (registers 0), then the axes as they are — the web ramping
    // down at 10 revolutions/s² (1.67 s from 1000 RPM) and then at rest, the knife with it.
    // The safe values are themselves 0: wait for a write after them (the axes as they are).
    let mut writes = 0;
    run.wait_until("the web at rest", || {
        writes += server
            .log()
            .iter()
            .filter(|l| l["op"] == "write" && l["table"] == "hr")
            .count();
        writes >= 2 && velocity(&mut server) == 0
    });
    let knife = server.get("hr", 2, 2);
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(server.get("hr", 2, 2), knife, "the knife stands still");
    assert_eq!(velocity(&mut server), 0);

    let (out, events) = run.interrupt();
    let printed = common::text(&out);
    assert!(out.status.success(), "{printed}");
    assert!(
        printed.contains("1 fault(s), 1 reconnection(s)"),
        "{printed}"
    );
    assert_whole(&events);
    assert_eq!(of_kind(&events, "io_fault").len(), 1);
    assert_eq!(of_kind(&events, "io_reconnect").len(), 1);
    assert!(
        of_kind(&events, "error").is_empty(),
        "{:?}",
        of_kind(&events, "error")
    );
}
