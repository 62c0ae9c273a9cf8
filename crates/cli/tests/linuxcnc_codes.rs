//! LinuxCNC codes kezuri runs as `rs274` (LinuxCNC's own interpreter) runs
//! them, compared motion by motion where rs274 is installed: `##n`
//! parameter indirection, the arc radius tolerance (a 0.0254 mm difference
//! on a 50 mm radius runs; 0.0284 mm on a 5 mm radius stops both), `G87`
//! with I J K in G90 and G91; and LinuxCNC's own example `systems.ngc`, 548
//! `G5.1` quadratic splines, whose end points rs274 gives when each G5.1 is
//! read as a G1 to its end (rs274's canon prints a spline without its
//! points). Without rs274 the test skips, as linuxcnc_examples.rs does.

mod common;
#[allow(dead_code)]
mod rs274;

use rs274::{first_difference, kezuri_linuxcnc, rs274, rs274_here, Motion};

/// (name, program, whether rs274 and kezuri both run it).
const PROGRAMS: &[(&str, &str, bool)] = &[
    ("hash.ngc", "G21 G90\n#1=2\n#2=7.5\n#3=3\nG0 X##1 Y#3\n##1=2\nG0 X#2 Y###1\nM2\n", true),
    ("arc50.ngc", "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG2 X100 Y0 I50.0127 J0\nG3 X0 Y0 I-49.9873 J0\nM2\n", true),
    ("arc5.ngc", "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG2 X10 Y0 I5.0142 J0\nM2\n", false),
    ("arc_inch.ngc", "G20 G90 G17\nG0 X0 Y0 Z0\nF10\nG2 X10 Y0 I5.0015 J0\nM2\n", true),
    (
        "g5.ngc",
        "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG5 X10 Y5 I2 J3 P-1 Q4\nG91 G1 X1\nG90 G5 X20 Y0 P0 Q3\nG91 G1 Y1\nG90 G5.1 X30 Y2 I2 J-3\nG5.1 X35 Y0 I1 J1\nX36\nG91 G1 X1\nM2\n",
        true,
    ),
    (
        "g87.ngc",
        "G21 G90 G17\nS1000 M3\nG0 X0 Y0 Z5.\nF100.\nG98 G87 X1 Y1 Z-3 R1 I0.5 J0.5 K-1\nX4 Y2\nG80\nM2\n",
        true,
    ),
    (
        "g87_g91.ngc",
        "G21 G90 G17\nS1000 M3\nG0 X0 Y0 Z5.\nF100.\nG91 G99 G87 X1 Y1 Z-2 R-4 I0.5 J-0.5 K1 L2\nG90 G80\nM2\n",
        true,
    ),
];

#[test]
fn linuxcnc_codes_move_as_rs274_moves_them() {
    if !rs274_here() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("tool.tbl");
    std::fs::write(&table, "T1 P1 Z0.1 D0.06\n").unwrap();
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n").unwrap();
    let mut failures = Vec::new();
    for &(name, text, runs) in PROGRAMS {
        let file = dir.path().join(name);
        std::fs::write(&file, text).unwrap();
        let scratch = dir.path().join(format!("{name}.d"));
        std::fs::create_dir(&scratch).unwrap();
        let theirs = rs274(&file, dir.path(), &table, &scratch);
        let ours = kezuri_linuxcnc(&file, dir.path(), &machine, &scratch);
        match (runs, &theirs.error, &ours) {
            (true, None, Ok(ours)) => {
                // rs274's canon prints a spline without its points: the
                // moves after it say where it ended.
                let ours = spline_ends(ours.clone(), text);
                let ours: Vec<Motion> = ours.into_iter().filter(|m| !on_spline_line(m, text)).collect();
                if let Some(d) = first_difference(&ours, &theirs.motions) {
                    failures.push(format!("{name}: {d}"));
                }
            }
            (false, Some(_), Err(e)) if e.contains("off its circle") => {}
            _ => failures.push(format!(
                "{name}: expected both to {}: rs274 {:?}, kezuri {:?}",
                if runs { "run" } else { "stop" },
                theirs.error,
                ours.as_ref().err()
            )),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Whether motion `m` comes from a spline block of `text` (G5, G5.1).
fn on_spline_line(m: &Motion, text: &str) -> bool {
    text.lines()
        .enumerate()
        .any(|(k, l)| (l.contains("G5.1") || l.contains("G5 ")) && m.at.starts_with(&format!("line {}:", k + 1)))
}

/// kezuri's motions with each spline block's moves (a line of `text` with
/// G5 or G5.1) down to its last: the spline's end point.
fn spline_ends(motions: Vec<Motion>, text: &str) -> Vec<Motion> {
    let spline_lines: Vec<String> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains("G5.1") || l.contains("G5 "))
        .map(|(k, _)| format!("line {}:", k + 1))
        .collect();
    let on_spline = |m: &Motion| spline_lines.iter().any(|l| m.at.starts_with(l.as_str()));
    let line_of = |m: &Motion| m.at.split(':').next().unwrap_or("").to_string();
    let mut out: Vec<Motion> = Vec::new();
    for m in motions {
        if let Some(last) = out.last() {
            if on_spline(&m) && on_spline(last) && line_of(last) == line_of(&m) {
                out.pop();
            }
        }
        out.push(m);
    }
    out
}

#[test]
fn linuxcnc_s_own_spline_example_ends_each_spline_where_rs274_does() {
    if !rs274_here() {
        return;
    }
    let example = std::path::Path::new("/usr/share/linuxcnc/ncfiles/systems.ngc");
    let Ok(text) = std::fs::read_to_string(example) else {
        eprintln!("LinuxCNC's systems.ngc is not here: skipped");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("tool.tbl");
    std::fs::write(&table, "T1 P1 Z0.1 D0.06\n").unwrap();
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n").unwrap();
    // Each `G5.1 X… Y… I… J…` as `G1 X… Y…`: the same end points in rs274.
    let straight: String = text
        .lines()
        .map(|l| match (l.find("G5.1"), l.find(" I[")) {
            (Some(g), Some(i)) => format!("{}G1{}\n", &l[..g], &l[g + 4..i]),
            _ => format!("{l}\n"),
        })
        .collect();
    let (file, lines) = (dir.path().join("systems.ngc"), dir.path().join("systems-g1.ngc"));
    std::fs::write(&file, &text).unwrap();
    std::fs::write(&lines, straight).unwrap();
    let theirs = rs274(&lines, dir.path(), &table, dir.path());
    assert!(theirs.error.is_none(), "{:?}", theirs.error);
    let ours = kezuri_linuxcnc(&file, dir.path(), &machine, dir.path()).unwrap();
    let splines = text.lines().filter(|l| l.contains("G5.1")).count();
    assert_eq!(splines, 548);
    assert!(ours.len() > theirs.motions.len() + splines, "each spline is several straight moves");
    let ours = spline_ends(ours, &text);
    assert_eq!(first_difference(&ours, &theirs.motions), None);
}
