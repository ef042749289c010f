//! Scenes made to check scene shadows against the exact reference (`relief shadows --scene`):
//! plain and displaced casters over plain and displaced receivers, and a curved one, under one directional light
//! whose elevation and size are parameters. Relief materials read the frame's height map
//! (bricks; see [`ShadowScene::address`]).

use std::fmt;
use std::str::FromStr;

use glam::{Mat4, Vec3};

use crate::heightfield::Address;

use super::{box_mesh, quad_mesh, sphere_mesh, Camera, Light, Material, Relief, Scene, ShadowMode};
use super::{ShadowSettings, DEFAULT_SCENE_METHOD};

/// The shadow test scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowScene {
    /// A plain box floating over a plain plane.
    BoxOverPlane,
    /// A floating slab of deep relief bricks (no sides) over a plain plane: the light passes
    /// through its mortar grooves near its edges, which a flat caster would block.
    SlabOverPlane,
    /// A plain box floating over a plane of relief bricks: a displaced receiver.
    BoxOverRelief,
    /// A coarse sphere with smooth normals floating over a plain plane: a curved receiver whose
    /// shading normals part widely from its triangles' planes, lit down to grazing at its
    /// terminator.
    SphereOverPlane,
}

impl ShadowScene {
    /// Every scene.
    pub const ALL: [ShadowScene; 4] = [
        ShadowScene::BoxOverPlane,
        ShadowScene::SlabOverPlane,
        ShadowScene::BoxOverRelief,
        ShadowScene::SphereOverPlane,
    ];

    /// How the frame's height map is addressed: the slab clamps, so its relief ends at its edges;
    /// the relief ground repeats its bricks.
    pub fn address(self) -> Address {
        match self {
            ShadowScene::SlabOverPlane => Address::Clamp,
            _ => Address::Repeat,
        }
    }

    /// The name the command line takes.
    pub fn id(self) -> &'static str {
        match self {
            ShadowScene::BoxOverPlane => "box-over-plane",
            ShadowScene::SlabOverPlane => "slab-over-plane",
            ShadowScene::BoxOverRelief => "box-over-relief",
            ShadowScene::SphereOverPlane => "sphere-over-plane",
        }
    }
}

impl fmt::Display for ShadowScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

impl FromStr for ShadowScene {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ShadowScene::ALL
            .into_iter()
            .find(|k| k.id() == s)
            .ok_or_else(|| {
                let ids: Vec<&str> = ShadowScene::ALL.iter().map(|k| k.id()).collect();
                format!("unknown shadow scene `{s}` (expected {})", ids.join(", "))
            })
    }
}

/// Depth scale of the scenes' bricks: deep, so the displaced shadow differs from the flat one.
pub const SHADOW_SCENE_DEPTH: f32 = 0.1;

fn material(name: &str, rgb: [f32; 3], relief: Option<Relief>) -> Material {
    Material {
        name: name.into(),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        roughness: 0.8,
        relief,
        ..Material::default()
    }
}

/// A directional light at `elevation_deg` above the horizon and `azimuth_deg` around +y (0:
/// shining toward -x), of angular radius `radius_deg`.
pub fn sun(elevation_deg: f32, azimuth_deg: f32, radius_deg: f32) -> Light {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    let toward = Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
    Light {
        direction: -toward,
        casts_shadows: true,
        radius: radius_deg.to_radians(),
        color: Vec3::splat(3.0),
        ..Light::default_light()
    }
}

/// `scene` lit by a sun at `elevation_deg` of angular radius `radius_deg`, with the relief's
/// self-shadows in mode `own` (hard for hard lights, cone for soft ones by default).
pub fn shadow_scene(kind: ShadowScene, elevation_deg: f32, radius_deg: f32) -> Scene {
    let own = if radius_deg > 0.0 {
        ShadowMode::Cone
    } else {
        ShadowMode::Hard
    };
    let relief = Relief {
        shadows: ShadowSettings::new(own),
        ..Relief::new(SHADOW_SCENE_DEPTH, DEFAULT_SCENE_METHOD)
    };
    let plain = material("plain", [0.6, 0.6, 0.6], None);
    let bricks = material("bricks", [0.62, 0.26, 0.17], Some(relief));
    let (materials, ground_material, caster_material) = match kind {
        ShadowScene::BoxOverPlane | ShadowScene::SphereOverPlane => (vec![plain], 0, 0),
        ShadowScene::SlabOverPlane => (vec![plain, bricks], 0, 1),
        ShadowScene::BoxOverRelief => (vec![plain, bricks], 1, 0),
    };
    let mut ground = quad_mesh("ground", 6.0, 6.0, 3.0, ground_material);
    ground.transform = Mat4::IDENTITY;
    let caster = match kind {
        ShadowScene::SlabOverPlane => {
            let mut slab = quad_mesh("slab", 1.5, 1.5, 1.0, caster_material);
            slab.transform = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
            slab
        }
        ShadowScene::SphereOverPlane => {
            let mut ball = sphere_mesh("sphere", 0.4, 10, 20, caster_material);
            ball.transform = Mat4::from_translation(Vec3::new(0.0, 0.55, 0.0));
            ball
        }
        _ => {
            let mut cube = box_mesh("box", Vec3::splat(0.35), caster_material);
            cube.transform =
                Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)) * Mat4::from_rotation_y(0.4);
            cube
        }
    };
    Scene {
        meshes: vec![ground, caster],
        materials,
        camera: Some(Camera::look_at(
            Vec3::new(-0.6, 3.2, 2.6),
            Vec3::new(-0.4, 0.0, 0.0),
            50f32.to_radians(),
            0.05,
            30.0,
        )),
        lights: vec![sun(elevation_deg, 200.0, radius_deg)],
        images: Vec::new(),
        camera_path: None,
    }
}
