//! Machine signals as macro variables: the interface inputs #1000–#1035
//! a macro reads (a door switch, a part-present sensor) and the outputs
//! #1100–#1135 it sets (a lamp, a clamp). See `docs/macro-variables.md`.
//!
//! Bits #1000–#1031 read 0 or 1; #1032 reads those 32 bits as one number,
//! bit i being #[1000+i]; #1033–#1035 are 32-bit words with no bit
//! variables. Outputs mirror this: #1100–#1131 bits, #1132 the same 32 bits
//! (writing it sets them all), #1133–#1135 words. A 32-bit group reads as a
//! signed number: bit 31 set gives a negative value.

use std::collections::BTreeMap;
use std::ops::RangeInclusive;

use super::value::Value;
use super::State;
use crate::number::number;

/// Input bits, one variable each.
pub(super) const INPUT_BITS: RangeInclusive<u32> = 1000..=1031;
/// #1032 (the bits above as one number) and the words #1033–#1035.
pub(super) const INPUT_GROUPS: RangeInclusive<u32> = 1032..=1035;
/// Output bits, one variable each.
pub(super) const OUTPUT_BITS: RangeInclusive<u32> = 1100..=1131;
/// #1132 (the bits above as one number) and the words #1133–#1135.
pub(super) const OUTPUT_GROUPS: RangeInclusive<u32> = 1132..=1135;

/// Checks input signal values as a machine file gives them: bits #1000–#1031
/// are 0 or 1, words #1033–#1035 whole 32-bit numbers; #1032 is made of the
/// bits and cannot be set itself.
pub fn check_inputs(inputs: &BTreeMap<u32, f64>) -> Result<(), String> {
    for (&n, &v) in inputs {
        match n {
            _ if INPUT_BITS.contains(&n) => {
                if v != 0.0 && v != 1.0 {
                    return Err(format!("input #{n} is one bit: 0 or 1, not {v}"));
                }
            }
            1032 => return Err("input #1032 is made of the bits #1000–#1031: set those instead".into()),
            _ if INPUT_GROUPS.contains(&n) => {
                word(v).map_err(|m| format!("input #{n}: {m}"))?;
            }
            _ => return Err(format!("#{n} is not an input signal (#1000–#1031, #1033–#1035)")),
        }
    }
    Ok(())
}

/// A value as a 32-bit word: whole, from -2^31 to 2^32 - 1 (above 2^31 - 1
/// it is the same bits as a negative number).
fn word(v: f64) -> Result<u32, String> {
    if v.fract() != 0.0 || !(-2_147_483_648.0..=4_294_967_295.0).contains(&v) {
        return Err(format!("a 32-bit signal group takes a whole number from -2147483648 to 4294967295, not {v}"));
    }
    Ok(if v < 0.0 { (v as i64 + (1i64 << 32)) as u32 } else { v as u32 })
}

/// A 32-bit word as a macro reads it: signed.
fn signed(bits: u32) -> f64 {
    f64::from(bits as i32)
}

/// The output signals a run has set; all start at 0.
#[derive(Clone, Debug, Default)]
pub(super) struct Outputs {
    /// #1132 (bit i is #[1100+i]), #1133, #1134, #1135.
    groups: [u32; 4],
}

impl State {
    /// The value of signal variable `n`, or `None` when `n` is no signal.
    pub(super) fn read_signal(&mut self, n: u32) -> Option<f64> {
        if INPUT_BITS.contains(&n) {
            let set = self.settings.input_signals.get(&n).copied();
            if set.is_none() {
                self.unset_input(
                    n,
                    format!("input signal #{n} is not in the machine file ([signals] inputs): it reads 0"),
                );
            }
            return Some(set.unwrap_or(0.0));
        }
        if n == 1032 {
            let bits = INPUT_BITS.filter(|b| self.settings.input_signals.get(b) == Some(&1.0));
            let word = bits.fold(0u32, |w, b| w | 1 << (b - 1000));
            if self.settings.input_signals.range(INPUT_BITS).next().is_none() {
                self.unset_input(n, "input signals #1000–#1031 are not in the machine file: #1032 reads 0".into());
            }
            return Some(signed(word));
        }
        if INPUT_GROUPS.contains(&n) {
            let set = self.settings.input_signals.get(&n).copied();
            if set.is_none() {
                self.unset_input(
                    n,
                    format!("input signal #{n} is not in the machine file ([signals] inputs): it reads 0"),
                );
            }
            // Checked by `check_inputs` before the run.
            return Some(set.and_then(|v| word(v).ok()).map_or(0.0, signed));
        }
        if OUTPUT_BITS.contains(&n) {
            return Some(f64::from(self.outputs.groups[0] >> (n - 1100) & 1));
        }
        if OUTPUT_GROUPS.contains(&n) {
            return Some(signed(self.outputs.groups[(n - 1132) as usize]));
        }
        None
    }

    /// One warning for each input the machine file does not set, at its
    /// first read.
    fn unset_input(&mut self, n: u32, message: String) {
        if self.unset_inputs_warned.insert(n) {
            self.warn("input-signal", self.at, message);
        }
    }

    /// Writes signal variable `n`; `None` when `n` is no signal. Each write
    /// to an output is kept for the program writer (`#1100=1`).
    pub(super) fn write_signal(&mut self, n: u32, value: Value) -> Option<Result<(), String>> {
        if INPUT_BITS.contains(&n) || INPUT_GROUPS.contains(&n) {
            return Some(Err(format!("#{n} is an input signal: a program can read it, not set it")));
        }
        let v = value.num();
        if OUTPUT_BITS.contains(&n) {
            if v != 0.0 && v != 1.0 {
                return Some(Err(format!("output #{n} is one bit: set it to 0 or 1, not {v}")));
            }
            let mask = 1u32 << (n - 1100);
            let group = &mut self.outputs.groups[0];
            *group = if v == 1.0 { *group | mask } else { *group & !mask };
        } else if OUTPUT_GROUPS.contains(&n) {
            match word(v) {
                Ok(bits) => self.outputs.groups[(n - 1132) as usize] = bits,
                Err(m) => return Some(Err(format!("#{n}: {m}"))),
            }
        } else {
            return None;
        }
        // The machine must set it between the same two moves.
        let text = format!("#{n}={}", number(v, 6).trim_end_matches('.'));
        self.keep(text, 0, false, self.at_line);
        Some(Ok(()))
    }
}
