//! The quadratic solver of the quadric tracer: Algorithm 2 of Kiglics et al. (Kiglics et al.), beside the textbook
//! formula it replaces so that tests can show the difference.
//!
//! The tracer solves `A t^2 + B t + C = 0` with `A >= 0` and `B < 0` and wants the smaller real root. The textbook
//! `(-B - sqrt(B^2 - 4AC)) / 2A` subtracts two nearly equal numbers when `B^2 >> 4AC` (a ray that meets a
//! shallow parabola early), so the root loses most of its digits, and it divides by zero when `A = 0` (a
//! vertical ray). Multiplying by the conjugate gives the same root as
//!
//! ```text
//! t = C / (-B/2 + sqrt((B/2)^2 - AC))
//! ```
//!
//! whose denominator adds two non-negative numbers (no cancellation, never zero since `B < 0`), and which is the
//! linear root `-C/B` at `A = 0`. The only branch left is the paper's "is the root real" test.
//!
//! Contract of the stable solvers: `A >= 0`, `B < 0`, `C` finite. They return the smaller real root (negative when
//! `C < 0`, zero when `C = 0`) or `+inf` when the discriminant is negative. The `f32` twin is what the GLSL port
//! computes; the discriminant is tested before the square root because GLSL leaves `sqrt` of a negative number
//! undefined, where Rust gives NaN.

/// Algorithm 2 in `f64`: the smaller real root of `a t^2 + b t + c` (`a >= 0`, `b < 0`), or `+inf` if none.
pub fn smaller_root(a: f64, b: f64, c: f64) -> f64 {
    let half_b = 0.5 * b;
    let disc = half_b * half_b - a * c;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    c / (disc.sqrt() - half_b)
}

/// Algorithm 2 in `f32`, operation for operation what the shader does.
pub fn smaller_root_f32(a: f32, b: f32, c: f32) -> f32 {
    let half_b = 0.5 * b;
    let disc = half_b * half_b - a * c;
    if disc < 0.0 {
        return f32::INFINITY;
    }
    c / (disc.sqrt() - half_b)
}

/// The textbook smaller root `(-b - sqrt(b^2 - 4ac)) / 2a` in `f64`, or `+inf` when the discriminant is negative.
/// Only for comparison: it cancels when `b^2 >> 4ac` and is undefined at `a = 0`.
pub fn naive_smaller_root(a: f64, b: f64, c: f64) -> f64 {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    (-b - disc.sqrt()) / (2.0 * a)
}

/// The textbook smaller root in `f32` (see [`naive_smaller_root`]).
pub fn naive_smaller_root_f32(a: f32, b: f32, c: f32) -> f32 {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return f32::INFINITY;
    }
    (-b - disc.sqrt()) / (2.0 * a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative error of an `f32` root against the `f64` solution of the same (exactly widened) coefficients.
    fn rel_err_f32(root: f32, a: f32, b: f32, c: f32) -> f64 {
        let exact = smaller_root(f64::from(a), f64::from(b), f64::from(c));
        ((f64::from(root) - exact) / exact).abs()
    }

    #[test]
    fn stable_keeps_full_precision_where_the_textbook_formula_cancels() {
        // b^2 / 4ac from 1e4 to 1e12: the smaller root is about c / |b| and the textbook numerator cancels.
        for k in 4..=12 {
            let (a, b) = (1.0e-3_f32, -1.0_f32);
            let c = (0.25 * 10f64.powi(-k) / 1.0e-3) as f32;
            let stable = rel_err_f32(smaller_root_f32(a, b, c), a, b, c);
            let naive = rel_err_f32(naive_smaller_root_f32(a, b, c), a, b, c);
            assert!(
                stable < 4.0 * f64::from(f32::EPSILON),
                "k={k}: stable rel err {stable}"
            );
            if k >= 7 {
                assert!(
                    naive > 1e-2,
                    "k={k}: naive rel err {naive} should have cancelled"
                );
            }
        }
    }

    #[test]
    fn f64_textbook_formula_collapses_to_zero_on_extreme_ratios() {
        let (a, b, c) = (1.0e-10, -2.0, 3.0e-10);
        let exact = c / 2.0; // a c = 3e-20, so the correction factor 1 + ac/b'^2 is below f64 resolution
        assert_eq!(naive_smaller_root(a, b, c), 0.0);
        let stable = smaller_root(a, b, c);
        assert!(
            ((stable - exact) / exact).abs() < 2.0 * f64::EPSILON,
            "{stable}"
        );
    }

    #[test]
    fn well_conditioned_roots_agree() {
        // (t - 1)(t - 3) = t^2 - 4t + 3 and 2(t - 0.5)(t - 2) = 2t^2 - 5t + 2.
        assert!((smaller_root(1.0, -4.0, 3.0) - 1.0).abs() < 1e-15);
        assert!((naive_smaller_root(1.0, -4.0, 3.0) - 1.0).abs() < 1e-15);
        assert!((smaller_root(2.0, -5.0, 2.0) - 0.5).abs() < 1e-15);
        assert!((smaller_root_f32(2.0, -5.0, 2.0) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn linear_case_a_zero_is_the_linear_root() {
        assert_eq!(smaller_root(0.0, -4.0, 3.0), 0.75);
        assert_eq!(smaller_root_f32(0.0, -4.0, 3.0), 0.75);
        // The textbook formula divides 0 by 0.
        assert!(naive_smaller_root(0.0, -4.0, 3.0).is_nan());
        assert!(naive_smaller_root_f32(0.0, -4.0, 3.0).is_nan());
    }

    #[test]
    fn c_zero_gives_the_root_at_zero() {
        // t (2t - 5): roots 0 and 2.5.
        assert_eq!(smaller_root(2.0, -5.0, 0.0), 0.0);
        assert_eq!(smaller_root_f32(2.0, -5.0, 0.0), 0.0);
        assert_eq!(smaller_root(0.0, -5.0, 0.0), 0.0);
    }

    #[test]
    fn negative_discriminant_is_infinite() {
        // t^2 - t + 1 has no real root.
        assert_eq!(smaller_root(1.0, -1.0, 1.0), f64::INFINITY);
        assert_eq!(smaller_root_f32(1.0, -1.0, 1.0), f32::INFINITY);
        assert_eq!(naive_smaller_root(1.0, -1.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn double_root_and_negative_c() {
        // (t - 2)^2 = t^2 - 4t + 4: the double root, reached exactly.
        assert_eq!(smaller_root(1.0, -4.0, 4.0), 2.0);
        // (t + 1)(t - 3) = t^2 - 2t - 3: the smaller root is negative.
        assert!((smaller_root(1.0, -2.0, -3.0) + 1.0).abs() < 1e-15);
    }
}
