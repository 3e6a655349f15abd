//! The Modbus map in `machine.toml`: a good map loads into the points and requests it should;
//! every bad entry is an error at the text it is about, and a bad map yields no map at all
//! (so no connection is ever opened for it); the plan runs on an in-memory device.

mod common;

use pacer::io::map::Table;
use pacer::io::memory::{MemoryDevice, PlanBackend};
use pacer::io::plan::plan;
use pacer::load::{load, LoadRequest, Loaded};

/// The labeler's wiring on a 16-in / 8-out coupler with one analog card.
const LABELER_MAP: &str = r#"
[io]
DriveInput = 6
ModuleInput = 4
DriveIO = 4

[variables.Speed]
decimals = 1

[variables.Setpoint]
decimals = 2

[modbus]
host = "127.0.0.1"
port = 5020
unit = 3
timeout = "20ms"

# Drive inputs 1–6 on inputs 0–5, module inputs 1–4 on inputs 6–9.
[[modbus.map]]
kind = "discrete_input"
address = 0
count = 6
member = "DriveInput.1"

[[modbus.map]]
kind = "discrete_input"
address = 6
count = 4
member = "ModuleInput.1"

# The three queue status outputs.
[[modbus.map]]
kind = "coil"
address = 0
count = 3
member = "DriveIO.1.Out"

# An analog speed (0.1 per count) and a signed 32-bit setpoint written back.
[[modbus.map]]
kind = "input_register"
address = 0
member = "Var.Speed"
scale = 0.1

[[modbus.map]]
kind = "holding_register"
address = 10
count = 2
signed = true
member = "Var.Setpoint"
scale = 0.01
safe = -1.5
"#;

struct Project {
    dir: std::path::PathBuf,
}

impl Drop for Project {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn load_machine(tag: &str, machine: &str) -> (Project, Result<Loaded, pacer::diag::Diagnostics>) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-io-map-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("program0.pt"), "End\n").expect("program");
    std::fs::write(dir.join("machine.toml"), machine).expect("machine");
    let result = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    (Project { dir }, result)
}

/// (code, text under the span, message) of every problem.
fn problems(tag: &str, machine: &str) -> Vec<(String, String, String)> {
    let (_p, result) = load_machine(tag, machine);
    common::problem_triples(&result)
}

/// (function code, start, count) of each request of an update, in order.
fn requests(p: &pacer::io::plan::PollPlan) -> Vec<(u8, u16, u16)> {
    p.reads
        .iter()
        .chain(&p.writes)
        .map(|r| (r.function(), r.start, r.count))
        .collect()
}

fn entry(body: &str) -> String {
    format!("[io]\nDriveInput = 6\n\n[variables.Speed]\n\n[modbus]\n[[modbus.map]]\n{body}\n")
}

#[test]
fn the_labeler_map_loads_and_costs_four_requests_per_update() {
    let (_p, result) = load_machine("labeler", LABELER_MAP);
    let loaded = result.unwrap_or_else(|d| panic!("{d:?}"));
    let map = loaded.io_map.expect("a map");
    assert_eq!(map.host.as_deref(), Some("127.0.0.1"));
    assert_eq!((map.port, map.unit, map.timeout_ns), (5020, 3, 20_000_000));
    let names: Vec<(&str, Table, u16)> = map
        .points
        .iter()
        .map(|p| (p.member.as_str(), p.table, p.address))
        .collect();
    assert_eq!(names.len(), 6 + 4 + 3 + 2);
    assert_eq!(names[0], ("DriveInput.1", Table::DiscreteInput, 0));
    assert_eq!(names[9], ("ModuleInput.4", Table::DiscreteInput, 9));
    assert_eq!(names[12], ("DriveIO.3.Out", Table::Coil, 2));
    assert_eq!(names[14], ("Var.Setpoint", Table::HoldingRegister, 10));
    let p = plan(&map);
    // One read of 10 discrete inputs, one of 1 input register, one write of 3 coils, one of 2
    // holding registers.
    let reqs = requests(&p);
    assert_eq!(reqs, vec![(2, 0, 10), (4, 0, 1), (15, 0, 3), (16, 10, 2)]);
    assert_eq!(p.requests_per_update(), 4);
}

#[test]
fn the_labelers_own_machine_file_costs_three_requests_per_update() {
    let loaded = load(&LoadRequest {
        paths: vec![std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/labeling")],
        ..Default::default()
    })
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let map = loaded.io_map.expect("programs/labeling has a [modbus] map");
    assert!(
        !map.enabled,
        "the labeler runs on the simulator unless --io says otherwise"
    );
    let p = plan(&map);
    // 10 discrete inputs in one read; 3 coils in one write; the label position and the 32-bit
    // servo position in one write of 3 holding registers.
    let reqs = requests(&p);
    assert_eq!(reqs, vec![(2, 0, 10), (15, 0, 3), (16, 0, 3)]);
    assert_eq!(p.requests_per_update(), 3);
}

#[test]
fn the_plan_runs_on_a_device_inputs_in_outputs_out_safe_values_on_demand() {
    let (_p, result) = load_machine("device", LABELER_MAP);
    let loaded = result.unwrap_or_else(|d| panic!("{d:?}"));
    let map = loaded.io_map.expect("a map");
    let slot = |name: &str| {
        map.points
            .iter()
            .find(|p| p.member == name)
            .map(|p| p.slot as usize)
            .expect("mapped")
    };
    let (di4, mi2, out2, speed, setpoint) = (
        slot("DriveInput.4"),
        slot("ModuleInput.2"),
        slot("DriveIO.2.Out"),
        slot("Var.Speed"),
        slot("Var.Setpoint"),
    );
    let mut device = MemoryDevice::default();
    device.discrete_inputs[3] = true;
    device.discrete_inputs[7] = true;
    device.input_registers[0] = 1234;
    let mut backend = PlanBackend::new(map, device);
    let mut values = vec![0.0; loaded.image.registry.slot_count()];
    backend.read_inputs(&mut values).expect("read");
    assert_eq!((values[di4], values[mi2]), (1.0, 1.0));
    assert!((values[speed] - 123.4).abs() < 1e-9);
    assert_eq!(backend.device.requests, 2);

    values[out2] = 1.0;
    values[setpoint] = -700.25;
    backend.write_outputs(&values).expect("write");
    assert_eq!(&backend.device.coils[0..3], &[false, true, false]);
    // -70025 as a signed 32-bit value, high word first.
    assert_eq!(&backend.device.holding[10..12], &[0xfffe, 0xee77]);
    assert_eq!(backend.device.requests, 4);
    assert!(backend.saturated.is_empty());

    backend.safe_state().expect("safe");
    assert_eq!(&backend.device.coils[0..3], &[false, false, false]);
    // -1.5 / 0.01 = -150.
    assert_eq!(&backend.device.holding[10..12], &[0xffff, 0xff6a]);
}

#[test]
fn a_machine_without_modbus_has_no_map() {
    let (_p, result) = load_machine("none", "[io]\nDriveInput = 2\n");
    assert!(result.expect("loads").io_map.is_none());
}

#[test]
fn bad_entries_are_errors_at_their_text() {
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "kind",
            "kind = \"coils\"\naddress = 0\nmember = \"DriveInput.1\"",
            "\"coils\"",
            "unknown Modbus table `coils`",
        ),
        (
            "address",
            "kind = \"coil\"\naddress = 70000\nmember = \"DriveIO.1.Out\"",
            "70000",
            "a Modbus address is 0 to 65535 (got 70000)",
        ),
        (
            "member",
            "kind = \"discrete_input\"\naddress = 0\nmember = \"DriveInput.9\"",
            "9",
            "",
        ),
        (
            "type",
            "kind = \"coil\"\naddress = 0\nmember = \"Var.Speed\"",
            "\"Var.Speed\"",
            "Var.Speed is an integer, but a coil holds a bit",
        ),
        (
            "status",
            "kind = \"discrete_input\"\naddress = 0\nmember = \"Queue.0.QueueFull\"",
            "\"Queue.0.QueueFull\"",
            "Queue.0.QueueFull is kept by pacer; a discrete_input cannot write it",
        ),
        (
            "safe-on-input",
            "kind = \"discrete_input\"\naddress = 0\nmember = \"DriveInput.1\"\nsafe = 1",
            "1",
            "a discrete_input is an input: it has no safe value",
        ),
        (
            "scale-on-bit",
            "kind = \"coil\"\naddress = 0\nmember = \"DriveIO.1.Out\"\nscale = 2.0",
            "2.0",
            "scale is for registers, not a coil",
        ),
        (
            "zero-scale",
            "kind = \"input_register\"\naddress = 0\nmember = \"Var.Speed\"\nscale = 0.0",
            "0.0",
            "scale must be a finite number other than 0 (got 0)",
        ),
        (
            "count",
            "kind = \"input_register\"\naddress = 0\ncount = 3\nmember = \"Var.Speed\"",
            "3",
            "count 3 is not valid for a input_register",
        ),
        (
            "bit-count",
            "kind = \"discrete_input\"\naddress = 0\ncount = 3000\nmember = \"DriveInput.1\"",
            "3000",
            "count 3000 is not valid for a discrete_input",
        ),
        (
            "run-past-instances",
            "kind = \"discrete_input\"\naddress = 0\ncount = 7\nmember = \"DriveInput.1\"",
            "\"DriveInput.1\"",
            "point 7 of the run (DriveInput.7): DriveInput.7 does not exist",
        ),
    ];
    for (tag, body, text, message) in cases {
        let found = problems(tag, &entry(body));
        assert_eq!(found.len(), 1, "{tag}: {found:?}");
        let (_, t, m) = &found[0];
        assert_eq!(t, text, "{tag}: span of {m}");
        if !message.is_empty() {
            assert_eq!(m, message, "{tag}");
        }
    }
}

#[test]
fn overlaps_and_double_drivers_are_errors_and_settings_are_checked() {
    let machine = "[io]\nDriveInput = 6\n\n[modbus]\nport = 0\nunit = 300\n\n\
                   [[modbus.map]]\nkind = \"discrete_input\"\naddress = 0\ncount = 4\nmember = \"DriveInput.1\"\n\n\
                   [[modbus.map]]\nkind = \"discrete_input\"\naddress = 3\nmember = \"DriveInput.5\"\n\n\
                   [[modbus.map]]\nkind = \"discrete_input\"\naddress = 9\nmember = \"DriveInput.2\"\n";
    let found = problems("overlap", machine);
    let got: Vec<(&str, &str)> = found
        .iter()
        .map(|(_, t, m)| (t.as_str(), m.as_str()))
        .collect();
    assert_eq!(
        got,
        vec![
            ("0", "port must be 1 to 65535 (got 0)"),
            ("300", "unit must be 0 to 255 (got 300)"),
            (
                "3",
                "discrete_input 3 is already mapped (to DriveInput.4, by entry 1 of the map)"
            ),
            (
                "\"DriveInput.2\"",
                "DriveInput.2 is already driven by discrete_input 1"
            ),
        ]
    );
    assert!(found.iter().all(|(c, _, _)| c == "pacer::machine::modbus"));
}

#[test]
fn the_exchange_period_and_max_age_are_checked_at_their_text() {
    let settings = |body: &str| {
        problems(
            "exchange",
            &format!("[io]\nDriveInput = 6\n\n[modbus]\n{body}\n"),
        )
        .into_iter()
        .map(|(_, t, m)| (t, m))
        .collect::<Vec<_>>()
    };
    let pair = |t: &str, m: &str| vec![(t.to_string(), m.to_string())];
    assert_eq!(
        settings("period = \"0.5ms\""),
        pair("\"0.5ms\"", "the exchange period must be from 1 ms to 1 s")
    );
    assert_eq!(
        settings("max_age = \"120s\""),
        pair("\"120s\"", "max_age must be from 1 ms to 60 s")
    );
    assert_eq!(
        settings("period = \"50ms\"\nmax_age = \"60ms\""),
        pair(
            "\"60ms\"",
            "max_age must be at least two exchange periods (100 ms): an image is this old between two exchanges"
        )
    );
    // Defaults: 5 ms and 100 ms; a long period raises the default age to two periods.
    let (_p, result) = load_machine("exchange-ok", "[modbus]\nperiod = \"80ms\"\n");
    let map = result
        .unwrap_or_else(|d| panic!("{d:?}"))
        .io_map
        .expect("a map");
    assert_eq!((map.period_ns, map.max_age_ns), (80_000_000, 160_000_000));
    let (_p, result) = load_machine("exchange-default", "[modbus]\n");
    let map = result
        .unwrap_or_else(|d| panic!("{d:?}"))
        .io_map
        .expect("a map");
    assert_eq!((map.period_ns, map.max_age_ns), (5_000_000, 100_000_000));
}

#[test]
fn the_docs_example_map_loads_and_costs_what_the_docs_say() {
    let page =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/machine-toml.md"))
            .expect("docs/machine-toml.md");
    let at = page
        .find("Real I/O over Modbus TCP")
        .expect("the Modbus section of docs/machine-toml.md");
    let block = page[at..]
        .split("```toml\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("its example");
    let machine = format!(
        "[io]\nDriveInput = 6\nDriveIO = 4\n\n[variables.Speed]\ndecimals = 1\n\n\
         [variables.Setpoint]\ndecimals = 2\n\n{block}"
    );
    let (_p, result) = load_machine("docs", &machine);
    let map = result
        .unwrap_or_else(|d| panic!("{d:?}"))
        .io_map
        .expect("a map");
    assert_eq!(map.points.len(), 6 + 3 + 1 + 1);
    assert_eq!(plan(&map).requests_per_update(), 4);
    assert!(page.contains("map above costs 4 requests per exchange"));
}
