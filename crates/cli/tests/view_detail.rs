//! The view page's level of detail: the simplified path never strays from
//! the true one by more than the tolerance (every original point, arcs
//! sampled along their curve, checked by brute force against every drawn
//! segment of its colour), colours, tools and breaks stay, and the
//! simplifier holds a bounded window; through the binary, a page over
//! --max-page-mb is drawn simplified and says so, and a million-move raster
//! makes a page within the default budget; every page opens in headless
//! Chromium without a script error.

mod common;

use common::{kezuri, ok, path};
use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane};
use kezuri_picture::view::detail::{kind, Drawn, Simplifier, UNPLACED, WINDOW};

/// A small generator, so that the paths are the same on every run.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

/// A path of every kind: raster rows of small noisy feeds (one every 0.05
/// mm, Z wandering by up to 0.03 mm), plunges, rapids between rows, runs of
/// arcs both ways (some helical), dwells, tool changes, a move to a place
/// the program does not give and the move back from it.
fn generated(seed: u64) -> Vec<Move> {
    let mut r = Lcg(seed);
    let mut moves: Vec<Move> = Vec::new();
    let mut here = at(0.0, 0.0, 5.0);
    let mut tool = 1;
    let go = |moves: &mut Vec<Move>, here: &mut Axes, kind: MoveKind, end: Axes, tool: u32, unknown: AxisSet| {
        moves.push(Move {
            kind,
            start: *here,
            end,
            feed: 600.0,
            tool,
            line: moves.len() as u32 + 1,
            unknown,
            ..Move::default()
        });
        *here = end;
    };
    for row in 0..8 {
        let y = row as f64 * 0.7;
        go(&mut moves, &mut here, MoveKind::Rapid, at(0.0, y, 2.0), tool, AxisSet::NONE);
        go(&mut moves, &mut here, MoveKind::Feed, at(0.0, y, -1.0), tool, AxisSet::NONE);
        let mut z = -1.0;
        for k in 1..=100 {
            z += (r.next() - 0.5) * 0.03;
            go(
                &mut moves,
                &mut here,
                MoveKind::Feed,
                at(k as f64 * 0.05, y + (r.next() - 0.5) * 0.004, z),
                tool,
                AxisSet::NONE,
            );
        }
        // Arcs, continuing from the row's end: a quarter of a small circle
        // cut in pieces, then back the other way, some climbing.
        let radius = 0.5 + r.next() * 3.0;
        let centre = [here.x, here.y + radius, here.z];
        let ccw = row % 2 == 0;
        let pieces = 3 + (r.next() * 20.0) as usize;
        let climb = if row % 3 == 0 { 0.02 } else { 0.0 };
        let start_angle = -std::f64::consts::FRAC_PI_2;
        for k in 1..=pieces {
            let sweep = std::f64::consts::PI * 0.8 * k as f64 / pieces as f64;
            let a = if ccw { start_angle + sweep } else { start_angle - sweep };
            let end = at(centre[0] + radius * a.cos(), centre[1] + radius * a.sin(), here.z + climb);
            let arc = Arc { center: [centre[0], centre[1], here.z], plane: Plane::Xy, ccw, turns: 0 };
            go(&mut moves, &mut here, MoveKind::Arc(arc), end, tool, AxisSet::NONE);
        }
        let stay = here;
        go(&mut moves, &mut here, MoveKind::Dwell(0.5), stay, tool, AxisSet::NONE);
        if row % 4 == 3 {
            tool += 1;
        }
        if row == 5 {
            // A return to a reference point the machine file does not
            // place, and the move back.
            go(&mut moves, &mut here, MoveKind::Home, at(0.0, 0.0, 0.0), tool, AxisSet(0b100));
            go(&mut moves, &mut here, MoveKind::Rapid, at(0.0, y + 0.35, 3.0), tool, AxisSet::NONE);
        }
    }
    moves
}

/// The points of a move along its true course: a line's ends and a point
/// between, an arc every 1/64 of its sweep.
fn course(m: &Move) -> Vec<[f64; 3]> {
    match m.kind {
        MoveKind::Arc(arc) => (0..=64).map(|k| arc.point_at(m.start, m.end, k as f64 / 64.0).xyz()).collect(),
        _ => {
            let (a, b) = (m.start.xyz(), m.end.xyz());
            vec![a, std::array::from_fn(|k| (a[k] + b[k]) / 2.0), b]
        }
    }
}

fn distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab: [f64; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let ap: [f64; 3] = std::array::from_fn(|k| p[k] - a[k]);
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    let t = if len2 > 0.0 { (0..3).map(|k| ap[k] * ab[k]).sum::<f64>() / len2 } else { 0.0 }.clamp(0.0, 1.0);
    (0..3).map(|k| (ap[k] - t * ab[k]).powi(2)).sum::<f64>().sqrt()
}

/// Whether a move is drawn as a line from its start (not a dwell, not to or
/// from a place the program does not give).
fn drawn_as_line(m: &Move, from_unknown: bool) -> bool {
    let k = kind(m);
    k != UNPLACED && k != 5 && !from_unknown
}

fn simplified(moves: &[Move], tol: f64) -> (Vec<Drawn>, usize) {
    let mut out = Vec::new();
    let mut held = 0;
    let mut s = Simplifier::new(tol, false);
    for m in moves {
        s.push(m, 1.0, &mut |d| out.push(d));
        held = held.max(s.held());
    }
    s.finish(&mut |d| out.push(d));
    (out, held)
}

#[test]
fn the_simplified_path_stays_within_the_tolerance_of_the_true_one() {
    for seed in 1..=2u64 {
        let moves = generated(seed);
        for tol in [0.005, 0.05, 0.5] {
            let (drawn, _) = simplified(&moves, tol);
            assert!(drawn.len() < moves.len(), "seed {seed}, {tol} mm: {} of {} moves", drawn.len(), moves.len());
            // Every point of the true path is within the tolerance of a
            // drawn segment of its colour and tool (brute force).
            let mut from_unknown = false;
            for m in &moves {
                let line = drawn_as_line(m, from_unknown);
                from_unknown = m.unknown.0 & 0b111 != 0;
                if !line {
                    continue;
                }
                for p in course(m) {
                    let near = drawn
                        .iter()
                        .filter(|d| d.kind == kind(m) && d.mv.tool == m.tool && !matches!(d.mv.kind, MoveKind::Arc(_)))
                        .map(|d| distance(p, d.mv.start.xyz(), d.mv.end.xyz()))
                        .fold(f64::INFINITY, f64::min);
                    assert!(near <= tol + 2e-9, "seed {seed}, {tol} mm: {p:?} of line {} is {near} mm away", m.line);
                }
            }
            // Every drawn point lies on the true path (a point of it, or of
            // an arc).
            for d in drawn.iter().filter(|d| d.kind != UNPLACED && d.kind != 5) {
                for p in [d.mv.start.xyz(), d.mv.end.xyz()] {
                    let on = moves
                        .iter()
                        .map(|m| match m.kind {
                            MoveKind::Arc(arc) => {
                                let r = arc.radius(m.start);
                                let c = arc.center;
                                let radial = ((p[0] - c[0]).hypot(p[1] - c[1]) - r).abs();
                                let (z0, z1) = (m.start.z.min(m.end.z), m.start.z.max(m.end.z));
                                radial.max(z0 - p[2]).max(p[2] - z1)
                            }
                            _ => distance(p, m.start.xyz(), m.end.xyz()),
                        })
                        .fold(f64::INFINITY, f64::min);
                    assert!(on <= 1e-9, "seed {seed}, {tol} mm: drawn point {p:?} is {on} mm off the path");
                }
            }
        }
    }
}

#[test]
fn colours_tools_breaks_and_whole_moves_keep_their_places() {
    let moves = generated(7);
    let (drawn, _) = simplified(&moves, 0.1);
    // The sequence of colours and tools, repeats folded, is the same.
    let runs = |it: &mut dyn Iterator<Item = (u8, u32)>| {
        let mut v: Vec<(u8, u32)> = Vec::new();
        for x in it {
            if v.last() != Some(&x) {
                v.push(x);
            }
        }
        v
    };
    let before = runs(&mut moves.iter().map(|m| (kind(m), m.tool)));
    let after = runs(&mut drawn.iter().map(|d| (d.kind, d.mv.tool)));
    assert_eq!(before, after);
    // Dwells, the move to the reference point and the one back from it
    // are drawn whole, in order.
    let whole: Vec<Move> =
        moves.iter().filter(|m| matches!(m.kind, MoveKind::Dwell(_) | MoveKind::Home)).copied().collect();
    let kept: Vec<Move> =
        drawn.iter().filter(|d| matches!(d.mv.kind, MoveKind::Dwell(_) | MoveKind::Home)).map(|d| d.mv).collect();
    assert_eq!(whole, kept);
    let home = moves.iter().position(|m| m.kind == MoveKind::Home).unwrap();
    let back = drawn.iter().position(|d| d.mv.kind == MoveKind::Home).unwrap();
    assert_eq!(drawn[back + 1].mv, moves[home + 1], "the move from the unknown place is drawn whole");
    // A segment starts where the last ended unless the original path broke
    // there: the drawn path breaks only at a break of the original.
    let breaks_before = moves.windows(2).filter(|w| w[0].end != w[1].start).count();
    let breaks_after = drawn.windows(2).filter(|w| w[0].mv.end != w[1].mv.start).count();
    assert_eq!(breaks_before, breaks_after);
    // Seconds are the moves' own, summed.
    let seconds: f64 = drawn.iter().map(|d| d.seconds).sum();
    assert!((seconds - moves.len() as f64).abs() < 1e-6, "{seconds}");
}

#[test]
fn the_simplifier_holds_a_bounded_window() {
    // 100,000 feeds along a wavy line: each window of points is drawn as
    // it fills.
    let moves: Vec<Move> = (0..100_000)
        .map(|k| {
            let x = |k: usize| k as f64 * 0.01;
            let z = |k: usize| (k as f64 * 0.37).sin() * 0.001;
            Move {
                kind: MoveKind::Feed,
                start: at(x(k), 0.0, z(k)),
                end: at(x(k + 1), 0.0, z(k + 1)),
                ..Move::default()
            }
        })
        .collect();
    let (drawn, held) = simplified(&moves, 0.01);
    assert!(held <= WINDOW, "{held} held");
    // One segment a window (its last point kept), not one a move.
    assert!(drawn.len() <= moves.len() / (WINDOW - 1) + 1, "{} drawn", drawn.len());
    assert_eq!(drawn.last().unwrap().mv.end, moves.last().unwrap().end);
}

/// A raster: `rows` rows of `per_row` G1 moves, Z a wave.
fn raster(rows: usize, per_row: usize) -> String {
    let mut nc = String::with_capacity(rows * per_row * 30);
    nc.push_str("G21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z0. F1200.\n");
    for j in 0..rows {
        let y = j as f64 * 0.2;
        for i in 0..per_row {
            let k = if j % 2 == 0 { i } else { per_row - 1 - i };
            let x = k as f64 * 0.05;
            let z = -1.0 + 0.5 * (x * 0.3).sin() * (y * 0.2).cos();
            nc.push_str(&format!("X{x:.3} Y{y:.3} Z{z:.4}\n"));
        }
    }
    nc.push_str("G0 Z5.\nM30\n");
    nc
}

/// A page over --max-page-mb is drawn simplified, not refused, says so on
/// the page and in the summary, and opens in headless Chromium; one no
/// tolerance can fit is refused, naming --max-page-mb.
#[test]
fn a_page_over_the_budget_is_drawn_simplified() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "raster.nc");
    std::fs::write(&nc, raster(40, 500)).unwrap();
    let html = path(dir.path(), "raster.html");
    let full = kezuri(&["view", &nc, "--no-text", "-o", &html]);
    ok(&full);
    let full_size = std::fs::metadata(&html).unwrap().len();
    assert!(!String::from_utf8_lossy(&full.stderr).contains("simplified"));
    let o = kezuri(&["view", &nc, "--no-text", "--max-page-mb", "0.2", "-o", &html]);
    ok(&o);
    let size = std::fs::metadata(&html).unwrap().len();
    assert!(size <= 200_000 && size < full_size, "{size} bytes (full detail {full_size})");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("simplified to ") && err.contains(" mm to fit 0.2 MB: 20,003 moves drawn as "), "{err}");
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("simplified to ") && page.contains("20,003 moves drawn as"));
    drawn_in_chromium(&html);
    // The viewer alone is some 60 kB: nothing fits 0.01 MB.
    let o = kezuri(&["view", &nc, "--max-page-mb", "0.01", "-o", &html]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--max-page-mb") && err.contains("5 mm"), "{err}");
}

/// A million-move raster makes a page within the default budget, and
/// headless Chromium draws it.
#[test]
fn a_million_moves_make_a_page_within_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "million.nc");
    std::fs::write(&nc, raster(500, 2000)).unwrap();
    let html = path(dir.path(), "million.html");
    let o = kezuri(&["view", &nc, "-o", &html]);
    ok(&o);
    let size = std::fs::metadata(&html).unwrap().len();
    assert!(size <= 32_000_000, "{size} bytes");
    eprintln!("{}", String::from_utf8_lossy(&o.stderr));
    drawn_in_chromium(&html);
}

/// Arcs in rows between straight feeds, lifts between rows, a tool change
/// and another work zero every 400 arcs: the page simplified to fit 0.2 MB
/// (whole arcs as chords, breaks, tools and work zeros kept) opens in
/// headless Chromium without a script error.
#[test]
fn a_simplified_page_of_arcs_tools_and_work_zeros_opens_without_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut nc = String::from("G21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z-1. F800.\n");
    let mut here = (0.0, 0.0);
    for k in 0..3000 {
        let (x, y) = ((k % 50) as f64 * 2.0, (k / 50) as f64);
        if (x, y) != here {
            nc.push_str(&format!("G0 Z2.\nX{x:.3} Y{y:.3}\nG1 Z-1.\n"));
        }
        nc.push_str(&format!(
            "G2 X{:.3} Y{y:.3} I0.5 J0.\nG1 X{:.3} Z{:.3}\n",
            x + 1.0,
            x + 2.0,
            -1.0 - 0.01 * (k % 5) as f64
        ));
        here = (x + 2.0, y);
        if k % 400 == 0 {
            nc.push_str(&format!(
                "G0 Z5.\nT{} M6\nG{} G0 X{:.3} Y{y:.3}\nG1 Z-1.\n",
                2 + k / 400,
                54 + (k / 400) % 3,
                here.0
            ));
        }
    }
    nc.push_str("G0 Z5.\nM30\n");
    let file = path(dir.path(), "arcs.nc");
    std::fs::write(&file, nc).unwrap();
    let html = path(dir.path(), "arcs.html");
    let o = kezuri(&["view", &file, "--max-page-mb", "0.2", "-o", &html]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("simplified to ") && err.contains("6,204 moves drawn as"), "{err}");
    assert!(std::fs::metadata(&html).unwrap().len() <= 200_000);
    drawn_in_chromium(&html);
}

/// Opens `html` in headless Chromium (as docs/view.md does) and checks the
/// page drawn (`data-ready="1"`) with no script error on its console;
/// without Chromium it says so.
fn drawn_in_chromium(html: &str) {
    let chromium = std::env::var("KEZURI_CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !std::path::Path::new(&chromium).exists() {
        eprintln!("skipped: no Chromium at {chromium}");
        return;
    }
    let o = std::process::Command::new(&chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--use-gl=angle",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--virtual-time-budget=20000",
            "--enable-logging=stderr",
            "--v=0",
            "--dump-dom",
            &format!("file://{html}"),
        ])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(out.contains(r#"data-ready="1""#), "{html}: {log}");
    let errors: Vec<&str> =
        log.lines().filter(|l| l.contains(":CONSOLE") && (l.contains("Uncaught") || l.contains("Error"))).collect();
    assert!(errors.is_empty(), "{html}: {errors:?}");
}
