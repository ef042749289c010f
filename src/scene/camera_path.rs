//! Camera paths: where the camera is at time t, as plain data the renderer samples per frame.
//!
//! A keyframed path is the chain of nodes from a scene root down to the camera's node, each with
//! a local transform that is fixed or follows keyframe tracks (glTF 2.0 animation semantics:
//! STEP, LINEAR with slerp for rotations, CUBICSPLINE Hermite curves). The camera's world matrix
//! is the product of the local transforms along the chain, root first.
//!
//! Invariants: every track has at least one key, finite strictly increasing times and finite
//! values, so sampling never divides by zero and never panics; rotations come out unit length
//! (a degenerate blend falls back to a key rather than giving NaN).

use glam::{Mat4, Quat, Vec3, Vec4};

use super::{Camera, Projection};

/// How a track blends between its keys (glTF's `sampler.interpolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// Each key's value holds until the next key.
    Step,
    /// Straight blend between keys; rotations are slerped along the shorter arc.
    Linear,
    /// Hermite curve through the keys; each key stores in-tangent, value, out-tangent.
    CubicSpline,
}

impl Interpolation {
    /// Stored values per key.
    fn values_per_key(self) -> usize {
        match self {
            Interpolation::CubicSpline => 3,
            Interpolation::Step | Interpolation::Linear => 1,
        }
    }
}

/// Why a track could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    #[error("a track needs at least one keyframe")]
    /// No keyframe at all.
    NoKeys,
    #[error("keyframe time {index} ({time}) is not finite or not greater than the one before")]
    /// Keyframe times that are not finite or do not increase.
    Times {
        /// Which keyframe.
        index: usize,
        /// Its time.
        time: f32,
    },
    #[error("{values} values for {keys} keyframes, but {interpolation:?} needs {need}")]
    /// A value count that does not fit the keyframes and interpolation.
    Count {
        /// Values given.
        values: usize,
        /// Keyframes given.
        keys: usize,
        /// How the track interpolates.
        interpolation: Interpolation,
        /// Values that interpolation needs for those keyframes.
        need: usize,
    },
    #[error("value {index} is not finite")]
    /// A value that is not finite.
    NotFinite {
        /// Which value.
        index: usize,
    },
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for glam::Vec3 {}
    impl Sealed for glam::Quat {}
}

/// A value a track can key: `Vec3` (translation, scale) or `Quat` (rotation).
pub trait Keyframe: Copy + std::fmt::Debug + PartialEq + sealed::Sealed {
    /// The value as four numbers, for the Hermite blend (a `Vec3` gets w = 0).
    #[doc(hidden)]
    fn to_vec4(self) -> Vec4;
    /// A blended value back from four numbers; `fallback` stands in where that is degenerate.
    #[doc(hidden)]
    fn from_blend(v: Vec4, fallback: Self) -> Self;
    /// The LINEAR blend a fraction `s` of the way from `a` to `b`.
    #[doc(hidden)]
    fn linear(a: Self, b: Self, s: f32) -> Self;
}

impl Keyframe for Vec3 {
    fn to_vec4(self) -> Vec4 {
        self.extend(0.0)
    }
    fn from_blend(v: Vec4, _: Vec3) -> Vec3 {
        v.truncate()
    }
    fn linear(a: Vec3, b: Vec3, s: f32) -> Vec3 {
        a.lerp(b, s)
    }
}

impl Keyframe for Quat {
    fn to_vec4(self) -> Vec4 {
        Vec4::from(self)
    }
    fn from_blend(v: Vec4, fallback: Quat) -> Quat {
        unit(v).unwrap_or_else(|| unit(fallback.into()).unwrap_or(Quat::IDENTITY))
    }
    fn linear(a: Quat, b: Quat, s: f32) -> Quat {
        slerp(a, b, s)
    }
}

/// `v` scaled to a unit quaternion, or `None` when it has no direction.
fn unit(v: Vec4) -> Option<Quat> {
    v.try_normalize().map(Quat::from_vec4)
}

/// Spherical blend along the shorter arc (q and -q are the same rotation). Nearly equal keys
/// use a normalized lerp, where slerp's sin(angle) divisor would vanish.
fn slerp(a: Quat, b: Quat, s: f32) -> Quat {
    let (a, mut b) = (Vec4::from(a), Vec4::from(b));
    let mut cos = a.dot(b);
    if cos < 0.0 {
        b = -b;
        cos = -cos;
    }
    let blend = if cos > 0.9995 {
        a.lerp(b, s)
    } else {
        let angle = cos.min(1.0).acos();
        let sin = angle.sin();
        a * (((1.0 - s) * angle).sin() / sin) + b * ((s * angle).sin() / sin)
    };
    Quat::from_blend(blend, Quat::from_vec4(a))
}

/// Keyframes of one animated property: times in seconds and the values at them.
#[derive(Debug, Clone, PartialEq)]
pub struct Track<T> {
    interpolation: Interpolation,
    times: Vec<f32>,
    /// One value per key, or (CUBICSPLINE) in-tangent, value, out-tangent per key.
    values: Vec<T>,
}

impl<T: Keyframe> Track<T> {
    /// A track, after checking the times strictly increase and the value count fits.
    pub fn new(
        interpolation: Interpolation,
        times: Vec<f32>,
        values: Vec<T>,
    ) -> Result<Track<T>, TrackError> {
        if times.is_empty() {
            return Err(TrackError::NoKeys);
        }
        for (index, &time) in times.iter().enumerate() {
            let after_previous = index == 0 || time > times[index - 1];
            if !time.is_finite() || !after_previous {
                return Err(TrackError::Times { index, time });
            }
        }
        let need = times.len() * interpolation.values_per_key();
        if values.len() != need {
            return Err(TrackError::Count {
                values: values.len(),
                keys: times.len(),
                interpolation,
                need,
            });
        }
        if let Some(index) = values.iter().position(|v| !v.to_vec4().is_finite()) {
            return Err(TrackError::NotFinite { index });
        }
        Ok(Track {
            interpolation,
            times,
            values,
        })
    }

    /// Time of the first key.
    pub fn start(&self) -> f32 {
        self.times[0]
    }

    /// Time of the last key.
    pub fn end(&self) -> f32 {
        self.times[self.times.len() - 1]
    }

    /// The value at key `k` (for CUBICSPLINE, the one between the tangents).
    fn key(&self, k: usize) -> T {
        match self.interpolation {
            Interpolation::CubicSpline => self.values[3 * k + 1],
            Interpolation::Step | Interpolation::Linear => self.values[k],
        }
    }

    /// The value at time `t`: the first key's before the track starts, the last key's after it
    /// ends (glTF's clamping), and a NaN time reads as the start.
    pub fn sample(&self, t: f32) -> T {
        let last = self.times.len() - 1;
        if t.is_nan() || t <= self.times[0] {
            return self.key(0);
        }
        if t >= self.times[last] {
            return self.key(last);
        }
        // times[k] <= t < times[k + 1], with k < last since t is before the last key.
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let dt = self.times[k + 1] - self.times[k];
        let s = (t - self.times[k]) / dt;
        match self.interpolation {
            Interpolation::Step => self.key(k),
            Interpolation::Linear => T::linear(self.key(k), self.key(k + 1), s),
            Interpolation::CubicSpline => self.hermite(k, s, dt),
        }
    }

    /// glTF's cubic Hermite spline between keys k and k+1; tangents are per second, so they
    /// are scaled by the interval's length.
    fn hermite(&self, k: usize, s: f32, dt: f32) -> T {
        let (s2, s3) = (s * s, s * s * s);
        let v0 = self.values[3 * k + 1].to_vec4();
        let out0 = self.values[3 * k + 2].to_vec4();
        let in1 = self.values[3 * k + 3].to_vec4();
        let v1 = self.values[3 * k + 4].to_vec4();
        let blend = v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
            + out0 * (dt * (s3 - 2.0 * s2 + s))
            + v1 * (-2.0 * s3 + 3.0 * s2)
            + in1 * (dt * (s3 - s2));
        T::from_blend(blend, self.key(k))
    }
}

/// A property that holds its rest value or follows a track.
#[derive(Debug, Clone, PartialEq)]
pub enum Keyed<T> {
    /// Holds this value at every time.
    Rest(T),
    /// Follows this track.
    Track(Track<T>),
}

impl<T: Keyframe> Keyed<T> {
    fn sample(&self, t: f32) -> T {
        match self {
            Keyed::Rest(v) => *v,
            Keyed::Track(track) => track.sample(t),
        }
    }

    fn range(&self) -> Option<(f32, f32)> {
        match self {
            Keyed::Rest(_) => None,
            Keyed::Track(track) => Some((track.start(), track.end())),
        }
    }
}

/// One node on the path from a scene root to the camera: its local transform over time.
#[derive(Debug, Clone, PartialEq)]
pub enum NodeMotion {
    /// A node that does not move (glTF nodes given by a matrix cannot be animated).
    Fixed(Mat4),
    /// A node whose translation, rotation and scale may each follow a track.
    Animated {
        /// Local translation.
        translation: Keyed<Vec3>,
        /// Local rotation.
        rotation: Keyed<Quat>,
        /// Local scale.
        scale: Keyed<Vec3>,
    },
}

impl NodeMotion {
    /// The local transform at time `t`.
    pub fn local(&self, t: f32) -> Mat4 {
        match self {
            NodeMotion::Fixed(m) => *m,
            NodeMotion::Animated {
                translation,
                rotation,
                scale,
            } => {
                let r = rotation.sample(t);
                Mat4::from_scale_rotation_translation(
                    scale.sample(t),
                    Quat::from_blend(r.into(), Quat::IDENTITY),
                    translation.sample(t),
                )
            }
        }
    }

    /// First and last key time over this node's tracks, `None` when it has none.
    fn range(&self) -> Option<(f32, f32)> {
        let NodeMotion::Animated {
            translation,
            rotation,
            scale,
        } = self
        else {
            return None;
        };
        [translation.range(), rotation.range(), scale.range()]
            .into_iter()
            .flatten()
            .reduce(|(a0, a1), (b0, b1)| (a0.min(b0), a1.max(b1)))
    }
}

/// Where the camera is over time: the camera's projection and its node chain, root first.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraPath {
    nodes: Vec<NodeMotion>,
    projection: Projection,
    start: f32,
    end: f32,
}

impl CameraPath {
    /// A path through `nodes` (a scene root first, the camera's own node last). Without any
    /// track the path stands still and lasts 0 seconds.
    pub fn new(nodes: Vec<NodeMotion>, projection: Projection) -> CameraPath {
        let (start, end) = nodes
            .iter()
            .filter_map(NodeMotion::range)
            .reduce(|(a0, a1), (b0, b1)| (a0.min(b0), a1.max(b1)))
            .unwrap_or((0.0, 0.0));
        CameraPath {
            nodes,
            projection,
            start,
            end,
        }
    }

    /// The nodes from the root to the camera.
    pub fn nodes(&self) -> &[NodeMotion] {
        &self.nodes
    }

    /// The camera's projection (it is not animated).
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// Time of the earliest key of any track, in seconds.
    pub fn start(&self) -> f32 {
        self.start
    }

    /// Time of the latest key of any track, in seconds (glTF times start at 0, so this is how
    /// long the animation plays).
    pub fn duration(&self) -> f32 {
        self.end
    }

    /// The camera's world matrix at `t` seconds, `t` clamped to `start()..=duration()`.
    pub fn world(&self, t: f32) -> Mat4 {
        let t = if t.is_nan() {
            self.start
        } else {
            t.clamp(self.start, self.end)
        };
        self.nodes
            .iter()
            .fold(Mat4::IDENTITY, |world, node| world * node.local(t))
    }

    /// The camera at `t` seconds, `t` clamped to `start()..=duration()`. A chain that scales
    /// to zero has no inverse; its view matrix is then not finite.
    pub fn sample(&self, t: f32) -> Camera {
        Camera {
            view: self.world(t).inverse(),
            projection: self.projection,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    fn vec3_track(i: Interpolation, times: &[f32], values: &[[f32; 3]]) -> Track<Vec3> {
        let values = values.iter().map(|&v| Vec3::from(v)).collect();
        Track::new(i, times.to_vec(), values).expect("a valid track")
    }

    fn perspective() -> Projection {
        Projection::Perspective {
            yfov: 0.8,
            aspect: None,
            znear: 0.1,
            zfar: 100.0,
        }
    }

    #[test]
    fn linear_is_the_straight_blend() {
        let t = vec3_track(
            Interpolation::Linear,
            &[0.0, 2.0, 3.0],
            &[[0.0; 3], [2.0, 4.0, 6.0], [2.0, 0.0, 6.0]],
        );
        assert!(close(t.sample(1.0), Vec3::new(1.0, 2.0, 3.0)));
        assert!(close(t.sample(0.5), Vec3::new(0.5, 1.0, 1.5)));
        assert!(close(t.sample(2.5), Vec3::new(2.0, 2.0, 6.0)));
    }

    #[test]
    fn step_holds_each_key_until_the_next() {
        let t = vec3_track(
            Interpolation::Step,
            &[0.0, 1.0, 2.0],
            &[[1.0; 3], [2.0; 3], [3.0; 3]],
        );
        assert_eq!(t.sample(0.99), Vec3::splat(1.0));
        assert_eq!(t.sample(1.0), Vec3::splat(2.0));
        assert_eq!(t.sample(1.5), Vec3::splat(2.0));
        assert_eq!(t.sample(2.0), Vec3::splat(3.0));
    }

    #[test]
    fn cubic_spline_matches_the_hermite_formula_by_hand() {
        // Keys (in, value, out) at t = 0 and 2. At t = 0.5: s = 0.25, dt = 2, and the Hermite
        // weights are h00 = 0.84375, dt*h10 = 0.28125, h01 = 0.15625, dt*h11 = -0.09375.
        let t = vec3_track(
            Interpolation::CubicSpline,
            &[0.0, 2.0],
            &[
                [9.0, 9.0, 9.0],
                [1.0, 2.0, 0.0],
                [1.0, 0.0, -2.0],
                [0.0, 4.0, 2.0],
                [3.0, 2.0, 4.0],
                [9.0, 9.0, 9.0],
            ],
        );
        assert!(close(t.sample(0.5), Vec3::new(1.59375, 1.625, -0.125)));
        assert!(close(t.sample(0.0), Vec3::new(1.0, 2.0, 0.0)));
        assert!(close(t.sample(2.0), Vec3::new(3.0, 2.0, 4.0)));
    }

    #[test]
    fn cubic_spline_finds_later_intervals() {
        // Zero tangents: halfway between keys 1 and 2 the curve is at their mean.
        let z = [0.0; 3];
        let t = vec3_track(
            Interpolation::CubicSpline,
            &[0.0, 1.0, 3.0],
            &[z, [0.0; 3], z, z, [2.0; 3], z, z, [4.0; 3], z],
        );
        assert!(close(t.sample(2.0), Vec3::splat(3.0)));
        assert!(close(t.sample(1.0), Vec3::splat(2.0)));
    }

    #[test]
    fn slerp_stays_unit_length_and_takes_the_short_arc() {
        let a = Quat::IDENTITY;
        let b = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 170f32.to_radians());
        let long = Track::new(Interpolation::Linear, vec![0.0, 1.0], vec![a, b]).unwrap();
        let short = Track::new(Interpolation::Linear, vec![0.0, 1.0], vec![a, -b]).unwrap();
        for i in 0..=20 {
            let t = i as f32 / 20.0;
            let q = long.sample(t);
            assert!(
                (q.length() - 1.0).abs() < 1e-5,
                "t {t}: length {}",
                q.length()
            );
            assert!(
                q.angle_between(short.sample(t)) < 1e-3,
                "q and -q are one rotation"
            );
        }
        let half = long.sample(0.5);
        assert!((half.angle_between(a) - 85f32.to_radians()).abs() < 1e-3);
    }

    #[test]
    fn cubic_rotation_is_normalized() {
        let b = Quat::from_rotation_y(1.0);
        let tangent = Quat::from_xyzw(0.3, 0.2, 0.0, 0.1);
        let values = vec![tangent, Quat::IDENTITY, tangent, tangent, b, tangent];
        let t = Track::new(Interpolation::CubicSpline, vec![0.0, 1.0], values).unwrap();
        let q = NodeMotion::Animated {
            translation: Keyed::Rest(Vec3::ZERO),
            rotation: Keyed::Track(t.clone()),
            scale: Keyed::Rest(Vec3::ONE),
        };
        for i in 0..=10 {
            let s = t.sample(i as f32 / 10.0);
            assert!((s.length() - 1.0).abs() < 1e-5);
            assert!(q.local(i as f32 / 10.0).is_finite());
        }
    }

    #[test]
    fn samples_clamp_to_the_first_and_last_keys() {
        let t = vec3_track(Interpolation::Linear, &[1.0, 3.0], &[[1.0; 3], [3.0; 3]]);
        assert_eq!(t.sample(0.0), Vec3::splat(1.0));
        assert_eq!(t.sample(-5.0), Vec3::splat(1.0));
        assert_eq!(t.sample(10.0), Vec3::splat(3.0));
        assert_eq!(t.sample(f32::NAN), Vec3::splat(1.0));
        let path = CameraPath::new(
            vec![NodeMotion::Animated {
                translation: Keyed::Track(t),
                rotation: Keyed::Rest(Quat::IDENTITY),
                scale: Keyed::Rest(Vec3::ONE),
            }],
            perspective(),
        );
        assert_eq!((path.start(), path.duration()), (1.0, 3.0));
        assert!(close(path.sample(-1.0).eye(), Vec3::splat(1.0)));
        assert!(close(path.sample(99.0).eye(), Vec3::splat(3.0)));
        assert!(close(path.sample(f32::INFINITY).eye(), Vec3::splat(3.0)));
    }

    #[test]
    fn the_world_matrix_composes_the_chain_from_the_root() {
        // The parent turns 90 degrees about +y over 1 s; the camera sits 2 units along its +x.
        let turn = Track::new(
            Interpolation::Linear,
            vec![0.0, 1.0],
            vec![Quat::IDENTITY, Quat::from_rotation_y(90f32.to_radians())],
        )
        .unwrap();
        let lift = vec3_track(
            Interpolation::Step,
            &[0.0, 4.0],
            &[[0.0; 3], [0.0, 5.0, 0.0]],
        );
        let path = CameraPath::new(
            vec![
                NodeMotion::Fixed(Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0))),
                NodeMotion::Animated {
                    translation: Keyed::Track(lift),
                    rotation: Keyed::Track(turn),
                    scale: Keyed::Rest(Vec3::ONE),
                },
                NodeMotion::Fixed(Mat4::from_translation(Vec3::new(2.0, 0.0, 0.0))),
            ],
            perspective(),
        );
        assert_eq!(path.duration(), 4.0, "the longest track sets the duration");
        assert!(close(path.sample(0.0).eye(), Vec3::new(2.0, 1.0, 0.0)));
        assert!(close(path.sample(1.0).eye(), Vec3::new(0.0, 1.0, -2.0)));
        assert!(close(path.sample(4.0).eye(), Vec3::new(0.0, 6.0, -2.0)));
        assert_eq!(path.sample(2.0).projection, perspective());
    }

    #[test]
    fn a_path_without_tracks_stands_still() {
        let path = CameraPath::new(vec![NodeMotion::Fixed(Mat4::IDENTITY)], perspective());
        assert_eq!((path.start(), path.duration()), (0.0, 0.0));
        assert!(close(path.sample(3.0).eye(), Vec3::ZERO));
    }

    #[test]
    fn bad_tracks_are_refused() {
        let v = |n: usize| vec![Vec3::ZERO; n];
        let linear = Interpolation::Linear;
        assert_eq!(Track::new(linear, vec![], v(0)), Err(TrackError::NoKeys));
        assert_eq!(
            Track::new(linear, vec![0.0, 1.0, 1.0], v(3)),
            Err(TrackError::Times {
                index: 2,
                time: 1.0
            })
        );
        assert!(matches!(
            Track::new(linear, vec![0.0, f32::NAN], v(2)),
            Err(TrackError::Times { index: 1, .. })
        ));
        assert!(matches!(
            Track::new(Interpolation::CubicSpline, vec![0.0, 1.0], v(2)),
            Err(TrackError::Count { need: 6, .. })
        ));
        let mut nan = v(2);
        nan[1].y = f32::NAN;
        assert_eq!(
            Track::new(linear, vec![0.0, 1.0], nan),
            Err(TrackError::NotFinite { index: 1 })
        );
    }
}
