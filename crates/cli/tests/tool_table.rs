//! `kezuri tool table`: the bundled samples of each format read to the
//! values written in them, a machine file importing one, the examples of
//! --help, bad files refused with file and line, and every real tool table
//! of Debian's linuxcnc-uspace and freecad-common (KEZURI_REAL_TOOLS, set
//! by .ci/run) read with plausible values.

use std::path::{Path, PathBuf};

use serde_json::Value;

mod common;
use common::{kezuri, ok, path};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn sample(name: &str) -> String {
    root().join("samples/tools").join(name).to_string_lossy().into_owned()
}

/// `tool table ARGS… --json`: its one table.
fn table(args: &[&str]) -> Value {
    let mut all = vec!["tool", "table", "--json"];
    all.extend_from_slice(args);
    let v: Value = serde_json::from_str(&ok(&kezuri(&all))).unwrap();
    assert_eq!(v["tables"].as_array().unwrap().len(), 1, "{v}");
    v["tables"][0].clone()
}

/// The tool numbered `n` of a table.
fn tool(t: &Value, n: u64) -> &Value {
    t["tools"].as_array().unwrap().iter().find(|e| e["number"] == n).unwrap_or_else(|| panic!("no T{n} in {t}"))
}

/// Runs `tool table ARGS…`, which must fail with exit code 1 saying `words`.
fn refused(args: &[&str], words: &str) {
    let mut all = vec!["tool", "table"];
    all.extend_from_slice(args);
    let o = kezuri(&all);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(err.contains(words) && !err.contains("panicked"), "{args:?}: {err}");
}

#[test]
fn samples_read_to_the_values_written_in_them() {
    let tbl = table(&[&sample("tool.tbl"), "--units", "inch"]);
    assert_eq!(tbl["format"], "LinuxCNC tool table");
    let t1 = tool(&tbl, 1);
    assert_eq!((t1["shape"].clone(), t1["h"].clone(), t1["d"].clone()), (Value::Null, 1.into(), 1.into()));
    assert_eq!((t1["length_mm"].as_f64(), t1["radius_mm"].as_f64()), (Some(31.75), Some(3.175)));
    assert_eq!(t1["name"], "1/4 flat end mill");
    assert_eq!(tbl["tools"].as_array().unwrap().len(), 4);
    let mm = table(&[&sample("tool.tbl"), "--units", "mm"]);
    assert_eq!(tool(&mm, 7)["radius_mm"].as_f64(), Some(0.09375));

    let fctl = table(&[&sample("Library/shop.fctl")]);
    let specs: Vec<Value> = fctl["tools"].as_array().unwrap().iter().map(|t| t["shape"].clone()).collect();
    assert_eq!(
        specs,
        ["flat:6", "ball:6", "bull:10,1", "v:12,90"]
            .map(Value::from)
            .into_iter()
            .chain([Value::Null])
            .collect::<Vec<_>>()
    );
    assert_eq!((tool(&fctl, 12)["h"].clone(), tool(&fctl, 12)["d"].clone()), (12.into(), Value::Null));
    assert!(fctl["warnings"][0].as_str().unwrap().contains("T12 (m6_thread_mill.fctb): no shape"), "{fctl}");

    let json = table(&[&sample("shop.json")]);
    let zipped = table(&[&sample("shop.tools")]);
    assert_eq!(json["tools"], zipped["tools"]);
    assert_eq!(tool(&json, 2)["shape"], "ball:4");
    assert_eq!((tool(&json, 2)["h"].clone(), tool(&json, 2)["d"].clone()), (2.into(), 22.into()));
    assert_eq!(tool(&json, 4)["shape"], "bull:12.7,0.762");
    assert_eq!(tool(&json, 6)["shape"], "v:6,90");
    assert!(json["skipped"][0].as_str().unwrap().contains("holder, BT30 ER20 collet chuck"), "{json}");

    let bit = table(&[&sample("Bit/10mm_bull.fctb")]);
    assert_eq!(tool(&bit, 1)["shape"], "bull:10,1");
}

#[test]
fn a_machine_file_imports_a_table_under_its_own_entries() {
    let m = table(&["--machine", &sample("mill.toml")]);
    assert_eq!(m["format"], "machine file");
    let t3 = tool(&m, 3);
    assert_eq!((t3["shape"].clone(), t3["name"].clone()), ("v:12.7,90".into(), "1/2 V-bit, 90 degrees".into()));
    assert_eq!((t3["length_mm"].as_f64(), t3["radius_mm"].as_f64()), (Some(50.8), Some(6.35)));
    assert_eq!(tool(&m, 7)["shape"], "v:4.7625,118");
    // check reads a machine file whose import lacks shapes, and says each
    // note itself with the line to add (it said "has 1 warnings").
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(sample("tool.tbl"), dir.path().join("tool.tbl")).unwrap();
    let machine = path(dir.path(), "m.toml");
    std::fs::write(&machine, "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n[tools.T1]\nshape = \"flat:6.35\"\n")
        .unwrap();
    std::fs::write(dir.path().join("a.nc"), "T1 M06\nG00 Z5\nM30\n").unwrap();
    let o = kezuri(&["check", &path(dir.path(), "a.nc"), "--machine", &machine]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("warnings (kezuri"), "{err}");
    for t in ["T2 (1/8 ball end mill)", "T3 (1/2 90 degree V-bit)", "T7 (3/16 drill)"] {
        let n = &t[..2];
        let line = format!(
            "warning: {machine}: imported tool table: {t}: the tool.tbl gives no shape: \
             add `shape = \"SPEC\"` under [tools.{n}]"
        );
        assert!(err.contains(&line), "{line}\n{err}");
    }
    assert!(!err.contains("T1 (1/4"), "{err}");
}

/// `check FILE --machine M`, which must succeed: its report after its stderr.
fn checked(nc: &str, machine: &str) -> String {
    let o = kezuri(&["check", nc, "--machine", machine]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err + &String::from_utf8_lossy(&o.stdout)
}

#[test]
fn a_missing_length_says_the_line_to_add() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "a.nc");
    std::fs::write(&nc, "%\nO0001\nG21 G90\nT1 M06\nG00 G43 H1 Z5.\nT5 M06\nG00 G43 H15 Z5.\nM30\n%\n").unwrap();
    let machine = path(dir.path(), "m.toml");
    let write = |text: &str| std::fs::write(&machine, text).unwrap();
    // `h = 1` alone: the warning says what is missing and where it goes.
    write("[tools.T1]\nh = 1\n[tools.T5]\nh = 15\n");
    let err = checked(&nc, &machine);
    for (h, t) in [(1, 1), (15, 5)] {
        let want = format!(
            "warning: tool length offset H{h} is not in the tool table: it reads 0; \
             add `length = <mm>` under [tools.T{t}] in {machine}"
        );
        assert!(err.contains(&want), "{want}\n{err}");
    }
    // Without a machine file, it says to give one.
    let o = kezuri(&["check", &nc]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("it reads 0; give it in a machine file (--machine M.toml): `length = <mm>` under [tools.T1]"),
        "{err}"
    );
    // The lines added, nothing is warned of.
    write("[tools.T1]\nh = 1\nlength = 127.0\n[tools.T5]\nh = 15\nlength = 80\n");
    let err = checked(&nc, &machine);
    assert!(!err.contains("warning:"), "{err}");
    assert!(err.contains("0 errors, 0 warnings"), "{err}");
}

#[test]
fn a_program_kezuri_wrote_checks_clean_on_its_machine() {
    let dir = tempfile::tempdir().unwrap();
    let grid = path(dir.path(), "g.xyz");
    // Flat, so that every cutter reaches all of it.
    std::fs::write(&grid, "0 0 0\n10 0 0\n0 10 0\n10 10 0\n").unwrap();
    let own = path(dir.path(), "own.toml");
    std::fs::write(&own, "[post]\npreset = \"haas\"\n[tools.T5]\nshape = \"ball:3\"\nh = 15\nlength = 80.5\n").unwrap();
    let mill = sample("mill.toml");
    for (machine, n, tool) in
        [(&mill, "1", "flat:6.35"), (&mill, "2", "ball:3.175"), (&mill, "7", "v:4.7625,118"), (&own, "5", "ball:3")]
    {
        let nc = path(dir.path(), &format!("t{n}.nc"));
        let args = ["mill", &grid, "--tool", tool, "--stepover", "1", "--tool-number", n, "--machine", machine];
        let o = kezuri(&[&args[..], &["-o", &nc]].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success() && !err.contains("warning"), "{err}");
        let err = checked(&nc, machine);
        assert!(!err.contains("warning:") && err.contains("0 errors, 0 warnings"), "T{n} on {machine}: {err}");
    }
}

/// A program made for another shape than the machine file gives its tool
/// number is warned of: its check with the machine file would cut with the
/// machine's.
#[test]
fn a_program_made_for_another_shape_than_the_tool_table_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let grid = path(dir.path(), "g.xyz");
    std::fs::write(&grid, "0 0 0\n10 0 0\n0 10 0\n10 10 -1\n").unwrap();
    let nc = path(dir.path(), "t2.nc");
    let machine = sample("mill.toml");
    let args = ["mill", &grid, "--tool", "ball:3", "--stepover", "1", "--tool-number", "2", "--machine", &machine];
    let o = kezuri(&[&args[..], &["-o", &nc]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success()
            && err.contains(
                "the machine file's T2 is ball:3.175 (1/8 ball end mill), but this program is made for ball:3"
            ),
        "{err}"
    );
}

#[test]
fn help_examples_run_on_the_samples() {
    let help = ok(&kezuri(&["tool", "table", "--help"]));
    assert!(help.contains("samples/tools/"), "{help}");
    let examples: Vec<&str> = help.lines().map(str::trim).filter(|l| l.starts_with("kezuri tool table")).collect();
    assert_eq!(examples.len(), 4, "{help}");
    for line in examples {
        let args: Vec<&str> = line.split_whitespace().skip(1).collect();
        let o =
            std::process::Command::new(env!("CARGO_BIN_EXE_kezuri")).args(&args).current_dir(root()).output().unwrap();
        let text = ok(&o);
        assert!(text.contains("T1 ") || text.contains("\"number\":1,"), "{line}: {text}");
    }
}

#[test]
fn bad_files_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        std::fs::write(dir.path().join(name), bytes).unwrap();
        path(dir.path(), name)
    };
    let tbl = write("tool.tbl", b"T1 P1 D3 ;ok\nT2 P2 D3,5 ;comma\n");
    refused(&[&tbl], "carries no units: say which with --units mm or --units inch");
    refused(&[&tbl, "--units", "mm"], "tool.tbl:2:7: 'D3,5': D takes a number");
    refused(&[&tbl, "--units", "cubits"], "'cubits' is not a unit of length");
    let old = write("old.tbl", b"TOOLNO POCKET LENGTH DIAMETER COMMENT\n1 1 0.5 0.125 end mill\n");
    refused(&[&old, "--units", "inch"], "old.tbl:1:1: this is the tool table of LinuxCNC before 2.4");
    let json = write("lib.fctl", b"{\"version\": 1,\n \"tools\": [\n {\"nr\": 1 \"path\": \"x.fctb\"}]}");
    refused(&[&json], "lib.fctl:3:11: expected `,` or `}`");
    let v1 = write("old.fctb", br#"{"version": 1, "name": "x", "shape": "endmill.fcstd", "parameter": {}}"#);
    refused(&[&v1], "old.fctb: tool bit format version 1: kezuri reads version 2");
    let bad = write(
        "bad.fctb",
        br#"{"version": 2, "name": "x", "shape": "endmill.fcstd", "parameter": {"Diameter": "6 furlong"}}"#,
    );
    refused(&[&bad], "bad.fctb: parameter Diameter: \"6 furlong\" is not a length");
    let zip = write("lib.tools", b"PK\x03\x04 not really a zip");
    refused(&[&zip], "lib.tools: not a zip archive");
    let fusion =
        write("f.json", br#"{"data": [{"type": "flat end mill", "unit": "cubits", "post-process": {"number": 1}}]}"#);
    refused(
        &[&fusion],
        "f.json: T1 tool 1 (flat end mill): the unit must be \"millimeters\" or \"inches\", not \"cubits\"",
    );
    refused(&[&write("t.csv", b"")], "t.csv: which tool file is it?");
    refused(&[&path(dir.path(), "none.fctl")], "cannot read");
    // A shape kezuri cannot cut with is read, without a shape, with a warning.
    let saw = write(
        "saw.fctb",
        br#"{"version": 2, "name": "saw", "shape": "slittingsaw.fcstd", "parameter": {"Diameter": "76.2 mm"}}"#,
    );
    let t = table(&[&saw]);
    assert_eq!(tool(&t, 1)["shape"], Value::Null);
    assert!(t["warnings"][0].as_str().unwrap().contains("kezuri cannot cut with a 'slittingsaw'"), "{t}");
    let usage = kezuri(&["tool", "table"]);
    assert_eq!(usage.status.code(), Some(2), "{}", String::from_utf8_lossy(&usage.stderr));
}

/// The folder of real tool tables, or `None` (the test says it skipped)
/// when KEZURI_REAL_TOOLS is not set; set, the folder must be there.
fn real_tools() -> Option<PathBuf> {
    let Some(dir) = std::env::var_os("KEZURI_REAL_TOOLS") else {
        eprintln!("skipped: KEZURI_REAL_TOOLS is not set (.ci/run sets it to the unpacked real tool tables)");
        return None;
    };
    let dir = PathBuf::from(dir);
    assert!(dir.is_dir(), "KEZURI_REAL_TOOLS={} is not a folder", dir.display());
    Some(dir)
}

/// Every file under `dir` whose name ends in `.ext`, links included (even
/// broken ones), in order.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if std::fs::symlink_metadata(&p).unwrap().is_dir() {
            found.extend(files(&p, ext));
        } else if p.extension().is_some_and(|e| e == ext) {
            found.push(p);
        }
    }
    found.sort();
    found
}

#[test]
fn every_real_linuxcnc_table_reads() {
    let Some(dir) = real_tools() else { return };
    let all = files(&dir, "tbl");
    assert!(all.len() >= 124, "{} .tbl files under {}: linuxcnc-uspace ships 124", all.len(), dir.display());
    let (mut read, mut tools, mut dangling, mut obsolete) = (0, 0, Vec::new(), Vec::new());
    for f in &all {
        let name = f.to_string_lossy();
        if !f.exists() {
            // A link to a file the package does not hold.
            refused(&[&name, "--units", "mm"], "cannot read");
            dangling.push(name.into_owned());
            continue;
        }
        let o = kezuri(&["tool", "table", "--json", &name, "--units", "mm"]);
        if !o.status.success() {
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(err.contains(":1:1: this is the tool table of LinuxCNC before 2.4"), "{name}: {err}");
            obsolete.push(name.into_owned());
            continue;
        }
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        let t = &v["tables"][0];
        for e in t["tools"].as_array().unwrap() {
            let n = e["number"].as_u64().unwrap();
            assert!(n > 0 && e["h"] == n && e["d"] == n && e["shape"].is_null(), "{name}: {e}");
            let r = e["radius_mm"].as_f64().unwrap_or(0.0);
            let z = e["length_mm"].as_f64().unwrap_or(0.0);
            assert!((0.0..=100.0).contains(&r) && z.abs() <= 1000.0, "{name}: {e}");
            tools += 1;
        }
        read += 1;
    }
    eprintln!(
        "{} .tbl files: {read} read ({tools} tools), {} links to no file ({dangling:?}), {} in LinuxCNC's \
         obsolete format ({obsolete:?})",
        all.len(),
        dangling.len(),
        obsolete.len()
    );
    assert!(read >= 121 && dangling.len() <= 1 && obsolete.len() <= 2, "read {read}");
    // Spot checks against the files' text.
    let sim = dir.join("usr/share/doc/linuxcnc/examples/sample-configs/sim/sim.tbl");
    let t = table(&[&sim.to_string_lossy(), "--units", "inch"]);
    let t1 = tool(&t, 1); // T1 P1 Z0.511 D0.125 ;1/8 end mill
    assert_eq!(
        (t1["length_mm"].as_f64(), t1["radius_mm"].as_f64(), t1["name"].clone()),
        (Some(12.9794), Some(1.5875), "1/8 end mill".into())
    );
    assert_eq!(tool(&t, 98876)["radius_mm"].as_f64(), None); // T98876 Z0.1 ;big tool number, no D
    let wp = dir.join("usr/share/doc/linuxcnc/examples/sample-configs/sim/qtvcp_screens/woodpecker/tool.tbl");
    let t = table(&[&wp.to_string_lossy(), "--units", "mm"]);
    assert_eq!(tool(&t, 6)["radius_mm"].as_f64(), Some(0.06335)); // the first of two T6 lines: D0.12670
    assert_eq!(tool(&t, 14)["radius_mm"].as_f64(), Some(6.35)); // T14 … D12.70000 ;1/2" ball end
    let skipped = t["skipped"].to_string();
    assert!(skipped.contains("line 2: T0 is no tool") && skipped.contains("line 8: T6 again"), "{skipped}");
}

#[test]
fn every_real_freecad_bit_and_library_reads() {
    let Some(dir) = real_tools() else { return };
    let bits = files(&dir, "fctb");
    let libraries = files(&dir, "fctl");
    assert!(
        bits.len() >= 11 && libraries.len() >= 3,
        "{} bits, {} libraries under {}",
        bits.len(),
        libraries.len(),
        dir.display()
    );
    let mut shaped = Vec::new();
    for f in &bits {
        let t = table(&[&f.to_string_lossy()]);
        let e = tool(&t, 1);
        assert!(!e["name"].as_str().unwrap_or("").is_empty(), "{}: {t}", f.display());
        if let Some(spec) = e["shape"].as_str() {
            shaped.push(format!("{}={spec}", f.file_stem().unwrap().to_string_lossy()));
        }
    }
    shaped.sort();
    shaped.dedup();
    eprintln!("{} bits read; with a shape: {shaped:?}", bits.len());
    for (bit, spec) in [
        ("5mm_Endmill", "flat:5"),
        ("6mm_Ball_End", "ball:6"),
        ("6mm_Bullnose", "bull:6,1.5"),
        ("5mm_Drill", "v:5,119"),
    ] {
        assert!(shaped.contains(&format!("{bit}={spec}")), "{bit}: {shaped:?}");
    }
    let mut total = 0;
    for f in &libraries {
        let t = table(&[&f.to_string_lossy()]);
        let (n, skipped) = (t["tools"].as_array().unwrap().len(), t["skipped"].as_array().unwrap().len());
        eprintln!("{}: {n} tools, {skipped} bits not found beside it", f.display());
        assert_eq!(n + skipped, 9, "{}: {t}", f.display());
        total += n;
    }
    // FreeCAD's own library: Tools/Library/Default.fctl with its bits in Tools/Bit.
    let default = dir.join("usr/share/freecad/Mod/Path/Tools/Library/Default.fctl");
    let t = table(&[&default.to_string_lossy()]);
    assert_eq!(t["tools"].as_array().unwrap().len(), 9, "{t}");
    assert_eq!(tool(&t, 4)["shape"], "bull:6,1.5"); // 6mm_Bullnose: Diameter 6, FlatRadius 1.5
    assert_eq!(tool(&t, 4)["name"], "6 mm Bull Nose");
    assert_eq!(tool(&t, 5)["shape"], Value::Null); // 60degree_Vbit: TipDiameter 1 mm
    assert!(total >= 9);
}

/// A Fusion 360 program's start (its real tool lines; the Spanish
/// "taladrar" is a drill) with the moves of T1 and of `second`.
fn fusion(second: &str) -> String {
    format!(
        "%\nO08787\n(Maquina)\n(T1 D=6. CR=0. - ZMIN=-3. - flat end mill)\n{second}\nN10 G90 G17\nN15 G21\n\
         N25 T1 M6\nN30 S5500 M3\nN35 G54\nN40 G0 X0. Y0.\nN45 G0 G43 Z15. H1\nN50 G1 Z-3. F300.\nN55 X20. F1000.\n\
         N60 G0 Z15.\nN70 T2 M6\nN75 S5500 M3\nN80 G0 X-8.66 Y5.\nN85 G0 G43 Z15. H2\nN90 G1 Z-3. F300.\n\
         N95 X0. Y10.\nN100 G0 Z15.\nN115 M30\n%\n"
    )
}

#[test]
fn a_cam_programs_tool_lines_are_its_tool_table() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "f.nc");
    std::fs::write(&nc, fusion("(T2 D=3. CR=1.5 - ZMIN=-3. - ball end mill)")).unwrap();
    let o = kezuri(&["check", &nc]);
    let (out, err) = (ok(&o), String::from_utf8_lossy(&o.stderr).into_owned());
    let said = "no machine file gives a tool table: tools from the program's comments: T1 flat:6 (line 4), \
                T2 ball:3 (line 5)";
    assert!(err.contains(said), "{err}");
    assert!(out.contains("T1 flat:6 H1 (flat end mill)") && out.contains("T2 ball:3 H2 (ball end mill)"), "{out}");
    // sim cuts with them, without --tool, and says where they came from.
    let o = kezuri(&["sim", &nc, "--res", "0.5", "--json"]);
    let v: Value = serde_json::from_str(&ok(&o)).unwrap();
    assert_eq!(
        (v["tool"].as_str(), v["tools_from"].as_str()),
        (Some("T1 flat:6, T2 ball:3"), Some("the program's comments"))
    );
    // A machine file's table is the table: the comments are not read.
    let o = kezuri(&["check", &nc, "--machine", &sample("mill.toml")]);
    let (out, err) = (ok(&o), String::from_utf8_lossy(&o.stderr).into_owned());
    assert!(!err.contains("program's comments") && out.contains("T2 ball:3.175 H2"), "{err}{out}");
}

/// Needs the drill shape (`drill:D,ANGLE`) in the cutter SPECs.
#[test]
fn a_fusion_drill_line_is_a_drill() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "f.nc");
    std::fs::write(&nc, fusion("(T2 D=2.5 CR=0. TAPER=118deg - ZMIN=-4.751 - taladrar)")).unwrap();
    let o = kezuri(&["check", &nc]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("tools from the program's comments: T1 flat:6 (line 4), T2 drill:2.5,118 (line 5)"), "{err}");
}
