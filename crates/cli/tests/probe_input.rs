//! `kezuri probe level|export|mill` on what users feed them: every input
//! format (the paper's `No,Z` files, capture files, `x,y,z` CSV, LinuxCNC
//! probe logs) read with the defaults of CLI.md, and bad data refused by
//! every command with exit code 1, a message naming the file, the line and
//! (for a bad field) the column, and no file written, not even a temporary
//! one.

use std::path::Path;

mod common;
use common::{kezuri, ok, path};

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// Runs `args` (which write only into `out`), expecting exit code 1, stderr
/// containing `message`, and `out` left empty.
fn refused(args: &[&str], message: &str, out: &Path) {
    let o = kezuri(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(err.contains(message), "{args:?}: expected {message:?} in {err}");
    assert!(listing(out).is_empty(), "{args:?}: wrote {:?}", listing(out));
}

/// The 3 × 2 grid the cases below describe, as a bare `No,Z` file in
/// zig-zag order (the paper's `0,0` first): z = 10·i + j at node (i, j).
const BARE: &str = "0,0\n1,0\n2,10\n3,20\n4,21\n5,11\n6,1\n";

#[test]
fn bad_data_is_refused_by_level_export_and_mill_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let o = |name: &str| path(&out, name);
    let grid = ["--count", "3,2", "--pitch", "1"];
    // (file name, contents, needs --count/--pitch, what stderr must say after "NAME: ")
    let cases: &[(&str, &str, bool, &str)] = &[
        ("short.txt", "0,0\n1,0\n2,10\n3,20\n4,21\n5,11\n", true, "line 6: 5 points, but the 3 × 2 grid has 6"),
        ("long.txt", "1,0\n2,10\n3,20\n4,21\n5,11\n6,1\n7,2\n", true, "line 7: more points than the 3 × 2 grid holds"),
        ("word.txt", "1,0\n2,10\n3,abc\n4,21\n5,11\n6,1\n", true, "line 3, column 3: 'abc' is not a number"),
        (
            "nan.txt",
            "1,0\n2,10\n3,20\n4, NaN\n5,11\n6,1\n",
            true,
            "line 4, column 4: 'NaN' must be a coordinate from -1000000 to 1000000 mm, got NaN",
        ),
        ("gap.txt", "1,0\n2,10\n4,21\n5,11\n6,1\n", true, "line 3: point No 4 where No 3 was expected"),
        ("no.txt", "1,0\n2,10\nthree,20\n4,21\n5,11\n6,1\n", true, "line 3, column 1: point number 'three'"),
        ("bare.txt", BARE, false, "a bare No,Z file does not say its grid: give --count NX,NY"),
        ("empty.txt", "\n# nothing\n", true, "no data: the file has no points"),
        ("junk.txt", "hello world\n", true, "line 1: 'hello world': expected a `# grid …` header"),
        (
            "capture.txt",
            "# grid nx=3 ny=2 pitch=1 origin=0,0 pattern=zigzag\nNo,Z\n1,0\n2,10\n3,20\n4,21\n5,11\n",
            false,
            "line 7: 5 points, but the 3 × 2 grid has 6 (an unfinished capture",
        ),
        (
            "header.txt",
            "# grid nx=3 ny=2 pitch=x\nNo,Z\n",
            false,
            "line 1, column 18: grid header: pitch=x is not a number",
        ),
        (
            "other.txt",
            "# grid nx=4 ny=2 pitch=1\nNo,Z\n",
            true,
            "line 1: the header's grid is 4 × 2, --count says 3 × 2",
        ),
        ("word.csv", "x,y,z\n0,0,0\n1,0,10\n2,0,2O\n", false, "line 4, column 5: '2O' is not a number"),
        (
            "nan.csv",
            "x,y,z\n0,0,0\n1,0,NaN\n",
            false,
            "line 3, column 5: 'NaN' must be a coordinate from -1000000 to 1000000 mm, got NaN",
        ),
        ("two.csv", "x,y,z\n0,0,0\n1,0\n", false, "line 3: expected three numbers x,y,z, got '1,0'"),
        ("again.csv", "x,y,z\n0,0,0\n1,0,1\n0,1,2\n0,0,3\n", false, "line 5: a second height at (0, 0)"),
        ("holes.csv", "x,y,z\n0,0,0\n1,0,1\n2,0,2\n0,1,3\n1,1,4\n", false, "the 5 points are not a regular grid"),
        (
            "inf.ngc",
            "0 0 0 0 0 0 0 0 0\n1 0 inf 0 0 0 0 0 0\n",
            false,
            "line 2, column 5: 'inf' must be a coordinate from -1000000 to 1000000 mm, got inf",
        ),
        ("two.ngc", "0.000000 0.000000 1.000000\n1.000000 0.000000\n", false, "line 2: expected numbers x y z"),
    ];
    for &(name, text, hint, message) in cases {
        let data = path(dir.path(), name);
        std::fs::write(&data, text).unwrap();
        let expected = format!("{data}: {message}");
        let with_grid = |args: &[&str]| -> Vec<String> {
            let mut v: Vec<String> = args.iter().map(|s| s.to_string()).collect();
            if hint {
                v.splice(3..3, grid.iter().map(|s| s.to_string()));
            }
            v
        };
        let commands = [
            with_grid(&["probe", "level", &data, "-o", &o("level.txt")]),
            with_grid(&["probe", "level", &data, "--json", "-o", &o("level.txt")]),
            with_grid(&[
                "probe",
                "export",
                &data,
                "--dxf",
                &o("a.dxf"),
                "--stl",
                &o("a.stl"),
                "--png",
                &o("a.png"),
                "--csv",
                &o("a.csv"),
            ]),
            with_grid(&["probe", "mill", &data, "--stylus", "ball:10", "--tool", "ball:6", "-o", &o("a.nc")]),
            with_grid(&[
                "probe",
                "mill",
                &data,
                "--stylus",
                "ball:10",
                "--tool",
                "ball:6",
                "--split-bytes",
                "2000",
                "-o",
                &o("a.nc"),
            ]),
        ];
        for args in &commands {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            refused(&args, &expected, &out);
        }
    }
}

#[test]
fn a_reference_region_outside_the_grid_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let data = path(dir.path(), "ume.txt");
    std::fs::write(&data, BARE).unwrap();
    let level = path(&out, "level.txt");
    let mask = |name: &str, text: &str| {
        let p = path(dir.path(), name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let cases = [
        ("rows:1,3".to_string(), format!("{data}: --reference rows:1,3: row 3 is outside the grid's rows 1..2")),
        ("cols:0,2".to_string(), format!("{data}: --reference cols:0,2: column 0 is outside the grid's columns 1..3")),
        ("cols:2,4".to_string(), format!("{data}: --reference cols:2,4: column 4 is outside the grid's columns 1..3")),
        ("rows:2,2".to_string(), "rows 2,2: two different rows are needed".to_string()),
        (
            "mask:".to_string() + &mask("wide.txt", "111\n1,0,1,1\n"),
            "wide.txt: line 2: 4 points, a row of the grid has 3".into(),
        ),
        (
            "mask:".to_string() + &mask("tall.txt", "111\n101\n111\n"),
            "tall.txt: line 3: more rows than the grid's 2".into(),
        ),
        (
            "mask:".to_string() + &mask("two.txt", "1 1 1\n1 2 1\n"),
            "two.txt: line 2, column 3: '2' is not 0 or 1".into(),
        ),
        ("mask:".to_string() + &mask("one.txt", "111\n"), "one.txt: 1 rows, the grid has 2".into()),
        ("mask:".to_string() + &mask("few.txt", "100\n001\n"), "the reference region has fewer than 3 points".into()),
        ("mask:".to_string() + &path(dir.path(), "none.txt"), "cannot read".into()),
    ];
    for (reference, message) in cases {
        let args = ["probe", "level", &data, "--count", "3,2", "--pitch", "1", "--reference", &reference, "-o", &level];
        refused(&args, &message, &out);
    }
}

/// Each format of the same 3 × 2 grid (z = 10·i + j at node (i, j),
/// x = 5 + i·2, y = −3 + j·2 where the file gives coordinates) read back
/// through `probe export --csv`.
#[test]
fn every_input_format_is_read_with_the_stated_defaults() {
    let dir = tempfile::tempdir().unwrap();
    let csv_of = |name: &str, text: &str, extra: &[&str]| -> String {
        let data = path(dir.path(), name);
        std::fs::write(&data, text).unwrap();
        ok(&kezuri(&[&["probe", "export", &data, "--csv", "-"][..], extra].concat()))
    };
    let at_origin = |dx: f64, dy: f64, pitch: f64| {
        let mut s = String::from("x,y,z\n");
        for j in 0..2 {
            for i in 0..3 {
                s += &format!("{},{},{}\n", dx + i as f64 * pitch, dy + j as f64 * pitch, 10 * i + j);
            }
        }
        s
    };
    // The paper's bare file, `0,0` first: --count and --pitch, zig-zag
    // and origin 0,0 by default.
    let paper = csv_of("ume.txt", BARE, &["--count", "3,2", "--pitch", "1"]);
    assert_eq!(paper, at_origin(0.0, 0.0, 1.0));
    // A `No,Z` title, CR LF line ends (DOS), one-way order and an origin.
    let one_way = "No,Z\r\n0,0\r\n1,0\r\n2,10\r\n3,20\r\n4,1\r\n5,11\r\n6,21\r\n";
    let extra = ["--count", "3,2", "--pitch", "2", "--pattern", "oneway", "--origin", "5,-3"];
    assert_eq!(csv_of("oneway.txt", one_way, &extra), at_origin(5.0, -3.0, 2.0));
    // A capture file says its grid; a wrong --count is an error, a right one fine.
    let capture = "# kezuri probe capture\n# grid nx=3 ny=2 pitch=2 origin=5,-3 pattern=zigzag\n\
                   # tip_z = bottom + sign * (reading - zero): bottom=0 sign=1 zero=0\nNo,Z\n\
                   1,0\n2,10\n3,20\n4,21\n5,11\n6,1\n";
    assert_eq!(csv_of("capture.txt", capture, &[]), at_origin(5.0, -3.0, 2.0));
    assert_eq!(csv_of("capture.txt", capture, &["--count", "3,2"]), at_origin(5.0, -3.0, 2.0));
    // CSV x,y,z in any order, with a byte-order mark (spreadsheets write one).
    let csv = "\u{feff}x,y,z\n9,-1,21\n5,-3,0\n7,-1,11\n9,-3,20\n5,-1,1\n7,-3,10\n";
    assert_eq!(csv_of("grid.csv", csv, &[]), at_origin(5.0, -3.0, 2.0));
    // A LinuxCNC probe log: `(PROBEOPEN file)` makes LinuxCNC write the nine
    // coordinates X Y Z A B C U V W of every probe, `%f` each, one line per
    // probe, in the order probed (here zig-zag).
    let mut log = String::new();
    for (i, j) in [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)] {
        let (x, y, z) = (5.0 + 2.0 * i as f64, -3.0 + 2.0 * j as f64, (10 * i + j) as f64);
        log += &format!("{x:.6} {y:.6} {z:.6} 0.000000 0.000000 0.000000 0.000000 0.000000 0.000000\n");
    }
    assert_eq!(csv_of("probe-results.txt", &log, &[]), at_origin(5.0, -3.0, 2.0));
    // A DPRNT log of the g31 plan (`probe plan --style g31`): x y z with
    // Fanuc's leading blanks, and the DC2 / DC4 codes of POPEN / PCLOS.
    let dprnt = "\u{12}\n    5.000   -3.000    0.000\n    7.000   -3.000   10.000\n    9.000   -3.000   20.000\n\
                 \u{20}   9.000   -1.000   21.000\n    7.000   -1.000   11.000\n    5.000   -1.000    1.000\n\u{14}\n";
    assert_eq!(csv_of("dprnt.txt", dprnt, &[]), at_origin(5.0, -3.0, 2.0));
}

/// `probe level` writes the format it read.
#[test]
fn level_writes_the_format_it_read() {
    let dir = tempfile::tempdir().unwrap();
    // A tilt of 0.01 per mm along X on a flat 3 × 3 plate: every reading
    // is on the reference (border) but the centre, 1 mm higher. Levelled,
    // the border lies at its mean height, 10.01.
    let z = |i: usize, j: usize| 10.0 + 0.01 * i as f64 + if (i, j) == (1, 1) { 1.0 } else { 0.0 };
    let zig = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1), (0, 2), (1, 2), (2, 2)];
    let mut bare = String::from("0,0\n");
    let mut log = String::new();
    let mut csv = String::from("x,y,z\n");
    for (k, &(i, j)) in zig.iter().enumerate() {
        bare += &format!("{},{}\n", k + 1, z(i, j));
        log += &format!("{i}.000000 {j}.000000 {:.6} 0 0 0 0 0 0\n", z(i, j));
        csv += &format!("{i},{j},{}\n", z(i, j));
    }
    let capture = format!("# grid nx=3 ny=3 pitch=1\nNo,Z\n{}", &bare[4..]);
    let cases = [
        ("bare.txt", bare.as_str(), "0,0\n1,10.01\n2,10.01\n3,10.01\n4,10.01\n5,11.01\n"),
        ("capture.txt", capture.as_str(), "# grid nx=3 ny=3 pitch=1\n# levelled: "),
        ("log.txt", log.as_str(), "0 0 10.01\n1 0 10.01\n2 0 10.01\n0 1 10.01\n1 1 11.01\n"),
        ("grid.csv", csv.as_str(), "x,y,z\n0,0,10.01\n1,0,10.01\n2,0,10.01\n0,1,10.01\n1,1,11.01\n"),
    ];
    for (name, text, start) in cases {
        let data = path(dir.path(), name);
        std::fs::write(&data, text).unwrap();
        let out = path(dir.path(), &format!("level-{name}"));
        let table =
            ok(&kezuri(&["probe", "level", &data, "--count", "3,3", "--pitch", "1", "--method", "plane", "-o", &out]));
        assert!(table.contains("raw") && table.contains("plane"), "{table}");
        let written = std::fs::read_to_string(&out).unwrap();
        assert!(written.starts_with(start), "{name}: {written}");
    }
}

/// A picture too large to make (a 112 × 112 grid at 64 pixels per pitch is
/// 7105 × 7105 pixels) is refused before anything is written.
#[test]
fn a_picture_too_large_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let data = path(dir.path(), "big.txt");
    let text: String = (1..=112 * 112).map(|k| format!("{k},{}\n", k % 7)).collect();
    std::fs::write(&data, text).unwrap();
    let (png, csv) = (path(&out, "big.png"), path(&out, "big.csv"));
    let args = ["probe", "export", &data, "--count", "112,112", "--pitch", "1", "--csv", &csv, "--png", &png];
    refused(&[&args[..], &["--png-scale", "64"]].concat(), "--png: 7105 × 7105 pixels is more than 50000000", &out);
    ok(&kezuri(&[&args[..], &["--png-scale", "2"]].concat()));
    assert_eq!(listing(&out), ["big.csv", "big.png"]);
}
