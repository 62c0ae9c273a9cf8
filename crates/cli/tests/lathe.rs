//! Turning programs on the command line: the machine file's lathe keys, the
//! dialect its kind chooses, and what `check --json` and `run --emit csv`
//! say of a lathe program (docs/lathe.md).

mod common;
#[allow(dead_code)]
mod rs274;

use common::{kezuri, ok, path};
use serde_json::Value;

/// Writes `files` into a new folder.
fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

/// `check --json` of `nc` on `machine` (when given): its object.
fn check(dir: &tempfile::TempDir, nc: &str, machine: Option<&str>) -> Value {
    let (nc, m) = (path(dir.path(), nc), machine.map(|m| path(dir.path(), m)));
    let mut args = vec!["check", nc.as_str(), "--json"];
    if let Some(m) = &m {
        args.extend(["--machine", m.as_str()]);
    }
    serde_json::from_str(&ok(&kezuri(&args))).unwrap()
}

const LATHE: &str = "[machine]\nkind = \"lathe\"\n";
const MILL_TURN: &str = "[machine]\nkind = \"mill-turn\"\nmax_rpm = 4000\n";
const MILL: &str = "[machine]\nkind = \"mill\"\n";
/// A lathe in G code system B with X a radius: G95 is feed per revolution
/// there, and X words are the tool's distance from the spindle axis.
const LATHE_B_RADIUS: &str = "[machine]\nkind = \"lathe\"\nx = \"radius\"\ngcode_system = \"B\"\nmax_rpm = 3000\n";

#[test]
fn the_machine_files_kind_reads_fanuc_and_haas_as_a_lathes() {
    let dir = folder(&[
        ("lathe.toml", LATHE),
        ("mill-turn.toml", MILL_TURN),
        ("mill.toml", MILL),
        ("o1.nc", "%\nO0001\nG21\nG00 X40. Z2.\nM30\n%\n"),
        ("plain.nc", "G21\nG00 X40. Z2.\nM30\n"),
        ("haas.nc", "G21\nG154 P1\nG00 X40. Z2.\nM30\n"),
        ("lcnc.ngc", "G21 G18\nG0 X40 Z2\nM2\n"),
    ]);
    let said = |nc: &str, m: Option<&str>| {
        let v = check(&dir, nc, m);
        (v["dialect"].as_str().unwrap().to_string(), v["dialect_reason"].as_str().unwrap().to_string())
    };
    let on_lathe = "; a lathe's, by the machine file's kind = \"lathe\"";
    assert_eq!(said("o1.nc", Some("lathe.toml")), ("fanuc-lathe".into(), format!("O0001 on line 2{on_lathe}")));
    assert_eq!(
        said("plain.nc", Some("lathe.toml")),
        ("fanuc-lathe".into(), format!("the default (no extension or marker of another dialect){on_lathe}"))
    );
    assert_eq!(said("haas.nc", Some("lathe.toml")), ("haas-lathe".into(), format!("G154 on line 2{on_lathe}")));
    assert_eq!(
        said("o1.nc", Some("mill-turn.toml")),
        ("fanuc-lathe".into(), "O0001 on line 2; a lathe's, by the machine file's kind = \"mill-turn\"".into())
    );
    // A mill's file, or none, leaves the mill's reading; LinuxCNC turns in
    // its own dialect (G7, G18).
    assert_eq!(said("o1.nc", Some("mill.toml")), ("fanuc".into(), "O0001 on line 2".into()));
    assert_eq!(said("o1.nc", None), ("fanuc".into(), "O0001 on line 2".into()));
    assert_eq!(said("lcnc.ngc", Some("lathe.toml")), ("linuxcnc".into(), "the extension .ngc".into()));
    // --dialect names the family; the machine says it turns.
    let nc = path(dir.path(), "plain.nc");
    let m = path(dir.path(), "lathe.toml");
    let v: Value =
        serde_json::from_str(&ok(&kezuri(&["check", &nc, "--json", "--machine", &m, "--dialect", "haas"]))).unwrap();
    assert_eq!(v["dialect"], "haas-lathe");
    assert_eq!(v["dialect_reason"], format!("given with --dialect{on_lathe}"));
    let v: Value = serde_json::from_str(&ok(&kezuri(&["check", &nc, "--json", "--dialect", "fanuc-lathe"]))).unwrap();
    assert_eq!(
        (v["dialect"].as_str(), v["dialect_reason"].as_str()),
        (Some("fanuc-lathe"), Some("given with --dialect"))
    );
    // The text report says it too.
    let text = ok(&kezuri(&["check", &nc, "--machine", &m]));
    assert!(
        text.contains(&format!(
            "dialect fanuc-lathe: the default (no extension or marker of another dialect){on_lathe}"
        )),
        "{text}"
    );
}

#[test]
fn linuxcnc_on_a_lathe_starts_as_linuxcnc_does() {
    // rs274 powers on in G8, X a radius, whatever the machine: the machine
    // file's lathe conventions are a Fanuc or Haas lathe's.
    let dir = folder(&[("lathe.toml", LATHE), ("a.ngc", "G18 G21\nG0 X40 Z2\nG1 Z-10 F100\nM2\n")]);
    let csv = ok(&kezuri(&[
        "run",
        &path(dir.path(), "a.ngc"),
        "--machine",
        &path(dir.path(), "lathe.toml"),
        "--emit",
        "csv",
    ]));
    let xs: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap().parse().unwrap()).collect();
    assert_eq!(xs, [40.0, 40.0], "{csv}");
}

#[test]
fn a_bad_lathe_key_is_refused_naming_it() {
    let dir = folder(&[
        ("kind.toml", "[machine]\nkind = \"turret\"\n"),
        ("tip.toml", "[machine]\nkind = \"lathe\"\n[tools.T1]\ntip = 3\n"),
        ("x.toml", "[machine]\nx = \"diameter\"\n"),
        ("a.nc", "G21\nG00 X40. Z2.\nM30\n"),
    ]);
    let nc = path(dir.path(), "a.nc");
    for (file, words) in [
        ("kind.toml", "machine.kind: 'turret' is not a kind of machine: \"mill\", \"lathe\" or \"mill-turn\""),
        ("tip.toml", "tools.T1.tip = 3 with no tools.T1.nose_radius"),
        ("x.toml", "machine.x is a lathe's: the machine is a mill"),
    ] {
        let o = kezuri(&["check", &nc, "--machine", &path(dir.path(), file)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(words), "{file}: {err}");
        assert!(err.contains(file), "the error names the file: {err}");
    }
}

/// A turning program in G18 with feed per revolution (G95, system B) and
/// two spindle speeds, X a radius on this machine.
///
/// By hand: G95 makes F the feed per revolution (FANUC Series 0i-TF Plus
/// Operator's Manual (B-64604EN), lathe system, "Feed per revolution"): the
/// feed along the path is F × S mm/min.
/// - N30 Z2 → Z-40 at S800, F0.25: 0.25 × 800 = 200 mm/min over 42 mm:
///   12.6 s.
/// - N50 X30 Z-40 → X40 Z-50 at S1200, F0.2: 240 mm/min over √200 =
///   14.1421 mm: 3.5355 s.
/// - Cutting speeds 800 and 1200 rpm: spindle_rpm [800, 1200].
const FEED_PER_REV: &str = "%\nO0002\nN10 G18 G21 G40\nN20 G97 S800 M03\nN25 G00 X30. Z2.\n\
                            N30 G95 G01 Z-40. F0.25\nN40 S1200\nN50 X40. Z-50. F0.2\nN60 G00 X60. Z10.\nN70 M05\nN80 M30\n%\n";

#[test]
fn check_reports_the_spindle_speeds_and_the_time_per_revolution() {
    let dir = folder(&[
        ("m.toml", LATHE_B_RADIUS),
        ("a.nc", FEED_PER_REV),
        ("still.nc", "G18 G21 G94\nG00 X40. Z2.\nG01 Z-10. F100.\nM30\n"),
    ]);
    let v = check(&dir, "a.nc", Some("m.toml"));
    assert_eq!(v["dialect"], "fanuc-lathe");
    assert_eq!(v["spindle_rpm"], serde_json::json!([800.0, 1200.0]));
    let feed_s = 42.0 / 200.0 * 60.0 + 200f64.sqrt() / 240.0 * 60.0;
    assert!((feed_s - 16.1355).abs() < 1e-3, "{feed_s}");
    // The same moves at the same feeds per minute (G94 F200, F240) take
    // the same time to the microsecond; the rapids (from X0 Z0 to X30 Z2,
    // X40 Z-50 to X60 Z10: 93 mm at 10 m/min, 0.56 s) and the acceleration
    // add about a second.
    let per_minute = FEED_PER_REV.replace("G95 G01 Z-40. F0.25", "G94 G01 Z-40. F200.").replace("F0.2\n", "F240.\n");
    std::fs::write(dir.path().join("per-minute.nc"), per_minute).unwrap();
    let same = check(&dir, "per-minute.nc", Some("m.toml"))["time_s"].as_f64().unwrap();
    let time = v["time_s"].as_f64().unwrap();
    assert!((time - same).abs() < 1e-6, "per revolution {time} s, per minute {same} s");
    assert!(time > feed_s + 0.56 && time < feed_s + 1.5, "time {time} s, feeds alone {feed_s} s");
    assert!((v["feed_length_mm"].as_f64().unwrap() - (42.0 + 200f64.sqrt())).abs() < 1e-9, "{v}");
    // X is a radius: the bounds are the tool's distances from the axis.
    assert_eq!(v["bounds"]["max"][0], 60.0);
    assert_eq!(v["threads"], serde_json::json!([]));
    // No spindle speed anywhere: null, as an axis without a position is.
    let v = check(&dir, "still.nc", Some("m.toml"));
    assert_eq!(v["spindle_rpm"], Value::Null);
    let text = ok(&kezuri(&["check", &path(dir.path(), "still.nc"), "--machine", &path(dir.path(), "m.toml")]));
    assert!(!text.contains("spindle"), "{text}");
    // One speed is said once.
    let one = FEED_PER_REV.replace("N40 S1200\n", "");
    std::fs::write(dir.path().join("one.nc"), one).unwrap();
    assert_eq!(check(&dir, "one.nc", Some("m.toml"))["spindle_rpm"], serde_json::json!([800.0, 800.0]));
    let text = ok(&kezuri(&["check", &path(dir.path(), "one.nc"), "--machine", &path(dir.path(), "m.toml")]));
    assert!(text.contains("  spindle 800 rpm (cutting)\n"), "{text}");
    // The text report's line.
    let text = ok(&kezuri(&["check", &path(dir.path(), "a.nc"), "--machine", &path(dir.path(), "m.toml")]));
    assert!(text.contains("  spindle 800 … 1200 rpm (cutting)\n"), "{text}");
    // X is said to be a radius; the Y the program never places is not said.
    assert!(text.contains("  X     30.000 …     60.000 (radius)\n"), "{text}");
    assert!(!text.contains("  Y "), "{text}");
}

#[test]
fn run_csv_gives_x_as_the_tools_radius() {
    let dir = folder(&[("m.toml", LATHE_B_RADIUS), ("a.nc", FEED_PER_REV)]);
    let csv =
        ok(&kezuri(&["run", &path(dir.path(), "a.nc"), "--machine", &path(dir.path(), "m.toml"), "--emit", "csv"]));
    let rows: Vec<(String, f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1].to_string(), f[2].parse().unwrap(), f[4].parse().unwrap())
        })
        .collect();
    let want = [("rapid", 30.0, 2.0), ("feed", 30.0, -40.0), ("feed", 40.0, -50.0), ("rapid", 60.0, 10.0)];
    assert_eq!(rows.len(), want.len(), "{csv}");
    for ((kind, x, z), (k, wx, wz)) in rows.iter().zip(want) {
        assert_eq!((kind.as_str(), *x, *z), (k, wx, wz), "{csv}");
    }
}

#[test]
fn a_linuxcnc_lathe_table_gives_each_tools_nose() {
    // Lines of LinuxCNC's sim lathe tool table (sample-configs/sim/axis/
    // lathe.tbl), in mm here: D the nose diameter, Q the orientation.
    let tbl = "T1 P1 D0.8 Z+0.1 I+95 J+155 Q1 ;\nT2 P2 D0.8 I+85 J+25 Q2 ;\nT3 P3 D0.4 I+275 J+335 Q3 ;\n\
               T9 P9 D0.1 Q9 ;\nT10 P10 D0. ; demo zero diameter\n";
    let machine = "[machine]\nkind = \"lathe\"\n[tools]\nimport = \"lathe.tbl\"\nunits = \"mm\"\n[tools.T3]\ntip = 2\nnose_radius = 0.2\n";
    let dir = folder(&[("lathe.tbl", tbl), ("m.toml", machine)]);
    let v: Value =
        serde_json::from_str(&ok(&kezuri(&["tool", "table", "--machine", &path(dir.path(), "m.toml"), "--json"])))
            .unwrap();
    let noses: Vec<(u64, Value, Value)> = v["tables"][0]["tools"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| (t["number"].as_u64().unwrap(), t["nose_radius_mm"].clone(), t["tip"].clone()))
        .collect();
    // Q1 (−X, +Z) is Fanuc's tip 4, Q2 (the outside turning tool) tip 3; T3's
    // own entry is over the table's; Q9 the nose centre; T10 no lathe tool.
    let n = |r: f64, tip: u64| (Value::from(r), Value::from(tip));
    let want = [(1, n(0.4, 4)), (2, n(0.4, 3)), (3, n(0.2, 2)), (9, n(0.05, 9)), (10, (Value::Null, Value::Null))];
    assert_eq!(noses.len(), want.len(), "{v}");
    for ((t, r, tip), (wt, (wr, wtip))) in noses.into_iter().zip(want) {
        assert_eq!((t, r, tip), (wt, wr, wtip));
    }
    // The text shows them after the name.
    let text = ok(&kezuri(&["tool", "table", "--machine", &path(dir.path(), "m.toml")]));
    assert!(text.contains("nose 0.4 mm, tip 3"), "{text}");
}

/// Where the point a tool is set to lies from its nose centre, in units of
/// the nose radius (X, Z), for each of Fanuc's imaginary tool tip
/// directions 1–9 (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
/// lathe system, "Imaginary tool nose": seen with X up and Z to the right,
/// 1 upper right, 2 upper left, 3 lower left (the outside turning tool),
/// 4 lower right, 5 right, 6 up, 7 left, 8 down, 9 the centre).
fn fanuc_corner(tip: u64) -> (i32, i32) {
    match tip {
        1 => (1, 1),
        2 => (1, -1),
        3 => (-1, -1),
        4 => (-1, 1),
        5 => (0, 1),
        6 => (1, 0),
        7 => (0, -1),
        8 => (-1, 0),
        _ => (0, 0),
    }
}

#[test]
fn each_linuxcnc_orientation_is_the_fanuc_tip_of_the_same_corner() {
    if !rs274::rs274_here() {
        return;
    }
    // Tools of orientation Q1 … Q9, nose diameter 0.04 inch (radius
    // 0.508 mm); rs274 reads the table in inches.
    let tbl: String = (1..=9).map(|q| format!("T{q} P{q} D0.04 Q{q}\n")).collect();
    let machine = "[machine]\nkind = \"lathe\"\n[tools]\nimport = \"t.tbl\"\nunits = \"inch\"\n";
    let dir = folder(&[("t.tbl", &tbl), ("m.toml", machine)]);
    let v: Value =
        serde_json::from_str(&ok(&kezuri(&["tool", "table", "--machine", &path(dir.path(), "m.toml"), "--json"])))
            .unwrap();
    let tools = v["tables"][0]["tools"].as_array().unwrap().clone();
    // Where rs274 puts the set point at the end of a G42 cut along -Z at X10
    // (the nose centre 0.508 mm off the contour): that end for each Q.
    let end_of_cut = |q: u64| -> (f64, f64) {
        let nc = format!(
            "G18 G21 G90 G40\nT{q} M6 G43\nG0 X20 Z10\nG42 G1 X10 Z5 F100\nG1 Z-20\nG1 X20\nG40 G0 X30 Z10\nM2\n"
        );
        std::fs::write(dir.path().join(format!("q{q}.ngc")), nc).unwrap();
        let mut cmd = std::process::Command::new("rs274");
        cmd.args(["-t", "t.tbl", &format!("q{q}.ngc")]);
        let done = rs274::run_limited(cmd, dir.path(), dir.path(), &format!("q{q}"));
        let feeds: Vec<&str> =
            done.stdout.lines().filter_map(|l| l.split_once("STRAIGHT_FEED(").map(|(_, r)| r)).collect();
        let f: Vec<f64> = feeds[1].trim_end_matches(')').split(',').map(|v| v.trim().parse().unwrap()).collect();
        (f[0], f[2])
    };
    let centre = end_of_cut(9);
    let r = 0.04 * 25.4 / 2.0;
    for q in 1..=8u64 {
        let (x, z) = end_of_cut(q);
        let corner = (((x - centre.0) / r).round() as i32, ((z - centre.1) / r).round() as i32);
        let tip = tools[q as usize - 1]["tip"].as_u64().unwrap();
        assert_eq!(fanuc_corner(tip), corner, "Q{q} read as tip {tip}: rs274 sets it to {corner:?} of the nose");
        assert!((tools[q as usize - 1]["nose_radius_mm"].as_f64().unwrap() - r).abs() < 1e-9);
    }
}

/// A Fanuc lathe program as a shop writes it: system A, X a diameter, the
/// power-on feed per revolution (G99), constant surface speed under a G50
/// clamp, then a G32 thread at a constant speed.
///
/// By hand (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
/// system: "Constant surface speed control", "Feed per revolution",
/// "Thread cutting (G32)"): under G96 the spindle turns at
/// n = 1000 V / (π D) rpm, V in m/min, D the diameter in mm.
/// - N40 puts the tool at Ø50 (X 25 from the axis): n = 150000 / (50 π) =
///   954.930 rpm. N50 turns Ø50 to Z-30 there: 32 mm at 0.2 × 954.930 =
///   190.986 mm/min.
/// - N60 faces out to Ø80: n falls to 150000 / (80 π) = 596.831 rpm. The
///   tool moves out at dr/dt = f n(r) = f V / (2 π r), so the move takes
///   t = π (r1² − r0²) / (f V) = π (40² − 25²) / (0.2 × 150000) min =
///   6.1261 s; at F0.1 twice that.
/// - N100 cuts a thread of lead 1.5 at G97 S600 from X 9.5 (Ø19), Z5 to
///   Z-20 (line 12 of the file).
/// - The cutting speeds run from 596.831 (N60's end) to 954.930 rpm
///   (N50); the thread's 600 is between.
const CSS: &str = "%\nO0003\nN10 G50 S2000\nN20 T0101\nN30 G96 S150 M03\nN40 G00 X50. Z2.\nN50 G01 Z-30. F0.2\n\
                   N60 X80.\nN70 G00 X100. Z5.\nN80 G97 S600\nN90 G00 X19. Z5.\nN100 G32 Z-20. F1.5\nN110 G00 X30.\n\
                   N120 M30\n%\n";

/// A lathe's T word is the tool and its offset (FANUC Series 0i-TF Plus
/// Operator's Manual, B-64604EN, lathe system, "Tool function": T0101 tool
/// 1 with offset 1): check says what each T word selected, never an H
/// register the lathe has not.
#[test]
fn check_names_what_a_lathes_t_words_selected() {
    let text = "%\nO0004\nT0101\nG97 S1000 M03\nG00 X50. Z2.\nG01 Z-10. F0.2\nT0111\nG01 Z-20.\n\
                T0202\nG00 X60. Z5.\nM30\n%\n";
    let machine = "[machine]\nkind = \"lathe\"\n[tools.T1]\nnose_radius = 0.8\ntip = 3\nname = \"OD finish\"\n";
    let dir = folder(&[("m.toml", machine), ("a.nc", text)]);
    let out = ok(&kezuri(&["check", &path(dir.path(), "a.nc"), "--machine", &path(dir.path(), "m.toml")]));
    assert!(out.contains("  tool  T0101, T0111 (tool 1, offsets 1, 11) nose 0.8 mm tip 3 (OD finish)\n"), "{out}");
    assert!(out.contains("  tool  T0202 (tool 2, offset 2) (not in the tool table)\n"), "{out}");
}

#[test]
fn a_diameter_program_reports_its_speeds_threads_and_time() {
    let slower = CSS.replace("N60 X80.", "N60 X80. F0.1");
    let machine = "[machine]\nkind = \"lathe\"\nmax_rpm = 3000\n[tools.T1]\nnose_radius = 0.8\ntip = 3\n";
    let dir = folder(&[("m.toml", machine), ("a.nc", CSS), ("b.nc", &slower)]);
    let v = check(&dir, "a.nc", Some("m.toml"));
    assert_eq!(v["dialect"], "fanuc-lathe");
    let rpm: Vec<f64> = v["spindle_rpm"].as_array().unwrap().iter().map(|r| r.as_f64().unwrap()).collect();
    assert!((rpm[0] - 596.831).abs() < 1e-3 && (rpm[1] - 954.930).abs() < 1e-3, "{rpm:?}");
    assert_eq!(
        v["threads"],
        serde_json::json!([{"lead": 1.5, "start": [9.5, 0.0, 5.0], "end": [9.5, 0.0, -20.0], "line": 12}])
    );
    // X is a radius everywhere: the bounds reach X 50 (Ø100 at N70).
    assert_eq!((v["bounds"]["min"][0].as_f64(), v["bounds"]["max"][0].as_f64()), (Some(9.5), Some(50.0)));
    // T0101 is tool 1, with its nose.
    let t1 = &v["tools"][0];
    assert_eq!(
        (t1["number"].as_u64(), t1["nose_radius_mm"].as_f64(), t1["tip"].as_u64()),
        (Some(1), Some(0.8), Some(3))
    );
    // A lathe's tool is offset by T0101, not G43: no warning of Z moves.
    assert_eq!(v["warnings"], serde_json::json!([]));
    // N60 at half the feed per revolution takes its 6.1261 s again.
    let t = |nc: &str| check(&dir, nc, Some("m.toml"))["time_s"].as_f64().unwrap();
    let more = t("b.nc") - t("a.nc");
    assert!((more - 6.1261).abs() < 2e-3, "N60 at F0.1 took {more} s more");
    // The text report.
    let text = ok(&kezuri(&["check", &path(dir.path(), "a.nc"), "--machine", &path(dir.path(), "m.toml")]));
    assert!(text.contains("  spindle 597 … 955 rpm (cutting)\n"), "{text}");
    // A lathe has no H register: T0101 selected tool 1 with offset 1.
    assert!(text.contains("  tool  T0101 (tool 1, offset 1) nose 0.8 mm tip 3\n"), "{text}");
    assert!(!text.contains(" H1"), "{text}");
    assert!(text.contains("  thread lead 1.5000 mm, Z 5.000 → -20.000, 1 pass, X 9.500 (radius; line 12)\n"), "{text}");
    // run --emit csv: x is the tool's radius, half of each X word.
    let csv =
        ok(&kezuri(&["run", &path(dir.path(), "a.nc"), "--machine", &path(dir.path(), "m.toml"), "--emit", "csv"]));
    let xs: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap().parse().unwrap()).collect();
    assert_eq!(xs, [25.0, 25.0, 40.0, 50.0, 9.5, 9.5, 15.0], "{csv}");
}

#[test]
fn constant_surface_speed_without_a_clamp_runs_to_max_rpm() {
    // Facing from Ø50 to Ø2 at 150 m/min asks for 150000 / (2 π) = 23873
    // rpm at the end; with no G50 S the spindle stops at the machine's 3000.
    let nc = "%\nO0004\nN10 T0101\nN20 G96 S150 M03\nN30 G00 X50. Z0.\nN40 G01 X2. F0.1\nN50 G00 Z5.\nN60 M30\n%\n";
    let dir = folder(&[("m.toml", "[machine]\nkind = \"lathe\"\nmax_rpm = 3000\n"), ("a.nc", nc)]);
    let v = check(&dir, "a.nc", Some("m.toml"));
    let rpm: Vec<f64> = v["spindle_rpm"].as_array().unwrap().iter().map(|r| r.as_f64().unwrap()).collect();
    assert!((rpm[0] - 954.930).abs() < 1e-3 && rpm[1] == 3000.0, "{rpm:?}");
    let warnings = v["warnings"].to_string();
    assert!(warnings.contains("3000 rpm"), "{warnings}");
}

#[test]
fn a_haas_lathes_u_is_an_incremental_diameter() {
    // By hand (Haas Lathe Operator's Manual, "U and W incremental"; FANUC
    // Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system, G code
    // system A): X40. puts the tool 20 mm from the axis; U-10. takes 10 mm
    // off the diameter, 5 off the radius (X 15), W-21. goes Z 1 → -20;
    // W-10. to Z-30; U20. W31. back out to X 25, Z1. The feed per
    // revolution F0.1 at S1000 is 100 mm/min.
    let nc = "%\nO00010\nT101\nG50 S2500\nG97 S1000 M03\nG00 X40. Z1.\nG01 U-10. W-21. F0.1\nG01 W-10.\n\
              G00 U20. W31.\nM30\n%\n";
    let dir = folder(&[("h.nc", nc)]);
    let csv = ok(&kezuri(&["run", &path(dir.path(), "h.nc"), "--dialect", "haas-lathe", "--emit", "csv"]));
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    let got: Vec<(&str, &str, &str, &str)> =
        rows.iter().map(|r| (r[1].as_str(), r[2].as_str(), r[4].as_str(), r[8].as_str())).collect();
    assert_eq!(
        got,
        [
            ("rapid", "20", "1", ""),
            ("feed", "15", "-20", "100"),
            ("feed", "15", "-30", "100"),
            ("rapid", "25", "1", "")
        ],
        "{csv}"
    );
    let v: Value =
        serde_json::from_str(&ok(&kezuri(&["check", &path(dir.path(), "h.nc"), "--dialect", "haas-lathe", "--json"])))
            .unwrap();
    assert_eq!(
        (v["dialect"].as_str(), v["spindle_rpm"].clone()),
        (Some("haas-lathe"), serde_json::json!([1000.0, 1000.0]))
    );
    assert_eq!(v["warnings"], serde_json::json!([]));
}
