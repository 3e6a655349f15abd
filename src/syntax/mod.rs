//! The front end: tokens, grammar, AST, block structure.

pub mod ast;
pub mod blocks;
pub mod lines;
pub mod span;
pub mod token;

lalrpop_util::lalrpop_mod!(
    #[allow(clippy::all, clippy::pedantic, unused_parens, missing_docs)]
    powertools
);

use crate::diag::Problem;
use ast::ProgramAst;
use lalrpop_util::{ErrorRecovery, ParseError};
use span::Span;
use token::{LexError, Tok};

/// Parse a PowerTools program. Syntax problems are appended to `problems`; the returned tree
/// holds every line that parsed, so later passes can report their problems too.
pub fn parse_powertools(src: &str, problems: &mut Vec<Problem>) -> ProgramAst {
    let mut recovered: Vec<ErrorRecovery<usize, Tok<'_>, LexError>> = Vec::new();
    let result = powertools::FileParser::new().parse(&mut recovered, token::lex(src));
    for r in recovered {
        problems.push(syntax_problem(r.error, src));
    }
    match result {
        Ok(lines) => ProgramAst {
            body: blocks::assemble(lines, src, problems),
        },
        Err(e) => {
            problems.push(syntax_problem(e, src));
            ProgramAst::default()
        }
    }
}

/// Longest line accepted, in tokens: bounds expression depth, so no input can exhaust the stack.
pub const MAX_LINE_TOKENS: usize = 512;

/// Parse a program, after checking that no line is absurdly long.
pub fn parse_program(src: &str, problems: &mut Vec<Problem>) -> ProgramAst {
    let mut count = 0usize;
    let mut line_start = 0usize;
    for tok in token::lex(src) {
        let Ok((l, t, r)) = tok else { continue };
        if matches!(t, Tok::Newline) {
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
    parse_powertools(src, problems)
}

/// Parse one expression (for tests and the REPL).
pub fn parse_expr(src: &str) -> Result<ast::Expr, Problem> {
    let mut recovered = Vec::new();
    let r = powertools::ExprParser::new().parse(&mut recovered, token::lex(src));
    match (r, recovered.into_iter().next()) {
        (Ok(e), None) => Ok(e),
        (_, Some(rec)) => Err(syntax_problem(rec.error, src)),
        (Err(e), None) => Err(syntax_problem(e, src)),
    }
}

fn syntax_problem(e: ParseError<usize, Tok<'_>, LexError>, src: &str) -> Problem {
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
        .with_help_opt(expected_help(&expected)),
        ParseError::UnrecognizedToken {
            token: (l, tok, r),
            expected,
        } => {
            let span = if matches!(tok, Tok::Newline) {
                Span::new(l, l)
            } else {
                Span::new(l, r)
            };
            let message = match tok {
                Tok::Bad(_) => format!("{tok}"),
                Tok::Newline => "the line ends too early".to_string(),
                _ => format!("unexpected {tok}"),
            };
            let label = if matches!(tok, Tok::Bad(_)) {
                "not part of the language"
            } else {
                "not expected here"
            };
            Problem::error(CODE, span, message, label).with_help_opt(expected_help(&expected))
        }
        ParseError::ExtraToken { token: (l, tok, r) } => Problem::error(
            CODE,
            Span::new(l, r),
            format!("unexpected {tok}"),
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

fn expected_help(expected: &[String]) -> Option<String> {
    if expected.is_empty() {
        return None;
    }
    let words: Vec<String> = expected.iter().map(|e| pretty_expected(e)).collect();
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

fn pretty_expected(e: &str) -> String {
    let t = e.trim_matches('"');
    match t {
        "\\n" => "end of line".into(),
        "num" => "a number".into(),
        "name" => "a name".into(),
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
