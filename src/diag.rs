//! Diagnostics: every problem found in a file a user wrote (program, machine file, scenario),
//! located by span and rendered with miette.
// miette's derive is not used here, but keep the lint allowance next to diagnostics code
// in case it is (miette issue 458).
#![allow(unused_assignments)]

use crate::span::{LineIndex, Span};
use miette::{Diagnostic, LabeledSpan, Severity, SourceCode};
use std::fmt;
use std::sync::Arc;

/// How bad a problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// Stops the program from running.
    Error,
    /// Reported; the program still runs.
    Warning,
}

/// One problem in one file, located by span.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Stable code, e.g. `pacer::check::unknown_member`.
    pub code: &'static str,
    /// Error or warning.
    pub level: Level,
    /// The message.
    pub message: String,
    /// The exact place.
    pub span: Span,
    /// Text of the label on the span.
    pub label: String,
    /// A hint, e.g. the nearest valid name.
    pub help: Option<String>,
}

impl Problem {
    /// An error.
    pub fn error(
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        label: impl Into<String>,
    ) -> Problem {
        Problem {
            code,
            level: Level::Error,
            message: message.into(),
            span,
            label: label.into(),
            help: None,
        }
    }

    /// A warning.
    pub fn warning(
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        label: impl Into<String>,
    ) -> Problem {
        Problem {
            code,
            level: Level::Warning,
            message: message.into(),
            span,
            label: label.into(),
            help: None,
        }
    }

    /// Add a help line.
    pub fn with_help(mut self, help: impl Into<String>) -> Problem {
        self.help = Some(help.into());
        self
    }

    /// Add a help line if there is one.
    pub fn with_help_opt(mut self, help: Option<String>) -> Problem {
        self.help = help;
        self
    }
}

/// A source file as diagnostics need it.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The path as the user gave it.
    pub name: String,
    /// The whole text.
    pub text: Arc<str>,
    index: Arc<LineIndex>,
}

impl PartialEq for SourceFile {
    fn eq(&self, other: &SourceFile) -> bool {
        self.name == other.name && self.text == other.text
    }
}

impl SourceFile {
    /// A named source.
    pub fn new(name: impl Into<String>, text: impl Into<Arc<str>>) -> SourceFile {
        let text: Arc<str> = text.into();
        let index = Arc::new(LineIndex::new(&text));
        SourceFile {
            name: name.into(),
            text,
            index,
        }
    }

    /// 1-based line and column (in characters) of a span's start.
    pub fn line_col(&self, span: Span) -> (usize, usize) {
        let offset = span.start.min(self.text.len());
        let line = self.index.line(offset);
        let start = self
            .index
            .line_range(line, self.text.len())
            .map_or(0, |r| r.0);
        let col = self
            .text
            .get(start..offset)
            .map_or(0, |t| t.chars().count())
            + 1;
        (line, col)
    }

    /// True when the lines around `span` are too wide to draw as a snippet.
    fn wide_around(&self, span: Span) -> bool {
        let line = self.index.line(span.start.min(self.text.len()));
        (line.saturating_sub(1)..=line + 1)
            .filter_map(|l| self.index.line_range(l, self.text.len()))
            .any(|(a, b)| b - a > MAX_SNIPPET_LINE)
    }
}

/// Lines wider than this (bytes) are not drawn as snippets: the message, place and help are
/// printed instead (miette cannot draw spans that start past column 65,535).
const MAX_SNIPPET_LINE: usize = 4096;

/// Problems drawn with a source snippet; the rest are listed one per line.
const MAX_DRAWN: usize = 100;

/// A problem tied to its file, ready to render.
#[derive(Debug, Clone)]
pub struct Located {
    /// The problem.
    pub problem: Problem,
    /// Its file.
    pub file: SourceFile,
}

impl fmt::Display for Located {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.problem.message)
    }
}

impl std::error::Error for Located {}

impl Diagnostic for Located {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.problem.code))
    }

    fn severity(&self) -> Option<Severity> {
        Some(match self.problem.level {
            Level::Error => Severity::Error,
            Level::Warning => Severity::Warning,
        })
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.problem
            .help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        Some(self)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = clamp(self.problem.span, self.file.text.len());
        Some(Box::new(std::iter::once(LabeledSpan::new_with_span(
            Some(self.problem.label.clone()),
            span,
        ))))
    }
}

impl SourceCode for Located {
    fn read_span<'a>(
        &'a self,
        span: &miette::SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn miette::SpanContents<'a> + 'a>, miette::MietteError> {
        let inner = self
            .file
            .text
            .read_span(span, context_lines_before, context_lines_after)?;
        Ok(Box::new(miette::MietteSpanContents::new_named(
            self.file.name.clone(),
            inner.data(),
            *inner.span(),
            inner.line(),
            inner.column(),
            inner.line_count(),
        )))
    }
}

fn clamp(span: Span, len: usize) -> Span {
    let start = span.start.min(len);
    Span::new(start, span.end.clamp(start, len))
}

/// Everything wrong with a set of files.
#[derive(Debug, Clone, Default)]
pub struct Diagnostics {
    /// In the order found (files in the order given, then by position).
    pub items: Vec<Located>,
}

impl Diagnostics {
    /// No problems yet.
    pub fn new() -> Diagnostics {
        Diagnostics::default()
    }

    /// Add the problems of one file, sorted by position.
    pub fn extend_file(&mut self, file: &SourceFile, mut problems: Vec<Problem>) {
        problems.sort_by_key(|p| (p.span.start, p.span.end));
        for problem in problems {
            self.items.push(Located {
                problem,
                file: file.clone(),
            });
        }
    }

    /// Count of errors (not warnings).
    pub fn error_count(&self) -> usize {
        self.items
            .iter()
            .filter(|d| d.problem.level == Level::Error)
            .count()
    }

    /// True when at least one error is present.
    pub fn has_errors(&self) -> bool {
        self.error_count() > 0
    }

    /// Render all problems as text, without colour, at a fixed width (for tests and goldens).
    pub fn render_plain(&self) -> String {
        self.render(false)
    }

    /// Render all problems; with colour when asked.
    pub fn render(&self, color: bool) -> String {
        let handler = handler(color);
        let mut out = String::new();
        for (i, d) in self.items.iter().enumerate() {
            let (line, col) = d.file.line_col(d.problem.span);
            let level = match d.problem.level {
                Level::Error => "error",
                Level::Warning => "warning",
            };
            if i < MAX_DRAWN && !d.file.wide_around(d.problem.span) {
                out.push_str(&format!("{}:{}:{}: {level}\n", d.file.name, line, col));
                if handler.render_report(&mut out, d).is_err() {
                    out.push_str(&d.problem.message);
                }
                out.push('\n');
            } else {
                out.push_str(&format!(
                    "{}:{}:{}: {level}[{}]: {} ({})",
                    d.file.name, line, col, d.problem.code, d.problem.message, d.problem.label
                ));
                if let Some(h) = &d.problem.help {
                    out.push_str(&format!("; help: {h}"));
                }
                out.push('\n');
            }
        }
        out
    }
}

/// The report handler every diagnostic is drawn with: 100 columns, colour when asked.
fn handler(color: bool) -> miette::GraphicalReportHandler {
    let theme = if color {
        miette::GraphicalTheme::unicode()
    } else {
        miette::GraphicalTheme::unicode_nocolor()
    };
    miette::GraphicalReportHandler::new_themed(theme).with_width(100)
}

/// One problem of `file` drawn as the compile-time ones are — `file:line:column: heading`, then
/// the snippet with the span underlined — for a problem found while running (a run-time error
/// in a program).
pub fn render_located(file: &SourceFile, problem: &Problem, heading: &str, color: bool) -> String {
    let (line, col) = file.line_col(problem.span);
    let mut out = format!("{}:{}:{}: {heading}\n", file.name, line, col);
    let located = Located {
        problem: problem.clone(),
        file: file.clone(),
    };
    if file.wide_around(problem.span) || handler(color).render_report(&mut out, &located).is_err() {
        out.push_str(&format!("  {}\n", problem.message));
    }
    out
}

/// The closest candidate to `name` (case-insensitive), if close enough to be a likely slip.
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_ascii_lowercase();
    let mut best: Option<(f64, &str)> = None;
    for c in candidates {
        let score = strsim::jaro_winkler(&lower, &c.to_ascii_lowercase());
        if best.is_none_or(|(s, _)| score > s) {
            best = Some((score, c));
        }
    }
    best.filter(|(s, _)| *s >= 0.75).map(|(_, c)| c)
}

/// A number as a message shows it: short (`1e300`, not 301 digits), `NaN`, `infinity`.
pub fn number(x: f64) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 {
            "infinity"
        } else {
            "minus infinity"
        }
        .into();
    }
    let plain = format!("{x}");
    if plain.len() <= 16 {
        return plain;
    }
    // Six significant digits in scientific form, without trailing zeros.
    let sci = format!("{x:.5e}");
    match sci.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let m = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{exp}")
        }
        _ => sci,
    }
}

/// `text` with every control or invisible character written as an escape (`\0`, `\u{200b}`),
/// so a message shows what is really there.
pub fn escaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if invisible(c) {
            match c {
                '\0' => out.push_str("\\0"),
                '\t' => out.push_str("\\t"),
                '\r' => out.push_str("\\r"),
                '\n' => out.push_str("\\n"),
                _ => out.push_str(&format!("\\u{{{:04x}}}", c as u32)),
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// A character that prints as nothing, or moves the text about: controls, zero-width and
/// direction marks, the byte-order mark, other format characters.
pub fn invisible(c: char) -> bool {
    c.is_control()
        || matches!(c,
            '\u{00ad}' | '\u{034f}' | '\u{061c}' | '\u{115f}' | '\u{1160}' | '\u{17b4}' | '\u{17b5}'
            | '\u{180b}'..='\u{180f}' | '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}'
            | '\u{2060}'..='\u{206f}' | '\u{3164}' | '\u{fe00}'..='\u{fe0f}' | '\u{feff}'
            | '\u{ffa0}' | '\u{fff0}'..='\u{fff8}' | '\u{e0000}'..='\u{e0fff}')
}

#[cfg(test)]
mod message_tests {
    use super::*;

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(0.5), "0.5");
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-1.234567891e40), "-1.23457e40");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "minus infinity");
    }

    #[test]
    fn invisible_characters_are_escaped() {
        assert_eq!(escaped("a\0b\u{200b}c"), "a\\0b\\u{200b}c");
        assert_eq!(escaped("µs °"), "µs °");
    }
}
