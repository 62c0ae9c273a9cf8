//! No output over an input: an output option naming one of the command's
//! inputs — by the same path, `./path`, a symbolic link or a hard link — is
//! refused with exit code 2 before anything is read or written, in every
//! command; `run`, `convert` and `probe level` still rewrite their own
//! input in place through `-o`.

use std::path::Path;
use std::process::{Command, Output};

mod common;

const PROGRAM: &str = "samples/nameplate-cam.nc";
const PICTURE: &str = "samples/plum-sketch.png";
const PROFILE: &str = "samples/tool-T7/new/f0.png";

/// A small ASCII STL: a ramp 40 × 30 mm rising 2 mm.
const STL: &str = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 40 0 0\nvertex 40 30 2\nendloop\n\
                   endfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 40 30 2\nvertex 0 30 0\nendloop\n\
                   endfacet\nendsolid t\n";

/// A capture of 5 × 4 readings (as `probe simulate` writes it).
fn capture(dir: &Path) -> Vec<u8> {
    std::fs::write(dir.join("ramp.stl"), STL).unwrap();
    let o = kezuri_in(dir, &["probe", "simulate", "ramp.stl", "--count", "5,4", "--pitch", "5", "--stylus", "ball:2"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::remove_file(dir.join("ramp.stl")).unwrap();
    o.stdout
}

fn repo(p: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(p)).unwrap()
}

/// Runs kezuri in `dir`.
fn kezuri_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kezuri")).current_dir(dir).args(args).output().expect("kezuri runs")
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// The input `name` (with `bytes`) named as the output `OUT` of `args`
/// four ways: each is refused with exit code 2, the input stays byte for
/// byte, and no other file appears.
fn refused(inputs: &[(&str, Vec<u8>)], name: &str, args: &[&str]) {
    for form in ["same", "dot", "symlink", "hardlink"] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for (n, bytes) in inputs {
            std::fs::write(d.join(n), bytes).unwrap();
        }
        let out = match form {
            "same" => name.to_string(),
            "dot" => format!("./{name}"),
            "symlink" => {
                std::os::unix::fs::symlink(name, d.join("link")).unwrap();
                "link".to_string()
            }
            _ => {
                std::fs::hard_link(d.join(name), d.join("hard")).unwrap();
                "hard".to_string()
            }
        };
        let before = names(d);
        let words: Vec<String> = args.iter().map(|a| a.replace("OUT", &out)).collect();
        let o = kezuri_in(d, &words.iter().map(String::as_str).collect::<Vec<_>>());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{form}: kezuri {}: {err}", words.join(" "));
        assert!(err.contains("never writes over an input"), "{form}: {err}");
        assert!(err.contains(&out), "{form}: the message names the output: {err}");
        for (n, bytes) in inputs {
            assert!(std::fs::read(d.join(n)).unwrap() == *bytes, "{form}: kezuri {}: {n} changed", words.join(" "));
        }
        assert_eq!(names(d), before, "{form}: kezuri {}: a file appeared or went", words.join(" "));
        assert!(std::fs::symlink_metadata(d.join(&out)).is_ok());
    }
}

#[test]
fn a_program_never_becomes_a_page_a_picture_or_another_program() {
    let p = || ("p.nc", repo(PROGRAM));
    refused(&[p()], "p.nc", &["view", "p.nc", "-o", "OUT"]);
    refused(&[p()], "p.nc", &["run", "p.nc", "--svg", "OUT", "-o", "x.nc"]);
    refused(&[p()], "p.nc", &["run", "p.nc", "--dprnt", "OUT"]);
    refused(&[p()], "p.nc", &["check", "p.nc", "--dprnt", "OUT"]);
    refused(&[p()], "p.nc", &["convert", "p.nc", "--view", "OUT", "-o", "x.nc"]);
    refused(&[p()], "p.nc", &["texture", "p.nc", "--seed", "1", "-o", "OUT"]);
    refused(&[p()], "p.nc", &["sim", "p.nc", "--res", "0.5", "--tool", "ball:3", "-o", "OUT"]);
    refused(
        &[p(), ("s.stl", STL.into())],
        "s.stl",
        &["sim", "p.nc", "--res", "0.5", "--tool", "ball:3", "--compare", "s.stl", "--stl", "OUT"],
    );
    // The stock is a text that may name a file: still an input.
    refused(
        &[p(), ("s.stl", STL.into())],
        "s.stl",
        &["sim", "p.nc", "--res", "0.5", "--tool", "ball:3", "--stock", "s.stl", "--stl", "OUT"],
    );
    refused(
        &[p(), ("m.toml", b"[machine]\n".to_vec())],
        "m.toml",
        &["check", "p.nc", "--machine", "m.toml", "--dprnt", "OUT"],
    );
}

#[test]
fn a_picture_a_mesh_or_a_capture_never_becomes_a_mill_program() {
    refused(
        &[("pic.png", repo(PICTURE))],
        "pic.png",
        &["relief", "pic.png", "--width", "20", "--depth", "1", "--tool", "ball:3", "--stepover", "2", "-o", "OUT"],
    );
    refused(
        &[("pic.png", repo(PICTURE))],
        "pic.png",
        &[
            "relief",
            "pic.png",
            "--width",
            "20",
            "--depth",
            "1",
            "--tool",
            "ball:3",
            "--stepover",
            "2",
            "--surface-stl",
            "OUT",
            "-o",
            "x.nc",
        ],
    );
    refused(
        &[("s.stl", STL.into())],
        "s.stl",
        &["dropcut", "s.stl", "--tool", "ball:2", "--grid", "0,0,10,10,5", "-o", "OUT"],
    );
    refused(&[("s.stl", STL.into())], "s.stl", &["mill", "s.stl", "--tool", "ball:2", "--stepover", "5", "-o", "OUT"]);
    refused(
        &[("s.stl", STL.into())],
        "s.stl",
        &["probe", "simulate", "s.stl", "--count", "5,4", "--pitch", "5", "--stylus", "ball:2", "-o", "OUT"],
    );
    let dir = tempfile::tempdir().unwrap();
    let data = || ("d.txt", capture(dir.path()));
    refused(&[data()], "d.txt", &["probe", "mill", "d.txt", "--stylus", "ball:2", "--tool", "ball:2", "-o", "OUT"]);
    refused(&[data()], "d.txt", &["probe", "export", "d.txt", "--csv", "OUT"]);
    let mask = ("m.txt", b"11111\n10001\n10001\n11111\n".to_vec());
    refused(&[data(), mask], "m.txt", &["probe", "level", "d.txt", "--reference", "mask:m.txt", "-o", "OUT"]);
}

#[test]
fn measurements_profiles_and_parts_are_never_replaced() {
    let meas = b"axis,command_mm,ex_mm,ey_mm,ez_mm\nX,0,0,0,0\nX,100,0.01,0,0\n".to_vec();
    refused(&[("meas.csv", meas)], "meas.csv", &["thermal", "fit", "meas.csv", "-o", "OUT"]);
    refused(&[("f.png", repo(PROFILE))], "f.png", &["tool", "profile", "f.png", "--pixel-um", "2", "-o", "OUT"]);
    let prof = b"z_mm,radius_mm\n0,0\n0.25,0.25\n".to_vec();
    let p = || ("p.nc", repo(PROGRAM));
    refused(
        &[p(), ("t.csv", prof.clone()), ("s.stl", STL.into())],
        "s.stl",
        &["wear", "apply", "p.nc", "--profile", "t.csv", "--nominal", "ball:0.5", "--surface", "s.stl", "-o", "OUT"],
    );
    refused(
        &[p(), ("t.csv", prof), ("s.stl", STL.into())],
        "t.csv",
        &["wear", "apply", "p.nc", "--profile", "t.csv", "--nominal", "ball:0.5", "--surface", "s.stl", "-o", "OUT"],
    );
}

/// `run`, `convert` and `probe level` rewrite their own input through `-o`
/// (read whole first, then replaced by a rename), as before.
#[test]
fn run_convert_and_level_still_rewrite_their_input_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.nc"), repo(PROGRAM)).unwrap();
    for args in
        [&["run", "p.nc", "--to", "linuxcnc", "-o", "./p.nc"][..], &["convert", "p.nc", "--to", "fanuc", "-o", "p.nc"]]
    {
        let before = std::fs::read(d.join("p.nc")).unwrap();
        let o = kezuri_in(d, args);
        assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        assert_ne!(std::fs::read(d.join("p.nc")).unwrap(), before, "{args:?}");
    }
    std::fs::write(d.join("d.txt"), capture(d)).unwrap();
    let o = kezuri_in(d, &["probe", "level", "d.txt", "--reference", "border", "-o", "d.txt"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read_to_string(d.join("d.txt")).unwrap().contains("# levelled"));
    // Two names of one input argument are no conflict.
    std::fs::write(d.join("t.tbl"), "T1 P1 D6.0 Z0 ;end mill\n").unwrap();
    common::ok(&kezuri_in(d, &["tool", "table", "t.tbl", "./t.tbl", "--units", "mm"]));
}
