//! Macro variables: locals per call level, commons, and system variables.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::ops::RangeInclusive;

use super::value::Value;
use super::{ModelRead, State};
use crate::number::number;
use crate::offsets::EXTRA_OFFSETS;
use kezuri_geom::{Axes, SplitMix64};

/// Local variables #1–#33 of one call level.
pub type Locals = [Value; 33];

/// Largest variable number a program may write.
const MAX_VARIABLE: f64 = 99_999_999.0;

/// Numbers that are never common variables: the locals and the system
/// variables (#1000–#9999) of a Fanuc control.
const RESERVED: [RangeInclusive<u32>; 2] = [0..=33, 1000..=9999];

/// Which common variables a control has, and which of them it keeps over a
/// reset and power off. A machine file's `[macro]` section sets it; see
/// `docs/macro-variables.md` for where each range comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct MacroVariables {
    /// Ranges of common variable numbers, both ends included. A variable
    /// outside every range (and not a local or system variable) is an error.
    pub common: Vec<RangeInclusive<u32>>,
    /// The ranges, within `common`, whose values are kept over a reset and
    /// power off; the others start vacant on every run.
    pub kept: Vec<RangeInclusive<u32>>,
    /// Values of kept variables at the start of the run: what earlier
    /// programs or the operator left in them.
    pub values: BTreeMap<u32, f64>,
}

impl Default for MacroVariables {
    /// The broadest set: #100–#199, #200–#499 (an option on Fanuc
    /// controls), #500–#999 and #900000–#999999 (seen in shop programs);
    /// #500–#999 kept over a reset.
    fn default() -> MacroVariables {
        MacroVariables {
            common: vec![100..=199, 200..=499, 500..=999, 900_000..=999_999],
            kept: vec![500..=999],
            values: BTreeMap::new(),
        }
    }
}

impl MacroVariables {
    /// Reads a range as a machine file writes it: `"100-199"`, or `"150"`
    /// for one variable.
    pub fn parse_range(text: &str) -> Result<RangeInclusive<u32>, String> {
        let number = |t: &str| -> Result<u32, String> {
            let t = t.trim().trim_start_matches('#');
            t.parse::<u32>().map_err(|_| format!("'{text}' is not a variable range such as \"100-199\""))
        };
        match text.split_once('-') {
            Some((first, last)) => Ok(number(first)?..=number(last)?),
            None => number(text).map(|n| n..=n),
        }
    }

    /// Whether `#n` is one of the common variables.
    pub fn is_common(&self, n: u32) -> bool {
        self.common.iter().any(|r| r.contains(&n))
    }

    /// Whether `#n` is kept over a reset.
    pub fn is_kept(&self, n: u32) -> bool {
        self.kept.iter().any(|r| r.contains(&n)) && self.is_common(n)
    }

    /// The common ranges as a machinist reads them: `#100–#199, #500–#999`.
    pub fn describe(&self) -> String {
        let mut out = String::new();
        for (k, r) in self.common.iter().enumerate() {
            let sep = if k == 0 { "" } else { ", " };
            let _ = match r.start() == r.end() {
                true => write!(out, "{sep}#{}", r.start()),
                false => write!(out, "{sep}#{}–#{}", r.start(), r.end()),
            };
        }
        if out.is_empty() {
            out.push_str("none");
        }
        out
    }

    /// Checks the ranges: each in order, none over the locals #0–#33 or
    /// the system variables #1000–#9999, no number above 99999999, every
    /// kept range within the common ones, starting values only for kept
    /// variables.
    pub fn check(&self) -> Result<(), String> {
        for r in self.common.iter().chain(&self.kept) {
            if r.start() > r.end() {
                return Err(format!("#{}–#{}: the first number is above the last", r.start(), r.end()));
            }
            if f64::from(*r.end()) > MAX_VARIABLE {
                return Err(format!("#{}–#{}: variable numbers end at #99999999", r.start(), r.end()));
            }
            if let Some(x) = RESERVED.iter().find(|x| r.start() <= x.end() && x.start() <= r.end()) {
                let what = if *x.start() == 0 { "local variables" } else { "system variables" };
                return Err(format!(
                    "#{}–#{} overlaps the {what} #{}–#{}: common variables cannot be there",
                    r.start(),
                    r.end(),
                    x.start(),
                    x.end()
                ));
            }
        }
        for r in &self.kept {
            if let Some(n) = [*r.start(), *r.end()].into_iter().find(|&n| !self.is_common(n)) {
                return Err(format!("kept variable #{n} is not a common variable ({})", self.describe()));
            }
        }
        for (&n, &v) in &self.values {
            if !self.is_kept(n) {
                return Err(format!("#{n} is not kept over a reset: only kept variables have a starting value"));
            }
            if !v.is_finite() {
                return Err(format!("#{n} = {v} is not a finite number"));
            }
        }
        Ok(())
    }
}

/// The `G10` that sets offset variable `n` to `v` (mm, as kezuri reads the
/// variables), or `None` for a variable that is no offset.
fn offset_as_g10(n: u32, v: f64) -> Option<String> {
    const LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];
    let value = number(v, 6);
    let (l, p, word) = match n {
        2001..=2200 => (10, n - 2000, 'R'),
        2201..=2400 => (12, n - 2200, 'R'),
        10001..=10999 => (11, n - 10000, 'R'),
        11001..=11999 => (10, n - 11000, 'R'),
        12001..=12999 => (13, n - 12000, 'R'),
        13001..=13999 => (12, n - 13000, 'R'),
        5201..=5326 if (n - 5201) % 20 < 6 => (2, (n - 5201) / 20, LETTERS[((n - 5201) % 20) as usize]),
        7001..=7960 | 14001..=15980 if extra_offset(n).1 < 6 => {
            let (index, axis) = extra_offset(n);
            (20, (index - EXTRA_OFFSETS + 1) as u32, LETTERS[axis as usize])
        }
        _ => return None,
    };
    Some(format!("G21 G90 G10 L{l} P{p} {word}{value}"))
}

/// The work offset index and axis of #7001… (G54.1 P1…) or #14001… (G154
/// P1…).
fn extra_offset(n: u32) -> (usize, u32) {
    let base = if n >= 14001 { 14001 } else { 7001 };
    (EXTRA_OFFSETS + ((n - base) / 20) as usize, (n - base) % 20)
}

fn axis(a: Axes, i: u32) -> Option<f64> {
    a.to_array().get(i as usize).copied()
}

/// Where an assignment or read lands.
pub(super) enum Slot {
    Vacant,
    Local(usize),
    /// #100–#999, kept in an array: macro loops use them most.
    Dense(usize),
    /// Any other common variable, kept in a map.
    Sparse(u32),
    System(u32),
}

impl State {
    /// What variable `#number` is on this machine.
    pub(super) fn slot(&self, number: f64) -> Result<Slot, String> {
        if number.fract() != 0.0 || !(0.0..=MAX_VARIABLE).contains(&number) {
            return Err(format!("#{number} is not a variable number (use whole numbers from 0 to 99999999)"));
        }
        let n = number as u32;
        if self.settings.dialect == crate::Dialect::LinuxCnc {
            // LinuxCNC: #1–#30 are a subroutine's arguments, #31–#5000 plain
            // global parameters (no Fanuc signals, offsets or alarms there).
            match n {
                1..=30 => return Ok(Slot::Local(n as usize - 1)),
                31..=5000 => return Ok(Slot::Sparse(n)),
                _ => {}
            }
        }
        let vars = &self.settings.macro_variables;
        Ok(match n {
            0 => Slot::Vacant,
            1..=33 => Slot::Local(n as usize - 1),
            1000..=9999 => Slot::System(n),
            100..=999 if vars.is_common(n) => Slot::Dense(n as usize - 100),
            _ if vars.is_common(n) => Slot::Sparse(n),
            // Tool offsets, geometry and wear (where no common range has them).
            10001..=13999 | 14001..=15980 => Slot::System(n),
            _ => {
                return Err(format!(
                    "#{n} is not a variable of this machine: its common variables are {} \
                     (the machine file's [macro] common sets them)",
                    vars.describe()
                ))
            }
        })
    }

    /// Reads variable `#number`.
    pub(super) fn read_var(&mut self, number: f64) -> Result<Value, String> {
        Ok(match self.slot(number)? {
            Slot::Vacant => Value::Vacant,
            Slot::Local(i) => self.locals[self.level][i],
            Slot::Dense(i) => self.common[i],
            Slot::Sparse(n) => self.sparse.get(&n).copied().unwrap_or(Value::Vacant),
            Slot::System(n) => Value::Num(self.read_system(n)?),
        })
    }

    /// Writes variable `#number`.
    pub(super) fn write_var(&mut self, number: f64, value: Value) -> Result<(), String> {
        match self.slot(number)? {
            Slot::Vacant => return Err("#0 is always vacant and cannot be assigned".into()),
            Slot::Local(i) => self.locals[self.level][i] = value,
            Slot::Dense(i) => self.common[i] = value,
            Slot::Sparse(n) => match value {
                Value::Vacant => {
                    self.sparse.remove(&n);
                }
                Value::Num(_) => {
                    self.sparse.insert(n, value);
                }
            },
            Slot::System(n) => self.write_system(n, value)?,
        }
        Ok(())
    }

    /// A LinuxCNC predefined named parameter (`_x`, `_metric`, …: the name
    /// as parsed, lower case with its underscore), or `None` where `name`
    /// is none. Read-only; lengths in the program's units.
    pub(super) fn predefined(&self, name: &str) -> Option<f64> {
        use super::modal::{Distance, FeedMode, Units};
        let inch = self.modal.units == Units::Inch;
        let length = |v: f64| if inch { v / 25.4 } else { v };
        let bool = |b: bool| if b { 1.0 } else { 0.0 };
        let position = |p: Axes, axis: &str| -> Option<f64> {
            let a = p.to_array();
            Some(match axis {
                "x" => length(a[0]),
                "y" => length(a[1]),
                "z" => length(a[2]),
                "a" => a[3],
                "b" => a[4],
                "c" => a[5],
                "u" => length(a[6]),
                "v" => length(a[7]),
                "w" => length(a[8]),
                _ => return None,
            })
        };
        let group = |g: u32| self.modal.group_value(g).unwrap_or(0.0);
        Some(match name {
            "_line" => f64::from(self.at_line),
            "_motion_mode" => 10.0 * self.modal.cycle.map_or(group(1), |c| f64::from(c.number())),
            "_plane" => 10.0 * group(2),
            "_ccomp" => 10.0 * group(7),
            "_metric" => bool(!inch),
            "_imperial" => bool(inch),
            "_absolute" => bool(self.modal.distance == Distance::Absolute),
            "_incremental" => bool(self.modal.distance == Distance::Incremental),
            "_inverse_time" => bool(self.modal.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => bool(self.modal.feed_mode == FeedMode::PerMinute),
            "_units_per_rev" => bool(self.modal.feed_mode == FeedMode::PerRev),
            "_coord_system" => match self.modal.work_offset {
                k @ 0..=5 => 540.0 + 10.0 * k as f64,
                _ => 0.0,
            },
            "_tool_offset" => bool(self.modal.length_comp.is_some()),
            "_retract_r_plane" => bool(group(10) == 99.0),
            "_retract_old_z" => bool(group(10) == 98.0),
            "_spindle_on" => bool(self.spindle != kezuri_geom::Spindle::Off),
            "_spindle_cw" => bool(self.spindle == kezuri_geom::Spindle::Cw),
            "_mist" => bool(self.coolant.mist),
            "_flood" => bool(self.coolant.flood),
            "_feed" => self.feed_word,
            "_rpm" => self.speed,
            "_current_tool" => f64::from(self.tool),
            "_selected_tool" => f64::from(self.pending_tool),
            "_value" => self.returned.unwrap_or(0.0),
            "_value_returned" => bool(self.returned.is_some()),
            "_call_level" => f64::from(self.call_level),
            // What LinuxCNC 2.9's interpreter reports of itself and of the
            // machine it runs on, as its standalone run (`rs274`) reads them:
            // kezuri is that run, not the machine's task.
            "_vmajor" => 2.9,
            "_vminor" => 0.0,
            "_task" => 0.0,
            "_remap_level" => 0.0,
            "_feed_override" | "_speed_override" | "_feed_hold" => 1.0,
            "_adaptive_feed" => 0.0,
            // kezuri has no tool changer: a tool's pocket is its number
            // (-1: no tool selected).
            "_selected_pocket" => match self.pending_tool {
                0 => -1.0,
                t => f64::from(t),
            },
            "_current_pocket" => f64::from(self.tool),
            "_ijk_absolute_mode" => bool(self.coords.arc_absolute),
            // G7 / G8 and G96 / G97 (a mill: G8 and G97 always).
            "_lathe_diameter_mode" => bool(self.linuxcnc_diameter()),
            "_lathe_radius_mode" => bool(!self.linuxcnc_diameter()),
            "_spindle_css_mode" => bool(self.surface_speed_on()),
            "_spindle_rpm_mode" => bool(!self.surface_speed_on()),
            // kezuri's machine works in mm.
            "_metric_machine" => 1.0,
            _ => match name.strip_prefix("_abs_") {
                Some(axis) => position(self.machine_position(), axis)?,
                None => position(self.program_position(), name.strip_prefix('_')?)?,
            },
        })
    }

    /// Reads LinuxCNC named parameter `#<name>`.
    pub(super) fn read_named(&mut self, name: &str) -> Result<f64, String> {
        if self.settings.dialect != crate::Dialect::LinuxCnc {
            return Err(format!(
                "named parameters (#<{name}>) are LinuxCNC's: read the program in the LinuxCNC dialect"
            ));
        }
        let found = match name.starts_with('_') {
            true => self.predefined(name).or_else(|| self.globals.get(name).copied()),
            false => self.named.get(self.level).and_then(|m| m.get(name)).copied(),
        };
        found.ok_or_else(|| format!("#<{name}> is read before it is set (EXISTS[#<{name}>] tells whether it is)"))
    }

    /// Whether LinuxCNC named parameter `#<name>` is set (`EXISTS`).
    pub(super) fn named_exists(&mut self, name: &str) -> bool {
        self.read_named(name).is_ok()
    }

    /// Sets LinuxCNC named parameter `#<name>`: local to the call level,
    /// global where the name starts with `_`.
    pub(super) fn write_named(&mut self, name: &str, value: Value) -> Result<(), String> {
        if self.settings.dialect != crate::Dialect::LinuxCnc {
            return Err(format!(
                "named parameters (#<{name}>) are LinuxCNC's: read the program in the LinuxCNC dialect"
            ));
        }
        if self.predefined(name).is_some() {
            return Err(format!("#<{name}> is a predefined parameter: a program reads it and cannot set it"));
        }
        let v = value.num();
        if name.starts_with('_') {
            self.globals.insert(name.to_string(), v);
        } else {
            let level = self.level;
            if self.named.len() <= level {
                self.named.resize_with(level + 1, Default::default);
            }
            self.named[level].insert(name.to_string(), v);
        }
        Ok(())
    }

    /// Sets the kept variables to their starting values.
    pub(super) fn load_kept_values(&mut self) {
        let values = std::mem::take(&mut self.settings.macro_variables.values);
        for (&n, &v) in &values {
            // Checked before the run: each is a kept common variable.
            self.write_var(f64::from(n), Value::Num(v)).expect("Settings::check saw every starting value");
        }
        self.settings.macro_variables.values = values;
    }

    /// Notes the first read of each kind of value the machine model gives.
    fn note_model_read(&mut self, n: u32) {
        let what = match n {
            1000..=1035 => "input signal",
            2001..=2400 | 10001..=13999 => "tool offset",
            3001 | 3002 | 3011 | 3012 => "clock",
            5021..=5026 => "machine position",
            5201..=5326 | 7001..=7960 | 14001..=15980 => "work offset",
            _ => return,
        };
        if !self.model_reads.iter().any(|r| r.what == what) && !self.set_by_program.contains(&n) {
            self.model_reads.push(ModelRead { what, variable: n, line: self.at_line });
        }
    }

    fn read_system(&mut self, n: u32) -> Result<f64, String> {
        if super::params::linuxcnc_numbering(self.settings.dialect) && (5001..=5999).contains(&n) {
            return Ok(self.read_linuxcnc(n));
        }
        self.note_model_read(n);
        if let Some(v) = self.read_signal(n) {
            return Ok(v);
        }
        Ok(match n {
            2001..=2200 => self.settings.tool_lengths.get(&(n - 2000)).copied().unwrap_or(0.0),
            2201..=2400 => self.settings.tool_radii.get(&(n - 2200)).copied().unwrap_or(0.0),
            10001..=10999 => self.length_wear.get(&(n - 10000)).copied().unwrap_or(0.0),
            11001..=11999 => self.settings.tool_lengths.get(&(n - 11000)).copied().unwrap_or(0.0),
            12001..=12999 => self.radius_wear.get(&(n - 12000)).copied().unwrap_or(0.0),
            13001..=13999 => self.settings.tool_radii.get(&(n - 13000)).copied().unwrap_or(0.0),
            3000 => 0.0,
            3001 => self.clock.read_ms(),
            3002 => self.clock.read_ms() / 3_600_000.0,
            // The date and time of day: the run's clock from midnight of
            // 2000-01-01 (a fixed day, so runs repeat).
            3011 => 20_000_101.0,
            3012 => {
                let s = (self.clock.read_ms() / 1000.0).floor() as u64 % 86_400;
                (s / 3600 * 10_000 + s / 60 % 60 * 100 + s % 60) as f64
            }
            // Single block and feed hold switches, parts counts: kept, no effect.
            3003 | 3004 | 3901 | 3902 => self.panel.get(&n).copied().unwrap_or(0.0),
            4001..=4022 => self
                .lathe_group(n - 4000)
                .or_else(|| self.coords_group(n - 4000))
                .or_else(|| self.modal.group_value(n - 4000))
                .unwrap_or(0.0),
            4102 => self.last.b,
            4107 => self.last.d,
            4108 => self.last.e,
            4109 => self.feed_word,
            4111 => self.last.h,
            4113 => self.last.m,
            4114 => self.last.n,
            4115 => self.last.o,
            4119 => self.speed,
            4120 => self.pending_tool as f64,
            // The P of G54.1 P in force (0 under G54 … G59).
            4130 => (self.modal.work_offset + 1).saturating_sub(EXTRA_OFFSETS) as f64,
            5001..=5006 => axis(self.work_position(), n - 5001).unwrap_or(0.0),
            5021..=5026 => axis(self.machine_position(), n - 5021).unwrap_or(0.0),
            // As on a Fanuc control, #5001… is the programmed end point (no
            // tool length offset); #5021…, #5041… and #5061… include it: they
            // are where the spindle's reference point is, and #5081… is the
            // offset itself (so #5063-#5083 is the tool tip).
            5041..=5046 => {
                axis(self.work_position(), n - 5041).unwrap_or(0.0) + if n == 5043 { self.length_offset() } else { 0.0 }
            }
            5061..=5066 => axis(self.skip_position, n - 5061).unwrap_or(0.0),
            5081..=5086 => {
                if n == 5083 {
                    self.length_offset()
                } else {
                    0.0
                }
            }
            // #7001… G54.1 P1 … (Fanuc), #14001… G154 P1 … (Haas): 20 a number.
            7001..=7960 | 14001..=15980 => {
                let (index, axis_index) = extra_offset(n);
                axis(self.work_offsets[index], axis_index)
                    .ok_or_else(|| format!("#{n} is not a work offset variable"))?
            }
            // #5201… external offset, #5221… G54, …, #5321… G59 (six axes each).
            5201..=5326 => {
                let (frame, axis_index) = ((n - 5201) / 20, (n - 5201) % 20);
                let offset = if frame == 0 { self.external_offset } else { self.work_offsets[frame as usize - 1] };
                axis(offset, axis_index).ok_or_else(|| format!("#{n} is not a work offset variable"))?
            }
            _ => return Err(format!("system variable #{n} is not supported")),
        })
    }

    fn write_system(&mut self, n: u32, value: Value) -> Result<(), String> {
        if super::params::linuxcnc_numbering(self.settings.dialect) && (5001..=5999).contains(&n) {
            return self.write_linuxcnc(n, value);
        }
        if let Some(done) = self.write_signal(n, value) {
            return done;
        }
        let v = value.num();
        // Read back later, it is the program's own value.
        self.set_by_program.insert(n);
        if let Some(text) = offset_as_g10(n, v) {
            // The control must hold the offset the program set: kept as the
            // G10 that sets it (a written program may have no macros).
            self.keep(text, 0, true, self.at_line);
        }
        match n {
            2001..=2200 => {
                self.settings.tool_lengths.insert(n - 2000, v);
            }
            2201..=2400 => {
                self.settings.tool_radii.insert(n - 2200, v);
            }
            10001..=10999 => {
                self.length_wear.insert(n - 10000, v);
            }
            11001..=11999 => {
                self.settings.tool_lengths.insert(n - 11000, v);
            }
            12001..=12999 => {
                self.radius_wear.insert(n - 12000, v);
            }
            13001..=13999 => {
                self.settings.tool_radii.insert(n - 13000, v);
            }
            3001 => self.clock.set_ms(v),
            3002 => self.clock.set_ms(v * 3_600_000.0),
            3003 | 3004 | 3901 | 3902 => {
                self.panel.insert(n, v);
            }
            7001..=7960 | 14001..=15980 if extra_offset(n).1 < 6 => {
                let (index, axis_index) = extra_offset(n);
                let mut a = self.work_offsets[index].to_array();
                a[axis_index as usize] = v;
                self.work_offsets[index] = Axes::from_array(a);
            }
            5201..=5326 if (n - 5201) % 20 < 6 => {
                let (frame, axis_index) = ((n - 5201) / 20, ((n - 5201) % 20) as usize);
                let offset =
                    if frame == 0 { &mut self.external_offset } else { &mut self.work_offsets[frame as usize - 1] };
                let mut a = offset.to_array();
                a[axis_index] = v;
                *offset = Axes::from_array(a);
            }
            _ => return Err(format!("system variable #{n} cannot be written")),
        }
        Ok(())
    }
}

/// The control's clocks #3001 (ms) and #3002 (hours).
///
/// By default each read of the clock advances it by one 16 ms tick, so runs
/// are deterministic. With a seed, each read advances it by an independent,
/// reproducible pseudo-random 1–1000 ms: an idealisation of a real control,
/// where the value read depends on the time a block takes and on the 16 ms
/// tick. (On a control whose clock moves in 16 ms steps the last digit of
/// `#3001` is always even, so the texture paper's `#3001 MOD 10` would never give an
/// odd digit there.) `#3001` wraps at 65,536 ms as on the control.
#[derive(Clone, Debug)]
pub(super) struct Clock {
    ms: f64,
    rng: Option<SplitMix64>,
}

impl Clock {
    pub(super) fn new(seed: Option<u64>) -> Clock {
        Clock { ms: 0.0, rng: seed.map(|s| SplitMix64::new(s ^ 0x9E37_79B9_7F4A_7C15)) }
    }

    fn read_ms(&mut self) -> f64 {
        let step = match &mut self.rng {
            None => 16.0,
            Some(rng) => 1.0 + (rng.next_u64() % 1000) as f64,
        };
        self.ms = (self.ms + step) % 65_536.0;
        self.ms
    }

    fn set_ms(&mut self, v: f64) {
        self.ms = v.rem_euclid(65_536.0);
    }
}
