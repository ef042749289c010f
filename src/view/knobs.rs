//! What the viewer's keys change on every relief material at once: the method, the shadow mode,
//! the AO mode, LOD on or off, and a factor on the depth scales. The scene the command line made
//! stays as it was; each change yields a new scene for a new renderer (pipelines and maps are
//! planned per scene, so nothing else would be right).

use crate::method::Method;
use crate::scene::{AoMode, Lod, Relief, Scene, ShadowMode};

/// The viewer's overrides; `None` keeps each material's own setting.
#[derive(Debug, Clone, PartialEq)]
pub struct Knobs {
    method: Option<Method>,
    shadows: Option<ShadowMode>,
    ao: Option<AoMode>,
    lod: Option<bool>,
    depth_factor: f32,
}

/// How far the depth keys may scale the depth scales, either way.
const MAX_DEPTH_FACTOR: f32 = 64.0;

impl Default for Knobs {
    fn default() -> Knobs {
        Knobs {
            method: None,
            shadows: None,
            ao: None,
            lod: None,
            depth_factor: 1.0,
        }
    }
}

/// The entry `step` places after `current` in `all`, wrapping around.
fn cycle<T: PartialEq + Copy>(all: &[T], current: T, step: i32) -> T {
    let at = all.iter().position(|&x| x == current).unwrap_or(0) as i64;
    let n = all.len() as i64;
    all[(at + i64::from(step)).rem_euclid(n) as usize]
}

impl Knobs {
    /// `base` with the overrides applied to every relief material.
    pub fn apply(&self, base: &Scene) -> Scene {
        let mut scene = base.clone();
        for relief in scene.materials.iter_mut().filter_map(|m| m.relief.as_mut()) {
            if let Some(method) = self.method {
                relief.method = method;
            }
            if let Some(mode) = self.shadows {
                relief.shadows.mode = mode;
            }
            if let Some(ao) = self.ao {
                relief.ao = ao;
            }
            match self.lod {
                Some(true) if relief.lod.is_none() => relief.lod = Some(Lod::default()),
                Some(false) => relief.lod = None,
                _ => {}
            }
            relief.depth_scale *= self.depth_factor;
        }
        scene
    }

    /// The first relief material of `scene` as the knobs leave it, which the others follow.
    fn current(&self, base: &Scene) -> Option<Relief> {
        self.apply(base)
            .materials
            .into_iter()
            .find_map(|m| m.relief)
    }

    /// Whether `base` has anything for the knobs to turn.
    pub fn has_relief(base: &Scene) -> bool {
        base.materials.iter().any(|m| m.relief.is_some())
    }

    /// The next (`step` 1) or previous (-1) method.
    pub fn cycle_method(&mut self, base: &Scene, step: i32) {
        if let Some(now) = self.current(base) {
            let all: Vec<Method> = Method::all().collect();
            self.method = Some(cycle(&all, now.method, step));
        }
    }

    /// The next shadow mode.
    pub fn cycle_shadows(&mut self, base: &Scene) {
        if let Some(now) = self.current(base) {
            self.shadows = Some(cycle(&ShadowMode::ALL, now.shadows.mode, 1));
        }
    }

    /// The next AO mode.
    pub fn cycle_ao(&mut self, base: &Scene) {
        if let Some(now) = self.current(base) {
            self.ao = Some(cycle(&AoMode::all(), now.ao, 1));
        }
    }

    /// LOD on where it was off, off where it was on.
    pub fn toggle_lod(&mut self, base: &Scene) {
        if let Some(now) = self.current(base) {
            self.lod = Some(now.lod.is_none());
        }
    }

    /// Multiplies the depth scales by `factor`, within 1/64..64 of the scene's own.
    pub fn scale_depth(&mut self, factor: f32) {
        self.depth_factor =
            (self.depth_factor * factor).clamp(1.0 / MAX_DEPTH_FACTOR, MAX_DEPTH_FACTOR);
    }

    /// One line for the window title: method, shadows, AO, LOD, depth scale.
    pub fn describe(&self, base: &Scene) -> String {
        let Some(r) = self.current(base) else {
            return "no relief materials".into();
        };
        format!(
            "{} | shadows {} | ao {} | lod {} | depth {:.3}",
            r.method,
            r.shadows.mode,
            r.ao,
            if r.lod.is_some() { "on" } else { "off" },
            r.depth_scale
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::default_scene;

    #[test]
    fn cycling_wraps_both_ways() {
        let all = [1, 2, 3];
        assert_eq!(cycle(&all, 3, 1), 1);
        assert_eq!(cycle(&all, 1, -1), 3);
        assert_eq!(cycle(&all, 2, 1), 3);
    }

    #[test]
    fn default_knobs_leave_the_scene_as_it_is() {
        let base = default_scene(Method::QDM);
        let knobs = Knobs::default();
        let applied = knobs.apply(&base);
        assert_eq!(
            format!("{:?}", applied.materials),
            format!("{:?}", base.materials)
        );
    }

    #[test]
    fn every_key_changes_every_relief_material_and_comes_back_around() {
        let base = default_scene(Method::QDM);
        let mut knobs = Knobs::default();
        let first = knobs.current(&base).unwrap();
        knobs.cycle_method(&base, 1);
        let after = knobs.current(&base).unwrap();
        assert_ne!(after.method, first.method);
        knobs.cycle_method(&base, -1);
        assert_eq!(knobs.current(&base).unwrap().method, first.method);
        for _ in 0..ShadowMode::ALL.len() {
            knobs.cycle_shadows(&base);
        }
        assert_eq!(
            knobs.current(&base).unwrap().shadows.mode,
            first.shadows.mode
        );
        knobs.cycle_ao(&base);
        assert_ne!(knobs.current(&base).unwrap().ao, first.ao);
        knobs.toggle_lod(&base);
        assert_eq!(
            knobs.current(&base).unwrap().lod.is_some(),
            first.lod.is_none()
        );
        knobs.scale_depth(2.0);
        let scene = knobs.apply(&base);
        for r in scene.materials.iter().filter_map(|m| m.relief.as_ref()) {
            assert!((r.depth_scale - 2.0 * first.depth_scale).abs() < 1e-6);
        }
        knobs.scale_depth(1e9);
        let deepest = knobs.current(&base).unwrap().depth_scale;
        assert!((deepest - MAX_DEPTH_FACTOR * first.depth_scale).abs() < 1e-4);
    }
}
