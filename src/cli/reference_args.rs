//! `--displaced-reference`: draw the scene's relief as really displaced geometry, the ground truth
//! the per-pixel methods are measured against on curved meshes.

use clap::Args;
use relief::displaced_reference::displaced_scene;
use relief::heightfield::{Address, Heightfield};
use relief::scene::Scene;

#[derive(Args)]
pub struct DisplacedReferenceArgs {
    /// Draw every relief mesh tessellated until an edge spans at most TEXELS height texels
    /// (default 1) and displaced on the CPU, with the plain raster pass: the reference the
    /// methods are measured against (docs/silhouettes.md).
    #[arg(long, value_name = "TEXELS", num_args = 0..=1, default_missing_value = "1")]
    displaced_reference: Option<f64>,
}

impl DisplacedReferenceArgs {
    /// `scene`, displaced when asked for; says on stderr what each relief mesh became.
    pub fn apply(
        &self,
        scene: Scene,
        heights: Option<&Heightfield>,
        address: Address,
    ) -> anyhow::Result<Scene> {
        let Some(texels) = self.displaced_reference else {
            return Ok(scene);
        };
        let displaced = displaced_scene(&scene, heights, address, texels)?;
        if displaced.meshes.is_empty() {
            anyhow::bail!("--displaced-reference: the scene has no relief mesh to displace");
        }
        for m in &displaced.meshes {
            eprintln!(
                "displaced reference: {} subdivided {} times to {} triangles (longest edge {:.1} texels, at most {texels} now)",
                m.name, m.levels, m.triangles, m.longest_edge_texels
            );
        }
        Ok(displaced.scene)
    }
}
