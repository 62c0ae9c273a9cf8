//! Programs as shops write them: keywords run together with no spaces
//! (`WH[#1LT10]DO1`, `IF[#1EQ1]GOTO5`), Haas local subprograms (`M97`)
//! after the main program's `M30`, and notes left at the end of a file.
//! Each case runs the program and checks the moves it makes.

use kezuri_nc::interp::{Outcome, Settings};
use kezuri_nc::{parse, Diagnostic, Program, SourceFile, Sources};

mod common;

/// Parses and runs `text`; the parse diagnostics, the outcome and the
/// sources (to render diagnostics with). Panics on a parse error.
fn run_with(text: &str, settings: &Settings) -> (Vec<Diagnostic>, Outcome, Sources) {
    let ran = common::run("shop.nc", text, settings);
    (ran.parsed, ran.outcome, ran.sources)
}

/// The end points (X, Y) of the moves of a run that must complete.
fn ends(text: &str) -> Vec<(f64, f64)> {
    common::run("shop.nc", text, &Settings::default()).path().moves.iter().map(|m| (m.end.x, m.end.y)).collect()
}

/// The one-line error (`file:line:col: error: …`) that stopped the run.
fn run_error(text: &str) -> String {
    common::run("shop.nc", text, &Settings::default()).headline()
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

/// The example of M97 in the Haas mill operator's manual (96-8000): the
/// subprogram after M30 runs five times, each pass 0.2 deeper.
const HAAS_M97: &str = "O00011 (M97 CALL)\n\
                        T1 M06\n\
                        G00 G90 G54 X0 Y0 S1000 M03\n\
                        G43 H01 Z1.\n\
                        G01 Z0 F20.\n\
                        M97 P1000 L5 (L5 will cause the program to run the N1000 line five times)\n\
                        G00 G90 Z1.\n\
                        M30\n\
                        N1000 (N line that will run after M97 P1000 is run)\n\
                        G01 G91 Z-0.1\n\
                        G90 X2.\n\
                        G91 Z-0.1\n\
                        G90 X0\n\
                        M99\n";

#[test]
fn m97_runs_the_local_subprogram_l_times_and_returns_after_it() {
    let (_, outcome, _) = run_with(HAAS_M97, &Settings::default());
    assert!(outcome.completed);
    let z: Vec<f64> = outcome.toolpath.moves.iter().map(|m| (m.end.z * 10.0).round() / 10.0).collect();
    // X0 Y0, Z1, Z0, five passes of four moves, Z1.
    assert_eq!(z.len(), 24);
    assert_eq!(z[3..7], [-0.1, -0.1, -0.2, -0.2]);
    assert_eq!(z[19..23], [-0.9, -0.9, -1.0, -1.0]);
    assert_eq!(z[23], 1.0);
    let x: Vec<f64> = outcome.toolpath.moves[3..7].iter().map(|m| m.end.x).collect();
    assert_eq!(x, [0.0, 2.0, 2.0, 0.0]);
}

#[test]
fn m97_looks_for_the_label_in_the_program_it_is_in() {
    // O0002 has its own N10; the main program's N10 is not it.
    let text = "O0001\nM98 P0002\nM97 P10\nM30\nN10 G01 X1. F100.\nM99\n\
                O0002\nM97 P10 L2\nM99\nN10 G91 G01 Y5. F100.\nM99\n";
    assert_eq!(ends(text), [(0.0, 5.0), (0.0, 10.0), (1.0, 10.0)]);
    // L0 calls nothing.
    assert_eq!(ends("M97 P10 L0\nG01 X3. F100.\nM30\nN10 G01 X1.\nM99\n"), [(3.0, 0.0)]);
}

#[test]
fn m97_errors_name_the_missing_label() {
    assert_eq!(
        run_error("O0001\nG91 M97 P200\nM30\nN100 M99\n"),
        "shop.nc:2:5: error: M97 P200: there is no block N200 in O0001"
    );
    assert_eq!(run_error("M97\nM30\n"), "shop.nc:1:1: error: M97 needs P, the N number to call");
    assert_eq!(run_error("M97 P1.5\nM30\n"), "shop.nc:1:5: error: sequence number must be a whole number, got 1.5");
}

#[test]
fn notes_after_m30_are_one_warning_and_programs_after_it_still_run() {
    let text = "O0001\n\
                M97 P100\n\
                M98 P0002\n\
                M30\n\
                N100 G01 X5. F100.\n\
                M99\n\
                SETUP: VISE JAWS 2 IN OPEN\n\
                TOOL 1 = 1/2 END MILL\n\
                O0002 (SUB)\n\
                G01 Y3.\n\
                M99\n";
    let (parsed, outcome, sources) = run_with(text, &Settings::default());
    let rendered: Vec<String> = parsed.iter().map(|d| d.headline(&sources)).collect();
    assert_eq!(
        rendered,
        ["shop.nc:7:1: warning: text after M30/M02 that is not an NC block is ignored (and 1 more line like it)"]
    );
    assert!(outcome.completed);
    let ends: Vec<(f64, f64)> = outcome.toolpath.moves.iter().map(|m| (m.end.x, m.end.y)).collect();
    assert_eq!(ends, [(5.0, 0.0), (5.0, 3.0)]);
}

#[test]
fn a_note_after_m30_that_a_call_reaches_stops_the_run_there() {
    let text = "M97 P100\nM30\nN100 G01 X5. F100.\nFIXTURE NOTES\nM99\n";
    assert_eq!(
        run_error(text),
        "shop.nc:4:1: error: this line after M30 was read as a note, not an NC block (address F has no value)"
    );
}

#[test]
fn text_before_m30_that_is_no_block_is_still_an_error() {
    let text = "G01 X1. F100.\nSETUP NOTES\nM30\n";
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("shop.nc", text));
    let parsed = parse(&mut Program::default(), file, text);
    let errors: Vec<String> = parsed.iter().filter(|d| d.is_error()).map(|d| d.headline(&sources)).collect();
    assert_eq!(errors, ["shop.nc:2:1: error: address S has no value"]);
}
