//! Toolpath to G-code program text: Fanuc, LinuxCNC and GRBL.
//!
//! [`program`] writes one block per line and only what changes: modal words
//! (the motion G code, the plane, `F`, `S`) are written when their value
//! changes, axis words when the rounded coordinate changes. Numbers are
//! rounded to [`WriteOptions::digits`] decimals and trailing zeros trimmed;
//! every axis and feed word carries a decimal point (`X10.`, `X0.`), in every
//! dialect: a Fanuc control reads `X10` as 10 increments (0.010 mm), and a
//! program written for LinuxCNC or GRBL is often read by a Fanuc or by a
//! tool set for one; LinuxCNC and GRBL read `X10.` as 10 mm. A rounded zero
//! is written `0.`, never `-0.`. Programs are
//! in mm (`G21`) or inches (`G20`, [`WriteOptions::inch`]), absolute (`G90`)
//! or incremental (`G91`, [`WriteOptions::incremental`], below), feed per
//! minute (`G94`).
//!
//! Decisions a reader might not guess:
//! - Where the control's position is not known (at the start of the
//!   program, and after a tool change, whose macro may move the axes), a
//!   move writes the axes it names ([`kezuri_geom::Move::named`]): every
//!   axis for a generated toolpath, only the axes of the source block for an
//!   interpreted one, so an expanded `G00 X.. Y..` never gains a `Z` at the
//!   model's guess of where the spindle is. After a tool change the motion
//!   code, the plane and `F` are written again too: a Fanuc tool change
//!   macro may have changed them.
//! - Positions are written in program coordinates of the move's
//!   [`kezuri_geom::Frame`]: its work offset (`G54`…`G59`) and tool length
//!   offset (`G43`/`G44 H`, or `G43.1 Z` with the value on GRBL) are
//!   commanded again when they change, so the control applies its own
//!   offsets; a work offset the program changed (`G10 L2`, `#5221…`) is set
//!   again with `G10 L2`. `G92` and external offset shifts are baked into
//!   the positions.
//! - A return to the reference point is `G91 G28` of its axes then `G90`;
//!   a move in machine coordinates is `G53 G00` with the spindle gauge line's
//!   machine position. Neither becomes a move to the model's idea of where
//!   the reference point is.
//! - Straight moves (rapid, feed, probe) go from wherever the tool is to
//!   their end: their start is not written. An arc needs its start, so an arc
//!   that does not start where the tool is (as the first move, after a tool
//!   change, or after a gap in the toolpath) is preceded by a straight feed
//!   move to its start.
//! - Arc centres are written as `I J K` relative to the start, as Fanuc,
//!   LinuxCNC and GRBL read them, rounded; when the rounded end then misses
//!   the circle by more than half a unit of the last digit or 0.001 mm, the
//!   centre is the one of the nine grid points around it that puts the end
//!   best on the circle (GRBL rejects an arc whose radii differ by 0.005 mm
//!   and 0.1 %).
//!   An arc whose rounded end equals its start is a full circle if it sweeps
//!   more than half a turn, otherwise it is too small for the digits and is
//!   written as a straight move; so is an arc that rounding would turn the
//!   other way round. Extra helical turns ([`kezuri_geom::Arc::turns`]) are
//!   written as one full circle per turn.
//! - A move that changes nothing at the written precision writes nothing.
//! - Spindle, coolant and tool changes are written on their own blocks before
//!   the move that needs them, one M code per block (a Fanuc control without
//!   the multiple-M option accepts only one). A tool change stops the spindle
//!   and the coolant first (`M05`, `M09`) and they are switched on again for
//!   the next move. GRBL has no tool changer: there a tool change is a
//!   comment naming the tool and an `M0` pause, to change the tool by hand
//!   and resume.
//! - Mist coolant is `M07`; GRBL accepts `M7` only when built with
//!   `ENABLE_M7`.
//! - Probe moves are `G31` (Fanuc) or `G38.2` (LinuxCNC, GRBL); the motion G
//!   code is written again on the move after.
//! - Dwells are `G04 P<milliseconds>` (Fanuc) or `G4 P<seconds>`.
//! - `N` numbers, when asked for, count up by their step and start again at
//!   the step after 99999, the largest a Fanuc control reads.
//!
//! Incremental programs ([`WriteOptions::incremental`]) write the same
//! motions as absolute ones, block for block, with the axis words of the
//! motion blocks as increments while the control is in `G91`:
//! - A motion block is written in `G91` only where the control's position on
//!   every axis the program writes is exact: it was written by the program
//!   (absolute, or as increments from an exact position) and nothing moved
//!   it since. Elsewhere the block is written in `G90`, exactly as the
//!   absolute program writes it. So the first positioning is absolute, and
//!   `G91` comes on the first motion block after the one that made X, Y and
//!   Z (and any rotary axis the program turns) known; the `G90` or `G91` is
//!   written on the motion block that needs it, not on a block of its own.
//! - An increment is the difference of the rounded absolute positions the
//!   absolute program writes, counted in units of the last digit, so the
//!   increments add up to those positions exactly, with no drift however
//!   many moves there are; an axis with a zero increment is not written.
//!   Arcs in `G91` have incremental end points; `I J K` are relative to the
//!   start in both modes.
//! - What leaves a position inexact, and so the next motion block in `G90`:
//!   a return to the reference point (`G91 G28`, which leaves the control in
//!   `G91`), a `G53` move (written `G90 G53 G00`: a control reads `G53` in
//!   absolute only), a probe move (it stops where it touches, not at its
//!   end; it is written in the mode the control is in), a change of frame
//!   (its `G10 L2` and `G54`…/`G43` blocks are written in `G90`: in `G91` a
//!   `G10 L2` adds to the offset) and a tool change (written after a `G90`
//!   block, and `G90` is written again after it, as the macro may change the
//!   mode). Absolute blocks follow until every axis has been written again.
//! - `G90` is written before the program end, to leave the control in
//!   absolute.

use kezuri_geom::{Axes, AxisSet, Frame, LengthOffset, Move, MoveKind, ToolState, Toolpath};

use super::blocks::{Motion, Writer};
use super::options::WriteOptions;
use crate::Error;

/// Writes `toolpath` as a program in `options.dialect`.
///
/// ```
/// use kezuri_geom::{Axes, Frame, LengthOffset, Move, MoveKind, Toolpath};
/// use kezuri_nc::write::{program, Dialect, WriteOptions};
/// let at = |x, y, z| Axes { x, y, z, ..Axes::ZERO };
/// let mut path = Toolpath::default();
/// path.push(Move { kind: MoveKind::Rapid, end: at(10.0, 0.0, 5.0), ..Move::default() });
/// let (start, end) = (at(10.0, 0.0, 5.0), at(10.0, 0.0, -0.5));
/// path.push(Move { kind: MoveKind::Feed, start, end, feed: 300.0, ..Move::default() });
/// let text = program(&path, &WriteOptions::default()).unwrap();
/// assert!(text.contains("G00 X10. Y0. Z5.\nG01 Z-0.5 F300.\n"));
/// let grbl = program(&path, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() }).unwrap();
/// assert!(grbl.contains("G0 X10. Y0. Z5.\nG1 Z-0.5 F300.\n"));
/// ```
pub fn program(toolpath: &Toolpath, options: &WriteOptions) -> Result<String, Error> {
    let writer = ProgramWriter::new(options)?;
    let axes = writer.w.axes_ahead(&toolpath.moves, toolpath.unknown_start);
    let mut writer = writer.with_axes(axes).with_tool_order(tool_order(toolpath));
    let mut text = writer.piece(toolpath, None)?;
    text.push_str(&writer.finish()?);
    Ok(text)
}

/// The tools `toolpath` loads, in order: what a post that pre-stages the
/// next tool (haas) must know ahead ([`ProgramWriter::with_tool_order`]).
fn tool_order(toolpath: &Toolpath) -> Vec<u32> {
    let mut loads: Vec<u32> = Vec::new();
    for m in toolpath.moves.iter().filter(|m| m.tool != 0) {
        if loads.last() != Some(&m.tool) {
            loads.push(m.tool);
        }
    }
    loads
}

/// A program written as its toolpath comes, piece by piece (a run's
/// [`PathSink`](kezuri_geom::PathSink) pieces, in order): the pieces'
/// texts and the end's joined are the text [`program`] writes of the
/// whole path, or its error.
///
/// Nothing in a piece's text depends on moves still to come, but for two
/// things the caller may know ahead and tell it:
/// - the rotary axes and U V W the program uses
///   ([`ProgramWriter::with_axes`]): such an axis is written from the
///   start, as [`program`] writes every axis the whole path turns: a made
///   path's first positioning names it (`G00 X0. Y0. Z50. A0.`), a
///   `G10 L2` gives its origin, an incremental program's `G91` waits
///   until it is written. Any other is written from the first move that
///   turns it (or, in a program read, names it). One the dialect has not
///   is refused at that move.
/// - the tools it loads, in order ([`ProgramWriter::with_tool_order`]),
///   for a post that pre-stages the next tool (haas).
///
/// The control's limits ([`WriteOptions::block_limit`],
/// [`WriteOptions::byte_limit`]) are checked at the end, over everything
/// handed on, as they are of a whole program.
///
/// ```
/// use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
/// use kezuri_nc::write::{program, ProgramWriter, WriteOptions};
/// let at = |x| Axes { x, ..Axes::ZERO };
/// let path = Toolpath::from((1..=4).map(|i| Move { kind: MoveKind::Feed, end: at(i as f64), feed: 100.0, ..Move::default() }).collect::<Vec<_>>());
/// let options = WriteOptions::default();
/// let mut writer = ProgramWriter::new(&options).unwrap();
/// let mut text = String::new();
/// let mut rest = path.clone();
/// while !rest.moves.is_empty() {
///     text += &writer.piece(&rest.split_before(1), None).unwrap();
/// }
/// text += &writer.finish().unwrap();
/// assert_eq!(text, program(&path, &options).unwrap());
/// ```
pub struct ProgramWriter {
    w: Writer,
    /// Program units per mm.
    unit: f64,
    /// Whether a piece came: the first tells whether the path was made.
    started: bool,
    /// The moves of the pieces so far: the index of the next piece's first.
    done: usize,
    /// The end (as an index from the first move) of the moves the last
    /// kept block makes itself (a tapping cycle).
    covered: usize,
    /// The last move's end, machine coordinates in program units.
    last: Option<Axes>,
}

impl ProgramWriter {
    /// A writer of a program in `options.dialect`, its options checked;
    /// the header comes with the first piece's text.
    pub fn new(options: &WriteOptions) -> Result<ProgramWriter, Error> {
        let mut w = Writer::new(options)?;
        w.header(options);
        let unit = if options.inch { 1.0 / 25.4 } else { 1.0 };
        Ok(ProgramWriter { w, unit, started: false, done: 0, covered: 0, last: None })
    }

    /// The axes beyond X Y Z (A B C, U V W) the program turns or names,
    /// known ahead: each is written from the start, its position unknown
    /// until the program writes it. Those the dialect has not are left to
    /// the moves: refused at the first that turns one.
    pub fn with_axes(mut self, axes: AxisSet) -> ProgramWriter {
        for k in 3..Axes::COUNT {
            if axes.contains(k) && self.w.has_axis(k) {
                self.w.use_axis(k);
            }
        }
        self
    }

    /// The tools the program loads, in order: a post that pre-stages the
    /// next tool (haas) names it after each tool change. Without it, that
    /// post pre-stages none.
    pub fn with_tool_order(mut self, tools: Vec<u32>) -> ProgramWriter {
        self.w.loads = tools;
        self
    }

    /// The text of `piece`, the next piece of the toolpath, or of
    /// `programmed` where it comes with one: the programmed contour of
    /// the same stretch under cutter radius compensation, which a program
    /// gives the control (its G41/G42 D and G40 kept). The first piece's
    /// text begins with the header. After an error the program is
    /// refused: write nothing more with this writer.
    pub fn piece(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) -> Result<String, Error> {
        let path = programmed.unwrap_or(piece);
        let unit = self.unit;
        let w = &mut self.w;
        if !self.started {
            w.generated = !path.unknown_start;
            self.started = true;
        }
        w.out.reserve(path.moves.len() * 24);
        let mut kept = path.kept.iter().peekable();
        // The last move's frame: its number, the frame, its zero and the
        // frame in the program's units (most moves share it).
        let mut last_frame: Option<(u32, Frame, Axes, Frame)> = None;
        for (i, machine) in path.moves.iter().enumerate() {
            let index = self.done + i;
            w.at = (index, machine.line);
            w.take_axes(machine)?;
            let (frame, zero, framed) = match last_frame {
                Some((k, frame, zero, framed)) if k == machine.frame => (frame, zero, framed),
                _ => {
                    let frame = path.frame(machine);
                    last_frame = Some((machine.frame, frame, frame.zero(), in_units(frame, unit)));
                    (frame, frame.zero(), in_units(frame, unit))
                }
            };
            let m = &in_program(machine, zero, unit);
            if index < self.covered {
                // Made by the kept block before it, spindle reversals and all.
                w.made(m.end)?;
                continue;
            }
            // The kept blocks before this move, each in the tool, spindle and
            // coolant state it came in; a cycle in the move's frame.
            w.next_rapid_z = None;
            while let Some(k) = kept.next_if(|k| k.before <= i) {
                w.state(k.state)?;
                if k.moves > 0 {
                    w.frame(framed, self.last)?;
                }
                w.kept(k)?;
                self.covered = self.covered.max(self.done + k.before + k.moves);
            }
            w.next_rapid_z = (m.kind == MoveKind::Rapid).then_some(m.end.z);
            w.state(ToolState::of(machine))?;
            w.frame(framed, self.last)?;
            self.last = Some(scaled(machine.end, Axes::ZERO, unit));
            if index < self.covered {
                // A kept block (a tapping cycle) makes this move itself.
                w.made(m.end)?;
                continue;
            }
            w.reckon(m)?;
            match m.kind {
                MoveKind::Rapid => w.straight(Some(Motion::Rapid), m.end, None, m.named)?,
                MoveKind::Feed => w.straight(Some(Motion::Linear), m.end, Some(m.feed), m.named)?,
                MoveKind::Probe => w.straight(None, m.end, Some(m.feed), m.named)?,
                MoveKind::Dwell(seconds) => w.dwell(seconds)?,
                MoveKind::Arc(arc) => w.arc(m, arc)?,
                MoveKind::Home => w.home(m.named, m.end)?,
                MoveKind::Machine => {
                    let lift = frame.length.map_or(0.0, |l| l.signed());
                    let gauge = Axes { z: machine.end.z + lift, ..machine.end };
                    w.machine(m.named, scaled(gauge, Axes::ZERO, unit), m.end)?
                }
            }
        }
        // Blocks after the last move (a piece's come with the next piece).
        for k in kept {
            w.state(k.state)?;
            w.kept(k)?;
        }
        self.done += path.moves.len();
        Ok(self.w.hand_out())
    }

    /// The rest of the program: the end and the closing line. Refused
    /// where the whole program breaks the control's limits.
    pub fn finish(mut self) -> Result<String, Error> {
        self.w.finish()
    }
}

/// What a made program written as text (the measuring programs) gets from
/// the post around its own blocks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MadeText {
    /// The header, the safe start and the change to the program's tool
    /// (with its retract): everything before the first move.
    pub start: String,
    /// The words that apply the tool's length offset (`G43 H1`), to be
    /// written on the first block that moves Z; `None` where the post
    /// applies none.
    pub length: Option<String>,
    /// The end: spindle and coolant off, retract, home, program end.
    pub end: String,
}

/// The post's start, tool change to `tool` and end of `options` (which
/// must have a [`Setup`](super::Setup)), for a program kezuri writes as text.
///
/// ```
/// use kezuri_nc::write::{made_text, WriteOptions};
/// let haas = WriteOptions { title: Some("PROBE".into()), ..WriteOptions::preset("haas").unwrap() };
/// let t = made_text(&haas, 9).unwrap();
/// assert!(t.start.ends_with("G53 G00 Z0.\nT9 M06\n"), "{}", t.start);
/// assert_eq!(t.length.as_deref(), Some("G43 H9"));
/// assert_eq!(t.end, "G53 G00 Z0.\nG53 G00 X0. Y0.\nM30\n%\n");
/// ```
pub fn made_text(options: &WriteOptions, tool: u32) -> Result<MadeText, Error> {
    let mut w = Writer::new(options)?;
    w.header(options);
    w.state(ToolState { tool, ..ToolState::default() })?;
    let length = w.take_pending_length();
    let start = std::mem::take(&mut w.out);
    let end = w.finish()?;
    Ok(MadeText { start, length, end })
}

/// A dwell of `seconds` as `options` writes it (`G04 P500`, `G04 X0.5`,
/// `G4 P0.5`), one block without its line end, for a program kezuri writes
/// as text.
///
/// ```
/// use kezuri_nc::write::{dwell_block, WriteOptions};
/// let fanuc = WriteOptions::preset("fanuc").unwrap();
/// assert_eq!(dwell_block(&fanuc, 0.5).unwrap(), "G04 P500");
/// assert_eq!(dwell_block(&WriteOptions { dwell_ms: Some(false), ..fanuc }, 0.5).unwrap(), "G04 X0.5");
/// assert_eq!(dwell_block(&WriteOptions::preset("linuxcnc").unwrap(), 0.5).unwrap(), "G4 P0.5");
/// ```
pub fn dwell_block(options: &WriteOptions, seconds: f64) -> Result<String, Error> {
    let mut w = Writer::new(&WriteOptions { line_numbers: None, ..options.clone() })?;
    w.dwell(seconds)?;
    Ok(w.out.trim_end().to_string())
}

/// `p - origin`, its linear axes times `unit` (rotary axes stay degrees).
fn scaled(p: Axes, origin: Axes, unit: f64) -> Axes {
    let (p, o) = (p.to_array(), origin.to_array());
    Axes::from_array(std::array::from_fn(|k| (p[k] - o[k]) * if Axes::is_linear(k) { unit } else { 1.0 }))
}

/// `frame` with its lengths times `unit`.
fn in_units(frame: Frame, unit: f64) -> Frame {
    Frame {
        origin: scaled(frame.origin, Axes::ZERO, unit),
        shift: scaled(frame.shift, Axes::ZERO, unit),
        length: frame.length.map(|l| LengthOffset { value: l.value * unit, given: l.given.map(|g| g * unit), ..l }),
        ..frame
    }
}

/// `m` in program coordinates: relative to the work offset's `origin`,
/// lengths (and the feed of a move with linear travel) times `unit`.
fn in_program(m: &Move, origin: Axes, unit: f64) -> Move {
    if origin == Axes::ZERO && unit == 1.0 {
        return *m;
    }
    let kind = match m.kind {
        MoveKind::Arc(arc) => {
            let c = arc.center;
            let centre = scaled(Axes { x: c[0], y: c[1], z: c[2], ..Axes::ZERO }, origin, unit);
            MoveKind::Arc(kezuri_geom::Arc { center: centre.xyz(), ..arc })
        }
        kind => kind,
    };
    let feed = if m.length() > 0.0 { m.feed * unit } else { m.feed };
    Move { kind, start: scaled(m.start, origin, unit), end: scaled(m.end, origin, unit), feed, ..*m }
}
