//! The worn tool corrected on flat, inclined and cylindrical surfaces,
//! checked by an oracle that knows the true surfaces and walks the
//! measured tool's whole surface of revolution.

use kezuri_correct::wear::{correct, Nominal, Options, Surface};
use kezuri_correct::ErrorKind;
use kezuri_geom::{Mesh, ToolProfile, Triangle, Vec3};

const R: f64 = 0.5;
const RUNOUT: f64 = 0.010;
const TIP_WEAR: f64 = 0.002;

/// The worn band about the 45° point of the ball, 12 µm deep, wide enough
/// (σ 0.1 mm along the axis) that the wear is what the neighbouring
/// edge shows too: the first-order check below holds.
fn wear(z: f64) -> f64 {
    0.012 * (-((z - R * (1.0 - std::f64::consts::FRAC_1_SQRT_2)) / 0.1).powi(2)).exp()
}

/// The measured profile of a 1 mm ball end mill: 10 µm runout, the band,
/// the tip worn back 2 µm; 0.71 µm rows.
fn worn() -> ToolProfile {
    let n = (0.8 / 0.00071) as usize;
    let z: Vec<f64> = (0..n).map(|k| TIP_WEAR + 0.00071 * k as f64).collect();
    let r = z.iter().map(|&z| if z < R { (z * (2.0 * R - z)).sqrt() } else { R } + RUNOUT - wear(z)).collect();
    ToolProfile::new(z, r).unwrap()
}

/// A true surface: its signed height of a point above it (along its
/// normal) and a mesh of it.
enum Truth {
    /// z = x·tan(angle).
    Plane(f64),
    /// The top of a cylinder of this radius, axis along Y at z = −radius.
    Cylinder(f64),
}

impl Truth {
    fn distance(&self, p: Vec3) -> f64 {
        match *self {
            Truth::Plane(a) => p.z * a.cos() - p.x * a.sin(),
            Truth::Cylinder(rc) => p.x.hypot(p.z + rc) - rc,
        }
    }

    fn normal_at(&self, x: f64) -> Vec3 {
        match *self {
            Truth::Plane(a) => Vec3::new(-a.sin(), 0.0, a.cos()),
            Truth::Cylinder(rc) => {
                let t = (x / rc).asin();
                Vec3::new(t.sin(), 0.0, t.cos())
            }
        }
    }

    fn point_at(&self, x: f64) -> Vec3 {
        match *self {
            Truth::Plane(a) => Vec3::new(x, 0.0, x * a.tan()),
            Truth::Cylinder(rc) => Vec3::new(x, 0.0, (rc * rc - x * x).sqrt() - rc),
        }
    }

    fn mesh(&self) -> Mesh {
        let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, d)];
        match *self {
            Truth::Plane(_) => {
                let p = |x: f64, y: f64| Vec3::new(x, y, self.point_at(x).z);
                Mesh::from_triangles(quad(p(-20.0, -20.0), p(20.0, -20.0), p(20.0, 20.0), p(-20.0, 20.0)))
            }
            Truth::Cylinder(rc) => {
                let n = 1440;
                let at = |k: usize, y: f64| {
                    let t = -1.2 + 2.4 * k as f64 / n as f64;
                    Vec3::new(rc * t.sin(), y, rc * t.cos() - rc)
                };
                Mesh::from_triangles(
                    (0..n).flat_map(|k| quad(at(k, -20.0), at(k + 1, -20.0), at(k + 1, 20.0), at(k, 20.0))),
                )
            }
        }
    }
}

/// The least height of the measured tool at `tip` (axis `a`) above the
/// true surface: every profile sample, every degree around the axis, then
/// every 0.005° within a degree of the best.
fn oracle_gap(truth: &Truth, profile: &ToolProfile, tip: Vec3, a: Vec3) -> f64 {
    let u = if a.x.abs() < 0.9 { Vec3::new(1.0, 0.0, 0.0) } else { Vec3::new(0.0, 0.0, 1.0) };
    let u = u - a * u.dot(a);
    let u = u * (1.0 / u.norm());
    let v = a.cross(u);
    let least_at = |deg: f64| {
        let t = deg.to_radians();
        let side = u * t.cos() + v * t.sin();
        profile
            .z()
            .iter()
            .zip(profile.radius())
            .map(|(&z, &r)| truth.distance(tip + a * z + side * r))
            .fold(f64::INFINITY, f64::min)
    };
    let (best, _) =
        (0..360)
            .map(|k| (k as f64, least_at(k as f64)))
            .fold((0.0, f64::INFINITY), |b, p| if p.1 < b.1 { p } else { b });
    (0..=400).map(|k| least_at(best - 1.0 + 0.005 * k as f64)).fold(f64::INFINITY, f64::min)
}

#[test]
fn the_worn_tool_touches_the_target_within_a_tenth_of_a_micrometre() {
    let profile = worn();
    let nominal = Nominal { radius: R, corner: R };
    let options = Options { reach: 0.05 };
    let feed = Vec3::new(0.0, 1.0, 0.0);
    let mut worst = 0.0f64;
    for (truth, tilt_deg) in [
        (Truth::Plane(0.0), 0.0),
        (Truth::Plane(0.0), 30.0),
        (Truth::Plane(45f64.to_radians()), 0.0),
        (Truth::Plane(30f64.to_radians()), -20.0),
        (Truth::Cylinder(5.0), 0.0),
        (Truth::Cylinder(5.0), 15.0),
    ] {
        let mesh = truth.mesh();
        let surface = Surface::new(&mesh);
        let b = f64::to_radians(tilt_deg);
        let axis = Vec3::new(b.sin(), 0.0, b.cos());
        for x in [-2.5, -1.0, 0.0, 0.7, 2.0, 3.3] {
            // The nominal ball touches the true surface at x.
            let tip = truth.point_at(x) + truth.normal_at(x) * R - axis * R;
            let c = correct(&surface, nominal, &profile, tip, axis, Some(feed), &options).unwrap().unwrap();
            let cos = truth.normal_at(x).dot(axis);
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            let contact = R * (1.0 - cos);
            // Uncorrected: the error is the wear less the runout, seen along
            // the normal (the tip's wear on a level floor).
            let before = oracle_gap(&truth, &profile, tip, axis);
            let radial = RUNOUT - wear(contact);
            let expected = if sin < 1e-9 { TIP_WEAR } else { -radial * sin };
            assert!((before - expected).abs() < 2e-4 + 0.05 * expected.abs(), "before {before}, expected {expected}");
            // The mesh is the cylinder to 12 nm.
            assert!((before - c.worn_gap).abs() < 5e-5, "{before} vs {}", c.worn_gap);
            let moved = tip + Vec3::new(c.shift[0], c.shift[1], c.shift[2]);
            let after = oracle_gap(&truth, &profile, moved, axis);
            assert!(after.abs() < 1e-4, "after {after} at x {x}, tilt {tilt_deg}");
            assert!(c.shift[1].abs() < 1e-12, "the shift is normal to the feed: {:?}", c.shift);
            assert!(c.residual.abs() < 1e-9);
            worst = worst.max(after.abs());
        }
    }
    eprintln!("worst gap after correction: {:.2e} mm", worst);
}

#[test]
fn plunges_move_along_the_tool_axis_and_far_points_are_skipped() {
    let profile = worn();
    let nominal = Nominal { radius: R, corner: R };
    let options = Options { reach: 0.05 };
    let truth = Truth::Plane(0.0);
    let mesh = truth.mesh();
    let surface = Surface::new(&mesh);
    let up = Vec3::new(0.0, 0.0, 1.0);
    let c =
        correct(&surface, nominal, &profile, Vec3::new(1.0, 2.0, 0.0), up, Some(up * -1.0), &options).unwrap().unwrap();
    assert!(c.along_axis);
    assert!((c.shift[2] + TIP_WEAR).abs() < 1e-12 && c.shift[0] == 0.0, "{:?}", c.shift);
    let far = correct(&surface, nominal, &profile, Vec3::new(1.0, 2.0, 3.0), up, None, &options).unwrap();
    assert!(matches!(far, Err(kezuri_correct::wear::Skip::Far(_))), "{far:?}");
    // Fed square into a vertical wall with the tool along it: skipped, not
    // moved a long way along the wall.
    let w = |y: f64, z: f64| Vec3::new(0.0, y, z);
    let mesh = Mesh::from_triangles([
        Triangle::new(w(-20.0, -20.0), w(-20.0, 20.0), w(20.0, 20.0)),
        Triangle::new(w(-20.0, -20.0), w(20.0, 20.0), w(20.0, -20.0)),
    ]);
    let surface = Surface::new(&mesh);
    let tip = Vec3::new(-R, 0.0, 1.0);
    let into = Some(Vec3::new(1.0, 0.0, 0.0));
    let c = correct(&surface, nominal, &profile, tip, up, into, &options).unwrap();
    assert!(matches!(c, Err(kezuri_correct::wear::Skip::NoDirection(_))), "{c:?}");
    // A profile shorter than the part of the tool that cuts a wall.
    let short = ToolProfile::new(vec![0.0, 0.1], vec![0.0, 0.3]).unwrap();
    let wall = Truth::Plane(80f64.to_radians());
    let mesh = wall.mesh();
    let surface = Surface::new(&mesh);
    let tip = wall.point_at(0.0) + wall.normal_at(0.0) * R - up * R;
    let e = correct(&surface, nominal, &short, tip, up, Some(Vec3::new(0.0, 1.0, 0.0)), &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::ProfileTooShort, "{e}");
    assert!(e.message.contains("measure more of the tool"), "{e}");
}
