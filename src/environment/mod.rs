//! Light from an environment, on the CPU: an equirectangular radiance image (read from a
//! Radiance `.hdr` file, the built-in analytic sky, or a uniform colour), its directions, and the
//! exact integrals image-based lighting approximates (`reference`), against which the GPU's
//! prefiltered maps are checked. Nothing here knows of Vulkan.
//!
//! Directions: +Y is up. Column u in [0, 1) turns around the up axis from +X toward +Z, row v in
//! [0, 1] runs from straight up (v = 0, the image's top row) to straight down.

mod hdr_file;
pub mod reference;
mod sky;

use std::f32::consts::PI;
use std::path::PathBuf;

use glam::Vec3;

pub use hdr_file::EnvironmentError;
pub use sky::sky_radiance;

/// The largest radiance an environment keeps: the GPU stores it as half floats, whose largest
/// finite value is 65504. Brighter texels (a sun) are clamped to it when loaded.
pub const MAX_RADIANCE: f32 = 65504.0;

/// Where a frame's ambient light comes from.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum EnvironmentSource {
    /// One flat ambient colour, no environment maps built (timing runs, the library's default).
    #[default]
    Flat,
    /// The built-in analytic sky and ground ([`sky_radiance`]).
    Sky,
    /// An equirectangular Radiance `.hdr` image.
    File(PathBuf),
    /// An image given directly (tests, engines with their own loader).
    Image(Environment),
}

impl EnvironmentSource {
    /// The environment's radiance image, `None` for flat ambient light.
    pub fn load(&self) -> Result<Option<Environment>, EnvironmentError> {
        match self {
            EnvironmentSource::Flat => Ok(None),
            EnvironmentSource::Sky => Ok(Some(Environment::sky())),
            EnvironmentSource::File(path) => Environment::load(path).map(Some),
            EnvironmentSource::Image(env) => env.check().map(|()| Some(env.clone())),
        }
    }
}

/// What the frame shows where no surface is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Background {
    /// One dark colour (what timing runs and the tests draw).
    #[default]
    Colour,
    /// The environment lighting the frame, when it has one.
    Environment,
}

impl std::str::FromStr for Background {
    type Err = String;

    fn from_str(s: &str) -> Result<Background, String> {
        match s {
            "colour" | "color" => Ok(Background::Colour),
            "environment" => Ok(Background::Environment),
            _ => Err(format!(
                "unknown background {s:?}: use environment or colour"
            )),
        }
    }
}

/// An equirectangular image of linear radiance.
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    /// What it is, for messages and `--explain` (a file name, "built-in sky").
    pub name: String,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Linear RGB radiance, rows top (up) to bottom.
    pub texels: Vec<[f32; 3]>,
}

impl Environment {
    /// An environment of `radiance` in every direction (a white furnace, a black void).
    pub fn uniform(radiance: [f32; 3]) -> Environment {
        Environment {
            name: format!("uniform {radiance:?}"),
            width: 8,
            height: 4,
            texels: vec![radiance; 32],
        }
    }

    /// The built-in sky and ground, 256 x 128.
    pub fn sky() -> Environment {
        Environment::from_fn("built-in sky", 256, 128, sky_radiance)
    }

    /// A `width` x `height` image of `radiance` at each texel's centre direction.
    pub fn from_fn(
        name: &str,
        width: u32,
        height: u32,
        radiance: impl Fn(Vec3) -> Vec3,
    ) -> Environment {
        let mut texels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let v = (y as f32 + 0.5) / height as f32;
                texels.push(radiance(direction(u, v)).to_array());
            }
        }
        Environment {
            name: name.into(),
            width,
            height,
            texels,
        }
    }

    /// Checks the image is one the GPU can use: not empty, sizes matching, every value finite
    /// and non-negative and at most [`MAX_RADIANCE`].
    pub fn check(&self) -> Result<(), EnvironmentError> {
        let bad = |problem: String| EnvironmentError::Invalid {
            name: self.name.clone(),
            problem,
        };
        if self.width == 0 || self.height == 0 {
            return Err(bad(format!("is {}x{}", self.width, self.height)));
        }
        if self.texels.len() != (self.width * self.height) as usize {
            return Err(bad(format!(
                "has {} texels for {}x{}",
                self.texels.len(),
                self.width,
                self.height
            )));
        }
        if let Some(i) = self.texels.iter().position(|t| {
            t.iter()
                .any(|c| !c.is_finite() || *c < 0.0 || *c > MAX_RADIANCE)
        }) {
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            return Err(bad(format!(
                "texel ({x}, {y}) holds {:?}: radiance must be finite, at least 0 and at most {MAX_RADIANCE}",
                self.texels[i]
            )));
        }
        Ok(())
    }

    /// The texel at column `x` (wrapping) and row `y` (clamped).
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.rem_euclid(self.width as i64) as u32;
        let y = y.clamp(0, self.height as i64 - 1) as u32;
        Vec3::from(self.texels[(y * self.width + x) as usize])
    }

    /// Bilinear radiance seen along `dir`.
    pub fn sample(&self, dir: Vec3) -> Vec3 {
        let (u, v) = equirect_uv(dir);
        let fx = u * self.width as f32 - 0.5;
        let fy = v * self.height as f32 - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let row = |y| self.texel(x0, y).lerp(self.texel(x0 + 1, y), tx);
        row(y0).lerp(row(y0 + 1), ty)
    }

    /// The image at half the size (Vulkan's rule: halve, round down, at least 1), each texel the
    /// mean of the 2 x 2 it covers: the next level of a mip chain.
    pub fn halved(&self) -> Environment {
        let (w, h) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let mut texels = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let (x0, y0) = (i64::from(2 * x), i64::from(2 * y));
                let sum = self.texel(x0, y0)
                    + self.texel(x0 + 1, y0)
                    + self.texel(x0, y0 + 1)
                    + self.texel(x0 + 1, y0 + 1);
                texels.push((sum * 0.25).to_array());
            }
        }
        Environment {
            name: self.name.clone(),
            width: w,
            height: h,
            texels,
        }
    }

    /// Solid angle of a texel of row `y`.
    pub fn texel_solid_angle(&self, y: u32) -> f32 {
        let theta0 = PI * y as f32 / self.height as f32;
        let theta1 = PI * (y + 1) as f32 / self.height as f32;
        2.0 * PI / self.width as f32 * (theta0.cos() - theta1.cos())
    }

    /// The centre direction of texel (`x`, `y`).
    pub fn texel_direction(&self, x: u32, y: u32) -> Vec3 {
        direction(
            (x as f32 + 0.5) / self.width as f32,
            (y as f32 + 0.5) / self.height as f32,
        )
    }
}

/// The direction at equirectangular coordinates (`u`, `v`).
pub fn direction(u: f32, v: f32) -> Vec3 {
    let (theta, phi) = (PI * v, 2.0 * PI * u);
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.cos(),
        theta.sin() * phi.sin(),
    )
}

/// The equirectangular coordinates of `dir` (any length but zero): u in [0, 1), v in [0, 1].
pub fn equirect_uv(dir: Vec3) -> (f32, f32) {
    let d = dir.normalize();
    let u = (d.z.atan2(d.x) / (2.0 * PI)).rem_euclid(1.0);
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    (u, v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_and_coordinates_round_trip() {
        for &(u, v) in &[(0.1, 0.3), (0.7, 0.9), (0.5, 0.5), (0.99, 0.01)] {
            let (u2, v2) = equirect_uv(direction(u, v));
            assert!(
                (u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5,
                "{u},{v} -> {u2},{v2}"
            );
        }
        assert!(direction(0.3, 0.0).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(direction(0.0, 0.5).abs_diff_eq(Vec3::X, 1e-6));
        assert!(direction(0.25, 0.5).abs_diff_eq(Vec3::Z, 1e-6));
    }

    #[test]
    fn texel_solid_angles_cover_the_sphere() {
        let env = Environment::uniform([1.0; 3]);
        let total: f32 = (0..env.height)
            .map(|y| env.texel_solid_angle(y) * env.width as f32)
            .sum();
        assert!((total - 4.0 * PI).abs() < 1e-4, "{total}");
    }

    #[test]
    fn bad_radiance_is_refused_by_texel() {
        let mut env = Environment::uniform([1.0; 3]);
        env.texels[9] = [f32::NAN, 0.0, 0.0];
        let err = env.check().unwrap_err().to_string();
        assert!(err.contains("(1, 1)") && err.contains("NaN"), "{err}");
        env.texels[9] = [-1.0, 0.0, 0.0];
        assert!(env.check().is_err());
        env.texels.pop();
        assert!(env.check().unwrap_err().to_string().contains("31 texels"));
    }

    #[test]
    fn the_sky_is_finite_brighter_above_than_below() {
        let sky = Environment::sky();
        sky.check().expect("the built-in sky is valid");
        let up = sky.sample(Vec3::Y);
        let down = sky.sample(Vec3::NEG_Y);
        assert!(up.y > down.y && up.z > up.x, "up {up}, down {down}");
    }
}
