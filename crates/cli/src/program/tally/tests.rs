//! The tally taken piece by piece is the tally of the whole path, to the
//! bit, for every program of the repository.

use std::path::PathBuf;

use kezuri_geom::{PathSink, Toolpath};
use kezuri_machine::{Machine, ToolEntry};
use kezuri_nc::interp::{self, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

use super::{Tallied, Tally};
use crate::files::Folder;
use crate::program::corpus::each_case;
use crate::program::dialect_settings;

/// A sink that counts the pieces it hands on to a tally.
struct Counted {
    tally: Tally,
    pieces: usize,
}

impl PathSink for Counted {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.tally.take(piece, programmed);
        self.pieces += 1;
    }
}

/// A mill whose tool table gives T1 to T30, every seventh with an H
/// register not its own number (so that the check of Z moves without the
/// tool's length offset has something to say).
fn machine() -> Machine {
    let mut machine = Machine::default();
    for t in 1..=30 {
        let h = if t % 7 == 0 { t + 100 } else { t };
        machine.tools.insert(t, ToolEntry { shape: None, h, d: None, name: None, nose: None });
    }
    machine
}

#[test]
fn every_program_tallied_in_pieces_is_tallied_whole() {
    let machine = machine();
    let tally = || Tally::new(&machine.dynamics, &machine.kinematics, true);
    let (mut compared, mut cut, mut warned) = (0, 0, 0);
    each_case(&machine, |mut case| {
        let name = case.name.clone();
        let mut all = tally();
        all.take(&case.whole.toolpath, None);
        let all: Tallied = all.finish(&case.whole, &machine.tools);
        let mut pieces = Counted { tally: tally(), pieces: 0 };
        let handed = case.run_into(&mut pieces);
        let in_pieces = pieces.tally.finish(&handed, &machine.tools);
        // Debug writes every f64 so that it reads back to the same bits (and
        // −0 apart from +0): equal text is equal bits.
        assert_eq!(format!("{in_pieces:?}"), format!("{all:?}"), "{name}");
        assert_eq!(in_pieces, all, "{name}");
        // The lengths are summed as the path's own sums are.
        let path = &case.whole.toolpath;
        assert_eq!(all.report.feed_length_mm.to_bits(), path.feed_length().to_bits(), "{name}");
        assert_eq!(all.report.rapid_length_mm.to_bits(), path.rapid_length().to_bits(), "{name}");
        compared += 1;
        cut += usize::from(pieces.pieces > 2);
        warned += usize::from(!all.unoffset_z.is_empty() || !all.missing_axes.is_empty());
    });
    // Pinned, so that the test cannot pass by comparing nothing.
    assert!(compared >= 180 && cut >= 100 && warned >= 10, "{compared} programs, {cut} cut in pieces, {warned} warned");
}

/// A LinuxCNC program of `n` moves: straight feeds of 1 µm to 60 mm at
/// varied feeds and headings (runs of tiny ones along a line among them),
/// arcs, dwells and rapids, and W beside X Y in its second half.
fn long_program(n: usize) -> String {
    let mut r = kezuri_geom::SplitMix64::new(7);
    let mut text = String::from("G21 G90 G17 G94 G54\nG0 X0 Y0 Z5\nG1 Z-1 F500\n");
    let (mut x, mut y, mut heading) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..n {
        let length = match r.below(4) {
            0 => 0.001 * (1 + r.below(10)) as f64,
            1 => 0.1 + r.next_f64(),
            2 => 1.0 + 10.0 * r.next_f64(),
            _ => 10.0 + 50.0 * r.next_f64(),
        };
        heading += match r.below(4) {
            0 => 0.0,
            1 => 0.01 * r.normal(),
            2 => std::f64::consts::PI,
            _ => 2.0 * r.next_f64(),
        };
        // On the program's 0.1 µm grid, so that it goes where it says.
        let grid = |v: f64| (v * 1e4).round() / 1e4;
        let (to_x, to_y) = (grid(x + length * heading.cos()), grid(y + length * heading.sin()));
        let feed = 200 * (1 + r.below(40));
        text += &match r.below(100) {
            0..2 => format!("G0 Z5\nG0 X{to_x:.4} Y{to_y:.4}\nG1 Z-1 F{feed}\n"),
            2..4 => {
                text += &format!("G4 P{:.3}\n", r.next_f64());
                continue;
            }
            4..10 => format!("G2 X{to_x:.4} Y{to_y:.4} I{:.4} J{:.4} F{feed}\n", (to_x - x) / 2.0, (to_y - y) / 2.0),
            // W beside X Y, from the second half on.
            10..12 if k > n / 2 => format!("G1 X{to_x:.4} Y{to_y:.4} W{:.3} F{feed}\n", r.next_f64()),
            _ => format!("G1 X{to_x:.4} Y{to_y:.4} F{feed}\n"),
        };
        (x, y) = (to_x, to_y);
    }
    text + "M2\n"
}

#[test]
fn a_long_program_in_pieces_of_any_size_takes_the_same_time_to_the_bit() {
    let machine = machine();
    let text = long_program(50_000);
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new("long.ngc", text.clone()));
    let mut program = Program::default();
    assert!(parse_as(&mut program, id, &text, Dialect::LinuxCnc).is_empty());
    let settings = dialect_settings(Dialect::LinuxCnc, None, &machine);
    let library = || Folder::new(PathBuf::from("."));
    let whole = interp::run(&mut program.clone(), &mut sources.clone(), 0, &mut library(), &settings);
    assert!(whole.diagnostics.is_empty() && whole.toolpath.moves.len() > 50_000, "{:?}", whole.diagnostics.first());
    let mut all = Tally::new(&machine.dynamics, &machine.kinematics, false);
    all.take(&whole.toolpath, None);
    let all = all.finish(&whole, &machine.tools);
    assert!(all.report.time_s > 60.0, "{}", all.report.time_s);
    assert!(all.report.uvw_bounds[2].is_some() && all.report.uvw_bounds[0].is_none(), "{:?}", all.report.uvw_bounds);
    for piece_moves in [1, 7, 4096] {
        let settings = Settings { piece_moves, ..settings.clone() };
        let mut pieces = Counted { tally: Tally::new(&machine.dynamics, &machine.kinematics, false), pieces: 0 };
        let handed =
            interp::run_into(&mut program.clone(), &mut sources.clone(), 0, &mut library(), &settings, &mut pieces);
        assert!(pieces.pieces > whole.toolpath.moves.len() / (2 * (piece_moves + 1)), "{} pieces", pieces.pieces);
        let in_pieces = pieces.tally.finish(&handed, &machine.tools);
        assert_eq!(in_pieces.report.time_s.to_bits(), all.report.time_s.to_bits(), "pieces of {piece_moves}");
        assert_eq!(format!("{in_pieces:?}"), format!("{all:?}"), "pieces of {piece_moves}");
    }
}
