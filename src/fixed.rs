//! Fixed-point storage as the controllers keep it: signed 32-bit values with a number of decimal
//! places, rounded half away from zero on the decimal value the user wrote.

/// Powers of ten for the decimal places 0 to 9.
pub const POW10: [f64; 10] = [1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Round a scaled value (value × 10^decimals) to a whole number, half away from zero.
///
/// A decimal such as 1.005 has no exact binary form (it is 1.00499999999999989…), so its scaled
/// value lands a hair below the half. Values within a few units in the last place of a half are
/// taken as the half the user wrote. Avoids a libm call for anything a 32-bit store can keep.
///
/// Every fixed-point store of a PowerTools program with decimals goes through here, often on a
/// dependency chain (a filter's `Var.Y = Var.Y + K * (Var.X - Var.Y)`): below 2^49 the rounding
/// stays in floating point (two additions round to nearest), which waits for no conversion
/// between the number units; its result is that of [`round_scaled_wide`] (`tests` compare them).
#[inline(always)]
pub fn round_scaled(y: f64) -> f64 {
    // 1.5 × 2^52: adding it to |y| < 2^51 leaves a number whose last place is 1, so the sum is
    // y rounded to a whole number (ties to even), and subtracting it again is exact.
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    const NARROW: f64 = 562_949_953_421_312.0; // 2^49: below it the slack is under a half
    let a = y.abs();
    if a >= NARROW || y.is_nan() {
        return round_scaled_wide(y);
    }
    let near = (y + MAGIC) - MAGIC;
    let d = y - near; // exact, within ±0.5
    let slack = a * (4.0 * f64::EPSILON);
    // Within the slack of a half, the half is taken and rounds away from zero: `near` moves one
    // away when it lies toward zero from y (then d has y's sign). Selects of constants, no
    // branch: how often a value is near a half depends on the data.
    let half = d.abs() + slack >= 0.5;
    let toward = d * y > 0.0;
    let step = if half && toward {
        1.0f64.copysign(y)
    } else {
        0.0
    };
    // Never -0, as an integer converted is not: `near` is a difference of equal numbers (+0)
    // or whole, and `near + step` is 0 only as -1 + 1 or 1 - 1 (+0).
    near + step
}

/// [`round_scaled`] through a 64-bit integer, for every magnitude: the values of 2^49 and more
/// (none fits a 32-bit store), infinities and NaN.
pub fn round_scaled_wide(y: f64) -> f64 {
    const LIMIT: f64 = 4_503_599_627_370_496.0; // 2^52: above it every f64 is whole
    if y.abs() >= LIMIT || y.is_nan() {
        return y.round();
    }
    // SAFETY: |y| < 2^52 and y is not NaN (checked above), so it fits an i64.
    let t: i64 = unsafe { y.to_int_unchecked() };
    let frac = (y - t as f64).abs();
    let slack = y.abs() * (4.0 * f64::EPSILON);
    // Branch-free: the rounding direction depends on data and predicts poorly.
    let up = i64::from(frac + slack >= 0.5);
    let sign = if y >= 0.0 { 1 } else { -1 };
    (t + up * sign) as f64
}

/// `v` rounded to `decimals` places.
#[inline(always)]
pub fn round_to(v: f64, decimals: u8) -> f64 {
    let scale = POW10[decimals.min(9) as usize];
    round_scaled(v * scale) / scale
}

/// `x` as stored in a signed 32-bit fixed-point slot with `decimals` places, or `None` when it
/// does not fit (or is not a number).
#[inline(always)]
pub fn to_fixed(x: f64, decimals: u8) -> Option<f64> {
    // Whole numbers within 32 bits are stored as they are (the common case for counters): a
    // round trip through `trunc_i32` gives back exactly those.
    if decimals == 0 && f64::from(trunc_i32(x)) == x {
        // x itself (-0 made 0): a value computed from the conversions would wait for them.
        return Some(x + 0.0);
    }
    let scale = POW10[decimals.min(9) as usize];
    let r = round_scaled(x * scale);
    // NaN fails this test too.
    let fits = r >= f64::from(i32::MIN) && r <= f64::from(i32::MAX);
    fits.then(|| r / scale)
}

/// `x` truncated to an `i32`, any `i32` when it is out of range or NaN: callers keep the result
/// only when it converts back to `x`, so only a whole `x` within 32 bits is used. On x86-64 this
/// is the bare conversion instruction (whose out-of-range answer, `i32::MIN`, converts back to
/// `x` only when `x` is exactly that); Rust's `as` adds a clamp and a NaN test the round trip
/// makes unnecessary.
#[inline(always)]
pub fn trunc_i32(x: f64) -> i32 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_cvttsd_si32, _mm_set_sd};
        // SAFETY: SSE2 is part of the x86-64 baseline, so these instructions always exist.
        unsafe { _mm_cvttsd_si32(_mm_set_sd(x)) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        x as i32
    }
}

/// `x` truncated to an `i64`, any `i64` when it is out of range or NaN: as [`trunc_i32`], for
/// callers that keep the result only when it converts back to `x` (the bare conversion
/// instruction on x86-64, without `as`'s clamp and NaN test).
#[inline(always)]
pub fn trunc_i64(x: f64) -> i64 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_cvttsd_si64, _mm_set_sd};
        // SAFETY: SSE2 is part of the x86-64 baseline, so these instructions always exist.
        unsafe { _mm_cvttsd_si64(_mm_set_sd(x)) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        x as i64
    }
}

/// The range of a 32-bit fixed-point slot with `decimals` places, for messages.
pub fn range_text(decimals: u8) -> String {
    let scale = POW10[decimals.min(9) as usize];
    format!(
        "{} to {}",
        f64::from(i32::MIN) / scale,
        f64::from(i32::MAX) / scale
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The two roundings agree bit for bit, zeros' signs included.
    fn same(y: f64) {
        let (quick, wide) = (round_scaled(y), round_scaled_wide(y));
        assert_eq!(
            quick.to_bits(),
            wide.to_bits(),
            "{y:e}: {quick} against {wide}"
        );
    }

    /// The double next below a positive `x`.
    fn below(x: f64) -> f64 {
        f64::from_bits(x.to_bits() - 1)
    }

    #[test]
    fn both_roundings_agree_at_halves_zeros_and_limits() {
        for y in [
            0.0,
            -0.0,
            0.3,
            -0.3,
            0.5,
            -0.5,
            0.7,
            -0.7,
            1.5,
            -1.5,
            2.5,
            -2.5,
            3.5,
            -3.5,
            below(100_500.0),
            below(1_005.0),
            -below(1_005.0),
            2_147_483_647.5,
            -2_147_483_648.5,
            below(2_147_483_646.5),
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            562_949_953_421_311.5,
            562_949_953_421_312.0,
            -562_949_953_421_311.5,
            1e15 + 0.5,
        ] {
            if y.is_nan() {
                assert!(round_scaled(y).is_nan());
            } else {
                same(y);
            }
        }
        // Every decimal with up to 6 places a program writes, scaled as a store scales it.
        for decimals in 1..=6u8 {
            let scale = POW10[decimals as usize];
            for k in -3000..3000 {
                let v = f64::from(k) / scale + f64::from(k % 7) * 0.25;
                same(v * scale);
                same((v + 0.5 / scale) * scale);
            }
        }
    }

    proptest! {
        #[test]
        fn both_roundings_agree_everywhere(bits in any::<u64>()) {
            let y = f64::from_bits(bits);
            if !y.is_nan() {
                same(y);
            }
        }

        #[test]
        fn both_roundings_agree_near_halves(k in -(1i64 << 50)..(1i64 << 50), ulps in -40i64..40) {
            let half = k as f64 + 0.5;
            let y = f64::from_bits((half.to_bits() as i64 + ulps) as u64);
            same(y);
            same(y / 1e6 * 1e6);
        }
    }

    #[test]
    fn halves_round_away_from_zero_on_the_decimal_value() {
        assert_eq!(round_to(1.005, 2), 1.01);
        assert_eq!(round_to(-1.005, 2), -1.01);
        assert_eq!(round_to(2.675, 2), 2.68);
        assert_eq!(round_to(1.00005, 4), 1.0001);
        assert_eq!(round_to(0.1 + 0.2, 2), 0.3);
        assert_eq!(round_to(2.5, 0), 3.0);
        assert_eq!(round_to(-2.5, 0), -3.0);
        assert_eq!(round_to(2.4999, 0), 2.0);
        assert_eq!(round_to(1e15 + 0.5, 0), 1e15 + 1.0);
    }

    #[test]
    fn the_whole_signed_range_fits() {
        assert_eq!(to_fixed(-2_147_483_648.0, 0), Some(-2_147_483_648.0));
        assert_eq!(to_fixed(2_147_483_647.0, 0), Some(2_147_483_647.0));
        assert_eq!(to_fixed(2_147_483_648.0, 0), None);
        assert_eq!(to_fixed(-21_474_836.48, 2), Some(-21_474_836.48));
        assert_eq!(to_fixed(f64::NAN, 0), None);
        assert_eq!(to_fixed(f64::INFINITY, 3), None);
    }
}
