//! Blocks kept as the program gave them ([`Kept`]): written in place, a
//! line each, and what GRBL cannot run refused.

use kezuri_geom::{Axes, CycleBlock, Kept};

use super::blocks::{unsupported, Writer, N};
use super::dialect::Dialect;
use crate::Error;

impl Writer {
    /// A block kept as the program wrote it ([`Kept`]), a line each. Only
    /// the Fanuc and LinuxCNC writers can give it to the control; what GRBL
    /// has not is refused.
    pub(super) fn kept(&mut self, k: &Kept) -> Result<(), Error> {
        let dialect = self.dialect;
        let refused = match dialect {
            Dialect::Grbl => !grbl_has(&k.text),
            // Compensation by a diameter is LinuxCNC's alone.
            // So are G33.1 rigid tapping, G43.1 dynamic tool length offsets
            // and G76 threading (a kept G76 outside a canned cycle's holes:
            // Fanuc's G76 is fine boring).
            Dialect::Fanuc => {
                ["G41.1", "G42.1", "G33.1", "G43.1"].iter().any(|c| k.text.contains(c))
                    || (k.cycle.is_none() && k.text.lines().any(|line| has(line, 'G', 76.0)))
            }
            Dialect::LinuxCnc => false,
        };
        if refused {
            return Err(unsupported(dialect, k.line, &k.text));
        }
        // A new cycle, or a block with axis words, ends the cycle in force;
        // the next hole, and M codes and the like between holes, go on in it.
        match k.cycle {
            Some(CycleBlock::Next) => {}
            Some(CycleBlock::Start) => self.end_cycle(),
            None if has_axis_words(&k.text) => self.end_cycle(),
            None => {}
        }
        for line in k.text.lines() {
            self.block();
            self.code(line);
            self.out.push('\n');
            // The block may set G90/G91.
            if has(line, 'G', 91.0) {
                self.relative = Some(true);
            } else if has(line, 'G', 90.0) {
                self.relative = Some(false);
            }
        }
        let (ours, other) = if self.inch { ("G20", 21.0) } else { ("G21", 20.0) };
        if k.text.lines().any(|line| has(line, 'G', other)) {
            self.line(ours);
        }
        if k.moves > 0 {
            self.motion = None;
        }
        if k.cycle.is_some() {
            self.cycle_open = true;
        }
        if k.sets_offsets {
            // The frames after it carry the origins the block gave them.
            self.origins.iter_mut().for_each(|o| *o = None);
        }
        Ok(())
    }

    /// The control is at `end` (program coordinates) after a move a kept
    /// block made.
    pub(super) fn made(&mut self, end: Axes) -> Result<(), Error> {
        let t = self.target(end)?;
        for k in (0..N).filter(|&k| self.used[k]) {
            self.pos[k] = Some(t[k]);
            self.exact[k] = false;
        }
        Ok(())
    }
}

/// Whether GRBL runs a kept block: program stops (`M0`, `M1`), work
/// offsets set by `G10 L2`/`L20`, and `G92`, `G92.1`.
fn grbl_has(text: &str) -> bool {
    text.lines().all(|line| {
        let w = words(line);
        let stop = w.len() == 1 && (w[0] == ('M', 0.0) || w[0] == ('M', 1.0));
        let g10 = has(line, 'G', 10.0) && (has(line, 'L', 2.0) || has(line, 'L', 20.0));
        stop || g10 || has(line, 'G', 92.0) || has(line, 'G', 92.1) || has(line, 'G', 30.0)
    })
}

/// The words of a line outside its comments, as letters and values.
fn words(line: &str) -> Vec<(char, f64)> {
    crate::rewrite::words(line)
        .into_iter()
        .map(|w| (w.letter, line[w.number.0..w.number.1].parse().unwrap_or(f64::NAN)))
        .collect()
}

/// Whether a line holds the word `letter` `value` (`G91`, not `G91.1`).
fn has(line: &str, letter: char, value: f64) -> bool {
    words(line).contains(&(letter, value))
}

/// Whether kept text holds an axis word (`X5.`, `Z-1`; not in a comment).
fn has_axis_words(text: &str) -> bool {
    text.lines().any(|line| words(line).iter().any(|(l, _)| "XYZABCUVW".contains(*l)))
}
