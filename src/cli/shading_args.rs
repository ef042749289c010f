//! The render flags that choose how relief materials are shaded beyond their hit: self-shadow
//! mode, ambient occlusion mode and the lights' size. They override what the scene's extras say.

use clap::Args;

use super::scene_args::Toggle;
use relief::scene::{AoMode, LightKind, Scene, ShadowMode, Silhouettes, MAX_ANGULAR_RADIUS_DEG};

#[derive(Args)]
pub struct ShadingArgs {
    /// Self-shadowing of every relief material: none, hard, pom-soft, horizon or cone
    /// (default: each material's extras.relief.shadows, else hard).
    #[arg(long, value_name = "MODE")]
    shadows: Option<ShadowMode>,
    /// Shadow samples (pom-soft, horizon) or the cone walk's cap (default: the mode's: 16, 5,
    /// 128).
    #[arg(long, value_name = "N")]
    shadow_steps: Option<u32>,
    /// Horizon shadows: how far the samples reach, as a multiple of the distance at which the
    /// light's lowest direction clears the top plane (Drobot's light vector scale; default 1).
    #[arg(long, value_name = "SCALE")]
    horizon_reach: Option<f32>,
    /// Ambient occlusion of every relief material: none, horizon-4|8|16 (optionally -rotated)
    /// or exact-horizon (default: each material's extras.relief.ao, else none).
    #[arg(long, value_name = "MODE")]
    ao: Option<AoMode>,
    /// Size of every light: angular radius in degrees for directional lights (the sun: 0.27),
    /// the radius in world units for point and spot lights (default: each light's extras).
    #[arg(long, value_name = "R")]
    light_radius: Option<f32>,
    /// Outline of every relief material: flat (the mesh's polygons), curved (the relief
    /// follows the mesh's curvature and its outline is the displaced surface's) or shells
    /// (each triangle extruded into a prism and the ray walked through the prisms: the
    /// displaced outline on open meshes too, at several times the cost); curved and shells
    /// need method relief. Default: each material's extras.relief.silhouettes, else flat.
    #[arg(long, value_name = "flat|curved|shells")]
    silhouettes: Option<Silhouettes>,
    /// Whether every relief material writes its displaced hit's depth into the frame's depth
    /// (on), or its polygon's (off: other surfaces, the sky and the G-buffer's depth then see
    /// the flat polygon). Default: each material's extras.relief.write_depth, else on.
    #[arg(long, value_name = "on|off")]
    write_depth: Option<Toggle>,
}

impl ShadingArgs {
    /// Applies the flags to `scene`'s materials and lights.
    pub fn apply(&self, scene: &mut Scene) -> anyhow::Result<()> {
        if self.shadow_steps.is_some_and(|s| !(1..=4096).contains(&s)) {
            anyhow::bail!("--shadow-steps must be in 1..=4096");
        }
        if self
            .horizon_reach
            .is_some_and(|r| !(r.is_finite() && r > 0.0))
        {
            anyhow::bail!("--horizon-reach must be a finite number above 0");
        }
        for relief in scene.materials.iter_mut().filter_map(|m| m.relief.as_mut()) {
            if let Some(mode) = self.shadows {
                relief.shadows.mode = mode;
            }
            if let Some(steps) = self.shadow_steps {
                relief.shadows.steps = Some(steps);
            }
            if let Some(reach) = self.horizon_reach {
                relief.shadows.horizon_reach = reach;
            }
            if let Some(mode) = self.ao {
                relief.ao = mode;
            }
            if let Some(silhouettes) = self.silhouettes {
                relief.silhouettes = silhouettes;
            }
            if let Some(write) = self.write_depth {
                relief.write_depth = write == Toggle::On;
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
