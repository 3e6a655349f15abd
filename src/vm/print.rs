//! `PRINT` as Microsoft BASIC writes it: numbers with a sign position and a trailing space,
//! at most 7 (SINGLE) or 16 (DOUBLE) significant digits, E notation when the plain form would
//! need more digits; print zones of 14 columns; each task's line kept until it ends.

use crate::compile::bytecode::PrintHow;
use std::io::Write as _;

/// The width of a print zone (`,` moves to the next one).
pub const ZONE: usize = 14;

/// A number as `PRINT` writes it: `" 5 "`, `"-2.5 "`, `" .5 "`, `" 1E+07 "`.
pub fn number(x: f64, how: PrintHow) -> String {
    let mut text = String::new();
    push_number(x, how, &mut text);
    text
}

/// [`number`] written at the end of `out`.
pub fn push_number(x: f64, how: PrintHow, out: &mut String) {
    if push_plain(x, how, true, out) {
        return;
    }
    let a = x.abs();
    let sign = if x < 0.0 { "-" } else { " " };
    let body = match how {
        PrintHow::Integer | PrintHow::Text => format!("{}", a.round()),
        PrintHow::Single => magnitude(a, 7, 'E'),
        PrintHow::Double => magnitude(a, 16, 'D'),
    };
    out.push_str(sign);
    out.push_str(&body);
    out.push(' ');
}

/// [`number`] at the end of `out` when `x` is a whole number that every form writes as its
/// plain digits (the common case), without the formatting machinery; `trailing`: with the
/// blank PRINT puts after a number (STR$ has none). False, and nothing written, otherwise.
#[inline]
pub fn push_plain(x: f64, how: PrintHow, trailing: bool, out: &mut String) -> bool {
    let a = x.abs();
    // A SINGLE has 7 digits; the others are exact below 2^53.
    let plain = if how == PrintHow::Single {
        1.0e7
    } else {
        9.0e15
    };
    if !(a < plain && a as u64 as f64 == a) {
        return false;
    }
    // Sign, at most 16 digits and the blank, built on the stack and pushed in one copy.
    let mut buf = [b' '; 18];
    let end = buf.len() - usize::from(trailing);
    let mut at = write_digits(a as u64, &mut buf[..end]);
    at -= 1;
    buf[at] = if x < 0.0 { b'-' } else { b' ' };
    // SAFETY: every byte of `buf` is a blank, a minus or `b'0'` plus a digit 0-9: ASCII, so
    // valid UTF-8.
    out.push_str(unsafe { std::str::from_utf8_unchecked(&buf[at..]) });
    true
}

/// The decimal digits of `n` at the end of `out`.
pub fn push_digits(n: u64, out: &mut String) {
    let mut digits = [0u8; 20];
    let at = write_digits(n, &mut digits);
    // SAFETY: every byte from `at` on was written above as `b'0'` plus a digit 0–9: ASCII,
    // so valid UTF-8. (One copy of the bytes, not a push per character.)
    out.push_str(unsafe { std::str::from_utf8_unchecked(&digits[at..]) });
}

/// The decimal digits of `n` written at the end of `buf` (which holds them: 20 bytes hold any
/// `u64`); where they start.
#[inline]
fn write_digits(mut n: u64, buf: &mut [u8]) -> usize {
    let mut at = buf.len();
    loop {
        at -= 1;
        buf[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            return at;
        }
    }
}

/// A non-negative `x` to `digits` significant digits: plain (no leading zero, no trailing
/// zeros or point) when that form needs no more than `digits` digits, else scaled with
/// `exp` (`E` or `D`) and a signed exponent of at least two digits.
///
/// GW-BASIC User's Guide, PRINT: "1E-7 is output as .0000001 and 1E-8 is output as 1E-08".
fn magnitude(x: f64, digits: usize, exp: char) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x == 0.0 { "0".into() } else { format!("{x}") };
    }
    // `d.ddddde±x` rounded to `digits` significant digits.
    let scaled = format!("{:.*e}", digits - 1, x);
    let (mantissa, power) = scaled.split_once('e').unwrap_or((&scaled, "0"));
    let power: i32 = power.parse().unwrap_or(0);
    let all: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let significant = all.trim_end_matches('0');
    let significant = if significant.is_empty() {
        "0"
    } else {
        significant
    };
    let n = significant.len() as i32;
    // Digits the plain form writes: integer digits and fraction digits (leading zeros too).
    let plain_digits = if power >= 0 {
        n.max(power + 1)
    } else {
        -power - 1 + n
    };
    if plain_digits <= digits as i32 {
        if power >= 0 {
            let int_len = (power + 1) as usize;
            if significant.len() <= int_len {
                format!("{significant}{}", "0".repeat(int_len - significant.len()))
            } else {
                format!("{}.{}", &significant[..int_len], &significant[int_len..])
            }
        } else {
            format!(".{}{significant}", "0".repeat((-power - 1) as usize))
        }
    } else {
        let (first, rest) = significant.split_at(1);
        let point = if rest.is_empty() { "" } else { "." };
        let sign = if power < 0 { '-' } else { '+' };
        format!("{first}{point}{rest}{exp}{sign}{:02}", power.abs())
    }
}

/// The line each task is printing, and where finished lines go besides the trace.
#[derive(Default)]
pub struct Printer {
    lines: Vec<String>,
    output: Option<Box<dyn std::io::Write>>,
    /// Finished lines kept for the caller to take (the REPL shows them).
    kept: Option<Vec<String>>,
}

impl Printer {
    /// Finished lines are also written to `output` (`pacer run`: standard output).
    pub fn set_output(&mut self, output: Box<dyn std::io::Write>) {
        self.output = Some(output);
    }

    /// Keep finished lines until [`Printer::take`] takes them.
    pub fn keep(&mut self) {
        self.kept.get_or_insert_with(Vec::new);
    }

    /// The finished lines kept since the last call.
    pub fn take(&mut self) -> Vec<String> {
        self.kept.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Write a finished line to the output, if there is one. A failed write (a closed pipe)
    /// loses nothing the trace does not keep.
    pub fn output(&mut self, text: &str) {
        if let Some(kept) = &mut self.kept {
            kept.push(text.to_string());
        }
        if let Some(out) = &mut self.output {
            let _ = writeln!(out, "{text}");
            let _ = out.flush();
        }
    }

    fn line(&mut self, task: usize) -> &mut String {
        if self.lines.len() <= task {
            self.lines.resize(task + 1, String::new());
        }
        &mut self.lines[task]
    }

    /// Add `text` to `task`'s line.
    pub fn write(&mut self, task: usize, text: &str) {
        self.line(task).push_str(text);
    }

    /// `,`: pad `task`'s line to the start of the next print zone.
    pub fn zone(&mut self, task: usize) {
        let line = self.line(task);
        let column = line.chars().count();
        let next = (column / ZONE + 1) * ZONE;
        line.extend(std::iter::repeat_n(' ', next - column));
    }

    /// End `task`'s line: its text.
    pub fn finish(&mut self, task: usize) -> String {
        std::mem::take(self.line(task))
    }

    /// A finished line of `task` running `program` (None: a typed REPL line): to the output
    /// and the trace.
    pub fn emit(
        &mut self,
        trace: &mut crate::trace::Trace,
        tick: u64,
        task: usize,
        program: Option<u32>,
        text: String,
    ) {
        self.output(&text);
        trace.emit(
            tick,
            &crate::trace::Event::Print {
                task,
                program,
                text: text.into(),
            },
        );
    }

    /// `task`'s unfinished line (a `PRINT` that ended with `;` or `,`), if any.
    pub fn pending(&mut self, task: usize) -> Option<String> {
        let line = self.line(task);
        (!line.is_empty()).then(|| std::mem::take(line))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn single(x: f64) -> String {
        number(x, PrintHow::Single)
    }

    #[test]
    fn numbers_have_a_sign_position_and_a_trailing_space() {
        assert_eq!(single(5.0), " 5 ");
        assert_eq!(single(-2.5), "-2.5 ");
        assert_eq!(single(0.0), " 0 ");
        assert_eq!(number(-7.0, PrintHow::Integer), "-7 ");
        assert_eq!(number(2147483647.0, PrintHow::Integer), " 2147483647 ");
    }

    #[test]
    fn fractions_have_no_leading_zero_and_no_trailing_zeros() {
        assert_eq!(single(0.5), " .5 ");
        assert_eq!(single(-0.25), "-.25 ");
        assert_eq!(single(2.50), " 2.5 ");
        assert_eq!(single(1.0 / 3.0), " .3333333 ");
        assert_eq!(single(2.0 / 3.0), " .6666667 ");
        assert_eq!(number(1.0 / 3.0, PrintHow::Double), " .3333333333333333 ");
    }

    #[test]
    fn seven_digits_plain_then_scaled() {
        assert_eq!(single(1234567.0), " 1234567 ");
        assert_eq!(single(1e7), " 1E+07 ");
        assert_eq!(single(12345678.0), " 1.234568E+07 ");
        // GW-BASIC's own example: 1E-7 plain, 1E-8 scaled.
        assert_eq!(single(1e-7), " .0000001 ");
        assert_eq!(single(1e-8), " 1E-08 ");
        assert_eq!(single(-1.5e-10), "-1.5E-10 ");
        assert_eq!(number(1e16, PrintHow::Double), " 1D+16 ");
        assert_eq!(number(123456789.0, PrintHow::Double), " 123456789 ");
    }

    #[test]
    fn zones_are_14_columns() {
        let mut p = Printer::default();
        p.write(0, "A");
        p.zone(0);
        p.write(0, "B");
        p.zone(0);
        assert_eq!(
            p.pending(0).as_deref(),
            Some("A             B             ")
        );
        p.zone(1);
        p.write(1, "X");
        assert_eq!(p.finish(1), format!("{}X", " ".repeat(14)));
        assert_eq!(p.pending(1), None);
    }
}
