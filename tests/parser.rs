//! The PowerTools front end: one test per construct, operator precedence checked on the shape
//! of the tree, and syntax errors (all of them, with exact spans).

use pacer::diag::Problem;
use pacer::span::Span;
use pacer::syntax::ast::{
    BinOp, Expr, ExprKind, Name, NumForm, ProgramAst, Stmt, StmtKind, UnOp, Using,
};
use pacer::syntax::parse_program;

// ---------------------------------------------------------------------------------------------
// helpers

/// Parse, asserting there is no problem at all.
fn parse_ok(src: &str) -> ProgramAst {
    let mut problems = Vec::new();
    let ast = parse_program(src, &mut problems);
    assert!(
        problems.is_empty(),
        "expected no problems for {src:?}, got {problems:#?}"
    );
    ast
}

/// Parse, returning the problems (which must not be empty).
fn parse_err(src: &str) -> (ProgramAst, Vec<Problem>) {
    let mut problems = Vec::new();
    let ast = parse_program(src, &mut problems);
    assert!(!problems.is_empty(), "expected problems for {src:?}");
    (ast, problems)
}

/// The one statement of a one-statement program.
fn single(src: &str) -> Stmt {
    let ast = parse_ok(src);
    assert_eq!(
        ast.body.len(),
        1,
        "expected one statement in {src:?}: {ast:#?}"
    );
    ast.body.into_iter().next().unwrap()
}

/// The span of the first occurrence of `needle` in `src`.
fn at(src: &str, needle: &str) -> Span {
    let start = src
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in {src:?}"));
    Span::new(start, start + needle.len())
}

/// The span of the `n`-th (0-based) occurrence of `needle` in `src`.
fn at_nth(src: &str, needle: &str, n: usize) -> Span {
    let start = src
        .match_indices(needle)
        .nth(n)
        .unwrap_or_else(|| panic!("occurrence {n} of {needle:?} not in {src:?}"))
        .0;
    Span::new(start, start + needle.len())
}

fn text(src: &str, span: Span) -> &str {
    &src[span.start..span.end]
}

/// An expression as an S-expression, to check the shape the parser built.
fn shape(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(v, _) => format!("{v}"),
        ExprKind::Bool(true) => "ON".into(),
        ExprKind::Bool(false) => "OFF".into(),
        ExprKind::Name(n) => n.text(),
        ExprKind::Unary(UnOp::Neg, x) => format!("(neg {})", shape(x)),
        ExprKind::Unary(UnOp::Not, x) => format!("(NOT {})", shape(x)),
        ExprKind::Binary(op, a, b) => format!("({} {} {})", op.symbol(), shape(a), shape(b)),
        ExprKind::Call(f, args) => {
            let args: Vec<String> = args.iter().map(shape).collect();
            format!("{}[{}]", f.text, args.join(", "))
        }
        ExprKind::Paren(x) => format!("<{}>", shape(x)),
        ExprKind::Str(t) => format!("{t:?}"),
        ExprKind::AxisSet(items) => {
            let items: Vec<String> = items.iter().map(shape).collect();
            format!("{{{}}}", items.join(", "))
        }
    }
}

/// The value of `Var.X = <expr>`.
fn expr_of(expr_src: &str) -> (String, Expr) {
    let src = format!("Var.X = {expr_src}");
    let s = single(&src);
    match s.kind {
        StmtKind::Assign { value, .. } => (src, value),
        other => panic!("not an assignment: {other:?}"),
    }
}

fn shape_of(expr_src: &str) -> String {
    shape(&expr_of(expr_src).1)
}

fn segments(n: &Name) -> Vec<&str> {
    n.segments.iter().map(|s| s.text.as_str()).collect()
}

/// Names assigned at top level, in order (to see which lines survived an error).
fn assigned(ast: &ProgramAst) -> Vec<String> {
    ast.body
        .iter()
        .filter_map(|s| match &s.kind {
            StmtKind::Assign { target, .. } => Some(target.text()),
            _ => None,
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// statements

#[test]
fn assignment() {
    let src = "Var.Count = 5";
    let s = single(src);
    assert_eq!(s.span, Span::new(0, src.len()));
    let StmtKind::Assign { target, value } = s.kind else {
        panic!("not an assignment: {s:?}")
    };
    assert_eq!(target.text(), "Var.Count");
    assert_eq!(segments(&target), ["Var", "Count"]);
    assert_eq!(target.span, at(src, "Var.Count"));
    assert_eq!(target.segments[1].span, at(src, "Count"));
    assert_eq!(value.kind, ExprKind::Number(5.0, NumForm::Whole));
    assert_eq!(value.span, at(src, "5"));
}

#[test]
fn assignment_of_object_member_without_spaces() {
    let src = "Queue.0.QueueOffset=Queue.0.QueueOffset + 0.10";
    let s = single(src);
    let StmtKind::Assign { target, value } = s.kind else {
        panic!("not an assignment: {s:?}")
    };
    assert_eq!(segments(&target), ["Queue", "0", "QueueOffset"]);
    assert_eq!(target.segments[1].span, at(src, "0"));
    assert_eq!(shape(&value), "(+ Queue.0.QueueOffset 0.1)");
    assert_eq!(text(src, value.span), "Queue.0.QueueOffset + 0.10");
}

#[test]
fn bare_action() {
    let src = "Queue.0.QueueRemove";
    let s = single(src);
    assert_eq!(s.span, at(src, src));
    let StmtKind::Action {
        target,
        using,
        profile,
    } = s.kind
    else {
        panic!("not an action: {s:?}")
    };
    assert_eq!(segments(&target), ["Queue", "0", "QueueRemove"]);
    assert_eq!(using, None);
    assert_eq!(profile, None);

    // A bare global action.
    let s = single("Gear.Initiate");
    assert!(
        matches!(s.kind, StmtKind::Action { ref target, .. } if target.text() == "Gear.Initiate")
    );
}

fn action_parts(src: &str) -> (Name, Option<Using>, Option<Name>) {
    match single(src).kind {
        StmtKind::Action {
            target,
            using,
            profile,
        } => (target, using, profile),
        other => panic!("not an action: {other:?}"),
    }
}

#[test]
fn initiate_using_last() {
    let src = "Index.0.Initiate Using Last";
    let (target, using, profile) = action_parts(src);
    assert_eq!(target.text(), "Index.0.Initiate");
    assert_eq!(target.span, at(src, "Index.0.Initiate"));
    assert_eq!(using, Some(Using::Last(at(src, "Using Last"))));
    assert_eq!(profile, None);
}

#[test]
fn initiate_using_capture() {
    let src = "Index.0.Initiate Using Capture.1";
    let (target, using, profile) = action_parts(src);
    assert_eq!(target.text(), "Index.0.Initiate");
    let Some(Using::Capture(c)) = using else {
        panic!("expected Using Capture, got {using:?}")
    };
    assert_eq!(segments(&c), ["Capture", "1"]);
    assert_eq!(c.span, at(src, "Capture.1"));
    assert_eq!(profile, None);
}

#[test]
fn initiate_on_profile() {
    let src = "Index.1.Initiate On Profile.1";
    let (target, using, profile) = action_parts(src);
    assert_eq!(target.text(), "Index.1.Initiate");
    assert_eq!(using, None);
    let p = profile.expect("a profile");
    assert_eq!(segments(&p), ["Profile", "1"]);
    assert_eq!(p.span, at(src, "Profile.1"));
}

#[test]
fn initiate_with_both_modifiers_in_either_order() {
    let src = "Index.0.Initiate Using Capture.1 On Profile.1";
    let (_, using, profile) = action_parts(src);
    assert!(matches!(using, Some(Using::Capture(ref c)) if c.span == at(src, "Capture.1")));
    assert_eq!(profile.expect("a profile").span, at(src, "Profile.1"));

    let src = "Jog.0.PlusInitiate On Profile.0 Using Last";
    let (target, using, profile) = action_parts(src);
    assert_eq!(target.text(), "Jog.0.PlusInitiate");
    assert_eq!(using, Some(Using::Last(at(src, "Using Last"))));
    assert_eq!(profile.expect("a profile").text(), "Profile.0");
}

#[test]
fn a_second_using_or_profile_is_an_error() {
    let src = "Index.0.Initiate Using Last Using Capture.1";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax::modifier");
    assert_eq!(problems[0].message, "a second `Using`");
    assert_eq!(problems[0].span, at(src, "Capture.1"));

    let src = "Index.0.Initiate On Profile.0 On Profile.1";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax::modifier");
    assert_eq!(problems[0].message, "a second `On Profile`");
    assert_eq!(problems[0].span, at(src, "Profile.1"));
}

#[test]
fn dwell_for_time() {
    let src = "Dwell For Time 0.5";
    let s = single(src);
    assert_eq!(s.span, at(src, src));
    let StmtKind::DwellTime(e, _) = s.kind else {
        panic!("not a dwell: {s:?}")
    };
    assert_eq!(e.kind, ExprKind::Number(0.5, NumForm::Real));
    assert_eq!(e.span, at(src, "0.5"));

    let s = single("Dwell For Time Var.T * 2");
    let StmtKind::DwellTime(e, _) = s.kind else {
        panic!("not a dwell: {s:?}")
    };
    assert_eq!(shape(&e), "(* Var.T 2)");
}

#[test]
fn dwell_for_master_dist() {
    let src = "Dwell For Master Dist 12.5";
    let s = single(src);
    let StmtKind::DwellMaster(e, _) = s.kind else {
        panic!("not a master dwell: {s:?}")
    };
    assert_eq!(e.kind, ExprKind::Number(12.5, NumForm::Real));
    assert_eq!(e.span, at(src, "12.5"));
}

#[test]
fn wait_for_time() {
    let src = "Wait For Time 1.5";
    let s = single(src);
    let StmtKind::WaitTime(e) = s.kind else {
        panic!("not a timed wait: {s:?}")
    };
    assert_eq!(e.kind, ExprKind::Number(1.5, NumForm::Real));
    assert_eq!(e.span, at(src, "1.5"));
}

#[test]
fn wait_for_expression() {
    let src = "Wait For DriveInput.4=ON";
    let s = single(src);
    let StmtKind::WaitFor(e) = s.kind else {
        panic!("not a wait: {s:?}")
    };
    assert_eq!(shape(&e), "(= DriveInput.4 ON)");
    assert_eq!(e.span, at(src, "DriveInput.4=ON"));

    // A bare bit is a condition too.
    let s = single("Wait For Queue.0.QueueEmpty");
    assert!(matches!(s.kind, StmtKind::WaitFor(ref e) if shape(e) == "Queue.0.QueueEmpty"));

    let src = "Wait For (DriveInput.4=ON OR DriveInput.5=ON)";
    let s = single(src);
    let StmtKind::WaitFor(e) = s.kind else {
        panic!("not a wait: {s:?}")
    };
    assert_eq!(shape(&e), "<(OR (= DriveInput.4 ON) (= DriveInput.5 ON))>");
    assert_eq!(e.span, at(src, "(DriveInput.4=ON OR DriveInput.5=ON)"));
}

#[test]
fn if_then_else_endif() {
    let src = "If Var.A > 1 Then\nVar.B = 1\nVar.C = 1\nElse\nVar.B = 2\nEndif\nVar.D = 4\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 2);
    let s = &ast.body[0];
    assert_eq!(s.span, at(src, "If Var.A > 1 Then"));
    let StmtKind::If {
        cond,
        then_body,
        else_body,
    } = &s.kind
    else {
        panic!("not an If: {s:?}")
    };
    assert_eq!(shape(cond), "(> Var.A 1)");
    assert_eq!(then_body.len(), 2);
    assert_eq!(then_body[0].span, at(src, "Var.B = 1"));
    assert_eq!(then_body[1].span, at(src, "Var.C = 1"));
    let else_body = else_body.as_ref().expect("an Else");
    assert_eq!(else_body.len(), 1);
    assert_eq!(else_body[0].span, at(src, "Var.B = 2"));
    assert_eq!(ast.body[1].span, at(src, "Var.D = 4"));
}

#[test]
fn if_without_else_and_end_if_in_two_words() {
    let src = "If DriveInput.1 = ON Then\nVar.B = 1\nEnd If\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 1);
    let StmtKind::If {
        then_body,
        else_body,
        ..
    } = &ast.body[0].kind
    else {
        panic!("not an If")
    };
    assert_eq!(then_body.len(), 1);
    assert!(else_body.is_none());
}

#[test]
fn nested_ifs() {
    // The layout of Program 2 of the labeler.
    let src = "If (DriveInput.4=ON) Then\n\nIf (DriveInput.6=ON) Then\nVar.A = 1\n\nElse\nVar.A = 2\n\nEndif\nElse\nVar.A = 3\nEndif\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 1);
    let StmtKind::If {
        then_body,
        else_body,
        ..
    } = &ast.body[0].kind
    else {
        panic!("not an If")
    };
    assert_eq!(then_body.len(), 1);
    let StmtKind::If {
        cond,
        then_body: inner_then,
        else_body: inner_else,
    } = &then_body[0].kind
    else {
        panic!("not a nested If")
    };
    assert_eq!(shape(cond), "<(= DriveInput.6 ON)>");
    assert_eq!(inner_then.len(), 1);
    assert_eq!(inner_else.as_ref().map(Vec::len), Some(1));
    assert_eq!(else_body.as_ref().map(Vec::len), Some(1));
    assert_eq!(else_body.as_ref().unwrap()[0].span, at(src, "Var.A = 3"));
}

#[test]
fn do_while_loop() {
    let src = "Do While Var.I < 10\nVar.I = Var.I + 1\nLoop\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 1);
    assert_eq!(ast.body[0].span, at(src, "Do While Var.I < 10"));
    let StmtKind::DoWhile { cond, body } = &ast.body[0].kind else {
        panic!("not a Do While")
    };
    assert_eq!(shape(cond), "(< Var.I 10)");
    assert_eq!(body.len(), 1);
    assert_eq!(body[0].span, at(src, "Var.I = Var.I + 1"));

    let s = parse_ok("Do While TRUE\nLoop\n");
    assert!(
        matches!(&s.body[0].kind, StmtKind::DoWhile { cond, body } if cond.kind == ExprKind::Bool(true) && body.is_empty())
    );
}

#[test]
fn for_to_step_next() {
    let src = "For Var.I = 1 To 10 Step 2\nVar.S = Var.S + Var.I\nNext Var.I\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 1);
    assert_eq!(ast.body[0].span, at(src, "For Var.I = 1 To 10 Step 2"));
    let StmtKind::For {
        var,
        from,
        to,
        step,
        body,
    } = &ast.body[0].kind
    else {
        panic!("not a For")
    };
    assert_eq!(var.text(), "Var.I");
    assert_eq!(var.span, at(src, "Var.I"));
    assert_eq!(from.kind, ExprKind::Number(1.0, NumForm::Whole));
    assert_eq!(to.kind, ExprKind::Number(10.0, NumForm::Whole));
    assert_eq!(step.as_ref().map(shape).as_deref(), Some("2"));
    assert_eq!(body.len(), 1);

    // No Step, bare Next, expressions as bounds, a negative step.
    let ast = parse_ok("For Var.I = Var.A + 1 To Var.B * 2\nNext\n");
    let StmtKind::For { from, to, step, .. } = &ast.body[0].kind else {
        panic!("not a For")
    };
    assert_eq!(shape(from), "(+ Var.A 1)");
    assert_eq!(shape(to), "(* Var.B 2)");
    assert!(step.is_none());

    let ast = parse_ok("For Var.I = 10 To 1 Step -1\nNext\n");
    let StmtKind::For { step, .. } = &ast.body[0].kind else {
        panic!("not a For")
    };
    assert_eq!(step.as_ref().map(shape).as_deref(), Some("(neg 1)"));
}

#[test]
fn call_program() {
    let src = "Call Program.2";
    let s = single(src);
    let StmtKind::Call(n) = s.kind else {
        panic!("not a Call: {s:?}")
    };
    assert_eq!(segments(&n), ["Program", "2"]);
    assert_eq!(n.span, at(src, "Program.2"));
}

#[test]
fn program_initiate_is_an_action() {
    let (target, using, profile) = action_parts("Program.1.Initiate");
    assert_eq!(segments(&target), ["Program", "1", "Initiate"]);
    assert!(using.is_none() && profile.is_none());
}

#[test]
fn labels_goto_and_jump() {
    let src = "Top:\nVar.A = Var.A + 1\nGoto Top\nJump Top\nJump To Top\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 5);
    let StmtKind::Label(l) = &ast.body[0].kind else {
        panic!("not a label")
    };
    assert_eq!(l.text, "Top");
    assert_eq!(l.span, at(src, "Top"));
    assert_eq!(ast.body[0].span, at(src, "Top:"));
    for (i, n) in [(2, 1), (3, 2), (4, 3)] {
        let StmtKind::Goto(g) = &ast.body[i].kind else {
            panic!("statement {i} is not a Goto: {:?}", ast.body[i])
        };
        assert_eq!(g.text, "Top");
        assert_eq!(g.span, at_nth(src, "Top", n));
    }
}

#[test]
fn end_statement() {
    let ast = parse_ok("Var.A = 1\nEnd\nVar.A = 2\n");
    assert_eq!(ast.body.len(), 3);
    assert_eq!(ast.body[1].kind, StmtKind::End);
}

#[test]
fn every_boolean_word() {
    for word in [
        "ON", "TRUE", "YES", "SET", "ENABLE", "on", "True", "yes", "Set", "enable",
    ] {
        let (_, e) = expr_of(word);
        assert_eq!(e.kind, ExprKind::Bool(true), "{word}");
        let src = format!("Bit.1 = {word}");
        assert_eq!(e.span, at(&src, word), "{word}");
    }
    for word in [
        "OFF", "FALSE", "NO", "CLEAR", "DISABLE", "off", "False", "no", "Clear", "disable",
    ] {
        let (_, e) = expr_of(word);
        assert_eq!(e.kind, ExprKind::Bool(false), "{word}");
    }
    // In conditions too.
    let s = single("Wait For Bit.1 = YES AND Bit.2 = DISABLE");
    let StmtKind::WaitFor(e) = s.kind else {
        panic!()
    };
    assert_eq!(shape(&e), "(AND (= Bit.1 ON) (= Bit.2 OFF))");
}

#[test]
fn keywords_are_case_insensitive() {
    let src = "DO WHILE true\nwait for time 1\nWAIT FOR bit.1 = on\nif Var.A > 1 THEN\nvar.b = 1\nELSE\nvar.b = 2\nendIF\nIF Var.A > 1 then\nend if\nfor var.i = 1 TO 3 step 1\nNEXT\ndwell FOR time 1\nDWELL for MASTER dist 1\ncall Program.1\nlabel1:\ngoto label1\nJUMP TO label1\nEND\nloop\n";
    let ast = parse_ok(src);
    assert_eq!(ast.body.len(), 1);
    let StmtKind::DoWhile { cond, body } = &ast.body[0].kind else {
        panic!("not a Do While")
    };
    assert_eq!(cond.kind, ExprKind::Bool(true));
    let kinds: Vec<&str> = body
        .iter()
        .map(|s| match s.kind {
            StmtKind::WaitTime(_) => "waittime",
            StmtKind::WaitFor(_) => "waitfor",
            StmtKind::If { .. } => "if",
            StmtKind::For { .. } => "for",
            StmtKind::DwellTime(..) => "dwell",
            StmtKind::DwellMaster(..) => "dwellmaster",
            StmtKind::Call(_) => "call",
            StmtKind::Label(_) => "label",
            StmtKind::Goto(_) => "goto",
            StmtKind::End => "end",
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "waittime",
            "waitfor",
            "if",
            "if",
            "for",
            "dwell",
            "dwellmaster",
            "call",
            "label",
            "goto",
            "goto",
            "end"
        ]
    );
    // Operators written as words.
    assert_eq!(
        shape_of("not Bit.1 and Bit.2 Or Bit.3 xor Bit.4"),
        "(XOR (OR (AND (NOT Bit.1) Bit.2) Bit.3) Bit.4)"
    );
    assert_eq!(
        shape_of("Bit.1 AND Bit.2 oR Bit.3"),
        "(OR (AND Bit.1 Bit.2) Bit.3)"
    );
    assert_eq!(shape_of("7 mod 2"), "(MOD 7 2)");
}

#[test]
fn names_are_case_insensitive() {
    // `Next` matches its loop variable whatever the case.
    parse_ok("For Var.Index = 1 To 3\nNext VAR.INDEX\n");
    parse_ok("For Var.Index = 1 To 3\nNext var.index\n");

    // Object, instance and member names resolve whatever the case.
    let machine: pacer::config::machine::MachineFile =
        toml::from_str("[variables.Count]\ndecimals = 0\n").unwrap();
    let (registry, problems) = pacer::config::registry(&machine, &[0, 1], &[]);
    assert!(problems.is_empty(), "{problems:?}");
    let src = "var.count = VAR.COUNT + 1\nWait For queue.0.queueempty\nIf DRIVEINPUT.4 = on Then\nqueue.0.QUEUEREMOVE\nEndif\ncapture.0.capturereset\nprogram.1.initiate\n";
    let ast = parse_ok(src);
    let env = pacer::check::CheckEnv {
        registry: &registry,
        loaded_programs: &[0, 1],
        all_programs: true,
    };
    let problems = pacer::check::check_program(&ast, &env);
    assert!(problems.is_empty(), "{problems:#?}");
    // The resolved name is the canonical one.
    let StmtKind::Assign { target, .. } = &ast.body[0].kind else {
        panic!()
    };
    assert_eq!(registry.resolve(target).unwrap().name, "Var.Count");
}

#[test]
fn comments_straight_and_curly() {
    let src = "' Program 0 - a comment with keywords: If Then Loop Do While End\n\
               ‘ a typeset comment\n\
               ’ the other quote\n\
               Var.A = 1 ' trailing comment: Else\n\
               Var.B = 2 ‘ trailing typeset comment\n\
               \n\
               '\n\
               Var.C = 3’closing quote with no space\n";
    let ast = parse_ok(src);
    assert_eq!(assigned(&ast), ["Var.A", "Var.B", "Var.C"]);
    // Spans are byte offsets, counted correctly after the multi-byte quotes.
    assert_eq!(ast.body[0].span, at(src, "Var.A = 1"));
    assert_eq!(ast.body[1].span, at(src, "Var.B = 2"));
    assert_eq!(ast.body[2].span, at(src, "Var.C = 3"));
}

#[test]
fn labeling_programs_parse() {
    for f in ["program0.pt", "program1.pt", "program2.pt"] {
        let path = format!("{}/tests/fixtures/labeling/{f}", env!("CARGO_MANIFEST_DIR"));
        let src = std::fs::read_to_string(&path).unwrap();
        let ast = parse_ok(&src);
        assert!(!ast.body.is_empty(), "{f}");
    }
}

#[test]
fn fixture_with_every_construct_parses() {
    let path = format!(
        "{}/tests/fixtures/unit/every_construct.pt",
        env!("CARGO_MANIFEST_DIR")
    );
    let src = std::fs::read_to_string(&path).unwrap();
    let ast = parse_ok(&src);
    // Top level: Label, Assign, Do While (holding the rest), End.
    assert_eq!(ast.body.len(), 4, "{ast:#?}");
    assert!(matches!(ast.body[0].kind, StmtKind::Label(_)));
    assert!(matches!(ast.body[2].kind, StmtKind::DoWhile { .. }));
    assert_eq!(ast.body[3].kind, StmtKind::End);
}

// ---------------------------------------------------------------------------------------------
// expressions

#[test]
fn numbers() {
    assert_eq!(shape_of("5"), "5");
    assert_eq!(shape_of("0.25"), "0.25");
    assert_eq!(shape_of(".5"), "0.5");
    assert_eq!(shape_of("1e3"), "1000");
    assert_eq!(shape_of("2.5E-1"), "0.25");
    assert_eq!(shape_of("10."), "10");
    assert_eq!(shape_of("+5"), "5");
}

#[test]
fn precedence_of_arithmetic() {
    assert_eq!(shape_of("1 + 2 * 3"), "(+ 1 (* 2 3))");
    assert_eq!(shape_of("1 * 2 + 3"), "(+ (* 1 2) 3)");
    assert_eq!(shape_of("1 - 2 - 3"), "(- (- 1 2) 3)");
    assert_eq!(shape_of("8 / 4 / 2"), "(/ (/ 8 4) 2)");
    assert_eq!(shape_of("8 / 4 * 2"), "(* (/ 8 4) 2)");
    assert_eq!(shape_of("2 + 3 ^ 2"), "(+ 2 (^ 3 2))");
    assert_eq!(shape_of("2 * 3 ^ 2"), "(* 2 (^ 3 2))");
    assert_eq!(shape_of("2 ^ 3 ^ 2"), "(^ (^ 2 3) 2)");
}

#[test]
fn precedence_of_mod() {
    // MOD binds looser than * and /, tighter than + and -.
    assert_eq!(shape_of("7 MOD 3 + 1"), "(+ (MOD 7 3) 1)");
    assert_eq!(shape_of("1 + 7 MOD 3"), "(+ 1 (MOD 7 3))");
    assert_eq!(shape_of("2 * 7 MOD 3"), "(MOD (* 2 7) 3)");
    assert_eq!(shape_of("7 MOD 3 * 2"), "(MOD 7 (* 3 2))");
    assert_eq!(shape_of("9 MOD 5 MOD 3"), "(MOD (MOD 9 5) 3)");
}

#[test]
fn unary_minus() {
    assert_eq!(shape_of("-5"), "(neg 5)");
    assert_eq!(shape_of("-Var.A * 3"), "(* (neg Var.A) 3)");
    assert_eq!(shape_of("3 * -Var.A"), "(* 3 (neg Var.A))");
    assert_eq!(shape_of("1 - -1"), "(- 1 (neg 1))");
    // Exponentiation binds tighter than the sign, as in BASIC: -2^2 = -4.
    assert_eq!(shape_of("-2 ^ 2"), "(neg (^ 2 2))");
    assert_eq!(shape_of("2 ^ -1"), "(^ 2 (neg 1))");
    assert_eq!(shape_of("- -1"), "(neg (neg 1))");
    let (src, e) = expr_of("2 ^ -1");
    let ExprKind::Binary(_, _, b) = &e.kind else {
        panic!()
    };
    assert_eq!(b.span, at(&src, "-1"));
}

#[test]
fn parentheses() {
    assert_eq!(shape_of("(1 + 2) * 3"), "(* <(+ 1 2)> 3)");
    assert_eq!(shape_of("2 ^ (1 + 1)"), "(^ 2 <(+ 1 1)>)");
    assert_eq!(shape_of("-(1 + 2)"), "(neg <(+ 1 2)>)");
    assert_eq!(shape_of("((1))"), "<<1>>");
    let (src, e) = expr_of("(1 + 2) * 3");
    let ExprKind::Binary(_, a, _) = &e.kind else {
        panic!()
    };
    assert_eq!(a.span, at(&src, "(1 + 2)"));
    assert_eq!(e.span, at(&src, "(1 + 2) * 3"));
}

#[test]
fn comparisons() {
    for (op, sym) in [
        ("=", "="),
        ("<>", "<>"),
        ("<", "<"),
        ("<=", "<="),
        (">", ">"),
        (">=", ">="),
    ] {
        assert_eq!(
            shape_of(&format!("Var.A + 1 {op} Var.B * 2")),
            format!("({sym} (+ Var.A 1) (* Var.B 2))")
        );
    }
    let (_, e) = expr_of("Var.A <= 1");
    assert!(matches!(e.kind, ExprKind::Binary(BinOp::Le, _, _)));
}

#[test]
fn comparisons_do_not_chain() {
    let src = "Var.X = 1 < 2 < 3";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax");
    assert_eq!(problems[0].span, at_nth(src, "<", 1));
}

#[test]
fn precedence_of_logic() {
    assert_eq!(
        shape_of("Var.A = 1 AND Var.B = 2 OR Var.C = 3"),
        "(OR (AND (= Var.A 1) (= Var.B 2)) (= Var.C 3))"
    );
    assert_eq!(
        shape_of("Bit.1 OR Bit.2 AND Bit.3"),
        "(OR Bit.1 (AND Bit.2 Bit.3))"
    );
    assert_eq!(
        shape_of("Bit.1 AND Bit.2 OR Bit.3"),
        "(OR (AND Bit.1 Bit.2) Bit.3)"
    );
    assert_eq!(
        shape_of("Bit.1 XOR Bit.2 AND Bit.3"),
        "(XOR Bit.1 (AND Bit.2 Bit.3))"
    );
    assert_eq!(
        shape_of("Bit.1 OR Bit.2 XOR Bit.3"),
        "(XOR (OR Bit.1 Bit.2) Bit.3)"
    );
    assert_eq!(
        shape_of("Bit.1 XOR Bit.2 XOR Bit.3"),
        "(XOR (XOR Bit.1 Bit.2) Bit.3)"
    );
    assert_eq!(
        shape_of("Bit.1 OR Bit.2 OR Bit.3"),
        "(OR (OR Bit.1 Bit.2) Bit.3)"
    );
    // NOT binds tighter than AND, looser than comparisons.
    assert_eq!(shape_of("NOT Bit.1 AND Bit.2"), "(AND (NOT Bit.1) Bit.2)");
    assert_eq!(shape_of("NOT Var.A = 1"), "(NOT (= Var.A 1))");
    assert_eq!(shape_of("NOT NOT Bit.1"), "(NOT (NOT Bit.1))");
    assert_eq!(shape_of("Bit.1 AND NOT Bit.2"), "(AND Bit.1 (NOT Bit.2))");
    assert_eq!(shape_of("NOT (Bit.1 OR Bit.2)"), "(NOT <(OR Bit.1 Bit.2)>)");
    let (src, e) = expr_of("NOT Bit.1 AND Bit.2");
    let ExprKind::Binary(BinOp::And, a, _) = &e.kind else {
        panic!()
    };
    assert_eq!(a.span, at(&src, "NOT Bit.1"));
}

#[test]
fn or_binds_tighter_than_xor() {
    // Conventional BASIC (QBasic, Visual Basic): NOT, then AND, then OR, then XOR.
    // With ON for all three, XOR-first gives ON while BASIC gives OFF.
    assert_eq!(
        shape_of("Bit.1 XOR Bit.2 OR Bit.3"),
        "(XOR Bit.1 (OR Bit.2 Bit.3))"
    );
    assert_eq!(
        shape_of("Bit.1 XOR Bit.2 OR Bit.3 AND Bit.4"),
        "(XOR Bit.1 (OR Bit.2 (AND Bit.3 Bit.4)))"
    );
}

#[test]
fn function_calls() {
    assert_eq!(shape_of("ABS(Var.A - 1)"), "ABS[(- Var.A 1)]");
    assert_eq!(shape_of("MAX(1, 2)"), "MAX[1, 2]");
    assert_eq!(
        shape_of("ATAN2(Var.Y, Var.X) * 2"),
        "(* ATAN2[Var.Y, Var.X] 2)"
    );
    assert_eq!(
        shape_of("MIN(ABS(-1), 2 + 3)"),
        "MIN[ABS[(neg 1)], (+ 2 3)]"
    );
    assert_eq!(shape_of("-sqrt(4)"), "(neg sqrt[4])");
    let (src, e) = expr_of("1 + ABS(Var.A)");
    let ExprKind::Binary(_, _, call) = &e.kind else {
        panic!()
    };
    assert_eq!(call.span, at(&src, "ABS(Var.A)"));
    let ExprKind::Call(f, args) = &call.kind else {
        panic!()
    };
    assert_eq!(f.span, at(&src, "ABS"));
    assert_eq!(args.len(), 1);
}

#[test]
fn expression_spans() {
    let (src, e) = expr_of("Var.A + 2 * Var.B");
    assert_eq!(e.span, at(&src, "Var.A + 2 * Var.B"));
    let ExprKind::Binary(BinOp::Add, a, b) = &e.kind else {
        panic!()
    };
    assert_eq!(a.span, at(&src, "Var.A"));
    assert_eq!(b.span, at(&src, "2 * Var.B"));
}

// ---------------------------------------------------------------------------------------------
// syntax errors

#[test]
fn every_syntax_error_of_a_file_is_reported() {
    let src =
        "Var.A = 1\nVar.B = = 2\nVar.C = 3\nIf Var.A > Then\nVar.D = 4\nEndif\nWait For Time\nVar.E = 5\n";
    let (ast, problems) = parse_err(src);
    assert_eq!(problems.len(), 3, "{problems:#?}");
    assert!(problems.iter().all(|p| p.code == "pacer::syntax"));
    let mut spans: Vec<Span> = problems.iter().map(|p| p.span).collect();
    spans.sort_by_key(|s| s.start);
    // The second `=` of line 2, `Then` on line 4, the end of line 6.
    assert_eq!(spans[0], at_nth(src, "=", 2));
    assert_eq!(
        problems
            .iter()
            .find(|p| p.span == spans[0])
            .unwrap()
            .message,
        "unexpected `=`"
    );
    assert_eq!(spans[1], at(src, "Then"));
    let eol = at(src, "Wait For Time").end;
    assert_eq!(spans[2], Span::new(eol, eol));
    let p = problems.iter().find(|p| p.span == spans[2]).unwrap();
    assert_eq!(p.message, "the line ends too early");
    assert!(
        p.help.as_deref().unwrap_or("").contains("a number"),
        "{p:?}"
    );
    // The good lines are all kept; the broken If still opens its block, which holds Var.D.
    assert_eq!(assigned(&ast), ["Var.A", "Var.C", "Var.E"]);
    let inside = ast.body.iter().find_map(|s| match &s.kind {
        StmtKind::If { then_body, .. } => Some(then_body.len()),
        _ => None,
    });
    assert_eq!(inside, Some(1), "the If block keeps its line");
}

#[test]
fn syntax_and_block_errors_reported_together() {
    let src = "Var.A = = 1\nElse\nDo While TRUE\nVar.B = 2 3\n";
    let (_, problems) = parse_err(src);
    let codes: Vec<&str> = problems.iter().map(|p| p.code).collect();
    assert_eq!(problems.len(), 4, "{problems:#?}");
    assert!(codes.contains(&"pacer::syntax"));
    assert!(codes.contains(&"pacer::syntax::unbalanced"));
    assert!(codes.contains(&"pacer::syntax::unclosed"));
    let extra = problems
        .iter()
        .find(|p| p.span == at(src, "3"))
        .expect("the extra `3`");
    assert_eq!(extra.message, "unexpected `3`");
}

#[test]
fn unexpected_character() {
    let src = "Var.A = 3 $ 4\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax");
    assert_eq!(problems[0].message, "unexpected character `$`");
    assert_eq!(problems[0].label, "not part of the language");
    assert_eq!(problems[0].span, at(src, "$"));
}

#[test]
fn file_ending_inside_a_statement() {
    let src = "Var.A = 1\nVar.B =";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax");
    assert_eq!(problems[0].span, Span::new(src.len(), src.len()));
}

#[test]
fn else_without_if() {
    let src = "Var.A = 1\nElse\nVar.A = 2\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::unbalanced");
    assert_eq!(p.message, "Else without a matching If");
    assert_eq!(p.span, at(src, "Else"));
    assert_eq!(
        p.help.as_deref(),
        Some("remove this Else or add the If it belongs to")
    );
}

#[test]
fn loop_without_do() {
    let src = "Var.A = 1\nLoop\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::unbalanced");
    assert_eq!(p.message, "Loop without a matching Do While");
    assert_eq!(p.span, at(src, "Loop"));
    assert_eq!(
        p.help.as_deref(),
        Some("remove this Loop or add the Do While it belongs to")
    );
}

#[test]
fn loop_inside_an_if_names_the_open_block() {
    let src = "Do While TRUE\nIf Var.A > 1 Then\nVar.A = 0\nLoop\nEndif\nLoop\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::unbalanced");
    assert_eq!(p.message, "Loop without a matching Do While");
    assert_eq!(p.span, at(src, "Loop"));
    assert_eq!(
        p.help.as_deref(),
        Some("the innermost open block is the If at line 2, closed by `Endif`")
    );
}

#[test]
fn endif_and_next_without_opener() {
    let src = "Endif\nEnd If\nNext\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 3, "{problems:#?}");
    assert_eq!(problems[0].message, "Endif without a matching If");
    assert_eq!(problems[0].span, at(src, "Endif"));
    assert_eq!(problems[1].message, "Endif without a matching If");
    assert_eq!(problems[1].span, at(src, "End If"));
    assert_eq!(problems[2].message, "Next without a matching For");
    assert_eq!(problems[2].span, at(src, "Next"));
}

#[test]
fn missing_endif() {
    let src = "Var.A = 1\nIf Var.A > 1 Then\nVar.A = 2\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::unclosed");
    assert_eq!(p.message, "this If is never closed");
    assert_eq!(p.span, at(src, "If Var.A > 1 Then"));
    assert_eq!(p.help.as_deref(), Some("add `Endif` where the block ends"));
}

#[test]
fn missing_loop_and_next() {
    let src = "Do While TRUE\nFor Var.I = 1 To 2\nVar.A = 1\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 2, "{problems:#?}");
    let for_p = problems
        .iter()
        .find(|p| p.message == "this For is never closed")
        .unwrap();
    assert_eq!(for_p.span, at(src, "For Var.I = 1 To 2"));
    assert_eq!(
        for_p.help.as_deref(),
        Some("add `Next` where the block ends")
    );
    let do_p = problems
        .iter()
        .find(|p| p.message == "this Do While is never closed")
        .unwrap();
    assert_eq!(do_p.span, at(src, "Do While TRUE"));
    assert_eq!(
        do_p.help.as_deref(),
        Some("add `Loop` where the block ends")
    );
}

#[test]
fn next_with_the_wrong_variable() {
    let src = "For Var.I = 1 To 3\nVar.A = Var.A + 1\nNext Var.J\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::next");
    assert_eq!(p.message, "Next Var.J closes the loop over Var.I");
    assert_eq!(p.span, at(src, "Var.J"));
    assert_eq!(p.help.as_deref(), Some("write `Next Var.I` or just `Next`"));
}

#[test]
fn second_else() {
    let src = "If Bit.1 Then\nElse\nVar.A = 1\nElse\nEndif\n";
    let (_, problems) = parse_err(src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    let p = &problems[0];
    assert_eq!(p.code, "pacer::syntax::else");
    assert_eq!(p.span, at_nth(src, "Else", 1));
    assert_eq!(
        p.help.as_deref(),
        Some("this If already has its Else at line 2")
    );
}

#[test]
fn too_long_a_line() {
    let expr = vec!["1"; 400].join(" + ");
    let src = format!("Var.A = 1\nVar.B = {expr}\n");
    let (_, problems) = parse_err(&src);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, "pacer::syntax::line_too_long");
    assert_eq!(text(&src, problems[0].span), format!("Var.B = {expr}"));
}

#[test]
fn too_deep_nesting() {
    let mut src = String::new();
    for _ in 0..70 {
        src.push_str("If Bit.1 Then\n");
    }
    for _ in 0..70 {
        src.push_str("Endif\n");
    }
    let (_, problems) = parse_err(&src);
    assert!(
        problems.iter().any(|p| p.code == "pacer::syntax::nesting"),
        "{problems:#?}"
    );
}
