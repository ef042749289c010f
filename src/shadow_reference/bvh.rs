//! A bounding volume hierarchy over boxes, blind to what the boxes hold: the caller's closure tests the
//! primitive itself. Built by median split of the centroids along the widest axis (simple, deterministic, and
//! within a small factor of SAH for the few thousand triangles a test scene has); traversal is a stack of nodes
//! visited nearer child first, so `first_hit` can shorten the ray as it finds hits.
//!
//! Invariant: every primitive index appears in exactly one leaf, and every node's box holds its subtree's boxes.

use glam::Vec3;

/// Primitives per leaf: below this, splitting costs more box tests than it saves primitive tests.
const LEAF_SIZE: usize = 4;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The smallest corner.
    pub min: Vec3,
    /// The largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box around `points` (at least one).
    pub fn around(points: &[Vec3]) -> Aabb {
        let first = Aabb {
            min: points[0],
            max: points[0],
        };
        points.iter().fold(first, |b, &p| Aabb {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }

    fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Whether `p` lies inside (boundary included).
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The ray's entry parameter if it meets the box within `[0, max_t]`. `inv_dir` is `1 / dir` per axis.
    fn entry(&self, origin: Vec3, inv_dir: Vec3, max_t: f32) -> Option<f32> {
        let (mut near, mut far) = (0.0f32, max_t);
        for axis in 0..3 {
            let (o, inv) = (origin[axis], inv_dir[axis]);
            let (lo, hi) = (self.min[axis], self.max[axis]);
            if inv.is_infinite() {
                // A ray that does not move along this axis is inside the slab everywhere or nowhere; the
                // general formula would give 0 * inf = NaN on a face.
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let (a, b) = ((lo - o) * inv, (hi - o) * inv);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        (near <= far).then_some(near)
    }
}

#[derive(Debug, Clone)]
enum Node {
    Leaf { first: usize, count: usize },
    Inner { left: usize, right: usize },
}

/// The hierarchy: nodes with their boxes, and the primitive indices the leaves point into.
#[derive(Debug, Clone)]
pub struct Bvh {
    boxes: Vec<Aabb>,
    nodes: Vec<Node>,
    order: Vec<usize>,
}

impl Bvh {
    /// Builds the hierarchy over `boxes`; primitive `k` is the one with box `boxes[k]`.
    pub fn build(boxes: &[Aabb]) -> Bvh {
        let mut bvh = Bvh {
            boxes: Vec::new(),
            nodes: Vec::new(),
            order: (0..boxes.len()).collect(),
        };
        if !boxes.is_empty() {
            bvh.split(boxes, 0, boxes.len());
        }
        bvh
    }

    /// Adds the node over `order[first..first + count]` and its subtree; returns its index.
    fn split(&mut self, boxes: &[Aabb], first: usize, count: usize) -> usize {
        let slice = &mut self.order[first..first + count];
        let bounds = slice
            .iter()
            .map(|&k| boxes[k])
            .reduce(Aabb::union)
            .expect("a node holds at least one primitive");
        let index = self.nodes.len();
        self.boxes.push(bounds);
        self.nodes.push(Node::Leaf { first, count });
        if count <= LEAF_SIZE {
            return index;
        }
        let extent = bounds.max - bounds.min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let half = count / 2;
        slice.select_nth_unstable_by(half, |&a, &b| {
            boxes[a].centroid()[axis].total_cmp(&boxes[b].centroid()[axis])
        });
        let left = self.split(boxes, first, half);
        let right = self.split(boxes, first + half, count - half);
        self.nodes[index] = Node::Inner { left, right };
        index
    }

    /// The nearest hit in `[0, max_t]`: `hit(k, t_max)` tests primitive `k` and returns its hit parameter, if
    /// any, no farther than `t_max` (the nearest found so far).
    pub fn first_hit(
        &self,
        origin: Vec3,
        dir: Vec3,
        max_t: f32,
        mut hit: impl FnMut(usize, f32) -> Option<f32>,
    ) -> Option<f32> {
        let mut best: Option<f32> = None;
        self.traverse(origin, dir, max_t, |k, limit| {
            if let Some(t) = hit(k, limit).filter(|&t| t <= limit) {
                best = Some(t);
                return Some(t);
            }
            None
        });
        best
    }

    /// Whether any primitive blocks the ray in `[0, max_t]`; stops at the first one found.
    pub fn any_hit(
        &self,
        origin: Vec3,
        dir: Vec3,
        max_t: f32,
        mut hit: impl FnMut(usize, f32) -> bool,
    ) -> bool {
        let mut found = false;
        self.traverse(origin, dir, max_t, |k, limit| {
            found = hit(k, limit);
            // A hit at -inf prunes every remaining node, which ends the walk.
            found.then_some(f32::NEG_INFINITY)
        });
        found
    }

    /// Visits every primitive whose box holds `p`.
    pub fn containing(&self, p: Vec3, mut visit: impl FnMut(usize)) {
        let mut stack = vec![0];
        while let Some(n) = stack.pop() {
            if self.nodes.is_empty() || !self.boxes[n].contains(p) {
                continue;
            }
            match self.nodes[n] {
                Node::Leaf { first, count } => {
                    self.order[first..first + count]
                        .iter()
                        .for_each(|&k| visit(k));
                }
                Node::Inner { left, right } => stack.extend([left, right]),
            }
        }
    }

    /// Walks the nodes the ray meets, nearer child first; `test(k, limit)` returns a new, smaller limit when
    /// primitive `k` shortens the ray.
    fn traverse(
        &self,
        origin: Vec3,
        dir: Vec3,
        max_t: f32,
        mut test: impl FnMut(usize, f32) -> Option<f32>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let inv_dir = dir.recip();
        let mut limit = max_t;
        let mut stack = vec![0];
        while let Some(n) = stack.pop() {
            if self.boxes[n].entry(origin, inv_dir, limit).is_none() {
                continue;
            }
            match self.nodes[n] {
                Node::Leaf { first, count } => {
                    for &k in &self.order[first..first + count] {
                        if let Some(t) = test(k, limit) {
                            limit = t;
                        }
                        if limit == f32::NEG_INFINITY {
                            return;
                        }
                    }
                }
                Node::Inner { left, right } => {
                    let near = |c: usize| self.boxes[c].entry(origin, inv_dir, limit);
                    // Pushed far first, so the nearer child is popped (and may shorten the ray) first.
                    let (first, second) = match (near(left), near(right)) {
                        (Some(a), Some(b)) if b < a => (right, left),
                        _ => (left, right),
                    };
                    stack.extend([second, first]);
                }
            }
        }
    }
}
