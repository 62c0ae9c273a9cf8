//! The multiple repetitive cycles that work from a finishing shape: `G70`
//! finishing, `G71` stock removal in turning, `G72` in facing, `G73`
//! pattern repeating (FANUC Series 0i-TF Plus Operator's Manual
//! (B-64604EN), lathe system, "Multiple repetitive cycle"; in G code
//! system C they are G72–G75), in Fanuc's two-block forms
//!
//! ```text
//! G71 U(Δd) R(e);            G73 U(Δi) W(Δk) R(d);
//! G71 P(ns) Q(nf) U(Δu) W(Δw) F S T;   G73 P Q U W F;   G70 P Q;
//! ```
//!
//! and Haas's one-block forms (Haas Lathe Operator's Manual, G70–G73):
//! `G71 P Q U W D I K F R1`, `G72` the same, `G73 P Q U W I K D F`,
//! `G70 P Q`. The shape is the blocks N(ns) … N(nf) of the program: they
//! are read as the control reads them (X a diameter, U and W increments,
//! chamfers and corners), from the cycle's start point, without moving the
//! tool; `G70` runs them as they stand, their F, S and T in force. After
//! the cycle the tool is back at the start point, and where the shape's
//! blocks follow the cycle block the program goes on after N(nf).

use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane};

use super::super::block::Action;
use super::super::modal::{ContourCycle, GCode};
use super::super::words::Words;
use super::super::State;
use super::profile::{Contour, Piece, P};
use super::roughing::{self, cut_count, Rough, Step};
use super::words::LatheCodes;
use super::{GCodeSystem, XMode};
use crate::ast::{Program, Statement, Word, WordValue};
use crate::source::{Diagnostic, Span};

/// The escape after each cut (mm) where the program gives none: Fanuc's
/// parameter 5133, Haas's Setting 73, neither of which the machine file
/// holds.
const DEFAULT_ESCAPE: f64 = 1.0;

/// Most cuts one cycle makes: a larger count is a mistyped depth.
const MAX_CUTS: f64 = 1_000_000.0;

/// What the first blocks of `G71`/`G72` and `G73` leave for the next
/// (modal, as the manual says: "not changed until another value is
/// designated").
#[derive(Clone, Copy, Debug, Default)]
pub(in crate::interp) struct Memory {
    /// Δd and where it was given.
    depth: Option<(f64, Span)>,
    /// e.
    escape: Option<f64>,
    /// G73's Δi (X, radius), Δk (Z) and d (the passes).
    relief: Option<(f64, f64)>,
    passes: Option<(f64, Span)>,
}

/// The shape read from its blocks.
struct Shape {
    /// The moves the blocks make, from the start point.
    moves: Vec<Move>,
    /// How many of them the first block (ns) makes.
    approach: usize,
    /// The block index of each move.
    blocks: Vec<u32>,
    /// The first block starts with G00 (else G01).
    rapid: bool,
    /// Block indices of N(ns) and N(nf).
    first: u32,
    last: u32,
}

/// A frame of the cycle: `a` along the cut and `d` into the stock, from the
/// start point; `m` maps (z, x) offsets to (a, d).
struct Frame {
    origin: Axes,
    m: [[f64; 2]; 2],
}

impl Frame {
    fn to(&self, x: f64, z: f64) -> P {
        let (dz, dx) = (z - self.origin.z, x - self.origin.x);
        [self.m[0][0] * dz + self.m[0][1] * dx, self.m[1][0] * dz + self.m[1][1] * dx]
    }

    fn from(&self, p: P) -> (f64, f64) {
        let dz = self.m[0][0] * p[0] + self.m[1][0] * p[1];
        let dx = self.m[0][1] * p[0] + self.m[1][1] * p[1];
        (self.origin.x + dx, self.origin.z + dz)
    }

    /// Whether the frame turns arcs the other way.
    fn flips(&self) -> bool {
        self.m[0][0] * self.m[1][1] - self.m[0][1] * self.m[1][0] < 0.0
    }
}

impl State {
    /// The contour cycle a lathe's G code names in its G code system
    /// (`None`: not one of them, or not a Fanuc or Haas lathe).
    fn contour_code(&self, tenths: u32) -> Option<ContourCycle> {
        match self.decode_g(tenths)? {
            GCode::Contour(c) => Some(c),
            _ => None,
        }
    }

    /// Whether `letter` is a count or a sequence number, not a length, in
    /// the block of `words` (its G codes `codes`): P and Q of a contour
    /// cycle, G73's R (the divisions) and Haas's R1 (type II) of G71 and G72.
    pub(in crate::interp) fn contour_count(&self, letter: u8, codes: &LatheCodes, words: &[Word]) -> bool {
        if !matches!(letter, b'P' | b'Q' | b'R') || self.turning.is_none() {
            return false;
        }
        let haas = self.settings.dialect.is_haas();
        match codes.contour {
            None => false,
            Some(ContourCycle::Pattern) if letter == b'R' => !words.iter().any(|w| w.letter == b'P'),
            Some(ContourCycle::Turning | ContourCycle::Facing) if letter == b'R' => haas,
            Some(_) => letter != b'R',
        }
    }

    /// A block with `G70`–`G73` (lathe): the whole cycle. Returns the block
    /// the program goes on at where it is not the next (after the shape),
    /// and the first of the moves that are the cycle's own (not those of
    /// the shape's blocks that `G70` runs as they stand).
    #[inline(never)]
    pub(in crate::interp) fn contour_cycle(
        &mut self,
        program: &Program,
        pc: u32,
        cycle: ContourCycle,
        w: &Words,
        gspan: Span,
        line: u32,
    ) -> Result<(Option<u32>, usize), Diagnostic> {
        let name = self.contour_name(cycle);
        let haas = self.settings.dialect.is_haas();
        let at = |l: u8| if w.has(l) { w.span(l) } else { gspan };
        if !(w.has(b'P') && w.has(b'Q')) {
            if haas || cycle == ContourCycle::Finishing || w.has(b'P') || w.has(b'Q') {
                let form = match cycle {
                    ContourCycle::Finishing => "P(first block) Q(last block)",
                    ContourCycle::Pattern if haas => "P Q I K D(passes) U W F",
                    _ if haas => "P Q D(depth of cut) U W F",
                    _ => "P(first block) Q(last block) U W F",
                };
                return Err(Diagnostic::error(
                    at(if w.has(b'P') { b'Q' } else { b'P' }),
                    format!("{name} needs P and Q, the sequence numbers of the shape's first and last blocks: {name} {form} (alarm PS0061: P or Q not given)"),
                ));
            }
            return self.first_block(cycle, w, name).map(|()| (None, self.toolpath.moves.len()));
        }
        let shape = self.read_shape(program, pc, w, name)?;
        let start = self.tip;
        let mut own = self.toolpath.moves.len();
        if cycle == ContourCycle::Finishing {
            self.finish(program, &shape)?;
            own = self.toolpath.moves.len();
            self.comp_cycle_return(|s| s.push_move(MoveKind::Rapid, start, 0.0, AxisSet::NONE.with(0).with(2), line));
        } else {
            let on = self.compensated_shape(program, &shape)?;
            let rough = on.as_ref().unwrap_or(&shape);
            let steps = match cycle {
                ContourCycle::Pattern => self.pattern_steps(program, rough, w, gspan, name, haas)?,
                _ => self.rough_steps(program, rough, cycle, w, gspan, name, haas)?,
            };
            // With compensation in force the cuts are the imaginary tip's
            // already: they are made with the offset cancelled, from the
            // start point and back to it; the next move starts it up again.
            let mut made = Ok(());
            self.comp_cycle_return(|s| made = s.put_steps(&steps.0, &steps.1, gspan, line));
            made?;
        }
        // The shape's blocks right after the cycle are its, not the program's.
        let next =
            (pc + 1..shape.first + 1).find(|&k| !matches!(program.blocks[k as usize].statement, Statement::Empty));
        Ok(((next == Some(shape.first)).then_some(shape.last + 1), own))
    }

    fn contour_name(&self, cycle: ContourCycle) -> &'static str {
        let c = self.turning.as_ref().is_some_and(|t| t.system == GCodeSystem::C);
        match (cycle, c) {
            (ContourCycle::Finishing, false) => "G70",
            (ContourCycle::Turning, false) => "G71",
            (ContourCycle::Facing, false) => "G72",
            (ContourCycle::Pattern, false) => "G73",
            (ContourCycle::Finishing, true) => "G72",
            (ContourCycle::Turning, true) => "G73",
            (ContourCycle::Facing, true) => "G74",
            (ContourCycle::Pattern, true) => "G75",
        }
    }

    /// `G71 U(Δd) R(e)`, `G72 W(Δd) R(e)`, `G73 U(Δi) W(Δk) R(d)`: kept
    /// for the cycle's second block.
    fn first_block(&mut self, cycle: ContourCycle, w: &Words, name: &str) -> Result<(), Diagnostic> {
        let depth_letter = if cycle == ContourCycle::Facing { b'W' } else { b'U' };
        match cycle {
            ContourCycle::Pattern => {
                if w.has(b'U') || w.has(b'W') {
                    let (i, k) = self.contour.relief.unwrap_or((0.0, 0.0));
                    let u = w.get(b'U').map_or(i, |u| self.mm(u));
                    let k = w.get(b'W').map_or(k, |k| self.mm(k));
                    self.contour.relief = Some((u, k));
                }
                if let Some(d) = w.get(b'R') {
                    self.contour.passes = Some((d, w.span(b'R')));
                }
            }
            _ => {
                if let Some(d) = w.get(depth_letter) {
                    if d <= 0.0 {
                        return Err(Diagnostic::error(
                            w.span(depth_letter),
                            format!("{name}'s depth of cut {}{d} must be greater than 0 (alarm PS0062: the depth of cut is zero or negative)", depth_letter as char),
                        ));
                    }
                    self.contour.depth = Some((self.mm(d), w.span(depth_letter)));
                }
                if let Some(e) = w.get(b'R') {
                    self.contour.escape = Some(self.mm(e).abs());
                }
            }
        }
        Ok(())
    }

    /// The blocks N(P) … N(Q) of the cycle's program, read from the tool's
    /// position without moving it.
    fn read_shape(&mut self, program: &Program, pc: u32, w: &Words, name: &str) -> Result<Shape, Diagnostic> {
        let unit = program.units.iter().find(|u| u.blocks.contains(&pc)).map_or(0..0, |u| u.blocks.clone());
        let find = |letter: u8, from: u32| -> Result<u32, Diagnostic> {
            let n = w.get(letter).unwrap_or(-1.0);
            let found = (n.fract() == 0.0 && n >= 0.0)
                .then(|| (from..unit.end).find(|&k| program.blocks[k as usize].number == Some(n as u32)))
                .flatten();
            found.ok_or_else(|| {
                Diagnostic::error(
                    w.span(letter),
                    format!(
                        "{name} {}{n}: no block N{n}{} in this program (alarm PS0063: the block of the sequence number given by {} cannot be found)",
                        letter as char,
                        if letter == b'Q' { " after the first block of the shape" } else { "" },
                        letter as char
                    ),
                )
            })
        };
        let first = find(b'P', unit.start)?;
        let last = find(b'Q', first)?;
        // The first block moves with G00 or G01 (alarm PS0065 otherwise).
        let first_block = &program.blocks[first as usize];
        let motion = program.words(first_block).iter().find_map(|word| match (word.letter, word.value()) {
            (b'G', WordValue::Number { value, .. }) if value == 0.0 || value == 1.0 => Some(value == 0.0),
            _ => None,
        });
        let Some(rapid) = motion else {
            return Err(Diagnostic::error(
                first_block.span,
                format!(
                    "the shape's first block N{} must give G00 or G01 (alarm PS0065: G00 or G01 is not commanded in the block of P)",
                    first_block.number.unwrap_or(0)
                ),
            ));
        };
        let toolpath = std::mem::take(&mut self.toolpath);
        let diagnostics = std::mem::take(&mut self.diagnostics);
        let mut scratch = self.clone();
        self.toolpath = toolpath;
        self.diagnostics = diagnostics;
        let (mut blocks, mut approach) = (Vec::new(), 0);
        for k in first..=last {
            let block = &program.blocks[k as usize];
            let why = match &block.statement {
                Statement::Empty => continue,
                _ if block.delete && self.settings.block_delete => continue,
                Statement::Words { .. } if self.names_contour_cycle(program.words(block)) => "another repetitive cycle",
                Statement::Words { .. } => match scratch.exec_block(program, k)? {
                    Action::Next => "",
                    _ => "a call, return or end of program",
                },
                _ => "a macro statement",
            };
            if !why.is_empty() {
                return Err(Diagnostic::error(
                    block.span,
                    format!(
                        "the shape N{}–N{} of {name} holds {why} (alarm PS0066: a command not allowed in the shape)",
                        first_block.number.unwrap_or(0),
                        program.blocks[last as usize].number.unwrap_or(0)
                    ),
                ));
            }
            blocks.resize(scratch.toolpath.moves.len(), k);
            if k == first {
                approach = blocks.len();
            }
        }
        // A chamfer or corner R needs a next block of the shape (alarm PS0069).
        if let Some(corner) = scratch.turning.as_ref().and_then(|t| t.corner) {
            return Err(Diagnostic::error(
                corner.span,
                format!("the shape's last block N{} of {name} cannot end in a chamfer or corner R: no block of the shape follows it (alarm PS0069: the last block of the shape is illegal)", program.blocks[last as usize].number.unwrap_or(0)),
            ));
        }
        self.diagnostics.append(&mut scratch.diagnostics);
        self.warned = scratch.warned;
        Ok(Shape { moves: scratch.toolpath.moves, approach, blocks, rapid, first, last })
    }

    /// With tool nose radius compensation in force, the shape the roughing
    /// is made on: the imaginary tip's path of the compensated finishing
    /// shape, each move from the block of the shape move it comes from
    /// (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
    /// system, "Multiple repetitive cycle", "Tool nose radius
    /// compensation"). `None` without compensation: the shape as written.
    fn compensated_shape(&self, program: &Program, shape: &Shape) -> Result<Option<Shape>, Diagnostic> {
        let Some(done) = self.comp_cycle_shape(&shape.moves) else { return Ok(None) };
        let (moves, origin) = done.map_err(|e| {
            let k = e.move_index().unwrap_or_default().min(shape.blocks.len().saturating_sub(1));
            let span = shape
                .blocks
                .get(k)
                .map_or(program.blocks[shape.first as usize].span, |&b| program.blocks[b as usize].span);
            Diagnostic::error(span, self.comp_alarm(&format!("{} (the cycle's shape, offset by the nose)", e.message)))
        })?;
        let approach = origin.iter().take_while(|&&o| o < shape.approach).count();
        let blocks = origin.iter().map(|&o| shape.blocks[o]).collect();
        Ok(Some(Shape { moves, approach, blocks, ..*shape }))
    }

    /// Whether a block's words name one of these cycles (literal G numbers).
    fn names_contour_cycle(&self, words: &[Word]) -> bool {
        words.iter().any(|w| {
            w.letter == b'G'
                && matches!(w.value(), WordValue::Number { value, .. } if self.contour_code((value * 10.0).round() as u32).is_some())
        })
    }

    /// `G70`: the shape's blocks run as they stand.
    fn finish(&mut self, program: &Program, shape: &Shape) -> Result<(), Diagnostic> {
        for k in shape.first..=shape.last {
            let block = &program.blocks[k as usize];
            if matches!(block.statement, Statement::Words { .. }) && !(block.delete && self.settings.block_delete) {
                self.exec_block(program, k)?;
            }
        }
        Ok(())
    }

    /// The shape's moves after its first block, in `frame`, checked to be
    /// what a cycle can follow.
    fn pieces(&self, program: &Program, shape: &Shape, frame: &Frame, name: &str) -> Result<Contour, Diagnostic> {
        let mut pieces = Vec::new();
        for (k, m) in shape.moves.iter().enumerate() {
            let span = program.blocks[shape.blocks[k] as usize].span;
            let other = (m.start.y - m.end.y).abs()
                + (m.start.a - m.end.a).abs()
                + (m.start.b - m.end.b).abs()
                + (m.start.c - m.end.c).abs();
            let arc = match m.kind {
                MoveKind::Rapid | MoveKind::Feed => None,
                MoveKind::Arc(a) if a.plane == Plane::Zx && a.turns == 0 => {
                    Some((frame.to(a.center[0], a.center[2]), a.ccw != frame.flips()))
                }
                _ => {
                    return Err(Diagnostic::error(
                        span,
                        format!("{name}'s shape is made of G00, G01, G02 and G03 moves in the ZX plane (G18) only (alarm PS0066)"),
                    ))
                }
            };
            if other > 1e-9 {
                return Err(Diagnostic::error(span, format!("{name}'s shape moves only X and Z (alarm PS0066)")));
            }
            if k < shape.approach {
                continue;
            }
            let piece = Piece {
                from: frame.to(m.start.x, m.start.z),
                to: frame.to(m.end.x, m.end.z),
                arc,
                rapid: m.kind == MoveKind::Rapid,
                block: k,
            };
            pieces.push(piece);
        }
        Ok(Contour { pieces })
    }

    /// Where the shape's first block leaves the tool (A'), and where the
    /// shape ends (B).
    fn shape_ends(&self, shape: &Shape) -> (Axes, Axes) {
        let a1 = shape.moves.get(shape.approach.wrapping_sub(1)).map_or(self.tip, |m| m.end);
        let b = shape.moves.last().map_or(a1, |m| m.end);
        (a1, b)
    }

    /// The finishing allowance: U (X, a diameter where X is) and W.
    fn allowance(&self, w: &Words) -> (f64, f64) {
        let diameter = self.turning.as_ref().is_some_and(|t| t.x == XMode::Diameter);
        let u = w.get(b'U').map_or(0.0, |u| self.mm(u));
        (if diameter { u / 2.0 } else { u }, w.get(b'W').map_or(0.0, |v| self.mm(v)))
    }
}

impl State {
    /// `G71`/`G72`: the cuts by depth and along the shape.
    #[allow(clippy::too_many_arguments)]
    fn rough_steps(
        &mut self,
        program: &Program,
        shape: &Shape,
        cycle: ContourCycle,
        w: &Words,
        gspan: Span,
        name: &str,
        haas: bool,
    ) -> Result<(Frame, Vec<Step>), Diagnostic> {
        let turning = cycle == ContourCycle::Turning;
        let at = |l: u8| if w.has(l) { w.span(l) } else { gspan };
        let depth = if haas {
            match w.get(b'D') {
                Some(d) if d > 0.0 => self.mm(d),
                _ => {
                    return Err(Diagnostic::error(
                        at(b'D'),
                        format!("{name} needs D, the depth of each cut, greater than 0 (the control's alarm: the depth of cut is zero or negative)"),
                    ))
                }
            }
        } else {
            match self.contour.depth {
                Some((d, _)) if d > 0.0 => d,
                _ => {
                    let first = if turning { "U" } else { "W" };
                    return Err(Diagnostic::error(
                        gspan,
                        format!("{name} has no depth of cut: give {name} {first}(depth) R(escape) in the block before (alarm PS0062: the depth of cut is zero or negative)"),
                    ));
                }
            }
        };
        let escape = self.contour.escape.unwrap_or(DEFAULT_ESCAPE);
        let first_words = program.words(&program.blocks[shape.first as usize]);
        let names = |l: &[u8]| first_words.iter().any(|word| l.contains(&word.letter));
        // Type II: the first block names the cut's axis too (Fanuc, and Haas
        // in its Fanuc-compatible reading: real Haas programs rely on it), or
        // Haas's R1.
        let pockets = (haas && w.get(b'R') == Some(1.0)) || if turning { names(b"ZW") } else { names(b"XU") };
        let (a1, b) = self.shape_ends(shape);
        let start = self.tip;
        let ns = &program.blocks[shape.first as usize];
        let (across, along) = if turning { (start.x - a1.x, b.z - a1.z) } else { (start.z - a1.z, b.x - a1.x) };
        if across.abs() < 1e-9 || along.abs() < 1e-9 {
            let (axis, other) = if turning { ("X", "Z") } else { ("Z", "X") };
            let what = if across.abs() < 1e-9 {
                format!(
                    "its first block N{} does not move the tool in {axis} towards the shape",
                    ns.number.unwrap_or(0)
                )
            } else {
                format!("the shape ends where it starts in {other}")
            };
            return Err(Diagnostic::error(ns.span, format!("{name} cannot tell which way to cut: {what}")));
        }
        let (sd, sa) = (across.signum(), along.signum());
        // (z, x) offsets → (a, d).
        let m = if turning { [[sa, 0.0], [0.0, -sd]] } else { [[0.0, sa], [-sd, 0.0]] };
        let frame = Frame { origin: start, m };
        let contour = self.pieces(program, shape, &frame, name)?;
        // Haas: I and K, the rough cuts' own allowance; the cut along the
        // shape only with them.
        let (ux, wz) = self.allowance(w);
        let rough_extra = if haas {
            (w.get(b'I').map_or(0.0, |i| self.mm(i)), w.get(b'K').map_or(0.0, |k| self.mm(k)))
        } else {
            (0.0, 0.0)
        };
        let along_shape = !haas || w.has(b'I') || w.has(b'K');
        let moved = |frame: &Frame, x: f64, z: f64| {
            let p0 = frame.to(start.x, start.z);
            let p1 = frame.to(start.x + x, start.z + z);
            [p1[0] - p0[0], p1[1] - p0[1]]
        };
        let finish = moved(&frame, ux, wz);
        let roughing = moved(&frame, ux + rough_extra.0, wz + rough_extra.1);
        let shift = |c: &Contour, by: P| Contour {
            pieces: c
                .pieces
                .iter()
                .map(|p| {
                    let mv = |q: P| [q[0] + by[0], q[1] + by[1]];
                    Piece { from: mv(p.from), to: mv(p.to), arc: p.arc.map(|(c, ccw)| (mv(c), ccw)), ..*p }
                })
                .collect(),
        };
        let blame = |k: usize| program.blocks[shape.blocks[contour.pieces[k].block] as usize].span;
        if let Some(k) = contour.first_backwards() {
            let (axis, alarm) = if turning {
                ("Z", "PS0329: the finishing shape is not a monotonous change (second axis)")
            } else {
                ("X", "PS0064: the finishing shape is not a monotonous change (first axis)")
            };
            return Err(Diagnostic::error(blame(k), format!("{name}'s shape must run one way in {axis}, the way it cuts, and this block turns back (alarm {alarm})")));
        }
        // Type I: the shape's depth changes one way, rising toward the
        // start point's level or going deeper (the alarm is for a shape
        // that is not a monotonous increase or decrease).
        let deepening = !pockets && contour.first_deeper().is_some() && contour.first_shallower().is_none();
        if !pockets && !deepening {
            // Where it turns: the later of the first rise and the first drop.
            let turn = contour.first_deeper().map(|k| contour.first_shallower().map_or(k, |j| j.max(k)));
            if let Some(k) = turn {
                let (axis, alarm, other) = if turning {
                    ("X", "PS0064: the finishing shape is not a monotonous change (first axis)", "Z (W)")
                } else {
                    ("Z", "PS0329: the finishing shape is not a monotonous change (second axis)", "X (U)")
                };
                return Err(Diagnostic::error(
                    blame(k),
                    format!("{name} type I needs a shape whose {axis} changes one way from its first block, and this block turns back (alarm {alarm}); a shape with pockets needs type II: name {other} in the first block N{} too", ns.number.unwrap_or(0)),
                ));
            }
        }
        let rough_shape = shift(&contour, roughing);
        let cuts = cut_count(&rough_shape, depth, deepening);
        if cuts > MAX_CUTS {
            return Err(Diagnostic::error(
                self.contour.depth.filter(|_| !haas).map_or(at(b'D'), |(_, s)| s),
                format!(
                    "{name} would make {cuts} cuts of {depth} mm: more than {MAX_CUTS}; is the depth of cut mistyped?"
                ),
            ));
        }
        let rough = Rough { depth, escape, pockets, rapid_approach: shape.rapid, to_start: deepening };
        let along = along_shape.then(|| shift(&contour, finish));
        Ok((frame, roughing::rough(&rough_shape, along.as_ref(), &rough)))
    }

    /// `G73`: the shape again and again, each time nearer.
    fn pattern_steps(
        &mut self,
        program: &Program,
        shape: &Shape,
        w: &Words,
        gspan: Span,
        name: &str,
        haas: bool,
    ) -> Result<(Frame, Vec<Step>), Diagnostic> {
        let (relief, passes) = if haas {
            let i = w.get(b'I').map_or(0.0, |i| self.mm(i));
            let k = w.get(b'K').map_or(0.0, |k| self.mm(k));
            ((i, k), w.get(b'D').map(|d| (d, w.span(b'D'))))
        } else {
            (self.contour.relief.unwrap_or((0.0, 0.0)), self.contour.passes)
        };
        let count = match passes {
            Some((d, _)) if d >= 1.0 && d.fract() == 0.0 && d <= MAX_CUTS => d,
            Some((d, span)) => {
                return Err(Diagnostic::error(
                    span,
                    format!("{name}'s number of passes must be a whole number from 1, not {d} (alarm PS0062: the repetition count is zero or negative)"),
                ))
            }
            None => {
                let give = if haas { "D(passes)" } else { "R(passes) in the block before" };
                return Err(Diagnostic::error(gspan, format!("{name} needs the number of passes: give {give} (alarm PS0062)")));
            }
        };
        let frame = Frame { origin: self.tip, m: [[1.0, 0.0], [0.0, 1.0]] };
        let (ux, wz) = self.allowance(w);
        // Pass j of n is Δi (n - j) / (n - 1) + Δu/2 from the shape in X,
        // Δk (n - j) / (n - 1) + Δw in Z: the first at Δi + Δu/2, the last
        // at the finishing allowance.
        let n = count as usize;
        let offsets: Vec<P> = (1..=n)
            .map(|j| {
                let f = if n > 1 { (n - j) as f64 / (n - 1) as f64 } else { 0.0 };
                [wz + relief.1 * f, ux + relief.0 * f]
            })
            .collect();
        let contour = self.pieces(program, shape, &frame, name)?;
        Ok((frame, roughing::pattern(&contour, &offsets, shape.rapid)))
    }

    /// The cycle's moves, made.
    fn put_steps(&mut self, frame: &Frame, steps: &[Step], span: Span, line: u32) -> Result<(), Diagnostic> {
        let named = AxisSet::NONE.with(0).with(2);
        let feed = if steps.iter().any(|s| !matches!(s, Step::Rapid(_))) { self.feed_mm_min(span)? } else { 0.0 };
        for s in steps {
            let (x, z) = frame.from(s.end());
            let end = Axes { x, z, ..self.tip };
            match *s {
                Step::Rapid(_) => self.push_move(MoveKind::Rapid, end, 0.0, named, line),
                Step::Feed(_) => self.push_move(MoveKind::Feed, end, feed, named, line),
                Step::Arc { center, ccw, .. } => {
                    let (cx, cz) = frame.from(center);
                    let arc =
                        Arc { center: [cx, self.tip.y, cz], plane: Plane::Zx, ccw: ccw != frame.flips(), turns: 0 };
                    self.push_move(MoveKind::Arc(arc), end, feed, named, line);
                }
            }
        }
        Ok(())
    }
}
