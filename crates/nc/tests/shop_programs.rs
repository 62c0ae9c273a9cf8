//! Programs as shops write them: keywords run together with no spaces
//! (`WH[#1LT10]DO1`, `IF[#1EQ1]GOTO5`), Haas local subprograms (`M97`)
//! after the main program's `M30`, and notes left at the end of a file.
//! Each case runs the program and checks the moves it makes.

use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{parse, Diagnostic, Program, SourceFile, Sources};

/// Parses and runs `text`; the parse diagnostics, the outcome and the
/// sources (to render diagnostics with). Panics on a parse error.
fn run_with(text: &str, settings: &Settings) -> (Vec<Diagnostic>, Outcome, Sources) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("shop.nc", text));
    let mut program = Program::default();
    let parsed = parse(&mut program, file, text);
    if let Some(d) = parsed.iter().find(|d| d.is_error()) {
        panic!("{text}\ndoes not parse:\n{}", d.render(&sources));
    }
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings);
    (parsed, outcome, sources)
}

/// The end points (X, Y) of the moves of a run that must complete.
fn ends(text: &str) -> Vec<(f64, f64)> {
    let (_, outcome, sources) = run_with(text, &Settings::default());
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        panic!("{text}\nstopped:\n{}", d.render(&sources));
    }
    assert!(outcome.completed, "{text}: the run ends at M30");
    outcome.toolpath.moves.iter().map(|m| (m.end.x, m.end.y)).collect()
}

#[test]
fn keywords_without_spaces_as_fanuc_programs_are_written() {
    // The loop and branch forms of real Fanuc and Haas programs, written
    // with no blank anywhere.
    let text = "O1000(BOLT ROW)\n\
                #1=0\n\
                WH[#1LT4]DO1\n\
                G01X[#1*10.+10.]F100.\n\
                #1=#1+1\n\
                END1\n\
                IF[#1EQ4]GOTO5\n\
                G01X99.\n\
                N5#10=7\n\
                IF[#10GT5]THEN#2=2.\n\
                GOTO#10\n\
                N6G01X66.\n\
                N7G01Y#2\n\
                M30\n";
    assert_eq!(ends(text), [(10.0, 0.0), (20.0, 0.0), (30.0, 0.0), (40.0, 0.0), (40.0, 2.0)]);
}

#[test]
fn wh_is_while_in_any_case_and_with_blanks() {
    for loop_start in ["WH[#1LT3]DO1", "wh[#1lt3]do1", "WH [#1 LT 3] DO 1", "N20WH[#1LT3]DO1", "WHILE[#1LT3]DO1"] {
        let text = format!("#1=0\n{loop_start}\n#1=#1+1\nG01X#1F100.\nEND1\nM30\n");
        assert_eq!(ends(&text), [(1.0, 0.0), (2.0, 0.0), (3.0, 0.0)], "{loop_start}");
    }
}

#[test]
fn w_is_still_an_address_when_no_bracket_follows_wh() {
    // `WH` without `[` is no loop: the W word has no value.
    let text = "WH1\nM30\n";
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("shop.nc", text));
    let parsed = parse(&mut Program::default(), file, text);
    let error = parsed.iter().find(|d| d.is_error()).expect("an error");
    assert_eq!(error.headline(&sources), "shop.nc:1:1: error: address W has no value");
}

#[test]
fn nested_unspaced_loops_with_end_labels() {
    let text = "#1=0\n\
                WH[#1LT2]DO1\n\
                #2=0\n\
                WH[#2LT2]DO2\n\
                G01X#1Y#2F50.\n\
                #2=#2+1\n\
                END2\n\
                #1=#1+1\n\
                END1\n\
                G01X9.Y9.\n\
                M30\n";
    assert_eq!(ends(text), [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0), (9.0, 9.0)]);
}
