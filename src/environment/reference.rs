//! The integrals image-based lighting approximates, summed exactly over an environment's texels
//! on the CPU: the reference the GPU's irradiance map, prefiltered specular levels and BRDF table
//! are measured against (tests), and the definition of what each holds.
//!
//! The split sum: the specular light of a GGX surface under an environment is approximated as
//! (the environment averaged over the GGX lobe around the reflected direction, taken with the
//! normal and the view both along it) times (the lobe's directional albedo, as a scale on F0 plus
//! a bias). The diffuse light is the cosine-weighted mean radiance around the normal.

use std::f32::consts::PI;

use glam::Vec3;

use super::Environment;

/// The cosine-weighted mean radiance around `n` (unit): (1/pi) times the integral of L(l) max(n.l,
/// 0) over the sphere, so a white Lambertian surface shows exactly this. Summed over the texels'
/// centres and divided by the same sum of the weights alone (which tends to pi), so that a
/// uniform environment gives back its radiance exactly at any resolution.
pub fn irradiance(env: &Environment, n: Vec3) -> Vec3 {
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0f64);
    for y in 0..env.height {
        let solid_angle = env.texel_solid_angle(y);
        for x in 0..env.width {
            let cos = n.dot(env.texel_direction(x, y));
            if cos > 0.0 {
                sum += env.texel(x as i64, y as i64) * (cos * solid_angle);
                weight += f64::from(cos * solid_angle);
            }
        }
    }
    sum / weight as f32
}

/// The environment averaged over the GGX lobe of `roughness` (perceptual, alpha = roughness
/// squared) around `r`, with the normal and view along `r`: each direction l weighted by
/// D(h) max(r.l, 0), the weights the GPU's importance sampling converges to. Roughness 0 is the
/// radiance along `r` itself.
pub fn prefiltered(env: &Environment, r: Vec3, roughness: f32) -> Vec3 {
    if roughness <= 0.0 {
        return env.sample(r);
    }
    let a2 = (roughness * roughness).powi(2);
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0f64);
    for y in 0..env.height {
        let solid_angle = env.texel_solid_angle(y);
        for x in 0..env.width {
            let l = env.texel_direction(x, y);
            let cos = r.dot(l);
            if cos <= 0.0 {
                continue;
            }
            let nh = r.dot((r + l).normalize());
            let d = a2 / (PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
            let w = d * cos * solid_angle;
            sum += env.texel(x as i64, y as i64) * w;
            weight += f64::from(w);
        }
    }
    sum / weight as f32
}

/// The GGX lobe's directional albedo at view cosine `nv` and `roughness`, as (scale, bias) on
/// F0 (Schlick's Fresnel, Smith's visibility with k = alpha / 2): the lookup table's entry.
/// Integrated by a midpoint rule over the hemisphere of half vectors, `steps` by `steps`.
pub fn brdf_scale_bias(nv: f32, roughness: f32, steps: u32) -> (f32, f32) {
    let nv = nv.clamp(1e-4, 1.0);
    let v = Vec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
    let a = (roughness * roughness).max(1e-4);
    let a2 = a * a;
    let k = a / 2.0;
    let g1 = |c: f32| c / (c * (1.0 - k) + k);
    let (mut scale, mut bias) = (0.0f64, 0.0f64);
    for i in 0..steps {
        // Uniform in the GGX cdf: cos^2(theta_h) = (1 - xi) / (1 + (a2 - 1) xi).
        let xi = (i as f32 + 0.5) / steps as f32;
        let cos_h = ((1.0 - xi) / (1.0 + (a2 - 1.0) * xi)).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).sqrt();
        for j in 0..steps {
            let phi = 2.0 * PI * (j as f32 + 0.5) / steps as f32;
            let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
            let vh = v.dot(h);
            let l = 2.0 * vh * h - v;
            if l.z <= 0.0 || vh <= 0.0 {
                continue;
            }
            // Sampled with pdf D(h) cos_h / (4 vh): the estimator is G vh / (nh nv).
            let g = g1(l.z) * g1(nv);
            let g_vis = g * vh / (cos_h * nv);
            let fc = (1.0 - vh).powi(5);
            scale += f64::from((1.0 - fc) * g_vis);
            bias += f64::from(fc * g_vis);
        }
    }
    let n = f64::from(steps * steps);
    ((scale / n) as f32, (bias / n) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_environment_is_its_own_average() {
        let env = Environment::uniform([2.0, 1.0, 0.5]);
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.8, 0.5).normalize()] {
            let e = irradiance(&env, n);
            assert!(e.abs_diff_eq(Vec3::new(2.0, 1.0, 0.5), 1e-4), "{e}");
            let s = prefiltered(&env, n, 0.6);
            assert!(s.abs_diff_eq(Vec3::new(2.0, 1.0, 0.5), 1e-3), "{s}");
        }
    }

    #[test]
    fn a_sky_above_lights_an_upward_face_fully_and_a_side_face_half() {
        let env = Environment::from_fn("upper white", 64, 32, |d| {
            Vec3::splat(if d.y > 0.0 { 1.0 } else { 0.0 })
        });
        assert!((irradiance(&env, Vec3::Y).x - 1.0).abs() < 0.01);
        assert!((irradiance(&env, Vec3::X).x - 0.5).abs() < 0.01);
    }

    #[test]
    fn the_lobes_albedo_is_at_most_one_and_falls_with_roughness() {
        let (s0, b0) = brdf_scale_bias(0.7, 0.05, 64);
        assert!((s0 + b0 - 1.0).abs() < 0.02, "{s0} {b0}");
        let (s1, b1) = brdf_scale_bias(0.7, 1.0, 64);
        assert!(s1 + b1 < s0 + b0 && s1 + b1 > 0.3, "{s1} {b1}");
    }
}
