//! Running a program: its whole toolpath at the end, or handed on piece by
//! piece as it is made.

use kezuri_geom::PathSink;

use super::{control, Library, Outcome, Settings, State};
use crate::ast::Program;
use crate::source::Sources;

/// Runs program unit `main` of `program` and returns the toolpath with its
/// diagnostics. Subprograms are looked up first in `program`, then in
/// `library` (whose files are added to `sources` and parsed into `program`).
pub fn run(
    program: &mut Program,
    sources: &mut Sources,
    main: usize,
    library: &mut dyn Library,
    settings: &Settings,
) -> Outcome {
    let mut interp = control::Interp::new(program, sources, library, settings.clone(), None);
    interp.run(main);
    interp.finish()
}

/// Runs program unit `main` of `program` as [`run`] does, handing the
/// toolpath to `sink` piece by piece as it is made (a piece of some
/// [`Settings::piece_moves`] moves where the path may be cut: see
/// [`PathSink`]), so
/// that the moves of a program of any size are never held together. The
/// outcome's `toolpath` is then empty and its `programmed` `None`: both
/// went to the sink.
pub fn run_into(
    program: &mut Program,
    sources: &mut Sources,
    main: usize,
    library: &mut dyn Library,
    settings: &Settings,
    sink: &mut dyn PathSink,
) -> Outcome {
    let mut interp = control::Interp::new(program, sources, library, settings.clone(), Some(sink));
    interp.run(main);
    interp.finish()
}

impl State {
    /// Whether the path made so far may be cut here and its moves but the
    /// last handed on: nothing run later refers back to them. Not while
    /// cutter radius compensation has moves recorded (the centre path of a
    /// stretch is made once it is done with, [`State::comp_flush`]), a
    /// canned cycle's holes wait to be kept, or on a
    /// lathe (a corner, a single cycle or a contour may still change the
    /// last moves).
    pub(super) fn may_hand_on(&self) -> bool {
        self.radius.unused() && self.hole.settled() && self.turning.is_none() && self.profile.is_none()
    }
}
