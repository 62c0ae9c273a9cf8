//! Cutter radius compensation in a run handed on in pieces: a stretch from
//! G41/G42 to two moves after G40 is made the centre path as soon as it is
//! done with and handed on with its programmed contour. Drawn programs of
//! several contours (lines and arcs, both sides, Fanuc's start-ups A and B
//! and LinuxCNC's rules, some that alarm) run whole and in pieces of one
//! move must give the same centre path, programmed contour, diagnostics
//! and end.

use std::cell::Cell;
use std::collections::BTreeMap;
use std::fmt::Write;

use kezuri_geom::{PathSink, Toolpath, WholePath};
use kezuri_nc::interp::comp::{Approach, Rules};
use kezuri_nc::interp::{self, IntegerInput, Library, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// No subprograms.
struct NoLibrary;

impl Library for NoLibrary {
    fn load(&mut self, _number: u32) -> Option<SourceFile> {
        None
    }
}

/// The pieces joined, and how many came with a programmed contour.
#[derive(Default)]
struct Pieces {
    whole: WholePath,
    compensated: usize,
}

impl PathSink for Pieces {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.compensated += usize::from(programmed.is_some());
        self.whole.take(piece, programmed);
    }
}

/// One contour: from its corner (x, y), the sides of a closed polygon with
/// an arc on some sides, tool on the left or right, entered and left along
/// a line from outside.
#[derive(Clone, Debug)]
struct Contour {
    x: f64,
    y: f64,
    size: f64,
    left: bool,
    /// Each side: a line, or a half circle bulging out (G02) or in (G03).
    arcs: Vec<Option<bool>>,
    /// How far off the corner the entry starts, on the diagonal.
    entry: f64,
    /// Two moves after G40 (else one: the stretch waits for the next).
    settle: bool,
}

fn contour() -> impl Strategy<Value = Contour> {
    let sides = proptest::collection::vec(proptest::option::of(any::<bool>()), 4);
    (0..40u32, 0..40u32, 2..30u32, any::<bool>(), sides, prop_oneof![Just(8.0), Just(1.0)], any::<bool>()).prop_map(
        |(x, y, size, left, arcs, entry, settle)| Contour {
            x: f64::from(x),
            y: f64::from(y),
            size: f64::from(size),
            left,
            arcs,
            entry,
            settle,
        },
    )
}

fn text(contours: &[Contour], linuxcnc: bool) -> String {
    let mut t = String::from(if linuxcnc { "G21 G90 G17\n" } else { "O0001\nG21 G90 G17 G54\n" });
    for c in contours {
        let (x0, y0, s) = (c.x, c.y, c.size);
        let corners = [(x0, y0), (x0, y0 + s), (x0 + s, y0 + s), (x0 + s, y0), (x0, y0)];
        writeln!(t, "G00 X{:.3} Y{:.3}", x0 - c.entry, y0 - c.entry).unwrap();
        let side = if c.left { "G41" } else { "G42" };
        let d = if linuxcnc { "D1" } else { "D01" };
        writeln!(t, "{side} G01 X{x0:.3} Y{y0:.3} {d} F500.").unwrap();
        for (k, w) in corners.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            // A half circle on the side (the square is gone round clockwise).
            let (i, j) = ((b.0 - a.0) / 2.0, (b.1 - a.1) / 2.0);
            match c.arcs[k] {
                Some(out) => writeln!(t, "G0{} X{:.3} Y{:.3} I{i:.3} J{j:.3}", if out { 2 } else { 3 }, b.0, b.1),
                None => writeln!(t, "G01 X{:.3} Y{:.3}", b.0, b.1),
            }
            .unwrap();
        }
        writeln!(t, "G40 G01 X{:.3} Y{:.3}", x0 - c.entry, y0 - c.entry).unwrap();
        if c.settle {
            writeln!(t, "G00 Z5.").unwrap();
        }
    }
    t.push_str("G00 Z20.\nM30\n");
    t
}

fn settings(rules: Rules, linuxcnc: bool) -> Settings {
    Settings {
        tool_radii: BTreeMap::from([(1, 1.5)]),
        comp_rules: rules,
        integer_input: if linuxcnc { IntegerInput::Units } else { IntegerInput::Increments },
        dialect: if linuxcnc { kezuri_nc::Dialect::LinuxCnc } else { kezuri_nc::Dialect::Fanuc },
        piece_moves: 1,
        ..Settings::default()
    }
}

#[test]
fn compensation_handed_on_stretch_by_stretch_is_the_whole_run() {
    let rules = [
        (Rules::Fanuc { startup: Approach::A }, false),
        (Rules::Fanuc { startup: Approach::B }, false),
        (Rules::LinuxCnc, true),
    ];
    let (early, alarms, runs) = (Cell::new(0), Cell::new(0), Cell::new(0));
    let mut runner = TestRunner::new(Config { cases: 120, ..Config::default() });
    runner
        .run(&(proptest::collection::vec(contour(), 1..5), 0..3usize), |(contours, r)| {
            let (rules, linuxcnc) = rules[r];
            let text = text(&contours, linuxcnc);
            let settings = settings(rules, linuxcnc);
            let mut sources = Sources::default();
            let file = sources.add(SourceFile::new("t.nc", text.as_str()));
            let mut whole_program = Program::default();
            let parsed = parse(&mut whole_program, file, &text);
            prop_assert!(!parsed.iter().any(|d| d.is_error()), "{text}\n{parsed:?}");
            let whole = interp::run(&mut whole_program, &mut sources.clone(), 0, &mut NoLibrary, &settings);
            let mut program = Program::default();
            program.read_in_pages(3, 2);
            parse(&mut program, file, &text);
            let mut pieces = Pieces::default();
            let handed = interp::run_into(&mut program, &mut sources, 0, &mut NoLibrary, &settings, &mut pieces);
            prop_assert_eq!(&pieces.whole.path, &whole.toolpath, "{}", text);
            prop_assert_eq!(&pieces.whole.programmed, &whole.programmed, "{}", text);
            prop_assert_eq!(format!("{:?}", handed.diagnostics), format!("{:?}", whole.diagnostics), "{}", text);
            prop_assert_eq!((handed.completed, handed.statements), (whole.completed, whole.statements));
            runs.set(runs.get() + 1);
            early.set(early.get() + usize::from(pieces.compensated > 1));
            alarms.set(alarms.get() + usize::from(whole.diagnostics.iter().any(|d| d.is_error())));
            Ok(())
        })
        .unwrap();
    // Pinned, so the test cannot pass with nothing handed on early or no
    // alarm met.
    let (runs, early, alarms) = (runs.get(), early.get(), alarms.get());
    println!("{runs} runs, {early} with stretches handed on early, {alarms} alarmed");
    assert!(early >= runs / 3 && alarms >= 1, "{runs} runs, {early} early, {alarms} alarmed");
}
