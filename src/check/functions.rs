//! The math functions programs may call.

/// A built-in function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Func {
    Abs,
    Sqrt,
    Sin,
    Cos,
    Tan,
    Atan,
    Atan2,
    Exp,
    Ln,
    Log10,
    Int,
    Fix,
    Round,
    Sgn,
    Min,
    Max,
    /// Microsoft BASIC's CINT/CLNG: to the nearest integer, halves to even.
    Cint,
    /// CSNG: to single precision.
    Csng,
    /// CDBL: the value itself (pacer computes in double precision).
    Cdbl,
}

/// Names, arity and meaning. Angles are in radians, as in BASIC.
pub const FUNCTIONS: &[(&str, Func, usize, &str)] = &[
    ("ABS", Func::Abs, 1, "absolute value"),
    ("SQRT", Func::Sqrt, 1, "square root"),
    ("SQR", Func::Sqrt, 1, "square root (BASIC spelling)"),
    ("SIN", Func::Sin, 1, "sine of radians"),
    ("COS", Func::Cos, 1, "cosine of radians"),
    ("TAN", Func::Tan, 1, "tangent of radians"),
    ("ATAN", Func::Atan, 1, "arc tangent, radians"),
    (
        "ATN",
        Func::Atan,
        1,
        "arc tangent, radians (BASIC spelling)",
    ),
    ("ATAN2", Func::Atan2, 2, "arc tangent of y/x, radians"),
    ("EXP", Func::Exp, 1, "e to the power"),
    ("LN", Func::Ln, 1, "natural logarithm"),
    ("LOG", Func::Ln, 1, "natural logarithm (BASIC meaning)"),
    ("LOG10", Func::Log10, 1, "base-10 logarithm"),
    ("INT", Func::Int, 1, "largest integer not above"),
    ("FIX", Func::Fix, 1, "integer part (towards zero)"),
    ("TRUNC", Func::Fix, 1, "integer part (towards zero)"),
    (
        "ROUND",
        Func::Round,
        1,
        "nearest integer, halves away from zero",
    ),
    ("SGN", Func::Sgn, 1, "-1, 0 or 1"),
    ("MIN", Func::Min, 2, "smaller of two"),
    ("MAX", Func::Max, 2, "larger of two"),
    (
        "CINT",
        Func::Cint,
        1,
        "nearest integer, halves to even (Microsoft BASIC)",
    ),
    (
        "CLNG",
        Func::Cint,
        1,
        "nearest integer, halves to even (Microsoft BASIC)",
    ),
    ("CSNG", Func::Csng, 1, "to single precision"),
    ("CDBL", Func::Cdbl, 1, "to double precision"),
];

/// Look up a function by name, ignoring case.
pub fn find(name: &str) -> Option<(Func, usize)> {
    FUNCTIONS
        .iter()
        .find(|f| f.0.eq_ignore_ascii_case(name))
        .map(|f| (f.1, f.2))
}

impl Func {
    /// Apply the function. The result may be NaN or infinite; the caller reports that.
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Func::Abs => a.abs(),
            Func::Sqrt => a.sqrt(),
            Func::Sin => a.sin(),
            Func::Cos => a.cos(),
            Func::Tan => a.tan(),
            Func::Atan => a.atan(),
            Func::Atan2 => a.atan2(b),
            Func::Exp => a.exp(),
            Func::Ln => a.ln(),
            Func::Log10 => a.log10(),
            Func::Int => a.floor(),
            Func::Fix => a.trunc(),
            Func::Round => a.round(),
            Func::Sgn => {
                if a > 0.0 {
                    1.0
                } else if a < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
            Func::Min => a.min(b),
            Func::Max => a.max(b),
            Func::Cint => a.round_ties_even() + 0.0,
            Func::Csng => f64::from(a as f32),
            Func::Cdbl => a,
        }
    }

    /// The name used in disassembly.
    pub fn name(self) -> &'static str {
        FUNCTIONS.iter().find(|f| f.1 == self).map_or("?", |f| f.0)
    }
}

pub use crate::devices::command::KernelFunc;

/// Kernel functions: name, function, arity, meaning.
pub const KERNEL_FUNCTIONS: &[(&str, KernelFunc, usize, &str)] = &[
    (
        "REGIST",
        KernelFunc::Regist,
        7,
        "REGIST(EN, AXIS, DIST, TOLR, IGNR, LGTH, DIM): length registration on a fast input",
    ),
    (
        "STATUSSV",
        KernelFunc::StatusSv,
        1,
        "STATUSSV(AXIS): registration status bits",
    ),
    (
        "READ_SV",
        KernelFunc::ReadSv,
        2,
        "READ_SV(AXIS, VAR): read servo variable VAR (9–25)",
    ),
    (
        "WRITE_SV",
        KernelFunc::WriteSv,
        3,
        "WRITE_SV(AXIS, VAR, VALUE): write servo variable VAR",
    ),
];

/// Look up a kernel function by name, ignoring case.
pub fn find_kernel(name: &str) -> Option<(KernelFunc, usize)> {
    KERNEL_FUNCTIONS
        .iter()
        .find(|f| f.0.eq_ignore_ascii_case(name))
        .map(|f| (f.1, f.2))
}

impl KernelFunc {
    /// The name as written.
    pub fn name(self) -> &'static str {
        KERNEL_FUNCTIONS
            .iter()
            .find(|f| f.1 == self)
            .map_or("?", |f| f.0)
    }

    /// How many arguments it takes (the table's count, as a `match` for the VM, which needs
    /// it at every call).
    pub fn arity(self) -> usize {
        match self {
            KernelFunc::Regist => 7,
            KernelFunc::StatusSv => 1,
            KernelFunc::ReadSv => 2,
            KernelFunc::WriteSv => 3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_arity_is_the_tables_count() {
        for &(name, func, count, _) in KERNEL_FUNCTIONS {
            assert_eq!(func.arity(), count, "{name}");
            assert_eq!(func.name(), name);
        }
        assert_eq!(KERNEL_FUNCTIONS.len(), 4);
    }
}
