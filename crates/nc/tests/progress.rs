//! Progress through a program by bytes: the parser counts the bytes it has
//! read, the interpreter stores the offset of the block it runs (a loop
//! moves it back), for the progress bar another thread draws.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use kezuri_nc::interp::{self, Library, Settings};
use kezuri_nc::{parse_as, parse_counting, Dialect, Program, SourceFile, Sources};

/// A raster of `rows` rows, a few hundred kilobytes: several 64 KiB steps.
fn raster(rows: usize) -> String {
    let mut s = String::from("%\nO0001\nG90 G21 G17\nG0 X0 Y0 Z5.\nG1 Z-1. F800.\n");
    for r in 0..rows {
        s += &format!("G1 X{}. Y{}.\nG1 X0. Y{}.5\n", 100 + r % 7, r, r);
    }
    s + "M30\n%\n"
}

#[test]
fn the_parse_counts_every_byte_and_reads_as_without_counting() {
    let text = raster(10_000);
    assert!(text.len() > 4 * 65_536, "{} bytes", text.len());
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new("raster.nc", text.clone()));
    let done = AtomicU64::new(0);
    let (mut counted, mut plain) = (Program::default(), Program::default());
    let d1 = parse_counting(&mut counted, id, &text, Dialect::Fanuc, &done);
    let d2 = parse_as(&mut plain, id, &text, Dialect::Fanuc);
    assert_eq!(done.load(Ordering::Relaxed), text.len() as u64);
    assert_eq!(format!("{d1:?}"), format!("{d2:?}"));
    assert_eq!(counted.blocks.len(), plain.blocks.len());
    // Three set-up blocks, two a row, M30 (the '%' lines and O0001 are
    // not blocks).
    assert_eq!(counted.blocks.len(), 3 + 2 * 10_000 + 1);
}

/// Subprograms from a folder: each load notes where the main program's
/// counter stands at that moment.
struct Noting {
    counter: Arc<AtomicU64>,
    seen: Vec<(u32, u64)>,
}

impl Library for Noting {
    fn load(&mut self, number: u32) -> Option<SourceFile> {
        self.seen.push((number, self.counter.load(Ordering::Relaxed)));
        Some(SourceFile::new(format!("O{number}.nc"), format!("O{number}\nG4 P1\nM99\n")))
    }
}

#[test]
fn the_run_follows_the_blocks_back_through_a_goto_loop() {
    // Each pass of the loop calls two subprograms not loaded yet (O1000,
    // O1001, then O1002, O1003): the first at the loop's top, the second
    // lower; GOTO 10 takes the run back up, and the counter with it.
    let text = "O0001\n#1=1000\nN10 M98 P#1\n#1=#1+1\nM98 P#1\n#1=#1+1\nIF[#1LT1004]GOTO10\nM30\n";
    let top = text.find("N10").unwrap() as u64;
    let lower = text.match_indices("M98 P#1").nth(1).unwrap().0 as u64;
    assert!(lower > top);
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new("loop.nc", text));
    let mut program = Program::default();
    let counter = Arc::new(AtomicU64::new(0));
    assert!(parse_counting(&mut program, id, text, Dialect::Fanuc, &counter).iter().all(|d| !d.is_error()));
    assert_eq!(counter.load(Ordering::Relaxed), text.len() as u64);
    let mut library = Noting { counter: Arc::clone(&counter), seen: Vec::new() };
    let settings = Settings { progress: Some(Arc::clone(&counter)), ..Settings::default() };
    let outcome = interp::run(&mut program, &mut sources, 0, &mut library, &settings);
    assert!(outcome.completed, "{:?}", outcome.diagnostics);
    assert_eq!(library.seen, [(1000, top), (1001, lower), (1002, top), (1003, lower)]);
    // The last block run is M30 (the subprograms' blocks, in files of their
    // own, leave it alone).
    assert_eq!(counter.load(Ordering::Relaxed), text.find("M30").unwrap() as u64);
    // Without a counter the run is the same.
    let mut again = Program::default();
    let mut sources2 = Sources::default();
    let id2 = sources2.add(SourceFile::new("loop.nc", text));
    parse_as(&mut again, id2, text, Dialect::Fanuc);
    let mut quiet = Noting { counter: Arc::new(AtomicU64::new(0)), seen: Vec::new() };
    let plain = interp::run(&mut again, &mut sources2, 0, &mut quiet, &Settings::default());
    assert_eq!(format!("{:?}", plain.toolpath), format!("{:?}", outcome.toolpath));
}
