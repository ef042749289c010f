//! The rays from a point toward a light of some size: stratified, equal-solid-angle directions over the cone
//! the light fills as seen from the point.
//!
//! - Directional light: the cone of half-angle `Light::radius` (radians) around the direction toward it.
//! - Point and spot light: a sphere of radius `Light::radius` at `Light::position`; the cone is its silhouette,
//!   half-angle `asin(radius / distance)`, and each ray ends where it reaches the sphere. Sampling the
//!   silhouette by solid angle (not the facing disk by area) is what a uniformly bright sphere delivers.
//! - Radius 0: one ray to the centre.
//!
//! An `n x n` grid of strata on the unit square, each jittered by a fixed-seed hash of its indices (the same for
//! every point, so results are reproducible), is carried onto the cone by the concentric square-to-disk map and
//! the equal-area disk-to-cap map `1 - cos(theta) = rho^2 (1 - cos r)`: every sample stands for the same solid
//! angle, so a visible fraction is a plain count.

use glam::Vec3;

use crate::heightfield::rng::hash_unit;
use crate::heightfield::visibility::concentric;
use crate::scene::{Light, LightKind};

/// Seed of the jitter: fixed, so every run draws the same samples.
const JITTER_SEED: u64 = 0x5eed_5a4d;

/// One ray toward the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point toward the light.
    pub dir: Vec3,
    /// Where the ray reaches the light (infinite for a directional light).
    pub max_t: f32,
}

/// The rays from `p` toward `light`: `samples_per_side^2` of them (at least one), or a single one for a light of
/// radius 0; empty when `p` is inside a point or spot light's sphere (nothing can come between).
pub fn light_samples(p: Vec3, light: &Light, samples_per_side: u32) -> Vec<LightSample> {
    let (axis, half_angle, sphere) = match light.kind {
        // Beyond pi the cone is the whole sphere.
        LightKind::Directional => (
            -light.direction.normalize(),
            light.radius.clamp(0.0, std::f32::consts::PI),
            None,
        ),
        LightKind::Point | LightKind::Spot { .. } => {
            let to = light.position - p;
            let distance = to.length();
            if distance <= light.radius || distance == 0.0 {
                return Vec::new();
            }
            let half = (light.radius / distance).clamp(0.0, 1.0).asin();
            (to / distance, half, Some((light.position, light.radius)))
        }
    };
    let n = if half_angle > 0.0 {
        samples_per_side.max(1)
    } else {
        1
    };
    let (side, up) = axis.any_orthonormal_pair();
    // 2 sin^2(r/2) rather than 1 - cos(r): a small light keeps its precision.
    let one_minus_cos = 2.0 * (0.5 * f64::from(half_angle)).sin().powi(2);
    let mut samples = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (a, b) = stratum_point(i, j, n);
            let (x, y) = concentric(a, b);
            let rho2 = x * x + y * y;
            let cos_t = 1.0 - rho2 * one_minus_cos;
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let scale = if rho2 > 0.0 { sin_t / rho2.sqrt() } else { 0.0 };
            let dir = (axis * cos_t as f32 + side * (x * scale) as f32 + up * (y * scale) as f32)
                .normalize();
            let max_t = sphere.map_or(f32::INFINITY, |(c, r)| to_sphere(p, dir, c, r));
            samples.push(LightSample { dir, max_t });
        }
    }
    samples
}

/// The jittered point of stratum `(i, j)` of an `n x n` grid on `[-1, 1]^2`; the centre for `n == 1`, so a
/// hard light's one ray goes to the light's centre.
fn stratum_point(i: u32, j: u32, n: u32) -> (f64, f64) {
    let jitter = |axis: u64| {
        if n == 1 {
            0.5
        } else {
            f64::from(hash_unit(
                JITTER_SEED,
                u64::from(i),
                u64::from(j),
                u64::from(n) * 2 + axis,
            ))
        }
    };
    let cell = |k: u32, axis: u64| (f64::from(k) + jitter(axis)) / f64::from(n) * 2.0 - 1.0;
    (cell(i, 0), cell(j, 1))
}

/// Distance from `p` along `dir` to the near side of the sphere, or to its closest approach when rounding at
/// the silhouette makes the ray just miss.
fn to_sphere(p: Vec3, dir: Vec3, centre: Vec3, radius: f32) -> f32 {
    let to = centre - p;
    let b = dir.dot(to);
    let disc = b * b - (to.length_squared() - radius * radius);
    (b - disc.max(0.0).sqrt()).max(0.0)
}
