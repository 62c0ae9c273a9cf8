//! The frame the control is in: the work offset (`G54`…, and `G10 L2`/`L20`
//! where the program changed an origin) and the tool length offset.

use kezuri_geom::{Axes, Frame, LengthOffset};

use super::blocks::{unsupported, Writer, AXIS_LETTERS, N};
use super::dialect::Dialect;
use crate::number::push_uint;
use crate::offsets::EXTRA_OFFSETS;
use crate::Error;

impl Writer {
    /// Brings the control to frame `f`: the work offset (`G54`…`G59`, and a
    /// `G10 L2` where the program changed an offset's origin) and the tool
    /// length offset ([`Writer::length`]). `last` is the
    /// tool tip in machine coordinates, to carry the known position over to
    /// the new work offset.
    pub(super) fn frame(&mut self, f: Frame, last: Option<Axes>) -> Result<(), Error> {
        let old = self.frame;
        if old == Some(f) {
            return Ok(());
        }
        self.end_cycle();
        // Positions in the new frame are the writer's reckoning, not what
        // the program wrote: absolute until every axis is written again.
        self.exact = [false; N];
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
            for k in (0..N).filter(|&k| used[k]) {
                let n = self.fixed(v[k], AXIS_LETTERS[k])?;
                self.word(AXIS_LETTERS[k], n, self.point);
            }
            self.out.push('\n');
            self.origins[work] = Some(f.origin);
        }
        let new_work = old.map(|o| o.work) != Some(f.work);
        let old_length = old.map(|o| o.length);
        let (first, more) = if old_length == Some(f.length) { (None, Vec::new()) } else { self.length(f, old_length)? };
        if new_work || first.is_some() {
            self.block();
            self.distance(false);
            if new_work {
                self.code(&code);
            }
            if let Some(words) = first {
                self.code(&words);
            }
            self.out.push('\n');
        }
        for words in more {
            self.line(&words);
        }
        if let (Some(o), Some(e)) = (old, last) {
            if o.zero() != f.zero() {
                let (e, origin) = (e.to_array(), f.zero().to_array());
                for k in 0..N {
                    if self.pos[k].is_some() {
                        self.pos[k] = Some(self.fixed(e[k] - origin[k], AXIS_LETTERS[k])?);
                    }
                }
            }
        }
        self.frame = Some(f);
        Ok(())
    }

    /// The words that bring the tool length offset to `f`'s from `old`'s:
    /// those of the first block (with the work offset), and whole blocks
    /// after it (LinuxCNC's G43.2 additions, each in its own block: they
    /// are one modal group). `G43`/`G44 H`, `G49`; GRBL's `G43.1 Z` with
    /// the value; LinuxCNC's `G43.1 Z` and `G43.2 H` as the program gave
    /// them, only the new additions where the rest is in force already.
    /// Fanuc has no dynamic offset: refused.
    fn length(&self, f: Frame, old: Option<Option<LengthOffset>>) -> Result<(Option<String>, Vec<String>), Error> {
        let Some(l) = f.length else {
            return Ok((Some(self.codes.length_cancel.to_string()), Vec::new()));
        };
        if self.dialect == Dialect::Grbl {
            // GRBL has no offset table: the offset itself.
            let z = self.word_text('Z', self.fixed(l.signed(), 'Z')?, false);
            return Ok((Some(format!("G43.1 {z}")), Vec::new()));
        }
        let added: Vec<u32> = l.added.iter().copied().take_while(|&h| h != 0).collect();
        let adds = |from: usize| added[from..].iter().map(|h| format!("G43.2 H{h}")).collect::<Vec<_>>();
        if l.dynamic() && self.dialect == Dialect::Fanuc {
            let text = match l.given {
                Some(z) => {
                    let z = self.word_text('Z', self.fixed(z, 'Z')?, self.point);
                    format!("G43.1 {z} (a dynamic tool length offset, LinuxCNC's)")
                }
                None => format!("G43.2 H{} (a tool length added to the offset in force, LinuxCNC's)", added[0]),
            };
            return Err(unsupported(self.dialect, self.at.1, &text));
        }
        // Only G43.2 additions since: the offset in force stays.
        if let Some(Some(o)) = old {
            let before = o.added.iter().take_while(|&&h| h != 0).count();
            let same_base = (o.register, o.negative, o.given) == (l.register, l.negative, l.given);
            if same_base && before < added.len() && o.added[..before] == l.added[..before] {
                return Ok((None, adds(before)));
            }
        }
        let first = match l.given {
            Some(z) => {
                format!("G43.1 {}", self.word_text('Z', self.fixed(z, 'Z')?, self.point))
            }
            None => format!("{} H{}", self.codes.length[usize::from(l.negative)], l.register),
        };
        Ok((Some(first), adds(0)))
    }

    /// The code that selects work offset `work`: G54 … G59, then G54.1 P
    /// (Fanuc) or G59.1 … G59.3 (LinuxCNC); what the dialect has not is
    /// refused.
    fn work_code(&self, work: usize) -> Result<String, Error> {
        let p = (work + 1).saturating_sub(EXTRA_OFFSETS);
        Ok(match work {
            0..EXTRA_OFFSETS => ["G54", "G55", "G56", "G57", "G58", "G59"][work].to_string(),
            _ if self.dialect == Dialect::Fanuc => format!("G54.1 P{p}"),
            _ if self.dialect == Dialect::LinuxCnc && p <= 3 => format!("G59.{p}"),
            _ => return Err(unsupported(self.dialect, self.at.1, &format!("G54.1 P{p} (an additional work offset)"))),
        })
    }
}
