//! LinuxCNC codes kezuri runs as `rs274` (LinuxCNC's own interpreter) runs
//! them, compared motion by motion where rs274 is installed: `##n`
//! parameter indirection, the arc radius tolerance (a 0.0254 mm difference
//! on a 50 mm radius runs; 0.0284 mm on a 5 mm radius stops both), `G87`
//! with I J K in G90 and G91. Without rs274 the test skips, as
//! linuxcnc_examples.rs does.

mod common;
#[allow(dead_code)]
mod rs274;

use rs274::{first_difference, kezuri_linuxcnc, rs274, rs274_here};

/// (name, program, whether rs274 and kezuri both run it).
const PROGRAMS: &[(&str, &str, bool)] = &[
    ("hash.ngc", "G21 G90\n#1=2\n#2=7.5\n#3=3\nG0 X##1 Y#3\n##1=2\nG0 X#2 Y###1\nM2\n", true),
    ("arc50.ngc", "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG2 X100 Y0 I50.0127 J0\nG3 X0 Y0 I-49.9873 J0\nM2\n", true),
    ("arc5.ngc", "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG2 X10 Y0 I5.0142 J0\nM2\n", false),
    ("arc_inch.ngc", "G20 G90 G17\nG0 X0 Y0 Z0\nF10\nG2 X10 Y0 I5.0015 J0\nM2\n", true),
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
                if let Some(d) = first_difference(ours, &theirs.motions) {
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
