//! The index of a program unit, built once when it first runs: where each
//! sequence number is, and each WHILE/DO block's END (or why it has none).

use std::collections::HashMap;

use crate::ast::{Program, Statement};

/// Sequence numbers and loop pairs of one program unit.
// (A program read in pages skips its dropped pages here.)
#[derive(Default)]
pub(super) struct UnitIndex {
    pub(super) labels: HashMap<u32, u32>,
    /// For each WHILE/DO block, its END; for each END, its WHILE/DO; or why
    /// it has none.
    pub(super) loops: HashMap<u32, Result<u32, String>>,
}

/// The index of `unit`; for a program read in pages its loops alone (a
/// dropped page holds no loop statement; its numbers are searched for).
pub(super) fn build_index(program: &Program, unit: usize) -> UnitIndex {
    let mut index = UnitIndex::default();
    let mut open: Vec<(u8, u32)> = Vec::new();
    let labels = !program.paging();
    for i in program.units[unit].blocks.clone() {
        let Some(block) = program.blocks.get(i as usize) else { continue };
        if let Some(n) = block.number.filter(|_| labels) {
            index.labels.entry(n).or_insert(i);
        }
        match block.statement {
            Statement::While { label, .. } | Statement::Do { label } => open.push((label, i)),
            Statement::End { label } => match open.last() {
                Some(&(l, start)) if l == label => {
                    open.pop();
                    index.loops.insert(start, Ok(i));
                    index.loops.insert(i, Ok(start));
                }
                Some(&(l, _)) => {
                    let crossing =
                        format!("END{label} comes before END{l}: the DO{label} and DO{l} loops cross; loops must nest");
                    if let Some(&(_, start)) = open.iter().rev().find(|(o, _)| *o == label) {
                        index.loops.insert(start, Err(crossing.clone()));
                    }
                    index.loops.insert(i, Err(crossing));
                }
                None => {
                    index.loops.insert(i, Err(format!("END{label} has no WHILE … DO{label} before it")));
                }
            },
            _ => {}
        }
    }
    for (label, start) in open {
        index
            .loops
            .entry(start)
            .or_insert_with(|| Err(format!("DO{label} has no END{label} after it in this program")));
    }
    index
}
