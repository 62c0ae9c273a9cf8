//! The extent of what a toolpath says of the tool tip: only the positions
//! the program gave ([`Move::unknown`]), never a reference point or a
//! `G53` position.

use super::{arc_extremes, Axes, AxisSet, Move, MoveKind, Toolpath};

/// Per axis X Y Z, the smallest and largest value; `None` for an axis no
/// known position gives.
pub type AxisRanges = [Option<(f64, f64)>; 3];

impl Toolpath {
    /// The tool tip's extent over the positions the program gave: in
    /// program coordinates (each point less its frame's
    /// [`zero`](super::Frame::zero)) where `program`, else in machine
    /// coordinates. The end of a return to the reference point or of a
    /// `G53` move is left out whatever the machine file says of it (they
    /// are the machine's, see [`Toolpath::machine_moves`]), and so is each
    /// axis of a point that is not known
    /// ([`Move::unknown`](super::Move::unknown)): a move's start counts
    /// where the move before left it known; arcs count at their quadrant
    /// points.
    pub fn known_bounds(&self, program: bool) -> AxisRanges {
        let mut b = KnownBounds::new(program, false);
        b.add(self);
        b.finish()
    }

    /// The extent of U V W over the positions the program gave, as
    /// [`Toolpath::known_bounds`] has X Y Z's: `None` for an axis no known
    /// position gives (every program that does not name it).
    pub fn known_bounds_uvw(&self, program: bool) -> AxisRanges {
        let mut b = KnownBounds::new(program, true);
        b.add(self);
        b.finish()
    }

    /// The moves in machine coordinates: returns to a reference point
    /// (G28, G30) and `G53` moves, which [`Toolpath::known_bounds`] leaves
    /// out.
    pub fn machine_moves(&self) -> usize {
        self.moves.iter().filter(|m| m.is_machine()).count()
    }
}

impl Move {
    /// Whether the move is in machine coordinates: a return to a reference
    /// point (G28, G30) or a `G53` move.
    pub fn is_machine(&self) -> bool {
        matches!(self.kind, MoveKind::Home | MoveKind::Machine)
    }

    /// Gives `add` the points the box of the move is made of, in order: its
    /// start, its end and an arc's quadrant points ([`Toolpath::bounds`]).
    pub fn extreme_points(&self, add: &mut impl FnMut([f64; 3])) {
        add(self.start.xyz());
        add(self.end.xyz());
        if let MoveKind::Arc(arc) = self.kind {
            for p in arc_extremes(&arc, self.start, self.end) {
                add(p);
            }
        }
    }
}

/// [`Toolpath::known_bounds`] (or [`Toolpath::known_bounds_uvw`]) of a
/// toolpath taken piece by piece, in order: the same ranges, holding only
/// them and what the last move left known.
#[derive(Clone, Debug)]
pub struct KnownBounds {
    /// In program coordinates, else in machine coordinates.
    program: bool,
    /// The first of the three linear axes: 0 (X Y Z) or 6 (U V W).
    first: usize,
    out: AxisRanges,
    /// The axes the last move left unknown; `None` before the first piece.
    before: Option<AxisSet>,
    /// Whether a move has placed any of U V W: most programs never do
    /// (every one but LinuxCNC's), and then U V W have no extent.
    uvw_placed: bool,
}

impl KnownBounds {
    /// The extent of X Y Z, or of U V W where `uvw`, in program
    /// coordinates where `program`, before the first piece.
    pub fn new(program: bool, uvw: bool) -> KnownBounds {
        let first = if uvw { 6 } else { 0 };
        KnownBounds { program, first, out: [None; 3], before: None, uvw_placed: false }
    }

    /// The next piece of the path; arcs add their quadrant points on X Y Z
    /// (U V W move on a straight line beside them).
    pub fn add(&mut self, piece: &Toolpath) {
        let (program, first) = (self.program, self.first);
        let three = |p: Axes| -> [f64; 3] {
            if first == 0 {
                p.xyz()
            } else {
                p.uvw()
            }
        };
        let out = &mut self.out;
        let mut add = |p: [f64; 3], unknown: AxisSet, zero: [f64; 3]| {
            for k in (0..3).filter(|&k| !unknown.contains(first + k)) {
                let v = p[k] - zero[k];
                out[k] = Some(out[k].map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))));
            }
        };
        let start = if piece.unknown_start { AxisSet::ALL } else { AxisSet::NONE };
        let mut before = self.before.unwrap_or(start);
        // The program's zero of the last move's frame (most moves share it).
        let mut last_zero = (u32::MAX, [0.0; 3]);
        for m in &piece.moves {
            self.uvw_placed |= m.unknown.0 & AxisSet::UVW.0 != AxisSet::UVW.0;
            if program && m.frame != last_zero.0 {
                last_zero = (m.frame, three(piece.frame(m).zero()));
            }
            let zero = last_zero.1;
            // A start counts where known: a move leaving a return's end
            // counts it only where that place is known (the machine file
            // gives it, or a G92 there names it).
            add(three(m.start), before, zero);
            let was = std::mem::replace(&mut before, m.unknown);
            if m.is_machine() {
                continue;
            }
            add(three(m.end), m.unknown, zero);
            if let (MoveKind::Arc(arc), 0) = (m.kind, first) {
                for p in arc_extremes(&arc, m.start, m.end) {
                    add(p, AxisSet(m.unknown.0 | was.0), zero);
                }
            }
        }
        if !piece.moves.is_empty() {
            self.before = Some(before);
        }
    }

    /// The ranges of every piece taken: `None` for an axis no known
    /// position gives.
    pub fn finish(&self) -> AxisRanges {
        if self.first == 6 && !self.uvw_placed {
            return [None; 3];
        }
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Axes, Frame, Move};
    use super::*;

    fn at(x: f64, y: f64, z: f64) -> Axes {
        Axes { x, y, z, ..Axes::ZERO }
    }

    #[test]
    fn returns_and_unknown_axes_are_left_out_and_frames_taken_off() {
        let z_unknown = AxisSet(0b100);
        let moves = vec![
            // From the unknown start to the reference point: neither counts
            // (X and Y not named yet, Z at the reference point).
            Move {
                kind: MoveKind::Home,
                start: at(0.0, 0.0, 0.0),
                end: at(0.0, 0.0, -31.75),
                unknown: AxisSet(0b111),
                ..Move::default()
            },
            // X Y given, Z still at the reference point.
            Move {
                kind: MoveKind::Rapid,
                start: at(0.0, 0.0, -31.75),
                end: at(110.0, 20.0, -31.75),
                unknown: z_unknown,
                frame: 1,
                ..Move::default()
            },
            Move {
                kind: MoveKind::Rapid,
                start: at(110.0, 20.0, -31.75),
                end: at(110.0, 20.0, 5.0),
                frame: 1,
                ..Move::default()
            },
            Move {
                kind: MoveKind::Feed,
                start: at(110.0, 20.0, 5.0),
                end: at(140.0, 20.0, -3.0),
                frame: 1,
                ..Move::default()
            },
            Move {
                kind: MoveKind::Machine,
                start: at(140.0, 20.0, -3.0),
                end: at(140.0, 20.0, -60.0),
                unknown: z_unknown,
                frame: 1,
                ..Move::default()
            },
        ];
        let frames = vec![Frame::default(), Frame { origin: at(100.0, 0.0, 0.0), ..Frame::default() }];
        let path = Toolpath { moves, frames, unknown_start: true, ..Toolpath::default() };
        assert_eq!(path.known_bounds(true), [Some((10.0, 40.0)), Some((20.0, 20.0)), Some((-3.0, 5.0))]);
        assert_eq!(path.known_bounds(false)[0], Some((110.0, 140.0)));
        assert_eq!(path.machine_moves(), 2);
        // The old box: the reference point's Z and the assumed start.
        let (lo, hi) = path.bounds().unwrap();
        assert_eq!((lo[2], hi[2], lo[0]), (-60.0, 5.0, 0.0));
    }
}
