//! Which meshes the plan draws through cell complexes (`relief render --cells NODE|all`, paper
//! 002): a complex per mesh name, shaded with the material its meshes share. Those meshes leave
//! the surface pass; the cells pass, its pipeline and its maps are planned only when a complex is.

use crate::cells::MeshSelection;
use crate::render::kit::pass::Pass;
use crate::render::plan::frame_plan::{PassPlan, Plan, PlanError};
use crate::scene::Scene;

/// One cell complex to build and draw.
#[derive(Debug, Clone, PartialEq)]
pub struct CellsPlan {
    /// The meshes' name.
    pub name: String,
    /// The scene's meshes it replaces.
    pub meshes: Vec<usize>,
    /// The material they share, which shades the complex.
    pub material: usize,
}

/// The complexes `selection` asks of `scene`: each selected name's meshes must share one
/// material, and a named selection must name a mesh.
pub fn plan_cells(scene: &Scene, selection: &MeshSelection) -> Result<Vec<CellsPlan>, PlanError> {
    let groups = selection.groups(scene);
    if let (MeshSelection::Named(name), true) = (selection, groups.is_empty()) {
        let mut names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
        names.dedup();
        return Err(PlanError::NoCellsMesh {
            name: name.clone(),
            names: names.join(", "),
        });
    }
    groups
        .into_iter()
        .map(|(name, meshes)| {
            let mut materials: Vec<usize> =
                meshes.iter().map(|&k| scene.meshes[k].material).collect();
            materials.sort_unstable();
            materials.dedup();
            match materials[..] {
                [material] => Ok(CellsPlan {
                    name,
                    meshes,
                    material,
                }),
                _ => Err(PlanError::CellsMaterials {
                    name,
                    count: materials.len(),
                }),
            }
        })
        .collect()
}

impl Plan {
    /// Lists the cells pass, or why there is none.
    pub(in crate::render) fn note_cells(&mut self, scene: &Scene) {
        if self.cells.is_empty() {
            self.skip(
                Pass::Cells.name(),
                "no mesh is drawn through a cell complex (--cells)",
            );
            return;
        }
        let names: Vec<&str> = self.cells.iter().map(|c| c.name.as_str()).collect();
        self.passes.push(PassPlan {
            pass: Pass::Cells,
            why: format!(
                "{} mesh(es) drawn through cell complexes: {}",
                names.len(),
                names.join(", ")
            ),
        });
        let relief: Vec<String> = self
            .cells
            .iter()
            .filter(|c| scene.materials[c.material].relief.is_some())
            .map(|c| {
                let material = &scene.materials[c.material].name;
                format!("relief of material {material:?} on {:?}", c.name)
            })
            .collect();
        for what in relief {
            self.skip(
                what,
                "the cell complex is that mesh's displaced surface; the material's height map is not traced",
            );
        }
    }
}
