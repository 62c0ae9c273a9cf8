//! What the tests of a lathe's tool nose radius compensation share: a lathe
//! with X a radius in the plain Fanuc dialect, the OD and bore profiles and
//! their hand-derived nose centre points, and the measure of what a nose
//! swept along a centre path cuts.

use std::collections::BTreeMap;

use kezuri_geom::{MoveKind, Toolpath};
use kezuri_nc::interp::{GCodeSystem, Lathe, Nose, Outcome, Settings, XMode};

/// √2.
pub const S2: f64 = std::f64::consts::SQRT_2;

/// A lathe with X read as a radius, the plain Fanuc dialect (a lathe's
/// codes, system A: `G98` feed per minute, `T0101` tool 1 with offset 1),
/// `nose` as tool `tool`'s.
pub fn lathe(tool: u32, nose: Nose) -> Settings {
    Settings {
        lathe: Some(Lathe { x: XMode::Radius, system: GCodeSystem::A }),
        noses: BTreeMap::from([(tool, nose)]),
        ..Settings::default()
    }
}

/// Runs `text` as `t.nc`, which must complete without an error.
pub fn run(text: &str, settings: &Settings) -> Outcome {
    super::run("t.nc", text, settings).completed()
}

/// The (X, Z) end of each move.
pub fn ends(path: &Toolpath) -> Vec<(f64, f64)> {
    path.moves.iter().map(|m| (m.end.x, m.end.z)).collect()
}

/// Asserts the (X, Z) ends of the moves are `want`, within 1e-6 mm.
pub fn assert_ends(what: &str, path: &Toolpath, want: &[(f64, f64)]) {
    let got = ends(path);
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g.0 - w.0).abs() < 1e-6 && (g.1 - w.1).abs() < 1e-6, "{what}, move {k}: (X, Z) {g:?}, want {w:?}");
    }
}

/// An OD profile toward the chuck, X a radius: start-up down onto the end
/// face (−Z), the face up to X4 (+X), a 45° chamfer to X6 Z−2, the OD X6
/// to Z−10, a concave fillet R3 to the shoulder X9 Z−13 (G02, centre X9
/// Z−10), the shoulder face up to X12, a convex round R2 (G03, centre X12
/// Z−15) onto the OD X14, the OD to Z−20, cancel up to X18.
pub fn od(comp: &str, cancel: &str, tool: u32) -> String {
    format!(
        "G18 G21 G40 G98
T{tool:02}{tool:02}
G00 X20. Z10.
G00 X0. Z3.
{comp} G01 Z0. F100.
X4.
X6. Z-2.
Z-10.
G02 X9. Z-13. I3. K0.
G01 X12.
G03 X14. Z-15. I0. K-2.
G01 Z-20.
{cancel} G00 X18.
M30
"
    )
}

/// The OD profile's nose centre points with G42 and R = 0.8 (they do not
/// depend on the tip: the offset is the nose's). Right of travel in (Z, X)
/// is (dX, −dZ): +X on the OD (−Z), +Z on the faces (+X), (+X, +Z)/√2 on
/// the chamfer (direction (−Z, +X)/√2).
/// - start-up (−Z) then face (+X): an inside corner (the path turns right,
///   toward the nose); the offset lines X = 0.8 and Z = 0.8 meet at
///   (X0.8, Z0.8).
/// - face then chamfer at X4 Z0: outside, obtuse; the chamfer's line is
///   Z + X = 4, offset Z + X = 4 + 0.8·√2; with Z = 0.8: X = 4 + 0.8·(√2 − 1).
/// - chamfer then OD at X6 Z−2: outside, obtuse; X = 6.8 on Z + X = 4 +
///   0.8·√2: Z = −2.8 + 0.8·√2.
/// - OD then fillet: tangent; the OD's offset end X6.8 Z−10. The fillet is
///   concave (the nose inside it): centre path radius 3 − 0.8 round X9
///   Z−10, ending tangent to the shoulder face at X9 Z−12.2.
/// - shoulder face to X12 at Z−12.2; the round is convex: radius 2 + 0.8
///   round X12 Z−15, ending at X14.8 Z−15.
/// - the OD at X14.8 meets the cancel move's offset (up, +X: Z = −20 +
///   0.8) at X14.8 Z−19.2 (inside corner); the cancel move then ends on
///   the programmed point X18 Z−20.
pub const OD_CENTRE: [(f64, f64); 9] = [
    (0.8, 0.8),
    (4.0 + 0.8 * (S2 - 1.0), 0.8),
    (6.8, -2.8 + 0.8 * S2),
    (6.8, -10.0),
    (9.0, -12.2),
    (12.0, -12.2),
    (14.8, -15.0),
    (14.8, -19.2),
    (18.0, -20.0),
];

/// The first two moves, before compensation: the imaginary tip on the
/// programmed points.
pub const OD_APPROACH: [(f64, f64); 2] = [(20.0, 10.0), (0.0, 3.0)];

/// `centre` points moved by the tip vector `v` (X, Z), the last (the
/// cancel move's end, a programmed point) left.
pub fn tips(centre: &[(f64, f64)], v: (f64, f64)) -> Vec<(f64, f64)> {
    let n = centre.len();
    centre.iter().enumerate().map(|(k, &(x, z))| if k + 1 < n { (x + v.0, z + v.1) } else { (x, z) }).collect()
}

/// A bore, X a radius, toward the chuck with a boring bar (G41, the nose
/// below the wall): start-up onto the front face (−Z) at X14, the face
/// down to X10 (−X), a 45° chamfer to X8 Z−2, the bore X8 to Z−10, a
/// concave fillet R3 (G03, centre X5 Z−10) down to the step X5 Z−13, the
/// step down to X4, a convex round R2 (G02, centre X4 Z−15) into the bore
/// X2, the bore to Z−20, cancel down to X0.5.
pub fn bore(comp: &str) -> String {
    format!(
        "G18 G21 G40 G98
T0202
G00 X14. Z3.
{comp} G01 Z0. F100.
X10.
X8. Z-2.
Z-10.
G03 X5. Z-13. I-3. K0.
G01 X4.
G02 X2. Z-15. I0. K-2.
G01 Z-20.
G40 G00 X0.5
M30
"
    )
}

/// The centre (X, Z) and radius of an arc move.
pub fn arc_of(m: &kezuri_geom::Move) -> Option<((f64, f64), f64)> {
    let MoveKind::Arc(a) = m.kind else { return None };
    Some(((a.center[0], a.center[2]), (m.end.x - a.center[0]).hypot(m.end.z - a.center[2])))
}

/// The nose centres along the cutting moves (feeds and arcs) of `path`,
/// every `step` mm and at each end.
pub fn centres(path: &Toolpath, step: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for m in &path.moves {
        let (a, b) = ((m.start.x, m.start.z), (m.end.x, m.end.z));
        match m.kind {
            MoveKind::Feed => {
                let n = ((b.0 - a.0).hypot(b.1 - a.1) / step).ceil().max(1.0) as usize;
                out.extend((0..=n).map(|k| {
                    let t = k as f64 / n as f64;
                    (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
                }));
            }
            MoveKind::Arc(arc) => {
                let c = (arc.center[0], arc.center[2]);
                let r = (a.0 - c.0).hypot(a.1 - c.1);
                // Angles in (Z, X), counter-clockwise from +Z seen from +Y.
                let (t0, t1) = ((a.0 - c.0).atan2(a.1 - c.1), (b.0 - c.0).atan2(b.1 - c.1));
                let mut sweep = t1 - t0;
                if arc.ccw && sweep <= 0.0 {
                    sweep += std::f64::consts::TAU;
                }
                if !arc.ccw && sweep >= 0.0 {
                    sweep -= std::f64::consts::TAU;
                }
                let n = (r * sweep.abs() / step).ceil().max(1.0) as usize;
                out.extend((0..=n).map(|k| {
                    let t = t0 + sweep * k as f64 / n as f64;
                    (c.0 + r * t.sin(), c.1 + r * t.cos())
                }));
            }
            _ => {}
        }
    }
    out
}

/// Where the part's surface is along the line through the contour point
/// `p` (X, Z) in the unit direction `n` toward the tool: the signed
/// distance from `p` to the first point the swept nose (radius `r` round
/// `centres`) removed, coming from the material. Positive: material left
/// standing beyond the contour; negative: cut into it.
pub fn cut_surface(centres: &[(f64, f64)], r: f64, p: (f64, f64), n: (f64, f64)) -> f64 {
    let mut first = f64::INFINITY;
    for &c in centres {
        let d = (c.0 - p.0, c.1 - p.1);
        let along = d.0 * n.0 + d.1 * n.1;
        let across2 = d.0 * d.0 + d.1 * d.1 - along * along;
        if across2 < r * r {
            first = first.min(along - (r * r - across2).sqrt());
        }
    }
    first
}

/// Unit vector at `deg` degrees from +X toward +Z, as (X, Z).
pub fn dir(deg: f64) -> (f64, f64) {
    let a = deg.to_radians();
    (a.cos(), a.sin())
}
