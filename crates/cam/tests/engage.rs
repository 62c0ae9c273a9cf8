//! The chip of one tooth and its sections (issue 17), checked against
//! estimates written here from the solid's definition, not from the
//! module's intervals.

use kezuri_cam::engage::{sweep, Chip, Cut, Engagement, Step};
use kezuri_cam::{scallop, Cutter, ErrorKind};
use std::f64::consts::TAU;

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn paper(angle: f64, step: Step, cut: Cut, pick_feed: f64) -> Engagement {
    Engagement {
        cutter: "oval:16,24".parse().unwrap(),
        flutes: 2,
        helix: deg(30.0),
        angle: deg(angle),
        depth: 0.8,
        pick_feed,
        feed_per_tooth: 0.16,
        step,
        cut,
    }
}

/// The chip solid from its definition, with the cutter's `height` (not its
/// inverse): inside this body, outside the body one tooth behind and the
/// previous pass's swept body, below the stock plane.
struct Solid {
    cutter: Cutter,
    behind: f64,
    y2: f64,
    z2: f64,
    slope: f64,
    stock: f64,
    reference: f64,
    twist: f64,
}

impl Solid {
    fn new(e: &Engagement, feed: f64) -> Solid {
        let c = e.cutter;
        let r = c.radius();
        let slope = e.angle.tan();
        // The finished plane touches the body: min over r of height − slope·r.
        let finished = (0..=200_000)
            .map(|i| c.height(r * i as f64 / 200_000.0) - slope * r * i as f64 / 200_000.0)
            .fold(f64::MAX, f64::min);
        let up = if e.step == Step::Down { 1.0 } else { -1.0 };
        Solid {
            cutter: c,
            behind: -feed * e.feed_per_tooth,
            y2: up * e.pick_feed * e.angle.cos(),
            z2: up * e.pick_feed * e.angle.sin(),
            slope,
            stock: finished + e.depth / e.angle.cos(),
            reference: c.height(r),
            twist: e.helix.tan() / r,
        }
    }

    fn in_body(&self, x: f64, y: f64, z: f64) -> bool {
        let r = x.hypot(y);
        r <= self.cutter.radius() && z >= self.cutter.height(r)
    }

    fn contains(&self, x: f64, y: f64, z: f64) -> bool {
        let swept =
            (y - self.y2).abs() <= self.cutter.radius() && z - self.z2 >= self.cutter.height((y - self.y2).abs());
        self.in_body(x, y, z) && !self.in_body(x - self.behind, y, z) && !swept && z <= self.slope * y + self.stock
    }

    /// The rake face's point at (ρ, z) at tool angle θ.
    fn rake(&self, theta: f64, rho: f64, z: f64) -> [f64; 3] {
        let psi = theta + self.twist * (self.reference - z);
        [rho * psi.sin(), rho * psi.cos(), z]
    }
}

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Monte-Carlo area and centroid of the section at θ, with its standard
/// error: a coarse grid over `[0, R] × [0, top]` finds the box (widened by
/// 30 of its cells), then
/// uniform samples in it weighted by `√(1 + k²ρ²)`.
fn monte_carlo(solid: &Solid, theta: f64, samples: usize, stream: u64) -> (f64, f64, [f64; 3]) {
    let r = solid.cutter.radius();
    let top = solid.stock + solid.slope * r;
    let n = 400;
    let (mut rlo, mut rhi, mut zlo, mut zhi) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for i in 0..n {
        for j in 0..n {
            let rho = r * (i as f64 + 0.5) / n as f64;
            let z = top * (j as f64 + 0.5) / n as f64;
            let p = solid.rake(theta, rho, z);
            if solid.contains(p[0], p[1], p[2]) {
                rlo = rlo.min(rho);
                rhi = rhi.max(rho);
                zlo = zlo.min(z);
                zhi = zhi.max(z);
            }
        }
    }
    assert!(rhi > rlo, "the coarse grid found the section");
    let pad = |lo: f64, hi: f64, cell: f64, max: f64| ((lo - 30.0 * cell).max(0.0), (hi + 30.0 * cell).min(max));
    let (rlo, rhi) = pad(rlo, rhi, r / n as f64, r);
    let (zlo, zhi) = pad(zlo, zhi, top / n as f64, top);
    let boxed = (rhi - rlo) * (zhi - zlo);
    let mut rng = Lcg(stream);
    let (mut s, mut s2) = (0.0, 0.0);
    let mut m = [0.0; 3];
    for _ in 0..samples {
        let rho = rlo + (rhi - rlo) * rng.next();
        let z = zlo + (zhi - zlo) * rng.next();
        let p = solid.rake(theta, rho, z);
        if solid.contains(p[0], p[1], p[2]) {
            let w = (1.0 + (solid.twist * rho).powi(2)).sqrt();
            s += w;
            s2 += w * w;
            for k in 0..3 {
                m[k] += w * p[k];
            }
        }
    }
    let n = samples as f64;
    let mean = s / n;
    let var = (s2 / n - mean * mean).max(0.0);
    (boxed * mean, boxed * (var / n).sqrt(), [m[0] / s, m[1] / s, m[2] / s])
}

/// The sections agree with a Monte-Carlo estimate from the solid's
/// definition within 4.5 standard errors, for the oval with a helix and
/// for other shapes.
#[test]
fn sections_agree_with_monte_carlo() {
    let mut cases = vec![paper(45.0, Step::Up, Cut::Down, 0.8), paper(15.0, Step::Down, Cut::Up, 0.8)];
    for (tool, angle) in [("ball:10", 30.0), ("bull:10,2", 20.0), ("v:12,90", 10.0), ("flat:10", 0.0)] {
        let mut e = paper(angle, Step::Down, Cut::Down, 1.0);
        e.cutter = tool.parse().unwrap();
        e.depth = 0.6;
        cases.push(e);
    }
    for (n, e) in cases.iter().enumerate() {
        let chip = Chip::new(e).unwrap();
        let solid = Solid::new(e, chip.feed_direction());
        let s = sweep(&chip, 72);
        // The largest section and one on its flank.
        let best = (0..72).max_by(|&a, &b| s.sections[a].area.total_cmp(&s.sections[b].area)).unwrap();
        // The flank: two steps (10°) from the largest, on the side where
        // the tooth is still in the chip.
        let flank = [best + 2, best + 70]
            .into_iter()
            .max_by(|&a, &b| s.sections[a % 72].area.total_cmp(&s.sections[b % 72].area))
            .unwrap();
        for j in [best, flank] {
            let theta = s.theta[j % 72];
            let exact = chip.section(theta);
            let (mc, err, g) = monte_carlo(&solid, theta, 2_000_000, 17 + n as u64 + j as u64);
            assert!(exact.area > 0.0, "case {n} θ={}", theta.to_degrees());
            println!(
                "{} α={:.0}° θ={:.0}°: A {:.6} mm², Monte-Carlo {mc:.6} ± {err:.6}",
                e.cutter,
                e.angle.to_degrees(),
                theta.to_degrees(),
                exact.area
            );
            assert!(
                (exact.area - mc).abs() <= 4.5 * err + 1e-12,
                "case {n} ({}) θ={:.1}°: exact {} vs Monte-Carlo {mc} ± {err}",
                e.cutter,
                theta.to_degrees(),
                exact.area
            );
            for k in 0..3 {
                assert!(
                    (exact.centroid[k] - g[k]).abs() < 0.02,
                    "case {n} centroid {k}: {:?} vs {g:?}",
                    exact.centroid
                );
            }
        }
    }
}

/// A flat end mill in side milling (α = 0, helix 0): the area is close to
/// the classic `R_d·S_z·sin φ` (φ from the feed's normal), too high by the
/// known second-order term `R_d·S_z²·cos²φ/(2R)`, and equal to the exact
/// radial chord between the two circles times the depth.
#[test]
fn flat_side_milling_is_the_classic_chip() {
    let (r, depth, sz) = (5.0, 3.0, 0.1);
    let e = Engagement {
        cutter: "flat:10".parse().unwrap(),
        flutes: 2,
        helix: 0.0,
        angle: 0.0,
        depth,
        pick_feed: 2.0,
        feed_per_tooth: sz,
        step: Step::Down,
        cut: Cut::Down,
    };
    let chip = Chip::new(&e).unwrap();
    // Step-down at α = 0: the chip is on −Y, where a tooth turning
    // clockwise moves toward −X; climbing, it meets the stock against the
    // tool's travel, so a down-cut feeds toward +X.
    assert!(chip.chip_side() < 0.0);
    assert_eq!(chip.feed_direction(), 1.0);
    // Entering at the free surface, at its thickest, and leaving thin.
    assert!(chip.section(deg(130.0)).area > 3.0 * chip.section(deg(175.0)).area);
    for psi in [165.0f64, 155.0, 145.0, 135.0] {
        let s = chip.section(deg(psi));
        let (sin, cos) = deg(psi).sin_cos();
        let classic = depth * sz * sin.abs();
        // Exact: from the circle about the axis behind (at −S_z on X) to R.
        let inner = -sz * sin.abs() + (r * r - sz * sz * cos * cos).sqrt();
        let exact = depth * (r - inner);
        assert!((s.area - exact).abs() < 1e-12, "ψ={psi}: {} vs {exact}", s.area);
        let second = depth * sz * sz * cos * cos / (2.0 * r);
        assert!(s.area > classic && s.area - classic <= second * 1.01, "ψ={psi}: {} vs classic {classic}", s.area);
        assert!((s.area - classic - second).abs() <= 1e-3 * second, "ψ={psi}");
        // Straight flute: E_d is the radial moment.
        assert!((s.ed - chip.radial_moment(deg(psi))).abs() < 1e-12);
    }
    // Past the pick feed's edge the previous pass has taken everything.
    assert_eq!(chip.section(deg(120.0)).area, 0.0);
}

/// `∫ M(θ) dθ` over a revolution is the chip's volume (from the
/// cross-section formula, an independent path); with helix 0, `M = E_d`.
#[test]
fn radial_moment_integrates_to_the_volume() {
    for (e, tol) in [
        // The trapezoidal rule over 7,200 angles, kinks and all, is good to
        // about 1e-7: the section jumps where the tooth enters the chip at
        // its thickest (down-cut) or leaves it there (up-cut), and more with
        // a straight flute.
        (paper(45.0, Step::Up, Cut::Down, 0.8), 1e-7),
        (paper(30.0, Step::Down, Cut::Up, 0.8), 1e-7),
        (
            {
                let mut e = paper(20.0, Step::Down, Cut::Down, 1.0);
                e.cutter = "bull:10,2".parse().unwrap();
                e.helix = 0.0;
                e
            },
            3e-7,
        ),
    ] {
        let chip = Chip::new(&e).unwrap();
        let n = 7200;
        let h = TAU / n as f64;
        let total: f64 = (0..n).map(|j| chip.radial_moment(j as f64 * h)).sum::<f64>() * h;
        let v = chip.volume();
        println!(
            "{} α={:.0}°: ∫M dθ {total:.10} mm³, volume {v:.10} mm³, S_z·cross-section/volume − 1 = {:.5}",
            e.cutter,
            e.angle.to_degrees(),
            e.feed_per_tooth * chip.cross_section_area() / v - 1.0
        );
        assert!((total - v).abs() <= tol * v, "{}: ∫M dθ = {total}, volume {v}", e.cutter);
        if e.helix == 0.0 {
            for j in (0..n).step_by(37) {
                let s = chip.section(j as f64 * h);
                assert!((s.ed - chip.radial_moment(j as f64 * h)).abs() <= 1e-12 * (1.0 + s.ed));
            }
        }
        // S_z × the cross-section's area is slightly too high.
        let over = e.feed_per_tooth * chip.cross_section_area() / v - 1.0;
        assert!(over > 0.0 && over < 0.01, "{}: {over}", e.cutter);
    }
    let chip = Chip::new(&paper(45.0, Step::Up, Cut::Down, 0.8)).unwrap();
    let over = 0.16 * chip.cross_section_area() / chip.volume() - 1.0;
    assert!(over > 0.0015 && over < 0.0025, "the paper's case: {over}");
}

/// The quadrature's error: the sections do not move when the tolerance
/// would be met many times over (compared by halving the height range's
/// pieces: two chips equal but for where the range is cut).
#[test]
fn step_up_and_down_are_mirror_images_at_zero_angle() {
    let chip = Chip::new(&paper(45.0, Step::Up, Cut::Down, 0.8)).unwrap();
    let s = sweep(&chip, 360);
    // Symmetry check: step-up and step-down at α = 0 are the same chip
    // turned half a revolution.
    let up = Chip::new(&paper(0.0, Step::Up, Cut::Down, 0.8)).unwrap();
    let down = Chip::new(&paper(0.0, Step::Down, Cut::Down, 0.8)).unwrap();
    for j in 0..72 {
        let t = j as f64 * TAU / 72.0;
        let (a, b) = (up.section(t).area, down.section(t + std::f64::consts::PI).area);
        assert!((a - b).abs() <= 1e-10 * s.area_max, "θ={}: {a} vs {b}", t.to_degrees());
    }
}

/// The paper's grid: α = 0…75° × step up/down × down/up-cut, at
/// `P_f = 0.8 mm` and at the pick feed for a 10 µm cusp; its conclusion (2)
/// where the exact model bears it out, and where it does not.
#[test]
fn paper_grid() {
    let angles = [0.0, 15.0, 30.0, 45.0, 60.0, 75.0];
    let combos = [(Step::Up, Cut::Down), (Step::Down, Cut::Down), (Step::Up, Cut::Up), (Step::Down, Cut::Up)];
    let egg: Cutter = "oval:16,24".parse().unwrap();
    for controlled in [false, true] {
        println!("| P_f | α | pick feed mm | A_max up/down-cut | A_max down/down-cut | A_max up/up-cut | A_max down/up-cut | E_dmax up/down | E_dmax down/down | E_dmax up/up | E_dmax down/up |");
        let mut ed = vec![[0.0; 4]; angles.len()];
        let mut amax = vec![[0.0; 4]; angles.len()];
        for (i, &a) in angles.iter().enumerate() {
            let pf = if controlled { scallop::pick_feed(&egg, deg(a), 0.010).unwrap().pick_feed } else { 0.8 };
            for (c, &(step, cut)) in combos.iter().enumerate() {
                let s = sweep(&Chip::new(&paper(a, step, cut, pf)).unwrap(), 360);
                ed[i][c] = s.ed_max;
                amax[i][c] = s.area_max;
            }
            let f = |v: [f64; 4]| v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(" | ");
            println!(
                "| {} | {a} | {pf:.3} | {} | {} |",
                if controlled { "controlled" } else { "0.8" },
                f(amax[i]),
                f(ed[i])
            );
        }
        for (c, (step, cut)) in combos.iter().enumerate() {
            println!(
                "E_dmax ratio {step:?}/{cut:?}: 60°/45° {:.2}, 75°/45° {:.2}",
                ed[4][c] / ed[3][c],
                ed[5][c] / ed[3][c]
            );
        }
        // Step-up and step-down are the same chip turned half a revolution
        // at α = 0. Conclusion (2): step-up's A_max is the larger up to
        // 60° with down-cut, both pick feeds; with up-cut up to 45°, and at
        // 60° the exact model finds step-down's the larger (docs/engage.md).
        for c in [0, 2] {
            assert!((amax[0][c] - amax[0][c + 1]).abs() <= 1e-9 * amax[0][c]);
        }
        for i in 1..=4 {
            assert!(amax[i][0] > amax[i][1], "down-cut, α={}: {:?}", angles[i], amax[i]);
        }
        for i in 1..=3 {
            assert!(amax[i][2] > amax[i][3], "up-cut, α={}: {:?}", angles[i], amax[i]);
        }
        assert!(amax[4][3] > amax[4][2], "up-cut at 60°: {:?}", amax[4]);
    }
}

/// Bad input is refused with the figures.
#[test]
fn bad_input_is_refused() {
    let good = paper(45.0, Step::Up, Cut::Down, 0.8);
    assert!(Chip::new(&good).is_ok());
    let check = |f: &dyn Fn(&mut Engagement), kind: ErrorKind, want: &str| {
        let mut e = good;
        f(&mut e);
        let err: kezuri_cam::Error = Chip::new(&e).unwrap_err();
        assert_eq!(err.kind, kind, "{err}");
        let text = err.to_string();
        assert!(text.contains(want), "{text}");
    };
    check(&|e| e.pick_feed = 30.0, ErrorKind::NoOverlap, "wider than the cutter");
    check(&|e| e.pick_feed = 0.0, ErrorKind::PickFeed, "pick feed must be");
    check(&|e| e.depth = 0.0, ErrorKind::Depth, "depth of cut must be");
    check(&|e| e.depth = -1.0, ErrorKind::Depth, "got -1");
    check(&|e| e.depth = f64::NAN, ErrorKind::Depth, "depth of cut must be");
    check(&|e| e.angle = deg(90.0), ErrorKind::Angle, "got 90");
    check(&|e| e.angle = deg(-5.0), ErrorKind::Angle, "plane's angle");
    check(&|e| e.helix = deg(90.0), ErrorKind::Helix, "helix angle");
    check(&|e| e.helix = f64::INFINITY, ErrorKind::Helix, "helix angle");
    check(&|e| e.flutes = 0, ErrorKind::Flutes, "at least 1 flute");
    check(&|e| e.feed_per_tooth = 0.0, ErrorKind::FeedPerTooth, "feed per tooth must be");
    check(&|e| e.feed_per_tooth = 16.0, ErrorKind::FeedPerToothTooWide, "not less than the cutter's diameter");
    check(
        &|e| {
            e.cutter = "flat:6".parse().unwrap();
            e.angle = 0.0;
            e.depth = 10.0;
        },
        ErrorKind::Reach,
        "cannot reach the depth",
    );
}

/// The quadrature's error, measured against the same chip integrated with
/// a thousandth of the tolerance and four times the samples.
#[test]
fn sections_are_exact_to_the_tolerance() {
    for (a, step, cut) in [
        (45.0, Step::Up, Cut::Down),
        (15.0, Step::Down, Cut::Down),
        (75.0, Step::Down, Cut::Up),
        (0.0, Step::Up, Cut::Up),
    ] {
        let chip = Chip::new(&paper(a, step, cut, 0.8)).unwrap();
        let fine = chip.refined();
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        for j in 0..360 {
            let t = j as f64 * TAU / 360.0;
            let (s, f) = (chip.section(t), fine.section(t));
            worst.0 = worst.0.max((s.area - f.area).abs());
            worst.1 = worst.1.max((s.ed - f.ed).abs());
            worst.2 = worst.2.max(f.area);
        }
        println!(
            "α={a} {step:?}/{cut:?}: largest error of A {:.2e} mm², of E_d {:.2e} mm³ (A_max {:.4})",
            worst.0, worst.1, worst.2
        );
        assert!(worst.0 <= 1e-9 * worst.2 && worst.1 <= 1e-9 * worst.2, "{worst:?}");
    }
}
