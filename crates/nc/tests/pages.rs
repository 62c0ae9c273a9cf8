//! A program read in pages runs as the program read whole, holding a few
//! pages: loops, jumps back and forth and subprogram calls over programs
//! many pages long.

use kezuri_geom::Toolpath;
use kezuri_nc::interp::{self, NoLibrary, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};

/// Lines a page holds here, and pages of plain blocks held at once.
const LINES: usize = 64;
const KEEP: usize = 2;

/// `text` read whole and read in pages: both runs' paths (which must be
/// equal) and the blocks the paged program holds at the end.
fn both(text: &str) -> (Toolpath, usize) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("long.nc", text));
    let mut whole = Program::default();
    assert!(parse(&mut whole, file, text).is_empty());
    let mut paged = Program::default();
    paged.read_in_pages(LINES, KEEP);
    assert!(parse(&mut paged, file, text).is_empty());
    let settings = Settings::default();
    let a = interp::run(&mut whole, &mut sources.clone(), 0, &mut NoLibrary, &settings);
    let b = interp::run(&mut paged, &mut sources, 0, &mut NoLibrary, &settings);
    assert!(a.completed, "{:?}", a.diagnostics.first());
    assert_eq!(format!("{:?}", a.diagnostics), format!("{:?}", b.diagnostics));
    assert_eq!(a.toolpath, b.toolpath);
    assert!(paged.pages_read_again() > 0, "the run came back to a dropped page");
    (b.toolpath, paged.blocks.iter().count())
}

/// `n` plain cutting blocks, numbered N`first`… where `numbered`.
fn body(n: usize, first: usize, numbered: bool) -> String {
    (0..n)
        .map(|k| {
            let label = if numbered { format!("N{} ", first + k) } else { String::new() };
            format!("{label}G01 X{}. Y{}. F100.\n", k % 7, k % 5)
        })
        .collect()
}

#[test]
fn a_loop_around_many_pages() {
    let text = format!("G90\n#1=0\nWHILE[#1LT3]DO1\n{}#1=#1+1\nEND1\nM30\n", body(5000, 0, false));
    let (path, held) = both(&text);
    assert_eq!(path.moves.len(), 3 * 5000);
    // The statements' page, the last page and two plain pages.
    assert!(held <= 4 * LINES, "{held} blocks held");
}

#[test]
fn jumps_back_and_forth_by_sequence_number() {
    // Every block numbered, as CAM programs are: a jump back to the middle
    // of the first 5000 blocks, then one forward over the next 3000 (found
    // by the numbers each page holds, their pages never read again).
    let text = format!(
        "G90\n#1=0\n{}N90000 #1=#1+1\nIF[#1LT2]GOTO2500\nGOTO99999\n{}N99999 M30\n",
        body(5000, 1, true),
        body(3000, 10000, true)
    );
    let (path, held) = both(&text);
    assert_eq!(path.moves.len(), 5000 + 2501);
    assert!(held <= 4 * LINES, "{held} blocks held");
}

#[test]
fn a_subprogram_at_the_end_of_a_long_file() {
    let text = format!(
        "O1\nG90\n{}M98 P2 L2\n{}M30\nO2\n{}M99\n",
        body(2000, 0, false),
        body(2000, 0, false),
        body(700, 0, false)
    );
    let (path, _) = both(&text);
    assert_eq!(path.moves.len(), 2000 + 2 * 700 + 2000);
}
