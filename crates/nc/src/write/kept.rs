//! Blocks kept as the program gave them ([`Kept`]): written in place, a
//! line each, and what GRBL cannot run refused.

use kezuri_geom::{Axes, CycleBlock, Kept};

use super::blocks::Writer;
use super::gcode::{Dialect, WriteError};

impl Writer {
    /// A block kept as the program wrote it ([`Kept`]), a line each. Only
    /// the Fanuc and LinuxCNC writers can give it to the control; what GRBL
    /// has not is refused.
    pub(super) fn kept(&mut self, k: &Kept, dialect: Dialect) -> Result<(), WriteError> {
        let refused = match dialect {
            Dialect::Grbl => !grbl_has(&k.text),
            // Compensation by a diameter is LinuxCNC's alone.
            Dialect::Fanuc => k.text.contains("G41.1") || k.text.contains("G42.1"),
            Dialect::LinuxCnc => false,
        };
        if refused {
            return Err(WriteError::Kept { line: k.line, text: k.text.clone(), dialect });
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
            if line.contains("G91") {
                self.relative = Some(true);
            } else if line.contains("G90") {
                self.relative = Some(false);
            }
        }
        let units = if self.inch { "G20" } else { "G21" };
        if k.text.contains(if self.inch { "G21" } else { "G20" }) {
            self.line(units);
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
    pub(super) fn made(&mut self, end: Axes) -> Result<(), WriteError> {
        let t = self.target(end)?;
        for k in (0..6).filter(|&k| self.used[k]) {
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
        let words: Vec<&str> = line.split_whitespace().collect();
        let rest = line.trim().split_once(char::is_whitespace).map_or("", |(_, r)| r.trim());
        (matches!(words.first(), Some(&("M00" | "M01" | "M0" | "M1"))) && (rest.is_empty() || rest.starts_with('(')))
            || (words.contains(&"G10") && (words.contains(&"L2") || words.contains(&"L20")))
            || words.contains(&"G92")
            || words.contains(&"G92.1")
            || words.contains(&"G30")
    })
}

/// Whether kept text holds an axis word (`X5.`, `Z-1`).
fn has_axis_words(text: &str) -> bool {
    text.split_whitespace().any(|w| {
        let mut c = w.chars();
        matches!(c.next(), Some('X' | 'Y' | 'Z' | 'A' | 'B' | 'C'))
            && c.next().is_some_and(|d| d.is_ascii_digit() || d == '-' || d == '.' || d == '+')
    })
}
