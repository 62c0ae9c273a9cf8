//! Many drop-cutter queries along one row of a mesh, the triangles near
//! the row found once: each point gets the z a query of its own gives.
//!
//! A query of its own walks the index's cells under the cutter's square
//! and meets each triangle about three times there (in up to four cells,
//! reported from one). Along a row of close points the triangles within a
//! radius of the row are gathered once, sorted into slots by where their
//! boxes begin along it; each point then scans the slots its disk reaches
//! for those whose boxes meet it: the very triangles the index reports
//! (the same test on the same boxes), so the same contacts are tried and
//! the highest is the same, bit for bit.

use rayon::prelude::*;

use super::{MeshScratch, MeshSurface, Probe, Surface};
use crate::cutter::{each_shape, Cutter};

/// Points of a run at least, for the triangles near it to be gathered
/// once; fewer are asked one by one.
const RUN: usize = 4;

impl MeshSurface {
    /// The tip z of `cutter` at every `u` of the row at `v` (along X at
    /// `y = v`, along Y at `x = v` where `along_y`), each what
    /// [`Surface::drop_cutter_with`] gives there. `us` in
    /// any order; runs of points each within half a radius of the last
    /// share the search for the triangles near them.
    pub fn drop_cutter_along(&self, cutter: &Cutter, along_y: bool, v: f64, us: &[f64]) -> Vec<Option<f64>> {
        let pooled = self.pool.lock().ok().and_then(|mut p| p.pop());
        let mut scratch = pooled.unwrap_or_else(|| self.scratch());
        let mut out = Vec::with_capacity(us.len());
        // Gathering the triangles near a run pays where its points are at
        // least two a radius: fewer are asked one by one.
        let gap = 0.5 * cutter.radius();
        let mut k = 0;
        while k < us.len() {
            let mut end = k + 1;
            while end < us.len() && (us[end] - us[end - 1]).abs() <= gap {
                end += 1;
            }
            let run = &us[k..end];
            if run.len() >= RUN && v.is_finite() {
                self.run(cutter, along_y, v, run, &mut scratch, &mut out);
            } else {
                for &u in run {
                    let (x, y) = if along_y { (v, u) } else { (u, v) };
                    out.push(self.drop_cutter_with(cutter, x, y, &mut scratch));
                }
            }
            k = end;
        }
        if let Ok(mut pool) = self.pool.lock() {
            pool.push(scratch);
        }
        out
    }

    /// The points `run` (finite, each within half a radius of the last), the
    /// triangles near them gathered once.
    fn run(
        &self,
        cutter: &Cutter,
        along_y: bool,
        v: f64,
        run: &[f64],
        scratch: &mut MeshScratch,
        out: &mut Vec<Option<f64>>,
    ) {
        let r = cutter.radius();
        let (lo, hi) = run.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &u| (a.min(u), b.max(u)));
        // A little wider than every point's square, against rounding: the
        // exact tests below decide.
        let slack = 1e-9 * (1.0 + r + lo.abs().max(hi.abs()) + v.abs());
        let (a0, a1, b0, b1) = (lo - r - slack, hi + r + slack, v - r - slack, v + r + slack);
        let strip = if along_y { [b0, a0, b1, a1] } else { [a0, b0, a1, b1] };
        let (u_lo, u_hi) = if along_y { (1, 3) } else { (0, 2) };
        // The triangles near the run by where their boxes begin along it,
        // in slots a quarter of a radius long (a counting sort).
        let slot = 0.25 * r;
        let slot_of = |a: f64, last: usize| (((a - a0) / slot).floor().max(0.0) as usize).min(last);
        let slots = (((a1 - a0) / slot).ceil() as usize).saturating_add(1);
        let (index, near, starts) = (&self.index, &mut scratch.near_row, &mut scratch.slot_starts);
        near.clear();
        index.for_each_in_box(strip, |t| {
            let b = index.triangle_box(t);
            near.push((b[u_lo], b[u_hi], t));
        });
        starts.clear();
        starts.resize(slots + 1, 0);
        for p in near.iter() {
            starts[slot_of(p.0, slots - 1) + 1] += 1;
        }
        for k in 1..starts.len() {
            starts[k] += starts[k - 1];
        }
        let mut fill = starts.clone();
        let sorted = &mut scratch.sorted_row;
        sorted.clear();
        sorted.resize(near.len(), (0.0, 0.0, 0));
        for &p in near.iter() {
            let k = slot_of(p.0, slots - 1);
            sorted[fill[k] as usize] = p;
            fill[k] += 1;
        }
        let widest = near.iter().map(|p| p.1 - p.0).fold(0.0, f64::max);
        for &u in run {
            let (x, y) = if along_y { (v, u) } else { (u, v) };
            if !(x.is_finite() && y.is_finite()) {
                out.push(None);
                continue;
            }
            out.push(each_shape!(cutter, shape => {
                let probe = Probe::new(shape, x, y);
                let (radius, [cx, cy]) = (probe.radius(), probe.centre());
                // The index's test: the box meets the disk.
                let r2 = radius * radius;
                let first = slot_of(u - radius - widest - slack, slots - 1);
                let last = slot_of(u + radius + slack, slots - 1);
                let range = scratch.slot_starts[first] as usize..scratch.slot_starts[last + 1] as usize;
                scratch.candidates.clear();
                for &(low, high, t) in &scratch.sorted_row[range] {
                    if low > u + radius + slack || high < u - radius - slack {
                        continue;
                    }
                    let b = self.index.triangle_box(t);
                    let dx = (b[0] - cx).max(cx - b[2]).max(0.0);
                    let dy = (b[1] - cy).max(cy - b[3]).max(0.0);
                    if dx * dx + dy * dy <= r2 {
                        scratch.candidates.push(t);
                    }
                }
                self.contacts(probe, scratch)
            }));
        }
    }
}

/// Points of a row one thread takes at a time: rows differ in how many
/// points they ask, and both cores stay busy to the last.
const PIECE: usize = 256;

/// [`MeshSurface::drop_cutter_along`] on every row `(v, us)`, in pieces of
/// [`PIECE`] points in parallel.
pub fn drop_cutter_along_rows(
    cutter: &Cutter,
    mesh: &MeshSurface,
    along_y: bool,
    rows: &[(f64, &[f64])],
) -> Vec<Vec<Option<f64>>> {
    let pieces: Vec<(usize, &[f64])> =
        rows.iter().enumerate().flat_map(|(k, &(_, us))| us.chunks(PIECE).map(move |piece| (k, piece))).collect();
    let zs: Vec<Vec<Option<f64>>> =
        pieces.par_iter().map(|&(k, us)| mesh.drop_cutter_along(cutter, along_y, rows[k].0, us)).collect();
    let mut out: Vec<Vec<Option<f64>>> = rows.iter().map(|(_, us)| Vec::with_capacity(us.len())).collect();
    for ((k, _), z) in pieces.iter().zip(zs) {
        out[*k].extend(z);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dropcut::drop_cutter;
    use kezuri_geom::{Mesh, SplitMix64, Triangle, Vec3};

    /// A wavy surface of 2 × 40 × 40 triangles over [0, 20]², some of its
    /// cells left out (a hole).
    fn wavy() -> MeshSurface {
        let z = |x: f64, y: f64| 2.0 * (x * 0.4).sin() * (y * 0.3).cos() + 0.7 * ((x + y) * 0.9).sin();
        let p = |i: usize, j: usize| {
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
            Vec3::new(x, y, z(x, y))
        };
        let mut triangles = Vec::new();
        for j in 0..40 {
            for i in (0..40).filter(|&i| !((10..14).contains(&i) && (20..23).contains(&j))) {
                triangles.push(Triangle::new(p(i, j), p(i + 1, j), p(i + 1, j + 1)));
                triangles.push(Triangle::new(p(i, j), p(i + 1, j + 1), p(i, j + 1)));
            }
        }
        MeshSurface::new(Mesh::from_triangles(triangles))
    }

    /// Every point of a row, dense runs and lone points, on and off the
    /// surface, gets the bits a query of its own gives.
    #[test]
    fn a_rows_points_are_each_what_a_query_of_its_own_gives() {
        let mesh = wavy();
        let mut random = SplitMix64::new(29);
        let mut asked = 0;
        for spec in ["ball:6", "flat:3", "bull:4,1", "v:6,90", "oval:8,12", "ball:0.4"] {
            let cutter: Cutter = spec.parse().unwrap();
            for along_y in [false, true] {
                for v in [0.0, 0.25, 5.3, 10.0, 11.1, 19.99, 20.0, 23.5, -4.0, f64::NAN] {
                    let mut us: Vec<f64> = (0..120).map(|k| -3.0 + k as f64 * 0.22).collect();
                    us.extend((0..30).map(|_| random.next_f64() * 30.0 - 5.0));
                    us.extend([0.0, 20.0, 1e9, f64::NAN, f64::INFINITY, 7.125, 7.125 + 1e-12]);
                    us.sort_by(f64::total_cmp);
                    let along = mesh.drop_cutter_along(&cutter, along_y, v, &us);
                    assert_eq!(along.len(), us.len());
                    for (&u, z) in us.iter().zip(along) {
                        let (x, y) = if along_y { (v, u) } else { (u, v) };
                        let alone = drop_cutter(&cutter, &mesh, x, y);
                        assert_eq!(z.map(f64::to_bits), alone.map(f64::to_bits), "{spec} {along_y} at ({x}, {y})");
                        asked += usize::from(alone.is_some());
                    }
                }
            }
        }
        // Most points are on the surface: the test is not of Nones.
        assert!(asked > 6000, "{asked}");
    }

    /// Rows of many lengths asked together, in pieces on both cores, come
    /// back each in its order.
    #[test]
    fn rows_asked_together_come_back_in_order() {
        let mesh = wavy();
        let cutter: Cutter = "bull:5,1".parse().unwrap();
        let us: Vec<Vec<f64>> = (0..7).map(|k| (0..k * 47).map(|i| -1.0 + i as f64 * 0.09).collect()).collect();
        let rows: Vec<(f64, &[f64])> = us.iter().enumerate().map(|(k, us)| (k as f64 * 2.9, &us[..])).collect();
        for along_y in [false, true] {
            let together = drop_cutter_along_rows(&cutter, &mesh, along_y, &rows);
            assert_eq!(together.len(), rows.len());
            for (&(v, us), zs) in rows.iter().zip(&together) {
                assert_eq!(zs, &mesh.drop_cutter_along(&cutter, along_y, v, us), "{along_y} {v}");
            }
        }
    }
}
