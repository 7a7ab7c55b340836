//! Directed rounding from f64 to f32, so that bounds computed in f64 stay
//! conservative once stored as f32.

/// Smallest f32 that is `>= x`.
#[inline]
pub(crate) fn up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

/// Largest f32 that is `<= x`.
#[inline]
pub(crate) fn down(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) > x { f.next_down() } else { f }
}

/// `x` nudged up past f64 rounding of the computation that produced it
/// (a square root or a short dot product), then rounded up to f32.
#[inline]
pub(crate) fn up_safe(x: f64) -> f32 {
    up(x + x.abs() * (4.0 * f64::EPSILON))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directed_rounding_brackets_the_value() {
        for x in [0.1f64, -0.1, 1.0 / 3.0, 1e30, -1e-30, 0.0, 16_777_217.0] {
            assert!(up(x) as f64 >= x && (up(x).next_down() as f64) < x);
            assert!(down(x) as f64 <= x && (down(x).next_up() as f64) > x);
        }
    }
}
