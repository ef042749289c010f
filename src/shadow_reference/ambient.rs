//! Ambient occlusion from the whole scene, brute force: the share of a cosine-weighted hemisphere
//! of rays about a receiver's normal that travel a given radius without meeting any occluder
//! (other objects and relief solids, the receiver's own included). The rays are fixed (the
//! centres of a stratified grid mapped to the hemisphere), so another tracer can send the very
//! same ones and be compared ray for ray.

use std::f32::consts::TAU;

use glam::Vec3;

use super::{SceneOccluders, NO_RECEIVER};

/// `samples_per_side^2` unit directions about `normal`, cosine-weighted: the centre of each cell of
/// a stratified square, mapped to the disk by radius `sqrt(u)` and lifted to the hemisphere
/// (Malley's method). Empty for a zero normal.
pub fn ambient_directions(normal: Vec3, samples_per_side: u32) -> Vec<Vec3> {
    let Some(n) = normal.try_normalize() else {
        return Vec::new();
    };
    let (t, b) = n.any_orthonormal_pair();
    let side = samples_per_side.max(1);
    let cell = |k: u32| (k as f32 + 0.5) / side as f32;
    (0..side * side)
        .map(|k| {
            let (u, v) = (cell(k % side), cell(k / side));
            let r = u.sqrt();
            let phi = TAU * v;
            let lift = (1.0 - u).max(0.0).sqrt();
            (t * (r * phi.cos()) + b * (r * phi.sin()) + n * lift).normalize()
        })
        .collect()
}

/// One receiver's rays: where they start (the receiver moved onto the exact surface, then the
/// scene's offset along each ray), their directions and how far they reach.
#[derive(Debug, Clone, PartialEq)]
pub struct AmbientRays {
    /// The receiver as the reference traces from it ([`SceneOccluders::receiver`]).
    pub receiver: Vec3,
    /// Unit directions ([`ambient_directions`]).
    pub directions: Vec<Vec3>,
    /// The offset each ray starts at along its direction.
    pub epsilon: f32,
    /// How far past the offset each ray reaches.
    pub reach: f32,
}

impl SceneOccluders {
    /// The rays of a receiver at `p` with shading normal `normal`, reaching `radius`.
    pub fn ambient_rays(
        &self,
        p: Vec3,
        normal: Vec3,
        samples_per_side: u32,
        radius: f32,
    ) -> AmbientRays {
        AmbientRays {
            receiver: self.receiver(p),
            directions: ambient_directions(normal, samples_per_side),
            epsilon: self.epsilon(),
            reach: (radius - self.epsilon()).max(0.0),
        }
    }

    /// The unblocked share of a receiver's ambient rays (1 with none, [`NO_RECEIVER`] for a
    /// non-finite point).
    pub fn ambient_visibility(
        &self,
        p: Vec3,
        normal: Vec3,
        samples_per_side: u32,
        radius: f32,
    ) -> f32 {
        if !p.is_finite() {
            return NO_RECEIVER;
        }
        let rays = self.ambient_rays(p, normal, samples_per_side, radius);
        if rays.directions.is_empty() || rays.reach <= 0.0 {
            return 1.0;
        }
        let open = rays
            .directions
            .iter()
            .filter(|&&d| !self.any_hit(rays.receiver + d * rays.epsilon, d, rays.reach))
            .count();
        open as f32 / rays.directions.len() as f32
    }

    /// [`Self::ambient_visibility`] of each receiver (`None`: [`NO_RECEIVER`]), on every thread.
    pub fn ambient_visibilities(
        &self,
        receivers: &[Option<(Vec3, Vec3)>],
        samples_per_side: u32,
        radius: f32,
    ) -> Vec<f32> {
        self.in_parallel(receivers, |r| {
            r.map_or(NO_RECEIVER, |(p, n)| {
                self.ambient_visibility(p, n, samples_per_side, radius)
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_lie_in_the_hemisphere_with_a_cosine_mean() {
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        let dirs = ambient_directions(n, 16);
        assert_eq!(dirs.len(), 256);
        assert!(dirs
            .iter()
            .all(|d| d.dot(n) > 0.0 && (d.length() - 1.0).abs() < 1e-5));
        // A cosine-weighted hemisphere's mean cosine is 2/3.
        let mean = dirs.iter().map(|d| d.dot(n)).sum::<f32>() / dirs.len() as f32;
        assert!((mean - 2.0 / 3.0).abs() < 0.01, "{mean}");
        // Its mean direction is the normal.
        let sum: Vec3 = dirs.iter().copied().sum();
        assert!(sum.normalize().dot(n) > 0.999);
        assert!(ambient_directions(Vec3::ZERO, 4).is_empty());
    }
}
