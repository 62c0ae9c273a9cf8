//! Where programs end: a program unit closed, and the ends written as
//! numbers (`M02`, `M30`, `M99`).

use crate::ast::{Block, Program, ProgramUnit, Word, WordValue};

/// What ends of a program `block` gives: whether one ends it (an `M30` or
/// `M02` word), and the first `M02`, `M30` or `M99` (2, 30 or 99), each
/// written as a number (`M#1` is not looked at before the run).
#[inline]
pub(super) fn program_ends(program: &Program, block: &Block) -> (bool, Option<u32>) {
    let mut ends = (false, None);
    for code in program.words(block).iter().filter_map(end_code) {
        ends.0 |= code != 99;
        ends.1 = ends.1.or(Some(code));
    }
    ends
}

/// 2, 30 or 99 where `w` is `M02`, `M30` or `M99` written as a number
/// (`M#1` is not looked at before the run).
#[inline]
fn end_code(w: &Word) -> Option<u32> {
    match w.value() {
        WordValue::Number { value, .. } if w.letter == b'M' && [2.0, 30.0, 99.0].contains(&value) => Some(value as u32),
        _ => None,
    }
}

/// Closes `unit` at the last block parsed and adds it to `program`, unless
/// it has no number and only empty blocks (`all_empty`).
pub(super) fn finish_unit(program: &mut Program, unit: &mut ProgramUnit, all_empty: bool) {
    unit.blocks.end = program.blocks.len() as u32;
    if unit.number.is_some() || !all_empty {
        program.units.push(unit.clone());
    }
}
