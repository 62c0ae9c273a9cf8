//! The passes of the stock removal cycles, as plain geometry in the frame
//! of [`super::profile`]: `a` along the cut, `d` the depth into the stock,
//! the cycle's start point at (0, 0). FANUC Series 0i-TF Plus Operator's
//! Manual (B-64604EN), lathe system, "Multiple repetitive cycle": G71/G72
//! remove the stock between the start point and the finishing shape (moved
//! by the finishing allowance) in cuts of depth Δd, each along `a`.
//!
//! - Type I (the shape's first block names only the depth axis; the shape
//!   rises steadily, or goes steadily deeper, when the cuts reach only its
//!   start's depth): each cut is approached along `d` as the shape's first
//!   block moves (G00 or G01), runs along `a` until it meets the shape, and
//!   leaves at 45° by the escape `e`; the tool goes back along `a` at rapid.
//! - Type II (pockets allowed): each cut goes on along the shape up to the
//!   previous cut's depth and leaves straight out by `e`; a pocket is
//!   entered down its wall from the previous depth. The pockets of a depth
//!   are cut in the order the shape meets them, depth by depth (kezuri's
//!   reading where the manual draws the order only in a figure).
//!
//! Then, unless left out, one cut along the whole shape (the "semi-finishing"
//! cut that leaves the allowance even), and the tool goes back to the start
//! point at rapid: out to the start's depth, then along `a`.

use super::profile::{Contour, Crossing, Piece, Spot, EPS, P};

/// A move of a cycle, in the cycle's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Step {
    Rapid(P),
    Feed(P),
    /// An arc to `to` about `center`, `ccw` from +a towards +d.
    Arc {
        to: P,
        center: P,
        ccw: bool,
    },
}

impl Step {
    /// Where the move ends.
    pub fn end(&self) -> P {
        match *self {
            Step::Rapid(p) | Step::Feed(p) => p,
            Step::Arc { to, .. } => to,
        }
    }
}

/// How a stock removal cycle cuts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rough {
    /// The depth of each cut (Δd), > 0.
    pub depth: f64,
    /// How far the tool leaves the stock after a cut (e), ≥ 0.
    pub escape: f64,
    /// Type II: the shape may have pockets.
    pub pockets: bool,
    /// The shape's first block is a rapid (G00): cuts are approached at
    /// rapid, else at the feed.
    pub rapid_approach: bool,
    /// Type I with a shape that goes deeper from its start: the cuts by
    /// depth go down to the shape's start only (the manual's cuts from A
    /// toward A'); the cut along the shape takes the rest.
    pub to_start: bool,
}

/// How many cuts by depth the cycle makes before the cut along the shape:
/// depths Δd, 2Δd, … shallower than the shape's deepest point (`to_start`:
/// than its start).
pub(super) fn cut_count(contour: &Contour, depth: f64, to_start: bool) -> f64 {
    let deepest = if to_start { contour.start()[1] } else { contour.deepest() };
    if deepest <= EPS {
        return 0.0;
    }
    ((deepest - EPS) / depth).floor()
}

/// The piece as the move that makes it.
fn step(p: &Piece) -> Step {
    match p.arc {
        Some((center, ccw)) => Step::Arc { to: p.to, center, ccw },
        None if p.rapid => Step::Rapid(p.to),
        None => Step::Feed(p.to),
    }
}

struct Path<'a> {
    steps: Vec<Step>,
    at: P,
    rough: &'a Rough,
}

impl Path<'_> {
    fn push(&mut self, s: Step) {
        let to = s.end();
        if (to[0] - self.at[0]).abs() > EPS || (to[1] - self.at[1]).abs() > EPS {
            self.steps.push(s);
            self.at = to;
        }
    }

    fn approach(&mut self, to: P) {
        self.push(if self.rough.rapid_approach { Step::Rapid(to) } else { Step::Feed(to) });
    }

    /// Along the shape, every piece a feed (the cut follows it).
    fn follow(&mut self, pieces: &[Piece]) {
        for p in pieces {
            self.push(match p.arc {
                Some((center, ccw)) => Step::Arc { to: p.to, center, ccw },
                None => Step::Feed(p.to),
            });
        }
    }

    /// At rapid above `to`'s `a`, clear of the shape in between: out to
    /// the escape above its shallowest point there, across, and no deeper
    /// than `to` (which the caller then moves to).
    fn travel(&mut self, contour: &Contour, to: P) {
        let clear = contour.shallowest_between(self.at[0], to[0]) - self.rough.escape;
        let h = self.at[1].min(clear).min(to[1]);
        self.push(Step::Rapid([self.at[0], h]));
        self.push(Step::Rapid([to[0], h]));
    }
}

/// The stock removal passes (G71, G72; Haas's one-block forms too): the
/// cuts by depth down to `shape` (the finishing shape moved by the
/// allowance the cuts leave), then the cut along `along` where there is
/// one (the shape moved by the finishing allowance), from the start point
/// (0, 0) and back.
pub(super) fn rough(shape: &Contour, along: Option<&Contour>, rough: &Rough) -> Vec<Step> {
    let mut contour = shape.clone();
    // Before the shape's start (along `a`) the cuts begin at the start
    // point: the stock there is the shape's first depth.
    let s = contour.start();
    if s[0] > EPS {
        let lead = Piece { from: [0.0, s[1]], to: s, arc: None, rapid: false, block: 0 };
        contour.pieces.insert(0, lead);
    }
    let mut path = Path { steps: Vec::new(), at: [0.0, 0.0], rough };
    let count = cut_count(&contour, rough.depth, rough.to_start) as usize;
    for k in 1..=count {
        let level = k as f64 * rough.depth;
        if rough.pockets {
            pocket_level(&mut path, &contour, level, level - rough.depth);
        } else {
            plain_level(&mut path, &contour, level);
        }
    }
    if let Some(along) = along.filter(|c| !c.pieces.is_empty()) {
        path.travel(&contour, [0.0, along.start()[1]]);
        path.approach(along.start());
        for p in &along.pieces {
            path.push(step(p));
        }
        contour = along.clone();
    }
    let end = path.at;
    if end[1] > 0.0 {
        path.travel(&contour, [0.0, 0.0]);
    }
    path.push(Step::Rapid([0.0, 0.0]));
    path.steps
}

/// Type I: in at `a` = 0, along to the shape, out at 45°, back.
fn plain_level(path: &mut Path, contour: &Contour, level: f64) {
    let end = contour.crossings(level).iter().find(|c| !c.down).map_or(contour.end(), |c| c.spot.at);
    if end[0] <= EPS {
        return;
    }
    let e = path.rough.escape;
    path.push(Step::Rapid([0.0, path.at[1]]));
    path.approach([0.0, level]);
    path.push(Step::Feed([end[0], level]));
    path.push(Step::Rapid([end[0] - e, level - e]));
    path.push(Step::Rapid([0.0, level - e]));
}

fn before(a: Spot, b: Spot) -> bool {
    (a.piece, a.t) < (b.piece, b.t) && !(a.piece == b.piece && (a.t - b.t).abs() < 1e-12)
}

/// Type II: each stretch where the shape lies deeper than `level`, cut
/// along `a` and followed along the shape up to `above` (the last cut's
/// depth).
fn pocket_level(path: &mut Path, contour: &Contour, level: f64, above: f64) {
    let here = contour.crossings(level);
    let up: Vec<Crossing> = contour.crossings(above);
    let start = Spot { piece: 0, t: 0.0, at: contour.start() };
    // The stretches: (where the shape goes below the level, where it comes up).
    let mut stretches = Vec::new();
    let mut open = contour.starts_below(level).then_some(start);
    for c in &here {
        match (c.down, open) {
            (true, None) => open = Some(c.spot),
            (false, Some(s)) => {
                stretches.push((s, c.spot));
                open = None;
            }
            _ => {}
        }
    }
    if let Some(s) = open {
        stretches.push((s, contour.end_spot()));
    }
    let e = path.rough.escape;
    let mut k = 0;
    while k < stretches.len() {
        let (s, _) = stretches[k];
        if s == start || s.at[0] <= EPS {
            path.travel(contour, [0.0, level]);
            path.approach([0.0, level]);
        } else {
            // Down the pocket's wall from the last cut's depth, or from
            // the shape's start where it lies between the two depths.
            let wall = up.iter().rev().find(|c| c.down && before(c.spot, s)).map(|c| c.spot);
            let from = wall.unwrap_or(start);
            path.travel(contour, from.at);
            if wall.is_some() {
                path.push(Step::Rapid(from.at));
            } else {
                path.approach(from.at);
            }
            path.follow(&contour.between(from, s));
        }
        // Along the level, and on along the shape: back down into the next
        // stretch (go on along it), up to the last depth, or to the end.
        loop {
            let (_, e_spot) = stretches[k];
            path.push(Step::Feed([e_spot.at[0], level]));
            let out = up.iter().find(|c| !c.down && before(e_spot, c.spot)).map(|c| c.spot);
            let next = stretches.get(k + 1).map(|&(s, _)| s);
            match (out, next) {
                (out, Some(n)) if out.is_none_or(|o| before(n, o)) => {
                    path.follow(&contour.between(e_spot, n));
                    k += 1;
                }
                (Some(o), _) => {
                    path.follow(&contour.between(e_spot, o));
                    path.push(Step::Rapid([o.at[0], o.at[1] - e]));
                    break;
                }
                (None, _) => {
                    path.follow(&contour.between(e_spot, contour.end_spot()));
                    path.push(Step::Rapid([path.at[0], path.at[1] - e]));
                    break;
                }
            }
        }
        k += 1;
    }
}

/// G73: the shape repeated once for each offset (in order), each time from
/// the start point moved by it, back to the next at rapid, then to the
/// start point.
pub(super) fn pattern(shape: &Contour, offsets: &[P], rapid_approach: bool) -> Vec<Step> {
    let rough = Rough { depth: 1.0, escape: 0.0, pockets: false, rapid_approach, to_start: false };
    let mut path = Path { steps: Vec::new(), at: [0.0, 0.0], rough: &rough };
    for o in offsets {
        let moved = |p: P| [p[0] + o[0], p[1] + o[1]];
        path.push(Step::Rapid(*o));
        path.approach(moved(shape.start()));
        for p in &shape.pieces {
            let arc = p.arc.map(|(c, ccw)| (moved(c), ccw));
            path.push(step(&Piece { from: moved(p.from), to: moved(p.to), arc, ..*p }));
        }
    }
    path.push(Step::Rapid([0.0, 0.0]));
    path.steps
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(from: P, to: P) -> Piece {
        Piece { from, to, arc: None, rapid: false, block: 0 }
    }

    fn r(depth: f64, escape: f64, pockets: bool) -> Rough {
        Rough { depth, escape, pockets, rapid_approach: true, to_start: false }
    }

    #[test]
    fn type_one_on_a_step() {
        // Depth 5 from a 0 to 10, up to 0 at a = 10 (a shoulder). Cuts of 2:
        // depths 2 and 4 (6 is past 5); each to a = 10, out 45° by 0.5.
        let c = Contour { pieces: vec![line([0.0, 5.0], [10.0, 5.0]), line([10.0, 5.0], [10.0, 0.0])] };
        let s = rough(&c, Some(&c), &r(2.0, 0.5, false));
        use Step::*;
        assert_eq!(
            s,
            vec![
                Rapid([0.0, 2.0]),
                Feed([10.0, 2.0]),
                Rapid([9.5, 1.5]),
                Rapid([0.0, 1.5]),
                Rapid([0.0, 4.0]),
                Feed([10.0, 4.0]),
                Rapid([9.5, 3.5]),
                Rapid([0.0, 3.5]),
                // Along the shape: in to its start, along, up the shoulder.
                Rapid([0.0, 5.0]),
                Feed([10.0, 5.0]),
                Feed([10.0, 0.0]),
                Rapid([0.0, 0.0]),
            ]
        );
    }

    #[test]
    fn type_two_enters_a_pocket_down_its_wall() {
        // Depth 4 for a 0..2, up to 1 over a 2..3, flat to 5, down to 4 at
        // 6, flat to 8, up to 0 at 8. Cut depth 2, escape 0.5.
        let c = Contour {
            pieces: vec![
                line([0.0, 4.0], [2.0, 4.0]),
                line([2.0, 4.0], [3.0, 1.0]),
                line([3.0, 1.0], [5.0, 1.0]),
                line([5.0, 1.0], [6.0, 4.0]),
                line([6.0, 4.0], [8.0, 4.0]),
                line([8.0, 4.0], [8.0, 0.0]),
            ],
        };
        let s = rough(&c, Some(&c), &r(2.0, 0.5, true));
        use Step::*;
        // Depth 2: from a 0 to where the wall 4 → 1 is at depth 2 (a = 2 + 2/3),
        // along the wall up to the last depth 0? The shape comes no higher
        // than 1: on over the hump (1 at a 3..5) and down to depth 2 at
        // a = 5 + 1/3, along to a 8, up the shoulder to 0, out by 0.5.
        let third = 2.0 / 3.0;
        let expected_first = [
            Rapid([0.0, 2.0]),
            Feed([2.0 + third, 2.0]),
            Feed([3.0, 1.0]),
            Feed([5.0, 1.0]),
            Feed([5.0 + 1.0 / 3.0, 2.0]),
            Feed([8.0, 2.0]),
            Feed([8.0, 0.0]),
            Rapid([8.0, -0.5]),
        ];
        for (k, want) in expected_first.iter().enumerate() {
            let (got, want) = (s[k].end(), want.end());
            assert!((got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9, "{k}: {s:?}");
        }
        // Depth 4 is the bottom: no cut there; then back over the shape (out
        // to -0.5 already), in to its start, along its six pieces, home.
        assert_eq!(s.len(), expected_first.len() + 2 + 6 + 1, "{s:?}");
    }

    #[test]
    fn pattern_repeats_the_shape() {
        let c = Contour { pieces: vec![line([0.0, 5.0], [10.0, 5.0])] };
        let s = pattern(&c, &[[2.0, -2.0], [0.0, 0.0]], false);
        use Step::*;
        assert_eq!(
            s,
            vec![
                Rapid([2.0, -2.0]),
                Feed([2.0, 3.0]),
                Feed([12.0, 3.0]),
                Rapid([0.0, 0.0]),
                Feed([0.0, 5.0]),
                Feed([10.0, 5.0]),
                Rapid([0.0, 0.0]),
            ]
        );
    }
}
