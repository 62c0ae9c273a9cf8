//! Points, triangles and the indexed triangle mesh.
//!
//! A [`Mesh`] keeps each distinct vertex once, each triangle as three vertex
//! indices, and each distinct edge once (with the three edges of every
//! triangle), so a drop-cutter query tests a vertex or an edge shared by six
//! or two triangles only once. Degenerate triangles (a repeated vertex, zero
//! area, a non-finite coordinate) are skipped and counted, never stored.

use std::ops::{Add, Mul, Sub};

/// A point or a vector in space, mm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3 {
    /// X.
    pub x: f64,
    /// Y.
    pub y: f64,
    /// Z.
    pub z: f64,
}

impl Vec3 {
    /// The point `(x, y, z)`.
    #[inline]
    pub const fn new(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3 { x, y, z }
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: Vec3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }

    /// Euclidean length.
    #[inline]
    pub fn norm(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// Whether all three coordinates are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, k: f64) -> Vec3 {
        Vec3::new(self.x * k, self.y * k, self.z * k)
    }
}

/// A triangle by its three corners.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Triangle {
    /// The corners.
    pub v: [Vec3; 3],
}

impl Triangle {
    /// The triangle `a b c`.
    pub const fn new(a: Vec3, b: Vec3, c: Vec3) -> Triangle {
        Triangle { v: [a, b, c] }
    }

    /// `(b − a) × (c − a)`: normal to the triangle, twice its area long.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        (self.v[1] - self.v[0]).cross(self.v[2] - self.v[0])
    }

    /// Area in mm².
    pub fn area(&self) -> f64 {
        0.5 * self.normal().norm()
    }

    /// Whether the triangle has a non-finite coordinate or no area: its
    /// corners are collinear to within rounding (twice the area at most
    /// 1e-12 of the longest edge squared).
    pub fn is_degenerate(&self) -> bool {
        if !self.v.iter().all(|p| p.is_finite()) {
            return true;
        }
        let longest = (0..3).map(|k| (self.v[(k + 1) % 3] - self.v[k]).dot(self.v[(k + 1) % 3] - self.v[k]));
        let longest = longest.fold(0.0, f64::max);
        let twice_area = self.normal().norm();
        twice_area.is_nan() || twice_area <= 1e-12 * longest
    }

    /// XY bounding box `[min x, min y, max x, max y]`.
    pub fn xy_box(&self) -> [f64; 4] {
        let [a, b, c] = self.v;
        [a.x.min(b.x).min(c.x), a.y.min(b.y).min(c.y), a.x.max(b.x).max(c.x), a.y.max(b.y).max(c.y)]
    }

    /// Highest z of the three corners.
    #[inline]
    pub fn max_z(&self) -> f64 {
        self.v[0].z.max(self.v[1].z).max(self.v[2].z)
    }
}

/// An indexed triangle mesh: distinct vertices, triangles as vertex index
/// triples, distinct edges.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    edges: Vec<[u32; 2]>,
    triangle_edges: Vec<[u32; 3]>,
    skipped: usize,
}

impl Mesh {
    /// Builds the mesh of `triangles`, merging corners with bit-identical
    /// coordinates (`-0` and `0` are one) and skipping degenerate triangles
    /// (see [`Triangle::is_degenerate`]; also two corners that merge).
    pub fn from_triangles<I: IntoIterator<Item = Triangle>>(triangles: I) -> Mesh {
        let triangles = triangles.into_iter();
        let hint = triangles.size_hint().0;
        Mesh::from_triangles_counted(triangles, hint)
    }

    /// [`Mesh::from_triangles`] of about `hint` triangles.
    pub(crate) fn from_triangles_counted(triangles: impl Iterator<Item = Triangle>, hint: usize) -> Mesh {
        let mut mesh = Mesh::default();
        mesh.triangles.reserve(hint);
        // A closed mesh, or a surface drawn as a grid, has about half as
        // many vertices as triangles.
        mesh.vertices.reserve(hint / 2 + 16);
        let mut vertex_ids = VertexTable::with_capacity(hint / 2 + 16);
        for t in triangles {
            if t.is_degenerate() {
                mesh.skipped += 1;
                continue;
            }
            let ids = [0, 1, 2].map(|k| vertex_ids.id(&mut mesh.vertices, t.v[k]));
            if ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2] {
                mesh.skipped += 1;
                continue;
            }
            mesh.triangles.push(ids);
        }
        // The table is no longer needed: its memory is free for the edges.
        drop(vertex_ids);
        (mesh.edges, mesh.triangle_edges) = edges_of(mesh.vertices.len(), &mesh.triangles);
        mesh
    }

    /// The distinct vertices.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The triangles as indices into [`Mesh::vertices`].
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The distinct edges as vertex index pairs (smaller index first).
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// For each triangle, its three edges as indices into [`Mesh::edges`]
    /// (corners 0–1, 1–2, 2–0).
    pub fn triangle_edges(&self) -> &[[u32; 3]] {
        &self.triangle_edges
    }

    /// How many triangles were skipped as degenerate.
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the mesh has no triangle.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Triangle `i` by its corners.
    #[inline]
    pub fn triangle(&self, i: usize) -> Triangle {
        Triangle { v: self.triangles[i].map(|k| self.vertices[k as usize]) }
    }

    /// All triangles by their corners.
    pub fn iter(&self) -> impl Iterator<Item = Triangle> + '_ {
        (0..self.len()).map(|i| self.triangle(i))
    }

    /// Bounding box `(min, max)` of the vertices; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.vertices.first()?;
        Some(self.vertices.iter().fold((first, first), |(lo, hi), p| {
            (
                Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)),
                Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)),
            )
        }))
    }
}

/// Vertex ids by exact coordinates: open addressing over `u32` ids (the
/// coordinates live in the vertex list), a table small enough to stay in
/// cache, where a general hash map of 32-byte entries would not.
struct VertexTable {
    slots: Vec<u32>,
    len: usize,
}

impl VertexTable {
    const EMPTY: u32 = u32::MAX;

    fn with_capacity(n: usize) -> VertexTable {
        VertexTable { slots: vec![VertexTable::EMPTY; (2 * n).next_power_of_two()], len: 0 }
    }

    #[inline]
    fn hash(p: Vec3) -> u64 {
        // Multiply-xor, then the splitmix finaliser: coordinates read from
        // `f32` have 29 zero low bits.
        let mut h = 0u64;
        for c in [p.x, p.y, p.z] {
            h = (h.rotate_left(23) ^ c.to_bits()).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^ (h >> 31)
    }

    /// The id of `p` (`-0` read as `0`), added to `vertices` if new.
    #[inline]
    fn id(&mut self, vertices: &mut Vec<Vec3>, p: Vec3) -> u32 {
        let p = Vec3::new(p.x + 0.0, p.y + 0.0, p.z + 0.0);
        let same = |q: &Vec3| {
            q.x.to_bits() == p.x.to_bits() && q.y.to_bits() == p.y.to_bits() && q.z.to_bits() == p.z.to_bits()
        };
        let mask = self.slots.len() - 1;
        let mut k = VertexTable::hash(p) as usize & mask;
        loop {
            let id = self.slots[k];
            if id == VertexTable::EMPTY {
                break;
            }
            if same(&vertices[id as usize]) {
                return id;
            }
            k = (k + 1) & mask;
        }
        let id = vertices.len() as u32;
        vertices.push(p);
        self.slots[k] = id;
        self.len += 1;
        if 2 * self.len > self.slots.len() {
            self.grow(vertices);
        }
        id
    }

    fn grow(&mut self, vertices: &[Vec3]) {
        self.slots = vec![VertexTable::EMPTY; 2 * self.slots.len()];
        let mask = self.slots.len() - 1;
        for (id, &p) in vertices.iter().enumerate() {
            let mut k = VertexTable::hash(p) as usize & mask;
            while self.slots[k] != VertexTable::EMPTY {
                k = (k + 1) & mask;
            }
            self.slots[k] = id as u32;
        }
    }
}

/// The distinct edges of `triangles` and each triangle's three: the edge
/// ends grouped by their smaller vertex (a counting sort), then matched
/// within each vertex's short list.
fn edges_of(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<[u32; 2]>, Vec<[u32; 3]>) {
    let ends = |t: &[u32; 3], k: usize| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        (a.min(b), a.max(b))
    };
    let mut start = vec![0u32; vertex_count + 1];
    for t in triangles {
        for k in 0..3 {
            start[ends(t, k).0 as usize + 1] += 1;
        }
    }
    for v in 1..start.len() {
        start[v] += start[v - 1];
    }
    // (other end, triangle·3 + corner), grouped by the smaller end.
    let mut sides = vec![(0u32, 0u32); 3 * triangles.len()];
    let mut fill = start.clone();
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = ends(t, k);
            sides[fill[a as usize] as usize] = (b, (3 * i + k) as u32);
            fill[a as usize] += 1;
        }
    }
    let mut edges = Vec::with_capacity(3 * triangles.len() / 2 + 3);
    let mut triangle_edges = vec![[0u32; 3]; triangles.len()];
    for a in 0..vertex_count {
        let list = &sides[start[a] as usize..start[a + 1] as usize];
        for (n, &(b, corner)) in list.iter().enumerate() {
            let id = match list[..n].iter().find(|(other, _)| *other == b) {
                Some(&(_, first)) => triangle_edges[first as usize / 3][first as usize % 3],
                None => {
                    edges.push([a as u32, b]);
                    (edges.len() - 1) as u32
                }
            };
            triangle_edges[corner as usize / 3][corner as usize % 3] = id;
        }
    }
    (edges, triangle_edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Triangle {
        let p = |v: [f64; 3]| Vec3::new(v[0], v[1], v[2]);
        Triangle::new(p(a), p(b), p(c))
    }

    #[test]
    fn shared_vertices_and_edges_are_stored_once() {
        // A unit square as two triangles: 4 vertices, 5 edges.
        let m = Mesh::from_triangles([
            t([0., 0., 0.], [1., 0., 0.], [1., 1., 0.]),
            t([0., 0., 0.], [1., 1., 0.], [0., 1., -0.0]),
        ]);
        assert_eq!((m.len(), m.vertices().len(), m.edges().len(), m.skipped()), (2, 4, 5, 0));
        let shared: Vec<u32> =
            m.triangle_edges()[0].iter().filter(|e| m.triangle_edges()[1].contains(e)).copied().collect();
        assert_eq!(shared.len(), 1);
        assert_eq!(m.edges()[shared[0] as usize], [0, 2]);
        assert_eq!(m.triangle(1), t([0., 0., 0.], [1., 1., 0.], [0., 1., 0.]));
        assert_eq!(m.bounds().unwrap().1, Vec3::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn degenerate_triangles_are_skipped_and_counted() {
        let m = Mesh::from_triangles([
            t([0., 0., 0.], [1., 0., 0.], [2., 0., 0.]),
            t([0., 0., 0.], [0., 0., 0.], [2., 1., 0.]),
            t([0., 0., f64::NAN], [1., 0., 0.], [2., 1., 0.]),
            t([0., 0., 0.], [1., 0., 0.], [1., 1e-9, 0.]),
            // A vertical wall has area: kept.
            t([0., 0., 0.], [1., 0., 0.], [1., 0., 1.]),
        ]);
        assert_eq!((m.len(), m.skipped()), (2, 3));
        assert!(Mesh::from_triangles([]).is_empty());
        assert_eq!(Mesh::from_triangles([]).bounds(), None);
    }
}
