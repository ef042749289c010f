//! The exact scene-shadow reference on the CPU: what a light's rays meet between a point and the light, against
//! every triangle of a [`Scene`] and every relief material's exact height field. It is the ground truth that
//! rendered shadow terms are measured against ([`measure_agreement`]), and knows nothing of Vulkan.
//!
//! Conventions, chosen for physical truth rather than for what a rasteriser sees:
//! - Every triangle whose material is not `Blend` blocks from **both sides**: a closed mesh blocks light
//!   whichever face the ray meets, whatever back-face culling a renderer applies when drawing it.
//! - A relief triangle does not block with its polygon but with the solid under it: between its displaced,
//!   bilinear, unorm16-quantized height field and its bottom plane, over the triangle's footprint, in the
//!   triangle's texture space (`relief_shell`). [`ReliefCasting::Flat`] replaces it by its polygon, to measure
//!   what the displacement changes.
//! - Rays start `epsilon` (1e-5 of the scene's bounding diagonal) along their direction from the point, so a
//!   point does not shadow itself by rounding; a receiver inside a relief triangle's shell is first moved onto
//!   the exact field (onto the polygon in the flat world), since a point read back from a frame carries the
//!   method's error and would otherwise start inside the solid it lies on.
//! - With a normal hint, light directions at or below the receiver's tangent plane count as blocked.
//!
//! Data flow: [`SceneOccluders`] gathers the primitives (`collect`) and builds a [`bvh::Bvh`] over their
//! bounds; queries walk it with the plain-triangle or relief-shell test; [`light_samples()`] turns a light into
//! rays; `visible_fraction` counts the rays that reach the light.

pub mod agreement;
pub mod ambient;
pub mod bvh;
mod collect;
pub mod light_samples;
pub mod relief_shell;
pub mod triangle;

#[cfg(test)]
mod tests;

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;

pub use agreement::{measure_agreement, shadow_edge_band, ShadowAgreement, Tally};
pub use ambient::{ambient_directions, AmbientRays};
pub use light_samples::{light_samples, LightSample};

use crate::heightfield::{Address, Heightfield, HeightfieldError};
use crate::scene::{Light, Scene};
use bvh::{Aabb, Bvh};
use collect::Primitive;
use triangle::Triangle;

/// Ray offsets, relative to the scene's bounding diagonal: far above f32 rounding of positions (about 1e-7
/// relative), far below any feature a scene resolves (at 1e-5 of a 12-unit scene, a twentieth of a texel of a
/// 256-texel map over 2 units).
pub const RELATIVE_EPSILON: f32 = 1e-5;

/// Value of a pixel with no receiver in [`SceneOccluders::visible_fractions`].
pub const NO_RECEIVER: f32 = -1.0;

/// How relief triangles cast.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReliefCasting {
    /// With their displaced height field (the truth).
    Displaced,
    /// With their flat polygon, as a renderer that ignores the displacement in its shadow pass does.
    Flat,
}

/// Why the occluders of a scene could not be gathered.
#[derive(Debug, thiserror::Error)]
pub enum ShadowReferenceError {
    /// A mesh names a material the scene does not have.
    #[error("mesh {mesh:?} uses material {material}, but the scene has {count}")]
    NoMaterial {
        /// The mesh's name.
        mesh: String,
        /// The index it names.
        material: usize,
        /// How many materials there are.
        count: usize,
    },
    /// A relief material's heights could not be read.
    #[error(transparent)]
    MaterialHeights(#[from] crate::scene::MaterialHeightsError),
    /// A height map could not be decoded.
    #[error(transparent)]
    Heights(#[from] HeightfieldError),
}

/// One occluder, as [`SceneOccluders::occluders`] lists them.
#[derive(Debug, Clone, Copy)]
pub enum Occluder<'a> {
    /// A triangle blocking from both sides: its world corners.
    Triangle([Vec3; 3]),
    /// A relief triangle's solid.
    Relief(&'a relief_shell::ReliefShell),
}

/// Every occluder of a scene, ready for exact ray queries.
#[derive(Debug, Clone)]
pub struct SceneOccluders {
    primitives: Vec<Primitive>,
    bvh: Bvh,
    casting: ReliefCasting,
    epsilon: f32,
}

impl SceneOccluders {
    /// The occluders of `scene`, relief casting with its displacement. Relief materials whose heights come from
    /// the frame read `frame_heights` with `frame_address`; the others read their own texture.
    pub fn new(
        scene: &Scene,
        frame_heights: Option<&Heightfield>,
        frame_address: Address,
    ) -> Result<SceneOccluders, ShadowReferenceError> {
        Self::build(
            scene,
            frame_heights,
            frame_address,
            ReliefCasting::Displaced,
        )
    }

    /// The occluders of `scene` with every relief triangle casting as its flat polygon (no heights needed).
    pub fn flat(scene: &Scene) -> Result<SceneOccluders, ShadowReferenceError> {
        Self::build(scene, None, Address::Repeat, ReliefCasting::Flat)
    }

    fn build(
        scene: &Scene,
        frame_heights: Option<&Heightfield>,
        frame_address: Address,
        casting: ReliefCasting,
    ) -> Result<SceneOccluders, ShadowReferenceError> {
        let primitives = collect::collect(scene, frame_heights, frame_address, casting)?;
        let boxes: Vec<Aabb> = primitives.iter().map(bounds).collect();
        let diagonal = boxes
            .iter()
            .copied()
            .reduce(|a, b| Aabb::around(&[a.min, a.max, b.min, b.max]))
            .map_or(1.0, |b| (b.max - b.min).length());
        Ok(SceneOccluders {
            bvh: Bvh::build(&boxes),
            primitives,
            casting,
            epsilon: (RELATIVE_EPSILON * diagonal).max(f32::MIN_POSITIVE),
        })
    }

    /// How relief triangles cast here.
    pub fn casting(&self) -> ReliefCasting {
        self.casting
    }

    /// How many triangles block: `(plain, relief)`.
    pub fn triangle_counts(&self) -> (usize, usize) {
        let relief = self
            .primitives
            .iter()
            .filter(|p| matches!(p, Primitive::Relief(_)))
            .count();
        (self.primitives.len() - relief, relief)
    }

    /// Every occluder, as this world casts it: relief triangles as their shells, or as their
    /// polygons in the flat world.
    pub fn occluders(&self) -> impl Iterator<Item = Occluder<'_>> {
        self.primitives.iter().map(|p| match (p, self.casting) {
            (Primitive::Plain(tri), _) => Occluder::Triangle(tri.corners),
            (Primitive::Relief(shell), ReliefCasting::Flat) => Occluder::Triangle(shell.corners()),
            (Primitive::Relief(shell), ReliefCasting::Displaced) => Occluder::Relief(shell),
        })
    }

    /// The distance rays start from their point (see the module docs).
    pub fn epsilon(&self) -> f32 {
        self.epsilon
    }

    /// The nearest blocking parameter of `origin + t dir` in `[0, max_t]` (`dir` need not be unit; `t` is in its
    /// units). Exact for plain triangles and for rays going down into a relief shell; a ray climbing out of a
    /// shell reports a point where it is inside the solid, which can lie beyond its first contact.
    pub fn first_hit(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<f32> {
        self.bvh.first_hit(origin, dir, max_t, |k, limit| {
            self.hit(&self.primitives[k], origin, dir, limit)
        })
    }

    /// Whether anything blocks `origin + t dir` for `t` in `[0, max_t]`.
    pub fn any_hit(&self, origin: Vec3, dir: Vec3, max_t: f32) -> bool {
        self.bvh.any_hit(origin, dir, max_t, |k, limit| {
            self.hit(&self.primitives[k], origin, dir, limit).is_some()
        })
    }

    fn hit(&self, primitive: &Primitive, origin: Vec3, dir: Vec3, max_t: f32) -> Option<f32> {
        match (primitive, self.casting) {
            (Primitive::Plain(tri), _) => tri.hit(origin, dir, max_t),
            (Primitive::Relief(shell), ReliefCasting::Displaced) => shell.hit(origin, dir, max_t),
            (Primitive::Relief(shell), ReliefCasting::Flat) => Triangle {
                corners: shell.corners(),
            }
            .hit(origin, dir, max_t),
        }
    }

    /// Where the light rays of a receiver at `p` start from: `p` itself, or the surface point over it when it
    /// lies in a relief shell (the nearest such point when shells overlap).
    pub fn receiver(&self, p: Vec3) -> Vec3 {
        let displaced = self.casting == ReliefCasting::Displaced;
        let mut best: Option<Vec3> = None;
        self.bvh.containing(p, |k| {
            if let Primitive::Relief(shell) = &self.primitives[k] {
                if let Some(q) = shell.surface_point(p, displaced) {
                    if best.is_none_or(|b| q.distance_squared(p) < b.distance_squared(p)) {
                        best = Some(q);
                    }
                }
            }
        });
        best.unwrap_or(p)
    }

    /// The visible fraction of `light` from the receiver at `p`: the share of `samples_per_side^2` stratified,
    /// equal-solid-angle rays toward it (one for a light of radius 0) that reach it unblocked. With
    /// `normal_hint`, directions at or below the tangent plane count as blocked. A non-finite `p` gives
    /// [`NO_RECEIVER`]; a point inside a sphere light sees all of it. A spot light's cone and a light's range
    /// are not visibility: the caller weighs them.
    pub fn visible_fraction(
        &self,
        p: Vec3,
        normal_hint: Option<Vec3>,
        light: &Light,
        samples_per_side: u32,
    ) -> f32 {
        if !p.is_finite() {
            return NO_RECEIVER;
        }
        let p = self.receiver(p);
        let samples = light_samples(p, light, samples_per_side);
        if samples.is_empty() {
            return 1.0;
        }
        let lit = samples
            .iter()
            .filter(|s| {
                let above = normal_hint.is_none_or(|n| n.dot(s.dir) > 0.0);
                let reach = s.max_t - self.epsilon;
                above && !(reach > 0.0 && self.any_hit(p + s.dir * self.epsilon, s.dir, reach))
            })
            .count();
        lit as f32 / samples.len() as f32
    }

    /// [`Self::visible_fraction`] for each point (`None`: no receiver, [`NO_RECEIVER`]), without normal hints,
    /// spread over the machine's threads.
    pub fn visible_fractions(
        &self,
        points: &[Option<Vec3>],
        light: &Light,
        samples_per_side: u32,
    ) -> Vec<f32> {
        self.in_parallel(points, |p| {
            p.map_or(NO_RECEIVER, |p| {
                self.visible_fraction(p, None, light, samples_per_side)
            })
        })
    }

    /// [`Self::visible_fractions`] with each receiver's normal as its hint.
    pub fn visible_fractions_with_normals(
        &self,
        receivers: &[Option<(Vec3, Vec3)>],
        light: &Light,
        samples_per_side: u32,
    ) -> Vec<f32> {
        self.in_parallel(receivers, |r| {
            r.map_or(NO_RECEIVER, |(p, n)| {
                self.visible_fraction(p, Some(n), light, samples_per_side)
            })
        })
    }

    /// `f` of every item, on every thread the machine offers. Items are handed out in small chunks as threads
    /// come free, since shadowed and relief pixels cost far more than open ground.
    fn in_parallel<T: Sync>(&self, items: &[T], f: impl Fn(&T) -> f32 + Sync) -> Vec<f32> {
        const CHUNK: usize = 64;
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let next = AtomicUsize::new(0);
        let mut done: Vec<(usize, Vec<f32>)> = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    scope.spawn(|| {
                        let mut mine = Vec::new();
                        loop {
                            let start = next.fetch_add(CHUNK, Ordering::Relaxed);
                            if start >= items.len() {
                                return mine;
                            }
                            let end = (start + CHUNK).min(items.len());
                            mine.push((start, items[start..end].iter().map(&f).collect()));
                        }
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("a shadow worker panicked"))
                .collect()
        });
        done.sort_unstable_by_key(|(start, _)| *start);
        done.into_iter().flat_map(|(_, values)| values).collect()
    }
}

fn bounds(primitive: &Primitive) -> Aabb {
    match primitive {
        Primitive::Plain(tri) => Aabb::around(&tri.corners),
        Primitive::Relief(shell) => shell.bounds(),
    }
}
