//! Error of traced hits against the exact reference (docs/conventions.md): the uv distance in
//! texels between a method's hit and the exact first hit of the bilinear surface, its depth
//! error, and how often the method was grossly wrong, capped or produced NaN.

use serde::{Deserialize, Serialize};

use crate::heightfield::reference::{trace, Address, RefRay, SurfaceModel};
use crate::heightfield::Heightfield;

/// Mean, 99th percentile and maximum of a quantity.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
pub struct Spread {
    /// Arithmetic mean (0 for no values).
    pub mean: f64,
    /// 99th percentile, the sorted value at rank `ceil(0.99 (n - 1))` (0 for no values).
    pub p99: f64,
    /// Largest value (0 for no values).
    pub max: f64,
}

impl Spread {
    pub(crate) fn of(mut values: Vec<f64>) -> Spread {
        if values.is_empty() {
            return Spread::default();
        }
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        values.sort_by(f64::total_cmp);
        let p99 = values[((values.len() - 1) * 99).div_ceil(100)];
        Spread {
            mean,
            p99,
            max: values[values.len() - 1],
        }
    }
}

/// Mean and maximum iterations per ray.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
pub struct StepStats {
    /// Mean iterations per ray.
    pub mean: f64,
    /// Most iterations any one ray took.
    pub max: u32,
}

impl StepStats {
    /// Mean and most of `counts` (0 and 0 for none).
    pub fn of(counts: impl ExactSizeIterator<Item = u32> + Clone) -> StepStats {
        let n = counts.len().max(1) as f64;
        StepStats {
            mean: counts.clone().map(u64::from).sum::<u64>() as f64 / n,
            max: counts.max().unwrap_or(0),
        }
    }
}

/// The statistics `relief trace` prints and `relief bench` records.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TraceStats {
    /// Rays traced, NaN ones included.
    pub rays: usize,
    /// Distance in uv between the method's hit and the exact bilinear hit ([`crate::heightfield::reference::trace`]),
    /// in texels of the map (u scaled by the width, v by the height); NaN hits excluded.
    pub error_texels: Spread,
    /// `|z - z_exact|` of the hit's depth below the top plane, in texels (depth in uv times the map width).
    pub depth_error_texels: Spread,
    /// Fraction of rays whose hit is more than one texel from the exact hit.
    pub gross_rate: f64,
    /// Fraction of rays whose method ran out of iterations before converging.
    pub capped_rate: f64,
    /// Rays whose hit is not a finite number (excluded from the error spreads).
    pub nan_pixels: usize,
    /// Iterations per ray, as the method counted them.
    pub steps: StepStats,
}

/// A bench ray direction for elevation `angle_deg` and azimuth `azimuth_deg` (docs/conventions.md).
/// Exactly 90 degrees gives an exactly vertical ray.
pub fn ray_direction(angle_deg: f64, azimuth_deg: f64) -> [f64; 3] {
    if angle_deg >= 90.0 {
        return [0.0, 0.0, 1.0];
    }
    let (e, a) = (angle_deg.to_radians(), azimuth_deg.to_radians());
    [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()]
}

/// Compares traced rays (`u0 v0 dx dy dz u_hit v_hit z_hit` each, plus `(steps, capped)`) with
/// the exact hits on `hf` (the heights exactly as the GPU stored them).
pub fn trace_stats(
    hf: &Heightfield,
    rays: &[[f32; 8]],
    steps: &[[u32; 2]],
    depth_scale: f64,
    address: Address,
) -> TraceStats {
    let (w, h) = (f64::from(hf.width()), f64::from(hf.height()));
    let mut errors = Vec::with_capacity(rays.len());
    let mut depth_errors = Vec::with_capacity(rays.len());
    let mut nan = 0;
    for r in rays {
        let z = f64::from(r[7]);
        if !r.iter().all(|v| v.is_finite()) {
            nan += 1;
            continue;
        }
        let ray = RefRay {
            u0: f64::from(r[0]),
            v0: f64::from(r[1]),
            dx: f64::from(r[2]),
            dy: f64::from(r[3]),
            dz: f64::from(r[4]),
        };
        let exact = trace(hf, &ray, depth_scale, SurfaceModel::Bilinear, address);
        let dz = z - exact.z;
        let (du, dv) = (dz * ray.dx / ray.dz, dz * ray.dy / ray.dz);
        errors.push(((du * w).powi(2) + (dv * h).powi(2)).sqrt());
        depth_errors.push(dz.abs() * w);
    }
    let n = rays.len().max(1) as f64;
    let gross = errors.iter().filter(|&&e| e > 1.0).count();
    let capped = steps.iter().filter(|s| s[1] != 0).count();
    TraceStats {
        rays: rays.len(),
        gross_rate: gross as f64 / n,
        capped_rate: capped as f64 / steps.len().max(1) as f64,
        nan_pixels: nan,
        steps: StepStats::of(steps.iter().map(|s| s[0])),
        error_texels: Spread::of(errors),
        depth_error_texels: Spread::of(depth_errors),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;

    #[test]
    fn exact_hits_have_zero_error_and_offsets_are_measured() {
        let hf = Generator::Fbm.generate(16, 16, 2);
        let s = 0.1;
        let d = ray_direction(30.0, 20.0);
        let mut rays = Vec::new();
        for k in 0..20 {
            let ray = RefRay {
                u0: 0.05 * k as f64,
                v0: 0.5,
                dx: d[0],
                dy: d[1],
                dz: d[2],
            };
            let hit = trace(&hf, &ray, s, SurfaceModel::Bilinear, Address::Repeat);
            rays.push(
                [ray.u0, ray.v0, ray.dx, ray.dy, ray.dz, hit.u, hit.v, hit.z].map(|x| x as f32),
            );
        }
        let steps = vec![[3, 0]; rays.len()];
        let exact = trace_stats(&hf, &rays, &steps, s, Address::Repeat);
        assert!(exact.error_texels.max < 1e-3, "{exact:?}");
        assert_eq!(exact.gross_rate, 0.0);
        // Move every hit 2 texels further along the ray: error 2, all gross.
        let shift = 2.0 / 16.0 * d[2] / (d[0].hypot(d[1]));
        let moved: Vec<[f32; 8]> = rays
            .iter()
            .map(|r| {
                let mut m = *r;
                m[7] += shift as f32;
                m
            })
            .collect();
        let off = trace_stats(&hf, &moved, &steps, s, Address::Repeat);
        assert!((off.error_texels.mean - 2.0).abs() < 1e-3, "{off:?}");
        assert_eq!(off.gross_rate, 1.0);
        let mut broken = rays.clone();
        broken[0][7] = f32::NAN;
        assert_eq!(
            trace_stats(&hf, &broken, &steps, s, Address::Repeat).nan_pixels,
            1
        );
        assert_eq!(ray_direction(90.0, 33.0), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn step_stats_are_the_mean_and_the_most() {
        let s = StepStats::of([4u32, 10, 1].into_iter());
        assert_eq!((s.mean, s.max), (5.0, 10));
        assert_eq!(StepStats::of(std::iter::empty()), StepStats::default());
    }
}
