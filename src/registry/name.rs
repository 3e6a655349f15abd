//! Names as programs and files write them — `Queue.0.QueueOffset`, `Var.Count`, `DriveInput.4` —
//! split into their dotted parts, each with its place in the text, so resolving a name can point
//! at the part that is wrong.

use crate::span::Span;

/// One segment of a dotted name (`Queue`, `0`, `QueueEmpty`).
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// The text as written.
    pub text: String,
    /// Where it is.
    pub span: Span,
}

/// A possibly dotted name, e.g. `Queue.0.QueueOffset`, `Var.Count`, `DriveInput.4`.
#[derive(Debug, Clone, PartialEq)]
pub struct Name {
    /// The dot-separated parts.
    pub segments: Vec<Segment>,
    /// The whole name.
    pub span: Span,
}

impl Name {
    /// Split a dotted-name token that starts at byte `start`.
    pub fn from_token(text: &str, start: usize) -> Name {
        let mut segments = Vec::new();
        let mut pos = start;
        for part in text.split('.') {
            segments.push(Segment {
                text: part.to_string(),
                span: Span::new(pos, pos + part.len()),
            });
            pos += part.len() + 1;
        }
        Name {
            segments,
            span: Span::new(start, start + text.len()),
        }
    }

    /// The name as written, dots included.
    pub fn text(&self) -> String {
        self.segments
            .iter()
            .map(|s| s.text.as_str())
            .collect::<Vec<_>>()
            .join(".")
    }
}
