//! `kezuri tool db`: profiles stored and read back, the wear table and its
//! chart, concurrent writers, a writer killed midway, and the errors.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

mod common;
use common::{kezuri, ok, path};

/// A ball-nosed tool of radius 3 sampled every `dz` mm from z 0 (the
/// backlit picture's rows): `worn` rows lost at the tip, the radius less
/// `loss` × a bump around z 1; written with five decimals.
fn profile_csv(rows: usize, dz: f64, worn: usize, loss: f64) -> String {
    let mut out = String::from("z_mm,radius_mm\n");
    for i in worn..rows {
        let z = i as f64 * dz;
        let ball = if z < 3.0 { (9.0 - (3.0 - z) * (3.0 - z)).max(0.0).sqrt() } else { 3.0 };
        let r = (ball - loss * (-((z - 1.0) / 0.8f64).powi(2)).exp()).max(0.0);
        out.push_str(&format!("{z:.5},{r:.5}\n"));
    }
    out
}

/// `(z, r)` of a CSV written by [`profile_csv`].
fn parse(csv: &str) -> Vec<(f64, f64)> {
    csv.lines()
        .skip(1)
        .map(|l| {
            let (z, r) = l.split_once(',').unwrap();
            (z.parse().unwrap(), r.parse().unwrap())
        })
        .collect()
}

fn radius_at(p: &[(f64, f64)], z: f64) -> f64 {
    let i = p.partition_point(|s| s.0 <= z).clamp(1, p.len() - 1);
    let ((z0, r0), (z1, r1)) = (p[i - 1], p[i]);
    r0 + (z - z0) / (z1 - z0) * (r1 - r0)
}

fn json(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Profiles and samples as stored, checked complete: `PRAGMA
/// integrity_check` is ok and each profile has the samples it records.
fn check_consistent(db: &Path) -> (usize, usize) {
    let c = rusqlite::Connection::open(db).unwrap();
    let check: String = c.query_row("PRAGMA integrity_check", [], |r| r.get(0)).unwrap();
    assert_eq!(check, "ok");
    let mut q = c
        .prepare("SELECT p.id, p.samples, (SELECT count(*) FROM sample s WHERE s.profile_id = p.id) FROM profile p")
        .unwrap();
    let rows: Vec<(i64, i64, i64)> =
        q.query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?))).unwrap().map(Result::unwrap).collect();
    for (id, want, have) in &rows {
        assert_eq!(want, have, "profile {id}: {have} of its {want} samples");
    }
    let orphans: i64 = c
        .query_row("SELECT count(*) FROM sample WHERE profile_id NOT IN (SELECT id FROM profile)", [], |r| r.get(0))
        .unwrap();
    assert_eq!(orphans, 0);
    (rows.len(), rows.iter().map(|r| r.2 as usize).sum())
}

#[test]
fn profiles_round_trip_through_add_list_and_show() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    let csvs = [profile_csv(600, 0.01, 0, 0.0), profile_csv(600, 0.01, 3, 0.004), profile_csv(600, 0.01, 7, 0.011)];
    for (k, csv) in csvs.iter().enumerate() {
        std::fs::write(dir.path().join(format!("p{k}.csv")), csv).unwrap();
    }
    // Added out of time order (and one time with an offset): shown in time order.
    let add = |k: usize, at: &str| {
        json(&kezuri(&[
            "tool",
            "db",
            "add",
            "T12",
            &path(dir.path(), &format!("p{k}.csv")),
            "--db",
            &db,
            "--at",
            at,
            "--json",
        ]))
    };
    let a = add(2, "2026-05-06T08:00:00Z");
    assert_eq!(a["profiles"], 1);
    assert_eq!(a["samples"], 593);
    add(0, "2026-05-01T17:00:00+09:00");
    let n = ok(&kezuri(&[
        "tool",
        "db",
        "add",
        "T12",
        &path(dir.path(), "p1.csv"),
        "--db",
        &db,
        "--at",
        "2026-05-03T08:00:00Z",
        "--note",
        "after part 7",
    ]));
    assert!(n.starts_with("stored profile 3 of tool T12") && n.contains("597 samples"), "{n}");
    ok(&kezuri(&["tool", "db", "add", "T7", &path(dir.path(), "p0.csv"), "--db", &db, "--at", "2026-04-01"]));

    let list = json(&kezuri(&["tool", "db", "list", "--db", &db, "--json"]));
    let tools = list["tools"].as_array().unwrap();
    assert_eq!(tools.len(), 2);
    assert_eq!(tools[0]["id"], "T12");
    assert_eq!(tools[0]["profiles"], 3);
    assert_eq!(tools[0]["first"], "2026-05-01T08:00:00Z");
    assert_eq!(tools[0]["latest"], "2026-05-06T08:00:00Z");
    assert_eq!(tools[0]["tip_z_mm"], 0.07);
    assert_eq!(tools[1]["id"], "T7");
    let text = ok(&kezuri(&["tool", "db", "list", "--db", &db]));
    assert!(
        text.lines().nth(1).unwrap().starts_with("T12          3  2026-05-01T08:00:00Z  2026-05-06T08:00:00Z"),
        "{text}"
    );

    let show = json(&kezuri(&["tool", "db", "show", "T12", "--db", &db, "--json"]));
    let heights: Vec<f64> = show["heights_mm"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(heights.len(), 10);
    assert!((heights[0] - 0.07).abs() < 1e-12 && (heights[9] - 5.99).abs() < 1e-12, "{heights:?}");
    let stored = show["profiles"].as_array().unwrap();
    let order = [0, 1, 2];
    let first = parse(&csvs[0]);
    for (row, &k) in stored.iter().zip(&order) {
        let p = parse(&csvs[k]);
        assert_eq!(row["samples"], p.len());
        // The CSV's numbers exactly: its five decimals parse to the same f64.
        assert_eq!(row["tip_z_mm"].as_f64().unwrap(), p[0].0);
        assert_eq!(row["max_radius_mm"].as_f64().unwrap(), p.iter().map(|s| s.1).fold(0.0, f64::max));
        for (z, c) in heights.iter().zip(row["radius_change_mm"].as_array().unwrap()) {
            let want = radius_at(&p, *z) - radius_at(&first, *z);
            assert!((c.as_f64().unwrap() - want).abs() < 1e-9, "z {z}: {c} vs {want}");
        }
    }
    assert_eq!(stored[1]["note"], "after part 7");
    assert!(stored[0]["largest_loss_mm"].is_null());
    // The bump of 0.011 mm at z 1 (sampled every 0.01 mm: exactly there).
    let loss = stored[2]["largest_loss_mm"].as_f64().unwrap();
    assert!((loss - 0.011).abs() <= 1e-5, "{loss}");
    assert!((stored[2]["largest_loss_z_mm"].as_f64().unwrap() - 1.0).abs() < 0.1);

    let table = ok(&kezuri(&["tool", "db", "show", "T12", "--db", &db]));
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 5, "{table}");
    assert!(lines[2].starts_with("  1  2026-05-01T08:00:00Z    0.0000    3.0000"), "{table}");
    assert!(lines[4].starts_with("  3  2026-05-06T08:00:00Z    0.0700    3.0000"), "{table}");
    assert!(lines[4].contains("   0.0110     1.0"), "{table}");
}

#[test]
fn show_png_draws_a_chart() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    for (k, (worn, loss)) in [(0, 0.0), (4, 0.02)].into_iter().enumerate() {
        let csv = path(dir.path(), &format!("p{k}.csv"));
        std::fs::write(&csv, profile_csv(400, 0.02, worn, loss)).unwrap();
        ok(&kezuri(&["tool", "db", "add", "E1", &csv, "--db", &db, "--at", &format!("2026-06-0{}T10:00:00Z", k + 1)]));
    }
    let png = path(dir.path(), "wear.png");
    let table = ok(&kezuri(&["tool", "db", "show", "E1", "--db", &db, "--png", &png]));
    assert!(table.contains("2026-06-02T10:00:00Z"));
    let img = image::open(&png).expect("a PNG").to_rgba8();
    assert_eq!(img.dimensions(), (860, 430));
    let dark = img.pixels().filter(|p| p[3] > 128 && (p[0] as u32 + p[1] as u32 + p[2] as u32) < 300).count();
    assert!(dark > 2000, "{dark} dark pixels");
    // The second profile's line (blue) is drawn.
    assert!(img.pixels().filter(|p| p[2] > 150 && p[0] < 80).count() > 100);
}

#[test]
fn concurrent_adds_all_land() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    let csv = path(dir.path(), "p.csv");
    std::fs::write(&csv, profile_csv(3000, 0.002, 0, 0.0)).unwrap();
    // A fresh database: the eight race to make it too.
    let children: Vec<_> = (0..8)
        .map(|k| {
            Command::new(env!("CARGO_BIN_EXE_kezuri"))
                .args(["tool", "db", "add", &format!("C{}", k % 3), &csv, "--db", &db])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for child in children {
        ok(&child.wait_with_output().unwrap());
    }
    assert_eq!(check_consistent(Path::new(&db)), (8, 8 * 3000));
    let list = json(&kezuri(&["tool", "db", "list", "--db", &db, "--json"]));
    let counts: Vec<u64> = list["tools"].as_array().unwrap().iter().map(|t| t["profiles"].as_u64().unwrap()).collect();
    assert_eq!(counts, [3, 3, 2]);
}

#[test]
fn a_writer_killed_midway_leaves_the_database_whole() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    let (small, big) = (path(dir.path(), "small.csv"), path(dir.path(), "big.csv"));
    std::fs::write(&small, profile_csv(100, 0.01, 0, 0.0)).unwrap();
    std::fs::write(&big, profile_csv(200_000, 0.0007, 0, 0.0)).unwrap();
    ok(&kezuri(&["tool", "db", "add", "K1", &small, "--db", &db]));
    let add_big = || {
        Command::new(env!("CARGO_BIN_EXE_kezuri"))
            .args(["tool", "db", "add", "K1", &big, "--db", &db])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    // How long a whole add takes here, now.
    let start = Instant::now();
    assert!(add_big().wait().unwrap().success());
    let whole = start.elapsed();
    let (mut profiles, mut samples) = check_consistent(Path::new(&db));
    assert_eq!((profiles, samples), (2, 200_100));
    // Kill adds at later and later moments until one dies inside its
    // transaction: its pages already in the WAL, its profile not stored.
    let wal = dir.path().join("tools.sqlite-wal");
    let mut inside = 0;
    for attempt in 0..16 {
        let fraction = [0.5, 0.65, 0.8, 0.9, 0.95, 0.75, 0.85, 0.6][attempt % 8];
        let mut child = add_big();
        std::thread::sleep(whole.mul_f64(fraction));
        child.kill().unwrap();
        let status = child.wait().unwrap();
        let wal_bytes = std::fs::metadata(&wal).map(|m| m.len()).unwrap_or(0);
        let (p, s) = check_consistent(Path::new(&db));
        eprintln!(
            "attempt {attempt}: killed after {fraction} of {whole:?}: {status}, WAL {wal_bytes} bytes, {p} profiles"
        );
        if status.success() {
            assert_eq!((p, s), (profiles + 1, samples + 200_000));
        } else {
            assert!(p == profiles || p == profiles + 1, "{p} profiles after {profiles}");
            inside += usize::from(p == profiles && wal_bytes > 0);
        }
        (profiles, samples) = (p, s);
        if inside >= 2 {
            break;
        }
    }
    assert!(inside > 0, "no add was killed inside its transaction (a whole add takes {whole:?})");
    // And the database takes the next add.
    let n = ok(&kezuri(&["tool", "db", "add", "K1", &small, "--db", &db]));
    assert!(n.contains(&format!("({} profiles of this tool)", profiles + 1)), "{n}");
    assert_eq!(check_consistent(Path::new(&db)), (profiles + 1, samples + 100));
}

#[test]
fn errors_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    let csv = path(dir.path(), "p.csv");
    std::fs::write(&csv, profile_csv(50, 0.01, 0, 0.0)).unwrap();
    let fail = |args: &[&str], says: &str| {
        let o = kezuri(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(says) && !e.contains("panicked"), "{args:?}: {e}");
    };
    // No database yet: reading does not make one.
    fail(&["tool", "db", "list", "--db", &db], "no tool database at");
    assert!(!Path::new(&db).exists());
    // A bad CSV or time stores nothing and makes no file.
    fail(&["tool", "db", "add", "T1", &path(dir.path(), "missing.csv"), "--db", &db], "cannot read");
    fail(&["tool", "db", "add", "T1", &csv, "--db", &db, "--at", "noon"], "RFC 3339");
    fail(&["tool", "db", "add", " T1", &csv, "--db", &db], "tool name");
    assert!(!Path::new(&db).exists());
    for id in ["A1", "B2", "C3"] {
        ok(&kezuri(&["tool", "db", "add", id, &csv, "--db", &db]));
    }
    fail(&["tool", "db", "show", "T9", "--db", &db], "no tool \"T9\" in");
    fail(&["tool", "db", "show", "T9", "--db", &db], "it knows A1, B2, C3");
    // Not a database at all, and a database of something else: untouched.
    fail(&["tool", "db", "list", "--db", &csv], "is not a kezuri tool database (not an SQLite file)");
    // The profile named as the database is an output over an input: a usage error, before anything.
    let o = kezuri(&["tool", "db", "add", "T1", &csv, "--db", &csv]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("never writes over an input"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), profile_csv(50, 0.01, 0, 0.0));
    let other = path(dir.path(), "other.sqlite");
    rusqlite::Connection::open(&other).unwrap().execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);").unwrap();
    let before = std::fs::read(&other).unwrap();
    fail(&["tool", "db", "add", "T1", &csv, "--db", &other], "an SQLite database but not a kezuri tool database");
    fail(&["tool", "db", "show", "T1", "--db", &other], "not a kezuri tool database");
    assert_eq!(std::fs::read(&other).unwrap(), before);
    // A usage error is exit code 2.
    assert_eq!(kezuri(&["tool", "db", "show"]).status.code(), Some(2));
}

/// A profile of another size than the tool's history (a 3 mm ball's
/// profiles, then one of a 1.5 mm ball, or one larger than the new tool)
/// is stored with a warning: wear only takes material away.
#[test]
fn a_profile_of_another_size_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "tools.sqlite");
    let half: String = profile_csv(600, 0.01, 0, 0.0)
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                l.to_string()
            } else {
                l.split_once(',').map(|(z, r)| format!("{z},{}", r.parse::<f64>().unwrap() / 2.0)).unwrap()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(dir.path().join("new.csv"), profile_csv(600, 0.01, 0, 0.0)).unwrap();
    std::fs::write(dir.path().join("worn.csv"), profile_csv(600, 0.01, 3, 0.004)).unwrap();
    std::fs::write(dir.path().join("half.csv"), half + "\n").unwrap();
    let add = |file: &str| {
        let o = kezuri(&["tool", "db", "add", "T7", &path(dir.path(), file), "--db", &db]);
        ok(&o);
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    assert_eq!(add("new.csv"), "");
    assert_eq!(add("worn.csv"), "");
    let warned = add("half.csv");
    assert!(
        warned.contains(
            "tool T7: this profile's largest radius is 1.5000 mm, a tenth or more smaller than the 3.0000 mm"
        ),
        "{warned}"
    );
}
