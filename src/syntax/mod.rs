//! The front end's first half: program text to a tree. Each dialect's tokens, the grammar,
//! the syntax tree both dialects share, and the block structure assembled from the lines.

pub mod ast;
pub mod blocks;
pub mod consts;
pub mod deftype;
pub mod lex;
pub mod lines;
pub mod token;

lalrpop_util::lalrpop_mod!(
    #[allow(clippy::all, clippy::pedantic, unused_parens, missing_docs)]
    program
);

/// The program languages pacer reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dialect {
    /// PowerTools-style user programs (`.pt`).
    #[default]
    PowerTools,
    /// ORMEC MotionBASIC (`.mb`).
    MotionBasic,
}

impl Dialect {
    /// The dialect a file's extension names (`.pt`, `.mb`), if any.
    pub fn of_path(path: &std::path::Path) -> Option<Dialect> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "pt" => Some(Dialect::PowerTools),
            "mb" | "bas" => Some(Dialect::MotionBasic),
            _ => None,
        }
    }

    /// The words that open and close its blocks, for messages.
    pub fn words(self) -> &'static blocks::Words {
        match self {
            Dialect::PowerTools => &blocks::POWERTOOLS_WORDS,
            Dialect::MotionBasic => &blocks::MOTIONBASIC_WORDS,
        }
    }
}

use crate::diag::Problem;
use crate::span::Span;
use ast::ProgramAst;
use lalrpop_util::{ErrorRecovery, ParseError};
use token::{LexError, Tok};

/// Parse a program of `dialect` (no line-length check: see [`parse_program_as`]). Syntax
/// problems are appended to `problems`; the returned tree holds every line that parsed, so
/// later passes can report their problems too.
fn parse_file(src: &str, dialect: Dialect, problems: &mut Vec<Problem>) -> ProgramAst {
    let mut recovered: Vec<ErrorRecovery<usize, Tok<'_>, LexError>> = Vec::new();
    let tokens = lex::lex(src, dialect);
    let result = match dialect {
        Dialect::PowerTools => program::PtFileParser::new().parse(&mut recovered, tokens),
        Dialect::MotionBasic => program::MbFileParser::new().parse(&mut recovered, tokens),
    };
    for r in recovered {
        problems.push(syntax_problem(r.error, src, dialect));
    }
    match result {
        Ok(lines) => {
            let mut body = blocks::assemble(lines, src, problems, dialect.words());
            if dialect == Dialect::MotionBasic {
                deftype::apply(&mut body, problems);
                consts::apply(&mut body, src, problems);
            }
            ProgramAst { body }
        }
        Err(e) => {
            problems.push(syntax_problem(e, src, dialect));
            ProgramAst::default()
        }
    }
}

/// Longest line accepted, in tokens: bounds expression depth, so no input can exhaust the stack.
pub const MAX_LINE_TOKENS: usize = 512;

/// Parse a PowerTools program, after checking that no line is absurdly long.
pub fn parse_program(src: &str, problems: &mut Vec<Problem>) -> ProgramAst {
    parse_program_as(src, Dialect::PowerTools, problems)
}

/// Parse a program of `dialect`, after checking that no line is absurdly long.
pub fn parse_program_as(src: &str, dialect: Dialect, problems: &mut Vec<Problem>) -> ProgramAst {
    let newlines = lex::lex(src, dialect)
        .filter_map(Result::ok)
        .map(|(l, t, r)| (l, matches!(t, Tok::Newline), r));
    let mut count = 0usize;
    let mut line_start = 0usize;
    for (l, newline, r) in newlines {
        if newline {
            count = 0;
            line_start = r;
            continue;
        }
        count += 1;
        if count > MAX_LINE_TOKENS {
            let end = src[l..].find('\n').map_or(src.len(), |i| l + i);
            problems.push(
                Problem::error(
                    "pacer::syntax::line_too_long",
                    Span::new(line_start, end),
                    format!("a line of more than {MAX_LINE_TOKENS} tokens"),
                    "split this line",
                )
                .with_help("use intermediate variables"),
            );
            return ProgramAst::default();
        }
    }
    parse_file(src, dialect, problems)
}

/// Parse one expression (for tests and the REPL).
pub fn parse_expr(src: &str) -> Result<ast::Expr, Problem> {
    let mut recovered = Vec::new();
    let tokens = lex::lex(src, Dialect::PowerTools);
    let r = program::PtExprParser::new().parse(&mut recovered, tokens);
    let d = Dialect::PowerTools;
    match (r, recovered.into_iter().next()) {
        (Ok(e), None) => Ok(e),
        (_, Some(rec)) => Err(syntax_problem(rec.error, src, d)),
        (Err(e), None) => Err(syntax_problem(e, src, d)),
    }
}

fn syntax_problem(e: ParseError<usize, Tok<'_>, LexError>, src: &str, dialect: Dialect) -> Problem {
    let upper = dialect == Dialect::MotionBasic;
    const CODE: &str = "pacer::syntax";
    match e {
        ParseError::InvalidToken { location } => Problem::error(
            CODE,
            Span::new(location, location + 1),
            "invalid token",
            "here",
        ),
        ParseError::UnrecognizedEof { location, expected } => Problem::error(
            CODE,
            Span::new(location, location),
            "the file ends in the middle of a statement",
            "statement incomplete",
        )
        .with_help_opt(expected_help(&expected, upper)),
        ParseError::UnrecognizedToken {
            token: (l, tok, r),
            expected,
        } => {
            let newline = matches!(tok, Tok::Newline);
            let bad = matches!(tok, Tok::Bad(_));
            let span = if newline {
                Span::new(l, l)
            } else {
                Span::new(l, r)
            };
            let words = (!newline && !bad)
                .then(|| in_words(src, l, r, &tok, dialect))
                .flatten();
            let message = if bad {
                tok.describe(dialect).into_owned()
            } else if newline {
                "the line ends too early".to_string()
            } else if let Some(w) = &words {
                w.clone()
            } else {
                format!("unexpected {}", tok.describe(dialect))
            };
            let label = if bad {
                "not part of the language"
            } else {
                "not expected here"
            };
            let expected = expected_help(&expected, upper);
            let help = match (&words, expected) {
                (Some(_), Some(e)) => Some(format!("at this place the grammar {e}")),
                (_, e) => e,
            };
            Problem::error(CODE, span, message, label).with_help_opt(help)
        }
        ParseError::ExtraToken { token: (l, tok, r) } => Problem::error(
            CODE,
            Span::new(l, r),
            format!("unexpected {}", tok.describe(dialect)),
            "extra token",
        ),
        ParseError::User { error: LexError } => Problem::error(
            CODE,
            Span::new(src.len(), src.len()),
            "unreadable input",
            "here",
        ),
    }
}

/// A machine builder's words for a token out of place, where the mistake is a common one: a
/// time written with a unit, `Using` after something that is not a motion start.
fn in_words(src: &str, l: usize, r: usize, tok: &Tok<'_>, dialect: Dialect) -> Option<String> {
    let text = src.get(l..r)?;
    let before = src.get(..l)?.trim_end_matches([' ', '\t']);
    let digits = before
        .rfind(|c: char| !(c.is_ascii_digit() || c == '.'))
        .map_or(0, |i| i + 1);
    let number: Option<f64> = before.get(digits..).and_then(|n| n.parse().ok());
    let scale = match text.to_ascii_lowercase().as_str() {
        "s" | "sec" | "secs" | "seconds" => Some(1.0),
        "ms" | "msec" => Some(1e-3),
        "us" | "µs" | "usec" => Some(1e-6),
        "min" => Some(60.0),
        _ => None,
    };
    if let (Some(n), Some(scale)) = (number, scale) {
        return Some(format!(
            "times in programs are seconds, without a unit: write {}",
            n * scale
        ));
    }
    if let Tok::Unsupported(word) = tok {
        if let Some(message) = crate::registry::not_yet::basic(word) {
            return Some(message);
        }
    }
    if dialect == Dialect::MotionBasic {
        let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
        // The statement's one word before the token, after a line number or a `LABEL:` if the
        // line has one (`CAM knife~ …`).
        let statement = line
            .rsplit(':')
            .next()
            .unwrap_or(line)
            .trim_start_matches(|c: char| c.is_ascii_digit() || c == ' ' || c == '\t');
        let first = statement.trim_end();
        if let Some(message) = crate::registry::not_yet::motionbasic(first) {
            return Some(message);
        }
    }
    if matches!(tok, Tok::On) && dialect == Dialect::MotionBasic {
        return Some(
            "`ON` is a keyword in MotionBASIC (`ON n GOTO …`), not a value: truth is TRUE (-1) \
             or FALSE (0)"
                .into(),
        );
    }
    if matches!(tok, Tok::Using) && dialect == Dialect::MotionBasic {
        return Some(
            "`USING` comes right after `PRINT`, before the values it formats: \
             `PRINT USING \"###.##\"; X, Y`"
                .into(),
        );
    }
    if matches!(tok, Tok::Using) {
        return Some(
            "`Using Last` and `Using Capture.N` go after a motion initiate (`Index.0.Initiate`) \
             or a dwell"
                .into(),
        );
    }
    None
}

fn expected_help(expected: &[String], upper: bool) -> Option<String> {
    if expected.is_empty() {
        return None;
    }
    let words: Vec<String> = expected.iter().map(|e| pretty_expected(e, upper)).collect();
    let mut uniq: Vec<String> = Vec::new();
    for w in words {
        if !uniq.contains(&w) {
            uniq.push(w);
        }
    }
    if uniq.len() > 8 {
        uniq.truncate(8);
        uniq.push("…".into());
    }
    Some(format!("expected {}", uniq.join(", ")))
}

fn pretty_expected(e: &str, upper: bool) -> String {
    let t = e.trim_matches('"');
    match t {
        "true" | "false" if upper => t.to_ascii_uppercase(),
        other
            if upper
                && other.len() > 1
                && other.chars().all(|c| c.is_ascii_alphabetic())
                && !matches!(other, "num" | "name" | "str" | "label" | "bad") =>
        {
            other.to_ascii_uppercase()
        }
        "\\n" => "end of line".into(),
        "num" => "a number".into(),
        "name" => "a name".into(),
        "str" => "a string".into(),
        "label" => "a label".into(),
        "true" | "on" => "ON".into(),
        "false" => "OFF".into(),
        "bad" => "?".into(),
        other if other.chars().all(|c| c.is_ascii_alphabetic()) => {
            let mut c = other.chars();
            match c.next() {
                Some(f) => f.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        }
        other => format!("`{other}`"),
    }
}
