//! The tool microscope, from pictures drawn from a known tool: a 0.3 mm
//! ball end mill with a worn band at 45°, a tip worn back 2 µm and 10 µm
//! runout, 0.71 µm pixels, noise; as one field of view and as four
//! fields overlapping by 100 µm (across) and 70 µm (along the axis).

use kezuri_correct::microscope::{measure_frames, Options};
use kezuri_correct::synthetic::View;
use kezuri_correct::ErrorKind;
use kezuri_geom::{SplitMix64, ToolProfile};

const PIXEL: f64 = 0.00071;
const R: f64 = 0.15;
const RUNOUT: f64 = 0.010;
const TIP_WEAR: f64 = 0.002;

/// The cutting edges' radius at `z`: the ball less a band 12 µm deep
/// about the 45° point.
fn edge_radius(z: f64) -> f64 {
    let ball = if z < R { (z * (2.0 * R - z)).sqrt() } else { R };
    let band = R * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
    ball - 0.012 * (-((z - band) / 0.012).powi(2)).exp()
}

fn view(axis_x: f64, tip_y: f64) -> View {
    let n = 3000;
    let z: Vec<f64> = (0..=n).map(|k| TIP_WEAR + (0.3 - TIP_WEAR) * k as f64 / n as f64).collect();
    let radius = z.iter().map(|&z| edge_radius(z)).collect();
    View {
        edges: ToolProfile::new(z, radius).unwrap(),
        runout_mm: RUNOUT,
        web: 0.8,
        pixel_mm: PIXEL,
        axis_x,
        tip_y,
        levels: (0.08, 0.92),
        noise: 0.01,
    }
}

/// The largest distance, in pixels, from a measured sample to the true
/// swept profile: the flat of the worn tip, then `edge_radius + runout`.
fn worst_miss(profile: &ToolProfile) -> f64 {
    let mut truth: Vec<(f64, f64)> =
        (0..=400).map(|k| (TIP_WEAR, (edge_radius(TIP_WEAR) + RUNOUT) * k as f64 / 400.0)).collect();
    truth.extend((0..=20_000).map(|k| {
        let z = TIP_WEAR + 0.3 * k as f64 / 20_000.0;
        (z, edge_radius(z) + RUNOUT)
    }));
    profile
        .z()
        .iter()
        .zip(profile.radius())
        .map(|(&z, &r)| truth.iter().map(|&(tz, tr)| (z - tz).hypot(r - tr)).fold(f64::INFINITY, f64::min) / PIXEL)
        .fold(0.0, f64::max)
}

#[test]
fn one_field_gives_the_profile_within_a_pixel_and_the_runout() {
    let v = view(280.0, 380.0);
    let mut rng = SplitMix64::new(1);
    let field = (v.frames(48, 560, 420, [0.0, 0.0], &mut rng), [0.0, 0.0]);
    let options = Options { pixel_mm: PIXEL, threshold: None, search: 20, tip_row: Some(380.0) };
    let (m, runout) = measure_frames(&[field], &options).unwrap();
    let miss = worst_miss(&m.profile);
    assert!(miss < 1.0, "worst miss {miss} px");
    // The tip worn back 2 µm shows as a profile starting above z = 0.
    assert!((m.profile.tip() - TIP_WEAR).abs() < PIXEL, "tip at {}", m.profile.tip());
    let runout = runout.unwrap();
    assert!((runout - RUNOUT).abs() < 0.3 * PIXEL, "runout {runout}");
    // Up the shank to the top of the picture.
    assert!(m.profile.top() > 0.26, "{}", m.profile.top());
    eprintln!("one field: worst miss {miss:.3} px, runout {:.5} mm", runout);
}

#[test]
fn four_tiles_are_placed_within_a_third_of_a_pixel() {
    // Tiles 330 × 260 pixels; 141 px = 100 µm across, 99 px = 70 µm along.
    let (w, h) = (330, 260);
    let truth = [[0.0, 0.0], [189.0, 0.0], [0.0, 161.0], [189.0, 161.0]];
    let stage = [[0.0, 0.0], [192.4, -1.7], [-2.2, 163.1], [186.5, 159.6]];
    let v = view(262.0, 390.0);
    let mut rng = SplitMix64::new(2);
    let fields: Vec<_> = truth.iter().zip(stage).map(|(&t, s)| (v.frames(24, w, h, t, &mut rng), s)).collect();
    let options = Options { pixel_mm: PIXEL, threshold: None, search: 20, tip_row: Some(390.0) };
    let (m, runout) = measure_frames(&fields, &options).unwrap();
    for (k, (got, want)) in m.placement.at.iter().zip(truth).enumerate() {
        let off = (got[0] - want[0]).hypot(got[1] - want[1]);
        assert!(off < 0.3, "field {}: at {got:?}, truth {want:?} ({off:.3} px)", k + 1);
    }
    let miss = worst_miss(&m.profile);
    assert!(miss < 1.0, "worst miss {miss} px");
    assert!((m.profile.tip() - TIP_WEAR).abs() < PIXEL, "tip at {}", m.profile.tip());
    // The lower tiles see both sides of the tool near its tip.
    let runout = runout.unwrap();
    assert!((runout - RUNOUT).abs() < 0.3 * PIXEL, "runout {runout}");
    eprintln!("tiles: {:?}, worst miss {miss:.3} px, warnings {:?}", m.placement.at, m.warnings);
}

#[test]
fn pictures_without_a_tool_and_tiles_apart_are_refused() {
    let v = view(280.0, 380.0);
    let mut rng = SplitMix64::new(3);
    let options = Options { pixel_mm: PIXEL, threshold: None, search: 5, tip_row: None };
    // Backlight and noise only.
    let mut empty = v.clone();
    empty.tip_y = -1000.0;
    let field = (empty.frames(3, 100, 80, [0.0, 0.0], &mut rng), [0.0, 0.0]);
    let e = measure_frames(&[field], &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NoTool, "{e}");
    let e = e.message;
    assert!(e.contains("no tool"), "{e}");
    // Two tiles 20 px apart.
    let a = (v.frames(2, 200, 420, [0.0, 0.0], &mut rng), [0.0, 0.0]);
    let b = (v.frames(2, 200, 420, [220.0, 0.0], &mut rng), [220.0, 0.0]);
    let e = measure_frames(&[a, b], &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NoOverlap, "{e}");
    let e = e.message;
    assert!(e.contains("field 2 does not overlap"), "{e}");
}

#[test]
fn a_tip_row_outside_the_pictures_is_refused() {
    let v = view(280.0, 380.0);
    let mut rng = SplitMix64::new(5);
    let field = (v.frames(3, 560, 420, [0.0, 0.0], &mut rng), [0.0, 0.0]);
    for row in [-1.0, 421.0, 880.0] {
        let options = Options { pixel_mm: PIXEL, threshold: None, search: 5, tip_row: Some(row) };
        let e = measure_frames(std::slice::from_ref(&field), &options).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TipRowOutside, "{e}");
        let e = e.message;
        assert!(e.contains(&format!("the tip row {row} is outside the pictures (rows 0 to 420")), "{e}");
    }
    let options = Options { pixel_mm: PIXEL, threshold: None, search: 5, tip_row: Some(400.0) };
    assert!(measure_frames(&[field], &options).is_ok());
}
