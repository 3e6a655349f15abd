//! The machine file (`machine.toml`) and the scenario file (`scenario.toml`): formats,
//! parsing and validation with located errors.

pub mod machine;
pub mod scenario;
pub mod values;

use crate::diag::Problem;
use crate::syntax::span::Span;

/// Parse a TOML document into `T`, turning a syntax or shape error into a located problem.
pub fn parse_toml<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> Result<T, Problem> {
    toml::from_str::<T>(text).map_err(|e| {
        let span = e
            .span()
            .map_or(Span::new(0, 0), |r| Span::new(r.start, r.end));
        Problem::error(
            "pacer::config",
            span,
            format!("{what}: {}", e.message().trim()),
            "here",
        )
    })
}

/// The span of a spanned TOML value.
pub fn span_of<T>(v: &toml::Spanned<T>) -> Span {
    let r = v.span();
    Span::new(r.start, r.end)
}
