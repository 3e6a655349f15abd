//! Value forms shared by the machine and scenario files: durations and boolean words.

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;
use std::fmt;

/// A duration in integer nanoseconds, written as seconds (`0.05`) or with a unit
/// (`"50ms"`, `"62.5us"`, `"2s"`, `"125ns"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Duration(pub u64);

impl Duration {
    /// Seconds as a float.
    pub fn seconds(self) -> f64 {
        self.0 as f64 / 1e9
    }
}

/// Parse `"50ms"`-style text to nanoseconds.
pub fn parse_duration(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| c.is_ascii_alphabetic() || c == 'µ')
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.trim().parse().map_err(|_| {
        format!("`{text}` is not a duration (write e.g. 0.05, \"50ms\", \"62.5us\")")
    })?;
    let scale = match unit.trim() {
        "" | "s" => 1e9,
        "ms" => 1e6,
        "us" | "µs" => 1e3,
        "ns" => 1.0,
        other => return Err(format!("unknown time unit `{other}` (use s, ms, us or ns)")),
    };
    seconds_to_ns(value * scale / 1e9)
}

/// Seconds to whole nanoseconds, refusing negative, infinite and absurd values.
pub fn seconds_to_ns(s: f64) -> Result<u64, String> {
    if !s.is_finite() || s < 0.0 {
        return Err(format!(
            "a duration must be a finite number of seconds, at least 0 (got {})",
            crate::diag::number(s)
        ));
    }
    let ns = (s * 1e9).round();
    if ns > super::limits::MAX_TIME_NS as f64 {
        return Err(format!(
            "{} s is too long: times are at most 1,000,000 s (about 11.6 days)",
            crate::diag::number(s)
        ));
    }
    Ok(ns as u64)
}

impl<'de> Deserialize<'de> for Duration {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Duration;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a duration: seconds as a number, or a string such as \"50ms\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Duration, E> {
                seconds_to_ns(v).map(Duration).map_err(E::custom)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Duration, E> {
                seconds_to_ns(v as f64).map(Duration).map_err(E::custom)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Duration, E> {
                seconds_to_ns(v as f64).map(Duration).map_err(E::custom)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Duration, E> {
                parse_duration(v).map(Duration).map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// A level written as `true`/`false` or a PowerTools word (`"ON"`, `"OFF"`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Level(pub bool);

/// The PowerTools meaning of a boolean word, if it is one.
pub fn bool_word(word: &str) -> Option<bool> {
    match word.to_ascii_uppercase().as_str() {
        "ON" | "TRUE" | "YES" | "SET" | "ENABLE" => Some(true),
        "OFF" | "FALSE" | "NO" | "CLEAR" | "DISABLE" => Some(false),
        _ => None,
    }
}

impl<'de> Deserialize<'de> for Level {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Level;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("true/false or ON/OFF")
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<Level, E> {
                Ok(Level(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Level, E> {
                bool_word(v)
                    .map(Level)
                    .ok_or_else(|| E::custom(format!("`{v}` is not a level: use ON or OFF")))
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("1ms"), Ok(1_000_000));
        assert_eq!(parse_duration("62.5us"), Ok(62_500));
        assert_eq!(parse_duration("2"), Ok(2_000_000_000));
        assert!(parse_duration("5 parsecs").is_err());
        assert!(parse_duration("-1ms").is_err());
    }
}
