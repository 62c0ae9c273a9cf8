//! Which axes are where the program put them ([`Move::unknown`]): not at
//! the start of the run until a move names them, not after a return to a
//! reference point or a `G53` move that the machine file does not place
//! (`Settings::reference_given`) until an absolute move names them again.
//! The interpreter says it; pictures, figures and the simulation read it.
//!
//! [`Move::unknown`]: kezuri_geom::Move::unknown

use kezuri_geom::{AxisSet, MoveKind};

use super::modal::{Distance, GCode};
use super::words::Words;
use super::State;

impl State {
    /// Before a move of `kind` naming `named` is pushed: the axes it
    /// places, and those it takes to a machine position (taken as unknown;
    /// [`State::placed_if`] says otherwise where the machine file places it).
    pub(super) fn place(&mut self, kind: MoveKind, named: AxisSet) {
        match kind {
            MoveKind::Dwell(_) => return,
            MoveKind::Home | MoveKind::Machine => self.at_machine = AxisSet(self.at_machine.0 | named.0),
            // An increment from a machine position is still one.
            _ if self.modal.distance == Distance::Absolute => {
                // A lathe's U W H are increments even in an absolute block.
                let absolute = named.0 & !self.lathe_increments().0;
                self.at_machine = AxisSet(self.at_machine.0 & !absolute)
            }
            _ => {}
        }
        // From the start, any move that names an axis places it: the
        // program's increments count from where it started.
        self.unplaced = AxisSet(self.unplaced.0 & !named.0);
    }

    /// After a return or a `G53` move on `axes`: where the machine file
    /// gives the point (`given`), the move and the axes are placed.
    pub(super) fn placed_if(&mut self, given: bool, axes: AxisSet) {
        if !given {
            return;
        }
        self.at_machine = AxisSet(self.at_machine.0 & !axes.0);
        if let Some(m) = self.toolpath.moves.last_mut() {
            m.unknown = AxisSet(self.unplaced.0 | self.at_machine.0);
        }
    }

    /// `G92`: the named axes are where the program says they are, and so
    /// is the end of the move that brought the tool there.
    pub(super) fn placed_by_g92(&mut self, w: &Words) {
        let named = w.axes();
        self.at_machine = AxisSet(self.at_machine.0 & !named.0);
        self.unplaced = AxisSet(self.unplaced.0 & !named.0);
        if let Some(m) = self.toolpath.moves.last_mut() {
            m.unknown = AxisSet(m.unknown.0 & !named.0);
        }
    }

    /// Whether the machine file gives the reference point of `G28` or of
    /// `G30` (P1 G28's, none or P2 the 2nd, P3, P4).
    pub(super) fn reference_given(&self, code: GCode, w: &Words) -> bool {
        let k = match (code, w.get(b'P')) {
            (GCode::Home, _) | (_, Some(1.0)) => 0,
            (_, Some(3.0)) => 2,
            (_, Some(4.0)) => 3,
            _ => 1,
        };
        self.settings.reference_given[k]
    }
}
