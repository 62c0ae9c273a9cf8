//! Which tool cuts each move, and what each tool removed.
//!
//! A program changes tools (`T2 M06`); every move carries the tool in the
//! spindle ([`kezuri_geom::Move::tool`]) and is cut with that tool's
//! shape. A move made before the program loads any tool (tool 0: the
//! approach before the first `M06`) is cut with the first tool the program
//! loads — the tool it expects in the spindle, so a rapid into the stock
//! there is still found; a move after `T0 M06` (an empty spindle) keeps the
//! last tool, as a Z-map cannot tell a spindle nose from a cutter.
//!
//! Tools change between segments at no cost: each segment carries the
//! index of its tool's shape. What a tool removed is counted exactly on the
//! cells: for each run of one tool's segments over a band of rows, the
//! cells the run can reach are kept before it and compared after it, the
//! volume being Σ (before − after) × cell area, and each lowered cell
//! remembers the tool that lowered it last ([`SimReport::cut_by`]).

use std::ops::Range;

use kezuri_geom::Toolpath;

use super::stock::round_nm;
use super::sweep::Shape;
use super::Tool;
use crate::error::{Error, ErrorKind};

/// Which tool cuts each move.
#[derive(Clone, Copy, Debug)]
pub enum Tooling<'a> {
    /// One tool for every move, whatever tools the program loads.
    One(&'a Tool),
    /// The tool of each tool number (a machine's tool table): a move of a
    /// tool the table lacks is an error ([`ErrorKind::NoTool`]).
    Table(&'a [(u32, Tool)]),
}

/// What one tool of the program did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolCut {
    /// Its tool number (`T`); 0 for a program that loads no tool.
    pub number: u32,
    /// Moves it made (dwells left out), placed or not.
    pub moves: usize,
    /// Straight segments it cut (arcs split into chords).
    pub segments: usize,
    /// Material it removed, mm³: Σ over the cells of (height before its
    /// moves − after) × cell area.
    pub volume: f64,
}

/// Most tools one simulation tells apart.
pub const MAX_TOOLS: usize = 254;

/// [`super::SimReport::cut_by`] of a cell no move lowered.
pub const UNCUT: u8 = u8::MAX;

/// The number of the tool that cuts each move of `path` (see the module
/// notes for moves before the first tool change).
pub fn cutting_tools(path: &Toolpath) -> impl Iterator<Item = u32> + '_ {
    path.moves.iter().scan(super::segments::first_tool(path), |current, m| {
        if m.tool != 0 {
            *current = m.tool;
        }
        Some(*current)
    })
}

/// The tools met so far, in the order they first cut: their numbers and
/// shapes by slot.
pub(super) struct Slots<'a> {
    tooling: Tooling<'a>,
    numbers: Vec<u32>,
    pub shapes: Vec<Shape<'a>>,
    /// Whether each is a drill (`drill:D,ANGLE`): it cuts along its axis only.
    pub drills: Vec<bool>,
}

impl<'a> Slots<'a> {
    pub fn new(tooling: Tooling<'a>) -> Slots<'a> {
        Slots { tooling, numbers: Vec::new(), shapes: Vec::new(), drills: Vec::new() }
    }

    /// The first slot, made for the moves before the first tool change
    /// (as tool 0), named for the first tool loaded.
    pub fn name_first(&mut self, number: u32) {
        if let Some(first) = self.numbers.first_mut() {
            *first = number;
        }
    }

    /// The slot of tool `number` (met at source line `line`), added at the
    /// end when new.
    pub fn slot(&mut self, number: u32, line: u32) -> Result<u8, Error> {
        if let Some(k) = self.numbers.iter().position(|&n| n == number) {
            return Ok(k as u8);
        }
        let tool = match self.tooling {
            Tooling::One(tool) => tool,
            Tooling::Table(table) => {
                &table
                    .iter()
                    .find(|(n, _)| *n == number)
                    .ok_or_else(|| {
                        Error::new(
                            ErrorKind::NoTool,
                            format!("T{number} (first moving at line {line}) has no shape to cut with"),
                        )
                    })?
                    .1
            }
        };
        if self.numbers.len() == MAX_TOOLS {
            return Err(Error::new(ErrorKind::TooManyTools, format!("the program uses more than {MAX_TOOLS} tools")));
        }
        self.numbers.push(number);
        self.shapes.push(tool.shape());
        self.drills.push(tool.is_drill());
        Ok((self.numbers.len() - 1) as u8)
    }
}

/// The cells of a band that one run of a tool's segments can lower:
/// `rows` (of the band) × `cols`.
pub(super) struct Window {
    pub rows: Range<usize>,
    pub cols: Range<usize>,
}

impl Window {
    /// The box of the cells of the band of grid rows `band` that segments
    /// reaching grid rows × columns can lower, with a column to spare on
    /// each side (of `nx`).
    pub fn around<'a>(
        reached: impl Iterator<Item = (Range<usize>, &'a Range<usize>)>,
        band: Range<usize>,
        nx: usize,
    ) -> Window {
        let (mut j0, mut j1, mut i0, mut i1) = (usize::MAX, 0, usize::MAX, 0);
        for (rows, cols) in reached {
            j0 = j0.min(rows.start.max(band.start));
            j1 = j1.max(rows.end.min(band.end));
            i0 = i0.min(cols.start.saturating_sub(1));
            i1 = i1.max((cols.end + 1).min(nx));
        }
        if j0 >= j1 || i0 >= i1 {
            return Window { rows: 0..0, cols: 0..0 };
        }
        Window { rows: j0 - band.start..j1 - band.start, cols: i0..i1 }
    }
}

/// A band's account of what each tool removed.
pub(super) struct Ledger {
    /// Σ (before − after) per slot, whole nanometres of height (times the
    /// cell area: mm³ · 10⁶), summed exactly whatever the order.
    pub removed: Vec<i64>,
    /// The window's heights before the run, nm.
    before: Vec<i32>,
}

impl Ledger {
    pub fn new(tools: usize) -> Ledger {
        Ledger { removed: vec![0; tools], before: Vec::new() }
    }

    /// Keeps the window's heights (mm) before a run, to the nanometre.
    pub fn open(&mut self, cells: &[f64], nx: usize, w: &Window) {
        self.before.clear();
        for j in w.rows.clone() {
            self.before.extend(cells[j * nx + w.cols.start..j * nx + w.cols.end].iter().map(|&z| round_nm(z)));
        }
    }

    /// Counts what the run of tool `slot` removed from the window, and
    /// marks the cells it lowered (by a nanometre or more, as the grid
    /// keeps them) as its own.
    pub fn close(&mut self, cells: &[f64], cut_by: &mut [u8], nx: usize, w: &Window, slot: u8) {
        let width = w.cols.len();
        let mut removed = 0i64;
        for (r, j) in w.rows.clone().enumerate() {
            let at = j * nx + w.cols.start;
            let before = &self.before[r * width..(r + 1) * width];
            for ((&b, &a), owner) in before.iter().zip(&cells[at..at + width]).zip(&mut cut_by[at..at + width]) {
                let a = round_nm(a);
                if a < b {
                    removed += b as i64 - a as i64;
                    *owner = slot;
                }
            }
        }
        self.removed[slot as usize] += removed;
    }
}
