//! A simulation fed its moves piece by piece, as a run makes them
//! ([`PathSink`]): a program of any size is cut holding only the grid and
//! the piece at hand.
//!
//! Each piece's segments are cut as the whole path's would be: over every
//! band of rows, in program order, each band cut in mm and rounded to the
//! nanometre once per piece. Rounding is monotone, so the lowest of heights
//! rounds to the lowest of their roundings: the cells come out the same,
//! to the nanometre, whatever the pieces, and so do the tool that lowered
//! each cell last and the volumes (whole nanometres summed). A segment is
//! narrowed by the next one where the path runs straight on
//! (`segments::continuations`), so the last segment of a piece waits for
//! the next piece. A rapid's depth is measured from the cell as it stood
//! before the rapid, rounded to the nanometre where an earlier piece cut it:
//! the same to half a nanometre.

use kezuri_geom::{PathSink, Toolpath};

use super::segments::{continuations, Segment, Segmenter, Unplaced};
use super::stock::{Start, ZMap};
use super::tools::{Tooling, UNCUT};
use super::{bad_tolerance, cut, out_of_memory, Cut, RapidHit, SimOptions, SimReport};
use crate::error::Error;
use kezuri_geom::limits;

/// A simulation over a grid (or a tile of one) taking the moves of a path
/// in order, piece by piece ([`Cutting::add`], or as a [`PathSink`]).
pub struct Cutting<'a> {
    zmap: &'a mut ZMap,
    cut_by: Vec<u8>,
    options: SimOptions,
    /// The stock the grid was made from, for the height a cell had before
    /// the program; `None`: the grid as it is when the first piece comes.
    start: Option<Start<'a>>,
    /// The grid's highest cell before cutting.
    top: f64,
    segmenter: Segmenter<'a>,
    /// Segments made and not cut yet: the last one waits for the next.
    waiting: Vec<Segment>,
    unplaced: Vec<Unplaced>,
    cut: Cut,
    /// The first error: nothing more is cut after it.
    error: Option<Error>,
    /// Told how much of each piece's work is done.
    pub progress: &'a (dyn Fn(u64, u64) + Sync),
}

/// What a cutting found, before it is a report: the cuts of the tiles of
/// one grid add up ([`Cuts::add`]).
#[derive(Clone, Debug)]
pub struct Cuts {
    report: SimReport,
    cut: Cut,
}

impl Cuts {
    /// `tile`'s cut added: the rapids and drill feeds that cut there and
    /// what each tool removed (the moves are the same passes' moves).
    pub fn add(&mut self, tile: Cuts) {
        self.cut.add(tile.cut);
    }

    /// The report, each tool's volume on cells of `res` mm; its `cut_by`
    /// empty.
    pub fn report(self, res: f64) -> SimReport {
        let mut report = self.report;
        self.cut.into_report(&mut report, res);
        report
    }
}

impl<'a> Cutting<'a> {
    /// A cutting of `zmap` with `tooling`, `first` the first tool the
    /// program loads (0 for none: see [`super::cutting_tools`]; `None`
    /// where it is not known before the run: with [`Tooling::One`]). `start`:
    /// the stock `zmap` was made from, which says where a rapid from an
    /// unknown position ends in the stock as it stood before the program;
    /// without it, the grid as the cutting finds it (the same where the
    /// whole path comes as one piece).
    pub fn new(
        tooling: Tooling<'a>,
        zmap: &'a mut ZMap,
        options: &SimOptions,
        first: Option<u32>,
        start: Option<Start<'a>>,
    ) -> Result<Cutting<'a>, Error> {
        if limits::length(options.chord_tolerance, "").is_err() {
            return Err(bad_tolerance(options.chord_tolerance));
        }
        let mut cut_by = Vec::new();
        if cut_by.try_reserve_exact(zmap.cells()).is_err() {
            return Err(out_of_memory(zmap.cells()));
        }
        cut_by.resize(zmap.cells(), UNCUT);
        let top = zmap.range().1;
        Ok(Cutting {
            zmap,
            cut_by,
            options: *options,
            start,
            top,
            segmenter: Segmenter::new(tooling, options.chord_tolerance, first),
            waiting: Vec::new(),
            unplaced: Vec::new(),
            cut: Cut::default(),
            error: None,
            progress: &|_, _| {},
        })
    }

    /// The next piece of the path, cut: all its segments but the last,
    /// which waits for the next piece. An error stops the cutting.
    pub fn add(&mut self, piece: &Toolpath) -> Result<(), Error> {
        self.add_piece(piece, false)
    }

    /// The last piece of the path (or the whole path), cut whole.
    pub fn add_last(&mut self, piece: &Toolpath) -> Result<(), Error> {
        self.add_piece(piece, true)
    }

    fn add_piece(&mut self, piece: &Toolpath, last: bool) -> Result<(), Error> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        let done = self.segmenter.add(&piece.moves, piece.unknown_start, &mut self.waiting, &mut self.unplaced);
        let wait = usize::from(!last);
        let done = done.and_then(|()| self.cut_waiting(self.waiting.len().saturating_sub(wait)));
        if let Err(e) = &done {
            self.error = Some(e.clone());
        }
        done
    }

    /// Cuts the first `n` waiting segments, and judges the rapids from an
    /// unknown position.
    fn cut_waiting(&mut self, n: usize) -> Result<(), Error> {
        self.judge_unplaced()?;
        if n == 0 {
            return Ok(());
        }
        continuations(&mut self.waiting, &self.segmenter.slots.shapes);
        let shapes = &self.segmenter.slots.shapes;
        let (segs, options) = (&self.waiting[..n], &self.options);
        let found = cut(segs, shapes, self.zmap, &mut self.cut_by, options, self.top, self.progress)?;
        self.cut.add(found);
        self.waiting.drain(..n);
        Ok(())
    }

    /// A rapid from an unknown position is not simulated, but if it ends
    /// inside the stock (as it stands before the program) it went through it.
    fn judge_unplaced(&mut self) -> Result<(), Error> {
        let z = &self.zmap;
        let (nx, ny, res, x0, y0, row0) = (z.nx, z.ny, z.res, z.x0, z.y0, z.first_row);
        for u in std::mem::take(&mut self.unplaced) {
            let e = u.end;
            let (i, j) = (((e[0] - x0) / res).floor(), ((e[1] - y0) / res).floor() - row0 as f64);
            if !(i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny) {
                continue;
            }
            let (i, j) = (i as usize, j as usize);
            let height = match &self.start {
                Some(start) => start.rows(&self.options, row0 + j..row0 + j + 1)?.height(i, 0),
                None => self.zmap.height(i, j),
            };
            let depth = height - e[2];
            if nx > 0 && depth > self.options.rapid_tolerance {
                self.cut.hits.push(RapidHit { index: u.index as usize, line: u.line, depth });
            }
        }
        Ok(())
    }

    /// The cutting done: what it found, and the tool that lowered each cell
    /// of the grid last (as [`SimReport::cut_by`]).
    pub fn finish(mut self) -> Result<(Cuts, Vec<u8>), Error> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.cut_waiting(self.waiting.len())?;
        let report = self.segmenter.finish()?;
        Ok((Cuts { report, cut: self.cut }, self.cut_by))
    }
}

impl PathSink for Cutting<'_> {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        // The error is kept for `finish`.
        let _ = self.add(piece);
    }
}

/// A cutting lent to a run for one pass (a tile's).
impl PathSink for &mut Cutting<'_> {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        (**self).take(piece, programmed);
    }
}
