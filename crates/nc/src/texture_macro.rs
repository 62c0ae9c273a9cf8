//! The random texture as the texture paper made it: a Fanuc Custom Macro B program
//! that the control calls on every block of the cutting section (`G66.1`)
//! and that draws each stroke's depth from the `#3001` clock, so every part
//! comes out different (`kezuri texture --mode macro`).
//!
//! [`TextureMacro::program`] writes the macro; [`TextureMacro::wrap`] puts
//! `G66.1 P…` before the first cutting block of a program and `G67` after
//! the last, and the macro after the program. The macro cuts what
//! `kezuri_cam::texture::bake` cuts: on a straight cutting block with XY
//! travel (any direction), a knot every `segment` mm of XY travel counted
//! across blocks, the depth offset running linearly from knot to knot,
//! added to the program's own Z (kept in a common variable, since the
//! tool's Z is the textured one) or to a fixed base, never below the
//! clamp. Rapids, arcs (`#4001` > 1), Z-only and incremental (G91) blocks
//! are run as written: every argument passed on (`R` and `K` too), nothing
//! of them used as scratch; an arc in the XZ or YZ plane first goes back to
//! the program's Z (a change of Z would change its radius).
//!
//! What the macro cannot pass on (M, S, T words, G04, G28 … inside the
//! section: under G66.1 they reach the macro as arguments or stop the
//! control) and incremental programs are refused by `kezuri texture`
//! before anything is written.
//!
//! The paper's O7023 slips, fixed here: its digit test `#28 GT 5` sent 5 to
//! the shallow side (a tenth depth, base + 1.0 mm); its Z-only test `[#24 +
//! #25] EQ #0` is never true (vacant + vacant is 0, not vacant), so Z-only
//! blocks fell into the X branch; it used `#18` (R) and `#6` (K) as scratch,
//! so an R-form arc lost its radius; it walked only along X.
//!
//! State between calls lives in common variables `#v … #v+6` (default
//! `#190`–`#196`): the program's Z, whether a run of strokes is under way,
//! the travel since the last knot, the offsets at the last and the next
//! knot, whether the next one is still to be drawn, and whether it is the
//! run's first (entered from wherever the tool was, so free of the step
//! range).

mod blocks;

use std::fmt::Write;

pub use blocks::Blocks;

use crate::number::number;

/// The numbers of a texture macro. Lengths in mm.
#[derive(Clone, Copy, Debug)]
pub struct TextureMacro {
    /// The macro's program number (the texture paper's 7023).
    pub number: u32,
    /// XY travel per knot.
    pub segment: f64,
    /// A fixed depth the offsets are added to; `None`: the program's Z.
    pub base: Option<f64>,
    /// Largest offset either way.
    pub spread: f64,
    /// Offsets are multiples of this (> 0).
    pub quantum: f64,
    /// Every multiple of the quantum equally likely, instead of the texture
    /// paper's digits.
    pub uniform: bool,
    /// Successive knots differ by at least and at most these.
    pub step_range: Option<[f64; 2]>,
    /// No textured point goes below this Z.
    pub max_depth: Option<f64>,
    /// The first of the seven common variables the macro keeps its state in.
    pub vars: u32,
}

/// A number as a program constant.
fn num(v: f64) -> String {
    number(v, 6)
}

impl TextureMacro {
    /// The macro program, `O…` to `M99`, one block a line.
    pub fn program(&self) -> String {
        let v = |k: u32| format!("#{}", self.vars + k);
        let (zp, running, travel, last, next, undrawn, entry) = (v(0), v(1), v(2), v(3), v(4), v(5), v(6));
        let l = num(self.segment);
        let reference = |z: &str| match self.base {
            Some(b) => num(b),
            None => z.to_string(),
        };
        let clamp = |var: &str| match self.max_depth {
            Some(floor) => format!("IF[{var}LT{f}]THEN{var}={f}\n", f = num(floor)),
            None => String::new(),
        };
        let mut t = String::new();
        let w = &mut t;
        let _ = writeln!(w, "O{:04} (KEZURI TEXTURE: A STROKE EVERY {l} MM OF XY TRAVEL)", self.number);
        let _ = writeln!(w, "(CALLED BY G66.1 ON EVERY BLOCK; STATE IN {zp}-{entry})");
        let _ = writeln!(w, "#27=#4001");
        let _ = writeln!(w, "IF[[#24EQ#0]AND[#25EQ#0]]GOTO80 (NO XY: AS WRITTEN)");
        let _ = writeln!(w, "IF[#27NE1]GOTO80 (RAPID OR ARC: AS WRITTEN)");
        let _ = writeln!(w, "IF[#4003NE90]GOTO80 (INCREMENTAL: AS WRITTEN)");
        let _ = writeln!(w, "#28=#5001\n#29=#5002\n#30=#28\n#31=#29");
        let _ = writeln!(w, "IF[#24NE#0]THEN#30=#24\nIF[#25NE#0]THEN#31=#25");
        let _ = writeln!(w, "#32={zp}\n#33={zp}\nIF[#26NE#0]THEN#33=#26");
        let _ = writeln!(w, "#14=SQRT[[#30-#28]*[#30-#28]+[#31-#29]*[#31-#29]]");
        let _ = writeln!(w, "IF[#14EQ0]GOTO80");
        let _ = writeln!(w, "#15=0 (TRAVEL DONE ON THIS BLOCK)");
        let _ = writeln!(w, "IF[{running}EQ1]GOTO10");
        let _ = writeln!(w, "(A RUN OF STROKES STARTS WHERE THE TOOL IS)");
        let _ = writeln!(w, "{last}=#5003-{}", reference("#32"));
        let _ = writeln!(w, "{travel}=0\n{running}=1\n{undrawn}=1\n{entry}=1");
        let _ = writeln!(w, "N10");
        let _ = writeln!(w, "IF[{undrawn}EQ0]GOTO20");
        self.draw(w, &last.clone(), &next.clone(), &entry.clone());
        let _ = writeln!(w, "{undrawn}=0\n{entry}=0");
        let _ = writeln!(w, "N20");
        let _ = writeln!(w, "#12={l}-{travel} (TRAVEL TO THE NEXT KNOT)");
        let _ = writeln!(w, "IF[#15+#12GE#14-0.000001]GOTO40");
        let _ = writeln!(w, "#15=#15+#12\n#16=#15/#14");
        let _ = writeln!(w, "#10={}+{next}", reference("[#32+[#33-#32]*#16]"));
        t.push_str(&clamp("#10"));
        let w = &mut t;
        let _ = writeln!(w, "G01X[#28+[#30-#28]*#16]Y[#29+[#31-#29]*#16]Z#10F#9");
        let _ = writeln!(w, "{last}={next}\n{travel}=0\n{undrawn}=1");
        let _ = writeln!(w, "GOTO10");
        let _ = writeln!(w, "N40 (THE BLOCK ENDS BEFORE THE KNOT)");
        let _ = writeln!(w, "{travel}={travel}+#14-#15");
        let _ = writeln!(w, "#10={}+{last}+[{next}-{last}]*{travel}/{l}", reference("#33"));
        t.push_str(&clamp("#10"));
        let w = &mut t;
        let _ = writeln!(w, "G01X#30Y#31Z#10F#9");
        let _ = writeln!(w, "IF[{travel}LT{l}-0.000001]GOTO90");
        let _ = writeln!(w, "{last}={next}\n{travel}=0\n{undrawn}=1");
        let _ = writeln!(w, "GOTO90");
        let _ = writeln!(w, "N80");
        let _ = writeln!(w, "IF[[#24NE#0]OR[#25NE#0]OR[#26NE#0]]THEN{running}=0 (A MOVE ENDS THE RUN)");
        let _ = writeln!(w, "IF[#27LT2]GOTO81");
        let _ = writeln!(w, "IF[#4002EQ17]GOTO81");
        let _ = writeln!(w, "#28=#4003");
        let _ = writeln!(w, "G90G01Z{zp} (AN ARC ACROSS Z STARTS AT THE PROGRAM'S Z)");
        let _ = writeln!(w, "G#28");
        let _ = writeln!(w, "N81");
        let _ = writeln!(w, "G#27X#24Y#25Z#26I#4J#5K#6R#18F#9");
        let _ = writeln!(w, "IF[#26EQ#0]GOTO99");
        let _ = writeln!(w, "IF[#4003EQ90]THEN{zp}=#26");
        let _ = writeln!(w, "IF[#4003NE90]THEN{zp}={zp}+#26");
        let _ = writeln!(w, "GOTO99");
        let _ = writeln!(w, "N90");
        let _ = writeln!(w, "{zp}=#33");
        let _ = writeln!(w, "N99");
        let _ = writeln!(w, "M99");
        t
    }

    /// The blocks that draw the next knot's offset into `next`, after
    /// `last`. The clock is read once: the count of its 16 ms ticks, not
    /// its milliseconds (on a control whose clock moves in 16 ms steps the
    /// last digit of `#3001` is always even). Where a step range is given
    /// and the value misses it, the next candidates step through the values
    /// from there (by 3 of the 10 digits, by 1 of the uniform values: every
    /// value once), since reading the clock again without moving gives the
    /// same value on a control. `entry` 1: the run's first stroke, free of
    /// the range.
    fn draw(&self, w: &mut String, last: &str, next: &str, entry: &str) {
        let q = num(self.quantum);
        let n = (self.spread / self.quantum + 1e-9).floor();
        let (count, stride) = if self.uniform { (2.0 * n + 1.0, 1.0) } else { (10.0, 3.0) };
        let k = num(count);
        let _ = writeln!(w, "#16=FIX[#3001/16] (CLOCK TICKS)");
        let _ = writeln!(w, "#10=0");
        let _ = writeln!(w, "WHILE[#10LT{k}]DO1");
        let _ = writeln!(w, "#12=#16+#10*{}", num(stride));
        let _ = writeln!(w, "#12=#12-FIX[#12/{k}]*{k} (0 TO {})", num(count - 1.0));
        if self.uniform {
            let _ = writeln!(w, "{next}=[#12-{}]*{q}", num(n));
        } else {
            let step = num(self.spread / 4.0);
            let _ = writeln!(w, "{next}=#12*{step}");
            let _ = writeln!(w, "IF[#12GE5]THEN{next}=-[#12-5]*{step}");
            let _ = writeln!(w, "{next}=ROUND[{next}/{q}]*{q}");
            let top = num(n * self.quantum);
            let _ = writeln!(w, "IF[{next}GT{top}]THEN{next}={top}");
            let _ = writeln!(w, "IF[{next}LT-{top}]THEN{next}=-{top}");
        }
        match self.step_range {
            Some([lo, hi]) => {
                let _ = writeln!(w, "IF[{entry}EQ1]GOTO11");
                let _ = writeln!(w, "#12=ABS[{next}-{last}]");
                let _ = writeln!(w, "IF[[#12GE{}]AND[#12LE{}]]GOTO11", num(lo - 1e-6), num(hi + 1e-6));
                let _ = writeln!(w, "#10=#10+1");
                let _ = writeln!(w, "END1");
                let _ = writeln!(w, "N11");
            }
            None => {
                let _ = writeln!(w, "#10={k}");
                let _ = writeln!(w, "END1");
            }
        }
    }

    /// `program` (its text) with `#v=#5003` and `G66.1 P…` put before line
    /// `first` (1-based), `G67` after line `last`, and the macro after the
    /// program (before a closing `%`).
    pub fn wrap(&self, program: &str, first: usize, last: usize) -> String {
        let mut out = String::new();
        let lines: Vec<&str> = program.lines().collect();
        // A closing `%` after the last cut (0-based index, 1-based line).
        let end = lines.iter().rposition(|l| l.trim() == "%").filter(|&k| k >= last);
        for (k, line) in lines.iter().enumerate() {
            let n = k + 1;
            if Some(k) == end {
                out.push('\n');
                out.push_str(&self.program());
            }
            if n == first {
                let _ = writeln!(out, "#{}=#5003 (KEZURI TEXTURE: THE PROGRAM'S Z)", self.vars);
                let _ = writeln!(out, "G66.1P{:04} (KEZURI TEXTURE ON EVERY BLOCK TO G67)", self.number);
            }
            out.push_str(line);
            out.push('\n');
            if n == last {
                out.push_str("G67\n");
            }
        }
        if end.is_none() {
            out.push('\n');
            out.push_str(&self.program());
        }
        out
    }
}
