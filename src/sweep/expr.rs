//! The small expressions of a sweep: an assertion (`Queue.0.QueueOverflow == OFF`,
//! `missed <= 2`) compares two sums; a computed measure (`captures - labels`) is one sum. A
//! term is a number, `ON`/`OFF`/`TRUE`/`FALSE`, a measure's name or a member's name.

/// A name in an expression: a measure of the sweep or a member of the machine (resolved when
/// the sweep is checked against the machine).
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// A constant.
    Number(f64),
    /// A name, as written.
    Name(String),
}

/// `a + b - c`: signed terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Sum {
    /// Each term with its sign (+1 or -1).
    pub terms: Vec<(f64, Term)>,
}

/// A comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl Op {
    /// `a OP b`.
    pub fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Op::Eq => a == b,
            Op::Ne => a != b,
            Op::Lt => a < b,
            Op::Le => a <= b,
            Op::Gt => a > b,
            Op::Ge => a >= b,
        }
    }
}

/// `left OP right`.
#[derive(Debug, Clone, PartialEq)]
pub struct Assertion {
    /// Left side.
    pub left: Sum,
    /// The comparison.
    pub op: Op,
    /// Right side.
    pub right: Sum,
}

impl Sum {
    /// The names it reads.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.terms.iter().filter_map(|(_, t)| match t {
            Term::Name(n) => Some(n.as_str()),
            Term::Number(_) => None,
        })
    }

    /// Its value, names read by `value` (`None` when one has none).
    pub fn eval(&self, value: &mut dyn FnMut(&str) -> Option<f64>) -> Option<f64> {
        let mut total = 0.0;
        for (sign, t) in &self.terms {
            total += sign
                * match t {
                    Term::Number(x) => *x,
                    Term::Name(n) => value(n)?,
                };
        }
        Some(total)
    }
}

impl Assertion {
    /// The names it reads.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.left.names().chain(self.right.names())
    }

    /// Whether it holds (`None` when a name has no value).
    pub fn eval(&self, value: &mut dyn FnMut(&str) -> Option<f64>) -> Option<bool> {
        let a = self.left.eval(value)?;
        let b = self.right.eval(value)?;
        Some(self.op.holds(a, b))
    }
}

/// Parse an assertion.
pub fn parse_assertion(text: &str) -> Result<Assertion, String> {
    const OPS: [(&str, Op); 6] = [
        ("==", Op::Eq),
        ("!=", Op::Ne),
        ("<=", Op::Le),
        (">=", Op::Ge),
        ("<", Op::Lt),
        (">", Op::Gt),
    ];
    let found = OPS
        .iter()
        .filter_map(|(s, op)| text.find(s).map(|i| (i, *s, *op)))
        .min_by_key(|(i, s, _)| (*i, std::cmp::Reverse(s.len())));
    let Some((at, sym, op)) = found else {
        return Err(format!(
            "`{text}` compares nothing: write e.g. `Queue.0.QueueOverflow == OFF` or `missed <= 2` \
             (==, !=, <, <=, >, >=)"
        ));
    };
    let right_text = &text[at + sym.len()..];
    if OPS.iter().any(|(s, _)| right_text.contains(s)) {
        return Err(format!("`{text}`: one comparison per assertion"));
    }
    Ok(Assertion {
        left: parse_sum(&text[..at])?,
        op,
        right: parse_sum(right_text)?,
    })
}

/// Parse a sum of terms.
pub fn parse_sum(text: &str) -> Result<Sum, String> {
    let mut terms = Vec::new();
    let mut sign = 1.0;
    let mut expect_term = true;
    let mut rest = text.trim_start();
    while !rest.is_empty() {
        let c = rest.chars().next().unwrap_or(' ');
        if !expect_term {
            match c {
                '+' => sign = 1.0,
                '-' => sign = -1.0,
                _ => {
                    return Err(format!(
                        "`{}`: expected + or - before `{rest}`",
                        text.trim()
                    ))
                }
            }
            expect_term = true;
            rest = rest[1..].trim_start();
            continue;
        }
        if c == '-' && terms.is_empty() && sign > 0.0 {
            sign = -1.0;
            rest = rest[1..].trim_start();
            continue;
        }
        let end = rest
            .find(|c: char| c.is_whitespace() || c == '+')
            .unwrap_or(rest.len());
        // A `-` ends a word (names hold none), except an exponent's (`1e-3`).
        let word_end = word_end(&rest[..end]);
        let word = &rest[..word_end];
        terms.push((sign, term(word)?));
        sign = 1.0;
        expect_term = false;
        rest = rest[word_end..].trim_start();
    }
    if terms.is_empty() || expect_term {
        return Err(format!("`{}`: a value is missing", text.trim()));
    }
    Ok(Sum { terms })
}

/// Where the word at the start of `s` ends: at a `-` that is not an exponent's sign.
fn word_end(s: &str) -> usize {
    let bytes = s.as_bytes();
    for (i, b) in bytes.iter().enumerate() {
        if *b == b'-' && i > 0 {
            let exponent = matches!(bytes[i - 1], b'e' | b'E')
                && bytes[..i - 1]
                    .iter()
                    .all(|b| b.is_ascii_digit() || *b == b'.');
            if !exponent {
                return i;
            }
        }
    }
    s.len()
}

fn term(word: &str) -> Result<Term, String> {
    match word.to_ascii_uppercase().as_str() {
        "ON" | "TRUE" => return Ok(Term::Number(1.0)),
        "OFF" | "FALSE" => return Ok(Term::Number(0.0)),
        _ => {}
    }
    if word.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        return word
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .map(Term::Number)
            .ok_or_else(|| format!("`{word}` is not a number"));
    }
    if word.is_empty()
        || !word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '$'))
    {
        return Err(format!(
            "`{word}` is not a number, ON/OFF, a measure or a member"
        ));
    }
    Ok(Term::Name(word.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assertions_parse_and_hold() {
        let a = parse_assertion("Queue.0.QueueOverflow == OFF").expect("parses");
        assert_eq!(a.op, Op::Eq);
        assert_eq!(a.names().collect::<Vec<_>>(), vec!["Queue.0.QueueOverflow"]);
        assert_eq!(a.eval(&mut |_| Some(0.0)), Some(true));
        assert_eq!(a.eval(&mut |_| Some(1.0)), Some(false));
        let b = parse_assertion("captures - labels-queued <= 1e-3 + 2").expect("parses");
        assert_eq!(b.op, Op::Le);
        let mut v = |n: &str| match n {
            "captures" => Some(10.0),
            "labels" => Some(7.0),
            "queued" => Some(1.0),
            _ => None,
        };
        assert_eq!(b.left.eval(&mut v), Some(2.0));
        assert_eq!(b.right.eval(&mut v), Some(2.001));
        assert_eq!(b.eval(&mut v), Some(true));
        assert_eq!(
            parse_sum("-3").expect("negative").eval(&mut |_| None),
            Some(-3.0)
        );
    }

    #[test]
    fn bad_assertions_say_why() {
        assert!(parse_assertion("missed")
            .expect_err("no op")
            .contains("compares nothing"));
        assert!(parse_assertion("a == b == c").is_err());
        assert!(parse_assertion("a == ")
            .expect_err("empty")
            .contains("missing"));
        assert!(parse_assertion("a + == 1").is_err());
        assert!(parse_assertion("a b == 1").is_err());
        assert!(parse_assertion("a == 1x")
            .expect_err("bad number")
            .contains("not a number"));
    }
}
