//! `kezuri demo`: every pipeline on bundled samples, into one folder.

mod wear;

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{bail, Context, Result};
use kezuri_geom::Heightfield;
use kezuri_nc::write::{csv, program, WriteOptions};

use crate::files::write_atomic;
use crate::program::{read_and_run, Report, RunOptions};

/// The bundled samples: file name, what it shows, text.
const SAMPLES: [(&str, &str, &str); 3] = [
    (
        "o1011-digitize.nc",
        "digitizing program O1011/O1012/O1013, 85 x 105 plunges",
        include_str!("../../../../samples/o1011-digitize.nc"),
    ),
    (
        "o7023-texture.nc",
        "texture: CAM path under G66.1 P7023, random depths from #3001 (--clock-seed 7)",
        include_str!("../../../../samples/o7023-texture.nc"),
    ),
    (
        "o2007-thermal.nc",
        "thermal drift test moves O2007 with B indexing",
        include_str!("../../../../samples/o2007-thermal.nc"),
    ),
];

/// The demo's pipelines (`--only`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Pipeline {
    /// The bundled programs run, expanded and drawn.
    Programs,
    /// The step between passes on a slope, a chip, a finishing program and its simulation on a
    /// dome.
    Geometry,
    /// Digitizing a model and copy-milling it.
    Copy,
    /// A sketch carved as a relief.
    Relief,
    /// A carved texture on a nameplate.
    Texture,
    /// Thermal drift measured (simulated sensor profiles in thermal/) and corrected.
    Thermal,
    /// A tool imaged new and worn (pictures in tool-T7-new/, tool-T7-worn/) and a groove corrected.
    Wear,
}

/// One pipeline of the demo, into the output folder.
type Step = fn(&Path) -> Result<()>;

/// Runs the demo's pipelines (`only`, or all) into `out`; `frames`: keep
/// every microscope picture of the tool-wear demo.
pub fn run(out: &Path, only: &[Pipeline], frames: bool) -> Result<()> {
    let samples = out.join("samples");
    std::fs::create_dir_all(&samples).with_context(|| format!("cannot create {}", samples.display()))?;
    println!("kezuri demo -> {}", out.display());
    let wanted = |p: Pipeline| only.is_empty() || only.contains(&p);
    if wanted(Pipeline::Programs) {
        programs(out, &samples)?;
    }
    let steps: [(Pipeline, Step); 5] = [
        (Pipeline::Geometry, geometry),
        (Pipeline::Copy, copy_milling),
        (Pipeline::Relief, relief_carving),
        (Pipeline::Texture, textured_nameplate),
        (Pipeline::Thermal, thermal_drift),
    ];
    for (pipeline, step) in steps {
        if wanted(pipeline) {
            step(out)?;
        }
    }
    if wanted(Pipeline::Wear) {
        wear::tool_wear(out, frames)?;
    }
    if only.is_empty() {
        index(out)?;
    }
    Ok(())
}

/// The bundled programs, each run, expanded, tabulated and drawn.
fn programs(out: &Path, samples: &Path) -> Result<()> {
    for (name, what, text) in SAMPLES {
        let file = samples.join(name);
        write_atomic(&file, text.as_bytes())?;
        let options = run_options(file.clone(), Some(7));
        let (ran, parse_diagnostics) = read_and_run(&options)?;
        if ran.errors() > 0 {
            ran.print_diagnostics(&parse_diagnostics);
            bail!("sample {name} did not run");
        }
        let stem = name.trim_end_matches(".nc");
        let path = &ran.outcome.toolpath;
        let expanded = out.join(format!("{stem}-expanded.nc"));
        let options = WriteOptions { title: Some(format!("{stem} expanded by kezuri")), ..WriteOptions::default() };
        write_atomic(&expanded, program(path, &options)?.as_bytes())?;
        write_atomic(&out.join(format!("{stem}.csv")), csv(path).as_bytes())?;
        write_atomic(&out.join(format!("{stem}.svg")), kezuri_picture::plot::svg(path, name).as_bytes())?;
        let r = Report::new(&ran);
        let warnings = parse_diagnostics.iter().chain(&ran.outcome.diagnostics).filter(|d| !d.is_error()).count();
        println!("\n{name}  ({what})");
        println!(
            "  {} blocks, {} motions, feed {:.1} mm, rapid {:.1} mm, cycle time {:.0} s, {}",
            r.blocks,
            r.motions,
            r.feed_length_mm,
            r.rapid_length_mm,
            r.time_s,
            crate::say::count(warnings as u64, "warning")
        );
        println!("  wrote {stem}-expanded.nc (Fanuc, macros expanded), {stem}.csv (motions), {stem}.svg (picture)");
    }
    Ok(())
}

/// What to open first: the 3D pages, then the pictures, each with a line
/// on what it shows; and what the folder holds.
fn index(out: &Path) -> Result<()> {
    const FIRST: [(&str, &str); 2] = [
        ("dome-ball.html", "the dome's finishing job in 3D, coloured by its deviation (open in a browser)"),
        ("plum-relief.html", "the relief carving: roughing T1 and finishing T2, and its deviation"),
    ];
    const PICTURES: [(&str, &str); 12] = [
        ("dome-ball-deviation.png", "the dome as cut against the surface, ±10 µm, gouges magenta"),
        ("plum-relief-deviation.png", "the relief as cut against its surface, ±10 µm"),
        ("groove-deviation.png", "the worn tool's groove, as programmed and corrected, one scale"),
        ("groove-before-after.png", "the same across the groove, as a chart"),
        ("plum-copy-deviation.png", "the copy of the plum mould against the model"),
        ("dome-ball.png", "simulated surfaces (also plum-relief.png, plum-copy.png, nameplate-textured.png)"),
        ("plum.png", "the probed mould, levelled"),
        ("tool-T7-worn.png", "the worn tool's silhouette against the nominal ball:0.5"),
        ("tool-T7-wear.png", "its radius loss along the tool"),
        ("oval-engage.png", "the oval end mill's chip per rotation angle and inclination"),
        ("dome-ball.svg", "toolpaths (also plum-copy.svg, o1011-digitize.svg, o7023-texture.svg, o2007-thermal.svg)"),
        ("thermal-before-after.svg", "O2007's stops on the warm machine, as programmed and corrected"),
    ];
    println!("\nOpen first:");
    for (file, what) in FIRST {
        println!("  {file:<26} {what}");
    }
    println!("then the pictures:");
    for (file, what) in PICTURES {
        println!("  {file:<26} {what}");
    }
    println!("and the other 3D pages: plum-copy.html, nameplate-textured.html, o2007-corrected.html");
    let (mut files, mut bytes) = (0u64, 0u64);
    let mut folders = vec![out.to_path_buf()];
    while let Some(dir) = folders.pop() {
        for entry in std::fs::read_dir(&dir).with_context(|| format!("cannot read {}", dir.display()))? {
            let entry = entry?;
            let meta = entry.metadata()?;
            if meta.is_dir() {
                folders.push(entry.path());
            } else {
                files += 1;
                bytes += meta.len();
            }
        }
    }
    println!("\n{files} files, {:.1} MB in {}", bytes as f64 / 1e6, out.display());
    Ok(())
}

/// The dome of the geometry demo: a 60 × 60 mm boss, a spherical cap of
/// radius 45 mm rising 12 mm with ripples, on a flat floor.
fn dome(x: f64, y: f64) -> f64 {
    let (u, v) = (x - 30.0, y - 30.0);
    let cap = (45.0f64.powi(2) - u * u - v * v).max(0.0).sqrt() - 33.0;
    let ripple = 0.4 * (u / 3.0).sin() * (v / 4.0).cos();
    (cap + ripple).max(0.0)
}

/// The geometry core on a surface: the oval end mill pick feeds and the chip
/// its tooth cuts on inclined planes, a finishing
/// program with pick-feed control, its simulation against the surface, and
/// a grid of CL points — each as the `kezuri` command a user would type.
fn geometry(out: &Path) -> Result<()> {
    let surface = Heightfield::from_fn(0.0, 0.0, 0.5, 121, 121, dome)?;
    let stl = out.join("samples").join("dome.stl");
    let mut files = crate::files::Outputs::new();
    crate::surface::stage_surface_stl(&mut files, &stl, &surface)?;
    files.commit()?;
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let stl = stl.to_string_lossy().into_owned();
    println!("\nsamples/dome.stl  (a 60 x 60 mm rippled dome, 28,800 triangles)");
    let commands: [Vec<String>; 6] = [
        words(&["scallop", "--tool", "oval:16,24", "--angle", "15", "--cusp", "0.010"]),
        words(&["scallop", "--tool", "oval:16,24", "--angle", "60", "--cusp", "0.010"]),
        words(&[
            "engage",
            "--tool",
            "oval:16,24",
            "--angle",
            "0:75:15",
            "--pick-feed",
            "auto",
            "--depth",
            "0.8",
            "--feed-per-tooth",
            "0.16",
            "--next-pass",
            "both",
            "--png",
            &at("oval-engage.png"),
            "--csv",
            &at("oval-engage.csv"),
        ]),
        words(&[
            "mill",
            &stl,
            "--tool",
            "ball:6",
            "--stepover",
            "1.5",
            "--cusp",
            "0.005",
            "-o",
            &at("dome-ball.nc"),
            "--svg",
            &at("dome-ball.svg"),
        ]),
        words(&[
            "sim",
            &at("dome-ball.nc"),
            "--tool",
            "ball:6",
            "--res",
            "0.1",
            "--compare",
            &stl,
            "--deviation-scale",
            "0.01",
            // The mill's own allowance (its --gouge-tol, 0.01 mm).
            "--gouge-tol",
            "0.01",
            "-o",
            &at("dome-ball.png"),
            "--view",
            &at("dome-ball.html"),
        ]),
        words(&["dropcut", &stl, "--tool", "oval:16,24", "--grid", "0,0,60,60,2", "-o", &at("dome-oval.cl")]),
    ];
    run_shown(out, &commands)?;
    println!("\nwrote oval-engage.png and .csv (the chip of one tooth per rotation angle, step-up and");
    println!("step-down, pick feeds for a 10 µm cusp), dome-ball.nc (ball:6, pick-feed control),");
    println!("dome-ball.svg, dome-ball.png and dome-ball-deviation.png (simulated cut against the");
    println!("surface, ±10 µm: the tolerance), dome-ball.html (the job in 3D: open it in a browser),");
    println!("dome-oval.cl (CL points)");
    Ok(())
}

/// The master model of the copy-milling demo, after the copy-milling study's rice mould
/// (物相御飯木型, the "UME" type): an 84 × 104 mm block with a flat top at
/// z = 30 and a five-petal plum-blossom pocket up to 20 mm deep, its walls
/// no steeper than 45°.
fn plum_mould(x: f64, y: f64) -> f64 {
    let (u, v) = (x - 42.0, (y - 52.0) / 1.2);
    let petals = 32.0 * (1.0 + 0.12 * (5.0 * v.atan2(u)).cos());
    let s = (u * u + v * v).sqrt() / petals;
    30.0 - if s < 1.0 { 20.0 * (1.0 - s * s).powf(1.5) } else { 0.0 }
}

/// The digitize-and-copy pipeline on a simulated capture of the plum mould:
/// readings of a 10 mm ball stylus on the 85 × 105 grid at 1 mm (the
/// original system's), set down out of level and with noise; levelling on
/// the border; cross sections, mesh and picture; the copy with a 10 mm ball
/// end mill; and its simulation against the model.
fn copy_milling(out: &Path) -> Result<()> {
    let model = out.join("samples").join("plum-mould.xyz");
    let mut text = String::with_capacity(1 << 20);
    for j in 0..=208 {
        for i in 0..=168 {
            let (x, y) = (f64::from(i) * 0.5, f64::from(j) * 0.5);
            let _ = writeln!(text, "{x} {y} {:.4}", plum_mould(x, y));
        }
    }
    write_atomic(&model, text.as_bytes())?;
    println!("\nsamples/plum-mould.xyz  (a rice mould master: 84 x 104 mm, a plum-blossom pocket 20 mm deep)");
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let model = model.to_string_lossy().into_owned();
    let commands: [Vec<String>; 5] = [
        words(&[
            "probe",
            "simulate",
            &model,
            "--count",
            "85,105",
            "--pitch",
            "1",
            "--origin",
            "0,0",
            "--stylus",
            "ball:10",
            "--tilt",
            "0.004,-0.003",
            "--noise",
            "0.003",
            "-o",
            &at("plum.txt"),
        ]),
        words(&["probe", "level", &at("plum.txt"), "--reference", "border", "-o", &at("plum-level.txt")]),
        words(&[
            "probe",
            "export",
            &at("plum-level.txt"),
            "--dxf",
            &at("plum.dxf"),
            "--stl",
            &at("plum.stl"),
            "--png",
            &at("plum.png"),
        ]),
        words(&[
            "probe",
            "mill",
            &at("plum-level.txt"),
            "--stylus",
            "ball:10",
            "--tool",
            "ball:10",
            "-o",
            &at("plum-copy.nc"),
            "--svg",
            &at("plum-copy.svg"),
        ]),
        words(&[
            "sim",
            &at("plum-copy.nc"),
            "--tool",
            "ball:10",
            "--res",
            "0.2",
            "--stock",
            "0,0,84,104,30",
            "--compare",
            &model,
            "-o",
            &at("plum-copy.png"),
            "--view",
            &at("plum-copy.html"),
        ]),
    ];
    run_shown(out, &commands)?;
    println!("\nwrote plum.txt (the capture), plum-level.txt (levelled), plum.dxf (a polyline per row),");
    println!("plum.stl, plum.png, plum-copy.nc (the copy), plum-copy.svg, plum-copy.png and");
    println!("plum-copy-deviation.png (the simulated copy against the model), plum-copy.html (in 3D)");
    Ok(())
}

/// Relief carving: the bundled sketch of a plum blossom carved as a relief 64 mm
/// wide and 3 mm deep, roughed with a 6 mm flat end mill and finished with
/// a 2 mm ball, and its simulation against the relief surface, each tool
/// with its own cutter from a machine file's tool table.
fn relief_carving(out: &Path) -> Result<()> {
    let sketch = out.join("samples").join("plum-sketch.png");
    write_atomic(&sketch, include_bytes!("../../../../samples/plum-sketch.png"))?;
    println!("\nsamples/plum-sketch.png  (a grayscale sketch for a relief, 256 x 192 pixels)");
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let sketch = sketch.to_string_lossy().into_owned();
    // The machine's tool table: the simulation cuts each tool's moves
    // with its own cutter.
    let tools = "[tools.T1]\nshape = \"flat:6\"\nname = \"roughing end mill\"\n\n\
                 [tools.T2]\nshape = \"ball:2\"\nname = \"finishing ball\"\n";
    write_atomic(&out.join("plum-tools.toml"), tools.as_bytes())?;
    let commands: [Vec<String>; 2] = [
        words(&[
            "relief",
            &sketch,
            "--width",
            "64",
            "--depth",
            "3",
            "--tool",
            "ball:2",
            "--stepover",
            "0.25",
            "--rough",
            "flat:6",
            "--step-down",
            "1.5",
            "--allowance",
            "0.3",
            "--surface-stl",
            &at("plum-relief.stl"),
            "-o",
            &at("plum-relief.nc"),
        ]),
        words(&[
            "sim",
            &at("plum-relief.nc"),
            "--machine",
            &at("plum-tools.toml"),
            "--res",
            "0.1",
            "--stock",
            "0,0,64,48,0",
            "--compare",
            &at("plum-relief.stl"),
            "--deviation-scale",
            "0.01",
            "-o",
            &at("plum-relief.png"),
            "--view",
            &at("plum-relief.html"),
        ]),
    ];
    run_shown(out, &commands)?;
    println!("\nwrote plum-relief.nc (roughing T1, finishing T2), plum-tools.toml (their cutters, simulated each");
    println!("with its own), plum-relief.stl (the relief surface), plum-relief.png (the simulated carving)");
    println!("plum-relief-deviation.png (±10 µm: the tolerance) and plum-relief.html (in 3D)");
    Ok(())
}

/// The carved texture on a nameplate: the CAM's area clearing at Z 0
/// textured with the original system's numbers (base -2, digits, design
/// rule 0.2–1.6 mm, a clamp), baked in and as the Custom Macro B program,
/// and the baked one simulated.
fn textured_nameplate(out: &Path) -> Result<()> {
    let cam = out.join("samples").join("nameplate-cam.nc");
    write_atomic(&cam, include_bytes!("../../../../samples/nameplate-cam.nc"))?;
    println!("\nsamples/nameplate-cam.nc  (a nameplate's zig-zag area clearing at CAM Z 0)");
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let cam = cam.to_string_lossy().into_owned();
    let design = ["--base", "-2", "--step-range", "0.2,1.6", "--max-depth", "-2.8"];
    let commands: [Vec<String>; 3] = [
        words(
            &[&["texture", cam.as_str(), "--seed", "7"][..], &design, &["-o", &at("nameplate-textured.nc")]].concat(),
        ),
        words(
            &[&["texture", cam.as_str()][..], &design, &["--mode", "macro", "-o", &at("nameplate-macro.nc")]].concat(),
        ),
        words(&[
            "sim",
            &at("nameplate-textured.nc"),
            "--tool",
            "ball:6",
            "--res",
            "0.2",
            "--stock",
            "-110,-62,110,1,0",
            "-o",
            &at("nameplate-textured.png"),
            "--view",
            &at("nameplate-textured.html"),
        ]),
    ];
    run_shown(out, &commands)?;
    println!("\nwrote nameplate-textured.nc (every stroke written out), nameplate-macro.nc (G66.1 P7023 and");
    println!("the macro: each part different on the control), nameplate-textured.png (the simulated plate)");
    println!("and nameplate-textured.html (in 3D)");
    Ok(())
}

/// The warm machine's drift at an O2007 stop on `axis` (0 X, 2 Z) at
/// command `c`, `t` of the way along its travel: the original study's shape — X
/// moves 50 µm off in X and 0–50 µm in Y across the travel, Z moves within
/// 20 µm — and Y a little.
fn drift(axis: usize, t: f64) -> [f64; 3] {
    match axis {
        0 => [0.050, 0.050 * t, 0.004 * t * t],
        1 => [0.001, 0.002 * t, 0.0],
        _ => [0.012 * t, 0.002, -0.020 * t + 0.006 * t * t],
    }
}

/// The thermal-drift pipeline on the mill-turn: the measuring program,
/// simulated cold and warm profiles of its stops from both line sensors,
/// the edges, the fitted model, the corrected O2007, and a before/after
/// picture of the errors on the warm machine.
fn thermal_drift(out: &Path) -> Result<()> {
    use kezuri_correct::thermal::{fit, Measurement};
    let dir = out.join("thermal");
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let machine = out.join("samples").join("mill-turn.toml");
    write_atomic(&machine, include_bytes!("../../../../samples/mill-turn.toml"))?;
    println!("\nsamples/mill-turn.toml  (a mill-turn: tool side X Z B, work side Y C)");
    // The stops of O2007, each axis's travel at each B angle, and Y about zero.
    let stations: [(f64, [(f64, f64); 3]); 2] = [
        (0.0, [(-22.0, -2.0), (-10.0, 10.0), (-94.0, -74.0)]),
        (-90.0, [(-165.0, -145.0), (-10.0, 10.0), (-155.0, -135.0)]),
    ];
    let profile = |u: f64, w: f64| {
        let mut t = String::from("x_mm,z_mm\n");
        for k in 0..=200 {
            let x = u - 1.0 + f64::from(k) * 0.01;
            let dx = x - u;
            let z = w + if dx < 0.0 { dx * 35f64.to_radians().tan() } else { -dx * 55f64.to_radians().tan() };
            let _ = writeln!(t, "{x:.9},{z:.9}");
        }
        t
    };
    let mut index = String::from("axis,command_mm,b_deg,state,profile_1,profile_2\n");
    let mut truth = Vec::new();
    for (b, axes) in stations {
        for (axis, (from, to)) in axes.into_iter().enumerate() {
            for k in 0..6 {
                let c = from + (to - from) * f64::from(k) / 5.0;
                let e = drift(axis, f64::from(k) / 5.0);
                truth.push(Measurement { axis, b_deg: b, command: c, error: e });
                for (state, err) in [("cold", [0.0; 3]), ("warm", e)] {
                    let mut edge = [0.3 + err[0], -0.2 + err[1], 0.1 + err[2]];
                    edge[axis] += c;
                    let name = format!("{}{}-b{}-{state}", ["x", "y", "z"][axis], k, b.abs());
                    write_atomic(&dir.join(format!("{name}-1.csv")), profile(edge[0], edge[2]).as_bytes())?;
                    write_atomic(&dir.join(format!("{name}-2.csv")), profile(edge[1], edge[2]).as_bytes())?;
                    let _ = writeln!(index, "{},{c},{b},{state},{name}-1.csv,{name}-2.csv", ["X", "Y", "Z"][axis]);
                }
            }
        }
    }
    write_atomic(&dir.join("index.csv"), index.as_bytes())?;
    let at = |name: &str| out.join(name).to_string_lossy().into_owned();
    let m = machine.to_string_lossy().into_owned();
    let o2007 = out.join("samples").join("o2007-thermal.nc");
    write_atomic(&o2007, include_bytes!("../../../../samples/o2007-thermal.nc"))?;
    let o2007 = o2007.to_string_lossy().into_owned();
    let commands: [Vec<String>; 4] = [
        words(&["thermal", "plan", "--machine", &m, "-o", &at("O2007-plan.nc")]),
        words(&["thermal", "measure", &at("thermal/index.csv"), "-o", &at("thermal-meas.csv")]),
        words(&["thermal", "fit", &at("thermal-meas.csv"), "--machine", &m, "-o", &at("thermal-model.json")]),
        words(&[
            "thermal",
            "apply",
            &o2007,
            "--model",
            &at("thermal-model.json"),
            "--machine",
            &m,
            // O2007's approach and retract at Z0 lie above the measured
            // range: their correction is extrapolated, and said.
            "--allow-extrapolation",
            "-o",
            &at("o2007-corrected.nc"),
            "--view",
            &at("o2007-corrected.html"),
        ]),
    ];
    run_shown(out, &commands)?;
    // Before and after on the warm machine (the drift above): each stop's
    // miss as commanded and as corrected.
    let model = fit(&truth, None)?;
    let k = crate::machine::load(&machine)?.kinematics;
    let stops = |file: &str| -> Result<Vec<[f64; 6]>> {
        let options = run_options(file.into(), None);
        let (ran, _) = read_and_run(&options)?;
        let inside = |c: &[f64; 6]| {
            stations.iter().any(|(b, r)| {
                *b == c[4]
                    && (r[0].0 - 1.0..=r[0].1 + 1.0).contains(&c[0])
                    && (r[2].0 - 1.0..=r[2].1 + 1.0).contains(&c[2])
            })
        };
        let mut v: Vec<[f64; 6]> =
            ran.outcome.toolpath.moves.iter().map(|m| m.end.xyzabc()).filter(|c| inside(c)).collect();
        v.dedup();
        Ok(v)
    };
    let (before, after) = (stops(&o2007)?, stops(&at("o2007-corrected.nc"))?);
    let miss = |command: &[f64; 6], target: [f64; 3]| -> Result<f64> {
        let p = model.deformed(&k, command)?;
        Ok((0..3).map(|i| (p[i] - target[i]).powi(2)).sum::<f64>().sqrt() * 1e3)
    };
    let (mut was, mut now) = (Vec::new(), Vec::new());
    for (plain, fixed) in before.iter().zip(&after) {
        let target = k.forward(plain);
        was.push(miss(plain, target)?);
        now.push(miss(fixed, target)?);
    }
    let chart = kezuri_picture::plot::log_chart(
        "o2007-thermal.nc and o2007-corrected.nc: O2007's stops on the warm machine, tool tip from target",
        "stop of O2007, in program order",
        "µm",
        1e-3,
        &[("as programmed", "#c0392b", was.clone()), ("corrected (4 decimals)", "#2471a3", now.clone())],
    );
    write_atomic(&out.join("thermal-before-after.svg"), chart.as_bytes())?;
    let largest = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    println!(
        "\nwrote O2007-plan.nc, thermal-meas.csv, thermal-model.json, o2007-corrected.nc (and .html, in 3D) and\n\
         thermal-before-after.svg: {} stops, up to {:.1} µm off as programmed, {:.3} µm corrected",
        was.len(),
        largest(&was),
        largest(&now)
    );
    Ok(())
}

/// Runs each command as `kezuri` would, showing it first without the
/// output folder's prefix (and a run of many pictures as its first and
/// last).
fn run_shown(out: &Path, commands: &[Vec<String>]) -> Result<()> {
    for command in commands {
        let mut shown: Vec<String> = command.iter().map(|w| w.replace(&format!("{}/", out.display()), "")).collect();
        let pictures = shown.iter().filter(|w| w.ends_with(".png") && !w.starts_with('-')).count();
        if pictures > 4 {
            if let Some(first) = shown.iter().position(|w| w.ends_with(".png")) {
                let last = first + shown[first..].iter().take_while(|w| w.ends_with(".png")).count() - 1;
                let summary = format!("{} … {} ({} pictures)", shown[first], shown[last], last - first + 1);
                shown.splice(first..=last, [summary]);
            }
        }
        println!("\n$ kezuri {}", shown.join(" "));
        let command: Vec<&str> = command.iter().map(String::as_str).collect();
        crate::run_words(&command)?;
    }
    Ok(())
}

/// How the demo runs a program: the file, the clock seeded or not,
/// everything else as the command line's defaults.
fn run_options(file: std::path::PathBuf, clock_seed: Option<u64>) -> RunOptions {
    RunOptions {
        file,
        lib: None,
        machine: None,
        dialect: None,
        var: None,
        no_decimal: None,
        clock_seed,
        block_delete: false,
        step_limit: 10_000_000,
        dprnt: None,
        keep_cycles: false,
    }
}

fn words(w: &[&str]) -> Vec<String> {
    w.iter().map(|s| s.to_string()).collect()
}
