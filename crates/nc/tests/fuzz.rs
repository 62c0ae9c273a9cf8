//! A fuzz test that needs no fuzzing tools: proptest makes NC-like programs
//! (words, `#` variables, brackets, `IF`/`GOTO`/`WHILE`, `G65`/`M98` calls,
//! comments), LinuxCNC programs (O-word subroutines and control flow,
//! named parameters, `**`, `EXISTS`, `(debug,…)`), and plain random bytes
//! read in both dialects; each must parse and run without a panic and
//! within a small step limit.
//!
//! Slow, so it runs only when `KEZURI_FUZZ` is set (to the number of cases,
//! or to anything else for 2,000):
//! `KEZURI_FUZZ=20000 cargo test --release -p kezuri-nc --test fuzz`.
//! The coverage-guided fuzz target is `fuzz/` (see fuzz/README.md).

use kezuri_nc::{interp, parse_as, Dialect, Program, SourceFile, Sources};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};

const STEP_LIMIT: u64 = 10_000;

/// Parses and runs `text` as the fuzz target does; fails on a run that does
/// not stop at the step limit. A panic fails the test by itself.
fn parse_and_run(text: &str) -> Result<(), TestCaseError> {
    parse_and_run_as(text, Dialect::Fanuc)
}

/// A library whose every LinuxCNC subroutine file is the program itself,
/// so `o<name> call` of a name the program does not define loads it again.
struct Itself(String);

impl interp::Library for Itself {
    fn load(&mut self, _: u32) -> Option<SourceFile> {
        None
    }

    fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
        Some(SourceFile::new(format!("{stem}.ngc"), self.0.clone()))
    }
}

fn parse_and_run_as(text: &str, dialect: Dialect) -> Result<(), TestCaseError> {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("fuzz.nc", text));
    let mut program = Program::default();
    for d in parse_as(&mut program, file, text, dialect) {
        d.render(&sources);
    }
    let integer_input =
        if dialect == Dialect::LinuxCnc { interp::IntegerInput::Units } else { interp::IntegerInput::Increments };
    let settings = interp::Settings { step_limit: STEP_LIMIT, dialect, integer_input, ..interp::Settings::default() };
    let mut library = Itself(text.to_string());
    for main in 0..program.units.len().min(2) {
        let outcome = interp::run(&mut program, &mut sources, main, &mut library, &settings);
        prop_assert!(outcome.statements <= STEP_LIMIT + 1, "ran {} statements", outcome.statements);
        for d in &outcome.diagnostics {
            d.render(&sources);
        }
    }
    Ok(())
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-2000i32..2000).prop_map(|n| n.to_string()),
        (-2000.0f64..2000.0).prop_map(|v| format!("{v:.3}")),
        Just("0".to_string()),
        Just(".5".to_string()),
        Just("1.".to_string()),
        Just("99999999".to_string()),
        Just("1234567890123456789".to_string()),
    ]
}

fn variable() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(0u32),
        1u32..34,
        100u32..110,
        500u32..503,
        prop::sample::select(vec![
            3000, 3001, 3002, 4001, 4003, 4109, 5001, 5021, 5041, 5061, 5221, 5321, 5341, 1000, 1032, 1100, 1132, 2001,
            2201, 10001, 13001, 900000, 901200
        ]),
    ]
    .prop_map(|n| format!("#{n}"))
}

/// An expression, nested a few levels.
fn expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![number(), variable()];
    leaf.prop_recursive(4, 24, 3, |inner| {
        let func = prop::sample::select(vec![
            "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN", "EXP", "BIN",
            "BCD",
        ]);
        let op = prop::sample::select(vec![
            "+", "-", "*", "/", " AND ", " OR ", " XOR ", " MOD ", " EQ ", " NE ", " GT ", " GE ", " LT ", " LE ",
        ]);
        prop_oneof![
            (inner.clone(), op, inner.clone()).prop_map(|(a, o, b)| format!("[{a}{o}{b}]")),
            (func, inner.clone()).prop_map(|(f, a)| format!("{f}[{a}]")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("POW[{a},{b}]")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("ATAN[{a}]/[{b}]")),
            inner.clone().prop_map(|a| format!("#[{a}]")),
            inner.prop_map(|a| format!("-{a}")),
        ]
    })
}

fn word() -> impl Strategy<Value = String> {
    let letter = prop::sample::select(b"ABCDEFGHIJKLMNPQRSTUVWXYZ".to_vec());
    let code = prop::sample::select(vec![
        "G00", "G01", "G02", "G03", "G04", "G17", "G18", "G19", "G20", "G21", "G28", "G31", "G40", "G41", "G43", "G49",
        "G53", "G54", "G59", "G65", "G66", "G66.1", "G67", "G80", "G90", "G91", "G92", "G94", "G95", "M03", "M05",
        "M06", "M08", "M09", "M98", "M99", "M30", "G05.1", "G08", "G10", "G15", "G16", "G30", "G41.1", "G50", "G50.1",
        "G51", "G51.1", "G52", "G68", "G69", "G73", "G74", "G76", "G81", "G82", "G83", "G84", "G85", "G86", "G87",
        "G88", "G89", "G98", "G99", "G92.1", "G90.1", "G91.1", "G187", "M19", "M29", "M97", "M10",
    ]);
    prop_oneof![
        code.prop_map(str::to_string),
        (letter.clone(), number()).prop_map(|(l, n)| format!("{}{n}", l as char)),
        (letter, expr()).prop_map(|(l, e)| format!("{}{e}", l as char)),
    ]
}

fn line() -> impl Strategy<Value = String> {
    let label = 1u32..4;
    prop_oneof![
        4 => prop::collection::vec(word(), 1..6).prop_map(|w| w.join(" ")),
        2 => (variable(), expr()).prop_map(|(v, e)| format!("{v}={e}")),
        1 => (expr(), 1u32..20).prop_map(|(c, n)| format!("IF [{c}] GOTO {n}")),
        1 => (expr(), variable(), expr()).prop_map(|(c, v, e)| format!("IF [{c}] THEN {v}={e}")),
        1 => (1u32..20).prop_map(|n| format!("GOTO {n}")),
        1 => (expr(), label.clone()).prop_map(|(c, m)| format!("WHILE [{c}] DO{m}")),
        1 => label.clone().prop_map(|m| format!("DO {m}")),
        1 => label.prop_map(|m| format!("END{m}")),
        1 => (1u32..20, prop::collection::vec(word(), 0..4)).prop_map(|(n, w)| format!("N{n} {}", w.join(" "))),
        1 => (prop::sample::select(vec![10u32, 11, 12, 9010]), prop::collection::vec(word(), 0..4))
            .prop_map(|(p, w)| format!("G65 P{p} {}", w.join(" "))),
        1 => (prop::sample::select(vec![10u32, 11, 12, 50010]), 0u32..4).prop_map(|(p, l)| format!("M98 P{p} L{l}")),
        1 => prop::sample::select(vec![
            "%", "O0010", "O0011 (SUB)", "O0012", "O9010", "M99", "M99 P5", "POPEN", "PCLOS", "DPRNT[X#1[43]*Y#2]",
            "(COMMENT", "; semicolon", "/ G00 X1.", "o100 sub", "#<name>=1", "$H", "[", "]", "#", "G", "X--1",
        ])
        .prop_map(str::to_string),
    ]
}

fn program() -> impl Strategy<Value = String> {
    prop::collection::vec(line(), 0..40).prop_map(|lines| lines.join("\n"))
}

/// A LinuxCNC parameter: numbered or named, local, global or predefined.
fn parameter() -> impl Strategy<Value = String> {
    prop_oneof![
        variable(),
        prop::sample::select(vec![
            "#<a>",
            "#<b>",
            "#<_g>",
            "#<_x>",
            "#<_z>",
            "#<_value>",
            "#<_value_returned>",
            "#<_line>",
            "#<_metric>",
            "#<_feed>",
            "#<_call_level>",
            "#<_motion_mode>",
            "#<unset>",
            "#31",
            "#4999",
            "#5000",
            "#< Spaced Name >",
        ])
        .prop_map(str::to_string),
    ]
}

/// A LinuxCNC expression: rs274ngc's operators and functions.
fn lexpr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![number(), parameter()];
    leaf.prop_recursive(3, 16, 3, |inner| {
        let func = prop::sample::select(vec!["SIN", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN", "EXP"]);
        let op = prop::sample::select(vec![
            "+", "-", "*", "/", "**", " AND ", " OR ", " XOR ", " MOD ", " EQ ", " NE ", " GT ", " LT ",
        ]);
        prop_oneof![
            (inner.clone(), op, inner.clone()).prop_map(|(a, o, b)| format!("[{a}{o}{b}]")),
            (func, inner.clone()).prop_map(|(f, a)| format!("{f}[{a}]")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("ATAN[{a}]/[{b}]")),
            prop::sample::select(vec!["a", "_g", "unset"]).prop_map(|n| format!("EXISTS[#<{n}>]")),
            inner.prop_map(|a| format!("-{a}")),
        ]
    })
}

/// A LinuxCNC O-word line: names few, so that constructs meet, nest and
/// cross.
fn oword() -> impl Strategy<Value = String> {
    let name = prop::sample::select(vec!["o1", "o2", "o3", "o<s>", "o<lib>", "o<T>"]);
    let bare = prop::sample::select(vec![
        "sub",
        "endsub",
        "return",
        "else",
        "endif",
        "endwhile",
        "do",
        "endrepeat",
        "break",
        "continue",
        "call",
    ]);
    let with_expr = prop::sample::select(vec!["if", "elseif", "while", "repeat", "endsub", "return"]);
    prop_oneof![
        (name.clone(), bare).prop_map(|(n, k)| format!("{n} {k}")),
        (name.clone(), with_expr, lexpr()).prop_map(|(n, k, e)| format!("{n} {k} [{e}]")),
        (name, prop::collection::vec(lexpr(), 0..4))
            .prop_map(|(n, a)| format!("{n} call {}", a.iter().map(|e| format!("[{e}]")).collect::<String>())),
    ]
}

fn linuxcnc_line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => oword(),
        2 => prop::collection::vec(word(), 1..5).prop_map(|w| w.join(" ")),
        2 => prop::collection::vec((parameter(), lexpr()), 1..4)
            .prop_map(|s| s.iter().map(|(p, e)| format!("{p}={e}")).collect::<Vec<_>>().join(" ")),
        1 => (parameter(), parameter()).prop_map(|(a, b)| format!("(debug, a={a} b={b})")),
        1 => parameter().prop_map(|a| format!("(print,{a})")),
        1 => (lexpr(), lexpr()).prop_map(|(a, b)| format!("G1 X{a} Y[{b}] F100")),
        1 => prop::sample::select(vec!["M2", "M30", "%", "O100", "o", "o<", "o<> call", "o1 if", "#<=1", "#<_x>=1"])
            .prop_map(str::to_string),
    ]
}

fn linuxcnc_program() -> impl Strategy<Value = String> {
    prop::collection::vec(linuxcnc_line(), 0..40).prop_map(|lines| lines.join("\n"))
}

fn cases() -> Option<u32> {
    let value = std::env::var("KEZURI_FUZZ").ok()?;
    Some(value.parse().unwrap_or(2_000))
}

#[test]
fn nc_like_programs_end_without_a_panic() {
    let Some(cases) = cases() else { return };
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    runner.run(&program(), |text| parse_and_run(&text)).unwrap();
}

#[test]
fn linuxcnc_programs_end_without_a_panic() {
    let Some(cases) = cases() else { return };
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    runner.run(&linuxcnc_program(), |text| parse_and_run_as(&text, Dialect::LinuxCnc)).unwrap();
}

#[test]
fn random_bytes_end_without_a_panic() {
    let Some(cases) = cases() else { return };
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let bytes = prop::collection::vec(
        prop_oneof![any::<u8>(), prop::sample::select(b"GXYZ#[]=.-+0123456789 \n()IFGOTOWHILEDOENDo<>*sub".to_vec())],
        0..400,
    );
    runner
        .run(&bytes, |data| {
            let text = String::from_utf8_lossy(&data);
            parse_and_run(&text)?;
            parse_and_run_as(&text, Dialect::LinuxCnc)
        })
        .unwrap();
}

/// A word of a lathe program: the codes and addresses a Fanuc or Haas
/// lathe reads (U W H, G32, G50 S, G96, C R I K chamfers, ,C ,R, T0101).
fn lathe_word() -> impl Strategy<Value = String> {
    let letter = prop::sample::select(b"XZUWCHIKRFSTPQ".to_vec());
    let code = prop::sample::select(vec![
        "G00", "G01", "G02", "G03", "G04", "G18", "G20", "G21", "G28", "G32", "G33", "G50", "G90", "G92", "G94", "G96",
        "G97", "G98", "G99", "G40", "G41", "G42", "M03", "M05", "M30", ",C1.", ",R2.", ",C-1", "T0101", "T0100", "T1",
    ]);
    prop_oneof![code.prop_map(str::to_string), (letter, number()).prop_map(|(l, n)| format!("{}{n}", l as char)),]
}

#[test]
fn lathe_programs_end_without_a_panic() {
    let Some(cases) = cases() else { return };
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let program = prop::collection::vec(prop::collection::vec(lathe_word(), 1..6).prop_map(|w| w.join(" ")), 0..30)
        .prop_map(|lines| lines.join("\n"));
    runner
        .run(&program, |text| {
            parse_and_run_as(&text, Dialect::FanucLathe)?;
            parse_and_run_as(&text, Dialect::HaasLathe)
        })
        .unwrap();
}
