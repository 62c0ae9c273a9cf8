//! The writers fed a toolpath piece by piece (`ProgramWriter`,
//! `CsvWriter`): what they must be told ahead to write the whole path's
//! text, and what they refuse. Every program of the corpora fed as a run
//! hands it on is `portable_corpus.rs`.

mod common;

use common::writer::{sample, Path};
use kezuri_geom::{Axes, AxisSet, MoveKind, Toolpath};
use kezuri_nc::interp::{self, Settings};
use kezuri_nc::write::{csv, may_move_uvw, program, CsvWriter, ProgramWriter, WriteOptions};
use kezuri_nc::{parse_as, Dialect, Error, ErrorKind, Place, Program, SourceFile, Sources};

/// `path` cut into pieces of one move, as `split_before` cuts it.
fn pieces(path: &Toolpath) -> Vec<Toolpath> {
    let mut rest = path.clone();
    let mut out = Vec::new();
    while !rest.moves.is_empty() {
        out.push(rest.split_before(1));
    }
    out.push(rest);
    out
}

/// The text `writer` writes fed `path` in pieces of one move.
fn fed(mut writer: ProgramWriter, path: &Toolpath) -> Result<String, Error> {
    let mut text = String::new();
    for piece in pieces(path) {
        text += &writer.piece(&piece, None)?;
    }
    Ok(text + &writer.finish()?)
}

/// A made five-axis fragment: A and B turn after the first positioning.
fn rotary() -> Toolpath {
    let mut p = Path::default();
    p.rapid(0.0, 0.0, 50.0);
    p.push(MoveKind::Rapid, Axes { b: 90.0, ..p.at });
    p.feed(0.0, 0.0, 20.0, 500.0);
    p.push(MoveKind::Feed, Axes { a: -45.5, x: 10.0, ..p.at });
    p.path.clone()
}

#[test]
fn a_made_path_names_the_axes_told_ahead_on_its_first_positioning() {
    let o = WriteOptions::default();
    let whole = program(&rotary(), &o).unwrap();
    assert!(whole.contains("\nG00 X0. Y0. Z50. A0. B0.\nB90.\n"), "{whole}");
    let ab = AxisSet::NONE.with(3).with(4);
    assert_eq!(fed(ProgramWriter::new(&o).unwrap().with_axes(ab), &rotary()).unwrap(), whole);
    // Not told, the writer names A and B from the moves that turn them.
    let untold = fed(ProgramWriter::new(&o).unwrap(), &rotary()).unwrap();
    assert_eq!(untold, whole.replace("Z50. A0. B0.", "Z50."));
}

#[test]
fn an_axis_the_dialect_has_not_is_refused_at_the_move_that_turns_it() {
    let grbl = WriteOptions { dialect: kezuri_nc::write::Dialect::Grbl, ..WriteOptions::default() };
    let whole = program(&rotary(), &grbl).unwrap_err();
    // Told or not: the axis told ahead is left to the moves.
    for writer in [ProgramWriter::new(&grbl).unwrap(), ProgramWriter::new(&grbl).unwrap().with_axes(AxisSet::ALL)] {
        let e = fed(writer, &rotary()).unwrap_err();
        assert_eq!((e.kind, e.place), (ErrorKind::RotaryAxis, Place::Move { index: 1, line: 2 }));
        assert_eq!(e.to_string(), whole.to_string());
    }
}

#[test]
fn a_post_that_pre_stages_needs_the_tools_ahead() {
    let haas = WriteOptions::preset("haas").unwrap();
    let path = sample();
    let whole = program(&path, &haas).unwrap();
    let order = vec![1, 2];
    assert!(whole.contains("\nT1 M06\nT2\n"), "{whole}");
    assert_eq!(fed(ProgramWriter::new(&haas).unwrap().with_tool_order(order), &path).unwrap(), whole);
    let untold = fed(ProgramWriter::new(&haas).unwrap(), &path).unwrap();
    assert!(untold.contains("\nT1 M06\n") && !untold.contains("\nT2\n"), "{untold}");
}

#[test]
fn the_controls_limits_are_those_of_the_whole_program() {
    let path = sample();
    let size = program(&path, &WriteOptions::default()).unwrap().len() as u64;
    // Over the memory by a byte, within it; a block longer than the line
    // buffer (the first, numbered from the program's first line).
    for (o, refused) in [
        (WriteOptions { byte_limit: Some(size - 1), ..WriteOptions::default() }, true),
        (WriteOptions { byte_limit: Some(size), ..WriteOptions::default() }, false),
        (WriteOptions { block_limit: Some(12), ..WriteOptions::default() }, true),
    ] {
        let whole = program(&path, &o).map_err(|e| e.to_string());
        assert_eq!(whole.is_err(), refused, "{whole:?}");
        assert_eq!(fed(ProgramWriter::new(&o).unwrap(), &path).map_err(|e| e.to_string()), whole);
    }
}

/// The CSV of LinuxCNC program `text`, run whole (`csv`) and handed on in
/// pieces of one move to a writer whose columns `may_move_uvw` chose.
fn csv_both_ways(text: &str) -> (String, Result<String, String>) {
    /// `o<uv> call` reads `uv.ngc`: a move of U and V.
    struct Uv;
    impl interp::Library for Uv {
        fn load(&mut self, _: u32) -> Option<SourceFile> {
            None
        }
        fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
            (stem == "uv").then(|| SourceFile::new("uv.ngc", "o<uv> sub\nG1 U3 V4 F60\no<uv> endsub\n"))
        }
    }
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("uvw.ngc", text));
    let mut program = Program::default();
    assert!(parse_as(&mut program, file, text, Dialect::LinuxCnc).is_empty());
    let settings = Settings { dialect: Dialect::LinuxCnc, piece_moves: 1, ..Settings::default() };
    let whole = interp::run(&mut program.clone(), &mut sources.clone(), 0, &mut Uv, &settings);
    assert!(whole.completed, "{:?}", whole.diagnostics);
    struct Sink(CsvWriter, Result<String, String>);
    impl kezuri_geom::PathSink for Sink {
        fn take(&mut self, piece: &Toolpath, _: Option<&Toolpath>) {
            if let Ok(text) = &mut self.1 {
                match self.0.piece(piece) {
                    Ok(rows) => text.push_str(&rows),
                    Err(e) => self.1 = Err(e.to_string()),
                }
            }
        }
    }
    let mut sink = Sink(CsvWriter::new(may_move_uvw(&program, Dialect::LinuxCnc)), Ok(String::new()));
    interp::run_into(&mut program, &mut sources, 0, &mut Uv, &settings, &mut sink);
    let streamed = sink.1.map(|t| t + &sink.0.finish());
    (csv(&whole.toolpath), streamed)
}

#[test]
fn the_csv_has_u_v_w_where_the_program_can_move_them() {
    // U V W words.
    let (whole, streamed) = csv_both_ways("G21 G90\nG0 X0 Y0 U0\nG1 U3 V4 F60\nG1 X3 Y4 U10 F60\nM2\n");
    assert!(whole.starts_with("line,kind,x,y,z,a,b,c,feed,u,v,w\n"), "{whole}");
    assert_eq!(streamed, Ok(whole));
    // A program without them has no columns either way.
    let (whole, streamed) = csv_both_ways("G0 X1\nG1 X2 F100\nM2\n");
    assert!(whole.starts_with("line,kind,x,y,z,a,b,c,feed\n") && streamed == Ok(whole));
    // Named but never moved: the columns, of zeros, where the whole path
    // has none.
    let (whole, streamed) = csv_both_ways("G0 X1. U0\nM2\n");
    assert_eq!(whole, "line,kind,x,y,z,a,b,c,feed\n1,rapid,1,0,0,0,0,0,\n");
    assert_eq!(streamed.unwrap(), "line,kind,x,y,z,a,b,c,feed,u,v,w\n1,rapid,1,0,0,0,0,0,,0,0,0\n");
    // Moved by a subprogram the program's text does not hold: refused at
    // the move, never dropped.
    let (whole, streamed) = csv_both_ways("G0 X1\no<uv> call\nM2\n");
    assert!(whole.contains("feed,u,v,w\n"), "{whole}");
    assert_eq!(streamed, Err("move 2 (line 2): the CSV has no u,v,w columns, but the toolpath moves U".into()));
}
