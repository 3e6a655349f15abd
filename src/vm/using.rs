//! `PRINT USING` as Microsoft BASIC formats it (GW-BASIC User's Guide, "PRINT USING"): a
//! format string of fields and literal text, used over the values in turn and again from its
//! start when values remain.
//!
//! Fields: `!` (a string's first character), `\  \` (as many characters as the field is wide,
//! backslashes included), `&` (the whole string); numbers: `#` digit positions, `.` the point,
//! `,` before the point (thousands separated by commas; one more position), a leading or
//! trailing `+` (the sign, `+` or `-`), a trailing `-` (a minus after negative numbers), `**`
//! (leading spaces filled with `*`, two more positions), `$$` (a `$` right before the digits,
//! two more positions, one for the `$`), `**$` (both, three more positions), `^^^^` or `^^^^^`
//! (E notation). A number that does not fit its field is printed whole after a `%`. `_` prints
//! the next character of the format as it is.

use crate::check::text::Value;

/// What one numeric field asks for.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
struct NumField {
    /// Digit positions before the point (`#`, `,`, and those of `**`/`$$`).
    before: usize,
    /// Digits after the point.
    after: usize,
    point: bool,
    commas: bool,
    stars: bool,
    dollar: bool,
    lead_plus: bool,
    trail_plus: bool,
    trail_minus: bool,
    /// `^^^^` (4) or `^^^^^` (5): E notation with 2 or 3 exponent digits.
    carets: usize,
}

/// A field of the format string.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Field {
    /// `!`.
    First,
    /// `\  \`: this many characters.
    Width(usize),
    /// `&`.
    Whole,
    /// A number.
    Num(NumField),
}

/// The field starting at `i` of `f`, and where it ends; `None` when a literal starts there.
fn field_at(f: &[char], i: usize) -> Option<(Field, usize)> {
    let at = |k: usize| f.get(k).copied();
    match at(i)? {
        '!' => return Some((Field::First, i + 1)),
        '&' => return Some((Field::Whole, i + 1)),
        '\\' => {
            let mut j = i + 1;
            while at(j) == Some(' ') {
                j += 1;
            }
            return (at(j) == Some('\\')).then_some((Field::Width(j - i + 1), j + 1));
        }
        _ => {}
    }
    let mut n = NumField::default();
    let mut j = i;
    if at(j) == Some('+') {
        n.lead_plus = true;
        j += 1;
    }
    if at(j) == Some('*') && at(j + 1) == Some('*') {
        n.stars = true;
        n.before += 2;
        j += 2;
        if at(j) == Some('$') {
            n.dollar = true;
            n.before += 1;
            j += 1;
        }
    } else if at(j) == Some('$') && at(j + 1) == Some('$') {
        n.dollar = true;
        n.before += 2;
        j += 2;
    }
    let prefix = j > i + usize::from(n.lead_plus);
    let digits_from = j;
    while matches!(at(j), Some('#') | Some(',')) {
        if at(j) == Some(',') {
            n.commas = true;
        }
        n.before += 1;
        j += 1;
    }
    if at(j) == Some('.') && (j > digits_from || prefix || at(j + 1) == Some('#')) {
        n.point = true;
        j += 1;
        while at(j) == Some('#') {
            n.after += 1;
            j += 1;
        }
    }
    if !prefix && j == digits_from {
        return None;
    }
    let carets = f[j..].iter().take_while(|&&c| c == '^').count();
    if carets >= 4 {
        n.carets = carets.min(5);
        j += n.carets;
    }
    match at(j) {
        Some('+') if !n.lead_plus => {
            n.trail_plus = true;
            j += 1;
        }
        Some('-') if !n.lead_plus => {
            n.trail_minus = true;
            j += 1;
        }
        _ => {}
    }
    Some((Field::Num(n), j))
}

/// Format `values` with the format string `format`. Err: the format has no field, or a value
/// does not suit its field ("Type mismatch").
pub fn format(format: &str, values: &[Value<'_>]) -> Result<String, String> {
    let f: Vec<char> = format.chars().collect();
    if !(0..f.len()).any(|i| field_at(&f, i).is_some()) {
        return Err(format!(
            "Illegal function call: the PRINT USING format \"{format}\" has no field"
        ));
    }
    let mut out = String::new();
    let mut i = 0;
    let mut next = 0;
    loop {
        if i >= f.len() {
            if next >= values.len() {
                break;
            }
            i = 0;
        }
        if f[i] == '_' {
            if let Some(&c) = f.get(i + 1) {
                out.push(c);
            }
            i += 2;
            continue;
        }
        match field_at(&f, i) {
            None => {
                out.push(f[i]);
                i += 1;
            }
            Some((field, end)) => {
                let Some(v) = values.get(next) else {
                    // The values are used up: the format stops at its next field.
                    break;
                };
                put(&mut out, field, *v)?;
                next += 1;
                i = end;
            }
        }
    }
    Ok(out)
}

fn put(out: &mut String, field: Field, v: Value<'_>) -> Result<(), String> {
    match (field, v) {
        (Field::First, Value::Text(s)) => out.push(s.chars().next().unwrap_or(' ')),
        (Field::Width(w), Value::Text(s)) => {
            let n = s.chars().count();
            out.extend(s.chars().take(w));
            out.extend(std::iter::repeat_n(' ', w.saturating_sub(n)));
        }
        (Field::Whole, Value::Text(s)) => out.push_str(s),
        (Field::Num(n), Value::Num(x)) => out.push_str(&number(n, x)),
        (Field::Num(_), Value::Text(_)) => {
            return Err("Type mismatch: a PRINT USING number field (#) gets a string".into())
        }
        (_, Value::Num(_)) => {
            return Err(
                "Type mismatch: a PRINT USING string field (!, &, \\ \\) gets a number".into(),
            )
        }
    }
    Ok(())
}

/// Digits of `s` (no sign) grouped by three with commas.
fn grouped(s: &str) -> String {
    let len = s.len();
    let mut out = String::with_capacity(len + len / 3);
    for (k, c) in s.chars().enumerate() {
        if k > 0 && (len - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// One number in its field.
fn number(n: NumField, x: f64) -> String {
    let negative = x < 0.0;
    let explicit_sign = n.lead_plus || n.trail_plus || n.trail_minus;
    let width = n.before + usize::from(n.point) + n.after + n.carets + usize::from(explicit_sign);
    let body = if n.carets > 0 {
        exponential(n, x.abs())
    } else {
        let text = format!("{:.*}", n.after, x.abs());
        let (int, frac) = text.split_once('.').unwrap_or((&text, ""));
        // A lone 0 before the point is written when the field has a position left for it.
        let taken = usize::from(n.dollar) + usize::from(negative && !explicit_sign);
        let int = if int == "0" && n.point && n.before <= taken {
            String::new()
        } else if n.commas {
            grouped(int)
        } else {
            int.to_string()
        };
        let int = if int.is_empty() && !n.point {
            "0".to_string()
        } else {
            int
        };
        if n.point {
            format!("{int}.{frac}")
        } else {
            int
        }
    };
    let dollar = if n.dollar { "$" } else { "" };
    let mut core = match (negative, explicit_sign) {
        (true, false) => format!("-{dollar}{body}"),
        _ => format!("{dollar}{body}"),
    };
    if n.lead_plus {
        core.insert(0, if negative { '-' } else { '+' });
    }
    if n.trail_plus {
        core.push(if negative { '-' } else { '+' });
    }
    if n.trail_minus {
        core.push(if negative { '-' } else { ' ' });
    }
    let len = core.chars().count();
    if len > width {
        return format!("%{core}");
    }
    let pad = if n.stars { '*' } else { ' ' };
    let mut s: String = std::iter::repeat_n(pad, width - len).collect();
    s.push_str(&core);
    s
}

/// `x` (not negative) in E notation: as many digits before the point as the field has
/// positions (one kept for the sign when the format gives none), `after` after it.
fn exponential(n: NumField, x: f64) -> String {
    let explicit_sign = n.lead_plus || n.trail_plus || n.trail_minus;
    let digits = n.before.saturating_sub(usize::from(!explicit_sign)) as i32;
    let exp_digits = if n.carets >= 5 { 3 } else { 2 };
    let mut exp = if x == 0.0 {
        0
    } else {
        x.log10().floor() as i32 - (digits - 1)
    };
    let mut mantissa = x / 10f64.powi(exp);
    let mut text = format!("{:.*}", n.after, mantissa);
    // Rounding may carry into one more digit: scale once more.
    let int_len = |t: &str| match t.split('.').next().unwrap_or_default() {
        "0" => 0,
        int => int.len() as i32,
    };
    if int_len(&text) > digits {
        exp += 1;
        mantissa = x / 10f64.powi(exp);
        text = format!("{:.*}", n.after, mantissa);
    }
    if digits == 0 {
        text = text.trim_start_matches('0').to_string();
    }
    if !n.point {
        text = text.split('.').next().unwrap_or_default().to_string();
    }
    let sign = if exp < 0 { '-' } else { '+' };
    format!("{text}E{sign}{:0width$}", exp.abs(), width = exp_digits)
}

#[cfg(test)]
mod tests {
    use super::format;
    use crate::check::text::Value::{Num as N, Text as T};

    fn f(fmt: &str, values: &[crate::check::text::Value<'_>]) -> String {
        format(fmt, values).unwrap()
    }

    /// The examples of the GW-BASIC User's Guide, "PRINT USING".
    #[test]
    fn the_manuals_examples() {
        assert_eq!(f("!", &[T("LOOK"), T("OUT")]), "LO");
        assert_eq!(f("\\  \\", &[T("LOOK"), T("OUT")]), "LOOKOUT ");
        assert_eq!(f("!", &[T("LOOK")]) + &f("&", &[T("OUT")]), "LOUT");
        assert_eq!(f("##.##", &[N(0.78)]), " 0.78");
        assert_eq!(f("###.##", &[N(987.654)]), "987.65");
        assert_eq!(
            f("##.##   ", &[N(10.2), N(5.3), N(66.789), N(0.234)]),
            "10.20    5.30   66.79    0.23   "
        );
        assert_eq!(
            f("+##.##   ", &[N(-68.95), N(2.4), N(55.6), N(-0.9)]),
            "-68.95    +2.40   +55.60    -0.90   "
        );
        assert_eq!(
            f("##.##-   ", &[N(-68.95), N(22.449), N(-7.01)]),
            "68.95-   22.45     7.01-   "
        );
        assert_eq!(
            f("**#.#   ", &[N(12.39), N(-0.9), N(765.1)]),
            "*12.4   *-0.9   765.1   "
        );
        assert_eq!(f("$$###.##", &[N(456.78)]), " $456.78");
        assert_eq!(f("**$##.##", &[N(2.34)]), "***$2.34");
        assert_eq!(f("####,.##", &[N(1234.5)]), "1,234.50");
        assert_eq!(f("##.##^^^^", &[N(234.56)]), " 2.35E+02");
        assert_eq!(f(".####^^^^-", &[N(-888888.0)]), ".8889E+06-");
        assert_eq!(f("+.##^^^^", &[N(123.0)]), "+.12E+03");
        assert_eq!(f("_!##.##_!", &[N(12.34)]), "!12.34!");
        assert_eq!(f("##.##", &[N(111.22)]), "%111.22");
        assert_eq!(f(".##", &[N(0.999)]), "%1.00");
    }

    #[test]
    fn fields_and_values_must_match() {
        assert!(format("##", &[T("A")]).is_err());
        assert!(format("&", &[N(1.0)]).is_err());
        assert!(format("no field", &[N(1.0)]).is_err());
        assert_eq!(f("A=## B=##!", &[N(1.0)]), "A= 1 B=");
    }
}
