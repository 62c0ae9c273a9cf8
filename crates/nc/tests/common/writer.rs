//! What the writer's tests share: a toolpath built move by move, the sample
//! toolpath, a program written and read back as the dialect's control reads
//! it, and the comparison of the two.

use kezuri_geom::{Arc, Axes, Coolant, Move, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::interp::{self, IntegerInput, Outcome, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::{parse, Program, SourceFile, Sources};
use proptest::prelude::*;

/// Builds a chained toolpath: every move starts where the last ended and
/// carries the current feed, spindle, coolant and tool.
#[derive(Default)]
pub struct Path {
    pub path: Toolpath,
    pub at: Axes,
    pub feed: f64,
    pub speed: f64,
    pub spindle: Spindle,
    pub coolant: Coolant,
    pub tool: u32,
}

pub fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

impl Path {
    pub fn push(&mut self, kind: MoveKind, end: Axes) -> &mut Path {
        let line = self.path.moves.len() as u32 + 1;
        let (feed, speed, spindle, coolant, tool) = (self.feed, self.speed, self.spindle, self.coolant, self.tool);
        self.path.push(Move {
            kind,
            start: self.at,
            end,
            feed,
            speed,
            spindle,
            coolant,
            tool,
            line,
            ..Move::default()
        });
        self.at = end;
        self
    }
    pub fn rapid(&mut self, x: f64, y: f64, z: f64) -> &mut Path {
        self.push(MoveKind::Rapid, Axes { x, y, z, ..self.at })
    }
    pub fn feed(&mut self, x: f64, y: f64, z: f64, feed: f64) -> &mut Path {
        self.feed = feed;
        self.push(MoveKind::Feed, Axes { x, y, z, ..self.at })
    }
    pub fn probe(&mut self, x: f64, y: f64, z: f64, feed: f64) -> &mut Path {
        self.feed = feed;
        self.push(MoveKind::Probe, Axes { x, y, z, ..self.at })
    }
    pub fn arc(&mut self, plane: Plane, ccw: bool, center: [f64; 3], end: [f64; 3]) -> &mut Path {
        let end = Axes { x: end[0], y: end[1], z: end[2], ..self.at };
        self.push(MoveKind::Arc(Arc { center, plane, ccw, turns: 0 }), end)
    }
    pub fn dwell(&mut self, seconds: f64) -> &mut Path {
        self.push(MoveKind::Dwell(seconds), self.at)
    }
    pub fn spindle(&mut self, spindle: Spindle, speed: f64) -> &mut Path {
        self.spindle = spindle;
        self.speed = speed;
        self
    }
    pub fn coolant(&mut self, mist: bool, flood: bool) -> &mut Path {
        self.coolant = Coolant { mist, flood };
        self
    }
    pub fn tool(&mut self, tool: u32) -> &mut Path {
        self.tool = tool;
        self
    }
}

/// Rapids, feeds, arcs in all three planes, a helix (full turn and a
/// quarter), a dwell, a probe, tool changes, spindle and coolant.
pub fn sample() -> Toolpath {
    let mut p = Path::default();
    p.tool(1).spindle(Spindle::Cw, 12000.0).coolant(false, true);
    p.rapid(0.0, 0.0, 5.0).dwell(0.5);
    p.feed(0.0, 0.0, -1.0, 200.0).feed(20.0, 0.0, -1.0, 600.0);
    p.arc(Plane::Xy, true, [20.0, 10.0, -1.0], [30.0, 10.0, -1.0]);
    p.feed(30.0, 20.0, -1.0, 600.0);
    // G18: a half turn in X-Z around (25, -1).
    p.arc(Plane::Zx, false, [25.0, 20.0, -1.0], [20.0, 20.0, -1.0]);
    // G19: a half turn in Y-Z around (25, -1).
    p.arc(Plane::Yz, false, [20.0, 25.0, -1.0], [20.0, 30.0, -1.0]);
    // A full helical turn down 2 mm, then a quarter turn down 0.5 mm.
    p.arc(Plane::Xy, false, [20.0, 35.0, -1.0], [20.0, 30.0, -3.0]);
    p.arc(Plane::Xy, true, [20.0, 35.0, -3.0], [25.0, 35.0, -3.5]);
    p.probe(25.0, 35.0, -10.0, 100.0);
    p.rapid(25.0, 35.0, 10.0);
    p.tool(2).spindle(Spindle::Ccw, 8000.0).coolant(true, true);
    p.rapid(50.0, 50.0, 10.0);
    p.coolant(true, false);
    p.feed(50.0, 50.0, -0.25, 150.0);
    p.feed(50.12345, -0.0004, -0.25, 150.0);
    p.spindle(Spindle::Off, 8000.0).coolant(false, false);
    p.rapid(50.12345, -0.0004, 25.0);
    p.path.clone()
}

pub fn written(path: &Toolpath, options: &WriteOptions) -> String {
    match program(path, options) {
        Ok(text) => text,
        Err(e) => panic!("program() failed: {e}"),
    }
}

/// Parses and runs a written program as the dialect's control reads it.
pub fn run(text: &str, dialect: Dialect) -> (Outcome, Vec<String>) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("written.nc", text));
    let mut program = Program::default();
    let mut messages: Vec<String> = parse(&mut program, file, text).iter().map(|d| d.render(&sources)).collect();
    let integer_input = if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units };
    let settings = Settings { integer_input, ..Settings::default() };
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings);
    messages.extend(outcome.diagnostics.iter().map(|d| d.render(&sources)));
    (outcome, messages)
}

/// The program's motion blocks: the lines between the safe start and the end.
pub fn body(path: &Toolpath, options: &WriteOptions) -> Vec<String> {
    let text = written(path, options);
    let lines: Vec<&str> = text.lines().collect();
    let first = lines.iter().position(|l| l.contains("G21 G90")).map_or(0, |i| i + 1);
    let last = lines.iter().rposition(|l| *l == "M30" || *l == "M2").unwrap_or(lines.len());
    lines[first..last].iter().map(|l| l.to_string()).collect()
}

pub fn kind_name(k: &MoveKind) -> &'static str {
    match k {
        MoveKind::Rapid => "rapid",
        MoveKind::Home => "home",
        MoveKind::Machine => "machine",
        MoveKind::Feed => "feed",
        MoveKind::Probe => "probe",
        MoveKind::Dwell(_) => "dwell",
        MoveKind::Arc(a) if a.ccw => "ccw",
        MoveKind::Arc(_) => "cw",
    }
}

/// Compares the run of the written program with the toolpath.
pub fn same_motion(want: &Toolpath, got: &Toolpath, digits: u8, dialect: Dialect) -> Result<(), String> {
    let unit = 10f64.powi(-i32::from(digits));
    if want.moves.len() != got.moves.len() {
        return Err(format!("{} moves written, {} read back", want.moves.len(), got.moves.len()));
    }
    let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * (1.0 + 1e-9) + 1e-9;
    for (k, (w, g)) in want.moves.iter().zip(&got.moves).enumerate() {
        let fail = |what: &str| Err(format!("move {k}: {what}\n want {w:?}\n got  {g:?}"));
        if kind_name(&w.kind) != kind_name(&g.kind) {
            return fail("kind");
        }
        let (we, ge) = (w.end.to_array(), g.end.to_array());
        if (0..6).any(|i| !near(we[i], ge[i], unit / 2.0)) {
            return fail("end point");
        }
        match (w.kind, g.kind) {
            (MoveKind::Arc(wa), MoveKind::Arc(ga)) => {
                let (i, j, _) = wa.plane.axes();
                if wa.plane != ga.plane {
                    return fail("plane");
                }
                if !near(wa.center[i], ga.center[i], 1.5 * unit) || !near(wa.center[j], ga.center[j], 1.5 * unit) {
                    return fail("centre");
                }
            }
            (MoveKind::Dwell(ws), MoveKind::Dwell(gs)) if !near(ws, gs, 0.0005) => return fail("dwell time"),
            _ => {}
        }
        if !w.is_rapid() && !matches!(w.kind, MoveKind::Dwell(_)) && !near(w.feed, g.feed, unit / 2.0) {
            return fail("feed");
        }
        if w.spindle != g.spindle || w.coolant != g.coolant || !near(w.speed, g.speed, unit / 2.0) {
            return fail("spindle or coolant");
        }
        if dialect != Dialect::Grbl && w.tool != g.tool {
            return fail("tool");
        }
    }
    Ok(())
}

pub fn point() -> impl Strategy<Value = [f64; 3]> {
    [-200.0f64..200.0, -200.0f64..200.0, -50.0f64..50.0]
}
