//! Where programs end: a program unit closed, and the ends written as
//! numbers (`M02`, `M30`, `M99`).

use crate::ast::{Block, Program, ProgramUnit, Word, WordValue};

/// Whether `block` ends the program: an `M30` or `M02` word written as a
/// number (`M#1` is not looked at before the run).
#[inline]
pub(super) fn ends_program(program: &Program, block: &Block) -> bool {
    program.words(block).iter().any(|w| matches!(end_code(w), Some(2 | 30)))
}

/// The program end `block` gives: 2, 30 or 99 for its first `M02`, `M30`
/// or `M99` word.
#[inline]
pub(super) fn program_end(program: &Program, block: &Block) -> Option<u32> {
    program.words(block).iter().find_map(end_code)
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
