//! Loops whose body is straight-line arithmetic (`IF`s inside), `FOR` and `WHILE` (`Do While`)
//! alike, run outside the interpreter on typed registers (`vm::body`) when nothing they write is traced; traced, every iteration runs
//! in the interpreter. Both ways must give the same values (to the bit, a -0 included), the
//! same instruction counts at every budget, and the same faults at the same place: checked here
//! on a few hundred programs drawn at random (a fixed seed: the same programs on every run) in
//! both dialects, with every operator the translation knows, overflows, divisions by zero,
//! values past 32 bits and past 2^53, and on written cases whose values are known.

mod common;

use common::{load_memory, run_loaded, slot_value};
use pacer::load::Loaded;
use pacer::trace::Trace;
use pacer::vm::{Machine, RunSummary};

fn try_load(
    name: &str,
    file: &str,
    program: &str,
    budget: u32,
) -> Result<Loaded, pacer::diag::Diagnostics> {
    // PowerTools variables are declared: Var.D with two decimal places.
    let variables = if file.ends_with(".pt") {
        "autostart = true\n[variables.A]\n[variables.B]\n[variables.C]\n[variables.E]\n\
         [variables.I]\n[variables.J]\n[variables.D]\ndecimals = 2\n"
    } else {
        ""
    };
    let machine = format!(
        "[machine]\nname = \"b\"\nbudget = {budget}\n\n[[program]]\nnumber = 0\nfile = \"{file}\"\n{variables}"
    );
    load_memory(name, &[(file, program), ("machine.toml", &machine)])
}

fn load(name: &str, file: &str, program: &str, budget: u32) -> Loaded {
    match try_load(name, file, program, budget) {
        Ok(l) => l,
        Err(d) => panic!("{}\n{program}", d.render_plain()),
    }
}

fn run_untraced(loaded: Loaded) -> (Machine, RunSummary) {
    let tick = loaded.image.tick_ns;
    let mut machine = Machine::new(loaded.image, Trace::new(None, tick));
    let summary = machine.run_observed(None, &mut |_| {});
    (machine, summary)
}

/// What a run leaves that a program can see: every slot's bits, then every string cell's text
/// (as bytes), the instruction count, the error's place and message.
fn outcome(machine: &Machine, summary: &RunSummary) -> (Vec<u64>, u64, Option<(u32, u32, String)>) {
    let slots = machine.registry().slots.len();
    let bits = machine.values()[..slots]
        .iter()
        .map(|v| v.to_bits())
        .chain(
            machine
                .strings()
                .iter()
                .flat_map(|t| t.bytes().map(u64::from).chain([u64::MAX])),
        )
        .collect();
    let error = summary
        .error
        .as_ref()
        .map(|e| (e.line, e.column, e.message.clone()));
    (bits, summary.instructions, error)
}

/// Run `program` traced and untraced at `budget`: both outcomes, and how many loops ran
/// outside the interpreter untraced.
fn both(file: &str, program: &str, budget: u32) -> (u64, Option<(u32, u32, String)>, u64) {
    let traced = run_loaded(load("body-traced", file, program, budget));
    assert_eq!(traced.machine.tight_runs(), 0);
    let (machine, summary) = run_untraced(load("body-untraced", file, program, budget));
    let a = outcome(&traced.machine, &traced.summary);
    let b = outcome(&machine, &summary);
    if a != b {
        let names: Vec<String> = machine
            .registry()
            .slots
            .iter()
            .map(|s| s.name.text().to_string())
            .collect();
        let diff: Vec<String> =
            a.0.iter()
                .zip(&b.0)
                .enumerate()
                .filter(|(_, (x, y))| x != y)
                .map(|(i, (x, y))| {
                    format!(
                        "{} {} vs {}",
                        names[i],
                        f64::from_bits(*x),
                        f64::from_bits(*y)
                    )
                })
                .collect();
        panic!(
            "budget {budget}: traced {:?} {:?}, untraced {:?} {:?}; {diff:?}\n{program}",
            a.1, a.2, b.1, b.2
        );
    }
    (a.1, a.2, machine.tight_runs())
}

/// A small deterministic generator (xorshift64*), so the programs are the same on every run.
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len())]
    }
}

/// The words of a dialect the generator writes with.
struct Dialect {
    file: &'static str,
    vars: &'static [&'static str],
    loop_var: &'static str,
    /// The variable of a loop inside the loop.
    inner_var: &'static str,
    constants: &'static [&'static str],
    ops: &'static [&'static str],
    not: &'static str,
    endif: &'static str,
    end: &'static str,
}

const MB: Dialect = Dialect {
    file: "x.mb",
    vars: &["A&", "B&", "C&", "D&", "P%", "Q%", "X", "Y#", "Z"],
    loop_var: "I&",
    inner_var: "J%",
    constants: &[
        "0",
        "1",
        "2",
        "3",
        "7",
        "-5",
        "31",
        "255",
        "65535",
        "1000003",
        "2147483647",
        "0.5",
        "2.25",
        "-1.5",
        "1E+300",
        "40000",
        "9007199254740993",
    ],
    ops: &[
        "+", "-", "*", "/", "\\", "MOD", "AND", "OR", "XOR", "+", "-", "*", "MOD",
    ],
    not: "NOT",
    endif: "END IF",
    end: "",
};

const PT: Dialect = Dialect {
    file: "x.pt",
    vars: &["Var.A", "Var.B", "Var.C", "Var.D", "Var.E"],
    loop_var: "Var.I",
    inner_var: "Var.J",
    constants: &[
        "0",
        "1",
        "2",
        "3",
        "7",
        "-5",
        "31",
        "255",
        "65535",
        "1000003",
        "2147483647",
        "40000",
    ],
    ops: &["+", "-", "*", "/", "MOD", "AND", "OR", "XOR", "+", "-", "*"],
    not: "NOT",
    endif: "Endif",
    end: "End\n",
};

/// The MotionBASIC arrays the programs use (`DIM`ed first): longs, INTEGERs, reals, and
/// longs of two subscripts.
const ARRAYS: [&str; 4] = ["A&(10)", "B%(10)", "R(10)", "G&(3, 3)"];

/// An element of one of [`ARRAYS`]: mostly a subscript within its bounds (`AND` of whole
/// bits, of a real rounded first), sometimes any expression (out of range: a fault).
fn element(d: &mut Draw, w: &Dialect, depth: u32) -> String {
    // A constant subscript names the element's own register (which a store through the
    // array must be seen in).
    let sub = |d: &mut Draw, mask: &str| match d.below(7) {
        0 => expr(d, w, depth),
        1 => format!("{}", d.below(if mask == "3" { 4 } else { 8 })),
        _ => format!("({} AND {mask})", expr(d, w, depth)),
    };
    match d.below(4) {
        0 => format!("A&({})", sub(d, "7")),
        1 => format!("B%({})", sub(d, "7")),
        2 => format!("R({})", sub(d, "7")),
        _ => {
            let i = sub(d, "3");
            format!("G&({i}, {})", sub(d, "3"))
        }
    }
}

fn expr(d: &mut Draw, w: &Dialect, depth: u32) -> String {
    let mb = w.file.ends_with(".mb");
    match d.below(if depth == 0 { 2 } else { 7 }) {
        0 => {
            let mut vars = w.vars.to_vec();
            vars.push(w.loop_var);
            d.pick(&vars).to_string()
        }
        1 => d.pick(w.constants).to_string(),
        2 => format!("({} {})", w.not, expr(d, w, depth - 1)),
        3 if mb => format!("-({})", expr(d, w, depth - 1)),
        6 if mb => element(d, w, depth - 1),
        _ => format!(
            "({} {} {})",
            expr(d, w, depth - 1),
            d.pick(w.ops),
            expr(d, w, depth - 1)
        ),
    }
}

fn condition(d: &mut Draw, w: &Dialect) -> String {
    let cmp = d.pick(&["=", "<>", "<", "<=", ">", ">="]);
    format!("{} {cmp} {}", expr(d, w, 1), expr(d, w, 1))
}

fn statement(d: &mut Draw, w: &Dialect, out: &mut String, depth: u32) {
    let var = if w.file.ends_with(".mb") && d.below(4) == 0 {
        element(d, w, 1)
    } else {
        d.pick(w.vars).to_string()
    };
    match d.below(if depth == 0 { 1 } else { 4 }) {
        0 | 1 => out.push_str(&format!("{var} = {}\n", expr(d, w, 2))),
        2 => {
            out.push_str(&format!("If {} Then\n", condition(d, w)));
            for _ in 0..1 + d.below(2) {
                statement(d, w, out, depth - 1);
            }
            if d.below(2) == 0 {
                out.push_str("Else\n");
                statement(d, w, out, depth - 1);
            }
            out.push_str(&format!("{}\n", w.endif));
        }
        _ => {
            out.push_str(&format!("If {} Then\n", condition(d, w)));
            statement(d, w, out, depth - 1);
            out.push_str(&format!("{}\n", w.endif));
        }
    }
}

/// A loop inside the loop, on [`Dialect::inner_var`]: a `FOR` or a `WHILE` (`Do While`) of a
/// few statements and a few iterations (none, when it starts past its limit); with `exit`, a
/// statement may leave both loops (`GOTO` that line).
fn inner_loop(d: &mut Draw, w: &Dialect, out: &mut String, exit: Option<usize>) {
    let mb = w.file.ends_with(".mb");
    let j = w.inner_var;
    let from = d.pick(&["0", "1", "-2", "5"]);
    let to = d.pick(&["3", "6", "0", "-4", "2.5"]);
    let step = d.pick(&["1", "2", "-1"]);
    if d.below(2) == 0 {
        out.push_str(&format!("For {j} = {from} To {to} Step {step}\n"));
        for _ in 0..1 + d.below(2) {
            statement(d, w, out, 1);
        }
        if let Some(line) = exit.filter(|_| d.below(2) == 0) {
            out.push_str(&format!("IF {} THEN GOTO {line}\n", condition(d, w)));
        }
        out.push_str("Next\n");
    } else {
        let cmp = if step.starts_with('-') { ">=" } else { "<=" };
        let head = if mb { "WHILE" } else { "Do While" };
        out.push_str(&format!("{j} = {from}\n{head} {j} {cmp} {to}\n"));
        for _ in 0..1 + d.below(2) {
            statement(d, w, out, 1);
        }
        out.push_str(&format!("{j} = {j} + {step}\n"));
        out.push_str(if mb { "WEND\n" } else { "Loop\n" });
    }
}

/// A program of [`Dialect`] `w`: a loop or two, with loops inside; with `subs` (MotionBASIC),
/// its loops call two subroutines after its `END` (`GOSUB`), which may return early (`IF …
/// THEN RETURN`: a subroutine a body does not run inside).
fn program(d: &mut Draw, w: &Dialect, subs: bool) -> String {
    let mut out = String::new();
    if w.file.ends_with(".mb") {
        out.push_str(&format!("DIM {}\n", ARRAYS.join(", ")));
    }
    for var in w.vars {
        let v = d.pick(&["0", "1", "-7", "12345", "3", "100", "-2", "0.75"]);
        // Only reals take a fraction here (a whole variable rounds it: that is tested too).
        out.push_str(&format!("{var} = {v}\n"));
    }
    let mb = w.file.ends_with(".mb");
    for k in 0..1 + d.below(2) {
        let from = d.pick(&["1", "0", "-3", "10"]);
        let counted = d.below(2) == 0;
        // A `WHILE` tests its limit at each iteration: a constant, so that it ends.
        let to = match d.below(8) {
            0 if counted => d.pick(w.vars),
            _ => d.pick(&["20", "60", "3", "-10", "200", "10.5", "-3.5"]),
        };
        let step = d.pick(&["1", "2", "-1", "3", "-2"]);
        let i = w.loop_var;
        // A `FOR`, or the same loop as a `WHILE` (`Do While`) counting by itself, sometimes
        // with a second condition; a MotionBASIC body may jump out of it (`GOTO` the line
        // after its end).
        let exits = mb && d.below(3) == 0;
        if counted {
            out.push_str(&format!("For {i} = {from} To {to} Step {step}\n"));
        } else {
            let cmp = if step.starts_with('-') { ">=" } else { "<=" };
            let also = match d.below(3) {
                0 => format!(" AND {} <> {}", d.pick(w.vars), d.pick(w.constants)),
                _ => String::new(),
            };
            out.push_str(&format!("{i} = {from}\n"));
            let head = if mb { "WHILE" } else { "Do While" };
            out.push_str(&format!("{head} {i} {cmp} {to}{also}\n"));
        }
        for _ in 0..1 + d.below(4) {
            if d.below(4) == 0 {
                inner_loop(d, w, &mut out, exits.then_some(90 + k));
            } else {
                statement(d, w, &mut out, 2);
            }
            if exits && d.below(3) == 0 {
                out.push_str(&format!("IF {} THEN GOTO {}\n", condition(d, w), 90 + k));
            }
            if subs && d.below(2) == 0 {
                out.push_str(&format!("GOSUB {}\n", 500 + d.below(2)));
            }
        }
        if counted {
            out.push_str("Next\n");
        } else {
            out.push_str(&format!("{i} = {i} + {step}\n"));
            out.push_str(if mb { "WEND\n" } else { "Loop\n" });
        }
        if exits {
            out.push_str(&format!("{} {} = {}\n", 90 + k, w.vars[0], w.vars[0]));
        }
    }
    out.push_str(w.end);
    if subs {
        out.push_str("END\n");
        for line in [500, 501] {
            out.push_str(&format!("{line} "));
            for _ in 0..1 + d.below(3) {
                statement(d, w, &mut out, 2);
            }
            if d.below(6) == 0 {
                out.push_str(&format!("IF {} THEN RETURN\n", condition(d, w)));
                statement(d, w, &mut out, 1);
            }
            out.push_str("RETURN\n");
        }
    }
    out
}

#[test]
fn random_loops_give_the_same_values_counts_and_faults_in_or_out_of_the_interpreter() {
    random_loops(&[
        (&MB, 0x5eed_0001u64, 300, false),
        (&PT, 0x5eed_0002, 200, false),
    ]);
}

#[test]
fn random_loops_calling_subroutines_give_the_same_as_the_interpreter() {
    // The subroutines run inside the bodies (stopping in them at a budget test, a fault, an
    // iteration left undone), or keep the loop in the interpreter (one that returns early).
    random_loops(&[(&MB, 0x5eed_0003u64, 300, true)]);
}

/// Draw `count` programs of each dialect from its seed (with subroutines or not), and run each
/// traced and untraced at two budgets: the same values, counts and faults.
fn random_loops(sets: &[(&Dialect, u64, usize, bool)]) {
    for &(w, seed, count, subs) in sets {
        let mut d = Draw(seed);
        let (mut outside, mut faults, mut clean, mut refused) = (0u64, 0, 0, 0);
        for _ in 0..count {
            let p = program(&mut d, w, subs);
            let p = if w.file.ends_with(".mb") {
                p.replace("If ", "IF ")
                    .replace(" Then\n", " THEN\n")
                    .replace("Else\n", "ELSE\n")
                    .replace("For ", "FOR ")
                    .replace(" To ", " TO ")
                    .replace(" Step ", " STEP ")
                    .replace("Next\n", "NEXT\n")
            } else {
                p
            };
            // The checker refuses some (a constant divisor of 0, a constant that overflows, a
            // constant subscript out of range): those are drawn again.
            if try_load("body-check", w.file, &p, 7).is_err_and(|d| {
                let text = d.render_plain();
                text.contains("run-time error") || text.contains("Subscript out of range")
            }) {
                refused += 1;
                continue;
            }
            for budget in [7, 10_000] {
                let (_, error, runs) = both(w.file, &p, budget);
                outside += runs;
                if budget == 10_000 {
                    if error.is_some() {
                        faults += 1;
                    } else {
                        clean += 1;
                    }
                }
            }
        }
        // The programs exercise both ways: many loops ran outside, many ended in a fault,
        // many ran to their end.
        assert!(outside > count as u64, "{} loops outside", outside);
        eprintln!(
            "{}: {outside} loops outside, {faults} faults, {clean} clean, {refused} refused",
            w.file
        );
        assert!(faults > count / 20, "{faults} faults of {count}");
        assert!(clean > count / 10, "{clean} clean of {count}");
        // (Subroutines add statements, and with them constant subscripts out of range.)
        let most_refused = if subs { count / 2 } else { count / 3 };
        assert!(refused < most_refused, "{refused} refused of {count}");
    }
}

#[test]
fn a_hash_of_longs_gives_lua_s_value_outside_the_interpreter() {
    // The hash of `bench/` in small: XOR, AND, *, \, MOD on longs (Lua 5.4 gives 684936 for
    // 3,000,000 iterations; 10,000 here, checked against the interpreter).
    let program = "H& = 12345
FOR I& = 1 TO 10000
  H& = ((H& XOR I&) AND 65535) * 31 + (I& \\ 7)
  H& = H& MOD 1000003
NEXT
";
    let (machine, summary) = run_untraced(load("body-hash", "x.mb", program, 1_000_000));
    assert_eq!(machine.tight_runs(), 1);
    assert!(summary.error.is_none());
    // 1 + 1 + 3 before the loop, 9 per iteration, the last for.next's fall, `END`.
    assert_eq!(summary.instructions, 5 + 10_000 * 9 + 1);
    let h = machine.value_of("H&").expect("H&");
    let mut want: i64 = 12345;
    for i in 1..=10_000i64 {
        want = ((want ^ i) & 65535) * 31 + i / 7;
        want %= 1_000_003;
    }
    assert_eq!(h, want as f64);
    assert_eq!(both("x.mb", program, 7).1, None);
}

/// Euclid's algorithm for every pair (i, j) of 1..=`n` in MotionBASIC, `more` after the
/// pair's two stores: a WHILE inside a FOR J inside a FOR I, summing the divisors into `S&`.
fn euclid(n: u32, more: &str) -> String {
    format!(
        "S& = 0
FOR I& = 1 TO {n}
  FOR J& = 1 TO {n}
    A& = I&: B& = J&{more}
    WHILE B& <> 0
      T& = A& MOD B&: A& = B&: B& = T&
    WEND
    S& = S& + A&
  NEXT
NEXT
"
    )
}

/// The greatest common divisor of `a` and `b`, and how many rounds Euclid's algorithm takes.
fn gcd(mut a: i64, mut b: i64) -> (i64, u64) {
    let mut rounds = 0;
    while b != 0 {
        (a, b) = (b, a % b);
        rounds += 1;
    }
    (a, rounds)
}

#[test]
fn while_loops_run_outside_the_interpreter_from_their_second_iteration() {
    // Euclid's algorithm for every pair (i, j) of 1..=40: a WHILE of MOD and moves, entered
    // 1,600 times, most for a few iterations, inside two FORs. Here the FORs hold a power
    // (`^`), which the translation does not know: the interpreter runs them, the WHILE's first
    // iteration too, and the WHILE's `loop` hands the rest over.
    let program = euclid(40, ": P& = J& ^ 1");
    let program = program.as_str();
    let (machine, summary) = run_untraced(load("body-gcd", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    let sum: i64 = (1..=40i64)
        .flat_map(|i| (1..=40).map(move |j| gcd(i, j).0))
        .sum();
    assert_eq!(machine.value_of("S&"), Some(sum as f64));
    // Each WHILE that goes round is handed over at its `loop` (to its test, at least): Euclid's
    // go round 3.25 times on average, too few to gain by it, so after its first 64 entries it
    // stays in the interpreter.
    assert_eq!(machine.tight_runs(), 64);
    // 1 + 4 before (FOR I: its for.check included), then for each I its FOR J (4) and
    // `for.next`; for each pair 2 stores, the power (2), the WHILE's last test (a
    // compare-and-jump), the sum (2) and NEXT J; for each round the test, the MOD and 3
    // stores and the `loop`; `END`.
    let rounds: u64 = (1..=40i64)
        .flat_map(|i| (1..=40).map(move |j| gcd(i, j).1))
        .sum();
    assert_eq!(
        summary.instructions,
        5 + 40 * (4 + 1) + 1600 * (2 + 2 + 1 + 2 + 1) + rounds * 6 + 1
    );
    for budget in [3, 7, 50] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
    // Collatz's sequences from 201 to 400 go round 59 times on average (57 for the first 64,
    // some 400 of the interpreter's instructions an entry): each is handed over.
    let collatz = "M& = 0
FOR I& = 201 TO 400
  N& = I&: L& = 0: P& = I& ^ 1
  WHILE N& <> 1
    IF N& MOD 2 = 0 THEN N& = N& \\ 2 ELSE N& = 3 * N& + 1
    L& = L& + 1
  WEND
  IF L& > M& THEN M& = L&
NEXT
";
    let (machine, summary) = run_untraced(load("body-collatz", "x.mb", collatz, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 200);
    assert_eq!(machine.value_of("M&"), Some(143.0));
    assert_eq!(both("x.mb", collatz, 7).1, None);
}

#[test]
fn a_loop_holding_loops_runs_outside_the_interpreter_as_one() {
    // Euclid's algorithm for every pair (i, j) of 1..=100: the WHILE inside the FOR J inside
    // the FOR I. The FOR I's body holds the rest, so the machine runs the whole of it: once
    // when nothing stops it, and when a budget does, each turn goes on where the last one
    // stopped (the start of a loop inside), in the same run.
    let program = euclid(100, "");
    let program = program.as_str();
    let pairs = || (1..=100i64).flat_map(|i| (1..=100).map(move |j| gcd(i, j)));
    let sum: i64 = pairs().map(|p| p.0).sum();
    let rounds: u64 = pairs().map(|p| p.1).sum();
    // As in the interpreter: 1 + 4 before, for each I its FOR J (4) and `for.next`; for each
    // pair 2 stores, the WHILE's last test, the sum (2) and NEXT J; for each round the test,
    // the MOD, 3 stores and the `loop`; `END`.
    let count = 5 + 100 * (4 + 1) + 10_000 * (2 + 1 + 2 + 1) + rounds * 6 + 1;
    let (machine, summary) = run_untraced(load("body-nested", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.value_of("S&"), Some(sum as f64));
    assert_eq!(summary.instructions, count);
    assert_eq!(machine.tight_runs(), 1);
    // At 1,000 instructions a turn, a turn goes on in the run where the last one stopped: one
    // run a turn (the interpreter would enter each FOR J, or each WHILE, on its own).
    let (machine, summary) = run_untraced(load("body-nested-turns", "x.mb", program, 1_000));
    assert_eq!(summary.instructions, count);
    assert_eq!(machine.value_of("S&"), Some(sum as f64));
    let turns = count / 1_000 + 1;
    assert!(
        machine.tight_runs() <= turns + 1,
        "{} runs in {turns} turns",
        machine.tight_runs()
    );
    for budget in [3, 7, 50, 1_000] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
    // INTEGER counters, a STEP, a FOR that does not go round, a fault inside the inner loop
    // (an INTEGER overflow at the place the interpreter gives), all as the interpreter does.
    let faults = "DIM G%(9)
S& = 0
FOR I% = 0 TO 9
  FOR J% = 9 TO 0 STEP -3
    G%(J%) = G%(J%) + I% * J%
  NEXT
  FOR K% = 5 TO 1
    S& = S& + 1
  NEXT
  S& = S& + G%(I%)
NEXT
FOR I% = 1 TO 20
  FOR J% = 1 TO 10
    P% = I% * J% * 200
  NEXT
NEXT
";
    for budget in [3, 7, 50, 1_000_000] {
        let (_, error, runs) = both("x.mb", faults, budget);
        let (line, _, message) = error.expect("an overflow");
        assert_eq!(line, 14);
        assert!(message.contains("Overflow"), "{message}");
        // The first FOR I in one run; the second in one until the iteration that overflows,
        // which (its product a temporary that may be -0) is left undone from its start: the
        // interpreter runs it again, and its FOR J runs outside on its own up to the fault.
        if budget == 1_000_000 {
            assert_eq!(runs, 3);
        }
    }
}

#[test]
fn an_element_of_two_subscripts_is_reached_with_both_checks() {
    // The offset of G&(i, j) (both subscripts checked, i * 7 + j) is one instruction outside
    // the interpreter. The second sum's second subscript leaves the array at K& = 35: the
    // interpreter's fault, at its place, with the sum of the iterations before.
    let program = "DIM G&(4, 6)
FOR I& = 0 TO 4
  FOR J& = 0 TO 6
    G&(I&, J&) = I& * 10 + J&
  NEXT
NEXT
S& = 0
FOR K& = 0 TO 34
  S& = S& + G&(K& \\ 7, K& MOD 7)
NEXT
FOR K& = 0 TO 40
  S& = S& + G&(K& MOD 5, K& \\ 5)
NEXT
";
    let first: i64 = (0..35).map(|k| (k / 7) * 10 + k % 7).sum();
    let second: i64 = (0..35).map(|k| (k % 5) * 10 + k / 5).sum();
    let (machine, summary) = run_untraced(load("body-2d", "x.mb", program, 1_000_000));
    let error = summary.error.as_ref().expect("a subscript out of range");
    assert_eq!(error.line, 12);
    assert!(
        error.message.contains("Subscript out of range"),
        "{}",
        error.message
    );
    assert_eq!(machine.value_of("S&"), Some((first + second) as f64));
    assert_eq!(machine.value_of("K&"), Some(35.0));
    assert!(machine.tight_runs() >= 3);
    for budget in [3, 7, 1_000_000] {
        assert!(both("x.mb", program, budget).1.is_some());
    }
}

#[test]
fn a_do_while_left_by_a_jump_out_ends_where_the_interpreter_ends_it() {
    // PowerTools `Do While` … `Loop` (as the labeler's programs write it: spec/labeling.md)
    // going round until its own test fails; a MotionBASIC `WHILE` left in the middle of an
    // iteration by an `IF … THEN GOTO` past its end.
    let pt = "Var.I = 0
Var.A = 0
Do While Var.I < 1000
  Var.A = (Var.A * 31 + Var.I) MOD 65521
  Var.I = Var.I + 1
Loop
End
";
    let (machine, summary) = run_untraced(load("body-do", "x.pt", pt, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    let s = (0..1000i64).fold(0, |s, i| (s * 31 + i) % 65521);
    assert_eq!(machine.value_of("Var.A"), Some(s as f64));
    assert_eq!(machine.value_of("Var.I"), Some(1000.0));
    let mb = "S& = 0: I& = 0
WHILE I& < 100000
  S& = (S& * 31 + I&) MOD 65521
  IF S& = 777 THEN GOTO 90
  I& = I& + 1
WEND
90 N& = I&
";
    let (machine, summary) = run_untraced(load("body-out", "x.mb", mb, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    let (mut s, mut i) = (0i64, 0i64);
    loop {
        s = (s * 31 + i) % 65521;
        if s == 777 {
            break;
        }
        i += 1;
    }
    assert!(i > 4 && i < 100_000, "{i}");
    assert_eq!(machine.value_of("N&"), Some(i as f64));
    assert_eq!(machine.value_of("S&"), Some(s as f64));
    for budget in [3, 7, 50] {
        assert_eq!(both("x.mb", mb, budget).1, None);
        assert_eq!(both("x.pt", pt, budget).1, None);
    }
}

#[test]
fn elements_are_read_and_stored_in_place_with_the_interpreter_s_checks() {
    // A histogram of a linear congruential generator: an element read, incremented and
    // stored at a subscript computed in the body (MotionBASIC arrays: the ORMEC MotionBASIC
    // manual's DIM; subscripts from 0, `OPTION BASE` aside).
    let program = "DIM H&(15), R(3)
X& = 1
FOR I& = 1 TO 20000
  X& = (X& * 1103 + 12345) MOD 65536
  K& = (X& \\ 16) AND 15
  H&(K&) = H&(K&) + 1
  R(I& AND 3) = R(I& AND 3) * 0.5 + K&
NEXT
";
    let (machine, summary) = run_untraced(load("body-hist", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    let (mut x, mut h, mut r) = (1i64, [0i64; 16], [0f64; 4]);
    for i in 1..=20000usize {
        x = (x * 1103 + 12345) % 65536;
        let k = (x / 16) & 15;
        h[k as usize] += 1;
        r[i & 3] = r[i & 3] * 0.5 + k as f64;
    }
    for (k, n) in h.iter().enumerate() {
        assert_eq!(
            machine.value_of(&format!("H&({k})")),
            Some(*n as f64),
            "H&({k})"
        );
    }
    for (k, v) in r.iter().enumerate() {
        let got = machine.value_of(&format!("R({k})")).map(f64::to_bits);
        assert_eq!(got, Some(v.to_bits()), "R({k})");
    }
    for budget in [3, 7, 50] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
    // A sum stored into an element that overflows, and a subscript out of range: the
    // interpreter's faults, at their places, with the iterations before done outside.
    let overflow = "DIM A&(3), B%(3)
FOR I& = 1 TO 100
  A&(I& AND 3) = 2147483600 + I&
  B%(1) = I&
NEXT
";
    let (machine, summary) = run_untraced(load("body-overflow", "x.mb", overflow, 1_000_000));
    let error = summary.error.as_ref().expect("an overflow");
    assert_eq!((error.line, error.column), (3, 18), "{}", error.message);
    assert!(error.message.starts_with("Overflow"), "{}", error.message);
    assert_eq!(machine.tight_runs(), 1);
    // I& = 48 overflows: 47 iterations done, the last of them stored into B%(1).
    assert_eq!(machine.value_of("B%(1)"), Some(47.0));
    assert_eq!(machine.value_of("A&(3)"), Some(2147483600.0 + 47.0));
    let range = "DIM A&(9)
FOR I& = 1 TO 100
  A&(I& \\ 3) = A&(I& \\ 3) + I&
NEXT
";
    let (machine, summary) = run_untraced(load("body-range", "x.mb", range, 1_000_000));
    let error = summary.error.as_ref().expect("a subscript out of range");
    assert_eq!(error.line, 3, "{}", error.message);
    assert!(
        error.message.contains("Subscript out of range"),
        "{}",
        error.message
    );
    // I& = 30 subscripts 10: the 29 before summed into A&(0..=9).
    assert_eq!(machine.value_of("A&(9)"), Some(27.0 + 28.0 + 29.0));
    for budget in [3, 7, 50] {
        assert_eq!(both("x.mb", overflow, budget).1.map(|e| e.0), Some(3));
        assert_eq!(both("x.mb", range, budget).1.map(|e| e.0), Some(3));
    }
}

#[test]
fn a_filter_with_a_counter_mixes_integers_and_reals_as_the_interpreter_does() {
    // `bench/unseen` in small: an integer MOD, a real filter, a conditional counter.
    // (With integer work around it: a body mostly of reals is left to the interpreter.)
    let program = "C& = 0
F = 0
K& = 0
FOR I& = 1 TO 1000
  M& = I& MOD 7
  K& = (K& * 31 + (I& XOR M&)) MOD 1009
  IF (K& AND 3) = 1 THEN K& = K& \\ 2
  F = F * 0.875 + M& * 0.125
  IF F > 3.5 THEN C& = C& + 1
NEXT
";
    let (machine, summary) = run_untraced(load("body-filter", "x.mb", program, 1_000_000));
    assert_eq!(machine.tight_runs(), 1);
    assert!(summary.error.is_none());
    let (mut c, mut f, mut k) = (0.0, 0.0f64, 0i64);
    for i in 1..=1000i64 {
        let m = i % 7;
        k = (k * 31 + (i ^ m)) % 1009;
        if k & 3 == 1 {
            k /= 2;
        }
        f = f * 0.875 + m as f64 * 0.125;
        if f > 3.5 {
            c += 1.0;
        }
    }
    assert_eq!(machine.value_of("C&"), Some(c));
    assert_eq!(machine.value_of("K&"), Some(k as f64));
    assert_eq!(machine.value_of("F").map(f64::to_bits), Some(f.to_bits()));
    for budget in [3, 7, 50] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
}

#[test]
fn a_fault_inside_a_body_is_the_interpreter_s_at_its_place_with_the_iterations_before_done() {
    // The 11th iteration divides by zero: the ten before are done outside, the eleventh runs
    // in the interpreter and faults at line 4, column 13 (the `\`).
    let program = "S& = 0
FOR I& = 1 TO 100
  D& = 11 - I&
  S& = S& + 100 \\ D&
NEXT
";
    let (machine, summary) = run_untraced(load("body-fault", "x.mb", program, 1_000_000));
    assert_eq!(machine.tight_runs(), 1);
    let error = summary.error.as_ref().expect("a division by zero");
    assert_eq!(
        (error.line, error.message.as_str()),
        (4, "division by zero")
    );
    let sum: i64 = (1..=10).map(|i| 100 / (11 - i)).sum();
    assert_eq!(machine.value_of("S&"), Some(sum as f64));
    assert_eq!(machine.value_of("D&"), Some(0.0));
    assert_eq!(machine.value_of("I&"), Some(11.0));
    let (n, e, _) = both("x.mb", program, 1_000_000);
    assert_eq!(e.map(|e| e.0), Some(4));
    assert_eq!(n, summary.instructions);
}

#[test]
fn a_negative_zero_reaching_a_real_is_the_interpreter_s() {
    // `-3 MOD 3` is -0 in MotionBASIC (the sign of the dividend); a real keeps it.
    let program = "X = 1
FOR I& = 1 TO 10
  K& = -3
  X = (K& MOD 3) * 1
NEXT
";
    let (machine, _) = run_untraced(load("body-zero", "x.mb", program, 1_000_000));
    let x = machine.value_of("X").expect("X");
    assert!(x == 0.0 && x.is_sign_negative(), "{x}");
    both("x.mb", program, 1_000_000);
}

#[test]
fn a_zero_remainder_reaching_a_real_has_the_sign_of_its_dividend() {
    // Counting down to -12: the last remainders are zeros of a negative dividend (-0), the
    // one of `I& + 24` a zero of a positive one (+0); through a division, a store, a copy
    // into a real register, a sum. The body converts them with the dividend's sign rather
    // than leaving the iteration (each `MOD` by 2 or 3 gives a zero every few iterations).
    // The longs make it a body mostly of integers, which runs outside the interpreter.
    let program = "S = 0
FOR I& = 12 TO -12 STEP -1
  X = (I& MOD 3) / 4
  Y = I& MOD 4
  V = ((I& + 24) MOD 3) / 4
  W = (I& MOD 2) * 0.5 + (I& MOD 6)
  S = S + (I& MOD 2) / 8
  K& = (K& * 31 + I&) AND 65535
  H& = H& XOR (K& + I&)
  G& = (G& + K&) AND 255
  J& = (J& + H&) AND 4095
  L& = L& XOR (J& + G&)
NEXT
";
    let (machine, _) = run_untraced(load("body-mod-sign", "x.mb", program, 1_000_000));
    let value = |name: &str| machine.value_of(name).unwrap_or(f64::NAN);
    for (name, negative) in [("X", true), ("Y", true), ("V", false), ("W", true)] {
        let x = value(name);
        assert!(x == 0.0 && x.is_sign_negative() == negative, "{name}: {x}");
    }
    assert_eq!(value("S"), 0.0);
    let (_, error, tight) = both("x.mb", program, 1_000_000);
    assert_eq!(error, None);
    // Once, from its second iteration to its end: no iteration was left to the interpreter.
    assert_eq!(tight, 1, "runs outside the interpreter");
    assert_eq!(machine.slow_runs(), 0, "iterations left to the interpreter");
    // The same at budgets that cut iterations in the middle.
    for budget in [7, 10, 33] {
        both("x.mb", program, budget);
    }
}

#[test]
fn a_body_that_writes_a_traced_slot_or_calls_out_stays_in_the_interpreter() {
    // An outer loop (its body holds a loop) and a body with a PRINT are not translated; the
    // inner loop is.
    let program = "T& = 0
FOR J& = 1 TO 10
  FOR I& = 1 TO 20
    T& = T& + I& * J&
  NEXT
  PRINT T&;
NEXT
";
    let (machine, summary) = run_untraced(load("body-nest", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 10);
    assert_eq!(machine.value_of("T&"), Some(210.0 * 55.0));
    let _ = slot_value(&machine, "T&");
}

#[test]
fn an_iteration_left_in_the_middle_of_a_statement_goes_on_in_the_interpreter_there() {
    // At I& = 11, D& is 0: the iteration stops at the `\` with S& + I& * 1000 (a temporary)
    // computed; the interpreter takes over there and faults at that `\`, the values of the
    // ten iterations before kept, at every budget the same count as the interpreter's alone.
    let program = "S& = 0
FOR I& = 1 TO 100
  D& = 11 - I&
  S& = S& + I& * 1000 + 100 \\ D&
NEXT
";
    let (machine, summary) = run_untraced(load("body-middle", "x.mb", program, 1_000_000));
    assert_eq!(machine.tight_runs(), 1);
    let error = summary.error.as_ref().expect("a division by zero");
    assert_eq!((error.line, error.column), (4, 25));
    let sum: i64 = (1..=10).map(|i| i * 1000 + 100 / (11 - i)).sum();
    assert_eq!(machine.value_of("S&"), Some(sum as f64));
    for budget in [5, 9, 1_000_000] {
        let (n, e, _) = both("x.mb", program, budget);
        assert_eq!(e.map(|e| (e.0, e.1)), Some((4, 25)));
        assert_eq!(n, summary.instructions);
    }
}

#[test]
fn an_element_named_by_a_constant_subscript_sees_the_stores_through_its_array() {
    // `A&(3)` (a constant subscript) is the element's own register: a body that also stores
    // through `A&(I&)` must read it after those stores, as the interpreter does.
    let flat = "DIM A&(9)
FOR I& = 0 TO 9
  A&(I&) = I& * 2
  S& = S& + A&(3)
NEXT
";
    let (machine, summary) = run_untraced(load("body-alias", "x.mb", flat, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.value_of("S&"), Some((6 * 7) as f64));
    // A bubble sort (its swaps stores through the array) inside a loop that reads one
    // element by its register, at budgets that stop it at the start of each loop inside.
    let sort = "DIM A&(20)
FOR R% = 1 TO 30
  FOR I% = 0 TO 18
    FOR J% = 0 TO 18 - I%
      IF A&(J%) > A&(J% + 1) THEN
        X& = A&(J%): A&(J%) = A&(J% + 1): A&(J% + 1) = X&
      END IF
    NEXT
  NEXT
  FOR I% = 0 TO 19: A&(I%) = (I% * 7 + R%) MOD 13: NEXT
  T& = T& + A&(10)
NEXT
";
    for budget in [7, 100, 333, 1_000, 1_000_000] {
        assert_eq!(both("x.mb", flat, budget).1, None);
        assert_eq!(both("x.mb", sort, budget).1, None);
    }
}

#[test]
fn string_compares_and_assignments_run_outside_the_interpreter_as_its_own() {
    // `K$ = N$(i)` copies an element's text into K$'s own; each compare of the six gives what
    // the interpreter gives (byte order, a shorter string first).
    let program = "DIM N$(5)
N$(0) = \"AB\": N$(1) = \"ABC\": N$(2) = \"B\": N$(3) = \"\": N$(4) = \"ab\"
FOR I& = 0 TO 999
  K$ = N$(I& MOD 5)
  IF K$ = \"ABC\" THEN C& = C& + 1
  IF K$ <> \"AB\" THEN D& = D& + 1
  IF K$ < \"B\" THEN E& = E& + 1
  IF K$ <= \"AB\" THEN F& = F& + 1
  IF K$ > N$(4) THEN G& = G& + 1
  IF K$ >= \"\" THEN H& = H& + 1
NEXT
";
    let (machine, summary) = run_untraced(load("body-text", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    let texts = ["AB", "ABC", "B", "", "ab"];
    let count = |f: &dyn Fn(&str) -> bool| (0..1000).filter(|i| f(texts[i % 5])).count() as f64;
    for (name, want) in [
        ("C&", count(&|k| k == "ABC")),
        ("D&", count(&|k| k != "AB")),
        ("E&", count(&|k| k < "B")),
        ("F&", count(&|k| k <= "AB")),
        ("G&", count(&|k| k > "ab")),
        // Every string is at least the empty one.
        ("H&", count(&|_| true)),
    ] {
        assert_eq!(machine.value_of(name), Some(want), "{name}");
    }
    let k = machine.value_of("K$").expect("K$") as usize;
    assert_eq!(machine.strings()[k], "ab");
    for budget in [7, 100, 1_000_000] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
}

#[test]
fn string_array_elements_are_assigned_outside_the_interpreter() {
    // An insertion sort of a string array: the WHILE that moves elements up (`W$(J% + 1) =
    // W$(J%)`) runs as a body, and so does the FOR that fills the array from another's
    // elements. The texts, counts and faults are the interpreter's at every budget.
    let program = "DIM W$(40), S$(7)
S$(0) = \"PEAR\": S$(1) = \"APPLE\": S$(2) = \"FIG\": S$(3) = \"\": S$(4) = \"KIWI\"
S$(5) = \"APPLES\": S$(6) = \"BANANA\": S$(7) = \"apple\"
FOR I% = 1 TO 40
  W$(I%) = S$((I% * 5) MOD 8)
NEXT
FOR I% = 2 TO 40
  T$ = W$(I%): J% = I% - 1
  WHILE J% > 0
    IF W$(J%) <= T$ THEN GOTO 10
    W$(J% + 1) = W$(J%): J% = J% - 1
  WEND
10 W$(J% + 1) = T$
NEXT
";
    let (machine, summary) = run_untraced(load("body-text-put", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert!(machine.tight_runs() > 1, "{}", machine.tight_runs());
    let texts = [
        "PEAR", "APPLE", "FIG", "", "KIWI", "APPLES", "BANANA", "apple",
    ];
    let mut want: Vec<&str> = (1..=40).map(|i| texts[(i * 5) % 8]).collect();
    want.sort_unstable();
    let got: Vec<String> = (1..=40)
        .map(|i| {
            let h = machine.value_of(&format!("W$({i})")).expect("element") as usize;
            machine.strings()[h].clone()
        })
        .collect();
    assert_eq!(got, want);
    for budget in [3, 7, 50, 1_000_000] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
    // A subscript out of range in the body is the interpreter's fault, in the same place.
    let bad = program.replace("W$(J% + 1) = W$(J%)", "W$(J% + 40) = W$(J%)");
    let (_, error, _) = both("x.mb", &bad, 1_000_000);
    assert!(
        error
            .as_ref()
            .is_some_and(|e| e.2.contains("Subscript out of range")),
        "{error:?}"
    );
}

#[test]
fn a_for_too_short_to_pay_goes_back_to_the_interpreter_after_its_trial() {
    // The inner FOR runs 4 iterations of 6 instructions an entry: fewer than the 32 a hand-over
    // must pay for, so after its first 64 entries the interpreter keeps it. A FOR of 40
    // iterations is handed over at every entry. Values and counts are the same either way.
    let short = "FOR I& = 1 TO 1000
  X& = I&
  FOR K% = 1 TO 4
    Y& = Y& + (X& * K%) MOD 37
  NEXT
NEXT
";
    let (machine, summary) = run_untraced(load("body-short", "x.mb", short, 1_000_000));
    assert!(summary.error.is_none());
    // The outer loop holds the inner: it is one body, entered once; the inner is entered
    // from the interpreter only where the outer body is not run.
    let want: i64 = (1..=1000i64)
        .map(|x| (1..=4).map(|k| (x * k) % 37).sum::<i64>())
        .sum();
    assert_eq!(machine.value_of("Y&"), Some(want as f64));
    // A GOSUB in the outer loop keeps it in the interpreter, which enters the inner FOR each
    // time round.
    let called = "FOR I& = 1 TO 1000
  X& = I&
  GOSUB 100
NEXT
END
100 FOR K% = 1 TO 4
  Y& = Y& + (X& * K%) MOD 37
NEXT
RETURN
";
    let (machine, summary) = run_untraced(load("body-short-sub", "x.mb", called, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.value_of("Y&"), Some(want as f64));
    assert_eq!(machine.tight_runs(), 64, "handed over in its trial only");
    // 20 iterations (some 120 instructions an entry) do not pay either.
    let twenty = called.replace("TO 4", "TO 20");
    let (machine, _) = run_untraced(load("body-twenty-sub", "x.mb", &twenty, 1_000_000));
    assert_eq!(machine.tight_runs(), 64, "handed over in its trial only");
    let long = called.replace("TO 4", "TO 100");
    let (machine, _) = run_untraced(load("body-long-sub", "x.mb", &long, 1_000_000));
    assert_eq!(machine.tight_runs(), 1000, "handed over at every entry");
    for budget in [5, 64, 1_000_000] {
        for p in [short, called, long.as_str()] {
            assert_eq!(both("x.mb", p, budget).1, None);
        }
    }
}

#[test]
fn a_for_over_a_real_variable_runs_as_a_body_while_it_counts_whole_numbers() {
    // `FOR I = …` without a suffix counts a SINGLE: whole from a whole start by a whole step,
    // it runs outside the interpreter as a long's does. A start or step that is not whole, a
    // count past 32 bits (no Overflow for a real, the interpreter adds on) and a body that
    // writes the variable stay the interpreter's, with the same values and counts.
    let counted = "DIM H&(15)
X& = 1
FOR I = 1 TO 3000
  X& = (X& * 1103 + 12345) MOD 65536
  H&((X& \\ 16) AND 15) = H&((X& \\ 16) AND 15) + I
NEXT
";
    let (machine, summary) = run_untraced(load("body-real-for", "x.mb", counted, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    assert_eq!(machine.value_of("I"), Some(3001.0));
    let mut x: i64 = 1;
    let mut h = [0i64; 16];
    for i in 1..=3000 {
        x = (x * 1103 + 12345) % 65536;
        h[((x / 16) & 15) as usize] += i;
    }
    for (k, want) in h.iter().enumerate() {
        assert_eq!(machine.value_of(&format!("H&({k})")), Some(*want as f64));
    }
    let others = [
        counted.replace("FOR I = 1 TO 3000", "FOR I = 0.5 TO 3000"),
        counted.replace("FOR I = 1 TO 3000", "FOR I = 1 TO 3000 STEP 0.5"),
        counted
            .replace("FOR I = 1 TO 3000", "FOR I = 2147483000 TO 2147484000")
            .replace("+ I", "+ I - 2147483000"),
        counted.replace("NEXT", "IF I = 7 THEN I = I + 0.25\nNEXT"),
    ];
    for p in std::iter::once(counted.to_string()).chain(others) {
        for budget in [7, 100, 1_000_000] {
            assert_eq!(both("x.mb", &p, budget).1, None, "{p}");
        }
    }
}

#[test]
fn real_variables_given_whole_numbers_run_as_integers_in_a_body() {
    // Variables without a suffix are SINGLEs: a counter (`C = C + 1`), a remainder the body
    // tests and sums (`K = I MOD 13`), a sum of those. Given only whole numbers, the body keeps
    // them as integers and runs outside the interpreter. Counting down through negative
    // dividends, a zero remainder is -0 in the interpreter's real: those iterations are left
    // to it, which stores the sign. A variable holding a fraction when the loop starts keeps
    // this loop (all SINGLEs: no body of reals pays) in the interpreter; one the body gives a
    // fraction is a real throughout.
    let program = "C = 0: S = 0
FOR I = 1 TO 2000
  K = I MOD 13
  IF K > 6 THEN C = C + 1
  S = S + K
NEXT
";
    let (machine, summary) = run_untraced(load("body-singles", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    assert_eq!(machine.slow_runs(), 0);
    let (c, s) = (1..=2000).fold((0, 0), |(c, s), i| {
        let k = i % 13;
        (c + i64::from(k > 6), s + k)
    });
    assert_eq!(machine.value_of("C"), Some(c as f64));
    assert_eq!(machine.value_of("S"), Some(s as f64));
    assert_eq!(machine.value_of("K"), Some(2000.0 % 13.0));

    let down = program.replace("FOR I = 1 TO 2000", "FOR I = 40 TO -40 STEP -1");
    let (machine, _) = run_untraced(load("body-singles-down", "x.mb", &down, 1_000_000));
    let k = machine.value_of("K").unwrap_or(f64::NAN);
    // -40 MOD 13 is -1; the last zero was that of -39.
    assert_eq!(k, -1.0);
    assert!(
        machine.slow_runs() > 0,
        "the -0 remainders are the interpreter's"
    );
    let zero = down.replace("FOR I = 40 TO -40 STEP -1", "FOR I = 40 TO -39 STEP -1");
    let (machine, _) = run_untraced(load("body-singles-zero", "x.mb", &zero, 1_000_000));
    let k = machine.value_of("K").unwrap_or(f64::NAN);
    assert!(k == 0.0 && k.is_sign_negative(), "{k}");

    let fraction = program.replace("C = 0: S = 0", "C = 0.5: S = 0");
    let (machine, _) = run_untraced(load("body-singles-half", "x.mb", &fraction, 1_000_000));
    assert_eq!(machine.tight_runs(), 0);
    assert_eq!(machine.value_of("C"), Some(c as f64 + 0.5));
    // Longs with a SINGLE sum: kept as an integer, or (holding a fraction on entry) a real,
    // the loop running outside the interpreter either way.
    let longs = "C& = 0: S = 0
FOR I& = 1 TO 2000
  K& = I& MOD 13
  IF K& > 6 THEN C& = C& + 1
  S = S + K&
NEXT
";
    for (start, sum) in [("S = 0", s as f64), ("S = 0.5", s as f64 + 0.5)] {
        let p = longs.replace("S = 0", start);
        let (machine, _) = run_untraced(load("body-longs-sum", "x.mb", &p, 1_000_000));
        assert_eq!(machine.tight_runs(), 1, "{p}");
        assert_eq!(machine.value_of("S"), Some(sum), "{p}");
        for budget in [7, 1_000_000] {
            assert_eq!(both("x.mb", &p, budget).1, None, "{p}");
        }
    }
    let halves = program.replace("S = S + K", "S = S + K / 2");
    let (machine, _) = run_untraced(load("body-singles-halves", "x.mb", &halves, 1_000_000));
    assert_eq!(machine.value_of("S"), Some(s as f64 / 2.0));
    for p in [program.to_string(), down, zero, fraction, halves] {
        for budget in [7, 10, 33, 1_000_000] {
            assert_eq!(both("x.mb", &p, budget).1, None, "{p}");
        }
    }
}

#[test]
fn a_ring_buffer_of_singles_runs_as_a_body() {
    // A ring buffer written without suffixes: its index the remainder `P = (P + 1) MOD 16`,
    // a SINGLE kept as an integer (its zero's sign tested); the elements are SINGLEs (the
    // samples). Stepping down through negative dividends, a zero remainder (-0 in the
    // interpreter's variable) leaves the iteration at the `MOD`, which the interpreter
    // computes again: the elements stored before it stay as they are.
    let program = "DIM B(15)
P = 0: S = 0
FOR I = 1 TO 5000
  P = (P + 1) MOD 16
  B(P) = I
  S = S + P
NEXT
";
    let (machine, summary) = run_untraced(load("body-ring", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.tight_runs(), 1);
    assert_eq!(machine.slow_runs(), 0);
    let mut b = [0.0f64; 16];
    let (mut p, mut s) = (0usize, 0.0);
    for i in 1..=5000 {
        p = (p + 1) % 16;
        b[p] = f64::from(i);
        s += p as f64;
    }
    assert_eq!(machine.value_of("S"), Some(s));
    for (k, want) in b.iter().enumerate() {
        assert_eq!(machine.value_of(&format!("B({k})")), Some(*want), "B({k})");
    }
    let down = program
        .replace("P = 0: S = 0", "P = 0: S = 0: Q = 0")
        .replace("P = (P + 1) MOD 16", "Q = (7 - I) MOD 16: P = Q AND 15");
    let (machine, _) = run_untraced(load("body-ring-down", "x.mb", &down, 1_000_000));
    assert!(machine.tight_runs() >= 1);
    assert!(
        machine.slow_runs() > 0,
        "the -0 remainders are the interpreter's"
    );
    let q = machine.value_of("Q").unwrap_or(f64::NAN);
    assert_eq!(q, (7.0 - 5000.0) % 16.0);
    let zero = down.replace("FOR I = 1 TO 5000", "FOR I = 1 TO 4999");
    let (machine, _) = run_untraced(load("body-ring-zero", "x.mb", &zero, 1_000_000));
    let q = machine.value_of("Q").unwrap_or(f64::NAN);
    assert!(q == 0.0 && q.is_sign_negative(), "{q}");
    for p in [program.to_string(), down, zero] {
        for budget in [7, 10, 33, 1_000_000] {
            assert_eq!(both("x.mb", &p, budget).1, None, "{p}");
        }
    }
}

#[test]
fn a_do_loop_that_tests_at_its_end_runs_as_a_body() {
    // `DO … LOOP UNTIL c` is its body, a jump out unless `c`, and a jump back: the machine
    // runs it as it runs a `WHILE`, with the interpreter's values and counts at every budget,
    // an `EXIT DO` included.
    let program = "N& = 0: S& = 0
DO
  N& = N& + 1
  S& = (S& + N& * 7) MOD 1000003
  IF S& = 12345 THEN EXIT DO
LOOP UNTIL N& >= 30000
";
    let (machine, summary) = run_untraced(load("body-do-loop", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert!(machine.tight_runs() >= 1);
    let (mut n, mut s) = (0i64, 0i64);
    loop {
        n += 1;
        s = (s + n * 7) % 1_000_003;
        if s == 12345 || n >= 30000 {
            break;
        }
    }
    assert_eq!(machine.value_of("N&"), Some(n as f64));
    assert_eq!(machine.value_of("S&"), Some(s as f64));
    for budget in [7, 100, 1_000_000] {
        assert_eq!(both("x.mb", program, budget).1, None);
    }
}

/// The values `SUB_PROGRAM` leaves after `n` iterations: S&, C&, D&.
fn sub_values(n: i64) -> (i64, i64, i64) {
    let (mut s, mut c, mut d) = (0i64, 0i64, 0i64);
    for i in 1..=n {
        s = (s + i * 3) % 1_000_003;
        if s % 100 > 50 {
            c += 1;
        }
        if c > 5 {
            d += c * i;
            c = 0;
        }
    }
    (s, c, d)
}

/// A loop calling two subroutines, one of them conditionally (MotionBASIC: control returns
/// to the statement after the GOSUB).
const SUB_PROGRAM: &str = "S& = 0: C& = 0: D& = 0
FOR I& = 1 TO 3000
  S& = (S& + I& * 3) MOD 1000003
  GOSUB 100
  IF C& > 5 THEN GOSUB 200
NEXT
END
100 IF S& MOD 100 > 50 THEN C& = C& + 1
RETURN
200 D& = D& + C& * I&: C& = 0
RETURN
";

#[test]
fn a_loop_calling_subroutines_runs_them_inside_its_body() {
    let (machine, summary) = run_untraced(load("body-gosub", "x.mb", SUB_PROGRAM, 1_000_000));
    assert!(summary.error.is_none());
    // Entered once, every iteration run outside the interpreter with its subroutines.
    assert_eq!(machine.tight_runs(), 1);
    assert_eq!(machine.slow_runs(), 0);
    let (s, c, d) = sub_values(3000);
    assert!(d > 0 && c < 6, "both subroutines called: {d}, {c}");
    assert_eq!(machine.value_of("S&"), Some(s as f64));
    assert_eq!(machine.value_of("C&"), Some(c as f64));
    assert_eq!(machine.value_of("D&"), Some(d as f64));
    // Its budget spent after a GOSUB or a RETURN, a run stops where the interpreter yields
    // (inside the subroutine, in its frame, or after it): the same counts at every budget.
    for budget in [3, 5, 7, 10, 33, 1000, 1_000_000] {
        let (n, e, _) = both("x.mb", SUB_PROGRAM, budget);
        assert_eq!((n, e), (summary.instructions, None), "budget {budget}");
    }
}

#[test]
fn a_turn_starting_inside_a_subroutine_hands_the_loop_back_at_once() {
    // At a budget of 1000 most turns end after a GOSUB or a RETURN (a run stops there as the
    // interpreter yields there): the next turn runs the rest of that iteration in the
    // interpreter and gives the loop back to the machine, so nearly every turn runs it.
    let long = SUB_PROGRAM.replace("TO 3000", "TO 30000");
    let (machine, summary) = run_untraced(load("body-gosub-turns", "x.mb", &long, 1000));
    assert!(summary.error.is_none());
    let turns = summary.instructions / 1000;
    assert!(turns > 300, "{turns} turns");
    assert!(
        machine.tight_runs() * 10 >= turns * 9,
        "{} runs in {turns} turns",
        machine.tight_runs()
    );
    let (s, c, d) = sub_values(30000);
    assert_eq!(machine.value_of("S&"), Some(s as f64));
    assert_eq!(machine.value_of("C&"), Some(c as f64));
    assert_eq!(machine.value_of("D&"), Some(d as f64));
    assert_eq!(both("x.mb", &long, 1000).0, summary.instructions);
}

#[test]
fn a_fault_in_a_subroutine_run_inside_a_body_is_reported_in_the_subroutine() {
    // S& passes 2^31 at I& = 66 (1,000,000 * 66 * 67 / 2): the overflow is the subroutine's,
    // the 65 iterations before done.
    let program = "FOR I& = 1 TO 100
  GOSUB 100
NEXT
END
100 S& = S& + 1000000 * I&
RETURN
";
    let (machine, summary) = run_untraced(load("body-gosub-fault", "x.mb", program, 1_000_000));
    assert_eq!(machine.tight_runs(), 1);
    let error = summary.error.as_ref().expect("an overflow");
    assert_eq!(error.line, 5);
    assert_eq!(machine.value_of("S&"), Some(2_145_000_000.0));
    assert_eq!(machine.value_of("I&"), Some(66.0));
    for budget in [4, 7, 1_000_000] {
        let (n, e, _) = both("x.mb", program, budget);
        assert_eq!(n, summary.instructions);
        assert_eq!(e.map(|e| e.0), Some(5));
    }
}

#[test]
fn an_iteration_left_inside_a_subroutine_goes_on_there_and_returns() {
    // A remainder of a negative multiple of 10 is a -0 the SINGLE R takes with its sign: the
    // iteration is left at that MOD, inside the subroutine; the interpreter goes on there in
    // the GOSUB's frame, returns, and counts T&.
    let program = "FOR I& = -20 TO 20
  A& = I& * 5
  GOSUB 100
  T& = T& + 1
NEXT
END
100 R = A& MOD 10
S = S + R
RETURN
";
    let (machine, summary) = run_untraced(load("body-gosub-slow", "x.mb", program, 1_000_000));
    assert!(summary.error.is_none());
    assert_eq!(machine.value_of("T&"), Some(41.0));
    assert!(machine.tight_runs() >= 1);
    assert!(
        machine.slow_runs() >= 1,
        "an iteration left in the subroutine"
    );
    let s: i64 = (-20..=20i64).map(|i| (i * 5) % 10).sum();
    assert_eq!(machine.value_of("S"), Some(s as f64));
    for budget in [3, 6, 1_000_000] {
        let (n, e, _) = both("x.mb", program, budget);
        assert_eq!((n, e), (summary.instructions, None));
    }
}

#[test]
fn a_body_does_not_call_a_subroutine_one_frame_too_deep() {
    // Fourteen GOSUBs deep (the program's frame and 14 of theirs), the loop's GOSUB would be
    // the 16th frame's: the interpreter runs it and reports the depth. Thirteen deep, the
    // body runs its GOSUBs.
    let program = |deep: u32| {
        format!(
            "GOSUB 100
END
100 D& = D& + 1
IF D& < {deep} THEN GOSUB 100 ELSE GOSUB 300
RETURN
300 FOR I& = 1 TO 100
  GOSUB 400
NEXT
RETURN
400 S& = S& + I&
RETURN
"
        )
    };
    let (machine, summary) = run_untraced(load("body-deep", "x.mb", &program(13), 1_000_000));
    assert!(summary.error.is_none(), "{:?}", summary.error);
    assert_eq!(machine.value_of("S&"), Some(5050.0));
    assert_eq!(machine.tight_runs(), 1);
    let (machine, summary) = run_untraced(load("body-deeper", "x.mb", &program(14), 1_000_000));
    assert_eq!(machine.tight_runs(), 0);
    let error = summary.error.as_ref().expect("too deep");
    assert_eq!(error.line, 7);
    assert!(error.message.contains("nested deeper"), "{}", error.message);
    for deep in [13, 14] {
        for budget in [5, 1_000_000] {
            let (_, e, _) = both("x.mb", &program(deep), budget);
            assert_eq!(e.is_some(), deep == 14);
        }
    }
}

#[test]
fn two_tasks_see_each_other_where_the_interpreter_would_yield() {
    // Task 1 folds task 0's variables into a hash at every instruction it runs: where task 0's
    // turns end (inside its subroutine, after it, at its NEXT) shows in H&. Untraced (the
    // subroutine run inside task 0's body) and traced (the interpreter) give the same.
    let a = "FOR I& = 1 TO 2000
  A& = A& + 1
  GOSUB 100
  B& = B& + 1
NEXT
END
100 C& = C& + A& MOD 3
RETURN
";
    let b = "FOR K& = 1 TO 3000
  H& = (H& * 31 + A& + B& * 7 + C&) MOD 1000003
NEXT
";
    for budget in [3, 5, 7, 11, 64, 1000] {
        let machine = format!(
            "[machine]\nname = \"t\"\nbudget = {budget}\n\n[[program]]\nnumber = 0\nfile = \"a.mb\"\n\
             autostart = true\n\n[[program]]\nnumber = 1\nfile = \"b.mb\"\nautostart = true\n"
        );
        let files = [("a.mb", a), ("b.mb", b), ("machine.toml", machine.as_str())];
        let loaded = || match load_memory("tasks", &files) {
            Ok(l) => l,
            Err(d) => panic!("{}", d.render_plain()),
        };
        let traced = run_loaded(loaded());
        let (machine, summary) = run_untraced(loaded());
        assert!(machine.tight_runs() > 0);
        assert_eq!(
            outcome(&traced.machine, &traced.summary),
            outcome(&machine, &summary),
            "budget {budget}"
        );
        assert_eq!(machine.value_of("B&"), Some(2000.0));
    }
}

/// A machine of the PowerTools programs `programs` (program n in `pn.pt`; those in
/// `autostart` started), its whole variables S, K, X, I, Y, H and `D` of two decimals, at
/// `budget`: the outcome traced (the interpreter) and untraced, with the untraced machine and
/// the program of its error.
#[allow(clippy::type_complexity)]
fn pt_machines(
    programs: &[&str],
    autostart: &[u32],
    budget: u32,
) -> (
    (Vec<u64>, u64, Option<(u32, u32, String)>),
    (Vec<u64>, u64, Option<(u32, u32, String)>),
    Machine,
    Option<u32>,
) {
    let mut machine = format!("[machine]\nname = \"calls\"\nbudget = {budget}\n");
    for (n, _) in programs.iter().enumerate() {
        let auto = autostart.contains(&(n as u32));
        machine.push_str(&format!(
            "\n[[program]]\nnumber = {n}\nfile = \"p{n}.pt\"\nautostart = {auto}\n"
        ));
    }
    for v in ["S", "K", "X", "I", "Y", "H"] {
        machine.push_str(&format!("[variables.{v}]\n"));
    }
    machine.push_str("[variables.D]\ndecimals = 2\n");
    let names: Vec<String> = (0..programs.len()).map(|n| format!("p{n}.pt")).collect();
    let mut files: Vec<(&str, &str)> = names
        .iter()
        .zip(programs)
        .map(|(n, p)| (n.as_str(), *p))
        .collect();
    files.push(("machine.toml", &machine));
    let loaded = || match load_memory("calls", &files) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let traced = run_loaded(loaded());
    assert_eq!(traced.machine.tight_runs(), 0);
    let (machine, summary) = run_untraced(loaded());
    let program = summary.error.as_ref().map(|e| e.program);
    assert_eq!(program, traced.summary.error.as_ref().map(|e| e.program));
    (
        outcome(&traced.machine, &traced.summary),
        outcome(&machine, &summary),
        machine,
        program,
    )
}

/// bench/call's PowerTools programs in small: a loop calling a program that folds its
/// argument into a sum (PowerTools `Call Program`: the caller goes on after the called
/// program's `End`).
const CALLER: &str =
    "Var.S = 0\nVar.K = 0\nFor Var.I = 1 To 3000\n  Var.X = Var.I\n  Call Program.1\nNext\nEnd\n";
const CALLED: &str = "Var.S = Var.S + Var.X MOD 13\nIf Var.S > 1000 Then\n  Var.S = Var.S - 1000\n  Var.K = Var.K + 1\nEndif\nEnd\n";

#[test]
fn a_loop_calling_a_program_runs_it_inside_its_body() {
    let (mut s, mut k) = (0i64, 0i64);
    for i in 1..=3000i64 {
        s += i % 13;
        if s > 1000 {
            s -= 1000;
            k += 1;
        }
    }
    for budget in [3, 5, 7, 10, 33, 1000, 1_000_000] {
        let (traced, untraced, machine, _) = pt_machines(&[CALLER, CALLED], &[0], budget);
        assert_eq!(traced, untraced, "budget {budget}");
        assert!(machine.tight_runs() > 0);
        if budget == 1_000_000 {
            // Entered once, every iteration outside the interpreter with the program called.
            assert_eq!((machine.tight_runs(), machine.slow_runs()), (1, 0));
        }
        assert_eq!(slot_value(&machine, "Var.S"), Some(s as f64));
        assert_eq!(slot_value(&machine, "Var.K"), Some(k as f64));
        assert!(untraced.2.is_none());
    }
}

#[test]
fn a_fault_in_a_program_called_inside_a_body_is_that_program_s() {
    // At I = 50 the called program takes a remainder by zero: its fault, at its line, the
    // 49 calls before done.
    let called = "Var.S = Var.S + Var.X MOD (Var.X - 50)\nEnd\n";
    for budget in [4, 7, 1_000_000] {
        let (traced, untraced, machine, program) = pt_machines(&[CALLER, called], &[0], budget);
        assert_eq!(traced, untraced, "budget {budget}");
        assert_eq!(untraced.2.as_ref().map(|e| e.0), Some(1));
        assert_eq!(program, Some(1), "the error is program 1's");
        assert_eq!(slot_value(&machine, "Var.I"), Some(50.0));
        assert!(machine.tight_runs() > 0);
    }
}

#[test]
fn a_body_does_not_call_a_program_running_on_another_task() {
    // Program 1 waits on a task of its own: the loop's call is the interpreter's fault.
    let waiting = "Wait For Var.H = 1\nEnd\n";
    let (traced, untraced, machine, _) = pt_machines(&[CALLER, waiting], &[0, 1], 1_000_000);
    assert_eq!(traced, untraced);
    let message = untraced.2.map(|e| e.2).unwrap_or_default();
    assert!(message.contains("already running"), "{message}");
    assert_eq!(machine.tight_runs(), 0);
}

#[test]
fn two_tasks_see_a_program_called_inside_a_body_where_the_interpreter_would_yield() {
    // Program 2, on a task of its own, hashes what the loop and the program it calls write:
    // where task 0's turns end shows in H.
    let hash = "For Var.Y = 1 To 4000\n  Var.H = (Var.H * 31 + Var.S + Var.K * 7 + Var.X) MOD 1000003\nNext\nEnd\n";
    for budget in [3, 5, 7, 11, 64, 1000] {
        let (traced, untraced, machine, _) = pt_machines(&[CALLER, CALLED, hash], &[0, 2], budget);
        assert_eq!(traced, untraced, "budget {budget}");
        assert!(machine.tight_runs() > 0);
    }
}

#[test]
fn powertools_quotients_into_whole_variables_run_as_the_interpreter_rounds_them() {
    // PowerTools has no integer division: `/` divides as reals, and a whole variable stores
    // the quotient rounded (halves away from zero), alone or added to (taken from) a whole
    // variable. Each is one instruction of a body: the same values, counts and faults as the
    // interpreter's, halves and negative quotients included.
    let program = "Var.A = 0\nVar.B = 0\nVar.C = 7\nFor Var.I = -300 To 300\n  Var.A = Var.I / 4\n  Var.B = Var.B + Var.I / 3\n  Var.C = Var.C - Var.I / 8\n  Var.E = (Var.I * 1000) / (Var.I + 307)\nNext\nEnd\n";
    let (machine, summary) = run_untraced(load("pt-quotients", "x.pt", program, 1_000_000));
    assert!(summary.error.is_none(), "{:?}", summary.error);
    assert_eq!(machine.tight_runs(), 1);
    let round = |x: f64| {
        let r = x.round();
        // `f64::round` takes halves away from zero, as the fixed-point store does here (no
        // quotient below is within the store's slack of a half without being one).
        if r == 0.0 {
            0.0
        } else {
            r
        }
    };
    let (mut b, mut c) = (0.0f64, 7.0f64);
    for i in -300..=300i32 {
        let i = f64::from(i);
        b = round(b + i / 3.0);
        c = round(c - i / 8.0);
    }
    assert_eq!(slot_value(&machine, "Var.A"), Some(75.0));
    assert_eq!(slot_value(&machine, "Var.B"), Some(b));
    assert_eq!(slot_value(&machine, "Var.C"), Some(c));
    assert_eq!(
        slot_value(&machine, "Var.E"),
        Some(round(300_000.0 / 607.0))
    );
    for budget in [7, 10, 1_000_000] {
        assert_eq!(both("x.pt", program, budget).1, None);
    }
    // A divisor of 0 (at I = -250) and a sum past 32 bits are the interpreter's faults, at
    // their lines.
    let zero = program.replace("+ 307", "+ 250");
    let (_, summary) = run_untraced(load("pt-quotients-zero", "x.pt", &zero, 1_000_000));
    let error = summary.error.as_ref().expect("a division by zero");
    assert_eq!(error.line, 8);
    let past = "Var.J = 0\nFor Var.I = 1 To 10\n  Var.J = Var.J + 1500000000 / 1\nNext\nEnd\n";
    let (machine, summary) = run_untraced(load("pt-quotients-past", "x.pt", past, 1_000_000));
    assert_eq!(summary.error.as_ref().map(|e| e.line), Some(3));
    assert_eq!(slot_value(&machine, "Var.J"), Some(1_500_000_000.0));
    for budget in [5, 1_000_000] {
        assert_eq!(both("x.pt", &zero, budget).1.map(|e| e.0), Some(8));
        assert_eq!(both("x.pt", past, budget).1.map(|e| e.0), Some(3));
    }
}

#[test]
fn a_loop_given_back_by_its_trial_is_tried_again_later() {
    // Each loop's first 64 entries go round once or twice, too few to pay for a hand-over: the
    // interpreter keeps it. Later entries go round 100 and 150 times: some million of the
    // machine's instructions after its trial failed, the loop is tried again, and handed over
    // from then on. Values and counts are the interpreter's either way.
    let while_loop = "T& = 0
FOR I& = 1 TO 3000
  P& = I& ^ 1
  N& = 1
  IF I& > 64 THEN N& = 100
  WHILE N& > 0
    T& = T& + N& MOD 7
    N& = N& - 1
  WEND
NEXT
";
    let for_loop = "T& = 0
FOR I& = 1 TO 3000
  P& = I& ^ 1
  N& = 2
  IF I& > 64 THEN N& = 150
  FOR K& = 1 TO N&
    T& = T& + (K& * I&) MOD 7
  NEXT
NEXT
";
    let while_sum: i64 = (1..=3000i64)
        .map(|i| {
            let n = if i > 64 { 100 } else { 1 };
            (1..=n).map(|k| k % 7).sum::<i64>()
        })
        .sum();
    let for_sum: i64 = (1..=3000i64)
        .map(|i| {
            let n = if i > 64 { 150 } else { 2 };
            (1..=n).map(|k| (k * i) % 7).sum::<i64>()
        })
        .sum();
    for (name, program, sum) in [
        ("retry-while", while_loop, while_sum),
        ("retry-for", for_loop, for_sum),
    ] {
        let (machine, summary) = run_untraced(load(name, "x.mb", program, 10_000));
        assert!(summary.error.is_none(), "{name}: {:?}", summary.error);
        assert_eq!(machine.value_of("T&"), Some(sum as f64), "{name}");
        // The trial's 64 entries, then (past 2^20 instructions, of some 2.1 and 2.7 million)
        // every entry of the rest: more than a thousand.
        let runs = machine.tight_runs();
        assert!(runs > 1_000, "{name}: {runs} runs outside the interpreter");
        for budget in [7, 10_000] {
            let (_, error, untraced_runs) = both("x.mb", program, budget);
            assert_eq!(error, None, "{name}");
            assert!(untraced_runs > 64, "{name} at {budget}: {untraced_runs}");
        }
    }
}
