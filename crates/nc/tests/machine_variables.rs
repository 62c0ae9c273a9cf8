//! Macro variables as a machine has them: the common variable ranges and
//! which are kept over a reset (`Settings::macro_variables`), and the
//! interface signals #1000–#1035 (inputs) and #1100–#1135 (outputs).
//! Values are read back through moves (`G01 X#100`).

use std::collections::BTreeMap;

use kezuri_nc::interp::{MacroVariables, Outcome, Settings};
use kezuri_nc::Sources;

mod common;

fn run_with(text: &str, settings: &Settings) -> (Outcome, Sources) {
    let ran = common::run("shop.nc", text, settings);
    (ran.outcome, ran.sources)
}

/// The end points (X, Y) of a run that must complete without an error.
fn ends(text: &str, settings: &Settings) -> Vec<(f64, f64)> {
    common::run("shop.nc", text, settings).path().moves.iter().map(|m| (m.end.x, m.end.y)).collect()
}

/// The one-line error that stopped the run.
fn run_error(text: &str, settings: &Settings) -> String {
    common::run("shop.nc", text, settings).headline()
}

/// Warnings, one line each.
fn warnings(outcome: &Outcome, sources: &Sources) -> Vec<String> {
    outcome.diagnostics.iter().filter(|d| !d.is_error()).map(|d| d.headline(sources)).collect()
}

fn with_ranges(common: &[&str], kept: &[&str], values: &[(u32, f64)]) -> Settings {
    let range = |t: &&str| MacroVariables::parse_range(t).unwrap();
    Settings {
        macro_variables: MacroVariables {
            common: common.iter().map(range).collect(),
            kept: kept.iter().map(range).collect(),
            values: values.iter().copied().collect(),
        },
        ..Settings::default()
    }
}

#[test]
fn the_default_ranges_hold_every_common_variable_shop_programs_use() {
    let d = Settings::default();
    for n in [100, 199, 200, 499, 500, 999, 900_000, 901_200, 901_300, 999_999] {
        // In metres: a move of 1 km is beyond any machine.
        let text = format!("#{n}={n}.\nG01 X[#{n}/1000] F100.\nM30\n");
        assert_eq!(ends(&text, &d), [(f64::from(n) / 1000.0, 0.0)], "#{n}");
    }
    // Sparse numbers are distinct variables, and #0 empties one again.
    let text = "#901200=1.\n#901201=2.\nG01 X#901200 Y#901201 F100.\n#901200=#0\nG01 X#901200 Y5.\nM30\n";
    assert_eq!(ends(text, &d), [(1.0, 2.0), (1.0, 5.0)]);
}

#[test]
fn a_variable_outside_the_configured_ranges_is_a_located_error_naming_them() {
    let fanuc_0i = with_ranges(&["100-199", "500-999"], &["500-999"], &[]);
    assert_eq!(ends("#150=1.5\n#600=2.\nG01 X#150 Y#600 F100.\nM30\n", &fanuc_0i), [(1.5, 2.0)]);
    assert_eq!(
        run_error("#150=1.\n#250=1.\nM30\n", &fanuc_0i),
        "shop.nc:2:1: error: #250 is not a variable of this machine: its common variables are \
         #100–#199, #500–#999 (the machine file's [macro] common sets them)"
    );
    // Read in a word: the error points at the word.
    assert_eq!(
        run_error("G01 F100.\nG01 X1. Y#901200\nM30\n", &fanuc_0i),
        "shop.nc:2:9: error: #901200 is not a variable of this machine: its common variables are \
         #100–#199, #500–#999 (the machine file's [macro] common sets them)"
    );
    // Between the locals and the commons there is nothing.
    assert!(run_error("#50=1.\nM30\n", &Settings::default()).starts_with("shop.nc:1:1: error: #50 is not a variable"));
    assert_eq!(
        run_error("#1=#[100000000]\nM30\n", &Settings::default()),
        "shop.nc:1:1: error: #100000000 is not a variable number (use whole numbers from 0 to 99999999)"
    );
}

#[test]
fn kept_variables_start_with_their_values_and_the_others_vacant() {
    let settings = with_ranges(
        &["100-199", "500-999", "900000-900999"],
        &["500-999", "900000-900999"],
        &[(500, 2.5), (900_001, 7.0)],
    );
    let text = "G01 X#500 Y#900001 F100.\nG01 X#100 Y1.\nM30\n";
    // #100 is vacant: the X word is left out and X stays at 2.5.
    assert_eq!(ends(text, &settings), [(2.5, 7.0), (2.5, 1.0)]);
}

#[test]
fn impossible_ranges_are_refused_before_the_run() {
    for (common, kept, values, message) in [
        (&["20-199"][..], &[][..], &[][..], "[macro]: #20–#199 overlaps the local variables #0–#33"),
        (&["500-1100"], &[], &[], "[macro]: #500–#1100 overlaps the system variables #1000–#9999"),
        (&["199-100"], &[], &[], "[macro]: #199–#100: the first number is above the last"),
        (&["100-199"], &["500-999"], &[], "[macro]: kept variable #500 is not a common variable (#100–#199)"),
        (&["100-199"], &[], &[(150, 1.0)], "[macro]: #150 is not kept over a reset"),
    ] {
        let settings = with_ranges(common, kept, values);
        let error = settings.check().expect_err(message);
        assert!(error.starts_with(message), "{error}");
        let (outcome, _) = run_with("G01 X1. F100.\nM30\n", &settings);
        assert!(!outcome.completed && outcome.toolpath.moves.is_empty());
        assert!(outcome.diagnostics[0].message.starts_with(&format!("machine settings: {message}")));
    }
    assert!(MacroVariables::parse_range("#500 - #999").is_ok_and(|r| r == (500..=999)));
    assert!(MacroVariables::parse_range("150").is_ok_and(|r| r == (150..=150)));
    assert!(MacroVariables::parse_range("100..199").is_err());
}

fn with_inputs(inputs: &[(u32, f64)]) -> Settings {
    Settings { input_signals: inputs.iter().copied().collect::<BTreeMap<_, _>>(), ..Settings::default() }
}

#[test]
fn input_bits_come_from_the_machine_file_and_1032_reads_them_all() {
    let settings = with_inputs(&[(1000, 1.0), (1005, 0.0), (1002, 1.0), (1033, 7.0)]);
    let text = "G01 X#1000 Y#1005 F100.\nG01 X#1032 Y#1033\nM30\n";
    let (outcome, sources) = run_with(text, &settings);
    assert!(outcome.completed);
    let got: Vec<(f64, f64)> = outcome.toolpath.moves.iter().map(|m| (m.end.x, m.end.y)).collect();
    assert_eq!(got, [(1.0, 0.0), (5.0, 7.0)]);
    assert!(warnings(&outcome, &sources).is_empty());
    // Bit 31 is the sign of the 32-bit group.
    let settings = with_inputs(&[(1000, 1.0), (1031, 1.0)]);
    assert_eq!(ends("G01 X[#1032/1000000] F100.\nM30\n", &settings), [(-2_147.483_647, 0.0)]);
}

#[test]
fn an_input_never_set_reads_0_with_one_warning_naming_it() {
    let text = "#100=0\nWH[#100LT3]DO1\nG01 X[#1001+#100] F100.\n#100=#100+1\nEND1\nG01 Y#1034\nM30\n";
    let (outcome, sources) = run_with(text, &Settings::default());
    assert!(outcome.completed);
    let xs: Vec<f64> = outcome.toolpath.moves.iter().map(|m| m.end.x).collect();
    assert_eq!(xs, [0.0, 1.0, 2.0, 2.0]);
    assert_eq!(
        warnings(&outcome, &sources),
        [
            "shop.nc:3:1: warning: input signal #1001 is not in the machine file ([signals] inputs): it reads 0",
            "shop.nc:6:1: warning: input signal #1034 is not in the machine file ([signals] inputs): it reads 0",
        ]
    );
}

#[test]
fn input_values_are_checked() {
    for (inputs, message) in [
        (&[(1000, 2.0)][..], "[signals]: input #1000 is one bit: 0 or 1, not 2"),
        (&[(1032, 1.0)], "[signals]: input #1032 is made of the bits #1000–#1031: set those instead"),
        (&[(1100, 1.0)], "[signals]: #1100 is not an input signal (#1000–#1031, #1033–#1035)"),
        (&[(1033, 0.5)], "[signals]: input #1033: a 32-bit signal group takes a whole number"),
    ] {
        let error = with_inputs(inputs).check().expect_err(message);
        assert!(error.starts_with(message), "{error}");
    }
    assert_eq!(
        run_error("G01 X1. F100.\n#1000=1\nM30\n", &Settings::default()),
        "shop.nc:2:1: error: #1000 is an input signal: a program can read it, not set it"
    );
}

#[test]
fn output_writes_set_the_bits_and_are_kept_between_the_moves() {
    let text = "#1100=1\n\
                G01 X1. F100.\n\
                #1132=5\n\
                G01 X[#1100+#1101*10+#1102*100]\n\
                #1101=1\n\
                G01 X#1132\n\
                #1133=4294967295\n\
                G01 Y#1133\n\
                M30\n";
    let (outcome, _) = run_with(text, &Settings::default());
    assert!(outcome.completed);
    let got: Vec<(f64, f64)> = outcome.toolpath.moves.iter().map(|m| (m.end.x, m.end.y)).collect();
    assert_eq!(got, [(1.0, 0.0), (101.0, 0.0), (7.0, 0.0), (7.0, -1.0)]);
    // Kept for the program writer between the same two moves, with their lines.
    let writes: Vec<(usize, &str, u32)> =
        outcome.toolpath.kept.iter().map(|k| (k.before, k.text.as_str(), k.line)).collect();
    assert_eq!(writes, [(0, "#1100=1", 1), (1, "#1132=5", 3), (2, "#1101=1", 5), (3, "#1133=4294967295", 7)]);
    let written = kezuri_nc::write::program(&outcome.toolpath, &Default::default()).unwrap();
    let at = |t: &str| written.find(t).unwrap_or_else(|| panic!("no {t} in {written}"));
    assert!(at("#1100=1") < at("X1.") && at("X1.") < at("#1132=5") && at("#1132=5") < at("X101."), "{written}");
    assert_eq!(
        run_error("#1100=2\nM30\n", &Settings::default()),
        "shop.nc:1:1: error: output #1100 is one bit: set it to 0 or 1, not 2"
    );
}

#[test]
fn a_wait_for_a_signal_that_never_comes_stops_at_the_loop() {
    // A program that waits for the door to close: the simulation has no
    // door, so the loop never ends and the step limit names it.
    let settings = Settings { step_limit: 1000, ..Settings::default() };
    let text = "G01 X1. F100.\nN10 WH[#1000EQ0]DO1\n#100=1\nEND1\nG01 X2.\nM30\n";
    let (outcome, sources) = run_with(text, &settings);
    assert!(!outcome.completed);
    let errors: Vec<String> =
        outcome.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.headline(&sources)).collect();
    assert_eq!(
        errors,
        ["shop.nc:2:1: error: stopped after 1000 statements: the WHILE … DO1 loop does not seem to end \
         (raise the step limit if it should run longer)"]
    );
    assert_eq!(warnings(&outcome, &sources).len(), 1, "one warning for #1000, not one per pass");
    // With the door closed in the machine file the program runs through.
    let closed = Settings { input_signals: [(1000, 1.0)].into_iter().collect(), ..settings };
    assert_eq!(ends(text, &closed), [(1.0, 0.0), (2.0, 0.0)]);
}
