//! A program read in pages runs as the program read whole, holding a few
//! pages: loops, jumps back and forth and subprogram calls over programs
//! many pages long.

use kezuri_geom::Toolpath;
use kezuri_nc::interp::{self, NoLibrary, Outcome, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

/// Lines a page holds here, and pages of plain blocks held at once.
const LINES: usize = 64;
const KEEP: usize = 2;

/// `text` read whole and read in pages: both runs' paths (which must be
/// equal) and the blocks the paged program holds at the end.
fn both(text: &str) -> (Toolpath, usize) {
    let (outcome, held) = both_in(text, Dialect::Fanuc, &Settings::default());
    assert!(outcome.completed, "{:?}", outcome.diagnostics.first());
    (outcome.toolpath, held)
}

/// [`both`] in `dialect` with `settings`, for runs that stop too: the
/// paged run's outcome (its diagnostics and path the whole run's).
fn both_in(text: &str, dialect: Dialect, settings: &Settings) -> (Outcome, usize) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("long.nc", text));
    let mut whole = Program::default();
    assert!(parse_as(&mut whole, file, text, dialect).is_empty());
    let mut paged = Program::default();
    paged.read_in_pages(LINES, KEEP);
    assert!(parse_as(&mut paged, file, text, dialect).is_empty());
    let settings = Settings { dialect, ..settings.clone() };
    let a = interp::run(&mut whole, &mut sources.clone(), 0, &mut NoLibrary, &settings);
    let b = interp::run(&mut paged, &mut sources, 0, &mut NoLibrary, &settings);
    assert_eq!(format!("{:?}", a.diagnostics), format!("{:?}", b.diagnostics));
    assert_eq!(a.toolpath, b.toolpath);
    assert!(paged.pages_read_again() > 0, "the run came back to a dropped page");
    (b, paged.blocks.iter().count())
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

#[test]
fn errors_name_blocks_on_dropped_pages() {
    // A GOTO loop round 3,000 blocks stopped by the step limit, as the
    // whole program's run stops.
    let settings = Settings { step_limit: 10_000, ..Settings::default() };
    let text = format!("G90\nN10 G01 X0. F100.\n{}GOTO10\nM30\n", body(3000, 0, false));
    let (o, _) = both_in(&text, Dialect::Fanuc, &settings);
    let e = o.diagnostics.iter().find(|d| d.is_error()).expect("stopped");
    assert!(e.message.contains("the backward GOTO here does not seem to end"), "{}", e.message);
    // A Haas local subprogram (M97) long after its label stops with an
    // error: the call chain names the label's block.
    let text = format!(
        "O0001\nG90\nM97 P100\nM30\n{}N100 G01 X0. F100.\n{}#1=1/0\nM99\n",
        body(200, 0, false),
        body(3000, 0, false)
    );
    let (o, _) = both_in(&text, Dialect::Haas, &Settings::default());
    let e = o.diagnostics.iter().find(|d| d.is_error()).expect("stopped");
    assert_eq!(e.call_chain.first().map(|c| c.0.as_str()), Some("local subprogram N100 of O0001 (M97)"));
}
