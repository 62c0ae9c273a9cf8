//! The page of a path fed in pieces ([`PathSink`]): a program of any size
//! drawn within `--max-page-mb`, holding no more than the page can show.
//!
//! Each move is timed as the cycle time times it ([`CycleClock`]: only the
//! moves whose speeds later moves may still change wait) and then drawn at
//! every level of detail at once: at full detail and at each tolerance of
//! [`TOLERANCES`] (a [`Simplifier`] each). Every level counts what its page
//! would take ([`Tally`]) and keeps its moves as the page will draw them
//! ([`Drawing`]) only while that fits the page with nothing else on it;
//! past that it is let go. At the end, once the program text and the
//! simulated part have taken their room, the finest level kept that fits
//! what is left is packed: the same choice, and the same page to the byte,
//! as the whole path drawn at once.

use std::collections::{BTreeSet, VecDeque};

use kezuri_geom::{CycleClock, Dynamics, Move, PathSink, Toolpath};

use super::detail::{kind, Drawn, Simplifier, Tally, TOLERANCES};
use super::drawing::Drawing;
use super::{Job, Page, PageOptions, Simulation};
use crate::Error;

/// The program's text, handed over in pieces: the function feeds each
/// piece to the closure it is given, in order, and stops when that says
/// `false`.
pub type TextPieces<'a> = &'a mut dyn FnMut(&mut dyn FnMut(&[u8]) -> bool);

/// One level of detail: full (no simplifier) or a tolerance.
pub(super) struct Level {
    /// The tolerance's simplifier; `None` at full detail.
    simplifier: Option<Simplifier>,
    /// What its page would take.
    tally: Tally,
    /// Its moves as the page draws them.
    pub(super) drawing: Drawing,
}

/// The page of a path fed in pieces (see the module documentation).
pub struct PathPage {
    options: PageOptions,
    /// What the page says of how the path was made (shortened).
    notes: Vec<String>,
    clock: Option<CycleClock>,
    /// The moves the clock has not timed yet.
    waiting: VecDeque<Move>,
    /// The work zero of each frame the moves give.
    zeros: Vec<[f64; 3]>,
    /// The numbers of the tools the moves use.
    tools: BTreeSet<u32>,
    /// Moves fed.
    count: u64,
    /// The most a level's page may take to be kept, bytes: the page with
    /// nothing else on it.
    reach: f64,
    /// The full detail, then each tolerance's, finest first; `None` once
    /// over `reach`. Empty before the first piece.
    levels: Vec<Option<Level>>,
    /// Scratch: seconds of moves timed.
    seconds: Vec<f64>,
}

impl PathPage {
    /// The page of a path run on a machine of `dynamics`, made as
    /// `options` say; `notes`: what the page says of how the path was made.
    pub fn new(dynamics: &Dynamics, options: &PageOptions, notes: Vec<String>) -> PathPage {
        PathPage {
            options: options.clone(),
            notes,
            clock: Some(CycleClock::new(dynamics)),
            waiting: VecDeque::new(),
            zeros: Vec::new(),
            tools: BTreeSet::new(),
            count: 0,
            reach: options.max_page_mb * 1e6 - super::fixed_bytes(0),
            levels: Vec::new(),
            seconds: Vec::new(),
        }
    }

    /// Moves fed so far.
    pub fn moves(&self) -> u64 {
        self.count
    }

    /// Bytes the levels hold now.
    pub fn held(&self) -> usize {
        self.levels.iter().flatten().map(|l| l.drawing.held()).sum()
    }

    /// The levels, made at the first piece.
    fn start(&mut self, unknown_start: bool) {
        if !self.levels.is_empty() {
            return;
        }
        let tol = self.options.arc_tol;
        let level =
            |simplifier| Some(Level { simplifier, tally: Tally::default(), drawing: Drawing::new(unknown_start, tol) });
        self.levels.push(level(None));
        self.levels.extend(TOLERANCES.iter().map(|&t| level(Some(Simplifier::new(t, unknown_start)))));
    }

    /// Draws the moves timed: `self.seconds` of the first waiting moves.
    fn draw_timed(&mut self) {
        let (reach, arc_tol, zeros) = (self.reach, self.options.arc_tol, &self.zeros);
        let zero = |frame: u32| zeros.get((frame as usize).min(zeros.len().max(1) - 1)).copied().unwrap_or([0.0; 3]);
        for &s in &self.seconds {
            let Some(m) = self.waiting.pop_front() else { break };
            for slot in self.levels.iter_mut() {
                let Some(level) = slot else { continue };
                let (tally, drawing) = (&mut level.tally, &mut level.drawing);
                let mut out = |d: Drawn| {
                    tally.add(&d, arc_tol);
                    drawing.add(&d.mv, d.kind, d.seconds, zero(d.mv.frame));
                };
                match &mut level.simplifier {
                    None => out(Drawn { mv: m, kind: kind(&m), seconds: s }),
                    Some(simplifier) => simplifier.push(&m, s, &mut out),
                }
                if level.tally.cost() > reach {
                    *slot = None;
                }
            }
        }
        self.seconds.clear();
    }

    /// Draws what is still waiting: the end of the path.
    fn end(&mut self) {
        self.start(false);
        if let Some(clock) = self.clock.take() {
            let seconds = &mut self.seconds;
            clock.finish_timed(&mut |s| seconds.push(s));
            self.draw_timed();
        }
        let (reach, arc_tol, zeros) = (self.reach, self.options.arc_tol, &self.zeros);
        let zero = |frame: u32| zeros.get((frame as usize).min(zeros.len().max(1) - 1)).copied().unwrap_or([0.0; 3]);
        for slot in self.levels.iter_mut() {
            let Some(level) = slot else { continue };
            if let Some(simplifier) = &mut level.simplifier {
                let (tally, drawing) = (&mut level.tally, &mut level.drawing);
                simplifier.finish(&mut |d: Drawn| {
                    tally.add(&d, arc_tol);
                    drawing.add(&d.mv, d.kind, d.seconds, zero(d.mv.frame));
                });
            }
            if level.tally.cost() > reach {
                *slot = None;
            }
        }
    }

    /// The page of `job` (its title, units and tools; its path, where
    /// there is a simulation, the one simulated) and of `sim`, with the
    /// program text `text` gives: the finest level kept that fits (see
    /// [`super::fitted_page`]).
    pub fn finish(mut self, job: &Job, sim: Option<&Simulation>, text: Option<TextPieces>) -> Result<Page, Error> {
        self.end();
        let levels: Vec<Option<(Option<f64>, f64, Drawing)>> = self
            .levels
            .into_iter()
            .enumerate()
            .map(|(k, l)| l.map(|l| (k.checked_sub(1).map(|r| TOLERANCES[r]), l.tally.cost(), l.drawing)))
            .collect();
        let tools: Vec<u32> = self.tools.into_iter().collect();
        super::page_of_levels(job, sim, text, &self.options, self.notes, &tools, self.count, levels)
    }
}

impl PathSink for PathPage {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        self.start(piece.unknown_start);
        if piece.frames.len() > self.zeros.len() {
            let known = self.zeros.len();
            self.zeros.extend(piece.frames[known..].iter().map(|f| f.zero().xyz()));
        }
        self.tools.extend(piece.moves.iter().map(|m| m.tool));
        self.count += piece.moves.len() as u64;
        self.waiting.extend(piece.moves.iter().copied());
        if let Some(clock) = &mut self.clock {
            let seconds = &mut self.seconds;
            clock.add_timed(&piece.moves, &mut |s| seconds.push(s));
        }
        self.draw_timed();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kezuri_geom::{Axes, MoveKind};

    /// `rows` rows of 1,000 feeds 0.1 mm long, Z stepping by a micrometre.
    fn raster(rows: usize) -> Vec<Move> {
        let at = |k: usize| {
            let (row, i) = (k / 1000, k % 1000);
            let i = if row % 2 == 1 { 999 - i } else { i };
            Axes { x: i as f64 * 0.1, y: row as f64 * 0.5, z: -1.0 - 0.001 * (k % 7) as f64, ..Axes::ZERO }
        };
        (1..rows * 1000)
            .map(|k| Move {
                kind: MoveKind::Feed,
                start: at(k - 1),
                end: at(k),
                feed: 1200.0,
                line: k as u32,
                ..Move::default()
            })
            .collect()
    }

    #[test]
    fn what_is_held_is_bounded_by_the_page_not_the_path() {
        // Under a 0.5 MB page, 20 times the moves hold no more: each level
        // is let go once its page would not fit.
        let options = PageOptions { max_page_mb: 0.5, ..PageOptions::default() };
        let most = |rows: usize| {
            let mut page = PathPage::new(&Dynamics::default(), &options, Vec::new());
            let mut most = 0;
            for piece in raster(rows).chunks(4096) {
                page.take(&Toolpath { moves: piece.to_vec(), ..Toolpath::default() }, None);
                most = most.max(page.held());
            }
            (most, page.moves())
        };
        let (small, large) = (most(10), most(200));
        assert_eq!((small.1, large.1), (9_999, 199_999));
        assert!(large.0 <= small.0.max(13 << 20), "{} bytes held for 1e4 moves, {} for 2e5", small.0, large.0);
    }
}
