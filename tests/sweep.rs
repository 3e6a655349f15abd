//! `pacer sweep` run as a user runs it, on the labeler (programs/labeling): the results do not
//! depend on `--jobs`; four shards merged are byte for byte the unsharded results; merge refuses
//! shards that do not make one sweep; a failing variant's re-run command reproduces its failure
//! in a trace; bad input gets a located error; `pacer run --set` sets what a sweep varies.

mod common;

use common::{pacer, scratch_in, text};
use std::path::{Path, PathBuf};

/// A small sweep of the labeler: 2 speeds × 2 spacings × 2 seeds, 2.5 s each. The spacing 0.65
/// overflows the label queue; 1.0 does not.
const SMALL: &[&str] = &[
    "sweep",
    "programs/labeling",
    "--vary",
    "master.speed=40,120",
    "--vary",
    "products.0.pitch=0.65,1.0",
    "--seeds",
    "2",
    "--for",
    "2.5",
    "-q",
];

fn with(extra: &[&str]) -> Vec<String> {
    SMALL.iter().chain(extra).map(|s| s.to_string()).collect()
}

fn run(args: &[String]) -> std::process::Output {
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    pacer(&refs)
}

fn arg(p: &Path) -> String {
    p.to_str().expect("a UTF-8 temp path").to_string()
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    ["sweep.json", "results.jsonl", "results.csv"]
        .iter()
        .map(|f| {
            (
                f.to_string(),
                std::fs::read(dir.join(f)).unwrap_or_else(|e| panic!("{}/{f}: {e}", dir.display())),
            )
        })
        .collect()
}

#[test]
fn jobs_and_shards_do_not_change_the_results() {
    let d = scratch_in("sweep", "same");
    let one = d.join("jobs1");
    let two = d.join("jobs2");
    let o1 = run(&with(&["--jobs", "1", "--out", &arg(&one)]));
    let o2 = run(&with(&["--jobs", "2", "--out", &arg(&two)]));
    // Variants fail (the queue overflows at 0.65): exit 2.
    assert_eq!(o1.status.code(), Some(2), "{}", text(&o1));
    assert_eq!(o2.status.code(), Some(2), "{}", text(&o2));
    assert_eq!(files(&one), files(&two), "--jobs 1 and --jobs 2 differ");
    assert_eq!(o1.stdout, o2.stdout, "the summaries differ");
    let summary = String::from_utf8_lossy(&o1.stdout).to_string();
    assert!(
        summary
            .contains("8 variants over master.speed × products.0.pitch × run.seed: 4 pass, 4 fail"),
        "{summary}"
    );
    assert!(
        summary.contains("master.speed = 40: products.0.pitch >= 1.0"),
        "{summary}"
    );
    let lines = std::fs::read_to_string(one.join("results.jsonl")).expect("results");
    assert_eq!(lines.lines().count(), 8);
    for (i, l) in lines.lines().enumerate() {
        let v: serde_json::Value = serde_json::from_str(l).expect("a JSON line");
        assert_eq!(v["variant"], i, "in variant order");
    }

    // Four shards, in an order of their own, merged.
    let mut shards = Vec::new();
    for i in [2, 0, 3, 1] {
        let s = d.join(format!("shard{i}"));
        let o = run(&with(&[
            "--shard",
            &format!("{i}/4"),
            "--jobs",
            "1",
            "--out",
            &arg(&s),
        ]));
        assert!(matches!(o.status.code(), Some(0 | 2)), "{}", text(&o));
        shards.push(s);
    }
    let merged = d.join("merged");
    let mut m: Vec<String> = vec!["sweep".into(), "merge".into()];
    m.extend(shards.iter().map(|s| arg(s)));
    m.extend(["--out".to_string(), arg(&merged)]);
    let om = run(&m);
    assert_eq!(om.status.code(), Some(2), "{}", text(&om));
    assert_eq!(
        files(&merged),
        files(&one),
        "merged shards differ from the unsharded run"
    );
    assert_eq!(om.stdout, o1.stdout, "the merged summary differs");

    // A shard missing, a shard twice, a shard of another sweep.
    let o = run(&[
        vec!["sweep".into(), "merge".into()],
        shards[..3].iter().map(|s| arg(s)).collect(),
        vec!["--out".into(), arg(&d.join("x"))],
    ]
    .concat());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("missing shard 1/4"), "{}", text(&o));
    let o = run(&[
        vec!["sweep".into(), "merge".into()],
        shards.iter().chain(&shards[..1]).map(|s| arg(s)).collect(),
        vec!["--out".into(), arg(&d.join("x"))],
    ]
    .concat());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("shard 2/4 twice"), "{}", text(&o));
    let other_spec = d.join("other2");
    let o = run(&[
        "sweep".to_string(),
        "programs/labeling".into(),
        "--vary".into(),
        "master.speed=40,121".into(),
        "--vary".into(),
        "products.0.pitch=0.65,1.0".into(),
        "--seeds".into(),
        "2".into(),
        "--for".into(),
        "2.5".into(),
        "-q".into(),
        "--shard".into(),
        "1/4".into(),
        "--out".into(),
        arg(&other_spec),
    ]);
    assert!(matches!(o.status.code(), Some(0 | 2)), "{}", text(&o));
    let o = run(&[
        vec![
            "sweep".into(),
            "merge".into(),
            arg(&shards[0]),
            arg(&other_spec),
            arg(&shards[2]),
            arg(&shards[3]),
        ],
        vec!["--out".into(), arg(&d.join("x"))],
    ]
    .concat());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("is of another sweep"), "{}", text(&o));
}

#[test]
fn a_failing_variants_command_reproduces_its_failure() {
    let d = scratch_in("sweep", "rerun");
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/labeling");
    let o = pacer(&[
        "sweep",
        &arg(&folder),
        "--vary",
        "products.0.pitch=0.65,1.0",
        "--vary",
        "master.speed=60",
        "--seeds",
        "1",
        "--for",
        "2.5",
        "--jobs",
        "1",
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let summary = String::from_utf8_lossy(&o.stdout).to_string();
    let line = summary
        .lines()
        .find(|l| l.trim_start().starts_with("pacer run "))
        .unwrap_or_else(|| panic!("no re-run command in {summary}"));
    assert!(
        summary.contains("#0 master.speed=60 products.0.pitch=0.65 run.seed=1"),
        "{summary}"
    );
    let words: Vec<&str> = line.split_whitespace().skip(1).collect();
    assert!(words.ends_with(&["--trace", "variant-0.jsonl"]), "{line}");
    let rerun = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(&words)
        .arg("-q")
        .current_dir(&d)
        .output()
        .expect("pacer runs");
    assert_eq!(rerun.status.code(), Some(0), "{}", text(&rerun));
    let trace = std::fs::read_to_string(d.join("variant-0.jsonl")).expect("the variant's trace");
    let overflow = trace
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).expect("JSON"))
        .find(|e| {
            e["kind"] == "change" && e["name"] == "Queue.0.QueueOverflow" && e["value"] == true
        })
        .expect("the overflow the sweep reported is in the trace");
    let at = summary
        .split("first at t = ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|t| t.parse::<f64>().ok())
        .expect("the time of the failure");
    assert!(
        (overflow["t"].as_f64().expect("t") - at).abs() < 1e-9,
        "{overflow} vs {at}"
    );
}

fn sweep_file(name: &str, toml: &str) -> PathBuf {
    let d = scratch_in("sweep", name);
    let p = d.join("sweep.toml");
    std::fs::write(&p, toml).expect("write sweep.toml");
    p
}

#[test]
fn bad_input_gets_a_located_error() {
    // An unknown value name in sweep.toml: located, with the nearest name.
    let f = sweep_file(
        "unknown",
        "[sweep]\nduration = 1.0\n\n[vary]\n\"master.sped\" = [10, 20]\n",
    );
    let o = pacer(&["sweep", "programs/labeling", "--sweep", &arg(&f)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("sweep.toml:5:"), "{t}");
    assert!(
        t.contains("master.sped") && t.contains("unknown key `sped`"),
        "{t}"
    );
    // A file's path that goes nowhere.
    let f = sweep_file("nowhere", "[vary]\n\"products.3.pitch\" = [1.0]\n");
    let o = pacer(&["sweep", "programs/labeling", "--sweep", &arg(&f)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("sweep.toml:2:") && text(&o).contains("`products` has 1 entry"),
        "{}",
        text(&o)
    );
    // An unknown member in a measure; an assertion that compares nothing.
    let f = sweep_file(
        "member",
        "[vary]\nseed = [1]\n[[measure]]\nname = \"q\"\nmax = \"Queue.0.QueueOverflw\"\n",
    );
    let o = pacer(&["sweep", "programs/labeling", "--sweep", &arg(&f)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("sweep.toml:5:")
            && text(&o).contains("did you mean")
            && text(&o).contains("`Queue.0.QueueOverflow`?"),
        "{}",
        text(&o)
    );
    let f = sweep_file(
        "expect",
        "[sweep]\nexpect = [\"labels\"]\n[vary]\nseed = [1]\n",
    );
    let o = pacer(&["sweep", "programs/labeling", "--sweep", &arg(&f)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("sweep.toml:2:") && text(&o).contains("compares nothing"),
        "{}",
        text(&o)
    );
    // On the command line: the argument is named; a usage error.
    for (args, says) in [
        (
            vec!["--vary", "mastr.speed=1,2"],
            "--vary `mastr.speed=1,2`: unknown value name",
        ),
        (
            vec!["--vary", "master.speed=60..10:3"],
            "--vary `master.speed=60..10:3`: the range `60..10:3` is empty",
        ),
        (vec!["--vary", "master.speed=10..60:0"], "asks for 0 values"),
        (
            vec!["--vary", "master.speed=1", "--shard", "4/4", "--out", "x"],
            "--shard `4/4`: shard 4 of 4 does not exist",
        ),
        (
            vec!["--vary", "master.speed=1", "--shard", "1/4"],
            "--shard: give --out DIR",
        ),
        (
            vec!["--vary", "master.speed=1", "--shard", "two/4", "--out", "x"],
            "--shard `two/4`: write I/N",
        ),
        (vec!["--seeds", "0"], "--seeds 0: 0 seeds"),
    ] {
        let mut a = vec!["sweep", "programs/labeling"];
        a.extend(&args);
        let o = pacer(&a);
        assert_eq!(o.status.code(), Some(64), "{a:?}: {}", text(&o));
        assert!(text(&o).contains(says), "{a:?}: {}", text(&o));
    }
    // The shard from the batch engine's variable, when asked.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args([
            "sweep",
            "programs/labeling",
            "--vary",
            "master.speed=1",
            "--shard",
            "env/4",
            "--out",
            "x",
        ])
        .env_remove("JOB_COMPLETION_INDEX")
        .env("SLURM_ARRAY_TASK_ID", "7")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("pacer runs");
    assert_eq!(o.status.code(), Some(64), "{}", text(&o));
    assert!(
        text(&o).contains("shard 7 of 4 does not exist"),
        "{}",
        text(&o)
    );
}

#[test]
fn run_set_changes_the_run_as_the_files_would() {
    let d = scratch_in("sweep", "set");
    let trace = d.join("t.jsonl");
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        "2",
        "-q",
        "--set",
        "Queue.0.QueueOffset=12",
        "--set",
        "master.speed=40",
        "--trace",
        &arg(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let t = std::fs::read_to_string(&trace).expect("trace");
    let first = t
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).expect("JSON"))
        .find(|e| e["kind"] == "queue_in" && e["object"] == "Queue.0")
        .expect("a product queued");
    let (value, exit) = (
        first["value"].as_f64().expect("value"),
        first["exit"].as_f64().expect("exit"),
    );
    assert!((exit - value - 12.0).abs() < 1e-9, "{first}");
    // At 40 units/s the first product (at 30) passes at 0.75 s, not at 1.5 s as at 20.
    assert!(first["t"].as_f64().expect("t") < 0.8, "{first}");
    for (set, says) in [
        ("master.change.9.speed=1", "`master.change` has 5 entries"),
        (
            "Queue.0.QueueFull=1",
            "only settings and data a program may write",
        ),
        ("products.0.pitch=0.3", "products would touch or overlap"),
    ] {
        let o = pacer(&["run", "programs/labeling", "--for", "1", "--set", set]);
        assert_eq!(o.status.code(), Some(1), "{set}: {}", text(&o));
        assert!(text(&o).contains(says), "{set}: {}", text(&o));
    }
    let o = pacer(&["run", "programs/labeling", "--set", "nothing"]);
    assert_eq!(o.status.code(), Some(64), "{}", text(&o));
}

#[test]
fn a_random_sample_is_the_same_whatever_the_jobs() {
    let d = scratch_in("sweep", "sample");
    let args = |jobs: &str, out: &Path| {
        vec![
            "sweep".to_string(),
            "programs/labeling".into(),
            "--sample".into(),
            "6".into(),
            "--sample-seed".into(),
            "9".into(),
            "--for".into(),
            "1.5".into(),
            "-q".into(),
            "--jobs".into(),
            jobs.into(),
            "--out".into(),
            arg(out),
        ]
    };
    let (a, b) = (d.join("a"), d.join("b"));
    let oa = run(&args("1", &a));
    let ob = run(&args("2", &b));
    assert!(matches!(oa.status.code(), Some(0 | 2)), "{}", text(&oa));
    assert_eq!(files(&a), files(&b));
    assert_eq!(oa.stdout, ob.stdout);
    let summary = String::from_utf8_lossy(&oa.stdout).to_string();
    assert!(summary.contains("a random sample: no grid"), "{summary}");
    let meta: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("sweep.json")).expect("sweep.json"))
            .expect("JSON");
    assert_eq!(meta["sampled"], true);
}
