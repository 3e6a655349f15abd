//! The harness the fuzz targets share (`tests/fuzz_parser.rs` for PowerTools,
//! `tests/fuzz_motionbasic.rs` for MotionBASIC). Each includes it with
//! `#[path = "common/fuzz.rs"] mod fuzz;`, so no other test binary compiles it.
//!
//! A target describes itself with a [`Target`]: its name, the extension of the inputs it saves,
//! the salt of its generator seeds, its machines, its `exercise` function, the seeds that must
//! compile, its fixed edge inputs and its three generators. [`run`] does the rest:
//!   * the seeds that must compile go through, on both machines;
//!   * the fixed edge inputs (those of any dialect here, then the target's) run once, each
//!     within 20 s;
//!   * the generators `grammar`, `mutation` and `raw` share the cases 40/35/25, each in its own
//!     thread, with a ChaCha seed of its own;
//!   * a watchdog reports an input that makes no progress as a hang, and prints progress;
//!   * a report line for each generator, and the total.
//!
//! Below the harness are the generator pieces that do not depend on the dialect: picking from
//! pools, laying out and damaging generated programs, the blocks both dialects write, the
//! mutations of seed programs, and the raw inputs (random characters and bytes, token soup,
//! long lines, many openers). Each target brings its own vocabulary to them.
//!
//! Files are saved to `CARGO_TARGET_TMPDIR/<target name>/`: `<generator>.crash.<ext>` (the
//! minimal input that panicked), `<generator>.hang.<ext>`, `<generator>.slowest.<ext>`.
//!
//! Environment:
//!   PACER_FUZZ_CASES   total generated inputs, split 40/35/25 (default 2000)
//!   PACER_FUZZ_SEED    u64 mixed into the fixed ChaCha seed (default 0: the standard run)
//!   PACER_FUZZ_ONLY    run one generator: grammar, mutation or raw
//!   PACER_FUZZ_DUMP    a directory: each worker writes the input it is about to run to
//!                      `<dir>/<generator>.current.<ext>` (to catch the input of a stack overflow)
//!   PACER_FUZZ_HANG_SECS  seconds without progress that count as a hang (default 120)
//!   PACER_FUZZ_STACK_KIB  stack of each worker thread (default 2048, as libtest's threads)

use pacer::diag::{Diagnostics, Level, Problem, SourceFile};
use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::test_runner::{Config, RngAlgorithm, TestError, TestRng, TestRunner};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

/// Builds a generator's strategy (inside its worker: strategies are not `Send`).
pub type MakeStrategy = fn() -> BoxedStrategy<String>;

/// Runs one input through a target's front end, counting in `Stats` how far it got. Panics
/// propagate (that is the failure we look for).
pub type Exercise<M> = fn(&str, &M, &Stats);

/// What a fuzz target brings to the shared harness. `M` is its pair of machines.
pub struct Target<M> {
    /// The test binary: prefixes the report lines and names `CARGO_TARGET_TMPDIR/<name>`.
    pub name: &'static str,
    /// The extension of the inputs saved (crash, hang, slowest, current).
    pub ext: &'static str,
    /// Mixed into every generator's ChaCha seed (each target keeps its own, so a run repeats
    /// the inputs of the runs before).
    pub salt: u64,
    /// Builds the two machines every input is run against.
    pub machines: fn() -> M,
    pub exercise: Exercise<M>,
    /// Programs that must compile on both machines (the harness reaches the compiler).
    pub complete_seeds: fn() -> Vec<String>,
    /// Inputs run once, before the generators, after those of [`edge_inputs`]; each must
    /// take less than 20 s.
    pub edge_inputs: fn() -> Vec<String>,
    pub grammar: MakeStrategy,
    pub mutation: MakeStrategy,
    pub raw: MakeStrategy,
    /// Whether the report counts programs the compiler refused after a clean check
    /// (`Stats::compile_refused`; a target that panics on them instead leaves it out).
    pub report_refused: bool,
}

impl<M> Clone for Target<M> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<M> Copy for Target<M> {}

#[derive(Default)]
pub struct Stats {
    pub executed: AtomicU64,
    pub parse_clean: AtomicU64,
    pub check_clean: AtomicU64,
    pub compiled: AtomicU64,
    /// Checked clean but the compiler still reported problems.
    pub compile_refused: AtomicU64,
    pub slowest_micros: AtomicU64,
    pub slowest_input: Mutex<String>,
    /// The input being run now (for the hang report).
    pub current: Mutex<String>,
    pub finished: AtomicBool,
}

pub fn has_errors(problems: &[Problem]) -> bool {
    problems.iter().any(|p| p.level == Level::Error)
}

/// Render a few problems as the CLI does (spans are resolved against the source there).
pub fn render(file_name: &str, src: &str, problems: &[Problem]) {
    if problems.is_empty() {
        return;
    }
    let mut d = Diagnostics::new();
    let file = SourceFile::new(file_name, src);
    d.extend_file(&file, problems.iter().take(3).cloned().collect());
    std::hint::black_box(d.render_plain());
}

/// Largest char boundary at or below `i`.
fn boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn env_u64(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(s) => s
            .trim()
            .replace('_', "")
            .parse()
            .unwrap_or_else(|_| panic!("{name}={s:?} is not a number")),
        Err(_) => default,
    }
}

/// A 32-byte ChaCha seed from the run seed, the generator number and the target's salt
/// (splitmix64).
fn seed_bytes(run_seed: u64, generator: u64, salt: u64) -> [u8; 32] {
    let mut x = run_seed ^ generator.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt;
    let mut out = [0u8; 32];
    for chunk in out.chunks_mut(8) {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        chunk.copy_from_slice(&z.to_le_bytes());
    }
    out
}

/// What a panic in a worker thread said, with its backtrace.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);
static HOOK: Once = Once::new();

fn install_panic_hook() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let in_worker = std::thread::current()
                .name()
                .is_some_and(|n| n.starts_with("fuzz-"));
            if in_worker {
                // Quiet: shrinking re-runs failing inputs many times. Keep the last report.
                let bt = std::backtrace::Backtrace::force_capture();
                *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) =
                    Some(format!("{info}\nbacktrace:\n{bt}"));
            } else {
                default(info);
            }
        }));
    });
}

fn out_dir(target_name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(target_name);
    let _ = std::fs::create_dir_all(&d);
    d
}

fn shown(s: &str) -> String {
    const MAX: usize = 3000;
    if s.len() <= MAX {
        format!("{s:?}")
    } else {
        let cut = boundary(s, MAX);
        format!("{:?}… ({} bytes in all)", &s[..cut], s.len())
    }
}

struct Worker {
    name: &'static str,
    cases: u32,
    stats: Arc<Stats>,
    handle: std::thread::JoinHandle<Result<(), String>>,
}

fn spawn_worker<M: Send + Sync + 'static>(
    target: Target<M>,
    name: &'static str,
    index: u64,
    cases: u32,
    make_strategy: MakeStrategy,
    machines: Arc<M>,
) -> Worker {
    let stats = Arc::new(Stats::default());
    let st = Arc::clone(&stats);
    let stack = env_u64("PACER_FUZZ_STACK_KIB", 2048) as usize * 1024;
    let run_seed = env_u64("PACER_FUZZ_SEED", 0);
    let dump = std::env::var_os("PACER_FUZZ_DUMP").map(std::path::PathBuf::from);
    let Target { ext, exercise, .. } = target;
    let handle = std::thread::Builder::new()
        .name(format!("fuzz-{name}"))
        .stack_size(stack)
        .spawn(move || {
            let strategy = make_strategy();
            let config = Config {
                cases,
                failure_persistence: None,
                source_file: None,
                fork: false,
                timeout: 0,
                verbose: 0,
                max_shrink_iters: 4000,
                max_shrink_time: 120_000,
                max_local_rejects: 1_000_000,
                max_global_rejects: 1_000_000,
                ..Config::default()
            };
            let seed = seed_bytes(run_seed, index, target.salt);
            let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed);
            let mut runner = TestRunner::new_with_rng(config, rng);
            let dump_file = dump.map(|d| {
                let _ = std::fs::create_dir_all(&d);
                d.join(format!("{name}.current.{ext}"))
            });
            let result = runner.run(&strategy, |input| {
                st.executed.fetch_add(1, Ordering::Relaxed);
                {
                    let mut cur = st.current.lock().unwrap_or_else(|e| e.into_inner());
                    cur.clear();
                    cur.push_str(&input);
                }
                if let Some(f) = &dump_file {
                    std::fs::write(f, &input).expect("write PACER_FUZZ_DUMP file");
                }
                let t0 = Instant::now();
                exercise(&input, &machines, &st);
                let us = t0.elapsed().as_micros() as u64;
                if us > st.slowest_micros.load(Ordering::Relaxed) {
                    st.slowest_micros.store(us, Ordering::Relaxed);
                    *st.slowest_input.lock().unwrap_or_else(|e| e.into_inner()) = input;
                }
                Ok(())
            });
            st.finished.store(true, Ordering::SeqCst);
            match result {
                Ok(()) => Ok(()),
                Err(TestError::Fail(reason, input)) => {
                    // Re-run the minimal input once to capture its own panic report.
                    *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) = None;
                    let again = catch_unwind(AssertUnwindSafe(|| {
                        exercise(&input, &machines, &Stats::default())
                    }));
                    let report = LAST_PANIC
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .take()
                        .unwrap_or_else(|| format!("{reason} (did not panic again: {again:?})"));
                    let path = out_dir(target.name).join(format!("{name}.crash.{ext}"));
                    let _ = std::fs::write(&path, &input);
                    Err(format!(
                        "generator `{name}`: the front end panicked.\nminimal input ({} bytes, saved to {}):\n{}\n{report}",
                        input.len(),
                        path.display(),
                        shown(&input)
                    ))
                }
                Err(TestError::Abort(reason)) => Err(format!("generator `{name}` aborted: {reason}")),
            }
        })
        .expect("spawn fuzz worker");
    Worker {
        name,
        cases,
        stats,
        handle,
    }
}

/// Fixed inputs at the edges of any line-based language: empty, blank, a lone quote,
/// runs of brackets, of one letter, of digits, of carriage returns.
fn edge_inputs() -> Vec<String> {
    vec![
        String::new(),
        "\n".into(),
        "'".into(),
        "‘".into(),
        "’".into(),
        "\r".into(),
        "\r\n\r\n".into(),
        "\t\t".into(),
        "(".repeat(10_000),
        ")".repeat(10_000),
        "L:\n".repeat(5000),
        "A".repeat(200_000),
        "9".repeat(100_000),
        "\r".repeat(20_000),
        "‘’".repeat(10_000),
    ]
}

/// The body of a fuzz target's `#[test]`.
pub fn run<M: Send + Sync + 'static>(target: Target<M>) {
    let Target {
        name: tname,
        ext,
        exercise,
        ..
    } = target;
    install_panic_hook();
    let started = Instant::now();
    let total = env_u64("PACER_FUZZ_CASES", 2000);
    let hang = Duration::from_secs(env_u64("PACER_FUZZ_HANG_SECS", 120));
    let only = std::env::var("PACER_FUZZ_ONLY").ok();
    let machines = Arc::new((target.machines)());

    // Sanity: the complete seeds go all the way through, so the harness reaches the compiler.
    for (i, s) in (target.complete_seeds)().iter().enumerate() {
        let st = Stats::default();
        exercise(s, &machines, &st);
        assert_eq!(
            st.compiled.load(Ordering::Relaxed),
            2,
            "seed program {i} should compile on both machines"
        );
    }
    // Fixed edge inputs.
    let mut edges = edge_inputs();
    edges.extend((target.edge_inputs)());
    let edge_stats = Stats::default();
    for e in &edges {
        let t0 = Instant::now();
        exercise(e, &machines, &edge_stats);
        let el = t0.elapsed();
        assert!(
            el < Duration::from_secs(20),
            "edge input took {el:?}: {}",
            shown(e)
        );
    }
    let edge_count = edges.len() as u64;

    let grammar = total * 40 / 100;
    let mutation = total * 35 / 100;
    let raw = total - grammar - mutation;
    let plan: Vec<(&'static str, u64, MakeStrategy)> = vec![
        ("grammar", grammar, target.grammar),
        ("mutation", mutation, target.mutation),
        ("raw", raw, target.raw),
    ];
    let mut workers = Vec::new();
    for (i, (name, n, make)) in plan.into_iter().enumerate() {
        if only.as_deref().is_some_and(|o| o != name) || n == 0 {
            continue;
        }
        let cases = u32::try_from(n).expect("PACER_FUZZ_CASES too large");
        workers.push(spawn_worker(
            target,
            name,
            i as u64,
            cases,
            make,
            Arc::clone(&machines),
        ));
    }

    // Watchdog: report an input that makes no progress, print progress now and then.
    let mut last: Vec<(u64, Instant)> = workers.iter().map(|_| (0, Instant::now())).collect();
    let mut last_report = Instant::now();
    loop {
        if workers
            .iter()
            .all(|w| w.stats.finished.load(Ordering::SeqCst))
        {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
        for (w, (seen, at)) in workers.iter().zip(last.iter_mut()) {
            let now = w.stats.executed.load(Ordering::Relaxed);
            if now != *seen || w.stats.finished.load(Ordering::SeqCst) {
                *seen = now;
                *at = Instant::now();
            } else if at.elapsed() > hang {
                let cur = w
                    .stats
                    .current
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .clone();
                let path = out_dir(tname).join(format!("{}.hang.{ext}", w.name));
                let _ = std::fs::write(&path, &cur);
                panic!(
                    "generator `{}`: no progress for {:?} on input #{} ({} bytes, saved to {}):\n{}",
                    w.name,
                    hang,
                    now,
                    cur.len(),
                    path.display(),
                    shown(&cur)
                );
            }
        }
        if last_report.elapsed() > Duration::from_secs(30) {
            last_report = Instant::now();
            let progress: Vec<String> = workers
                .iter()
                .map(|w| {
                    format!(
                        "{} {}/{}",
                        w.name,
                        w.stats.executed.load(Ordering::Relaxed),
                        w.cases
                    )
                })
                .collect();
            eprintln!("{tname}: {:.0?} {}", started.elapsed(), progress.join(", "));
        }
    }

    let mut failures = Vec::new();
    let mut generated = 0u64;
    for w in workers {
        let s = &w.stats;
        let executed = s.executed.load(Ordering::Relaxed);
        generated += executed;
        let refused = if target.report_refused {
            format!(
                ", refused by compiler after clean check {}",
                s.compile_refused.load(Ordering::Relaxed)
            )
        } else {
            String::new()
        };
        eprintln!(
            "{tname}: {:<8} executed {:>8} (planned {:>8}); parse clean {}, check clean {} \
             (of 2 machines each), compiled {}{refused}; \
             slowest {} µs ({} bytes, saved as {}.slowest.{ext})",
            w.name,
            executed,
            w.cases,
            s.parse_clean.load(Ordering::Relaxed),
            s.check_clean.load(Ordering::Relaxed),
            s.compiled.load(Ordering::Relaxed),
            s.slowest_micros.load(Ordering::Relaxed),
            s.slowest_input
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .len(),
            w.name,
        );
        let _ = std::fs::write(
            out_dir(tname).join(format!("{}.slowest.{ext}", w.name)),
            &*s.slowest_input.lock().unwrap_or_else(|e| e.into_inner()),
        );
        match w.handle.join() {
            Ok(Ok(())) => {}
            Ok(Err(msg)) => failures.push(msg),
            Err(_) => failures.push(format!("worker `{}` died", w.name)),
        }
    }
    eprintln!(
        "{tname}: total inputs executed: {} ({} generated + {} fixed edge inputs) in {:.1?}",
        generated + edge_count,
        generated,
        edge_count,
        started.elapsed()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

// ---------------------------------------------------------------------------------------------
// Generator pieces both targets use (the vocabulary they draw from is each target's own)
// ---------------------------------------------------------------------------------------------

pub fn pick(xs: &'static [&'static str]) -> BoxedStrategy<String> {
    select(xs).prop_map(str::to_string).boxed()
}

/// Concatenation of several static pools.
pub fn pick_any(pools: &[&'static [&'static str]]) -> BoxedStrategy<String> {
    let all: Vec<&'static str> = pools.iter().flat_map(|p| p.iter().copied()).collect();
    select(all).prop_map(str::to_string).boxed()
}

/// A regex strategy compiled once (a `&str` strategy would compile its regex for every value).
pub fn regex(re: &str) -> BoxedStrategy<String> {
    proptest::string::string_regex(re)
        .expect("valid regex")
        .boxed()
}

/// `leaf.prop_recursive(depth, desired_size, expected_branch_size, recurse)`, its tower of
/// strategies built once. proptest's `Recursive` calls `recurse` once per level for every value
/// it generates, so the grammar generators spent most of their time allocating and dropping
/// strategies (a MotionBASIC program some 30 a second). The tower depends on nothing but the
/// four arguments, so it is built here as proptest builds it — the same weights, clamped at 0.9
/// — and the same seed gives the same inputs.
pub fn recursive<T, R>(
    leaf: BoxedStrategy<T>,
    depth: u32,
    desired_size: u32,
    expected_branch_size: u32,
    recurse: impl Fn(BoxedStrategy<T>) -> R,
) -> BoxedStrategy<T>
where
    T: std::fmt::Debug + 'static,
    R: Strategy<Value = T> + 'static,
{
    let mut probabilities = Vec::new();
    let mut k2 = u64::from(expected_branch_size) * 2;
    for _ in 0..depth {
        probabilities.push(f64::from(desired_size) / k2 as f64);
        k2 = k2.saturating_mul(u64::from(expected_branch_size) * 2);
    }
    let mut strat = leaf;
    while let Some(p) = probabilities.pop() {
        let branch = recurse(strat.clone()).boxed();
        let (weight_branch, weight_leaf) = proptest::strategy::float_to_weight(p.min(0.9));
        strat = prop_oneof![weight_leaf => strat, weight_branch => branch].boxed();
    }
    strat
}

/// Number literals: from `pool`, integers, the text of any finite float, long digit strings.
pub fn number(pool: &'static [&'static str]) -> BoxedStrategy<String> {
    prop_oneof![
        3 => pick(pool),
        2 => (0u32..100_000).prop_map(|n| n.to_string()),
        1 => any::<f64>()
            .prop_filter("finite", |f| f.is_finite())
            .prop_map(|f| f.abs().to_string()),
        1 => regex("[0-9]{1,40}(\\.[0-9]{0,20})?([eE][+-]?[0-9]{1,4})?"),
    ]
    .boxed()
}

pub fn sp() -> BoxedStrategy<&'static str> {
    prop_oneof![6 => Just(" "), 1 => Just(""), 1 => Just("  "), 1 => Just("\t")].boxed()
}

/// Children of a block: indented by two spaces (`layout` turns that into the program's unit).
pub fn indent(lines: Vec<String>) -> impl Iterator<Item = String> {
    lines.into_iter().map(|l| format!("  {l}"))
}

/// `head`, the body indented, `end`.
pub fn block(head: String, body: Vec<String>, end: &str) -> Vec<String> {
    let mut out = vec![head];
    out.extend(indent(body));
    out.push(end.into());
    out
}

/// An IF block: `kw` spells IF, THEN and ELSE in the target's dialect.
pub fn if_block(
    kw: [&str; 3],
    cond: &str,
    then_body: Vec<String>,
    else_body: Option<Vec<String>>,
    end: &str,
) -> Vec<String> {
    let [if_, then, else_] = kw;
    let mut out = vec![format!("{if_} {cond} {then}")];
    out.extend(indent(then_body));
    if let Some(e) = else_body {
        out.push(else_.into());
        out.extend(indent(e));
    }
    out.push(end.into());
    out
}

/// A FOR loop (`kw` spells FOR, TO, STEP and NEXT), the NEXT naming its variable or not.
pub fn for_block(
    kw: [&str; 4],
    var: &str,
    from: &str,
    to: &str,
    step: Option<String>,
    body: Vec<String>,
    named_next: bool,
) -> Vec<String> {
    let [for_, to_, step_, next] = kw;
    let head = match step {
        Some(s) => format!("{for_} {var} = {from} {to_} {to} {step_} {s}"),
        None => format!("{for_} {var} = {from} {to_} {to}"),
    };
    let end = if named_next {
        format!("{next} {var}")
    } else {
        next.to_string()
    };
    block(head, body, &end)
}

/// Light damage to a generated program's lines, by `what`: drop one of the lines
/// `is_closer` accepts (it sees the line trimmed), duplicate a line, delete one, or insert
/// `else_line`.
pub fn damage(
    lines: &mut Vec<String>,
    at: Index,
    what: u8,
    is_closer: fn(&str) -> bool,
    else_line: &str,
) {
    if lines.is_empty() {
        return;
    }
    let closers: Vec<usize> = (0..lines.len())
        .filter(|&i| is_closer(lines[i].trim()))
        .collect();
    match what {
        0 if !closers.is_empty() => {
            lines.remove(closers[at.index(closers.len())]);
        }
        1 => {
            let i = at.index(lines.len());
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        2 => {
            lines.remove(at.index(lines.len()));
        }
        _ => {
            let i = at.index(lines.len());
            lines.insert(i, else_line.into());
        }
    }
}

/// Program text from its lines: each two spaces of indentation become the unit `ind` picks,
/// `eol` picks the line ending (mostly LF), `case` may upper- or lower-case all of it.
pub fn layout(lines: &[String], case: u8, ind: u8, eol: u8) -> String {
    let unit = ["  ", "\t", "", "    ", " ", " \t"][ind as usize];
    let eol = match eol {
        0 => "\r\n",
        // A lone CR: a line break to PowerTools, blank space to MotionBASIC.
        1 => "\r",
        _ => "\n",
    };
    let mut out = String::new();
    for l in lines {
        let depth = l.len() - l.trim_start_matches("  ").len();
        out.push_str(&unit.repeat(depth / 2));
        out.push_str(l.trim_start_matches("  "));
        out.push_str(eol);
    }
    match case {
        0 => out.to_uppercase(),
        1 => out.to_lowercase(),
        _ => out,
    }
}

/// Blocks opened one inside the other (`openers[kind]`), a statement `leaf` on every third
/// level, and when `close`, the matching `closers[kind]` in reverse order.
pub fn nested_blocks(
    kinds: &[u8],
    close: bool,
    leaf: &str,
    openers: &[&str],
    closers: &[&str],
) -> String {
    let mut s = String::new();
    for (d, k) in kinds.iter().enumerate() {
        s.push_str(openers[*k as usize]);
        if d % 3 == 0 {
            s.push_str(leaf);
            s.push('\n');
        }
    }
    if close {
        for k in kinds.iter().rev() {
            s.push_str(closers[*k as usize]);
        }
    }
    s
}

/// `start`, then ` op operand` for each pair, then a newline.
pub fn op_chain(start: String, rest: Vec<(String, String)>) -> String {
    let mut s = start;
    for (op, a) in rest {
        s.push_str(&format!(" {op} {a}"));
    }
    s.push('\n');
    s
}

// ---------------------------------------------------------------------------------------------
// Mutations of seed programs
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
pub enum Mutation {
    InsertToken(Index, &'static str),
    ReplaceWord(Index, &'static str),
    DeleteWord(Index),
    DeleteRange(Index, usize),
    InsertText(Index, String),
    SetByte(Index, u8),
    FlipBit(Index, u8),
    DuplicateLine(Index, usize),
    DeleteLine(Index),
    DropCloser(Index),
    SwapLines(Index, Index),
    InsertLine(Index, String),
    /// Two lines become one, joined by `:` (only when `mutation` is asked for it).
    JoinLines(Index),
}

/// One mutation: tokens from `tokens`, inserted lines from `line`, and when `join_lines`,
/// lines joined by `:`.
pub fn mutation(
    tokens: &'static [&'static str],
    line: BoxedStrategy<String>,
    join_lines: bool,
) -> BoxedStrategy<Mutation> {
    fn arm(w: u32, s: impl Strategy<Value = Mutation> + 'static) -> (u32, BoxedStrategy<Mutation>) {
        (w, s.boxed())
    }
    let idx = any::<Index>();
    let lines = prop_oneof![4 => 1usize..4, 1 => 4usize..200, 1 => 200usize..2000];
    let mut arms = vec![
        arm(
            3,
            (idx.clone(), select(tokens)).prop_map(|(i, t)| Mutation::InsertToken(i, t)),
        ),
        arm(
            3,
            (idx.clone(), select(tokens)).prop_map(|(i, t)| Mutation::ReplaceWord(i, t)),
        ),
        arm(2, idx.clone().prop_map(Mutation::DeleteWord)),
        arm(
            2,
            (idx.clone(), 1usize..40).prop_map(|(i, n)| Mutation::DeleteRange(i, n)),
        ),
        arm(
            2,
            (idx.clone(), regex("(?s).{0,12}")).prop_map(|(i, s)| Mutation::InsertText(i, s)),
        ),
        arm(
            1,
            (idx.clone(), any::<u8>()).prop_map(|(i, b)| Mutation::SetByte(i, b)),
        ),
        arm(
            1,
            (idx.clone(), 0u8..8).prop_map(|(i, b)| Mutation::FlipBit(i, b)),
        ),
        arm(
            2,
            (idx.clone(), lines).prop_map(|(i, n)| Mutation::DuplicateLine(i, n)),
        ),
        arm(2, idx.clone().prop_map(Mutation::DeleteLine)),
        arm(3, idx.clone().prop_map(Mutation::DropCloser)),
        arm(
            1,
            (idx.clone(), idx.clone()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        ),
    ];
    if join_lines {
        arms.push(arm(1, idx.clone().prop_map(Mutation::JoinLines)));
    }
    arms.push(arm(
        2,
        (idx, line).prop_map(|(i, l)| Mutation::InsertLine(i, l)),
    ));
    // What `prop_oneof!` makes of more than ten arms.
    proptest::strategy::Union::new_weighted(arms).boxed()
}

fn words(s: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in s.char_indices() {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(st)) => {
                out.push((st, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(st) = start {
        out.push((st, s.len()));
    }
    out
}

/// Apply one mutation; `is_closer` says which lines (trimmed) `DropCloser` may drop.
pub fn apply(mut s: String, m: &Mutation, is_closer: fn(&str) -> bool) -> String {
    match m {
        Mutation::InsertToken(i, t) => {
            let at = boundary(&s, i.index(s.len() + 1));
            let sep = if i.index(2) == 0 { " " } else { "" };
            s.insert_str(at, &format!("{sep}{t}{sep}"));
            s
        }
        Mutation::ReplaceWord(i, t) => {
            let w = words(&s);
            if !w.is_empty() {
                let (a, b) = w[i.index(w.len())];
                s.replace_range(a..b, t);
            }
            s
        }
        Mutation::DeleteWord(i) => {
            let w = words(&s);
            if !w.is_empty() {
                let (a, b) = w[i.index(w.len())];
                s.replace_range(a..b, "");
            }
            s
        }
        Mutation::DeleteRange(i, n) => {
            let a = boundary(&s, i.index(s.len() + 1));
            let b = boundary(&s, a + n);
            s.replace_range(a..b, "");
            s
        }
        Mutation::InsertText(i, t) => {
            let at = boundary(&s, i.index(s.len() + 1));
            s.insert_str(at, t);
            s
        }
        Mutation::SetByte(i, v) | Mutation::FlipBit(i, v) => {
            let mut b = s.into_bytes();
            if !b.is_empty() {
                let k = i.index(b.len());
                if matches!(m, Mutation::SetByte(..)) {
                    b[k] = *v;
                } else {
                    b[k] ^= 1 << v;
                }
            }
            String::from_utf8_lossy(&b).into_owned()
        }
        Mutation::DuplicateLine(i, n) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let k = i.index(lines.len());
            let l = lines[k];
            for _ in 0..*n {
                lines.insert(k, l);
            }
            lines.join("\n")
        }
        Mutation::DeleteLine(i) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            lines.remove(i.index(lines.len()));
            lines.join("\n")
        }
        Mutation::DropCloser(i) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let closers: Vec<usize> = (0..lines.len())
                .filter(|&k| is_closer(lines[k].trim()))
                .collect();
            if !closers.is_empty() {
                lines.remove(closers[i.index(closers.len())]);
            }
            lines.join("\n")
        }
        Mutation::SwapLines(a, b) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let (x, y) = (a.index(lines.len()), b.index(lines.len()));
            lines.swap(x, y);
            lines.join("\n")
        }
        Mutation::InsertLine(i, l) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            lines.insert(i.index(lines.len() + 1), l);
            lines.join("\n")
        }
        Mutation::JoinLines(i) => {
            // A label line becomes `NAME: stmt`.
            let nl: Vec<usize> = s.match_indices('\n').map(|(k, _)| k).collect();
            if !nl.is_empty() {
                let k = nl[i.index(nl.len())];
                let before = s[..k].trim_end();
                let sep = if before.ends_with(':') { " " } else { " : " };
                s = format!("{before}{sep}{}", s[k + 1..].trim_start());
            }
            s
        }
    }
}

/// A seed (followed by a second one when the first one's number is a multiple of
/// `append_every`, and the strategy says so) with one to seven mutations applied.
pub fn mutated(
    seeds: Vec<String>,
    append_every: usize,
    mutation: BoxedStrategy<Mutation>,
    is_closer: fn(&str) -> bool,
) -> BoxedStrategy<String> {
    let n = seeds.len();
    (
        0..n,
        prop::option::of(0..n), // sometimes append a second program
        prop::collection::vec(mutation, 1..8),
    )
        .prop_map(move |(a, b, muts)| {
            let mut s = seeds[a].clone();
            if let Some(b) = b.filter(|_| a % append_every == 0) {
                s.push_str(&seeds[b]);
            }
            for m in &muts {
                s = apply(s, m, is_closer);
            }
            s
        })
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// Raw strings and bytes
// ---------------------------------------------------------------------------------------------

/// Characters no program should hold, but a file may: controls, odd blanks, a BOM, letters
/// that change length when their case changes, the last code point, an emoji, a combining
/// accent.
const UNUSUAL_CHARS: &[char] = &[
    '\u{0}',
    '\u{b}',
    '\u{c}',
    '\u{85}',
    '\u{a0}',
    '\u{2028}',
    '\u{feff}',
    'é',
    'ﬁ',
    'İ',
    'ß',
    '\u{10FFFF}',
    '😀',
    '\u{301}',
];

/// Random characters, biased to `special` (the target's ASCII punctuation and letters that
/// matter) and the unusual ones.
pub fn random_chars(special: &'static [char]) -> BoxedStrategy<String> {
    let special: Vec<char> = special.iter().chain(UNUSUAL_CHARS).copied().collect();
    let ch = prop_oneof![
        4 => select(special),
        4 => proptest::char::range(' ', '~'),
        1 => any::<char>(),
    ];
    prop::collection::vec(ch, 0..400)
        .prop_map(|v| v.into_iter().collect::<String>())
        .boxed()
}

/// Arbitrary unicode text.
pub fn random_text() -> BoxedStrategy<String> {
    regex("(?s).{0,200}")
}

/// Random bytes, made valid UTF-8 the way a lossy file reader would.
pub fn random_bytes() -> BoxedStrategy<String> {
    prop::collection::vec(any::<u8>(), 0..600)
        .prop_map(|b| String::from_utf8_lossy(&b).into_owned())
        .boxed()
}

/// Tokens from `tokens`, each followed by one of `separators`.
pub fn token_soup(
    tokens: &'static [&'static str],
    separators: &'static [&'static str],
) -> BoxedStrategy<String> {
    prop::collection::vec((select(tokens), pick(separators)), 0..200)
        .prop_map(|v| {
            v.into_iter()
                .map(|(t, s)| format!("{t}{s}"))
                .collect::<String>()
        })
        .boxed()
}

/// Very long lines: one of `starts`, then one of `fragments` repeated up to 40,000 times.
pub fn long_line(
    starts: &'static [&'static str],
    fragments: &'static [&'static str],
) -> BoxedStrategy<String> {
    (
        pick(starts),
        pick(fragments),
        prop_oneof![3 => 1usize..600, 2 => 600usize..6000, 1 => 6000usize..40_000],
    )
        .prop_map(|(pre, frag, n)| format!("{pre}{}\n", frag.repeat(n)))
        .boxed()
}

/// Thousands of nested block openers, closed in part, in full, or not at all.
pub fn many_openers(
    openers: &'static [&'static str],
    closers: &'static [&'static str],
) -> BoxedStrategy<String> {
    (
        pick(openers),
        prop_oneof![1 => 1usize..100, 2 => 100usize..4000],
        pick(closers),
        0usize..5000,
    )
        .prop_map(|(open, n, close, m)| format!("{}{}", open.repeat(n), close.repeat(m)))
        .boxed()
}

/// Many lines of one statement, after one of `starts`.
pub fn many_lines(
    lines: &'static [&'static str],
    starts: &'static [&'static str],
) -> BoxedStrategy<String> {
    (pick(lines), 1usize..5000, pick(starts))
        .prop_map(|(line, n, pre)| format!("{pre}{}", line.repeat(n)))
        .boxed()
}
