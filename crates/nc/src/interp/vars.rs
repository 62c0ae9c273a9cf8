//! Macro variables: locals per call level, commons, and system variables.

use super::value::Value;
use super::State;
use kezuri_geom::{Axes, SplitMix64};

/// Local variables #1–#33 of one call level.
pub type Locals = [Value; 33];

/// Where an assignment or read lands.
pub(super) enum Slot {
    Vacant,
    Local(usize),
    Common(usize),
    Persistent(usize),
    System(u32),
}

pub(super) fn slot(number: f64) -> Result<Slot, String> {
    if number.fract() != 0.0 || !(0.0..=99_999.0).contains(&number) {
        return Err(format!("#{number} is not a variable number (use whole numbers from 0)"));
    }
    let n = number as u32;
    Ok(match n {
        0 => Slot::Vacant,
        1..=33 => Slot::Local(n as usize - 1),
        100..=199 => Slot::Common(n as usize - 100),
        500..=999 => Slot::Persistent(n as usize - 500),
        _ => Slot::System(n),
    })
}

fn axis(a: Axes, i: u32) -> Option<f64> {
    a.to_array().get(i as usize).copied()
}

impl State {
    /// Reads variable `#number`.
    pub(super) fn read_var(&mut self, number: f64) -> Result<Value, String> {
        Ok(match slot(number)? {
            Slot::Vacant => Value::Vacant,
            Slot::Local(i) => self.locals[self.level][i],
            Slot::Common(i) => self.common[i],
            Slot::Persistent(i) => self.persistent[i],
            Slot::System(n) => Value::Num(self.read_system(n)?),
        })
    }

    /// Writes variable `#number`.
    pub(super) fn write_var(&mut self, number: f64, value: Value) -> Result<(), String> {
        match slot(number)? {
            Slot::Vacant => return Err("#0 is always vacant and cannot be assigned".into()),
            Slot::Local(i) => self.locals[self.level][i] = value,
            Slot::Common(i) => self.common[i] = value,
            Slot::Persistent(i) => self.persistent[i] = value,
            Slot::System(n) => self.write_system(n, value)?,
        }
        Ok(())
    }

    fn read_system(&mut self, n: u32) -> Result<f64, String> {
        let work = self.work_position();
        Ok(match n {
            2001..=2200 => self.settings.tool_lengths.get(&(n - 2000)).copied().unwrap_or(0.0),
            2201..=2400 => self.settings.tool_radii.get(&(n - 2200)).copied().unwrap_or(0.0),
            3000 => 0.0,
            3001 => self.clock.read_ms(),
            3002 => self.clock.read_ms() / 3_600_000.0,
            4001..=4022 => self.modal.group_value(n - 4000).unwrap_or(0.0),
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
            5001..=5006 => axis(work, n - 5001).unwrap_or(0.0),
            5021..=5026 => axis(self.machine_position(), n - 5021).unwrap_or(0.0),
            // As on a Fanuc control, #5001… is the programmed end point (no
            // tool length offset); #5021…, #5041… and #5061… include it: they
            // are where the spindle's reference point is, and #5081… is the
            // offset itself (so #5063-#5083 is the tool tip).
            5041..=5046 => axis(work, n - 5041).unwrap_or(0.0) + if n == 5043 { self.length_offset() } else { 0.0 },
            5061..=5066 => axis(self.skip_position, n - 5061).unwrap_or(0.0),
            5081..=5086 => {
                if n == 5083 {
                    self.length_offset()
                } else {
                    0.0
                }
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
        let v = value.num();
        match n {
            2001..=2200 => {
                self.settings.tool_lengths.insert(n - 2000, v);
            }
            2201..=2400 => {
                self.settings.tool_radii.insert(n - 2200, v);
            }
            3001 => self.clock.set_ms(v),
            3002 => self.clock.set_ms(v * 3_600_000.0),
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
/// `#3001` is always even, so seed 004's `#3001 MOD 10` would never give an
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
