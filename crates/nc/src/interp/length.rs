//! LinuxCNC's dynamic tool length offsets: G43.1 (the offset given in the
//! block) and G43.2 (a tool's length added to the offset in force). Like
//! G43 in LinuxCNC they move nothing: the tip's programmed Z changes by the
//! change of offset ([`State::length_changed`]).

use kezuri_geom::LengthOffset;

use super::modal::{GCode, Units};
use super::words::Words;
use super::{Control, State};
use crate::source::{Diagnostic, Span};

impl State {
    /// G43.1: the Z word is the offset (mm once converted), absolute even
    /// under G91, in place of the one in force (G43 H, G43.2 additions and
    /// all). Without Z the offset stays (rs274: G43.1 sets only the axes it
    /// names). Offsets in other axes are refused.
    pub(super) fn length_given(&mut self, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        self.dynamic_length_rules(w, gspan, "G43.1")?;
        if let Some(letter) = b"XYABCUVW".iter().copied().find(|&l| w.has(l)) {
            return Err(Diagnostic::error(
                w.span(letter),
                format!(
                    "G43.1 {}: kezuri applies a tool length offset in Z only (LinuxCNC's offsets in other axes \
                     are not supported)",
                    letter as char
                ),
            ));
        }
        let Some(z) = w.get(b'Z') else {
            return Ok(());
        };
        let before = self.length_offset();
        let z = self.mm(z);
        self.modal.length_comp = Some((1.0, 0));
        self.length_loaded = Some(z);
        self.length_given = Some(z);
        self.length_added = [0; LengthOffset::ADDED];
        self.length_units = self.modal.units;
        self.length_changed(before);
        Ok(())
    }

    /// G43.2 H: tool H's length (the tool table's, as G43 loads it) added
    /// to the offset in force; with none in force, to zero.
    pub(super) fn length_added(&mut self, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        self.dynamic_length_rules(w, gspan, "G43.2")?;
        if let Some(letter) = b"XYZABCUVW".iter().copied().find(|&l| w.has(l)) {
            return Err(Diagnostic::error(
                w.span(letter),
                "G43.2: Can not have both H and axis words (LinuxCNC 2.9 adds a tool's length, given by H)",
            ));
        }
        let Some(h) = w.get(b'H') else {
            return Err(Diagnostic::error(gspan, "G43.2 needs H, the tool whose length it adds"));
        };
        let hspan = w.span(b'H');
        if h.fract() != 0.0 || !(0.0..=99_999_999.0).contains(&h) {
            return Err(Diagnostic::error(hspan, format!("G43.2 H{h}: the H number must be a whole number from 0")));
        }
        let h = h as u32;
        if self.modal.length_comp.is_some_and(|(sign, _)| sign < 0.0) {
            return Err(Diagnostic::error(gspan, "G43.2 adds to a G43 offset: not to G44's (give G49 or G43 first)"));
        }
        let before = self.length_offset();
        if before != 0.0 && self.length_units != self.modal.units {
            let (then, now) = match self.length_units {
                Units::Inch => ("G20", "G21"),
                Units::Mm => ("G21", "G20"),
            };
            return Err(Diagnostic::error(
                gspan,
                format!(
                    "G43.2 after {now}: LinuxCNC adds to the number of the offset in force, set under {then}, \
                     without converting it (rs274 reads an offset of 0.5 in as 0.5 mm): give G43 or G43.1 again \
                     under {now} first"
                ),
            ));
        }
        if h != 0 && self.tool_length(h).is_none() {
            self.warn("offset", hspan, self.missing_length(h));
        }
        self.last.h = f64::from(h);
        if self.modal.length_comp.is_none() {
            self.modal.length_comp = Some((1.0, 0));
            self.length_given = Some(0.0);
            self.length_added = [0; LengthOffset::ADDED];
        }
        if h != 0 {
            let Some(slot) = self.length_added.iter_mut().find(|a| **a == 0) else {
                return Err(Diagnostic::error(
                    gspan,
                    format!(
                        "more than {} G43.2 in a row: kezuri keeps that many additions; give G43 or G43.1 again",
                        LengthOffset::ADDED
                    ),
                ));
            };
            *slot = h;
        }
        self.length_loaded = Some(before + self.tool_length(h).unwrap_or(0.0));
        self.length_units = self.modal.units;
        self.length_changed(before);
        Ok(())
    }

    /// The warning of a G43/G43.2 `H{h}` the tool table lacks: what is
    /// missing and the line that gives it, under the entry of the tool
    /// that holds H`h` (`[tools.T5] h = 15`), else of tool `h`.
    pub(super) fn missing_length(&self, h: u32) -> String {
        let tool = self.settings.length_owners.get(&h).copied().unwrap_or(h);
        let line = format!("`length = <mm>` under [tools.T{tool}]");
        match &self.settings.tool_file {
            Some(file) => format!(
                "tool length offset H{h} is not in the tool table: it reads 0; add {line} in {file} \
                 (the length the control's H{h} holds)"
            ),
            None => format!(
                "tool length offset H{h} is not in the tool table: it reads 0; give it in a machine file \
                 (--machine M.toml): {line}"
            ),
        }
    }

    /// What G43.1 and G43.2 share: LinuxCNC's (G43.2 not GRBL's), nor
    /// with motion or a one-shot code in the block (G43.1 takes its axis
    /// words).
    fn dynamic_length_rules(&self, w: &Words, gspan: Span, name: &str) -> Result<(), Diagnostic> {
        let ours = self.settings.coords.control == Control::LinuxCnc
            && (name == "G43.1" || self.settings.dialect == crate::Dialect::LinuxCnc);
        if !ours {
            return Err(Diagnostic::error(gspan, format!("{name} is not supported")));
        }
        for &(tenths, span) in &w.g[..w.g_count] {
            let Some(code) = GCode::decode(tenths) else { continue };
            if matches!(code.group(), 0 | 1 | 9) && code != GCode::CycleOff {
                return Err(Diagnostic::error(
                    span,
                    format!(
                        "{name} with G{}{}: give the motion in another block ({name} takes the block's axis words)",
                        tenths / 10,
                        if tenths % 10 == 0 { String::new() } else { format!(".{}", tenths % 10) }
                    ),
                ));
            }
        }
        Ok(())
    }
}
