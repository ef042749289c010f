//! The render flags that choose how relief materials are shaded beyond their hit: self-shadow
//! mode, ambient occlusion mode and the lights' size. They override what the scene's extras say.

use clap::Args;
use relief::scene::{AoMode, LightKind, Scene, ShadowMode, MAX_ANGULAR_RADIUS_DEG};

#[derive(Args)]
pub struct ShadingArgs {
    /// Self-shadowing of every relief material: none, hard, pom-soft, horizon or cone
    /// (default: each material's extras.relief.shadows, else hard).
    #[arg(long, value_name = "MODE")]
    shadows: Option<ShadowMode>,
    /// Ambient occlusion of every relief material: none, horizon-4|8|16 (optionally -rotated)
    /// or exact-horizon (default: each material's extras.relief.ao, else none).
    #[arg(long, value_name = "MODE")]
    ao: Option<AoMode>,
    /// Size of every light: angular radius in degrees for directional lights (the sun: 0.27),
    /// the radius in world units for point and spot lights (default: each light's extras).
    #[arg(long, value_name = "R")]
    light_radius: Option<f32>,
}

impl ShadingArgs {
    /// Applies the flags to `scene`'s materials and lights.
    pub fn apply(&self, scene: &mut Scene) -> anyhow::Result<()> {
        for relief in scene.materials.iter_mut().filter_map(|m| m.relief.as_mut()) {
            if let Some(mode) = self.shadows {
                relief.shadows = mode;
            }
            if let Some(mode) = self.ao {
                relief.ao = mode;
            }
        }
        let Some(r) = self.light_radius else {
            return Ok(());
        };
        if !(r.is_finite() && r >= 0.0) {
            anyhow::bail!("--light-radius must be a finite number >= 0, got {r}");
        }
        for light in &mut scene.lights {
            light.radius = match light.kind {
                LightKind::Directional if r > MAX_ANGULAR_RADIUS_DEG => anyhow::bail!(
                    "--light-radius {r} is above {MAX_ANGULAR_RADIUS_DEG} degrees for a directional light"
                ),
                LightKind::Directional => r.to_radians(),
                LightKind::Point | LightKind::Spot { .. } => r,
            };
        }
        Ok(())
    }
}
