//! LinuxCNC's numbered parameters #5001–#5999 (the linuxcnc and grbl
//! dialects), beside Fanuc's system variables of `vars.rs`.
//!
//! From LinuxCNC's manual (Numbered Parameters): #5061–#5069 the G38 probe
//! result, #5161–#5169 the G28 position, #5181–#5189 G30's, #5210 whether a
//! G52/G92 offset is applied, #5211–#5219 that offset, #5220 the coordinate
//! system (1 G54 … 9 G59.3), #5221–#5230 G54 (X Y Z A B C U V W R), #5241…
//! G55, … #5381… G59.3, #5400 the tool, #5401–#5409 its offsets, #5410 its
//! diameter, #5420–#5428 the current position in program coordinates and
//! units. Lengths are in mm (the machine's units), the position in the
//! program's, the probe result in the program's when the probe was made
//! (the tip's program position, as `State::record_skip` says). U V W are axes as X Y Z are (LinuxCNC has nine); the rotation
//! R and every other number in the range are plain storage that starts at 0,
//! as in LinuxCNC.

use kezuri_geom::{Axes, AxisSet};

use super::modal::Units;
use super::{State, Value};
use crate::offsets::EXTRA_OFFSETS;
use crate::Dialect;

/// Whether `dialect` numbers its parameters as LinuxCNC does.
pub(super) fn linuxcnc_numbering(dialect: Dialect) -> bool {
    matches!(dialect, Dialect::LinuxCnc | Dialect::Grbl)
}

/// What LinuxCNC parameter `n` is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Param {
    Probe(usize),
    Home(usize),
    Second(usize),
    G92Applied,
    G92(usize),
    System,
    /// Coordinate system (0 G54 … 8 G59.3), axis.
    Offset(usize, usize),
    Tool,
    ToolOffset(usize),
    ToolDiameter,
    Position(usize),
    /// Anything else: storage.
    Plain,
}

fn param(n: u32) -> Param {
    let axis = |first: u32| (n - first) as usize;
    match n {
        5061..=5069 => Param::Probe(axis(5061)),
        5161..=5169 => Param::Home(axis(5161)),
        5181..=5189 => Param::Second(axis(5181)),
        5210 => Param::G92Applied,
        5211..=5219 => Param::G92(axis(5211)),
        5220 => Param::System,
        5221..=5390 if (n - 5221) % 20 < 10 => Param::Offset(((n - 5221) / 20) as usize, ((n - 5221) % 20) as usize),
        5400 => Param::Tool,
        5401..=5409 => Param::ToolOffset(axis(5401)),
        5410 => Param::ToolDiameter,
        5420..=5428 => Param::Position(axis(5420)),
        _ => Param::Plain,
    }
}

/// Axis `i` (X Y Z A B C U V W; `None` past W) of `a`.
fn get(a: Axes, i: usize) -> Option<f64> {
    a.to_array().get(i).copied()
}

/// `a` with axis `i` set to `v` (nothing past W).
fn set(a: &mut Axes, i: usize, v: f64) {
    let mut arr = a.to_array();
    if let Some(slot) = arr.get_mut(i) {
        *slot = v;
        *a = Axes::from_array(arr);
    }
}

/// The work offset index of LinuxCNC coordinate system `k` (0 G54 … 8 G59.3).
fn system_index(k: usize) -> usize {
    if k < 6 {
        k
    } else {
        EXTRA_OFFSETS + k - 6
    }
}

impl State {
    /// LinuxCNC's coordinate system number in force (0 G54 … 8 G59.3), if
    /// it is one.
    fn linuxcnc_system(&self) -> Option<usize> {
        match self.modal.work_offset {
            k @ 0..=5 => Some(k),
            k if (EXTRA_OFFSETS..EXTRA_OFFSETS + 3).contains(&k) => Some(k - EXTRA_OFFSETS + 6),
            _ => None,
        }
    }

    /// Plain storage of parameter `n`, 0 until set.
    fn stored(&self, n: u32) -> f64 {
        self.sparse.get(&n).map_or(0.0, |v| v.num())
    }

    /// Reads LinuxCNC parameter `n` (5001–5999).
    pub(super) fn read_linuxcnc(&mut self, n: u32) -> f64 {
        let inch = self.modal.units == Units::Inch;
        let unit = |i: usize, v: f64| if inch && Axes::is_linear(i) { v / 25.4 } else { v };
        let or_stored = |v: Option<f64>, st: &State| v.unwrap_or_else(|| st.stored(n));
        match param(n) {
            Param::Probe(i) => or_stored(get(self.skip_position, i), self),
            Param::Home(i) => or_stored(get(self.settings.home, i), self),
            Param::Second(i) => or_stored(get(self.settings.coords.reference_points[0], i), self),
            Param::G92Applied => f64::from(u8::from(self.g92_shift != Axes::ZERO)),
            Param::G92(i) => or_stored(get(self.g92_shift, i), self),
            Param::System => self.linuxcnc_system().map_or(0.0, |k| k as f64 + 1.0),
            Param::Offset(k, i) => or_stored(get(self.work_offsets[system_index(k)], i), self),
            Param::Tool => f64::from(self.tool),
            Param::ToolOffset(2) => self.tool_length(self.tool).unwrap_or(0.0),
            Param::ToolDiameter => 2.0 * self.tool_radius(self.tool).unwrap_or(0.0),
            Param::Position(i) => or_stored(get(self.work_position(), i).map(|v| unit(i, v)), self),
            Param::ToolOffset(_) | Param::Plain => self.stored(n),
        }
    }

    /// Writes LinuxCNC parameter `n` (5001–5999) from the program.
    pub(super) fn write_linuxcnc(&mut self, n: u32, value: Value) -> Result<(), String> {
        let v = value.num();
        match param(n) {
            Param::Offset(k, _) if Some(k) == self.linuxcnc_system() => {
                return Err(format!(
                    "#{n} belongs to the coordinate system in force (G{}): LinuxCNC uses a new value only once \
                     another system is selected and this one again, so kezuri refuses it; set it with G10 L2 P{}",
                    ["54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"][k],
                    k + 1
                ))
            }
            Param::G92Applied | Param::G92(_) => {
                return Err(format!("#{n} is the G52/G92 offset, which LinuxCNC applies at G92.3: set it with G92"))
            }
            Param::System | Param::Tool | Param::ToolOffset(_) | Param::ToolDiameter | Param::Position(_) => {
                return Err(format!(
                    "#{n} is read-only here: LinuxCNC recomputes it (the coordinate system, the tool, the position)"
                ))
            }
            _ => {}
        }
        self.set_linuxcnc(n, v);
        // Kept as the program set it: the control must hold it too.
        self.set_by_program.insert(n);
        self.keep(format!("#{n}={}", trim(v)), 0, true, self.at_line);
        Ok(())
    }

    /// Sets parameter `n` to `v`: the G28 and G30 positions, a work offset,
    /// else storage.
    fn set_linuxcnc(&mut self, n: u32, v: f64) {
        match param(n) {
            Param::Home(i) if i < Axes::COUNT => set(&mut self.settings.home, i, v),
            Param::Second(i) if i < Axes::COUNT => set(&mut self.settings.coords.reference_points[0], i, v),
            Param::Offset(k, i) if i < Axes::COUNT => {
                set(&mut self.work_offsets[system_index(k)], i, v);
                self.guessed = AxisSet::ALL;
            }
            Param::G92(i) if i < Axes::COUNT => set(&mut self.g92_shift, i, v),
            Param::System if (1.0..=9.0).contains(&v) => self.select_work_offset(system_index(v as usize - 1)),
            _ => {
                self.sparse.insert(n, Value::Num(v));
            }
        }
    }

    /// Sets the parameters' starting values (LinuxCNC's `.var` file, in
    /// `Settings::parameters`), as rs274 does at start-up: the offsets, the
    /// G28/G30 positions, the coordinate system #5220, the G92 offset where
    /// #5210 is 1; every other number as plain storage.
    pub(super) fn load_parameters(&mut self) -> Result<(), String> {
        if !linuxcnc_numbering(self.settings.dialect) {
            return Ok(());
        }
        let values = std::mem::take(&mut self.settings.parameters);
        let g92_applied = values.get(&5210).is_some_and(|&v| v == 1.0);
        let mut result = Ok(());
        for (&n, &v) in &values {
            match n {
                5211..=5219 if !g92_applied => {}
                5001..=5999 => self.set_linuxcnc(n, v),
                // #31–#5000 and the rest: what the program reads, as it
                // reads any variable; one it cannot hold is an error.
                _ => {
                    if let Err(m) = self.write_var(f64::from(n), Value::Num(v)) {
                        result = Err(format!("parameter #{n}: {m}"));
                        break;
                    }
                }
            }
        }
        self.settings.parameters = values;
        result
    }
}

/// `v` as a parameter assignment writes it: no trailing zeros.
fn trim(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0');
    s.strip_suffix('.').map_or_else(|| s.to_string(), |t| format!("{t}.0"))
}
