//! The measuring program's text: the moves between the post's start and
//! end, in each [`Style`].

use super::{order, Grid, Pattern, Plan, Style};
use crate::number::push_fixed;
use crate::write::{made_text, text_options, WriteOptions};
use crate::Error;

/// The program text of `plan`, laid out as `g`, framed by its post.
pub(super) fn text(plan: &Plan, g: Grid) -> Result<String, Error> {
    let mut w = Writer { out: String::new(), digits: plan.digits, plan, g, length: None };
    let options = WriteOptions {
        program_number: plan.program,
        title: Some(format!("KEZURI PROBE PLAN, {} STYLE", plan.style.name().to_ascii_uppercase())),
        notes: w.notes(),
        ..text_options(&plan.post)
    };
    let made = made_text(&options, plan.tool)?;
    w.out = made.start;
    w.length = made.length;
    match plan.style {
        Style::Subprogram => w.subprogram(),
        Style::Expanded => w.expanded(),
        Style::G31 => w.g31(),
    }
    // The subprograms follow the main program's end, inside its `%`.
    let (end, tape) = match made.end.strip_suffix("%\n") {
        Some(end) => (end, "%\n"),
        None => (made.end.as_str(), ""),
    };
    w.out.push_str(end);
    if plan.style == Style::Subprogram {
        w.subprograms();
    }
    w.out.push_str(tape);
    Ok(w.out)
}

/// The program being written, in integer units of `10^-digits` mm.
struct Writer<'a> {
    out: String,
    digits: u32,
    plan: &'a Plan,
    g: Grid,
    /// The post's length offset words, taken by the first Z move.
    length: Option<String>,
}

impl Writer<'_> {
    /// A length in units as Fanuc text: always a decimal point, trailing
    /// zeros trimmed (`1.`, `-0.5`, `0.`).
    fn n(&self, units: i64) -> String {
        let mut out = String::new();
        push_fixed(&mut out, units, self.digits, true);
        out
    }

    /// A feed: a decimal point, at most one decimal.
    fn f(feed: f64) -> String {
        let tenths = (feed * 10.0).round() as i64;
        if tenths % 10 == 0 {
            format!("{}.", tenths / 10)
        } else {
            format!("{}.{}", tenths / 10, tenths % 10)
        }
    }

    fn line(&mut self, s: &str) {
        self.out.push_str(s);
        self.out.push('\n');
    }

    /// The comments after the title that say what the program does.
    fn notes(&self) -> Vec<String> {
        let p = self.plan;
        let g = self.g;
        let [nx, ny] = p.count;
        let rows = match p.pattern {
            Pattern::Zigzag => "ZIGZAG, EVERY OTHER ROW BACK TOWARD -X",
            Pattern::OneWay => "ONE WAY, EVERY ROW TOWARD +X",
        };
        let mut notes = vec![
            format!(
                "GRID {nx} X {ny} = {} POINTS AT PITCH {}, FIRST X{} Y{}",
                u64::from(nx) * u64::from(ny),
                self.n(g.pitch),
                self.n(g.x0),
                self.n(g.y0)
            ),
            format!(
                "THE STYLUS TRAVELS AT Z{} AND PLUNGES {} TO Z{} AT EACH POINT",
                self.n(g.z_safe),
                self.n(g.plunge),
                self.n(g.bottom)
            ),
            format!("ROWS ALONG X STEPPING +Y, THE FIRST ROW TOWARD +X, {rows}"),
        ];
        let style: &[&str] = match p.style {
            Style::Subprogram => &["THE SUBPROGRAMS MOVE INCREMENTALLY, SO G91 FOLLOWS THE POSITIONING"],
            Style::Expanded => &["EVERY POINT WRITTEN OUT IN ABSOLUTE COORDINATES"],
            Style::G31 => &[
                "SKIP-SIGNAL PROBING, G31 STOPS AT THE TOUCH AND THE CONTROL RECORDS IT",
                "DPRNT WRITES ONE LINE X Y Z PER POINT TO THE DEVICE OPENED BY POPEN",
                "X AND Y ARE VARIABLES 5061 AND 5062, Z IS THE TIP, 5063 LESS THE LENGTH OFFSET 5083",
            ],
        };
        notes.extend(style.iter().map(|s| s.to_string()));
        if p.style == Style::G31 {
            notes.push(format!("NO TOUCH ABOVE THE BOTTOM, THE LINE GIVES Z{}", self.n(g.bottom)));
        }
        notes
    }

    /// ` (TEXT)`, or nothing where the post writes no comments.
    fn comment(&self, text: &str) -> String {
        if self.plan.post.comments {
            format!(" ({text})")
        } else {
            String::new()
        }
    }

    /// A line `(TEXT)` where the post writes comments.
    fn comment_line(&mut self, text: &str) {
        if self.plan.post.comments {
            self.line(&format!("({text})"));
        }
    }

    /// A subprogram's first line: `O1012 (WHAT IT DOES)`.
    fn subprogram_start(&mut self, number: u32, what: &str) {
        let line = format!("O{number:04}{}", self.comment(what));
        self.line(&line);
    }

    /// The dialect's motion code: 0 rapid, 1 feed.
    fn motion(&self, k: usize) -> &'static str {
        self.plan.post.dialect.codes().motion[k]
    }

    /// Position at the origin, go down to z-safe with the stylus's length
    /// offset: the post has retracted and changed to the stylus.
    fn approach(&mut self) {
        let g = self.g;
        let rapid = self.motion(0);
        self.line(&format!("G90 {rapid} X{} Y{}", self.n(g.x0), self.n(g.y0)));
        let length = self.length.take().map(|l| l + " ").unwrap_or_default();
        self.line(&format!("{rapid} {length}Z{}", self.n(g.z_safe)));
    }

    /// A move between points (or the retract): rapid, or feed at the feed.
    fn travel(&self, words: &str) -> String {
        match self.plan.feed {
            None => format!("{} {words}", self.motion(0)),
            Some(f) => format!("{} {words} F{}", self.motion(1), Self::f(f)),
        }
    }

    /// Plunge, trigger, retract. `incremental`: in G91.
    fn touch(&mut self, incremental: bool) {
        let g = self.g;
        let (down, up) = if incremental { (-g.plunge, g.plunge) } else { (g.bottom, g.z_safe) };
        self.line(&format!("{} Z{} F{}", self.motion(1), self.n(down), Self::f(self.plan.plunge_feed)));
        for t in &self.plan.trigger {
            self.line(t.trim());
        }
        let up = self.travel(&format!("Z{}", self.n(up)));
        self.line(&up);
    }

    fn subprogram(&mut self) {
        let p = self.plan;
        let [nx, ny] = p.count;
        let (row, fwd) = (p.program + 1, p.program + 2);
        self.approach();
        self.line("G91");
        let past = match p.pattern {
            Pattern::OneWay => {
                self.line(&format!("M98 P{row:04} L{ny}"));
                true
            }
            Pattern::Zigzag => {
                if ny >= 2 {
                    self.line(&format!("M98 P{row:04} L{}", ny / 2));
                }
                if ny % 2 == 1 {
                    self.comment_line("THE LAST ROW, TOWARD +X");
                    self.touch(true);
                    if nx > 1 {
                        self.line(&format!("M98 P{fwd:04} L{}", nx - 1));
                    }
                }
                ny % 2 == 0
            }
        };
        if past {
            self.comment_line("THE STYLUS IS ONE PITCH PAST THE LAST ROW, AT Z-SAFE");
        }
        // The subprograms leave the control in G91: the end is absolute.
        self.line("G90");
    }

    /// The subprograms, after the main program's end.
    fn subprograms(&mut self) {
        let p = self.plan;
        let g = self.g;
        let [nx, ny] = p.count;
        let (row, fwd, back) = (p.program + 1, p.program + 2, p.program + 3);
        let step = self.n(g.pitch);
        match p.pattern {
            Pattern::OneWay => {
                self.subprogram_start(row, "ONE ROW TOWARD +X, THEN BACK TO ITS START AND ONE PITCH IN Y");
                self.touch(true);
                if nx > 1 {
                    self.line(&format!("M98 P{fwd:04} L{}", nx - 1));
                    let ret = format!("X{} Y{step}", self.n(-i64::from(nx - 1) * g.pitch));
                    let ret = self.travel(&ret);
                    self.line(&ret);
                } else {
                    let ret = self.travel(&format!("Y{step}"));
                    self.line(&ret);
                }
                self.line("M99");
            }
            Pattern::Zigzag if ny >= 2 => {
                self.subprogram_start(row, "TWO ROWS, TOWARD +X AND BACK TOWARD -X, EACH THEN ONE PITCH IN Y");
                for sub in [fwd, back] {
                    self.touch(true);
                    if nx > 1 {
                        self.line(&format!("M98 P{sub:04} L{}", nx - 1));
                    }
                    let y = self.travel(&format!("Y{step}"));
                    self.line(&y);
                }
                self.line("M99");
            }
            Pattern::Zigzag => {}
        }
        if nx > 1 {
            let mut subs = vec![(fwd, g.pitch, "+X")];
            if p.pattern == Pattern::Zigzag && ny >= 2 {
                subs.push((back, -g.pitch, "-X"));
            }
            for (sub, dx, dir) in subs {
                self.subprogram_start(sub, &format!("ONE POINT, A PITCH TOWARD {dir}, PLUNGE, TRIGGER, RETRACT"));
                let s = self.travel(&format!("X{}", self.n(dx)));
                self.line(&s);
                self.touch(true);
                self.line("M99");
            }
        }
    }

    /// Each point's `[x, y]` in units, in order.
    fn grid_points(&self) -> impl Iterator<Item = [i64; 2]> + '_ {
        let g = self.g;
        order(self.plan.count, self.plan.pattern)
            .map(move |[i, j]| [g.x0 + i64::from(i) * g.pitch, g.y0 + i64::from(j) * g.pitch])
    }

    /// The move to the next point: only the words that change.
    fn position(&mut self, at: &mut [i64; 2], to: [i64; 2]) {
        let mut words = Vec::new();
        if to[0] != at[0] {
            words.push(format!("X{}", self.n(to[0])));
        }
        if to[1] != at[1] {
            words.push(format!("Y{}", self.n(to[1])));
        }
        if !words.is_empty() {
            let s = self.travel(&words.join(" "));
            self.line(&s);
        }
        *at = to;
    }

    fn expanded(&mut self) {
        self.approach();
        let mut at = [self.g.x0, self.g.y0];
        let points: Vec<[i64; 2]> = self.grid_points().collect();
        for to in points {
            self.position(&mut at, to);
            self.touch(false);
        }
    }

    fn g31(&mut self) {
        let g = self.g;
        let frac = self.digits.max(3);
        let fmt = format!("[{}{}]", 8 - frac, frac);
        self.approach();
        self.line("POPEN");
        let mut at = [g.x0, g.y0];
        let points: Vec<[i64; 2]> = self.grid_points().collect();
        for to in points {
            self.position(&mut at, to);
            self.line(&format!("G31 Z{} F{}", self.n(g.bottom), Self::f(self.plan.plunge_feed)));
            self.line("#1=#5063-#5083");
            self.line(&format!("DPRNT[#5061{fmt}*#5062{fmt}*#1{fmt}]"));
            self.line(&format!("G00 Z{}", self.n(g.z_safe)));
        }
        self.line("PCLOS");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_a_decimal_point() {
        let plan = Plan::new([0.0, 0.0], [1, 1], 1.0, 30.0, 50.0);
        let g = plan.layout().unwrap();
        let w = Writer { out: String::new(), digits: 3, plan: &plan, g, length: None };
        let got: Vec<String> = [0, 1000, -500, 1, -1_234_567, 120].iter().map(|&u| w.n(u)).collect();
        assert_eq!(got, ["0.", "1.", "-0.5", "0.001", "-1234.567", "0.12"]);
        assert_eq!(Writer::f(6000.0), "6000.");
        assert_eq!(Writer::f(12.25), "12.3");
    }
}
