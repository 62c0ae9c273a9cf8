//! What `check` counts of a run's toolpath ([`Report`]), and what it warns
//! of (axes the machine lacks, Z moves without a length offset), taken
//! piece by piece as a run hands the path on ([`PathSink`]): a program of
//! any size in bounded memory, with the same numbers, to the bit, as the
//! whole path gives.

use std::collections::BTreeMap;

use kezuri_correct::kinematics::{Kinematics, AXES};
use kezuri_geom::{AxisRanges, CycleClock, Dynamics, KnownBounds, LengthOffset, MoveKind, PathSink, Spindle, Toolpath};
use kezuri_machine::ToolEntry;
use kezuri_nc::interp::{Outcome, Thread};

use super::Ran;

/// What a run made, counted: the `check` report (the demo prints it too).
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub blocks: u64,
    pub holes: u64,
    pub statements: u64,
    pub motions: usize,
    pub feed_length_mm: f64,
    pub rapid_length_mm: f64,
    pub time_s: f64,
    /// The tool tip's extent in program coordinates over the positions the
    /// program gave ([`Toolpath::known_bounds`]).
    pub bounds: AxisRanges,
    /// U V W's extent likewise ([`Toolpath::known_bounds_uvw`]): `None`
    /// for an axis the program does not place (every program but a
    /// LinuxCNC one that names U V W).
    pub uvw_bounds: AxisRanges,
    /// Returns to a reference point and `G53` moves: not in `bounds`.
    pub machine_moves: usize,
    /// The tools that make moves, in the order they first do (0: none
    /// loaded), each with what the machine file's tool table says of it.
    pub tools: Vec<(u32, Option<ToolEntry>)>,
    /// The spindle speed's range over the cutting moves, rpm: at each
    /// one's start (the move before's end) and end
    /// ([`kezuri_geom::Move::speed`] is the speed at a move's end; under
    /// constant surface speed it changes along the move). Speeds with the
    /// spindle stopped, or on with no speed given, are not counted; `None`
    /// where none turns at a known speed.
    pub spindle_rpm: Option<(f64, f64)>,
    /// The threads cut, one a pass, in order (X a radius).
    pub threads: Vec<Thread>,
}

impl Report {
    /// The report of a run whose whole toolpath it holds.
    pub fn new(ran: &Ran) -> Report {
        let mut tally = Tally::new(&ran.machine.dynamics, &ran.machine.kinematics, false);
        tally.take(&ran.outcome.toolpath, None);
        tally.finish(&ran.outcome, &ran.machine.tools).report
    }
}

/// The tally of a run's toolpath kept as the run hands it on, piece by
/// piece: counts, lengths, cycle time, extents, tools, spindle speeds, and
/// the warnings of what the path does. It holds no move but the few the
/// cycle time still waits on ([`CycleClock`]).
#[derive(Clone, Debug)]
pub struct Tally {
    clock: CycleClock,
    motions: usize,
    feed_length_mm: f64,
    rapid_length_mm: f64,
    bounds: KnownBounds,
    uvw_bounds: KnownBounds,
    machine_moves: usize,
    tools: Vec<u32>,
    spindle_rpm: Option<(f64, f64)>,
    /// The spindle and its speed at the last move's end.
    spindle_before: Option<(Spindle, f64)>,
    axes: MissingAxes,
    /// Where the machine's tools are set with length offsets.
    unoffset_z: Option<UnoffsetZ>,
}

/// What a [`Tally`] says at the end of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Tallied {
    pub report: Report,
    /// The axes the path moves that the machine lacks ([`missing_axes`]).
    pub missing_axes: Vec<(char, u32)>,
    /// The Z moves after a tool change without the new tool's length
    /// offset (none, H0, the last tool's, or not the tool table's); none
    /// where the tally was made without length offsets.
    pub unoffset_z: Vec<String>,
}

impl Tally {
    /// A tally before the run, for a machine of `dynamics` and
    /// `kinematics`; `length_offsets`: whether its tools are set with
    /// length offsets (then Z moves without the new tool's are looked for).
    pub fn new(dynamics: &Dynamics, kinematics: &Kinematics, length_offsets: bool) -> Tally {
        Tally {
            clock: CycleClock::new(dynamics),
            motions: 0,
            feed_length_mm: 0.0,
            rapid_length_mm: 0.0,
            bounds: KnownBounds::new(true, false),
            uvw_bounds: KnownBounds::new(true, true),
            machine_moves: 0,
            tools: Vec::new(),
            spindle_rpm: None,
            spindle_before: None,
            axes: MissingAxes::new(kinematics),
            unoffset_z: length_offsets.then(UnoffsetZ::default),
        }
    }

    /// The one-line summary of a written program whose moves this
    /// tallied: `moves` of them, dwells included.
    pub fn summary(self, moves: usize) -> String {
        let (time, _) = self.clock.finish();
        crate::say::summary_line(moves, self.feed_length_mm, self.rapid_length_mm, time)
    }

    /// The report of the run that made `outcome` (its counts of blocks,
    /// statements, holes, threads), whose tool table is `tools` (the
    /// machine file's, or the one the program's comments gave after the
    /// run), with the warnings of its path.
    pub fn finish(self, outcome: &Outcome, tools: &BTreeMap<u32, ToolEntry>) -> Tallied {
        let report = Report {
            blocks: outcome.blocks,
            holes: outcome.holes,
            statements: outcome.statements,
            motions: self.motions,
            feed_length_mm: self.feed_length_mm,
            rapid_length_mm: self.rapid_length_mm,
            time_s: self.clock.finish().0,
            bounds: self.bounds.finish(),
            uvw_bounds: self.uvw_bounds.finish(),
            machine_moves: self.machine_moves,
            tools: self.tools.iter().map(|t| (*t, tools.get(t).cloned())).collect(),
            spindle_rpm: self.spindle_rpm,
            threads: outcome.threads.clone(),
        };
        let unoffset_z = self.unoffset_z.map(|u| u.finish(tools)).unwrap_or_default();
        Tallied { report, missing_axes: self.axes.found, unoffset_z }
    }
}

impl PathSink for Tally {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        self.clock.add(&piece.moves);
        self.bounds.add(piece);
        self.uvw_bounds.add(piece);
        self.axes.add(piece);
        if let Some(u) = &mut self.unoffset_z {
            u.add(piece);
        }
        let range = &mut self.spindle_rpm;
        let mut add = |rpm: f64| {
            if rpm > 0.0 && rpm.is_finite() {
                *range = Some(range.map_or((rpm, rpm), |(lo, hi)| (lo.min(rpm), hi.max(rpm))));
            }
        };
        for m in &piece.moves {
            self.motions += usize::from(!matches!(m.kind, MoveKind::Dwell(_)));
            // Summed in order from +0, as Toolpath::feed_length sums.
            if m.is_rapid() {
                self.rapid_length_mm += m.length();
            } else {
                self.feed_length_mm += m.length();
            }
            self.machine_moves += usize::from(m.is_machine());
            if !self.tools.contains(&m.tool) {
                self.tools.push(m.tool);
            }
            let cuts = matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_));
            if cuts && m.spindle != Spindle::Off {
                // The speed the move starts at, where the spindle was on before it.
                if let Some((_, speed)) = self.spindle_before.filter(|(s, _)| *s != Spindle::Off) {
                    add(speed);
                }
                add(m.speed);
            }
            self.spindle_before = Some((m.spindle, m.speed));
        }
    }
}

/// The axes `path` moves that `machine` does not have, each with the first
/// source line that moves it.
pub fn missing_axes(path: &Toolpath, machine: &Kinematics) -> Vec<(char, u32)> {
    let mut axes = MissingAxes::new(machine);
    axes.add(path);
    axes.found
}

/// [`missing_axes`] taken piece by piece.
#[derive(Clone, Debug)]
pub struct MissingAxes {
    /// Which of X Y Z A B C the machine has.
    has: [bool; 6],
    /// Each axis moved that the machine lacks, with the first line that
    /// moves it.
    pub found: Vec<(char, u32)>,
}

impl MissingAxes {
    /// None found yet, on `machine`.
    pub fn new(machine: &Kinematics) -> MissingAxes {
        MissingAxes { has: std::array::from_fn(|k| machine.has(k)), found: Vec::new() }
    }

    /// Looks for them in `piece`, the next piece of the path.
    pub fn add(&mut self, piece: &Toolpath) {
        for m in &piece.moves {
            for (k, (a, b)) in m.start.xyzabc().into_iter().zip(m.end.xyzabc()).enumerate() {
                if a != b && !self.has[k] && !self.found.iter().any(|&(axis, _)| axis == AXES[k]) {
                    self.found.push((AXES[k], m.line));
                }
            }
        }
    }
}

/// The first move that changes Z after each tool change with no tool
/// length offset of its own in force: none (or H0), the one the last tool
/// had (G43 is modal across M06), or a register other than the tool
/// table's for that tool. On a machine whose tools are set with length
/// offsets that Z is not the new tool's tip. Taken piece by piece: the
/// first Z move after each change is kept with the offsets in force, and
/// judged at the end against the tool table (which the program's comments
/// may give only after the run).
#[derive(Clone, Debug, Default)]
struct UnoffsetZ {
    tool: u32,
    /// Whether the tool changed and its first Z move is still to come.
    armed: bool,
    /// The length offset in force before the change, and now.
    before: Option<LengthOffset>,
    last: Option<LengthOffset>,
    /// The first Z move after each change: its line, tool, the offset in
    /// force and the one before the change.
    first_z: Vec<(u32, u32, Option<LengthOffset>, Option<LengthOffset>)>,
}

impl UnoffsetZ {
    fn add(&mut self, piece: &Toolpath) {
        for m in &piece.moves {
            if m.tool != self.tool {
                self.tool = m.tool;
                self.armed = self.tool != 0;
                self.before = self.last;
            }
            // Returns and G53 moves are in machine coordinates: no offset needed.
            let machine_coordinates = matches!(m.kind, MoveKind::Home | MoveKind::Machine | MoveKind::Dwell(_));
            let length = piece.frame(m).length.filter(|l| l.register != 0);
            if !machine_coordinates {
                self.last = length;
            }
            if !self.armed || machine_coordinates || (m.start.z == m.end.z && !m.named.contains(2)) {
                continue;
            }
            self.armed = false;
            self.first_z.push((m.line, self.tool, length, self.before));
        }
    }

    fn finish(self, tools: &BTreeMap<u32, ToolEntry>) -> Vec<String> {
        let mut out = Vec::new();
        for (line, tool, length, before) in self.first_z {
            let what = match (length, tools.get(&tool)) {
                (None, _) => "no tool length offset (G43 H) in force".to_string(),
                (Some(l), _) if before.is_some_and(|b| b.register == l.register) => {
                    format!("the last tool's length offset (H{}) still in force", l.register)
                }
                (Some(l), Some(e)) if e.h != l.register => {
                    format!("H{} in force where the tool table gives T{tool} H{}", l.register, e.h)
                }
                _ => continue,
            };
            out.push(format!(
                "line {line}: Z moves after the change to T{tool} with {what}: on a machine whose tools are set \
                 with length offsets this Z is not the tool tip's"
            ));
        }
        out
    }
}

#[cfg(test)]
mod tests;
