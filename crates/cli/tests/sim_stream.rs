//! A simulation fed a run's path in pieces as the run makes it (what `sim`
//! does, never holding the path) cuts the same grid as the whole path:
//! every program of the corpus and the test programs, handed on a piece
//! wherever the run may cut its path (pieces of one move), gives the same
//! cells to the nanometre, the same tool for each cell, the same volumes
//! and the same rapids into the stock (their depths to a nanometre).

use std::path::{Path, PathBuf};

use kezuri_cam::sim::{simulate_tools, Cuts, Cutting, SimOptions, SimReport, Start, Stock, Tool, Tooling};
use kezuri_cam::Cutter;
use kezuri_geom::PathSink;
use kezuri_nc::interp::{self, IntegerInput, Library, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Subprograms `O####.nc` (or `O#`, with `.nc` or none) from the
/// program's folder or the test library.
struct Folder(Vec<PathBuf>);

impl Library for Folder {
    fn load(&mut self, number: u32) -> Option<SourceFile> {
        for dir in &self.0 {
            for name in
                [format!("O{number:04}.nc"), format!("O{number}.nc"), format!("O{number:04}"), format!("{number}.nc")]
            {
                if let Ok(bytes) = std::fs::read(dir.join(&name)) {
                    let text = String::from_utf8_lossy(&bytes).into_owned();
                    return Some(SourceFile::new(dir.join(name).display().to_string(), text));
                }
            }
        }
        None
    }
}

/// The program files of the corpus, the test programs and the samples.
fn programs() -> Vec<PathBuf> {
    let root = root();
    let mut out = Vec::new();
    let mut walk = vec![root.join("corpus/shop"), root.join("samples"), root.join("bench/programs")];
    for dir in ["interp", "seeds", "write", "shop", "fuzz"] {
        walk.push(root.join("crates/nc/testdata").join(dir));
    }
    while let Some(dir) = walk.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for path in entries.flatten().map(|e| e.path()) {
            let name = path.to_string_lossy().to_lowercase();
            if path.is_dir() {
                walk.push(path);
            } else if name.ends_with(".nc") || name.ends_with(".ngc") || name.ends_with(".tap") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn a_simulation_fed_a_run_in_pieces_cuts_the_whole_paths_grid() {
    let ball = Tool::Cutter("ball:3".parse::<Cutter>().unwrap());
    let library = root().join("crates/nc/testdata/library");
    let (mut compared, mut cut_some, mut in_pieces, mut rapids) = (0, 0, 0, 0);
    for path in programs() {
        let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
        let name = path.display().to_string();
        let mut sources = Sources::default();
        let file = sources.add(SourceFile::new(name.as_str(), text.as_str()));
        let mut program = Program::default();
        if parse(&mut program, file, &text).iter().any(|d| d.is_error()) || program.units.is_empty() {
            continue;
        }
        let mut whole_program = Program::default();
        parse(&mut whole_program, file, &text);
        let lower = name.to_lowercase();
        let units = lower.ends_with(".ngc") || lower.contains(".linuxcnc.") || lower.contains(".grbl.");
        let integer_input = if units { IntegerInput::Units } else { IntegerInput::Increments };
        let settings = Settings { piece_moves: 1, integer_input, ..Settings::default() };
        let mut folder = Folder(vec![path.parent().unwrap().to_path_buf(), library.clone()]);
        let whole = interp::run(&mut whole_program, &mut sources.clone(), 0, &mut folder, &settings);
        let path_whole = &whole.toolpath;
        let Ok(stock) = Stock::around_tool(path_whole, &ball) else { continue };
        // At most some 40,000 cells.
        let area = (stock.x1 - stock.x0) * (stock.y1 - stock.y0);
        let res = (area / 40_000.0).sqrt().max(0.05);
        // Halfway down the path: the feeds cut, and some rapids.
        let (lo, hi) = path_whole.bounds().unwrap();
        let stock = Stock { top: stock.top.min((lo[2] + hi[2]) / 2.0), ..stock };
        let mut options = SimOptions::new(res);
        options.max_memory = 1 << 30;
        let start = Start::Box(stock);
        let Ok(mut want_grid) = start.rows(&options, 0..start.grid(&options).unwrap().ny) else { continue };
        let mut got_grid = want_grid.clone();
        let want = simulate_tools(path_whole, Tooling::One(&ball), &mut want_grid, &options, &|_, _| {});
        let first = path_whole.moves.iter().map(|m| m.tool).find(|&t| t != 0).unwrap_or(0);
        // And where the first tool is not known before the run (`sim --tool`
        // runs the program once, into the cutting).
        let mut unknown_grid = got_grid.clone();
        let mut cutting = Cutting::new(Tooling::One(&ball), &mut got_grid, &options, Some(first), Some(start)).unwrap();
        let mut unknown = Cutting::new(Tooling::One(&ball), &mut unknown_grid, &options, None, Some(start)).unwrap();
        let mut pieces = Counted { sink: (&mut cutting, &mut unknown), count: 0 };
        let handed = interp::run_into(&mut program, &mut sources, 0, &mut folder, &settings, &mut pieces);
        assert_eq!(handed.diagnostics.len(), whole.diagnostics.len(), "{name}");
        let count = pieces.count;
        let report = |(cuts, cut_by): (Cuts, Vec<u8>)| SimReport { cut_by, ..cuts.report(res) };
        let got = cutting.finish().map(report);
        let not_known_first = unknown.finish().map(report);
        let tools = |r: &Result<SimReport, kezuri_cam::Error>| r.as_ref().map(|r| r.tools.clone()).map_err(|e| e.kind);
        assert_eq!(tools(&got), tools(&not_known_first), "{name}: the first tool learnt in the run");
        let cut_by = |r: &Result<SimReport, kezuri_cam::Error>| r.as_ref().map(|r| r.cut_by.clone()).ok();
        assert!(cut_by(&got) == cut_by(&not_known_first), "{name}: the tool of every cell");
        assert_eq!(got_grid.nm, unknown_grid.nm, "{name}");
        let (mut want, mut got) = match (want, got) {
            (Ok(w), Ok(g)) => (w, g),
            (Err(w), Err(g)) => {
                assert_eq!(w.kind, g.kind, "{name}: the same error");
                continue;
            }
            (w, g) => panic!("{name}: whole {:?}, in pieces {:?}", w.err(), g.err()),
        };
        assert_eq!(got_grid.nm, want_grid.nm, "{name}: every cell");
        assert_eq!(got.cut_by, want.cut_by, "{name}: the tool of every cell");
        assert_eq!(got.rapid_hits.len(), want.rapid_hits.len(), "{name}: rapids into the stock");
        for (g, w) in got.rapid_hits.iter().zip(&want.rapid_hits) {
            assert_eq!((g.index, g.line), (w.index, w.line), "{name}");
            assert!((g.depth - w.depth).abs() <= 1e-6, "{name}: {} against {}", g.depth, w.depth);
        }
        rapids += want.rapid_hits.len();
        (got.rapid_hits, want.rapid_hits) = (Vec::new(), Vec::new());
        assert_eq!(got, want, "{name}: the report");
        compared += 1;
        cut_some += usize::from(want.tools.iter().any(|t| t.volume > 0.0));
        in_pieces += usize::from(count > 2);
    }
    println!(
        "{compared} programs compared, {cut_some} cut material, {in_pieces} in pieces, {rapids} rapids into stock"
    );
    // Pinned, so that the test cannot pass by comparing nothing.
    assert!(
        compared >= 85 && cut_some >= 45 && in_pieces >= 75 && rapids >= 10,
        "{compared} {cut_some} {in_pieces} {rapids}"
    );
}

/// A sink fed the pieces, counted.
struct Counted<S> {
    sink: S,
    count: usize,
}

impl<S: PathSink> PathSink for Counted<S> {
    fn take(&mut self, piece: &kezuri_geom::Toolpath, programmed: Option<&kezuri_geom::Toolpath>) {
        self.count += 1;
        self.sink.take(piece, programmed);
    }
}
