//! The flags that draw meshes through cell complexes (Apaza and Andujar) in `relief render` and
//! `relief view`.

use clap::Args;
use relief::cells::MeshSelection;
use relief::render::CellsOptions;

#[derive(Args)]
pub struct CellsRenderArgs {
    /// Draw these meshes through cell complexes instead of their triangles: a mesh (node) name,
    /// or `all`. The meshes must be closed; each name's meshes share one material.
    #[arg(long, value_name = "NODE|all")]
    cells: Option<MeshSelection>,
    /// Texels a side of each domain face's maps (with --cells).
    #[arg(long, value_name = "TEXELS", default_value_t = 32)]
    cells_resolution: u32,
    /// The grid doubles while more than this share of the maps' line crossings is hidden (with
    /// --cells).
    #[arg(long, value_name = "RATIO", default_value_t = 0.05)]
    cells_overlap: f64,
    /// The grid also doubles until the mesh's median edge spans this many map texels, so that the
    /// maps follow the mesh's detail (with --cells; 0: the overlap ratio alone, the paper's rule).
    #[arg(long, value_name = "TEXELS", default_value_t = 2.0)]
    cells_texels_per_edge: f64,
    /// The largest grid the doubling may reach, in cells a side (with --cells).
    #[arg(long, value_name = "N", default_value_t = 32)]
    cells_max_grid: u32,
    /// A fixed grid, in cells a side, instead of the doubling (with --cells).
    #[arg(long, value_name = "N")]
    cells_grid: Option<u32>,
}

impl CellsRenderArgs {
    pub fn check(&self) -> anyhow::Result<()> {
        if self.cells_resolution == 0 || self.cells_resolution > 1024 {
            anyhow::bail!(
                "--cells-resolution {}: a map needs 1 to 1024 texels a side",
                self.cells_resolution
            );
        }
        if !(0.0..=1.0).contains(&self.cells_overlap) {
            anyhow::bail!(
                "--cells-overlap {}: a ratio from 0 to 1",
                self.cells_overlap
            );
        }
        if !(0.0..=64.0).contains(&self.cells_texels_per_edge) {
            anyhow::bail!(
                "--cells-texels-per-edge {}: from 0 (the overlap ratio alone) to 64",
                self.cells_texels_per_edge
            );
        }
        if self.cells_max_grid == 0 || self.cells_max_grid > 256 {
            anyhow::bail!(
                "--cells-max-grid {}: from 1 to 256 cells a side",
                self.cells_max_grid
            );
        }
        if let Some(n) = self.cells_grid {
            if n == 0 || n > 256 {
                anyhow::bail!("--cells-grid {n}: from 1 to 256 cells a side");
            }
        }
        Ok(())
    }

    /// The options, `None` without --cells.
    pub fn options(&self) -> Option<CellsOptions> {
        self.cells.clone().map(|selection| {
            CellsOptions::new(selection)
                .with_resolution(self.cells_resolution)
                .with_overlap(self.cells_overlap)
                .with_texels_per_edge(self.cells_texels_per_edge)
                .with_max_grid(self.cells_max_grid)
                .with_grid(self.cells_grid)
        })
    }
}
