//! The demo's tool-wear pipeline: pictures of a turning 0.5 mm
//! ball end mill, new and worn, drawn from a known shape; their profiles
//! measured and kept in the tool database; a groove finished with the worn
//! tool, as programmed and corrected, simulated against its target.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{bail, Result};
use kezuri_cam::sim::{simulate_tool, MeasuredTool, SimOptions, Stock, Tool, ZMap};
use kezuri_correct::synthetic::View;
use kezuri_correct::tool_image::GrayImage;
use kezuri_geom::{write_binary_stl, SplitMix64, ToolProfile, Triangle, Vec3};
use kezuri_picture::chart::{line_chart, Line};
use kezuri_picture::figure::Figure;
use kezuri_picture::png_from_svg;
use kezuri_picture::sim::{deviation_panel, DeviationScale, GOUGE_MM};

use super::{run_options, run_shown, words};
use crate::files::write_atomic;
use crate::program::read_and_run;
use crate::simulation::{simulate, SimSetup};

/// The ball's radius, mm.
const R: f64 = 0.25;
/// Pixel side, mm (0.71 µm).
const PIXEL: f64 = 0.00071;
/// The groove: a trough of this radius along Y, its bottom at z 0.
const TROUGH: f64 = 0.8;
/// The stock the groove is simulated in.
const STOCK: &str = "-0.64,0.1,0.64,0.4,0.5";
/// Pictures of the tool turning.
const FRAMES: usize = 36;
/// The pictures kept without `--frames`: half a turn apart.
const KEPT: [usize; 2] = [0, 18];
/// The groove's deviation pictures show ±this, mm.
const GROOVE_SCALE: f64 = 0.004;

/// The cutting edges of the tool after `worn` of its life (0 new, 1 the
/// worn tool): the tip worn back 3 µm and a band at 45° 10 µm deep.
fn edges(worn: f64) -> ToolProfile {
    let tip = 0.003 * worn;
    let z: Vec<f64> = (0..=1500).map(|k| tip + 0.5 * k as f64 / 1500.0).collect();
    let band = R * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
    let r = z
        .iter()
        .map(|&z| {
            let ball = if z < R { (z * (2.0 * R - z)).sqrt() } else { R };
            ball - worn * 0.010 * (-((z - band) / 0.05).powi(2)).exp()
        })
        .collect();
    ToolProfile::new(z, r).expect("a profile")
}

/// Writes [`FRAMES`] frames of the tool turning (8 µm runout) as 16-bit
/// PNGs.
fn pictures(dir: &Path, worn: f64, seed: u64) -> Result<Vec<String>> {
    let view = View {
        edges: edges(worn),
        runout_mm: 0.008,
        web: 0.8,
        pixel_mm: PIXEL,
        axis_x: 420.0,
        tip_y: 520.0,
        levels: (0.12, 0.88),
        noise: 0.01,
    };
    let mut rng = SplitMix64::new(seed);
    let mut files = Vec::new();
    for (k, frame) in view.frames(FRAMES, 840, 580, [0.0, 0.0], &mut rng).iter().enumerate() {
        let file = dir.join(format!("f{k:02}.png"));
        write_atomic(&file, &png16(frame)?)?;
        files.push(file.to_string_lossy().into_owned());
    }
    Ok(files)
}

/// A gray picture as a 16-bit PNG.
fn png16(img: &GrayImage) -> Result<Vec<u8>> {
    let bytes: Vec<u8> =
        img.pixels.iter().flat_map(|&v| ((f64::from(v) * 65535.0).round() as u16).to_ne_bytes()).collect();
    let mut out = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut out),
        &bytes,
        img.width as u32,
        img.height as u32,
        image::ExtendedColorType::L16,
    )?;
    Ok(out)
}

/// The groove's target: the trough from −60° to 60°, flat beyond.
fn trough() -> Vec<u8> {
    let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, d)];
    let n = 480;
    let (y0, y1) = (-2.0, 3.0);
    let at = |k: usize, y: f64| {
        let t = (-60.0 + 120.0 * k as f64 / n as f64).to_radians();
        Vec3::new(TROUGH * t.sin(), y, TROUGH - TROUGH * t.cos())
    };
    let mut t: Vec<Triangle> = (0..n).flat_map(|k| quad(at(k, y0), at(k + 1, y0), at(k + 1, y1), at(k, y1))).collect();
    let (top, xl, xr) = (0.5 * TROUGH, at(0, 0.0).x, at(n, 0.0).x);
    t.extend(quad(Vec3::new(-4.0, y0, top), Vec3::new(xl, y0, top), Vec3::new(xl, y1, top), Vec3::new(-4.0, y1, top)));
    t.extend(quad(Vec3::new(xr, y0, top), Vec3::new(4.0, y0, top), Vec3::new(4.0, y1, top), Vec3::new(xr, y1, top)));
    write_binary_stl(&t)
}

/// The groove's finishing program: passes along Y, the ball touching the
/// trough at −55° … 55°, 10 µm apart across (cusps under 0.1 µm).
fn groove() -> String {
    let mut s = String::from("%\nO0200 (GROOVE FINISH, BALL 0.5)\nG90 G21 G17\nG0 Z2.\n");
    let passes = 130;
    for k in 0..=passes {
        let phi = (-55.0 + 110.0 * k as f64 / passes as f64).to_radians();
        let (x, z) = ((TROUGH - R) * phi.sin(), TROUGH - (TROUGH - R) * phi.cos() - R);
        let (ya, yb) = if k % 2 == 0 { (-0.5, 1.0) } else { (1.0, -0.5) };
        if k == 0 {
            let _ = writeln!(s, "G0 X{x:.5} Y{ya:.5}\nG1 Z{z:.5} F200");
        } else {
            let _ = writeln!(s, "G1 X{x:.5} Z{z:.5}");
        }
        let _ = writeln!(s, "Y{yb:.5}");
    }
    s + "G0 Z2.\nM30\n%\n"
}

/// The tool-wear demo into `out`, keeping every picture of the tool with
/// `all_frames` (else [`KEPT`]).
pub fn tool_wear(out: &Path, all_frames: bool) -> Result<()> {
    println!("\ntool wear: a 0.5 mm ball end mill imaged turning (36 frames, 0.71 µm pixels), new and worn");
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let mut commands = Vec::new();
    for (name, worn, seed, time) in
        [("new", 0.0, 11, "2026-11-02T08:00:00Z"), ("worn", 1.0, 12, "2026-11-20T17:30:00Z")]
    {
        let dir = out.join(format!("tool-T7-{name}"));
        std::fs::create_dir_all(&dir)?;
        let frames = pictures(&dir, worn, seed)?;
        let csv = at(&format!("tool-T7-{name}.csv"));
        let mut profile = words(&["tool", "profile"]);
        profile.extend(frames);
        profile.extend(words(&["--pixel-um", "0.71", "--tip-row", "520", "--nominal", "ball:0.5", "-o", &csv]));
        profile.extend(words(&["--png", &at(&format!("tool-T7-{name}.png"))]));
        commands.push(profile);
        commands.push(words(&["tool", "db", "add", "T7", &csv, "--db", &at("tools.sqlite"), "--at", time]));
    }
    commands.push(words(&["tool", "db", "show", "T7", "--db", &at("tools.sqlite"), "--png", &at("tool-T7-wear.png")]));
    write_atomic(&out.join("groove.nc"), groove().as_bytes())?;
    write_atomic(&out.join("groove-target.stl"), &trough())?;
    commands.push(words(&[
        "wear",
        "apply",
        &at("groove.nc"),
        "--tool-name",
        "T7",
        "--db",
        &at("tools.sqlite"),
        "--nominal",
        "ball:0.5",
        "--surface",
        &at("groove-target.stl"),
        // A groove 8 mm long, drawn in mm: no note that it may be inches.
        "--units",
        "mm",
        "-o",
        &at("groove-T7.nc"),
    ]));
    for program in ["groove.nc", "groove-T7.nc"] {
        commands.push(words(&[
            "sim",
            &at(program),
            "--profile",
            &at("tool-T7-worn.csv"),
            "--res",
            "0.002",
            "--stock",
            STOCK,
            "--compare",
            &at("groove-target.stl"),
            "--units",
            "mm",
        ]));
    }
    // A fresh database each run.
    let _ = std::fs::remove_file(out.join("tools.sqlite"));
    run_shown(out, &commands)?;
    if !all_frames {
        for name in ["new", "worn"] {
            for k in (0..FRAMES).filter(|k| !KEPT.contains(k)) {
                std::fs::remove_file(out.join(format!("tool-T7-{name}/f{k:02}.png")))?;
            }
        }
    }
    write_atomic(&out.join("groove-deviation.png"), &groove_deviation(out)?)?;
    let worn = crate::tool_profile::read_profile(&out.join("tool-T7-worn.csv"))?;
    let before = section(&out.join("groove.nc"), &worn)?;
    let after = section(&out.join("groove-T7.nc"), &worn)?;
    let largest = |v: &[(f64, f64)]| v.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let chart = line_chart(
        "Groove cut by the worn tool T7 (runout 8 µm, band worn 10 µm): across the groove at y 0.25",
        "x across the groove (mm)",
        "cut less target (µm; below 0: too deep)",
        &[
            Line { label: format!("as programmed, up to {:.2} µm", largest(&before)), points: before.clone() },
            Line { label: format!("corrected, up to {:.2} µm", largest(&after)), points: after.clone() },
        ],
    );
    write_atomic(&out.join("groove-before-after.png"), &png_from_svg(&chart)?)?;
    let kept = if all_frames {
        format!("all {FRAMES} pictures")
    } else {
        let names: Vec<String> = KEPT.iter().map(|k| format!("f{k:02}")).collect();
        format!("pictures {} of {FRAMES}; all with --frames", names.join(" and "))
    };
    println!(
        "\nwrote tool-T7-new/, tool-T7-worn/ (the tool's {kept}), tool-T7-*.csv and .png (profiles),\n\
         tools.sqlite, tool-T7-wear.png, groove.nc, groove-target.stl, groove-T7.nc (corrected),\n\
         groove-deviation.png (both grooves on one scale) and groove-before-after.png: across the groove\n\
         up to {:.2} µm off as programmed, {:.2} µm corrected",
        largest(&before),
        largest(&after)
    );
    Ok(())
}

/// The grooves as programmed and corrected, cut by the worn tool, their
/// deviation from the target one above the other on one scale.
fn groove_deviation(out: &Path) -> Result<Vec<u8>> {
    let mut scale = DeviationScale::fixed(GROOVE_SCALE, "one scale for both", GOUGE_MM);
    let mut panels = Vec::new();
    for (program, what) in [("groove.nc", "as programmed"), ("groove-T7.nc", "corrected for the wear")] {
        let (ran, _) = read_and_run(&run_options(out.join(program), None))?;
        let setup = SimSetup {
            profile: Some(out.join("tool-T7-worn.csv")),
            stock: Some(STOCK.into()),
            compare: Some(out.join("groove-target.stl")),
            units: Some(crate::surface::Units::Mm),
            chord_tol: 0.001,
            ..SimSetup::default()
        };
        let sim = simulate(
            &ran.outcome.toolpath,
            &ran.machine,
            &setup,
            Some(0.002),
            10,
            kezuri_cam::mill::GOUGE_TOL,
            program,
        )?;
        let Some((c, heights)) = &sim.comparison else { bail!("{program}: no comparison") };
        let caption = format!(
            "{program}, {what}: deepest gouge {:.2} µm, most left {:.2} µm",
            c.max_gouge * 1000.0,
            c.max_left * 1000.0
        );
        scale.include(&sim.zmap, heights);
        panels.push(deviation_panel(&sim.zmap, heights, &scale, &caption));
    }
    Ok(Figure {
        title: "groove.nc and groove-T7.nc: measured tool tool-T7-worn.csv".into(),
        subtitle: "deviation from groove-target.stl (simulated − target), 0.002 mm cells, +Y up".into(),
        panels,
        stacked: true,
        bar: Some(scale.bar()),
        legend: vec![],
    }
    .png()?)
}

/// The cut of `program` by the measured tool across the groove at y 0.25:
/// `(x, cut less target in µm)`.
fn section(program: &Path, worn: &ToolProfile) -> Result<Vec<(f64, f64)>> {
    let options = run_options(program.to_path_buf(), None);
    let (ran, _) = read_and_run(&options)?;
    let stock = Stock { x0: -0.64, y0: 0.24, x1: 0.64, y1: 0.26, top: 0.5 };
    let sim = SimOptions::new(0.002);
    let mut zmap = ZMap::new(&stock, &sim)?;
    simulate_tool(&ran.outcome.toolpath, &Tool::Measured(MeasuredTool::new(worn)), &mut zmap, &sim)?;
    Ok((0..zmap.nx)
        .map(|i| {
            let [x, _] = zmap.centre(i, 5);
            (x, 1e3 * (zmap.height(i, 5) - (TROUGH - (TROUGH * TROUGH - x * x).sqrt())))
        })
        .collect())
}
