//! The built-in analytic sky and ground that light a frame given no environment file: a blue
//! sky brightening toward a pale horizon, a dim warm ground, and a soft seam between them.

use glam::Vec3;

/// Radiance straight up.
const ZENITH: Vec3 = Vec3::new(0.12, 0.2, 0.38);
/// Radiance of the sky at the horizon.
const HORIZON: Vec3 = Vec3::new(0.36, 0.4, 0.45);
/// Radiance of the ground (any direction below the horizon).
const GROUND: Vec3 = Vec3::new(0.1, 0.09, 0.08);
/// Half the height of the seam between sky and ground, as the sine of the elevation (about 3
/// degrees): a hard seam would alias in the prefiltered maps' finest level.
const SEAM: f32 = 0.05;

/// The built-in sky's radiance along `dir` (+Y up). The sky blends from the horizon colour to
/// the zenith colour with the square root of the elevation's sine, so most of it is the
/// horizon's pale blue, as a clear sky's is.
pub fn sky_radiance(dir: Vec3) -> Vec3 {
    let y = dir.normalize_or(Vec3::Y).y;
    let sky = HORIZON.lerp(ZENITH, y.max(0.0).sqrt());
    let t = ((y + SEAM) / (2.0 * SEAM)).clamp(0.0, 1.0);
    let blend = t * t * (3.0 - 2.0 * t);
    GROUND.lerp(sky, blend)
}
