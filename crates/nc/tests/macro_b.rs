//! Custom Macro B through parse and run: every function, operator,
//! precedence rule and vacant case, one table row each. A value is read
//! back through a move (`G01 X#100`): a vacant `#100` leaves the X word out,
//! so no move is made.

use kezuri_nc::interp::{self, IntegerInput, Outcome, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};

fn run_with(text: &str, settings: &Settings) -> (Outcome, Sources) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.nc", text));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, text);
    if let Some(d) = diagnostics.iter().find(|d| d.is_error()) {
        panic!("{text}\ndoes not parse:\n{}", d.render(&sources));
    }
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings);
    (outcome, sources)
}

fn run(text: &str) -> Outcome {
    run_with(text, &Settings::default()).0
}

/// The error message that stopped the run, or the value of `#100` after
/// `setup` (vacant as `None`).
fn value_after(setup: &str) -> Result<Option<f64>, String> {
    let outcome = run(&format!("{setup}\nG90 G01 X#100 F1.\nM30\n"));
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        return Err(d.message.clone());
    }
    assert!(outcome.completed);
    Ok(outcome.toolpath.moves.first().map(|m| m.end.x))
}

/// `#100 = expr`, read back.
fn value(expr: &str) -> Result<Option<f64>, String> {
    value_after(&format!("#100={expr}"))
}

/// Whether `IF [cond]` holds after `setup`.
fn holds(setup: &str, cond: &str) -> bool {
    match value_after(&format!("{setup}\n#100=0\nIF[{cond}]THEN#100=1.")) {
        Ok(Some(v)) => v == 1.0,
        other => panic!("IF[{cond}]: {other:?}"),
    }
}

fn check_values(cases: &[(&str, f64)]) {
    let mut wrong = Vec::new();
    for &(expr, want) in cases {
        match value(expr) {
            Ok(Some(v)) if (v - want).abs() <= 1e-9 * want.abs().max(1.0) => {}
            got => wrong.push(format!("#100={expr}: want {want}, got {got:?}")),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn functions() {
    check_values(&[
        ("SIN[30.]", 0.5),
        ("SIN[-90.]", -1.0),
        ("COS[60.]", 0.5),
        ("COS[180.]", -1.0),
        ("TAN[45.]", 1.0),
        ("TAN[-45.]", -1.0),
        ("ASIN[0.5]", 30.0),
        ("ASIN[-1.]", -90.0),
        ("ACOS[0.5]", 60.0),
        ("ACOS[-1.]", 180.0),
        ("ATAN[1.]", 45.0),
        ("ATAN[1.]/[1.]", 45.0),
        ("ATAN[1.]/[-1.]", 135.0),
        ("ATAN[-1.]/[-1.]", 225.0),
        ("ATAN[-1.,1.]", 315.0),
        ("ATAN[0,-1.]", 180.0),
        ("ATAN[1.]/2.", 22.5),
        ("SQRT[16.]", 4.0),
        ("SQRT[2.]", std::f64::consts::SQRT_2),
        ("ABS[-3.5]", 3.5),
        ("ABS[3.5]", 3.5),
        ("ROUND[1.5]", 2.0),
        ("ROUND[-1.5]", -2.0),
        ("ROUND[2.4999]", 2.0),
        ("FIX[1.7]", 1.0),
        ("FIX[-1.7]", -1.0),
        ("FUP[1.2]", 2.0),
        ("FUP[-1.2]", -2.0),
        ("FUP[3.]", 3.0),
        ("LN[EXP[2.]]", 2.0),
        ("LN[1.]", 0.0),
        ("EXP[0]", 1.0),
        ("EXP[1.]", std::f64::consts::E),
        ("POW[2.,10.]", 1024.0),
        ("POW[9.,0.5]", 3.0),
        ("POW[-2.,3.]", -8.0),
        ("BIN[18]", 12.0),
        ("BIN[39321]", 9999.0),
        ("BCD[12]", 18.0),
        ("BCD[9999]", 39321.0),
        ("sin[30.]", 0.5),
        ("SIN [ 30. ]", 0.5),
    ]);
}

#[test]
fn function_domain_errors_stop_the_run() {
    for (expr, message) in [
        ("SQRT[-1.]", "SQRT[-1]: square root of a negative number"),
        ("ASIN[2.]", "ASIN[2]: the argument must lie between -1 and 1"),
        ("ACOS[-1.5]", "ACOS[-1.5]: the argument must lie between -1 and 1"),
        ("LN[0]", "LN[0]: logarithm of a number that is not positive"),
        ("LN[-1.]", "LN[-1]: logarithm of a number that is not positive"),
        ("TAN[90.]", "TAN[90] is infinite"),
        ("POW[-8.,0.5]", "POW[-8,0.5]: a negative base needs a whole exponent"),
        ("POW[0,-1.]", "POW[0, negative]: division by zero"),
        ("BIN[26]", "BIN[26]: not a BCD value (a nibble is 10)"),
        ("BCD[-1.]", "BCD[-1]: negative numbers have no BCD form"),
        ("EXP[1000.]", "EXP gives a result that is not a finite number"),
    ] {
        assert_eq!(value(expr), Err(message.to_string()), "{expr}");
    }
}

#[test]
fn operators() {
    check_values(&[
        ("7.*6.", 42.0),
        ("7./2.", 3.5),
        ("12 AND 10", 8.0),
        ("12 OR 10", 14.0),
        ("12 XOR 10", 6.0),
        ("17 MOD 5", 2.0),
        ("-17 MOD 5", -2.0),
        ("2.+3.", 5.0),
        ("2.-3.", -1.0),
        ("-[2.+3.]", -5.0),
        ("-2.*-3.", 6.0),
        ("+4.", 4.0),
        ("12and10", 8.0),
    ]);
    assert_eq!(value("1./0"), Err("division by zero".into()));
    assert_eq!(value("5 MOD 0"), Err("MOD by zero".into()));
    assert_eq!(value("1.5 AND 1"), Err("AND needs whole numbers up to 99999999, got 1.5".into()));
}

#[test]
fn comparisons() {
    let cases = [
        ("1 EQ 1", true),
        ("1 EQ 2", false),
        ("1 NE 2", true),
        ("1 NE 1", false),
        ("2 GT 1", true),
        ("1 GT 1", false),
        ("1 GE 1", true),
        ("0 GE 1", false),
        ("1 LT 2", true),
        ("1 LT 1", false),
        ("1 LE 1", true),
        ("2 LE 1", false),
        ("1eq1", true),
        ("[1 EQ 1] AND [2 EQ 2]", true),
        ("[1 EQ 1] AND [2 EQ 3]", false),
        ("[1 EQ 2] OR [2 EQ 2]", true),
        ("[1 EQ 1] XOR [2 EQ 2]", false),
    ];
    for (cond, want) in cases {
        assert_eq!(holds("", cond), want, "IF[{cond}]");
    }
}

#[test]
fn precedence() {
    // Functions > * / AND MOD > + - OR XOR > comparisons; left to right
    // within a level; brackets first.
    check_values(&[
        ("2.+3.*4.", 14.0),
        ("2.*3.+4.", 10.0),
        ("10.-4./2.", 8.0),
        ("1+3 AND 1", 2.0),
        ("3 AND 1+1", 2.0),
        ("1+7 MOD 4", 4.0),
        ("7 MOD 4+1", 4.0),
        ("3 OR 4*2", 11.0),
        ("4-1 OR 2", 3.0),
        ("5-1 XOR 3", 7.0),
        ("10.-4.-3.", 3.0),
        ("64./4./2.", 8.0),
        ("2.*SIN[30.]*4.", 4.0),
        ("SQRT[9.]+SQRT[16.]*2.", 11.0),
        ("[2.+3.]*4.", 20.0),
        ("2.*[3.+[4.-1.]*2.]", 18.0),
    ]);
    let cases = [
        ("1+1 EQ 2", true),
        ("2 GT 1+3", false),
        ("2*3 EQ 6", true),
        ("1 EQ 3 AND 1", true),
        ("3 AND 5 EQ 1", true),
        ("1 OR 2 EQ 3", true),
    ];
    for (cond, want) in cases {
        assert_eq!(holds("", cond), want, "IF[{cond}]");
    }
}

#[test]
fn vacant_values() {
    // The Fanuc table: a vacant variable is vacant when copied, 0 in
    // arithmetic and functions.
    let cases: [(&str, Option<f64>); 12] = [
        ("#1", None),
        ("#0", None),
        ("[#1]", None),
        ("-#1", None),
        ("#1*5.", Some(0.0)),
        ("#1+#1", Some(0.0)),
        ("#1+#2", Some(0.0)),
        ("#1-2.", Some(-2.0)),
        ("SQRT[#1]", Some(0.0)),
        ("ABS[#1]", Some(0.0)),
        ("#1 AND 3", Some(0.0)),
        ("#[#1+100]", None),
    ];
    for (expr, want) in cases {
        assert_eq!(value(expr), Ok(want), "#100={expr}");
    }
    assert_eq!(value("5./#1"), Err("division by zero".into()));
    assert_eq!(value_after("#1=#0\n#100=#1"), Ok(None));
    assert_eq!(value_after("#1=3.\n#1=#0\n#100=#1"), Ok(None));
}

#[test]
fn vacant_conditions() {
    // With #1 vacant, then with #1 = 0: EQ and NE tell vacant from 0, the
    // others take vacant as 0.
    let cases = [
        ("#1 EQ #0", true, false),
        ("#1 NE #0", false, true),
        ("#1 EQ 0", false, true),
        ("#1 NE 0", true, false),
        ("#1 GE #0", true, true),
        ("#1 GT #0", false, false),
        ("#1 GT 0", false, false),
        ("#1 LE 0", true, true),
        ("#1 LT 1", true, true),
        ("#0 EQ #0", true, true),
        ("[#1+#2] EQ #0", false, false),
        ("#1", false, false),
    ];
    for (cond, vacant, zero) in cases {
        assert_eq!(holds("", cond), vacant, "IF[{cond}] with #1 vacant");
        assert_eq!(holds("#1=0", cond), zero, "IF[{cond}] with #1 = 0");
    }
}

#[test]
fn variables() {
    assert_eq!(value_after("#1=2.\n#[#1*50]=7.5\n"), Ok(Some(7.5)));
    assert_eq!(value_after("#500=3.\n#999=4.\n#100=#500+#999"), Ok(Some(7.0)));
    assert_eq!(value_after("#199=1.25\n#100=#199"), Ok(Some(1.25)));
    assert_eq!(value_after("#33=6.\n#100=#33"), Ok(Some(6.0)));
    // A computed variable number is rounded to the nearest whole number.
    assert_eq!(value_after("#101=5.\n#100=#[100.6]"), Ok(Some(5.0)));
    assert_eq!(
        value("#34"),
        Err("#34 is not a variable of this machine: its common variables are #100–#199, #200–#499, #500–#999, \
             #900000–#999999 (the machine file's [macro] common sets them)"
            .into())
    );
    assert_eq!(value("#1036"), Err("system variable #1036 is not supported".into()));
    assert_eq!(value_after("#0=1."), Err("#0 is always vacant and cannot be assigned".into()));
    assert_eq!(value("#[-1]"), Err("#-1 is not a variable number (use whole numbers from 0 to 99999999)".into()));
}

/// The X of every move the program makes.
fn xs(text: &str, settings: &Settings) -> Vec<f64> {
    let (outcome, sources) = run_with(text, settings);
    let errors: Vec<String> = outcome.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.render(&sources)).collect();
    assert!(errors.is_empty(), "{text}\n{}", errors.join("\n"));
    outcome.toolpath.moves.iter().map(|m| m.end.x).collect()
}

#[test]
fn words_with_expressions_and_vacant_variables() {
    let s = Settings::default();
    let cases: [(&str, &[f64]); 9] = [
        ("G01 X#1 F1.", &[]),
        ("G01 X-#1 Y1. F1.", &[0.0]),
        ("G01 X[#1+2.] F1.", &[2.0]),
        ("#1=3.\nG01 X-#1 F1.", &[-3.0]),
        ("#1=3.\nG01 X[#1+2.] F1.", &[5.0]),
        ("#1=3.\nG01 X - [#1*2.] F1.", &[-6.0]),
        ("#1=1.\nG#1 X4. F1.", &[4.0]),
        ("#9=100.\nG01 X1. F#9\nG00 X#9", &[1.0, 100.0]),
        ("G01 XSQRT[4.] F1.", &[2.0]),
    ];
    for (text, want) in cases {
        assert_eq!(xs(text, &s), want, "{text}");
    }
}

#[test]
fn words_without_decimal_point() {
    let text = "G90 G01 X100 F100\nX100.\nX-5\nX0\nM30";
    let (outcome, _) = run_with(text, &Settings::default());
    let got: Vec<f64> = outcome.toolpath.moves.iter().map(|m| m.end.x).collect();
    assert_eq!(got, [0.1, 100.0, -0.005, 0.0]);
    let warned: Vec<u32> = outcome.diagnostics.iter().map(|d| d.span.start).collect();
    assert_eq!(warned, [8, 24], "X100 and X-5 are warned; X100. and X0 are not");
    assert!(outcome.diagnostics.iter().all(|d| !d.is_error()));
    let units = Settings { integer_input: IntegerInput::Units, ..Settings::default() };
    let (outcome, _) = run_with(text, &units);
    let got: Vec<f64> = outcome.toolpath.moves.iter().map(|m| m.end.x).collect();
    assert_eq!(got, [100.0, 100.0, -5.0, 0.0]);
    assert!(outcome.diagnostics.is_empty());
}

#[test]
fn modal_group_variables() {
    // #4001…#4022 after power-on, then after changing some groups.
    let mut text = String::from("POPEN\n");
    for n in 4001..=4022 {
        text.push_str(&format!("DPRNT[#{n}[31]]\n"));
    }
    text.push_str("G91 G03 G19 G95 G20 G43 H1 G59 G66 P1 X1.\n");
    for n in [4001, 4002, 4003, 4005, 4006, 4008, 4012, 4014] {
        text.push_str(&format!("DPRNT[#{n}[31]]\n"));
    }
    text.push_str("G67\nDPRNT[#4012[31]]\nM30\nO0001\nM99\n");
    let (outcome, _) = run_with(&text, &Settings::default());
    assert!(outcome.completed);
    let want = [
        "0.0", "17.0", "90.0", "22.0", "94.0", "21.0", "40.0", "49.0", "80.0", "98.0", "50.0", "67.0", "97.0", "54.0",
        "64.0", "69.0", "15.0", "40.1", "25.0", "160.0", "13.1", "50.1", // power-on
        "3.0", "19.0", "91.0", "95.0", "20.0", "43.0", "66.0", "59.0", // after the block
        "67.0",
    ];
    assert_eq!(outcome.prints, want);
}

#[test]
fn clock_seeds() {
    let text = "POPEN\n#1=#3001\n#2=#3001\nDPRNT[#1[50]*#2[50]]\nM30";
    let read = |seed| run_with(text, &Settings { clock_seed: seed, ..Settings::default() }).0.prints;
    assert_eq!(read(None), ["16 32"], "without a seed the clock ticks 16 ms per read");
    assert_eq!(read(Some(1)), read(Some(1)), "same seed, same clock");
    assert_ne!(read(Some(1)), read(Some(2)));
    for seed in 0..20 {
        let line = &read(Some(seed))[0];
        let v: Vec<f64> = line.split(' ').map(|s| s.parse().unwrap()).collect();
        let step = v[1] - v[0];
        assert!((1.0..=1000.0).contains(&v[0]) && (1.0..=1000.0).contains(&step), "seed {seed}: {line}");
    }
}

#[test]
fn macro_alarm_names_its_number_and_message() {
    let outcome = run("#1=1.\nIF[#1EQ1]THEN#3000=12 (TOOL BROKEN)\nM30");
    // Only an assignment may follow THEN; #3000 there raises the alarm.
    let error = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an alarm");
    assert_eq!(error.message, "macro alarm 3012: TOOL BROKEN");
    assert!(!outcome.completed);
}
