//! Where a command's words go: its one output to standard output when no
//! -o names a file, a one-line summary of a written program on standard
//! error, and `--quiet` leaving only errors and warnings there.

use std::fmt::Write as _;
use std::path::Path;

use kezuri_correct::synthetic::View;
use kezuri_geom::{SplitMix64, ToolProfile};

mod common;
use common::{kezuri, ok, path};

/// A 20 × 20 mm dome as an `x y z` height grid at 0.5 mm.
fn dome(dir: &Path) -> String {
    let mut t = String::new();
    for j in 0..=40 {
        for i in 0..=40 {
            let (x, y) = (f64::from(i) * 0.5, f64::from(j) * 0.5);
            let r2 = (x - 10.0).powi(2) + (y - 10.0).powi(2);
            let _ = writeln!(t, "{x} {y} {:.4}", (3.0 - r2 / 40.0).max(0.0));
        }
    }
    let file = path(dir, "dome.xyz");
    std::fs::write(&file, t).unwrap();
    file
}

fn stdout_of(args: &[&str]) -> String {
    ok(&kezuri(args))
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn every_one_output_goes_to_standard_output_without_o() {
    let dir = tempfile::tempdir().unwrap();
    let dome = dome(dir.path());
    let capture = stdout_of(&["probe", "simulate", &dome, "--count", "9,9", "--pitch", "2", "--stylus", "ball:2"]);
    assert!(
        capture.starts_with("# kezuri probe simulate\n") && capture.contains("No,Z\n1,") && capture.contains("\n81,"),
        "{capture}"
    );
    let data = path(dir.path(), "capture.txt");
    std::fs::write(&data, &capture).unwrap();
    let levelled = kezuri(&["probe", "level", &data]);
    let text = ok(&levelled);
    assert!(text.starts_with("# kezuri probe simulate\n") && text.contains("# levelled"), "{text}");
    // The table goes to standard error when the data take standard output.
    assert!(stderr(&levelled).contains("<- kept"), "{}", stderr(&levelled));
    let copy = stdout_of(&["probe", "mill", &data, "--stylus", "ball:2", "--tool", "ball:2"]);
    assert!(copy.starts_with("%\nO0001") && copy.trim_end().ends_with('%'), "{copy}");
    let split = kezuri(&["probe", "mill", &data, "--stylus", "ball:2", "--tool", "ball:2", "--split-bytes", "2000"]);
    assert!(stderr(&split).contains("--split-bytes writes files: give -o FILE"), "{}", stderr(&split));
    let plan = stdout_of(
        &["probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "1"]
            .into_iter()
            .chain(["--safe-z", "5", "--plunge", "10"])
            .collect::<Vec<_>>(),
    );
    assert!(plan.starts_with("%\nO1011"), "{plan}");
    // A model from measurements along each axis.
    let mut meas = String::from("axis,command_mm,ex_mm,ey_mm,ez_mm\n");
    for (axis, k) in ["X", "Y", "Z"].iter().zip(0..) {
        for c in 0..6 {
            let _ =
                writeln!(meas, "{axis},{},{},0.001,{}", -4 * c, 0.002 * f64::from(c * (k + 1)), 0.0001 * f64::from(c));
        }
    }
    let meas_file = path(dir.path(), "meas.csv");
    std::fs::write(&meas_file, meas).unwrap();
    let fit = kezuri(&["thermal", "fit", &meas_file]);
    let model: serde_json::Value = serde_json::from_str(&ok(&fit)).expect("the model on standard output");
    assert_eq!(model["kezuri_thermal_model"], 1);
    assert!(stderr(&fit).contains("error functions -> standard output"), "{}", stderr(&fit));
    let both = kezuri(&["thermal", "fit", &meas_file, "--json"]);
    assert!(stderr(&both).contains("give the model a file with -o"), "{}", stderr(&both));
    // A tool's profile from pictures of it turning.
    let z: Vec<f64> = (0..=300).map(|k| 0.2 * f64::from(k) / 300.0).collect();
    let r = z.iter().map(|&z| if z < 0.1 { (z * (0.2 - z)).sqrt() } else { 0.1 }).collect();
    let view = View {
        edges: ToolProfile::new(z, r).unwrap(),
        runout_mm: 0.004,
        web: 0.8,
        pixel_mm: 0.002,
        axis_x: 80.0,
        tip_y: 100.0,
        levels: (0.1, 0.9),
        noise: 0.0,
    };
    let mut args = vec!["tool".to_string(), "profile".to_string()];
    for (k, f) in view.frames(8, 160, 120, [0.0, 0.0], &mut SplitMix64::new(1)).iter().enumerate() {
        let name = path(dir.path(), &format!("f{k}.png"));
        let v: Vec<u8> = f.pixels.iter().map(|&p| (p * 255.0).round() as u8).collect();
        image::GrayImage::from_raw(f.width as u32, f.height as u32, v).unwrap().save(&name).unwrap();
        args.push(name);
    }
    args.extend(["--pixel-um", "2", "--tip-row", "100"].map(String::from));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let profile = stdout_of(&args);
    assert!(profile.starts_with("z_mm,radius_mm\n"), "{profile}");
}

#[test]
fn a_written_program_is_summed_up_on_standard_error_unless_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let dome = dome(dir.path());
    let nc = path(dir.path(), "dome.nc");
    // A ball:1, which reaches into the crease at the dome's foot (a ball:4
    // leaves 0.065 mm there, and mill says so).
    let mill =
        |extra: &[&str]| kezuri(&[&["mill", &dome, "--tool", "ball:1", "--stepover", "1", "-o", &nc], extra].concat());
    let o = mill(&[]);
    ok(&o);
    let said = stderr(&o);
    // The surface's size as read, then what was written.
    assert_eq!(said.lines().count(), 2, "{said}");
    let (model, said) = said.split_once('\n').unwrap();
    assert_eq!(model, format!("{dome}: model: 20.0 × 20.0 × 3.0 mm"));
    assert!(
        said.starts_with(&format!("wrote {nc}: ")) && said.contains(" moves, feed ") && said.contains("cycle time")
    );
    // Quiet: nothing but warnings.
    let o = mill(&["--quiet"]);
    assert_eq!(stderr(&ok_and(o)), "");
    let o = mill(&["-q", "--digits", "1"]);
    let said = stderr(&ok_and(o));
    assert!(said.starts_with("warning: 1 decimals round positions") && said.lines().count() == 1, "{said}");
    // The global flag before the command too, and on a program run.
    let plate = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/nameplate-cam.nc");
    let run = kezuri(&["--quiet", "run", plate, "-o", &path(dir.path(), "again.nc")]);
    assert_eq!(stderr(&ok_and(run)), "");
    let run = kezuri(&["run", plate, "-o", &path(dir.path(), "again.nc")]);
    let said = stderr(&ok_and(run));
    assert!(said.contains("dialect fanuc") && said.lines().last().unwrap().starts_with("wrote "), "{said}");
}

fn ok_and(o: std::process::Output) -> std::process::Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

#[test]
fn every_program_writer_says_one_line_of_what_it_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples");
    let plate = format!("{samples}/nameplate-cam.nc");
    let sketch = format!("{samples}/plum-sketch.png");
    let turn = format!("{samples}/mill-turn.toml");
    let dome = dome(dir.path());
    let capture = path(dir.path(), "capture.txt");
    ok(&kezuri(&["probe", "simulate", &dome, "--count", "9,9", "--pitch", "2", "--stylus", "ball:2", "-o", &capture]));
    let out = |name: &str| path(dir.path(), name);
    let writers: Vec<Vec<String>> = [
        vec!["run", &plate, "-o", &out("run.nc")],
        vec!["texture", &plate, "--seed", "1", "-o", &out("texture.nc")],
        vec!["texture", &plate, "--mode", "macro", "-o", &out("macro.nc")],
        vec!["convert", &plate, "-o", &out("plate.rml")],
        vec![
            "relief",
            &sketch,
            "--width",
            "20",
            "--depth",
            "1",
            "--tool",
            "ball:2",
            "--stepover",
            "2",
            "-o",
            &out("r.nc"),
        ],
        vec!["mill", &dome, "--tool", "ball:4", "--stepover", "2", "-o", &out("mill.nc")],
        vec!["probe", "mill", &capture, "--stylus", "ball:2", "--tool", "ball:2", "-o", &out("copy.nc")],
        vec!["probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "1", "--safe-z", "5", "--plunge", "9"],
        vec!["thermal", "plan", "--machine", &turn, "-o", &out("o2007.nc")],
    ]
    .into_iter()
    .map(|w| w.into_iter().map(String::from).collect())
    .collect();
    for words in writers {
        let args: Vec<&str> = words.iter().map(String::as_str).collect();
        let said = stderr(&ok_and(kezuri(&args)));
        let wrote: Vec<&str> = said.lines().filter(|l| l.starts_with("wrote ")).collect();
        assert_eq!(wrote.len(), 1, "{}: {said}", words.join(" "));
        let quiet = stderr(&ok_and(kezuri(&[&args[..], &["--quiet"]].concat())));
        assert!(!quiet.contains("wrote ") && !quiet.contains("dialect "), "{}: {quiet}", words.join(" "));
    }
}
