//! Cost curves: how a cost grows with a size, as the exponent `k` of a power law `cost ~ n^k`
//! fitted by least squares on the logarithms of every point. The papers state growth as ratios
//! over a range (QRM: about 1.5x from 256^2 to 2048^2, that is `k` near 0.1 in texels); a fitted
//! exponent compares across ranges and uses every size measured, not only the two ends.

/// The least-squares slope of `ln cost` against `ln n` over `points` (n, cost); `None` with
/// fewer than two distinct positive sizes or a non-positive cost.
pub fn fitted_exponent(points: &[(f64, f64)]) -> Option<f64> {
    if points.iter().any(|&(n, c)| !(n > 0.0 && c > 0.0)) {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(n, c)| (n.ln(), c.ln())).collect();
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (logs.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_power_law_gives_back_its_exponent() {
        let points: Vec<(f64, f64)> = [256.0f64, 1024.0, 4096.0]
            .iter()
            .map(|&n| (n, 3.0 * n.powf(0.25)))
            .collect();
        assert!((fitted_exponent(&points).unwrap() - 0.25).abs() < 1e-12);
        // QRM's 1.5x over 64x the texels.
        let qrm = fitted_exponent(&[(65536.0, 1.0), (4194304.0, 1.5)]).unwrap();
        assert!((qrm - 1.5f64.ln() / 64f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn too_few_or_bad_points_fit_nothing() {
        assert_eq!(fitted_exponent(&[(4.0, 1.0)]), None);
        assert_eq!(fitted_exponent(&[(4.0, 1.0), (4.0, 2.0)]), None);
        assert_eq!(fitted_exponent(&[(4.0, 0.0), (16.0, 2.0)]), None);
        assert_eq!(fitted_exponent(&[]), None);
    }
}
