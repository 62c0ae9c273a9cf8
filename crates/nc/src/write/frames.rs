//! The frame the control is in: the work offset (`G54`…, and `G10 L2`/`L20`
//! where the program changed an origin) and the tool length offset.

use kezuri_geom::{Axes, Frame};

use super::blocks::{push_uint, Writer, AXIS_LETTERS};
use super::gcode::{Dialect, WriteError};
use crate::interp::EXTRA_OFFSETS;

impl Writer {
    /// Brings the control to frame `f`: the work offset (`G54`…`G59`, and a
    /// `G10 L2` where the program changed an offset's origin) and the tool
    /// length offset (`G43`/`G44 H`, `G43.1 Z` on GRBL, `G49`). `last` is the
    /// tool tip in machine coordinates, to carry the known position over to
    /// the new work offset.
    pub(super) fn frame(&mut self, f: Frame, last: Option<Axes>) -> Result<(), WriteError> {
        let old = self.frame;
        if old == Some(f) {
            return Ok(());
        }
        self.end_cycle();
        // Positions in the new frame are the writer's reckoning, not what
        // the program wrote: absolute until every axis is written again.
        self.exact = [false; 6];
        let work = f.work as usize;
        let code = self.work_code(work)?;
        let known = *self.origins[work].get_or_insert(f.origin);
        if known != f.origin {
            let v = f.origin.to_array();
            self.block();
            // In G91, G10 L2 adds to the offset.
            self.distance(false);
            // G54 … G59: L2 P1 … P6; the additional ones: Fanuc's L20 P,
            // LinuxCNC's L2 P7 … P9.
            let (l, p) = if work >= EXTRA_OFFSETS && self.dialect == Dialect::Fanuc {
                ("G10 L20", work + 1 - EXTRA_OFFSETS)
            } else {
                ("G10 L2", work + 1)
            };
            self.code(l);
            self.space();
            self.out.push('P');
            push_uint(&mut self.out, p as u64);
            let used = self.used;
            for k in (0..6).filter(|&k| used[k]) {
                let n = self.fixed(v[k], AXIS_LETTERS[k])?;
                self.word(AXIS_LETTERS[k], n, self.point);
            }
            self.out.push('\n');
            self.origins[work] = Some(f.origin);
        }
        let new_work = old.map(|o| o.work) != Some(f.work);
        let new_length = old.map(|o| o.length) != Some(f.length);
        if new_work || new_length {
            self.block();
            self.distance(false);
            if new_work {
                self.code(&code);
            }
            if new_length {
                match f.length {
                    None => self.code(self.codes.length_cancel),
                    Some(l) if self.dialect == Dialect::Grbl => {
                        // GRBL has no offset table: the offset itself.
                        let n = self.fixed(l.signed(), 'Z')?;
                        self.code("G43.1");
                        self.word('Z', n, false);
                    }
                    Some(l) => {
                        self.code(if l.negative { self.codes.length[1] } else { self.codes.length[0] });
                        self.space();
                        self.out.push('H');
                        push_uint(&mut self.out, u64::from(l.register));
                    }
                }
            }
            self.out.push('\n');
        }
        if let (Some(o), Some(e)) = (old, last) {
            if o.zero() != f.zero() {
                let (e, origin) = (e.to_array(), f.zero().to_array());
                for k in 0..6 {
                    if self.pos[k].is_some() {
                        self.pos[k] = Some(self.fixed(e[k] - origin[k], AXIS_LETTERS[k])?);
                    }
                }
            }
        }
        self.frame = Some(f);
        Ok(())
    }

    /// The code that selects work offset `work`: G54 … G59, then G54.1 P
    /// (Fanuc) or G59.1 … G59.3 (LinuxCNC); what the dialect has not is
    /// refused.
    fn work_code(&self, work: usize) -> Result<String, WriteError> {
        let p = (work + 1).saturating_sub(EXTRA_OFFSETS);
        Ok(match work {
            0..EXTRA_OFFSETS => ["G54", "G55", "G56", "G57", "G58", "G59"][work].to_string(),
            _ if self.dialect == Dialect::Fanuc => format!("G54.1 P{p}"),
            _ if self.dialect == Dialect::LinuxCnc && p <= 3 => format!("G59.{p}"),
            _ => {
                return Err(WriteError::Kept {
                    line: self.at.1,
                    text: format!("G54.1 P{p} (an additional work offset)"),
                    dialect: self.dialect,
                })
            }
        })
    }
}
