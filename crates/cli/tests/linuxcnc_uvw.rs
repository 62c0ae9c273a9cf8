//! U V W, the three linear axes LinuxCNC has beside X Y Z A B C, against
//! LinuxCNC's own preview parser: the `gcode` module AXIS draws its preview
//! with (Debian package linuxcnc-uspace, run by `/usr/bin/python3`), given a
//! machine with all nine axes (`rs274/nine_axes.py`). LinuxCNC's standalone
//! `rs274` cannot be the reference here: it refuses U V W ("Bad character
//! 'u' used") whatever INI file it reads.
//!
//! Each program runs through both; every motion's kind and end point on all
//! nine axes must agree within 1e-6 mm (degrees for A B C). The programs are
//! LinuxCNC's own that move U V W (`cone.ngc`, which drills with W, and the
//! foam cutter's `foam.ngc`, which moves X Y and U V) where the package is
//! installed, and programs of this test's own: G92 and G92.1 on U V W, G10
//! L2 and L20 setting their offsets, G55, G91 increments, G20 inches, arcs
//! in each plane with U V W moving beside them, G28 through a U V W point,
//! G53, and the coordinate system parameters of U V W (#5227…, #5247…).
//!
//! Without `/usr/bin/python3` and its `gcode` module the test skips, saying
//! so, unless `KEZURI_REQUIRE_RS274` is set (CI), where it fails.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Both sides print full precision: a difference is a real one.
const TOLERANCE: f64 = 1e-6;

/// One motion: its kind, the source line and the nine axes' end point.
#[derive(Clone, Debug, PartialEq)]
struct Motion {
    kind: String,
    line: u32,
    end: [f64; 9],
}

/// Whether LinuxCNC's preview parser is here; when it is not, whether the
/// test must fail (`KEZURI_REQUIRE_RS274`) or skip.
fn parser_here() -> bool {
    let here = Command::new("/usr/bin/python3")
        .args(["-c", "import gcode"])
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !here {
        assert!(
            std::env::var_os("KEZURI_REQUIRE_RS274").is_none(),
            "LinuxCNC's preview parser (/usr/bin/python3, import gcode) is required and missing"
        );
        eprintln!("LinuxCNC's preview parser (python3's gcode module, package linuxcnc-uspace) is not here: skipped");
    }
    here
}

/// The parser's motions of `file`, or the error it stopped with.
fn linuxcnc(file: &Path, scratch: &Path) -> Result<Vec<Motion>, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rs274/nine_axes.py");
    // A parameter file of its own: the parser writes it back at the end.
    let vars = scratch.join(format!("{}.var", file.file_stem().unwrap().to_string_lossy()));
    std::fs::write(&vars, "").unwrap();
    let o = Command::new("/usr/bin/python3")
        .arg(&script)
        .arg(file)
        .arg(&vars)
        .current_dir(file.parent().unwrap())
        .stdin(Stdio::null())
        .output()
        .expect("python3 runs");
    let text = String::from_utf8_lossy(&o.stdout);
    let mut motions = Vec::new();
    for l in text.lines() {
        let f: Vec<&str> = l.split_whitespace().collect();
        match f.first() {
            Some(&"error") => return Err(l.to_string()),
            Some(&"result") => return Ok(motions),
            Some(kind) => motions.push(Motion {
                kind: kind.to_string(),
                line: f[1].parse().unwrap(),
                end: std::array::from_fn(|k| f[2 + k].parse().unwrap()),
            }),
            None => {}
        }
    }
    Err(format!("the parser ended without a result: {}", String::from_utf8_lossy(&o.stderr)))
}

/// kezuri's motions of `file` (`run --dialect linuxcnc --emit csv`, read by
/// its header: `u,v,w` are there where the program moves them).
fn kezuri(file: &Path) -> Result<Vec<Motion>, String> {
    let o = common::kezuri(&["run", &file.to_string_lossy(), "--dialect", "linuxcnc", "--emit", "csv"]);
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let axes: Vec<Option<usize>> = ["x", "y", "z", "a", "b", "c", "u", "v", "w"].iter().map(|a| column(a)).collect();
    Ok(lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Motion {
                kind: f[1].to_string(),
                line: f[0].parse().unwrap(),
                end: std::array::from_fn(|k| axes[k].map_or(0.0, |c| f[c].parse().unwrap())),
            }
        })
        .collect())
}

/// The motions that go somewhere: a straight move to where the tool is
/// (the two make such moves in different places, G28's intermediate point)
/// is left out on both sides.
fn moving(motions: Vec<Motion>) -> Vec<Motion> {
    let mut at = [f64::NAN; 9];
    let mut out = Vec::new();
    for m in motions {
        let stays = (0..9).all(|k| (m.end[k] - at[k]).abs() <= TOLERANCE);
        at = m.end;
        if !(stays && matches!(m.kind.as_str(), "rapid" | "feed")) {
            out.push(m);
        }
    }
    out
}

/// Runs `file` through both and compares; the motions compared.
fn agree(file: &Path, scratch: &Path) -> usize {
    let theirs = moving(linuxcnc(file, scratch).unwrap_or_else(|e| panic!("{}: LinuxCNC: {e}", file.display())));
    let ours = moving(kezuri(file).unwrap_or_else(|e| panic!("{}: kezuri: {e}", file.display())));
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        let off = (0..9).find(|&i| (a.end[i] - b.end[i]).abs() > TOLERANCE);
        assert!(
            a.kind == b.kind && off.is_none(),
            "{}: motion {k} differs at axis {:?}:\n  kezuri   {a:?}\n  LinuxCNC {b:?}",
            file.display(),
            off.map(|i| "XYZABCUVW".as_bytes()[i] as char)
        );
    }
    assert_eq!(ours.len(), theirs.len(), "{}: motion counts differ", file.display());
    // The program moves U V W: the comparison is not of zeros alone.
    assert!(theirs.iter().any(|m| m.end[6..].iter().any(|&v| v != 0.0)), "{}: no U V W motion", file.display());
    theirs.len()
}

/// Programs of this test's own, each a piece of U V W the two must agree on.
const PROGRAMS: &[(&str, &str)] = &[
    (
        // G92 on U V W (and X), G92.1, moves beside X Y.
        "g92.ngc",
        "G21 G90 G17\nG0 X0 Y0 Z0 U0 V0 W0\nG92 U10 V-2 X1\nG1 X10 U5 V3 F100\nG0 U0 V0 W2\nG92.1\n\
         G1 X5 U5 W-1\nG0 X0 Y0 U0 V0 W0\nM2\n",
    ),
    (
        // G10 L2 on P1 (in force) and P2, then G55; G10 L20 on U.
        "g10.ngc",
        "G21 G90\nG0 X0 Y0 U0 V0\nG10 L2 P1 U3 V4 W5\nG0 U1 V1 W1\nG10 L2 P2 X10 U-7\nG55 G0 X1 U1\n\
         G10 L20 P2 U20\nG0 U25 V0\nG54 G0 U0 V0 W0\nM2\n",
    ),
    (
        // G91 increments on U V W alone and with X Y Z; a U V W-only feed.
        "g91.ngc",
        "G21 G90\nG0 X1 Y2 Z3 U4 V5 W6\nG91 G1 U2 W-1 F200\nG1 X1 U1 V1\nG0 W3\nG1 X-2 Y-2 Z-2 U-2 V-2 W-2\nG90\n\
         G1 U0 V0 W0\nM2\n",
    ),
    (
        // Arcs with U V W moving beside them, in G17, G18 and G19, by I J K
        // and by R, and a full circle with a turn of W.
        "arcs.ngc",
        "G21 G90 G17\nG0 X0 Y0 Z0 U0 V0 W0\nG2 X20 Y0 I10 J0 U7 F300\nG3 X0 Y0 R10 V-3 W2\n\
         G18 G2 X10 Z0 I5 K0 U1\nG19 G3 Y10 Z0 J5 K0 W-4\nG17 G2 X10 Y10 I5 J0 U2 V2 W2\nM2\n",
    ),
    (
        // Inches: U V W in G20 as X Y Z are.
        "inch.ngc",
        "G20 G90\nG0 X0 Y0 U0\nG1 X1 U2 V-0.5 F10\nG10 L2 P1 W0.1\nG0 W1\nG21 G0 U10\nM2\n",
    ),
    (
        // G28 through a point on U W, the home on U V W parameters (#5167…
        // are 0 with an empty parameter file); G53 on W; G30.
        "home.ngc",
        "G21 G90\nG0 X5 U6 V7 W8\nG28 U1 W2\nG0 U3 V3 W3\nG53 G0 W-5\nG0 W1\nG30 V4\nG28\nM2\n",
    ),
    (
        // The coordinate system parameters of U V W: G55's #5247–#5249 and
        // G54's #5227, read and written, and G52 on U. The parameters are
        // in the machine's units (mm for kezuri, inches for the preview
        // parser's machine): the program only copies them and takes their
        // ratios, so both machines reach the same places.
        "params.ngc",
        "G21 G90\nG10 L2 P2 U11 V12 W13\n#5249=[#5247*2]\nG55 G0 U0 V0 W0\n#5227=#5248\n\
         G0 U[10*#5247/#5248] V[#5249/#5247]\nG52 U5\nG0 U0\nG52 U0\nG54 G0 U0 V0 W0\nM2\n",
    ),
];

#[test]
fn uvw_moves_agree_with_linuxcnc() {
    if !parser_here() {
        return;
    }
    let scratch = tempfile::tempdir().unwrap();
    let mut files: Vec<PathBuf> = Vec::new();
    for (name, text) in PROGRAMS {
        let f = scratch.path().join(name);
        std::fs::write(&f, text).unwrap();
        files.push(f);
    }
    for shipped in [
        "/usr/share/linuxcnc/ncfiles/cone.ngc",
        "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/foam/foam.ngc",
    ] {
        if Path::new(shipped).is_file() {
            files.push(shipped.into());
        } else {
            eprintln!("{shipped} is not here: not compared");
        }
    }
    for f in &files {
        let n = agree(f, scratch.path());
        eprintln!("{}: {n} motions agree", f.display());
    }
}

/// A foam cutter's move: U V alone, then X Y with U beside them.
const UV_ONLY_THEN_XY: &str = "G21 G90\nG0 X0 Y0 U0\nG1 U3 V4 F60\nG1 X3 Y4 U10 F60\nM2\n";

#[test]
fn check_reports_uvw_and_feeds_them_as_linuxcnc_does() {
    let dir = tempfile::tempdir().unwrap();
    let nc = common::path(dir.path(), "uv.ngc");
    std::fs::write(&nc, UV_ONLY_THEN_XY).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&common::ok(&common::kezuri(&["check", &nc, "--dialect", "linuxcnc", "--json"]))).unwrap();
    // LinuxCNC's G-code reference, "Feed Rate": line 3 moves only U V, so
    // F60 is along U V: √(3² + 4²) = 5 mm in 5 s; line 4 moves X Y, so F60
    // is along X Y, 5 mm in 5 s, U following. 10 s, and the acceleration's
    // few milliseconds. The feed length is the tool tip's: X Y's 5 mm.
    let time = json["time_s"].as_f64().unwrap();
    assert!((10.0..10.01).contains(&time), "{time}");
    assert_eq!(json["feed_length_mm"].as_f64(), Some(5.0));
    // U from 0 to 10; V known only where line 3 names it (4); W never named.
    assert_eq!(json["uvw_bounds"], serde_json::json!({"min": [0.0, 4.0, null], "max": [10.0, 4.0, null]}));
    // The CSV has u,v,w after the nine columns.
    let csv = common::ok(&common::kezuri(&["run", &nc, "--dialect", "linuxcnc", "--emit", "csv"]));
    assert!(csv.starts_with("line,kind,x,y,z,a,b,c,feed,u,v,w\n"), "{csv}");
    assert!(csv.contains("\n4,feed,3,4,0,0,0,0,60,10,4,0\n"), "{csv}");
}

#[test]
fn uvw_are_written_for_linuxcnc_and_refused_where_they_cannot_be() {
    let dir = tempfile::tempdir().unwrap();
    let nc = common::path(dir.path(), "uv.ngc");
    std::fs::write(&nc, UV_ONLY_THEN_XY).unwrap();
    // LinuxCNC's program names U V W where the blocks did, and runs back to
    // the same motions.
    let written = common::ok(&common::kezuri(&["run", &nc, "--dialect", "linuxcnc", "--emit", "linuxcnc"]));
    assert!(written.contains("\nG1 U3. V4. F60.\nX3. Y4. U10.\n"), "{written}");
    let again = common::path(dir.path(), "again.ngc");
    std::fs::write(&again, &written).unwrap();
    let csv = |f: &str| common::ok(&common::kezuri(&["run", f, "--dialect", "linuxcnc", "--emit", "csv"]));
    let rows = |t: String| t.lines().skip(1).map(|l| l.split_once(',').unwrap().1.to_string()).collect::<Vec<_>>();
    assert_eq!(rows(csv(&again)), rows(csv(&nc)));
    // Fanuc and GRBL have no U V W: refused, never dropped.
    for dialect in ["fanuc", "grbl"] {
        let o = common::kezuri(&["run", &nc, "--dialect", "linuxcnc", "--emit", dialect]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(&format!("{dialect} has no axis U")), "{err}");
    }
    // The simulation cuts at X Y Z: it refuses what U V W would change.
    let png = common::path(dir.path(), "uv.png");
    let o = common::kezuri(&["sim", &nc, "--dialect", "linuxcnc", "--tool", "flat:6", "-o", &png]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("line 3 moves U: the simulation cuts with the tool at X Y Z"), "{err}");
}
