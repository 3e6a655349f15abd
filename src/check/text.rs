//! MotionBASIC's string functions, as Microsoft BASIC defines them: their names, what they
//! take and give, and what they compute. Strings hold at most 255 characters, and a count or
//! position outside what the function allows is an "Illegal function call", as in GW-BASIC.

use super::typed::PrintHow;

/// Longest string a program may build (Microsoft BASIC's limit).
pub const MAX_LEN: usize = 255;

/// A string function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextFunc {
    /// `LEN(s$)`: its length.
    Len,
    /// `LEFT$(s$, n)`.
    Left,
    /// `RIGHT$(s$, n)`.
    Right,
    /// `MID$(s$, start[, n])`.
    Mid,
    /// `STR$(x)`: the number as PRINT writes it, without the trailing space.
    Str(PrintHow),
    /// `VAL(s$)`: the number the string starts with.
    Val,
    /// `CHR$(code)`.
    Chr,
    /// `ASC(s$)`: the code of its first character.
    Asc,
    /// `INSTR([start,] s$, find$)`: where `find$` first occurs, from 1; 0 when nowhere.
    Instr,
    /// `SPACE$(n)`.
    Space,
    /// `STRING$(n, code)` or `STRING$(n, s$)`: n times the character.
    Repeat,
    /// `UCASE$(s$)`.
    Upper,
    /// `LCASE$(s$)`.
    Lower,
    /// `LTRIM$(s$)`: without leading spaces.
    TrimStart,
    /// `RTRIM$(s$)`: without trailing spaces.
    TrimEnd,
    /// `HEX$(n)`.
    Hex,
    /// `OCT$(n)`.
    Oct,
    /// The `MID$(v$, start[, n]) = y$` statement: `v$` with its characters from `start`
    /// replaced by those of `y$` (at most `n`, never past the end of `v$`). Its arguments are
    /// `v$, start, y$[, n]`. Not callable by name: the checker makes it from the statement.
    MidSet,
}

/// What an argument is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arg {
    /// A number.
    Num,
    /// A string.
    Text,
    /// Either (`STRING$`'s character).
    Either,
}

/// One string function: its name, arguments (the first `min` required), whether it gives a
/// string, and what it does.
#[derive(Debug, Clone, Copy)]
pub struct TextDef {
    /// The name as written, upper case.
    pub name: &'static str,
    /// The function (`STR$` is completed by the checker with the argument's type).
    pub func: TextFunc,
    /// Its arguments in order.
    pub args: &'static [Arg],
    /// How many are required.
    pub min: usize,
    /// It gives a string (else a number).
    pub gives_text: bool,
    /// What it does, for help lines.
    pub meaning: &'static str,
}

const fn def(
    name: &'static str,
    func: TextFunc,
    args: &'static [Arg],
    min: usize,
    gives_text: bool,
    meaning: &'static str,
) -> TextDef {
    TextDef {
        name,
        func,
        args,
        min,
        gives_text,
        meaning,
    }
}

use Arg::{Either, Num, Text};

/// Every string function.
pub const TEXT_FUNCTIONS: &[TextDef] = &[
    def(
        "LEN",
        TextFunc::Len,
        &[Text],
        1,
        false,
        "length of a string",
    ),
    def(
        "LEFT$",
        TextFunc::Left,
        &[Text, Num],
        2,
        true,
        "first n characters",
    ),
    def(
        "RIGHT$",
        TextFunc::Right,
        &[Text, Num],
        2,
        true,
        "last n characters",
    ),
    def(
        "MID$",
        TextFunc::Mid,
        &[Text, Num, Num],
        2,
        true,
        "n characters from a position",
    ),
    def(
        "STR$",
        TextFunc::Str(PrintHow::Single),
        &[Num],
        1,
        true,
        "a number as text",
    ),
    def(
        "VAL",
        TextFunc::Val,
        &[Text],
        1,
        false,
        "the number a string starts with",
    ),
    def(
        "CHR$",
        TextFunc::Chr,
        &[Num],
        1,
        true,
        "the character of a code",
    ),
    def(
        "ASC",
        TextFunc::Asc,
        &[Text],
        1,
        false,
        "the code of the first character",
    ),
    // INSTR's start is optional in front: the checker moves two arguments to the back.
    def(
        "INSTR",
        TextFunc::Instr,
        &[Num, Text, Text],
        3,
        false,
        "where a string occurs in another",
    ),
    def("SPACE$", TextFunc::Space, &[Num], 1, true, "n spaces"),
    def(
        "STRING$",
        TextFunc::Repeat,
        &[Num, Either],
        2,
        true,
        "n times a character",
    ),
    def("UCASE$", TextFunc::Upper, &[Text], 1, true, "in capitals"),
    def(
        "LCASE$",
        TextFunc::Lower,
        &[Text],
        1,
        true,
        "in small letters",
    ),
    def(
        "LTRIM$",
        TextFunc::TrimStart,
        &[Text],
        1,
        true,
        "without leading spaces",
    ),
    def(
        "RTRIM$",
        TextFunc::TrimEnd,
        &[Text],
        1,
        true,
        "without trailing spaces",
    ),
    def(
        "HEX$",
        TextFunc::Hex,
        &[Num],
        1,
        true,
        "an integer in hexadecimal",
    ),
    def(
        "OCT$",
        TextFunc::Oct,
        &[Num],
        1,
        true,
        "an integer in octal",
    ),
];

/// The string function named `name` (any case).
pub fn find(name: &str) -> Option<&'static TextDef> {
    TEXT_FUNCTIONS
        .iter()
        .find(|d| d.name.eq_ignore_ascii_case(name))
}

impl TextFunc {
    /// The name as written.
    pub fn name(self) -> &'static str {
        let key = match self {
            TextFunc::Str(_) => TextFunc::Str(PrintHow::Single),
            TextFunc::MidSet => TextFunc::Mid,
            f => f,
        };
        TEXT_FUNCTIONS
            .iter()
            .find(|d| d.func == key)
            .map_or("?", |d| d.name)
    }
}

/// An argument's value.
#[derive(Debug, Clone, Copy)]
pub enum Value<'a> {
    /// A number.
    Num(f64),
    /// A string.
    Text(&'a str),
}

impl Value<'_> {
    fn num(self) -> f64 {
        match self {
            Value::Num(x) => x,
            Value::Text(_) => 0.0,
        }
    }
}

fn illegal(what: &str) -> String {
    format!("Illegal function call: {what}")
}

/// A count or position rounded as Microsoft BASIC rounds it (halves to even), within `lo..=hi`.
#[inline]
fn whole(x: f64, lo: i64, hi: i64, what: &str, func: TextFunc) -> Result<i64, String> {
    // Already whole and within (the common case): no rounding.
    let i = x as i64;
    if i as f64 == x && (lo..=hi).contains(&i) {
        return Ok(i);
    }
    rounded(x, lo, hi, what, func)
}

/// [`whole`] of a fraction or a value out of range: apart, so that the common case has no
/// frame for the message's formatting.
#[cold]
#[inline(never)]
fn rounded(x: f64, lo: i64, hi: i64, what: &str, func: TextFunc) -> Result<i64, String> {
    let name = func.name();
    let r = x.round_ties_even();
    if !r.is_finite() || r < lo as f64 || r > hi as f64 {
        return Err(illegal(&format!(
            "{name} takes {what} from {lo} to {hi}, not {x}"
        )));
    }
    Ok(r as i64)
}

/// Put `s` on the end of `out`. A string of at most 16 bytes, as most a program builds are,
/// is copied in place in two moves that may overlap; a call to `memcpy` (what `push_str`
/// makes of a length it does not know) cost more than the copy, and its fast-string move a
/// wait on this machine (8 % of `bench/strings`' time for 5 % of its instructions).
#[inline(always)]
pub fn push(out: &mut String, s: &str) {
    let n = s.len();
    if n > 16 {
        out.push_str(s);
        return;
    }
    out.reserve(n);
    // SAFETY: `reserve` made room for `n` more bytes after the string's `len`: every write
    // below is inside it, every read inside `s`'s `n` bytes (the two moves of a length from 8
    // to 16 cover it from both ends, as do those of 4 to 7). The bytes written are those of
    // `s`, a whole string, after a whole string: the result is valid UTF-8, and `set_len`
    // counts exactly them.
    unsafe {
        let v = out.as_mut_vec();
        let len = v.len();
        let dst = v.as_mut_ptr().add(len);
        let src = s.as_ptr();
        if n >= 8 {
            let head = src.cast::<u64>().read_unaligned();
            let tail = src.add(n - 8).cast::<u64>().read_unaligned();
            dst.cast::<u64>().write_unaligned(head);
            dst.add(n - 8).cast::<u64>().write_unaligned(tail);
        } else if n >= 4 {
            let head = src.cast::<u32>().read_unaligned();
            let tail = src.add(n - 4).cast::<u32>().read_unaligned();
            dst.cast::<u32>().write_unaligned(head);
            dst.add(n - 4).cast::<u32>().write_unaligned(tail);
        } else {
            for i in 0..n {
                *dst.add(i) = *src.add(i);
            }
        }
        v.set_len(len + n);
    }
}

/// `s` from character `from` (0-based), at most `n` characters. Inlined where it is called,
/// the walk through characters of a string that is not ASCII apart.
#[inline(always)]
fn chars(s: &str, from: usize, n: usize, out: &mut String) {
    if s.is_ascii() {
        // One byte a character: a slice, without walking the characters one by one.
        let b = s.as_bytes();
        let start = from.min(b.len());
        let part = &b[start..start + n.min(b.len() - start)];
        // SAFETY: a run of an ASCII string's bytes is ASCII, so valid UTF-8 (the slice of the
        // `str` would test both ends for character boundaries, which every byte of it is).
        push(out, unsafe { std::str::from_utf8_unchecked(part) });
        return;
    }
    wide_chars(s, from, n, out);
}

/// [`chars`] of a string with a character beyond ASCII.
#[cold]
#[inline(never)]
fn wide_chars(s: &str, from: usize, n: usize, out: &mut String) {
    out.extend(s.chars().skip(from).take(n));
}

/// The number of characters of `s` (its length in bytes when it is ASCII, as it mostly is).
pub fn count(s: &str) -> usize {
    if s.is_ascii() {
        s.len()
    } else {
        s.chars().count()
    }
}

/// A string function's arguments, read where they are when the function needs them (the
/// interpreter's registers, or a slice of [`Value`]s): no array of values is built first.
pub trait Args {
    /// How many arguments were given.
    fn count(&self) -> usize;
    /// Argument `i` is a string.
    fn is_text(&self, i: usize) -> bool;
    /// Argument `i` as a number (0 for a string).
    fn num(&self, i: usize) -> f64;
    /// Argument `i` as a string ("" for a number). Err: it names no string.
    fn text(&self, i: usize) -> Result<&str, String>;
}

impl Args for [Value<'_>] {
    fn count(&self) -> usize {
        self.len()
    }

    fn is_text(&self, i: usize) -> bool {
        matches!(self.get(i), Some(Value::Text(_)))
    }

    fn num(&self, i: usize) -> f64 {
        self.get(i).map_or(0.0, |v| v.num())
    }

    fn text(&self, i: usize) -> Result<&str, String> {
        Ok(match self.get(i) {
            Some(Value::Text(s)) => s,
            _ => "",
        })
    }
}

/// Apply `func` to `args`: a string result is written to `out` (emptied first) and `None`
/// returned; a number result is returned. Err: an "Illegal function call" or "String too long".
#[inline]
pub fn apply<A: Args + ?Sized>(
    func: TextFunc,
    args: &A,
    out: &mut String,
) -> Result<Option<f64>, String> {
    out.clear();
    match func {
        TextFunc::Len => return Ok(Some(count(args.text(0)?) as f64)),
        TextFunc::Val => return Ok(Some(val(args.text(0)?))),
        TextFunc::Asc => return asc(args.text(0)?).map(Some),
        TextFunc::Instr => {
            return if args.count() == 3 {
                instr_from(args.num(0), args.text(1)?, args.text(2)?)
            } else {
                Ok(instr(1, args.text(0)?, args.text(1)?))
            }
            .map(Some);
        }
        TextFunc::Left => left(args.text(0)?, args.num(1), out)?,
        TextFunc::Right => right(args.text(0)?, args.num(1), out)?,
        TextFunc::Mid => {
            let n = (args.count() > 2).then(|| args.num(2));
            mid(args.text(0)?, args.num(1), n, out)?;
        }
        TextFunc::MidSet => {
            let (target, replacement) = (args.text(0)?, args.text(2)?);
            let l = count(target);
            let start = whole(args.num(1), 1, 255, "a start", func)? as usize;
            let n = if args.count() > 3 {
                whole(args.num(3), 0, 255, "a count", func)? as usize
            } else {
                MAX_LEN
            };
            if start > l {
                return Err(illegal(&format!(
                    "MID$ = starts at character {start} of a string of {l}"
                )));
            }
            // The string keeps its length: the replacement stops at its end.
            let n = n.min(count(replacement)).min(l - start + 1);
            chars(target, 0, start - 1, out);
            chars(replacement, 0, n, out);
            chars(target, start - 1 + n, MAX_LEN, out);
        }
        TextFunc::Str(how) => str_of(args.num(0), how, out),
        TextFunc::Chr => chr(args.num(0), out)?,
        TextFunc::Space => {
            let n = whole(args.num(0), 0, 255, "a count", func)?;
            out.extend(std::iter::repeat_n(' ', n as usize));
        }
        TextFunc::Repeat => {
            let n = whole(args.num(0), 0, 255, "a count", func)?;
            let c = if args.is_text(1) {
                args.text(1)?
                    .chars()
                    .next()
                    .ok_or_else(|| illegal("STRING$ of an empty string"))?
            } else {
                char::from(whole(args.num(1), 0, 255, "a code", func)? as u8)
            };
            out.extend(std::iter::repeat_n(c, n as usize));
        }
        TextFunc::Upper => out.push_str(&args.text(0)?.to_ascii_uppercase()),
        TextFunc::Lower => out.push_str(&args.text(0)?.to_ascii_lowercase()),
        TextFunc::TrimStart => out.push_str(args.text(0)?.trim_start_matches(' ')),
        TextFunc::TrimEnd => out.push_str(args.text(0)?.trim_end_matches(' ')),
        TextFunc::Hex | TextFunc::Oct => {
            let x = args.num(0).round_ties_even();
            // Within -32768..65535 an INTEGER's 16 bits (GW-BASIC); a long's 32 beyond.
            let bits: u64 = if (-32768.0..=65535.0).contains(&x) {
                (x as i64 as u64) & 0xFFFF
            } else if (f64::from(i32::MIN)..=f64::from(u32::MAX)).contains(&x) {
                (x as i64 as u64) & 0xFFFF_FFFF
            } else {
                return Err(format!(
                    "Overflow: {} takes an integer of 32 bits, not {x}",
                    func.name()
                ));
            };
            let text = if func == TextFunc::Hex {
                format!("{bits:X}")
            } else {
                format!("{bits:o}")
            };
            out.push_str(&text);
        }
    }
    Ok(None)
}

// The functions programs call most, each on its arguments as they are: [`apply`] calls them,
// and the interpreter on the registers its specialised instructions name.

/// `ASC(s)`.
#[inline]
pub fn asc(s: &str) -> Result<f64, String> {
    match s.chars().next() {
        Some(c) => Ok(f64::from(u32::from(c))),
        None => Err(illegal("ASC of an empty string")),
    }
}

/// `INSTR(start, hay, needle)`.
#[inline]
pub fn instr_from(start: f64, hay: &str, needle: &str) -> Result<f64, String> {
    let start = whole(start, 1, 255, "a start", TextFunc::Instr)?;
    Ok(instr(start as usize, hay, needle))
}

/// `LEFT$(s, n)`, written to `out`.
#[inline]
pub fn left(s: &str, n: f64, out: &mut String) -> Result<(), String> {
    let n = whole(n, 0, 255, "a count", TextFunc::Left)?;
    chars(s, 0, n as usize, out);
    Ok(())
}

/// `RIGHT$(s, n)`, written to `out`.
#[inline]
pub fn right(s: &str, n: f64, out: &mut String) -> Result<(), String> {
    let n = whole(n, 0, 255, "a count", TextFunc::Right)? as usize;
    if s.is_ascii() {
        // One byte a character: the last `n` bytes, the string read once.
        push(out, &s[s.len().saturating_sub(n)..]);
    } else {
        wide_chars(s, s.chars().count().saturating_sub(n), n, out);
    }
    Ok(())
}

/// `MID$(s, start[, n])`, written to `out`.
#[inline]
pub fn mid(s: &str, start: f64, n: Option<f64>, out: &mut String) -> Result<(), String> {
    let start = whole(start, 1, 255, "a start", TextFunc::Mid)? as usize;
    let n = match n {
        Some(n) => whole(n, 0, 255, "a count", TextFunc::Mid)? as usize,
        None => MAX_LEN,
    };
    chars(s, start - 1, n, out);
    Ok(())
}

/// `STR$(x)` of a value of type `how`, written to `out`.
#[inline]
pub fn str_of(x: f64, how: PrintHow, out: &mut String) {
    if !crate::vm::print::push_plain(x, how, false, out) {
        crate::vm::print::push_number(x, how, out);
        out.truncate(out.trim_end_matches(' ').len());
    }
}

/// `CHR$(code)`, written to `out`.
#[inline]
pub fn chr(code: f64, out: &mut String) -> Result<(), String> {
    let code = whole(code, 0, 255, "a code", TextFunc::Chr)?;
    // Codes 128–255 are Latin-1 here (what pacer reads Windows-1252 programs as is the same
    // for letters such as `°` and `µ`).
    out.push(char::from(code as u8));
    Ok(())
}

/// INSTR from character `start` (1-based, at least 1): where `needle` first occurs in `hay`,
/// from 1; 0 when nowhere. Inlined where it is called for the common search, a character of
/// a short ASCII string from its start; [`instr_any`] for the others.
#[inline(always)]
pub fn instr(start: usize, hay: &str, needle: &str) -> f64 {
    if let (1, &[byte]) = (start, needle.as_bytes()) {
        let b = hay.as_bytes();
        if b.len() < 32 && hay.is_ascii() {
            return b
                .iter()
                .position(|&c| c == byte)
                .map_or(0.0, |i| (i + 1) as f64);
        }
    }
    instr_any(start, hay, needle)
}

/// [`instr`], every case.
#[inline(never)]
fn instr_any(start: usize, hay: &str, needle: &str) -> f64 {
    let from = start - 1;
    // One pass says whether byte positions are character positions.
    let ascii = hay.is_ascii();
    let len = if ascii {
        hay.len()
    } else {
        hay.chars().count()
    };
    if from >= len {
        return 0.0;
    }
    if needle.is_empty() {
        return start as f64;
    }
    if ascii {
        // A substring search, no copies.
        let rest = &hay.as_bytes()[from..];
        let at = match needle.as_bytes() {
            // A label's few characters are searched quicker than `memchr` is set up.
            [byte] if rest.len() < 32 => rest.iter().position(|c| c == byte),
            [byte] => memchr::memchr(*byte, rest),
            many => memchr::memmem::find(rest, many),
        };
        return at.map_or(0.0, |i| (from + i + 1) as f64);
    }
    let hay_chars: Vec<char> = hay.chars().collect();
    let needle_chars: Vec<char> = needle.chars().collect();
    (from..hay_chars.len())
        .find(|&i| hay_chars[i..].starts_with(&needle_chars))
        .map_or(0.0, |i| (i + 1) as f64)
}

/// Join `a` and `b` into `out`.
pub fn concat(a: &str, b: &str, out: &mut String) -> Result<(), String> {
    out.clear();
    push(out, a);
    append(out, b)
}

/// Put `b` on the end of `a`. Inlined where it is called, the count of characters of a join
/// longer in bytes than a string may be in characters apart.
#[inline(always)]
pub fn append(a: &mut String, b: &str) -> Result<(), String> {
    // Never more characters than bytes: most strings need no count.
    if a.len() + b.len() > MAX_LEN {
        return append_long(a, b);
    }
    push(a, b);
    Ok(())
}

/// [`append`] of a join of more than [`MAX_LEN`] bytes: too long unless characters beyond
/// ASCII (two bytes or more each) make it short enough.
#[cold]
#[inline(never)]
fn append_long(a: &mut String, b: &str) -> Result<(), String> {
    if count(a) + count(b) > MAX_LEN {
        return Err(too_long());
    }
    a.push_str(b);
    Ok(())
}

/// The "String too long" error.
pub fn too_long() -> String {
    format!("String too long: a string holds at most {MAX_LEN} characters")
}

/// Microsoft BASIC's VAL: blanks are skipped, then the longest number at the start is read
/// (`&H`/`&O` prefixes for hexadecimal and octal); 0 when there is none.
#[inline(always)]
pub fn val(s: &str) -> f64 {
    // The common case, a plain whole number of at most 15 digits (exact in an f64), read
    // where it is called, without the copies the general way makes; it gives what the general
    // way gives.
    let b = s.as_bytes();
    if !b.is_empty() && b.len() <= 15 && b.iter().all(u8::is_ascii_digit) {
        return b.iter().fold(0u64, |acc, d| acc * 10 + u64::from(d - b'0')) as f64;
    }
    val_any(s)
}

/// [`val`], every case.
#[inline(never)]
fn val_any(s: &str) -> f64 {
    let t: String = s
        .chars()
        .filter(|c| !matches!(c, ' ' | '\t' | '\n'))
        .collect();
    let upper = t.to_ascii_uppercase();
    if let Some(h) = upper.strip_prefix("&H") {
        let digits: String = h.chars().take_while(char::is_ascii_hexdigit).collect();
        return i64::from_str_radix(&digits, 16).map_or(0.0, |v| v as f64);
    }
    if let Some(o) = upper.strip_prefix("&O").or_else(|| upper.strip_prefix('&')) {
        let digits: String = o.chars().take_while(|c| ('0'..='7').contains(c)).collect();
        return i64::from_str_radix(&digits, 8).map_or(0.0, |v| v as f64);
    }
    let b = upper.as_bytes();
    let mut i = 0;
    if matches!(b.first(), Some(b'+' | b'-')) {
        i += 1;
    }
    let digits_from = i;
    while b.get(i).is_some_and(u8::is_ascii_digit) {
        i += 1;
    }
    if b.get(i) == Some(&b'.') {
        i += 1;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
    }
    if i == digits_from || (i == digits_from + 1 && b.get(digits_from) == Some(&b'.')) {
        return 0.0;
    }
    let mantissa_end = i;
    if matches!(b.get(i), Some(b'E' | b'D')) {
        let mut j = i + 1;
        if matches!(b.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp_digits = j;
        while b.get(j).is_some_and(u8::is_ascii_digit) {
            j += 1;
        }
        if j > exp_digits {
            let text = format!("{}E{}", &upper[..mantissa_end], &upper[i + 1..j]);
            return text.parse().unwrap_or(0.0);
        }
    }
    upper[..mantissa_end].parse().unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::{apply, val, TextFunc, Value};
    use crate::check::typed::PrintHow;

    fn text(func: TextFunc, args: &[Value<'_>]) -> Result<String, String> {
        let mut out = String::new();
        apply(func, args, &mut out)?;
        Ok(out)
    }

    fn num(func: TextFunc, args: &[Value<'_>]) -> Option<f64> {
        apply(func, args, &mut String::new()).ok().flatten()
    }

    use Value::{Num as N, Text as T};

    /// The MID$ statement: the GW-BASIC User's Guide's example (`MID$(A$, 14) = "KS"`), a
    /// count, a replacement longer than what is left, a shorter one, and the errors.
    #[test]
    fn mid_statement_as_microsoft_basic() {
        let set = |args: &[Value<'_>]| text(TextFunc::MidSet, args);
        assert_eq!(
            set(&[T("KANSAS CITY, MO"), N(14.0), T("KS")]).unwrap(),
            "KANSAS CITY, KS"
        );
        assert_eq!(
            set(&[T("ABCDE"), N(2.0), T("xyz"), N(1.0)]).unwrap(),
            "AxCDE"
        );
        assert_eq!(set(&[T("ABCDE"), N(4.0), T("xyz")]).unwrap(), "ABCxy");
        assert_eq!(set(&[T("ABCDE"), N(1.0), T("x")]).unwrap(), "xBCDE");
        assert_eq!(set(&[T("ABCDE"), N(5.0), T("")]).unwrap(), "ABCDE");
        assert_eq!(
            set(&[T("ABCDE"), N(2.0), T("xyz"), N(0.0)]).unwrap(),
            "ABCDE"
        );
        assert_eq!(set(&[T("ÀBC"), N(2.0), T("é")]).unwrap(), "ÀéC");
        for bad in [
            &[T("ABC"), N(0.0), T("x")][..],
            &[T("ABC"), N(4.0), T("x")],
            &[T(""), N(1.0), T("x")],
            &[T("ABC"), N(1.0), T("x"), N(-1.0)],
        ] {
            let e = set(bad).unwrap_err();
            assert!(e.starts_with("Illegal function call"), "{e}");
        }
        assert_eq!(TextFunc::MidSet.name(), "MID$");
    }

    /// The GW-BASIC User's Guide's examples and edge cases of each function.
    #[test]
    fn functions_as_microsoft_basic() {
        assert_eq!(text(TextFunc::Left, &[T("BASIC"), N(3.0)]).unwrap(), "BAS");
        assert_eq!(text(TextFunc::Left, &[T("AB"), N(9.0)]).unwrap(), "AB");
        assert_eq!(text(TextFunc::Right, &[T("BASIC"), N(2.0)]).unwrap(), "IC");
        assert_eq!(
            text(TextFunc::Mid, &[T("GOOD MORNING"), N(6.0), N(4.0)]).unwrap(),
            "MORN"
        );
        assert_eq!(text(TextFunc::Mid, &[T("ABC"), N(5.0)]).unwrap(), "");
        assert_eq!(text(TextFunc::Mid, &[T("ABCDE"), N(2.0)]).unwrap(), "BCDE");
        assert!(text(TextFunc::Mid, &[T("ABC"), N(0.0)]).is_err());
        assert!(text(TextFunc::Left, &[T("ABC"), N(-1.0)]).is_err());
        assert_eq!(num(TextFunc::Len, &[T("ABCD")]), Some(4.0));
        assert_eq!(num(TextFunc::Asc, &[T("A")]), Some(65.0));
        assert!(apply(TextFunc::Asc, &[T("")][..], &mut String::new()).is_err());
        assert_eq!(text(TextFunc::Chr, &[N(66.0)]).unwrap(), "B");
        assert_eq!(
            text(TextFunc::Str(PrintHow::Integer), &[N(42.0)]).unwrap(),
            " 42"
        );
        assert_eq!(
            text(TextFunc::Str(PrintHow::Integer), &[N(-7.0)]).unwrap(),
            "-7"
        );
        // Whole numbers take the quick way, to the edges of their form's plain digits.
        for (how, x, want) in [
            (PrintHow::Single, 0.0, " 0"),
            (PrintHow::Single, -0.0, " 0"),
            (PrintHow::Single, 9_999_999.0, " 9999999"),
            (PrintHow::Single, -9_999_999.0, "-9999999"),
            (PrintHow::Single, 10_000_000.0, " 1E+07"),
            (
                PrintHow::Double,
                8_999_999_999_999_999.0,
                " 8999999999999999",
            ),
            (PrintHow::Integer, -32768.0, "-32768"),
        ] {
            assert_eq!(text(TextFunc::Str(how), &[N(x)]).unwrap(), want, "{x}");
        }
        assert_eq!(
            text(TextFunc::Str(PrintHow::Single), &[N(0.5)]).unwrap(),
            " .5"
        );
        assert_eq!(num(TextFunc::Instr, &[T("ABCDEB"), T("B")]), Some(2.0));
        assert_eq!(
            num(TextFunc::Instr, &[N(3.0), T("ABCDEB"), T("B")]),
            Some(6.0)
        );
        assert_eq!(num(TextFunc::Instr, &[T("ABC"), T("")]), Some(1.0));
        assert_eq!(num(TextFunc::Instr, &[T(""), T("")]), Some(0.0));
        assert_eq!(num(TextFunc::Instr, &[T("ABC"), T("X")]), Some(0.0));
        // A substring, from a start, at the last character, past the end (an empty one too),
        // characters past ASCII in either string.
        let instr = |args: &[Value<'_>]| num(TextFunc::Instr, args);
        assert_eq!(instr(&[T("K-1234/XY"), T("34/")]), Some(5.0));
        assert_eq!(instr(&[N(6.0), T("ABABAB"), T("AB")]), Some(0.0));
        assert_eq!(instr(&[N(5.0), T("ABABAB"), T("AB")]), Some(5.0));
        assert_eq!(instr(&[N(6.0), T("ABABAB"), T("B")]), Some(6.0));
        assert_eq!(instr(&[N(7.0), T("ABABAB"), T("")]), Some(0.0));
        assert_eq!(instr(&[N(6.0), T("ABABAB"), T("")]), Some(6.0));
        assert_eq!(instr(&[T("ABC"), T("\u{b5}")]), Some(0.0));
        assert_eq!(instr(&[T("5 \u{b5}m/s"), T("m")]), Some(4.0));
        assert_eq!(
            instr(&[N(3.0), T("\u{b5}A\u{b5}A"), T("\u{b5}A")]),
            Some(3.0)
        );
        assert_eq!(text(TextFunc::Space, &[N(3.0)]).unwrap(), "   ");
        assert_eq!(text(TextFunc::Repeat, &[N(3.0), N(42.0)]).unwrap(), "***");
        assert_eq!(text(TextFunc::Repeat, &[N(2.0), T("XY")]).unwrap(), "XX");
        assert_eq!(text(TextFunc::Hex, &[N(255.0)]).unwrap(), "FF");
        assert_eq!(text(TextFunc::Hex, &[N(-1.0)]).unwrap(), "FFFF");
        assert_eq!(text(TextFunc::Oct, &[N(8.0)]).unwrap(), "10");
        assert_eq!(text(TextFunc::TrimStart, &[T("  A ")]).unwrap(), "A ");
        assert_eq!(text(TextFunc::Upper, &[T("abc")]).unwrap(), "ABC");
    }

    #[test]
    fn val_reads_the_leading_number() {
        assert_eq!(val(" -3.5E2 xyz"), -350.0);
        assert_eq!(val("12 34"), 1234.0);
        assert_eq!(val("ABC"), 0.0);
        assert_eq!(val("&HFF"), 255.0);
        assert_eq!(val("&O17"), 15.0);
        assert_eq!(val(".5"), 0.5);
        assert_eq!(val("."), 0.0);
        assert_eq!(val("1E"), 1.0);
        assert_eq!(val("-"), 0.0);
    }

    /// `push` copies every length from 0 to 20 bytes (its two moves of 4 and of 8 bytes, its
    /// bytes one by one, `push_str` past 16), onto empty, exactly full and roomy strings.
    #[test]
    fn push_copies_every_short_length() {
        let ascii = "ABCDEFGHIJKLMNOPQRSTUVWXYZ";
        for n in 0..=20 {
            // `µ` is two bytes: a piece with it is `n` bytes long too (2 when `n` is less).
            let pieces = [
                ascii[..n].to_string(),
                format!("µ{}", &ascii[..n.saturating_sub(2)]),
            ];
            for (piece, prefix) in pieces
                .iter()
                .flat_map(|p| ["", "x", "prefix of twenty-one"].map(|x| (p, x)))
            {
                for spare in [0, 3, 64] {
                    let mut out = String::with_capacity(prefix.len() + spare);
                    out.push_str(prefix);
                    super::push(&mut out, piece);
                    assert_eq!(out, format!("{prefix}{piece}"), "{n} {prefix:?} {spare}");
                }
            }
        }
    }

    /// A join longer than 255 bytes is too long only when it is longer than 255 characters.
    #[test]
    fn joins_count_characters_past_255_bytes() {
        let mu = "µ".repeat(120); // 240 bytes, 120 characters
        let mut a = mu.clone();
        assert!(super::append(&mut a, &"A".repeat(135)).is_ok());
        assert_eq!(a.chars().count(), 255);
        let mut b = mu.clone();
        assert!(super::append(&mut b, &"A".repeat(136)).is_err());
        assert_eq!(b, mu, "a join refused leaves the string as it was");
        let mut c = "A".repeat(200);
        assert!(super::append(&mut c, &"B".repeat(56)).is_err());
        assert!(super::append(&mut c, &"B".repeat(55)).is_ok());
        assert_eq!(c.len(), 255);
    }

    /// The ASCII quick ways (slices, byte search, digits read directly) give what walking the
    /// characters gives: the same strings written with a µ take the general way.
    #[test]
    fn ascii_quick_ways_agree_with_the_characters() {
        for (s, mu) in [("AB-1234/XY", "µB-1234/XY"), ("HELLO", "HELLµ")] {
            for (a, b) in [
                (0.0, 0.0),
                (1.0, 3.0),
                (3.0, 4.0),
                (2.0, 99.0),
                (9.0, 1.0),
                (200.0, 5.0),
            ] {
                for func in [TextFunc::Left, TextFunc::Right] {
                    let x = text(func, &[T(s), N(b)]).unwrap();
                    let y = text(func, &[T(mu), N(b)]).unwrap();
                    assert_eq!(x.chars().count(), y.chars().count(), "{func:?} {s} {b}");
                }
                if a >= 1.0 {
                    let x = text(TextFunc::Mid, &[T(s), N(a), N(b)]).unwrap();
                    let y = text(TextFunc::Mid, &[T(mu), N(a), N(b)]).unwrap();
                    assert_eq!(x.chars().count(), y.chars().count(), "MID$ {s} {a} {b}");
                    let start = a as usize - 1;
                    let want: String = s.chars().skip(start).take(b as usize).collect();
                    assert_eq!(x, want, "MID$ {s} {a} {b}");
                }
            }
            assert_eq!(num(TextFunc::Len, &[T(s)]), num(TextFunc::Len, &[T(mu)]));
            for find in ["B", "1234", "/X", "Z", "L", "LO", "µ"] {
                for start in [1.0, 2.0, 4.0, 11.0] {
                    for hay in [s, mu] {
                        let got = num(TextFunc::Instr, &[N(start), T(hay), T(find)]);
                        let h: Vec<char> = hay.chars().collect();
                        let f: Vec<char> = find.chars().collect();
                        let want = (start as usize - 1..h.len())
                            .find(|&i| h[i..].starts_with(&f))
                            .map_or(0.0, |i| (i + 1) as f64);
                        assert_eq!(got, Some(want), "INSTR({start}, {hay}, {find})");
                    }
                }
            }
        }
        assert_eq!(num(TextFunc::Instr, &[T("AB-1234/XY"), T("/")]), Some(8.0));
        // RIGHT$ reads an ASCII string once, as bytes: the characters' answer.
        for (s, n) in [
            ("HELLO", 2.0),
            ("HELLµ", 2.0),
            ("µB", 5.0),
            ("AB", 0.0),
            ("", 3.0),
        ] {
            let want: String = {
                let c: Vec<char> = s.chars().collect();
                c[c.len().saturating_sub(n as usize)..].iter().collect()
            };
            assert_eq!(
                text(TextFunc::Right, &[T(s), N(n)]).unwrap(),
                want,
                "{s} {n}"
            );
        }
        // INSTR of one character from the start searches a string shorter than 32 bytes in
        // place; longer ones, and any with a character beyond ASCII, the general way.
        let long = format!("{}/{}", "A".repeat(31), "B".repeat(8));
        let long_mu = format!("µ{}/{}", "A".repeat(30), "B".repeat(8));
        for (hay, find, want) in [
            ("A".repeat(31), "A", 1.0),
            (format!("{}/", "A".repeat(30)), "/", 31.0),
            (long.clone(), "/", 32.0),
            (long.clone(), "B", 33.0),
            (long_mu.clone(), "/", 32.0),
            (long_mu, "µ", 1.0),
            ("µ/".to_string(), "/", 2.0),
            (long, "Z", 0.0),
        ] {
            assert_eq!(
                num(TextFunc::Instr, &[T(&hay), T(find)]),
                Some(want),
                "{hay} {find}"
            );
        }
        for s in [
            "0",
            "7",
            "0042",
            "1234",
            "123456789012345",
            "1234567890123456",
            " 12",
        ] {
            assert_eq!(val(s), s.trim().parse::<f64>().unwrap(), "{s}");
        }
    }
}
