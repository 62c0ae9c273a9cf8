//! The controls' alarms and error messages, worded as each control words
//! them (LinuxCNC's from `rs274ngc_return.hh` and `interp_convert.cc`).

use super::{stop, Rules};
use crate::Error;

/// The conditions the controls alarm on.
#[derive(Clone, Copy, Debug)]
pub(super) enum Alarm {
    /// Fanuc: an arc as start-up move.
    ArcStartUp,
    /// An arc as cancel move (Fanuc), or just after G40 (LinuxCNC).
    ArcExit,
    /// A compensated move that runs against its programmed direction.
    Backwards { arc: bool, rapid: bool },
    /// An inside arc whose radius is not larger than the cutter's.
    InsideArcTooSmall,
    /// No intersection of the offset paths at an inside corner.
    NoIntersection { from_arc: bool, to_arc: bool },
    /// LinuxCNC: the entry move is not longer than the radius.
    EntryTooShort { arc: bool },
    /// LinuxCNC: no compensated entry arc exists.
    EntryArcImpossible,
    /// LinuxCNC: compensation in G19.
    PlaneUnsupported,
    /// An arc in another plane than the compensation's.
    ArcOtherPlane,
    /// G31 while compensation is on.
    Probe,
    /// G28 while compensation is on.
    Home,
    /// G53 while compensation is on.
    Machine,
    /// The tag changed without G40.
    Changed,
    /// An arc with its start or end on its centre.
    ZeroRadiusArc,
    /// A computed point is not finite.
    Numeric,
    /// LinuxCNC: an arc, or a feed round a convex corner, as the first
    /// move with plane travel after a jump of the tool centre (G70).
    AfterJump,
}

impl Alarm {
    pub(super) fn at(self, move_index: usize, rules: Rules) -> Error {
        stop(move_index, self.text(rules))
    }

    pub(super) fn text(self, rules: Rules) -> String {
        let fanuc = matches!(rules, Rules::Fanuc { .. });
        let t = match self {
            Alarm::ArcStartUp => "an arc cannot start cutter compensation: the G41/G42 start-up move must be G00 or G01 (Fanuc alarm PS0034)",
            Alarm::ArcExit if fanuc => "an arc cannot cancel cutter compensation: the G40 move must be G00 or G01 (Fanuc alarm PS0034)",
            Alarm::ArcExit => "The move just after exiting cutter compensation mode must be straight, not an arc",
            Alarm::Backwards { arc: false, .. } if fanuc => "interference: the compensated move runs backwards (Fanuc alarm PS0041)",
            Alarm::Backwards { arc: true, .. } if fanuc => "interference: the compensated arc runs backwards (Fanuc alarm PS0041)",
            Alarm::Backwards { arc: true, .. } => "Arc move in concave corner cannot be reached by the tool without gouging",
            Alarm::Backwards { rapid: true, .. } => "Straight traverse in concave corner cannot be reached by the tool without gouging",
            Alarm::Backwards { .. } => "Straight feed in concave corner cannot be reached by the tool without gouging",
            Alarm::InsideArcTooSmall if fanuc => "interference: the inside arc's radius is not larger than the cutter radius (Fanuc alarm PS0041)",
            Alarm::InsideArcTooSmall => "Tool radius not less than arc radius with comp",
            Alarm::NoIntersection { .. } if fanuc => "no intersection of the compensated paths at this corner (Fanuc alarm PS0033)",
            Alarm::NoIntersection { from_arc: false, to_arc: false } => "Zero degree inside corner is invalid for cutter compensation",
            Alarm::NoIntersection { from_arc: false, to_arc: true } => "Arc move in concave corner cannot be reached by the tool without gouging",
            Alarm::NoIntersection { from_arc: true, to_arc: false } => "Arc to straight motion makes a corner the compensated tool can't fit in without gouging",
            Alarm::NoIntersection { .. } => "Arc to arc motion makes a corner the compensated tool can't fit in without gouging",
            Alarm::EntryTooShort { arc: false } => "Length of cutter compensation entry move is not greater than the tool radius",
            Alarm::EntryTooShort { arc: true } => "Radius of cutter compensation entry arc is not greater than the tool radius",
            Alarm::EntryArcImpossible => "Tool radius not less than arc radius with comp",
            Alarm::PlaneUnsupported => "Cutter radius compensation allowed only in XY, XZ planes",
            Alarm::ArcOtherPlane if fanuc => "an arc outside the compensation plane while cutter compensation is on (Fanuc alarm PS0037)",
            Alarm::ArcOtherPlane => "Cannot change planes with cutter radius compensation on",
            Alarm::Probe if fanuc => "G31 cannot be commanded while cutter compensation is on (Fanuc alarm PS0035)",
            Alarm::Probe => "Cannot probe with cutter radius comp on",
            Alarm::Home if fanuc => "kezuri does not model G28 while cutter compensation is on: cancel it with G40 first",
            Alarm::Home => "Cannot use g28 or g30 with cutter radius comp",
            Alarm::Machine if fanuc => "kezuri does not model G53 while cutter compensation is on: cancel it with G40 first",
            Alarm::Machine => "Cannot use g53 with cutter radius comp",
            Alarm::Changed if fanuc => "kezuri does not model a change of side, offset or plane while cutter compensation is on: cancel it with G40 first",
            Alarm::Changed => "Cannot turn cutter radius comp on when on",
            Alarm::ZeroRadiusArc => "an arc whose start or end lies on its centre cannot be compensated",
            Alarm::Numeric => "cutter compensation produced a point that is not a number (a degenerate corner)",
            Alarm::AfterJump => "kezuri does not model an arc, or a feed round a convex corner, as the first move along the plane after a G70 under cutter compensation: LinuxCNC compensates that move from the end of the G70's profile, where reading the profile left its position",
        };
        t.to_string()
    }
}
