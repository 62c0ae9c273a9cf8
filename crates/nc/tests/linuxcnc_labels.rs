//! LinuxCNC's O-word labels: computed labels and numbers, which labels
//! pair, a label opening one construct, where subroutines are defined and
//! how a return leaves them. Each expectation comes from LinuxCNC's manual
//! (O Codes) and was confirmed by running the same program through
//! `rs274 -g` (LinuxCNC 2.9's standalone interpreter) once; the figures are
//! written here by hand, so these tests need no rs274. The program with a
//! computed label on every construct is in `linuxcnc_flow.rs`, whose
//! `rs274_agrees` runs it through rs274 again where it is installed.

mod common;

use common::ngc::{assert_ends, error_at, run, run_with, settings};

#[test]
fn computed_o_word_numbers_call_as_rs274_calls_them() {
    // rs274: `o#1 call` and `o[#1+1] call` call o100 and o101; a number
    // within 0.0001 of a whole one is that one.
    let text = "o100 sub\n(debug,in 100 #1)\no100 endsub\no101 sub\n(debug,in 101 #1)\no101 endsub\n#1=100\n\
                o#1 call [1]\no[#1+1] call [2]\no[100.00009] call [3]\nM2\n";
    let ran = run(text).ok();
    assert_eq!(ran.outcome.prints, ["in 100 1.000000", "in 101 2.000000", "in 100 3.000000"]);
    // From the library, by the number's file.
    let ran =
        run_with("#2=123\no#2 call [0] [5]\nM2\n", &[("123", "o123 sub\nG1 Y#2 F10\no123 endsub\n")], &settings());
    assert_ends(&ran.ok(), &[[0.0, 5.0, 0.0]]);
    // "Non integer value for integer"
    assert!(error_at("o100 sub\no100 endsub\nG0 X1\no[100.0001] call\nM2\n", 4).contains("whole number"));
    // "EOF … seeking o-word: o<-5>"
    assert!(error_at("#1=-5\no#1 call\nM2\n", 2).contains("no subroutine"));
}

#[test]
fn a_computed_label_pairs_with_any_label_that_reads_the_same() {
    // rs274 2.9: `o#1 if` … `o100 endif` with #1 100 pairs, the if taken
    // or not, and so does `o100 if` … `o#1 endif`.
    for (text, want) in [
        ("#1=100\no#1 if [1]\nG0 X1\no100 endif\nG0 X2\nM2\n", &[[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]][..]),
        ("#1=100\no#1 if [0]\nG0 X1\no100 endif\nG0 X2\nM2\n", &[[2.0, 0.0, 0.0]][..]),
        ("#1=100\no100 if [0]\nG0 X1\no#1 endif\nG0 X2\nM2\n", &[[2.0, 0.0, 0.0]][..]),
        // A branch not taken: #1=101 does not run, the endif reads 100.
        ("#1=100\no#1 if [0]\nG0 X1\n#1=101\no#1 endif\nG0 X2\nM2\n", &[[2.0, 0.0, 0.0]][..]),
    ] {
        assert_ends(&run(text).ok(), want);
    }
    // Nested, the labels read apart.
    let ran = run("#1=1\n#2=2\no#1 if [1]\no#2 if [0]\nG0 X1\no#2 else\nG0 X2\no#2 endif\no#1 endif\nM2\n").ok();
    assert_ends(&ran, &[[2.0, 0.0, 0.0]]);
}

#[test]
fn computed_labels_on_subroutines_as_rs274_reads_them() {
    // rs274 2.9: `o#1 sub` with #1 100 defines o100; its endsub may be
    // written either way; an endsub or return that the call reaches
    // returns whatever its label reads (here #1 is the argument, 5).
    for text in [
        "#1=100\no#1 sub\nG0 X#1\no#1 endsub\no100 call [5]\nG0 X2\nM2\n",
        "#1=100\no#1 sub\nG0 X#1\no100 endsub\no100 call [5]\nG0 X2\nM2\n",
        "#1=100\no100 sub\nG0 X#1\no#1 endsub\no100 call [5]\nG0 X2\nM2\n",
        "#1=100\no100 sub\nG0 X#1\no#1 return\no100 endsub\no100 call [5]\nG0 X2\nM2\n",
    ] {
        assert_ends(&run(text).ok(), &[[5.0, 0.0, 0.0], [2.0, 0.0, 0.0]]);
    }
    // A call before a computed definition: rs274 reads the label as it
    // searches, with the call's arguments in #1… ("EOF in file … seeking
    // o-word: o<100>" here, #1 being 5); kezuri's search passes it by.
    let e = error_at("#1=100\no100 call [5]\nG0 X2\no#1 sub\nG0 X#1\no#1 endsub\nM2\n", 2);
    assert!(e.contains("o100 is not defined"), "{e}");
    // Its name in the call chain is the one it read.
    let ran = run("#1=100\no#1 sub\nG0 X[1/0]\no#1 endsub\no100 call [5]\nM2\n");
    let d = ran.outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error");
    assert!(d.render(&ran.sources).contains("subroutine o100"), "{}", d.render(&ran.sources));
}

#[test]
fn computed_labels_that_do_not_agree_are_located_errors() {
    // Each as rs274 2.9 refuses it (its words in the comment), unless
    // said otherwise.
    // "5: undefined O-word label: 'o#1 endif'", after the move before it.
    let ran = run("#1=100\no#1 if [1]\nG0 X1\n#1=101\no#1 endif\nG0 X2\nM2\n");
    assert_ends(&ran, &[[1.0, 0.0, 0.0]]);
    let e = ran.error().unwrap();
    assert!(e.starts_with("t.ngc:5:") && e.contains("o#1 endif reads o101, where o#1 if (line 2) read o100"), "{e}");
    assert!(e.contains("undefined O-word label"), "{e}");
    assert!(error_at("#1=100\n#2=200\no#1 if [1]\no#2 endif\nM2\n", 4).contains("undefined O-word label"));
    // A branch not taken whose endif reads otherwise: rs274 skips on to
    // the end of the file ("File ended with no percent sign or program
    // end"); kezuri stops at that endif.
    let e = error_at("#1=100\n#2=200\no#1 if [0]\nG0 X1\no#2 endif\nG0 X2\nM2\n", 5);
    assert!(e.contains("skips on past it"), "{e}");
    // "Non integer value for integer", read even where the run skips.
    assert!(error_at("#1=100.5\no#1 if [1]\nG0 X1\no100 endif\nM2\n", 2).contains("Non integer value"));
    assert!(error_at("#1=1\no#1 if [0]\no[#1+0.5] if [1]\no[1.5] endif\no#1 endif\nM2\n", 3).contains("whole number"));
    assert!(error_at("#1=0.5\no100 sub\no#1 if [1]\no#1 endif\no100 endsub\nM2\n", 3).contains("whole number"));
    assert!(error_at("#1=0.5\no10 while [0]\no#1 if [1]\no#1 endif\no10 endwhile\nM2\n", 3).contains("whole number"));
    // "7: undefined O-word label: 'o#1 endwhile'"
    let text = "#1=7\n#2=0\no#1 while [#2 LT 3]\n#2=[#2+1]\nG0 X#2\n#1=8\no#1 endwhile\nG0 Y1\nM2\n";
    assert!(error_at(text, 7).contains("o#1 endwhile reads o8, where o#1 while (line 3) read o7"));
    // rs274 reads `o#1 while` reading 8 as a new while loop (G0 X1, then
    // G0 Y1); kezuri stops.
    let text = "#1=7\n#2=0\no#1 do\n#2=[#2+1]\nG0 X#2\n#1=8\no#1 while [#2 LT 3]\nG0 Y1\nM2\n";
    assert!(error_at(text, 7).contains("o#1 while reads o8, where o#1 do (line 3) read o7"));
    // "7: undefined O-word label: 'o#1 break'"
    let text = "#1=7\n#2=0\no#1 while [#2 LT 3]\n#2=[#2+1]\nG0 X#2\n#1=8\no#1 break\no7 endwhile\nM2\n";
    assert!(error_at(text, 7).contains("not inside a loop named o8"));
    // "no matching while/do label: 'o#1 break' (found 'repeat' in line 2)"
    assert!(error_at("#1=10\no#1 repeat [2]\no#1 break\no#1 endrepeat\nM2\n", 3).contains("not o10 repeat"));
    // "… (found 'if' in line 2)"
    assert!(error_at("#1=10\no10 if [1]\no20 while [1]\no#1 break\no20 endwhile\no10 endif\nM2\n", 4)
        .contains("names o10 if (line 2), which is not a loop"));
    // rs274: "File ended with no percent sign or program end" (it skips
    // on looking for o10).
    let text = "#1=10\no10 while [0]\no10 endwhile\no20 while [1]\nG0 X1\no#1 break\no20 endwhile\nM2\n";
    assert!(error_at(text, 6).contains("not inside o10 while (line 2)"));
    // "2: undefined O-word label: 'o#1 break'": no loop at all.
    assert!(error_at("#1=10\no#1 break\nM2\n", 2).contains("not inside a loop"));
    // "5: undefined O-word label: 'o#1 elseif [1]'"
    let text = "#1=10\no#1 if [1]\nG0 X1\n#1=11\no#1 elseif [1]\nG0 X2\no10 endif\nM2\n";
    assert!(error_at(text, 5).contains("o#1 elseif reads o11"));
    // "5: duplicate O-word label - already defined in line 2: 'o1 if [1]'"
    let e = error_at("#1=1\no#1 if [1]\nG0 X1\no#1 endif\no1 if [1]\nG0 X2\no1 endif\nM2\n", 5);
    assert!(e.contains("reuses the label of o#1 if (read as o1) (line 2)"), "{e}");
    // A `do` and its `while` written otherwise: rs274 pairs them where
    // they read the same (G0 X1, then G0 Y1); kezuri reads the while as a
    // loop of its own and refuses the file, saying how to write it.
    let e = error_at("#1=10\no#1 do\nG0 X1\no10 while [0]\nG0 Y1\nM2\n", 2);
    assert!(e.contains("written alike: o#1 do … o#1 while"), "{e}");
}

#[test]
fn a_label_opens_one_construct_in_a_subroutine() {
    // rs274: "duplicate O-word label - already defined in line 1", in the
    // main program as in a sub, for if and while alike; stopped where the
    // second is reached, after what ran before it.
    let ran = run("F1\no1 if [1]\nG1 X1\no1 endif\no1 while [0]\no1 endwhile\nM2\n");
    assert_ends(&ran, &[[1.0, 0.0, 0.0]]);
    let e = ran.error().expect("an error");
    assert!(e.starts_with("t.ngc:5:") && e.contains("o1 while reuses the label of o1 if (line 2)"), "{e}");
    let text = "o100 sub\no1 if [1]\no1 endif\no1 if [1]\no1 endif\no100 endsub\no100 call\nM2\n";
    assert!(run(text).error().unwrap().starts_with("t.ngc:4:"));
    // The same label in two subs and the main program, a sub's and an if's,
    // and one not reached (the branch not taken) are no duplicates.
    let text = "o100 sub\no1 if [1]\n(debug,x)\no1 endif\no100 endsub\no101 sub\no1 if [1]\n(debug,y)\no1 endif\n\
                o101 endsub\no1 if [1]\n(debug,z)\no1 endif\no100 call\no101 call\no100 if [1]\no100 endif\n\
                o2 if [0]\no3 if [1]\no3 endif\no2 else\no3 repeat [2]\no3 endrepeat\no2 endif\nM2\n";
    assert_eq!(run(text).ok().outcome.prints, ["z", "x", "y"]);
}

#[test]
fn subroutines_are_defined_where_the_run_reaches_them() {
    // rs274: a sub inside an if that runs is defined; inside one that does
    // not, not ("EOF … seeking o-word: o<100>").
    let ran = run("o1 if [1]\no100 sub\n(debug,in)\no100 endsub\no1 endif\no100 call\nM2\n").ok();
    assert_eq!(ran.outcome.prints, ["in"]);
    let e = error_at("o1 if [0]\no100 sub\n(debug,in)\no100 endsub\no1 endif\no100 call\nM2\n", 6);
    assert!(e.contains("o100 is not defined"), "{e}");
    // In a repeat run once, defined; in a loop that reaches it twice, or
    // reached after a call found it further on: "found in illegal location".
    let ran = run("o1 repeat [1]\no100 sub\n(debug,in)\no100 endsub\no1 endrepeat\no100 call\nM2\n").ok();
    assert_eq!(ran.outcome.prints, ["in"]);
    let text = "#1=0\no1 while [#1 LT 2]\no100 sub\no100 endsub\n#1=[#1+1]\no1 endwhile\nM2\n";
    assert!(run(text).error().unwrap().starts_with("t.ngc:3:"));
    let ran = run("o100 call\no100 sub\n(debug,in)\no100 endsub\nM2\n");
    assert_eq!(ran.outcome.prints, ["in"]);
    assert!(ran.error().unwrap().contains("reached a second time"));
    // Two definitions: "redefining sub: o|100| already defined".
    let e = run("o100 sub\no100 endsub\no100 sub\no100 endsub\nM2\n").error().unwrap();
    assert!(e.starts_with("t.ngc:3:") && e.contains("t.ngc line 1 defines it"), "{e}");
    // A library file's sub calls a sub its file defines before it: rs274
    // does not find it there ("EOF in file:foo.ngc seeking o-word").
    let foo =
        "o<helper> sub\n(debug,helper)\no<helper> endsub\no<foo> sub\n(debug,foo)\no<helper> call\no<foo> endsub\n";
    let ran = run_with("o<foo> call\nM2\n", &[("foo", foo)], &settings());
    assert_eq!(ran.outcome.prints, ["foo"]);
    assert!(ran.error().unwrap().contains("no helper.ngc"));
}

#[test]
fn return_leaves_the_subroutine_whatever_its_label() {
    // rs274 (LinuxCNC's retval.ngc): `o1010 return` inside `o1010 if`
    // returns from o1000 with its value; `o9999 return [5]` from o100;
    // a return inside a loop leaves the loop and the subroutine.
    let text = "o1000 sub\no1010 if [#1 GT 0]\no1010 return [123*[#1]]\no1010 endif\no1000 endsub [4712]\n\
                o1000 call [0]\n(debug,#<_value>)\no1000 call [2]\n(debug,#<_value>)\n\
                o100 sub\no9999 return [5]\no100 endsub\no100 call\n(debug,#<_value>)\n\
                o200 sub\n#1=0\no201 while [1]\n#1=[#1+1]\no202 if [#1 EQ 3]\no202 return [#1]\no202 endif\n\
                o201 endwhile\no200 endsub\no200 call\n(debug,#<_value>)\nM2\n";
    let ran = run(text).ok();
    assert_eq!(ran.outcome.prints, ["4712.000000", "246.000000", "5.000000", "3.000000"]);
}
