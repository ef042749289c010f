//! The viewer's camera: orbit (around a target, the scene's centre) or fly (from the eye, looking
//! where the mouse turns it), both starting from the scene's camera. Until the first move the rig
//! hands back that camera untouched, so a still viewer draws exactly what `relief render` draws.

use glam::{Mat4, Vec3};

use crate::scene::Camera;

/// How mouse and keys move the camera.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigMode {
    /// Dragging turns the camera about its target; the wheel moves it closer or further.
    Orbit,
    /// Dragging turns the camera where it stands; keys move it, the wheel sets the speed.
    Fly,
}

/// Orbit and fly state, in yaw (about +y) and pitch (above the horizon) of the viewing direction.
#[derive(Debug, Clone)]
pub struct CameraRig {
    start: Camera,
    start_target: Vec3,
    mode: RigMode,
    eye: Vec3,
    target: Vec3,
    yaw: f32,
    pitch: f32,
    /// World units per second when flying.
    speed: f32,
    moved: bool,
}

/// Kept off the poles so the view never loses its up direction.
const MAX_PITCH: f32 = 1.55;
/// Radians per pixel of mouse drag.
const TURN_PER_PIXEL: f32 = 0.008;

impl CameraRig {
    /// A rig starting at `camera`, orbiting `center` (the scene's centre; the point on the view
    /// axis as far away is the orbit's target, so the first drag does not jump).
    pub fn new(camera: Camera, center: Vec3) -> CameraRig {
        let eye = camera.eye();
        let forward = camera
            .view
            .inverse()
            .transform_vector3(-Vec3::Z)
            .normalize();
        let distance = (center - eye).length().max(1e-3);
        let target = eye + forward * distance;
        let (yaw, pitch) = angles_of(forward);
        CameraRig {
            start: camera,
            start_target: target,
            mode: RigMode::Orbit,
            eye,
            target,
            yaw,
            pitch,
            speed: distance * 0.5,
            moved: false,
        }
    }

    /// Whether it orbits or flies now.
    pub fn mode(&self) -> RigMode {
        self.mode
    }

    /// Switches between orbit and fly, keeping the current view.
    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            RigMode::Orbit => RigMode::Fly,
            RigMode::Fly => {
                // Orbit around the point as far ahead as the old target was.
                let distance = (self.target - self.eye).length().max(1e-3);
                self.target = self.eye + direction(self.yaw, self.pitch) * distance;
                RigMode::Orbit
            }
        };
    }

    /// Back to the scene's camera.
    pub fn reset(&mut self) {
        let mode = self.mode;
        *self = CameraRig::new(self.start, self.start_target);
        self.mode = mode;
    }

    /// A mouse drag of `(dx, dy)` pixels: orbit around the target, or turn the head when flying.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        if dx == 0.0 && dy == 0.0 {
            return;
        }
        self.yaw -= dx * TURN_PER_PIXEL;
        self.pitch = (self.pitch - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
        match self.mode {
            RigMode::Orbit => {
                let distance = (self.target - self.eye).length();
                self.eye = self.target - direction(self.yaw, self.pitch) * distance;
            }
            RigMode::Fly => {
                let distance = (self.target - self.eye).length();
                self.target = self.eye + direction(self.yaw, self.pitch) * distance;
            }
        }
        self.moved = true;
    }

    /// Wheel `steps` (positive: toward): closer to the target when orbiting, faster when flying.
    pub fn zoom(&mut self, steps: f32) {
        let factor = 0.9f32.powf(steps);
        match self.mode {
            RigMode::Orbit => {
                let offset = (self.eye - self.target) * factor;
                if offset.length() > 1e-4 {
                    self.eye = self.target + offset;
                }
            }
            RigMode::Fly => self.speed /= factor,
        }
        self.moved = true;
    }

    /// Flies by `(right, up, forward)` in units of `seconds` at the rig's speed (fly mode only).
    pub fn fly(&mut self, axes: Vec3, seconds: f32) {
        if self.mode != RigMode::Fly || axes == Vec3::ZERO {
            return;
        }
        let forward = direction(self.yaw, self.pitch);
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let step = (right * axes.x + Vec3::Y * axes.y + forward * axes.z) * self.speed * seconds;
        self.eye += step;
        self.target += step;
        self.moved = true;
    }

    /// The camera to draw with: the scene's own until the first move.
    pub fn camera(&self) -> Camera {
        if !self.moved {
            return self.start;
        }
        Camera {
            view: Mat4::look_at_rh(
                self.eye,
                self.eye + direction(self.yaw, self.pitch),
                Vec3::Y,
            ),
            projection: self.start.projection,
        }
    }
}

/// The unit viewing direction for `yaw` and `pitch`.
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    Vec3::new(
        -pitch.cos() * yaw.sin(),
        pitch.sin(),
        -pitch.cos() * yaw.cos(),
    )
}

/// Yaw and pitch of the unit direction `d`.
fn angles_of(d: Vec3) -> (f32, f32) {
    let pitch = d.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
    let yaw = (-d.x).atan2(-d.z);
    (yaw, pitch)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> Camera {
        Camera::framing(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.5, 1.0))
    }

    #[test]
    fn angles_round_trip_through_direction() {
        for d in [
            Vec3::new(0.3, -0.4, -0.8),
            Vec3::new(-0.9, 0.1, 0.2),
            Vec3::new(0.0, -0.99, 0.1),
        ] {
            let d = d.normalize();
            let (yaw, pitch) = angles_of(d);
            assert!((direction(yaw, pitch) - d).length() < 1e-5, "{d}");
        }
    }

    #[test]
    fn a_still_rig_hands_back_the_scene_camera_bit_for_bit() {
        let rig = CameraRig::new(start(), Vec3::new(0.0, 0.25, 0.0));
        assert_eq!(rig.camera(), start());
    }

    #[test]
    fn orbiting_keeps_the_distance_to_the_target_and_a_zero_drag_changes_nothing() {
        let center = Vec3::new(0.0, 0.25, 0.0);
        let mut rig = CameraRig::new(start(), center);
        rig.drag(0.0, 0.0);
        assert_eq!(rig.camera(), start());
        let before = (rig.camera().eye() - rig.target).length();
        rig.drag(120.0, -40.0);
        let cam = rig.camera();
        assert!(cam != start());
        assert!(((cam.eye() - rig.target).length() - before).abs() < 1e-3);
        // The camera still looks at the target.
        let seen = cam.view.transform_point3(rig.target);
        assert!(
            seen.x.abs() < 1e-3 && seen.y.abs() < 1e-3 && seen.z < 0.0,
            "{seen}"
        );
    }

    #[test]
    fn zoom_moves_toward_the_target_and_fly_moves_along_the_view() {
        let mut rig = CameraRig::new(start(), Vec3::ZERO);
        let d0 = (rig.eye - rig.target).length();
        rig.zoom(2.0);
        assert!(((rig.eye - rig.target).length() - d0 * 0.81).abs() < 1e-4);
        rig.toggle_mode();
        let eye = rig.eye;
        let forward = direction(rig.yaw, rig.pitch);
        rig.fly(Vec3::Z, 1.0);
        let moved = rig.eye - eye;
        assert!(moved.normalize().dot(forward) > 0.999);
        rig.reset();
        assert_eq!(rig.camera(), start());
        assert_eq!(rig.mode(), RigMode::Fly);
    }

    #[test]
    fn pitch_stays_off_the_poles() {
        let mut rig = CameraRig::new(start(), Vec3::ZERO);
        rig.drag(0.0, -100_000.0);
        assert!(rig.pitch <= MAX_PITCH);
        let cam = rig.camera();
        assert!(cam.view.is_finite());
    }
}
