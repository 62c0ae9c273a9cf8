//! G10 data setting (work and tool offsets), the work offset selected, and
//! the blocks that set offsets or shifts kept as the program gave them.

use kezuri_geom::{Axes, AxisSet};

use super::modal::{Distance, Units};
use super::words::Words;
use super::{Control, State};
use crate::offsets::EXTRA_OFFSETS;
use crate::source::{Diagnostic, Span};

impl State {
    /// Selects work offset `i` (G54 … G59, then the additional ones).
    pub(super) fn select_work_offset(&mut self, i: usize) {
        if i != self.modal.work_offset {
            self.guessed = AxisSet::ALL;
        }
        self.modal.work_offset = i;
    }

    /// Keeps a block that sets offsets or shifts (G10, G92, G52) as the
    /// program gave it: they depend on where the machine is, so the control
    /// must set them itself. Its values are in the program's units and
    /// G90/G91 mode, which the kept text names.
    pub(super) fn keep_as_given(&mut self, w: &Words, absolute: bool, line: u32) {
        let units = if self.modal.units == Units::Inch { "G20" } else { "G21" };
        let distance = if self.modal.distance == Distance::Incremental && !absolute { "G91" } else { "G90" };
        let words = w.text(|l, v| l != b'M' && !(l == b'G' && [20.0, 21.0, 90.0, 91.0].contains(&v)));
        self.keep(format!("{units} {distance} {words}"), 0, true, line);
    }

    /// G10 data setting: `L2 P0…6` a work offset (P0 the external offset,
    /// P1 to P6 G54 to G59) from the axis words, `L10 P… R…` (and the older
    /// `L1`) a tool length offset; in G91 the values are added.
    pub(super) fn set_offsets(&mut self, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        let linuxcnc = self.settings.coords.control == Control::LinuxCnc;
        // In G91 a Fanuc G10 adds to the offset; LinuxCNC ignores G91 here.
        let incremental =
            self.modal.distance == Distance::Incremental && self.settings.coords.control != Control::LinuxCnc;
        let whole = |v: Option<f64>| v.filter(|v| v.fract() == 0.0 && *v >= 0.0).map(|v| v as u32);
        match (whole(w.get(b'L')), whole(w.get(b'P'))) {
            (Some(2), Some(p)) if p <= 6 || (linuxcnc && p <= 9) => {
                // P0: the external offset on Fanuc, the current work offset
                // on LinuxCNC; P7 to P9: LinuxCNC's G59.1 to G59.3.
                let inch = self.modal.units == Units::Inch;
                let offset = match p {
                    0 if linuxcnc => &mut self.work_offsets[self.modal.work_offset],
                    0 => &mut self.external_offset,
                    _ => &mut self.work_offsets[linuxcnc_system(p)],
                };
                *offset = offset_words(*offset, w, incremental, inch);
                self.guessed = AxisSet::ALL;
                Ok(())
            }
            (Some(20), Some(p)) if linuxcnc && p <= 9 => {
                // LinuxCNC: the offset such that the tool is where the words say.
                let index = if p == 0 { self.modal.work_offset } else { linuxcnc_system(p) };
                let (tip, frame) = (self.tip.to_array(), self.frame_offset().to_array());
                let mut v = self.work_offsets[index].to_array();
                let base = self.work_offsets[self.modal.work_offset].to_array();
                for (i, value) in w.axis_words() {
                    let value = if Axes::is_linear(i) { self.mm(value) } else { value };
                    v[i] = tip[i] - (frame[i] - base[i]) - value;
                }
                self.work_offsets[index] = Axes::from_array(v);
                self.guessed = AxisSet::ALL;
                Ok(())
            }
            (Some(l @ (1 | 10 | 11)), Some(t @ 1..=999)) if linuxcnc => {
                // LinuxCNC's tool table: Z the length, R the radius. L1 sets
                // them; L10 the length such that, G43 reloaded, the current
                // Z (every offset in force) reads the value; L11 the same in
                // G59.3 without G52/G92.
                if self.comp_on() {
                    return Err(Diagnostic::error(
                        gspan,
                        format!("G10 L{l} with cutter compensation on (G41/G42): give G40 first"),
                    ));
                }
                if let Some(letter) = b"XYABCUVW".iter().copied().find(|&c| w.has(c)) {
                    return Err(Diagnostic::error(
                        w.span(letter),
                        format!("G10 L{l} {}: kezuri keeps a tool's length (Z) and radius (R) only", letter as char),
                    ));
                }
                if let Some(z) = w.get(b'Z') {
                    let z = self.mm(z);
                    let gauge = self.machine_position().z;
                    let z = match l {
                        10 => gauge - self.frame_offset().z - z,
                        11 => gauge - self.work_offsets[linuxcnc_system(9)].z - z,
                        _ => z,
                    };
                    self.settings.tool_lengths.insert(t, z);
                    self.length_wear.remove(&t);
                }
                if let Some(r) = w.get(b'R') {
                    let r = self.mm(r);
                    self.settings.tool_radii.insert(t, r);
                    self.radius_wear.remove(&t);
                }
                Ok(())
            }
            (Some(l @ (1 | 10..=13)), Some(n @ 1..=999)) => {
                let Some(r) = w.get(b'R') else {
                    return Err(Diagnostic::error(gspan, format!("G10 L{l} needs the offset value in R")));
                };
                let r = self.mm(r);
                // Fanuc tool offset memory: L10 H geometry, L11 H wear, L12 D
                // geometry, L13 D wear (L1: the one value of memory A).
                let table = match l {
                    1 | 10 => &mut self.settings.tool_lengths,
                    11 => &mut self.length_wear,
                    12 => &mut self.settings.tool_radii,
                    _ => &mut self.radius_wear,
                };
                let old = table.get(&n).copied().unwrap_or(0.0);
                table.insert(n, if incremental { old + r } else { r });
                Ok(())
            }
            (Some(20), Some(p @ 1..=99)) => {
                // Fanuc: the additional work offset G54.1 P.
                let index = EXTRA_OFFSETS + p as usize - 1;
                let inch = self.modal.units == Units::Inch;
                self.work_offsets[index] = offset_words(self.work_offsets[index], w, incremental, inch);
                self.guessed = AxisSet::ALL;
                Ok(())
            }
            (Some(2), _) => Err(Diagnostic::error(gspan, "G10 L2 needs P0 to P6 (P1 = G54 … P6 = G59)")),
            (Some(20), _) if self.settings.coords.control == Control::LinuxCnc => {
                Err(Diagnostic::error(gspan, "G10 L20 needs P0 to P6 (P0 = the current, P1 = G54 … P6 = G59)"))
            }
            (Some(20), _) => {
                Err(Diagnostic::error(gspan, "G10 L20 needs the additional work offset's number P1 to P99"))
            }
            (Some(l @ (1 | 10..=13)), _) => {
                Err(Diagnostic::error(gspan, format!("G10 L{l} needs the offset number P1 to P999")))
            }
            _ => Err(Diagnostic::error(
                gspan,
                "this G10 is not supported: L2 and L20 (work offsets), L1 and L10 to L13 (tool offsets) are",
            )),
        }
    }
}

/// A work offset with the axis words of a G10 block set (or, `incremental`,
/// added).
fn offset_words(offset: Axes, w: &Words, incremental: bool, inch: bool) -> Axes {
    let mut v = offset.to_array();
    for (i, value) in w.axis_words() {
        let value = if Axes::is_linear(i) && inch { value * 25.4 } else { value };
        v[i] = if incremental { v[i] + value } else { value };
    }
    Axes::from_array(v)
}

/// The work offset of LinuxCNC's coordinate system `p` (1 G54 … 6 G59, 7 to
/// 9 G59.1 to G59.3).
fn linuxcnc_system(p: u32) -> usize {
    match p {
        1..=6 => p as usize - 1,
        _ => EXTRA_OFFSETS + p as usize - 7,
    }
}
