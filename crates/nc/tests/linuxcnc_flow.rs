//! LinuxCNC's program language (issue 18): O-word subroutines and control
//! flow, named parameters, rs274ngc's expressions, and the bad input around
//! them. Each expectation comes from LinuxCNC's manual (O Codes, Named
//! Parameters, Expressions) and was confirmed by running the same program
//! through `rs274 -g` (LinuxCNC 2.9's standalone interpreter) once; the
//! figures are written here by hand, so these tests need no rs274.
//! `rs274_agrees` runs rs274 again where it is installed.
//! O-word labels and subroutine definitions are `linuxcnc_labels.rs`.

mod common;

use common::ngc::{assert_ends, error_at, run, run_with, settings};
use kezuri_nc::interp::{self, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

const SUBS_AND_FLOW: &str = "F100
o100 sub
  G1 X#1 Y#2
  #<loc>=#1
  o100 return [#1*10]
o100 endsub
o<sq> sub
  (debug, sq #1 #<_value> #<_value_returned>)
  o<sq> return [#1*#1]
  G1 Z99
o<sq> endsub
o100 call [3] [4]
(debug, v=#<_value> r=#<_value_returned> ex=EXISTS[#<loc>] one=#1)
o<sq> call [5]
(debug, v=#<_value> r=#<_value_returned>)
o<SQ> call
(debug, v=#<_value> r=#<_value_returned>)
o1 if [#<_value> GT 10]
  G1 X1
o1 elseif [#<_value> EQ 0]
  G1 X2
o1 else
  G1 X3
o1 endif
#1=0
o2 while [#1 LT 3]
  #1=[#1+1]
  o3 if [#1 EQ 2]
    o2 continue
  o3 endif
  G1 Y#1
o2 endwhile
o4 do
  #1=[#1-1]
  G1 Z#1
  o5 if [#1 LT 1]
    o4 break
  o5 endif
o4 while [#1 GT -5]
o6 repeat [2.6]
  G1 X[#1+10]
  #1=[#1+1]
o6 endrepeat
M2
";

#[test]
fn subroutines_branches_and_loops_as_rs274_runs_them() {
    let ran = run(SUBS_AND_FLOW).ok();
    // rs274 -g: STRAIGHT_FEED end points.
    assert_ends(
        &ran,
        &[
            [3.0, 4.0, 0.0],
            [2.0, 4.0, 0.0],
            [2.0, 1.0, 0.0],
            [2.0, 3.0, 0.0],
            [2.0, 3.0, 2.0],
            [2.0, 3.0, 1.0],
            [2.0, 3.0, 0.0],
            [10.0, 3.0, 0.0],
            [11.0, 3.0, 0.0],
            [12.0, 3.0, 0.0],
        ],
    );
    // rs274's MESSAGE(…) lines, but `EXISTS[…]`, which a debug comment
    // does not evaluate (rs274 prints it with the parameter replaced).
    assert_eq!(
        ran.outcome.prints,
        [
            " v=30.000000 r=1.000000 ex=EXISTS[######] one=0.000000",
            " sq 5.000000 30.000000 1.000000",
            " v=25.000000 r=1.000000",
            " sq 0.000000 25.000000 1.000000",
            " v=0.000000 r=1.000000",
        ]
    );
}

const RECURSION_AND_SCOPE: &str = "F100
#<_gg>=1
#<n>=0
o<tri> sub
  #<n>=[#1*10]
  G1 X#1 Y#<n>
  o<tri> if [#1 GT 1]
    o<tri> call [#1-1]
  o<tri> endif
  #<_gg>=[#<_gg>+1]
o<tri> endsub
o<tri> call [3]
(debug, n=#<n> gg=#<_gg> lvl=#<_call_level> v=#<_value_returned>)
o10 while [#<n> LT 100]
  o11 repeat [2]
    #<n>=[#<n>+1]
    o13 while [1]
      o12 if [#<n> EQ 4]
        o10 break
      o12 endif
      o13 break
    o13 endwhile
    G1 Z#<n>
  o11 endrepeat
o10 endwhile
(print, after n=#<n>)
G20
G0 X1 Y2 Z0.5
(debug, #<_x> #<_y> #<_z> #<_metric> #<_imperial> #<_motion_mode> #<_feed>)
G21 G91
(debug, #<_incremental> #<_absolute> #<_plane> #<_coord_system>)
M2
";

#[test]
fn recursion_locals_globals_and_predefined_parameters() {
    let ran = run(RECURSION_AND_SCOPE).ok();
    assert_ends(
        &ran,
        &[
            [3.0, 30.0, 0.0],
            [2.0, 20.0, 0.0],
            [1.0, 10.0, 0.0],
            [1.0, 10.0, 1.0],
            [1.0, 10.0, 2.0],
            [1.0, 10.0, 3.0],
            [25.4, 50.8, 12.7],
        ],
    );
    assert_eq!(
        ran.outcome.prints,
        [
            " n=0.000000 gg=4.000000 lvl=0.000000 v=0.000000",
            " after n=4.000000",
            " 1.000000 2.000000 0.500000 0.000000 1.000000 0.000000 100.000000",
            " 1.000000 0.000000 170.000000 540.000000",
        ]
    );
}

const EXPRESSIONS: &str = "#1=2 #2=[#1+1]
G1 X#2 F100
#3=[7.5 MOD 2] #4=[-7.5 MOD 2] #5=FIX[-1.5] #6=FUP[-1.5] #7=ROUND[-1.5] #8=ROUND[2.5]
(debug, a #3 b #4 c #5 d #6 e #7 f #8)
#9=[1 EQ 1.00005] #10=[1 EQ 1.0002] #11=[1 NE 1.00005] #12=[2 ** 3 * 2] #13=[-2 ** 2]
(debug, eq #9 #10 ne #11 pow #12 #13)
#14=[ATAN[-1]/[-1]] #15=[3 AND 0.5] #16=[0 OR 0] #17=[1 XOR 1] #18=[1 + 2 AND 0] #19=[1 LT 2 AND 3 GT 4]
(debug, atan #14 and #15 or #16 xor #17 prec #18 #19)
#<foo>=3
#<_g>=[#<foo>+1] #20=EXISTS[#<foo>] #21=EXISTS[#<bar>] #31=[2 + 3 ** 2 * 2 MOD 7] #5000=[#4999+1]
(debug, g=#<_g> exists #20 #21 prec #31 #5000 #<_line> #<_motion_mode> #<_feed> un=#<bar>)
G1 X[10 - 2 - 3] Y[12 / 2 / 3] Z[2 ** 3 ** 2]
M2
";

#[test]
fn expressions_as_rs274_computes_them() {
    let ran = run(EXPRESSIONS).ok();
    // `#1=2 #2=[#1+1]`: #1 is read (0) before it is set, so X1.
    assert_ends(&ran, &[[1.0, 0.0, 0.0], [5.0, 2.0, 64.0]]);
    assert_eq!(
        ran.outcome.prints,
        [
            " a 1.500000 b 0.500000 c -2.000000 d -1.000000 e -2.000000 f 3.000000",
            " eq 1.000000 0.000000 ne 0.000000 pow 16.000000 4.000000",
            " atan -135.000000 and 1.000000 or 0.000000 xor 0.000000 prec 0.000000 0.000000",
            " g=4.000000 exists 1.000000 0.000000 prec 6.000000 1.000000 11.000000 10.000000 100.000000 un=######",
        ]
    );
}

#[test]
fn subroutine_files_come_from_the_library() {
    let libsub = "o<libsub> sub\nG1 X#1 F10\n#<_gl>=7\no<libsub> endsub [3]\nM2\n";
    let numbered = "o123 sub\nG1 Y#2 F10\no123 endsub\nM2\n";
    let main = "o<LibSub> call [4]\n(debug, #<_value> #<_gl>)\no123 call [1] [2]\nM2\n";
    let ran = run_with(main, &[("libsub", libsub), ("123", numbered)], &settings()).ok();
    assert_ends(&ran, &[[4.0, 0.0, 0.0], [4.0, 2.0, 0.0]]);
    assert_eq!(ran.outcome.prints, [" 3.000000 7.000000"]);
    // The call chain of an error inside a library subroutine names it.
    let bad = "o<oops> sub\n#1=[1/0]\no<oops> endsub\n";
    let ran = run_with("o<oops> call\nM2\n", &[("oops", bad)], &settings());
    let d = ran.outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error");
    assert!(d.message.contains("division by zero"), "{}", d.message);
    assert_eq!(d.call_chain.len(), 1);
    assert_eq!(d.call_chain[0].0, "subroutine o<oops>");
}

#[test]
fn a_subroutine_defined_after_its_call_is_found() {
    // rs274 searches the file on for it.
    let ran = run("o<later> call\nM2\no<later> sub\nG1 X5 F1\no<later> endsub\n").ok();
    assert_ends(&ran, &[[5.0, 0.0, 0.0]]);
}

#[test]
fn nine_levels_of_calls_and_no_tenth() {
    // rs274: "in later 1" … "in later 9", then "Too many subroutine levels".
    let text = "o<later> sub\n(debug,in later #<_call_level>)\no<later> call\no<later> endsub\no<later> call\nM2\n";
    let e = error_at(text, 3);
    assert!(e.contains("nested deeper than 9"), "{e}");
    let ran = run(text);
    assert_eq!(ran.outcome.prints.len(), 9);
    assert_eq!(ran.outcome.prints[8], "in later 9.000000");
}

#[test]
fn bad_o_words_are_located_errors() {
    // Each as rs274 refuses it (its words in the comment).
    // "not in a subroutine definition"
    assert!(error_at("G0 X1\no1 endsub\nM2\n", 2).contains("o1 endsub has no o1 sub before it"));
    // "undefined O-word label"
    assert!(error_at("o1 if [1]\no2 endif\nM2\n", 2).contains("o2 endif"));
    assert!(error_at("G0 X1\no1 if [1]\nG0 X2\nM2\n", 2).contains("o1 if has no o1 endif"));
    assert!(error_at("o1 while [1]\nG0 X2\nM2\n", 1).contains("o1 while has no o1 endwhile"));
    assert!(error_at("o1 do\nG0 X2\no1 endwhile\nM2\n", 3).contains("o1 endwhile"));
    assert!(error_at("o1 break\nM2\n", 1).contains("not inside a loop named o1"));
    // "no matching while/do label … found 'repeat'"
    assert!(error_at("o1 repeat [2]\no1 break\no1 endrepeat\nM2\n", 2).contains("not o1 repeat"));
    assert!(error_at("o1 if [1]\no1 continue\no1 endif\nM2\n", 2).contains("not a loop"));
    // "Nested subroutine definition"
    assert!(error_at("o1 sub\no2 sub\no2 endsub\no1 endsub\nM2\n", 2).contains("not defined inside another"));
    assert!(error_at("o1 sub\no3 if [1]\no2 sub\no2 endsub\no3 endif\no1 endsub\nM2\n", 3).contains("inside o1 sub"));
    assert!(error_at("o1 if [1]\no1 else\no1 elseif [1]\no1 endif\nM2\n", 3).contains("after o1 else"));
    assert!(error_at("o1 if [1]\no2 while [1]\no1 endif\no2 endwhile\nM2\n", 3).contains("must nest"));
    assert!(error_at("o1 return\nM2\n", 1).contains("not inside a subroutine"));
    assert!(error_at("o1 call [1\nM2\n", 1).contains("not closed"));
    assert!(error_at("o1 frobnicate\nM2\n", 1).contains("expected sub, endsub"));
    // "EOF in file … seeking o-word: o<missing>"
    let e = error_at("G0 X1\no<missing> call\nM2\n", 2);
    assert!(e.contains("o<missing> is not defined") && e.contains("missing.ngc"), "{e}");
}

#[test]
fn bad_parameters_are_located_errors() {
    // "Named parameter #<bar> not defined"
    assert!(error_at("G0 X1\n#1=#<bar>\nM2\n", 2).contains("#<bar> is read before it is set"));
    // "Cannot assign to read-only parameter #<_x>"
    assert!(error_at("#<_x>=1\nM2\n", 1).contains("predefined"));
    assert!(error_at("#<_a>=1\nM2\n", 1).contains("predefined"));
    // A local named parameter is not seen in a subroutine: rs274 prints
    // "in ######" for it.
    let ran = run("#<a>=1\no1 sub\n(debug, in #<a>)\no1 endsub\no1 call\nM2\n").ok();
    assert_eq!(ran.outcome.prints, [" in ######"]);
    assert!(error_at("#1=[1/0]\nM2\n", 1).contains("division by zero"));
    assert!(error_at("#1=POW[2,3]\nM2\n", 1).contains("write a ** b"));
    assert!(error_at("#1=EXISTS[#2]\nM2\n", 1).contains("EXISTS takes a named parameter"));
}

#[test]
fn a_loop_without_end_stops_at_the_step_limit() {
    let settings = Settings { step_limit: 10_000, ..settings() };
    let ran = run_with("#1=0\no1 while [1]\n#1=[#1+1]\no1 endwhile\nM2\n", &[], &settings);
    let e = ran.error().expect("a runaway error");
    assert!(e.starts_with("t.ngc:2:") && e.contains("the o1 while loop does not seem to end"), "{e}");
    let ran = run_with("o1 do\no1 while [1]\nM2\n", &[], &settings);
    assert!(ran.error().unwrap().contains("the o1 do loop does not seem to end"));
    let ran = run_with("o2 sub\no2 call\no2 endsub\no2 call\nM2\n", &[], &settings);
    assert!(ran.error().unwrap().contains("nested deeper"));
}

#[test]
fn linuxcnc_numbered_parameters_are_plain_globals() {
    // rs274: #31…#5000 hold what they are given; #1000 (a Fanuc input
    // signal) and #3000 (a Fanuc alarm) are plain parameters too; never
    // set, a parameter reads 0.
    let ran = run("#31=4 #5000=2 #4999=1\n(debug, #31 #5000 #3000 #1000)\n#1000=5\n(debug, #1000)\nM2\n").ok();
    assert_eq!(ran.outcome.prints, [" 4.000000 2.000000 0.000000 0.000000", " 5.000000"]);
    // A word with a parameter never set is 0, not left out (Fanuc's vacant).
    let ran = run("G1 X#7 Y1 F1\nM2\n").ok();
    assert_ends(&ran, &[[0.0, 1.0, 0.0]]);
}

#[test]
fn fanuc_reading_is_unchanged() {
    // The same words in the Fanuc dialect: O-words and named parameters
    // are not Fanuc's.
    let mut sources = Sources::default();
    let text = "o1 if [1]\nG0 X1\no1 endif\nM30\n";
    let file = sources.add(SourceFile::new("t.nc", text));
    let mut program = Program::default();
    assert!(parse_as(&mut program, file, text, Dialect::Fanuc).is_empty());
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &Settings::default());
    assert!(outcome.diagnostics.iter().any(|d| d.message.contains("--dialect linuxcnc")));
}

/// Runs each program above through rs274 where it is installed and checks
/// that its motion end points are the ones written into the tests.
#[test]
fn rs274_agrees() {
    let rs274 = std::path::Path::new("/usr/bin/rs274");
    if !rs274.exists() {
        eprintln!("rs274_agrees: skipped, /usr/bin/rs274 is not installed (Debian's linuxcnc-uspace has it)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("kezuri-linuxcnc-flow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (i, text) in [SUBS_AND_FLOW, RECURSION_AND_SCOPE, EXPRESSIONS, MIXED_LINES, COMPUTED_LABELS].iter().enumerate()
    {
        let path = dir.join(format!("p{i}.ngc"));
        std::fs::write(&path, text).unwrap();
        let out = std::process::Command::new(rs274)
            .arg("-g")
            .arg(&path)
            .current_dir(&dir)
            .env("HOME", &dir)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let mut theirs = Vec::new();
        let mut inch = false;
        for line in stdout.lines() {
            inch |= line.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)");
            if line.contains("USE_LENGTH_UNITS(CANON_UNITS_MM)") {
                inch = false;
            }
            let Some(args) = line.split("STRAIGHT_FEED(").nth(1).or_else(|| line.split("STRAIGHT_TRAVERSE(").nth(1))
            else {
                continue;
            };
            let v: Vec<f64> = args.trim_end_matches(')').split(',').map(|s| s.trim().parse().unwrap()).collect();
            let k = if inch { 25.4 } else { 1.0 };
            theirs.push([v[0] * k, v[1] * k, v[2] * k]);
        }
        let ours = run(text).ok().ends();
        assert_eq!(ours.len(), theirs.len(), "program {i}: ours {ours:?}\nrs274 {theirs:?}\n{stdout}");
        for (a, b) in ours.iter().zip(&theirs) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3), "program {i}: {a:?} vs rs274 {b:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

const PREDEFINED: &str = "(debug,v #<_vmajor> #<_vminor> #<_task> #<_call_level> #<_remap_level>)
(debug,o #<_feed_override> #<_speed_override> #<_adaptive_feed> #<_feed_hold>)
(debug,m #<_selected_pocket> #<_ijk_absolute_mode> #<_lathe_diameter_mode> #<_lathe_radius_mode> #<_spindle_css_mode> #<_spindle_rpm_mode>)
(debug,n #<_coolant_flood> #<_tool_change>)
T0
(debug,t0 #<_selected_pocket>)
T3 G90.1
(debug,t #<_selected_tool> #<_selected_pocket> #<_ijk_absolute_mode>)
o1 sub
(debug,s #<_call_level> #<_remap_level>)
o1 endsub
o1 call
G91.1
(debug,i #<_ijk_absolute_mode>)
M2
";

#[test]
fn predefined_parameters_read_as_rs274_reads_them() {
    // rs274 -g, its MESSAGE lines. `_coolant_flood` and `_tool_change` are
    // not LinuxCNC's (its coolant ones are `_flood` and `_mist`).
    let ran = run(PREDEFINED).ok();
    assert_eq!(
        ran.outcome.prints,
        [
            "v 2.900000 0.000000 0.000000 0.000000 0.000000",
            "o 1.000000 1.000000 0.000000 1.000000",
            "m -1.000000 0.000000 0.000000 1.000000 0.000000 1.000000",
            "n ###### ######",
            "t0 -1.000000",
            "t 3.000000 3.000000 1.000000",
            "s 1.000000 0.000000",
            "i 0.000000",
        ]
    );
    // "Cannot assign to read-only parameter #<_vmajor>"
    assert!(error_at("#<_vmajor>=1\nM2\n", 1).contains("predefined"));
    assert!(error_at("G0 X1\n#<_feed_override>=0.5\nM2\n", 2).contains("predefined"));
    // Kezuri's machine works in mm (rs274 run alone reads -1 here).
    let ran = run("(debug,#<_metric_machine> #<_current_pocket>)\nM2\n").ok();
    assert_eq!(ran.outcome.prints, ["1.000000 0.000000"]);
}

const MIXED_LINES: &str = "F100
#1=5 G1 X#1 Y[#1+1]
(debug,after #1)
G1 X#1 #1=7 Y#1 #2=#1
(debug,now #1 #2)
#3=2 (debug,same #3) G1 Z#3
#<foo>=3 #<_g>=[#<foo>+1] G1 X#<foo>
(debug,g #<_g> foo #<foo>)
#<foo>=9 G1 Y#<foo> #<bar>=[#<foo>*2]
(debug,foo #<foo> bar #<bar>)
#4=1 #4=2
(debug,last #4)
G1 X1 (debug,a) (debug,b #1)
G1 X2 (debug,c) (plain)
G1 X3 ; (debug,semi)
(msg, hello #1 there)
(MSG,loud)
G1 X4 (print,p) (msg,m)
(logopen,run.log)
(log,first #1 #<_x>)
G1 X5 (log,second #2)
(logclose)
(log,nowhere)
(logappend,run.log)
(log,third)
(LOGCLOSE)
M2 (debug,end)
";

#[test]
fn a_line_of_settings_words_and_comments_runs_as_rs274_runs_it() {
    let ran = run(MIXED_LINES).ok();
    // rs274 -g: the words read the parameters as they were before the line
    // (X#1 is X0 on line 2, Y#1 Y5 on line 4 after #1=7 in it), a named
    // parameter first set on the line reads 0 after its setting (X#<foo>
    // on line 7), the debug comment runs after the settings.
    assert_ends(
        &ran,
        &[
            [0.0, 1.0, 0.0],
            [5.0, 5.0, 0.0],
            [5.0, 5.0, 0.0],
            [0.0, 5.0, 0.0],
            [0.0, 3.0, 0.0],
            [1.0, 3.0, 0.0],
            [2.0, 3.0, 0.0],
            [3.0, 3.0, 0.0],
            [4.0, 3.0, 0.0],
            [5.0, 3.0, 0.0],
        ],
    );
    // Its MESSAGE lines: only a line's last comment counts, none after ';',
    // msg as written.
    assert_eq!(
        ran.outcome.prints,
        [
            "after 5.000000",
            "now 7.000000 5.000000",
            "same 2.000000",
            "g 1.000000 foo 3.000000",
            "foo 9.000000 bar 6.000000",
            "last 2.000000",
            "b 7.000000",
            " hello #1 there",
            "loud",
            "m",
            "end",
        ]
    );
    // Its LOGOPEN, LOG, LOGCLOSE, LOGAPPEND calls; the line logged with no
    // file open goes nowhere, with a warning.
    assert_eq!(
        ran.outcome.logs,
        [
            interp::LogFile {
                name: "run.log".into(),
                append: false,
                lines: vec!["first 7.000000 4.000000".into(), "second 5.000000".into()],
            },
            interp::LogFile { name: "run.log".into(), append: true, lines: vec!["third".into()] },
        ]
    );
    let warning = ran.outcome.diagnostics.iter().find(|d| d.message.contains("no log file open")).expect("a warning");
    assert_eq!(warning.render(&ran.sources).split(':').nth(1), Some("23"));
}

#[test]
fn a_named_parameter_set_on_its_line_reads_0_after_the_setting() {
    // rs274: `#<b>=[#<b>+1]` sets #<b> to 1 where it was not set.
    let ran = run("#<b>=[#<b>+1]\n#<c>=[#<b>+1] #<d>=#<c>\n(debug,#<b> #<c> #<d>)\nM2\n").ok();
    assert_eq!(ran.outcome.prints, ["1.000000 2.000000 0.000000"]);
    // Read before its setting on the line: "Named parameter #<baz> not defined".
    assert!(error_at("F1\nG1 X#<baz> #<baz>=2\nM2\n", 2).contains("#<baz> is read before it is set"));
    // An O-word after a setting: "Bad character 'o' used".
    assert!(error_at("o100 sub\no100 endsub\n#1=5 o100 call\nM2\n", 3).contains("Bad character 'o' used"));
    // A setting's bad value is located on its line, words or not.
    assert!(error_at("G0 X1\nG1 X2 #1=[1/0]\nM2\n", 2).contains("division by zero"));
    assert!(error_at("G0 X1\nG1 X[1/0] #1=2\nM2\n", 2).contains("division by zero"));
}

/// Computed labels on every construct (the figures below are rs274 2.9's,
/// `rs274 -g`). Each section's labels differ from the others': a label
/// opens one construct in the main program.
const COMPUTED_LABELS: &str = "F100
#1=100
(if: computed at both ends, or at one)
o#1 if [#1 GT 0]
  G1 X1
o#1 endif
o[#1+1] if [1]
  G1 X2
o101 endif
(a branch not taken: its setting does not run, so the endif reads 102)
o[#1+2] if [0]
  G1 X99
  #1=7
o102 endif
(elseif and else, a named parameter)
#<lbl>=3
#2=0
o30 repeat [4]
  #2=[#2+1]
  o#<lbl> if [#2 EQ 1]
    G1 Y1
  o[#<lbl>] elseif [#2 EQ 2]
    G1 Y2
  o3 elseif [#2 EQ 3]
    G1 Y3
  o#<lbl> else
    G1 Y4
  o#<lbl> endif
o30 endrepeat
(do and while, continue)
#2=0
#5=50
o#5 do
  #2=[#2+1]
  o21 if [#2 EQ 2]
    o#5 continue
  o21 endif
  G1 X[#2+10]
o#5 while [#2 LT 4]
(while and endwhile, continue and break)
#2=0
o[#1/10] while [#2 LT 5]
  #2=[#2+1]
  o20 if [#2 EQ 2]
    o[#1/10] continue
  o20 endif
  o[#1/10+1] if [#2 EQ 4]
    o[#1/10] break
  o11 endif
  G1 Z#2
o10 endwhile
(repeat and endrepeat, and a repeat of none)
#3=7
#2=0
o#3 repeat [3]
  #2=[#2+1]
  G1 Y[#2+10]
o#3 endrepeat
o[#3+1] repeat [0]
  G1 Z99
o8 endrepeat
(a break written plainly in a loop of a computed label)
#6=9
#2=0
o#6 while [1]
  #2=[#2+1]
  G1 Z[#2+10]
  o40 if [#2 GE 2]
    o[9] break
  o40 endif
o#6 endwhile
(a negative label, and labels within 0.0001 of a whole number)
#4=-5
o#4 if [1]
  G1 X-5
o#4 endif
o[199.99995] if [1]
  G1 X20
o[200.00001] endif
(sub and endsub: the name read where the definition is, 1000)
(in the sub the labels read its argument, one label for each call)
o[#1*10] sub
  o#1 if [#1 GT 0]
    G1 X#1 Y0 Z0
  o#1 endif
o[#1*10] endsub
o1000 call [3]
o1000 call [4]
o[#1*10] call [5]
M2
";

#[test]
fn computed_labels_on_every_construct_as_rs274_reads_them() {
    let ran = run(COMPUTED_LABELS).ok();
    // rs274 2.9 -g: STRAIGHT_FEED end points.
    assert_ends(
        &ran,
        &[
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [2.0, 2.0, 0.0],
            [2.0, 3.0, 0.0],
            [2.0, 4.0, 0.0],
            [11.0, 4.0, 0.0],
            [13.0, 4.0, 0.0],
            [14.0, 4.0, 0.0],
            [14.0, 4.0, 1.0],
            [14.0, 4.0, 3.0],
            [14.0, 11.0, 3.0],
            [14.0, 12.0, 3.0],
            [14.0, 13.0, 3.0],
            [14.0, 13.0, 11.0],
            [14.0, 13.0, 12.0],
            [-5.0, 13.0, 12.0],
            [20.0, 13.0, 12.0],
            [3.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [5.0, 0.0, 0.0],
        ],
    );
}
