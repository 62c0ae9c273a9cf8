//! Drop-cutter, proven three ways: hand-computed contacts per shape and
//! contact type; random triangles against a brute-force oracle that knows
//! nothing of contacts (the cutter touches, and never cuts in); and one
//! suite through brute force, the spatial index and the height-grid fast
//! path.

use kezuri_cam::dropcut::{drop_cutter, drop_cutter_grid, drop_cutter_rows, Grid, MeshSurface};
use kezuri_cam::Cutter;
use kezuri_geom::{Heightfield, Mesh, Triangle, Vec3};
use proptest::prelude::*;

fn cutter(spec: &str) -> Cutter {
    spec.parse().unwrap()
}

fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Triangle {
    let p = |v: [f64; 3]| Vec3::new(v[0], v[1], v[2]);
    Triangle::new(p(a), p(b), p(c))
}

/// Drops `spec` at `(x, y)` by brute force and through the index; both must
/// give `want` (to 1e-12 mm).
#[track_caller]
fn check(spec: &str, tris: &[Triangle], x: f64, y: f64, want: f64) {
    let c = cutter(spec);
    let brute = drop_cutter(&c, tris, x, y).expect("a triangle under the cutter");
    let indexed = drop_cutter(&c, &MeshSurface::new(Mesh::from_triangles(tris.iter().copied())), x, y).unwrap();
    assert!((brute - want).abs() < 1e-12, "{spec} at ({x}, {y}): brute force {brute}, want {want}");
    assert!((indexed - want).abs() < 1e-12, "{spec} at ({x}, {y}): indexed {indexed}, want {want}");
}

/// A spike: the vertex (1, 0, 2), the rest falling steeply away.
fn spike() -> Vec<Triangle> {
    vec![tri([1., 0., 2.], [20., -1., -50.], [20., 1., -50.])]
}

/// The plane z = g·x over ±20 mm.
fn plane(g: f64) -> Vec<Triangle> {
    let p = |x: f64, y: f64| [x, y, g * x];
    vec![tri(p(-20., -20.), p(20., -20.), p(20., 20.)), tri(p(-20., -20.), p(20., 20.), p(-20., 20.))]
}

/// An edge along Y at x = 2 rising by `m` per mm, the facet behind it
/// falling steeply away from the cutter at the origin.
fn ridge(m: f64) -> Vec<Triangle> {
    vec![tri([2., -20., -20. * m], [2., 20., 20. * m], [3., 0., -100.])]
}

#[test]
fn vertex_contacts() {
    check("flat:6", &spike(), 0.0, 0.0, 2.0);
    check("ball:6", &spike(), 0.0, 0.0, 2.0 - (3.0 - 8f64.sqrt()));
    check("bull:10,2", &spike(), 0.0, 0.0, 2.0); // on the flat centre
    check("bull:10,2", &spike(), -3.0, 0.0, 2.0 - (2.0 - 3f64.sqrt())); // on the corner, 1 mm into it
    check("oval:16,24", &spike(), 0.0, 0.0, 2.0 - (24.0 - 3.0 * 63f64.sqrt()));
    check("oval:16,4", &spike(), 0.0, 0.0, 2.0 - 4.0 * (1.0 - (63f64 / 64.0).sqrt()));
    check("v:6,90", &spike(), 0.0, 0.0, 1.0);
    // On the rim, and just beyond it.
    check("ball:2", &spike(), 0.0, 0.0, 1.0);
    assert_eq!(drop_cutter(&cutter("ball:1.999"), &spike()[..], 0.0, 0.0), None);
}

#[test]
fn facet_contacts() {
    let level = plane(0.0);
    for spec in ["flat:6", "ball:6", "bull:10,2", "oval:16,24", "v:6,90"] {
        check(spec, &level, 0.3, -0.2, 0.0);
    }
    let g: f64 = 0.5;
    let tilted = plane(g);
    let lift = (1.0 + g * g).sqrt() - 1.0;
    check("flat:6", &tilted, 0.0, 0.0, 1.5); // the rim
    check("ball:6", &tilted, 0.0, 0.0, 3.0 * lift);
    check("bull:10,2", &tilted, 0.0, 0.0, g * 3.0 + 2.0 * lift);
    check("bull:10,0", &tilted, 0.0, 0.0, g * 5.0);
    check("oval:16,24", &tilted, 0.0, 0.0, (64.0 * g * g + 576.0).sqrt() - 24.0);
    check("oval:16,4", &tilted, 0.0, 0.0, (64.0 * g * g + 16.0).sqrt() - 4.0);
    check("v:6,90", &tilted, 0.0, 0.0, 0.0); // flatter than the cone: the tip
    check("v:6,90", &plane(2.0), 0.0, 0.0, 2.0 * 3.0 - 3.0); // steeper: the rim
    check("ball:6", &tilted, 4.0, 1.0, g * 4.0 + 3.0 * lift);
}

#[test]
fn edge_contacts() {
    // A level edge 2 mm from the axis: the profile's height there.
    let level = ridge(0.0);
    check("flat:6", &level, 0.0, 0.0, 0.0);
    check("ball:6", &level, 0.0, 0.0, -(3.0 - 5f64.sqrt()));
    check("bull:10,2", &level, -2.0, 0.0, -(2.0 - 3f64.sqrt()));
    check("oval:16,24", &level, 0.0, 0.0, -(24.0 - 6.0 * 15f64.sqrt()));
    check("v:6,90", &level, 0.0, 0.0, -2.0);
    // Rising 0.5 mm per mm: the contact slides along the edge.
    let m: f64 = 0.5;
    let rising = ridge(m);
    check("flat:6", &rising, 0.0, 0.0, m * 5f64.sqrt()); // where the rim crosses the edge
    check("ball:6", &rising, 0.0, 0.0, -0.5); // the circle slice: x = 1
    check("oval:16,24", &rising, 0.0, 0.0, 555f64.sqrt() - 24.0); // the ellipse slice
    check("v:6,90", &rising, 0.0, 0.0, -3f64.sqrt()); // the hyperbola slice
                                                      // Bull: a ball of the corner radius swept over the flat centre's disk
                                                      // (Minkowski), each ball resting on the line: maximise over the offset.
    let (flat, corner, d) = (3.0f64, 2.0f64, 2.0f64);
    let bull = |q: f64| {
        m * (flat * flat - q * q).sqrt() + (1.0 + m * m).sqrt() * (corner * corner - (d - q).powi(2)).sqrt() - corner
    };
    let (mut lo, mut hi) = (0.0, flat);
    for _ in 0..200 {
        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if bull(a) < bull(b) {
            lo = a
        } else {
            hi = b
        }
    }
    check("bull:10,2", &rising, 0.0, 0.0, bull(0.5 * (lo + hi)));
}

/// The largest `p.z − height(|p − c|)` over the triangle's points within the
/// cutter's radius, by sampling: a dense grid, then a pattern search that
/// moves a shrinking window of samples to its best point (the function is
/// concave, so this finds the maximum). `None` if no sample is in reach.
fn oracle(c: &Cutter, t: &Triangle, x: f64, y: f64) -> Option<f64> {
    let r = c.radius();
    let [a, b, cc] = t.v;
    let f = |u: f64, v: f64| {
        let (u, v) = (u.max(0.0), v.max(0.0));
        let (u, v) = if u + v > 1.0 { (u / (u + v), v / (u + v)) } else { (u, v) };
        let p = a + (b - a) * u + (cc - a) * v;
        let d = (p.x - x).hypot(p.y - y);
        if d <= r {
            p.z - c.height(d)
        } else {
            f64::NEG_INFINITY
        }
    };
    let n = 200;
    let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
    for i in 0..=n {
        for j in 0..=n - i {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let z = f(u, v);
            if z > best.0 {
                best = (z, u, v);
            }
        }
    }
    // The edges, finely: a thin overlap with the disk may lie between the
    // grid's points.
    let m = 20_000;
    for k in 0..=m {
        let s = k as f64 / m as f64;
        for (u, v) in [(s, 0.0), (0.0, s), (s, 1.0 - s)] {
            let z = f(u, v);
            if z > best.0 {
                best = (z, u, v);
            }
        }
    }
    // The rim, where a linear function on the disk peaks: a stall for the
    // search below (its improving region thins to a sliver), so it is
    // searched on its own, by angle.
    let (e1, e2) = (b - a, cc - a);
    let det = e1.x * e2.y - e1.y * e2.x;
    let rim = |phi: f64| {
        let (px, py) = (x + r * phi.cos() - a.x, y + r * phi.sin() - a.y);
        let (u, v) = ((px * e2.y - py * e2.x) / det, (e1.x * py - e1.y * px) / det);
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
            a.z + e1.z * u + e2.z * v - c.height(r)
        } else {
            f64::NEG_INFINITY
        }
    };
    let mut rim_best = (f64::NEG_INFINITY, 0.0);
    for k in 0..m {
        let phi = std::f64::consts::TAU * k as f64 / m as f64;
        let z = rim(phi);
        if z > rim_best.0 {
            rim_best = (z, phi);
        }
    }
    if rim_best.0 > f64::NEG_INFINITY {
        let mut h = std::f64::consts::TAU / m as f64;
        while h > 1e-15 {
            let phi0 = rim_best.1;
            for i in -10..=10 {
                let phi = phi0 + h * i as f64 / 10.0;
                let z = rim(phi);
                if z > rim_best.0 {
                    rim_best = (z, phi);
                }
            }
            if (rim_best.1 - phi0).abs() < 0.7 * h {
                h *= 0.5;
            }
        }
    }
    if best.0 == f64::NEG_INFINITY {
        return (rim_best.0 > f64::NEG_INFINITY).then_some(rim_best.0);
    }
    let mut h = 2.0 / n as f64;
    let k = 10;
    while h > 1e-13 {
        let (_, u0, v0) = best;
        for i in -k..=k {
            for j in -k..=k {
                let (u, v) = (u0 + h * i as f64 / k as f64, v0 + h * j as f64 / k as f64);
                let z = f(u, v);
                if z > best.0 {
                    best = (z, u, v);
                }
            }
        }
        // Shrink unless the best point moved to the window's edge.
        if (best.1 - u0).abs().max((best.2 - v0).abs()) < 0.7 * h {
            h *= 0.5;
        }
    }
    Some(best.0.max(rim_best.0))
}

/// XY distance from `(x, y)` to the triangle.
fn distance(t: &Triangle, x: f64, y: f64) -> f64 {
    let mut d = f64::INFINITY;
    let mut sides = [0.0; 3];
    for (k, side) in sides.iter_mut().enumerate() {
        let (p, q) = (t.v[k], t.v[(k + 1) % 3]);
        let (ex, ey) = (q.x - p.x, q.y - p.y);
        let s = (((x - p.x) * ex + (y - p.y) * ey) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
        d = d.min((p.x + s * ex - x).hypot(p.y + s * ey - y));
        *side = ex * (y - p.y) - ey * (x - p.x);
    }
    if sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0) {
        0.0
    } else {
        d
    }
}

fn any_cutter() -> impl Strategy<Value = Cutter> {
    let d = 1.0..8.0f64;
    prop_oneof![
        d.clone().prop_map(|d| cutter(&format!("flat:{d}"))),
        d.clone().prop_map(|d| cutter(&format!("ball:{d}"))),
        (d.clone(), 0.0..=1.0f64).prop_map(|(d, k)| cutter(&format!("bull:{d},{}", k * d / 2.0))),
        (d.clone(), 0.2..4.0f64).prop_map(|(d, k)| cutter(&format!("oval:{d},{}", k * d / 2.0))),
        (d, 20.0..160.0f64).prop_map(|(d, a)| cutter(&format!("v:{d},{a}"))),
    ]
}

fn any_point() -> impl Strategy<Value = Vec3> {
    (-4.0..4.0f64, -4.0..4.0f64, -3.0..3.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// The cutter at the returned z touches the triangle and never cuts it.
    #[test]
    fn touches_and_never_gouges(c in any_cutter(), a in any_point(), b in any_point(), p in any_point(),
                                x in -3.0..3.0f64, y in -3.0..3.0f64) {
        let t = Triangle::new(a, b, p);
        prop_assume!(t.area() > 0.2);
        let got = drop_cutter(&c, &[t][..], x, y);
        let want = oracle(&c, &t, x, y);
        match (got, want) {
            (Some(z), Some(o)) => {
                prop_assert!(z.is_finite());
                // The oracle's highest sample is the smallest vertical gap.
                prop_assert!(z - o >= -1e-9, "{c}: gouge: cutter at {z}, surface point holds it at {o}");
                prop_assert!(z - o <= 1e-6, "{c}: no touch: cutter at {z}, nearest gap {}", z - o);
            }
            (None, None) => {}
            (Some(_), None) => prop_assert!(distance(&t, x, y) >= c.radius() - 1e-6, "{c}: oracle found nothing"),
            (None, Some(o)) => prop_assert!(false, "{c}: missed the triangle (oracle {o})"),
        }
    }
}

/// A deterministic random source.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn shapes() -> Vec<Cutter> {
    ["flat:3", "ball:6", "bull:6,1", "oval:4,6", "oval:4,1", "v:4,60"].iter().map(|s| cutter(s)).collect()
}

/// A bumpy mesh with triangles of mixed sizes, some vertical, some loose.
fn bumpy_mesh(rng: &mut Rng) -> Vec<Triangle> {
    let h = Heightfield::from_fn(0.0, 0.0, 0.7, 25, 20, |x, y| (x * 0.9).sin() * (y * 0.6).cos() * 2.0).unwrap();
    let mut tris: Vec<Triangle> = h.to_mesh().iter().collect();
    for _ in 0..150 {
        let (x, y, s) = (rng.next() * 18.0, rng.next() * 14.0, 0.2 + 4.0 * rng.next());
        let mut p = || Vec3::new(x + s * rng.next(), y + s * rng.next(), 3.0 * rng.next() - 1.0);
        tris.push(Triangle::new(p(), p(), p()));
    }
    // A vertical wall.
    tris.push(tri([5., 5., -1.], [9., 6., -1.], [9., 6., 3.5]));
    tris
}

#[test]
fn the_index_finds_what_brute_force_finds() {
    let mut rng = Rng(99);
    let tris = bumpy_mesh(&mut rng);
    let mesh = Mesh::from_triangles(tris.iter().copied());
    assert_eq!(mesh.skipped(), 0);
    let surface = MeshSurface::new(mesh);
    for c in shapes() {
        for _ in 0..400 {
            let (x, y) = (rng.next() * 26.0 - 4.0, rng.next() * 22.0 - 4.0);
            let brute = drop_cutter(&c, &tris[..], x, y);
            let fast = drop_cutter(&c, &surface, x, y);
            match (brute, fast) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "{c} at ({x}, {y}): {a} vs {b}"),
                _ => assert_eq!(brute, fast, "{c} at ({x}, {y})"),
            }
        }
    }
}

#[test]
fn the_height_grid_fast_path_is_the_same_surface_as_its_mesh() {
    let wavy =
        Heightfield::from_fn(-3.0, 1.0, 0.4, 31, 23, |x, y| (x * 0.7).sin() + (y * 1.3).cos() * 0.8 + 0.05 * x * y)
            .unwrap();
    // Whole blocks of 8 × 8 cells, with lone spikes that only the block
    // tops know of, some on block boundaries.
    let spiky = Heightfield::from_fn(-2.0, 0.0, 0.25, 65, 41, |x, y| {
        let (i, j) = (((x + 2.0) * 4.0).round() as i64, (y * 4.0).round() as i64);
        let spike = if (i * 7 + j * 13) % 53 == 0 || (i % 8 == 0 && j % 16 == 8) { 1.5 } else { 0.0 };
        0.2 * (x * 0.5).sin() + spike
    })
    .unwrap();
    for (h, grid) in [
        // Grids that run past the edges on every side.
        (wavy, Grid::new(-7.0, -3.0, 13.5, 14.0, 0.37).unwrap()),
        (spiky, Grid::new(-5.0, -3.0, 17.0, 13.0, 0.29).unwrap()),
    ] {
        let surface = MeshSurface::new(h.to_mesh());
        let tris: Vec<Triangle> = h.to_mesh().iter().collect();
        for c in shapes() {
            let fast = drop_cutter_grid(&c, &h, &grid, &|| {});
            let mesh = drop_cutter_grid(&c, &surface, &grid, &|| {});
            for (k, (a, b)) in fast.iter().zip(&mesh).enumerate() {
                let (x, y) = (grid.x(k % grid.nx), grid.y(k / grid.nx));
                match (a, b) {
                    (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "{c} at ({x}, {y}): {a} vs {b}"),
                    _ => assert_eq!(a, b, "{c} at ({x}, {y})"),
                }
                if k % 7 == 0 {
                    let brute = drop_cutter(&c, &tris[..], x, y);
                    assert_eq!(brute.is_some(), b.is_some(), "{c} at ({x}, {y})");
                    if let (Some(p), Some(q)) = (brute, b) {
                        assert!((p - q).abs() < 1e-12, "{c} at ({x}, {y}): {p} vs {q}");
                    }
                }
            }
            assert!(fast.iter().any(|z| z.is_none()) && fast.iter().any(|z| z.is_some()));
        }
    }
}

/// Whole rows at once (the ball's piece-by-piece placement) against a
/// query of its own at every point: smooth, noisy, stepped and tiny grids;
/// balls larger and smaller than a cell; rows along X and Y running past
/// every border, at node lines and between them; the other shapes through
/// their point-by-point fallback.
#[test]
fn rows_at_once_are_the_same_as_one_query_per_point() {
    let mut rng = Rng(7);
    let noise: Vec<f64> = (0..23 * 17).map(|_| rng.next()).collect();
    let wavy = Heightfield::from_fn(-3.0, 1.0, 0.4, 31, 23, |x, y| (x * 0.7).sin() + (y * 1.3).cos() * 0.8).unwrap();
    let noisy = Heightfield::new(0.5, -1.0, 0.3, 23, 17, noise.iter().map(|v| 2.0 * v).collect()).unwrap();
    // Flat-topped blocks with vertical-ish steps, a lone spike and a pit.
    let stepped = Heightfield::from_fn(0.0, 0.0, 0.1, 60, 45, |x, y| {
        let block = if (1.0..3.5).contains(&x) && (0.8..2.0).contains(&y) { 2.0 } else { 0.0 };
        let spike = if (x - 4.5).abs() < 0.05 && (y - 3.0).abs() < 0.05 { 1.0 } else { 0.0 };
        let pit = if (x - 5.0).hypot(y - 1.0) < 0.3 { -0.8 } else { 0.0 };
        block + spike + pit + 0.1 * (y * 2.0).sin()
    })
    .unwrap();
    let tiny = Heightfield::new(1.0, 1.0, 1.0, 2, 2, vec![0.0, 1.0, 0.5, -0.5]).unwrap();
    // Wide flat and tilted planes (whole blocks of cells in one plane, drawn
    // at once), a curved step between them and a post.
    let planes = Heightfield::from_fn(0.0, 0.0, 0.125, 70, 60, |x, y| {
        let post = if (x - 1.5).abs() < 0.2 && (y - 5.0).abs() < 0.2 { 0.75 } else { 0.0 };
        post + if x < 3.0 {
            1.0
        } else if x < 4.0 {
            1.0 + (x - 3.0) * (x - 3.0)
        } else {
            2.0 + 0.25 * (x - 4.0) + 0.5 * y
        }
    })
    .unwrap();
    let cutters: Vec<Cutter> =
        ["ball:3", "ball:0.25", "ball:1", "flat:1", "bull:2,0.5"].iter().map(|s| cutter(s)).collect();
    let (mut total, mut equator) = (0, 0);
    for (name, h) in [("wavy", wavy), ("noisy", noisy), ("stepped", stepped), ("tiny", tiny), ("planes", planes)] {
        let [x0, y0, x1, y1] = h.xy_box();
        for c in &cutters {
            let reach = c.radius() + 0.3;
            for along_y in [false, true] {
                let (u0, u1, v0, v1) = if along_y { (y0, y1, x0, x1) } else { (x0, x1, y0, y1) };
                let mut rows: Vec<(f64, Vec<f64>)> = Vec::new();
                let mut v = v0 - reach;
                while v < v1 + reach {
                    let mut us: Vec<f64> = (0..80).map(|_| u0 - reach + rng.next() * (u1 - u0 + 2.0 * reach)).collect();
                    // Node positions and a regular run, as a raster asks.
                    us.extend((0..=40).map(|k| u0 + (u1 - u0) * k as f64 / 40.0));
                    us.sort_by(f64::total_cmp);
                    rows.push((v, us));
                    // Every third row on a node line.
                    v += if rows.len().is_multiple_of(3) { h.step() } else { 0.37 * h.step() + 0.05 };
                    if rows.len().is_multiple_of(3) {
                        v = v0 + ((v - v0) / h.step()).round() * h.step();
                    }
                }
                let asked: Vec<(f64, &[f64])> = rows.iter().map(|(v, us)| (*v, &us[..])).collect();
                let got = drop_cutter_rows(c, &h, along_y, &asked);
                for ((v, us), zs) in rows.iter().zip(&got) {
                    assert_eq!(us.len(), zs.len());
                    for (&u, &z) in us.iter().zip(zs) {
                        let (x, y) = if along_y { (*v, u) } else { (u, *v) };
                        let one = drop_cutter(c, &h, x, y);
                        total += 1;
                        match (z, one) {
                            (Some(a), Some(b)) if (a - b).abs() < 1e-9 => {}
                            // A ball touching at its equator: a rounding of the
                            // distance by 1e-16 moves the tip by √(2R·1e-16).
                            (Some(a), Some(b)) if (a - b).abs() < 1e-6 * c.radius() => equator += 1,
                            _ => assert_eq!(z, one, "{name} {c} along_y {along_y} at ({x}, {y})"),
                        }
                    }
                }
            }
        }
    }
    assert!(total > 100_000 && equator * 1000 < total, "{equator} of {total} points differ by more than 1e-9 mm");
}

#[test]
fn bad_input_gives_none_or_finite_numbers_never_a_panic() {
    let c = cutter("ball:6");
    // Degenerate triangles: collinear corners, a repeated corner, a point.
    let junk = [
        tri([0., 0., 0.], [1., 1., 1.], [2., 2., 2.]),
        tri([0., 0., 5.], [0., 0., 5.], [1., 0., 0.]),
        tri([1., 1., 1.], [1., 1., 1.], [1., 1., 1.]),
    ];
    assert_eq!(drop_cutter(&c, &junk[..], 0.0, 0.0), Some(5.0));
    let mesh = Mesh::from_triangles(junk.iter().copied());
    assert_eq!((mesh.len(), mesh.skipped()), (0, 3));
    // An empty mesh: nothing under the cutter anywhere.
    let empty = MeshSurface::new(mesh);
    assert_eq!(drop_cutter(&c, &empty, 0.0, 0.0), None);
    let grid = Grid::new(0.0, 0.0, 2.0, 2.0, 0.5).unwrap();
    assert!(drop_cutter_grid(&c, &empty, &grid, &|| {}).iter().all(|z| z.is_none()));
    // A grid beside the mesh: None, not a made-up z.
    let surface = MeshSurface::new(Mesh::from_triangles(plane(0.2)));
    let beside = Grid::new(30.0, 30.0, 40.0, 35.0, 1.0).unwrap();
    assert!(drop_cutter_grid(&c, &surface, &beside, &|| {}).iter().all(|z| z.is_none()));
    assert_eq!(drop_cutter(&c, &surface, f64::NAN, 0.0), None);
    assert_eq!(drop_cutter(&c, &surface, 0.0, f64::INFINITY), None);
    // Tiny and huge coordinates stay finite.
    let far = [tri([1e6, 1e6, 1e-9], [1e6 + 1e-3, 1e6, 0.0], [1e6, 1e6 + 1e-3, 0.0])];
    for c in shapes() {
        let z = drop_cutter(&c, &far[..], 1e6, 1e6).unwrap();
        assert!(z.is_finite() && z <= 1e-9, "{c}: {z}");
    }
}
