//! Program model to toolpath: a Fanuc-style control in software.
//!
//! The interpreter walks blocks by index. Macro statements (`#1=…`, `IF`,
//! `GOTO`, `WHILE … DO … END`) change variables and the block pointer; NC
//! blocks apply completely or not at all: every word is evaluated first
//! (a word whose variable is vacant is left out, as on the control), then
//! modal G codes, feed/speed/tool, motion, and last the calls and the end of
//! program. Calls (`M98`, `G65`, `G66`, `G66.1`) push frames; `M99` pops them.
//! Nothing here does I/O: subprograms outside the parsed files come from a
//! [`Library`], the clock is [`Settings::clock_seed`], `DPRNT` lines are
//! returned in [`Outcome::prints`].

mod block;
pub mod comp;
mod control;
mod coords;
mod cycle;
mod hint;
mod lathe;
mod length;
mod modal;
mod motion;
mod offsets;
mod params;
mod pieces;
mod placed;
mod pocket;
mod radius;
mod signals;
mod spline;
mod threads;
mod value;
mod vars;
mod words;

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use kezuri_geom::{Axes, AxisSet, Coolant, Frame, Kept, LengthOffset, Spindle, ToolState, Toolpath};

use crate::offsets::{EXTRA_OFFSETS, EXTRA_OFFSET_COUNT};
use crate::source::{Diagnostic, SourceFile, Span};
pub use coords::{Control, CoordSettings};
pub use cycle::CycleSettings;
pub use lathe::nose::{nose_centre_path, TipNumbers};
pub use lathe::{GCodeSystem, Lathe, Nose, Thread, XMode};
pub use modal::{Cycle, CycleReturn, Distance, FeedMode, GCode, Modal, ModalCallKind, Motion, RadiusComp, Units};
pub use pieces::{run, run_into};
pub use signals::check_inputs;
use signals::Outputs;
pub use value::Value;
pub use vars::MacroVariables;
use vars::{Clock, Locals};

/// How a word written without a decimal point is read on axis addresses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegerInput {
    /// A count of the least input increment (0.001 mm, 0.0001 inch, 0.001°),
    /// as a Fanuc control with decimal-point programming off: `X100` is
    /// 0.1 mm. The default; such words get a warning.
    #[default]
    Increments,
    /// Whole units, as LinuxCNC and GRBL read them: `X100` is 100 mm. The
    /// dwell `G4 P` is then in seconds too, as those controls read it.
    Units,
}

/// Everything a run needs besides the program.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The language the program is read in (the parser's too).
    pub dialect: crate::Dialect,
    /// How axis words without a decimal point are read.
    pub integer_input: IntegerInput,
    /// `None`: the clock advances 16 ms per read; `Some(seed)`: by a
    /// reproducible pseudo-random 1–1000 ms per read.
    pub clock_seed: Option<u64>,
    /// Most statements run again (after a jump back, in a loop's next turn,
    /// in a subprogram or macro called again) before the run is stopped as
    /// a runaway loop. A program read straight through is never stopped,
    /// whatever its size.
    pub step_limit: u64,
    /// How many moves a run handing its path on ([`run_into`]) gathers
    /// before it hands them on, where it may (4096; fewer only to test).
    pub piece_moves: usize,
    /// Skip blocks that start with `/` (the block delete switch is on).
    pub block_delete: bool,
    /// Tool length offsets by H number (mm).
    pub tool_lengths: BTreeMap<u32, f64>,
    /// Tool radius offsets by D number (mm); with LinuxCNC rules by tool
    /// number (`G41 D<tool>`, or the loaded tool's).
    pub tool_radii: BTreeMap<u32, f64>,
    /// The machine file the tool table comes from, named where a tool
    /// length it lacks is warned of (`add length = <mm> under [tools.T1]
    /// in FILE`).
    pub tool_file: Option<String>,
    /// The tool whose entry holds each H register that is not its own
    /// number (`[tools.T5] h = 15`: 15 → 5), for the same warning.
    pub length_owners: BTreeMap<u32, u32>,
    /// Which control's cutter radius compensation (G41/G42) to reproduce.
    pub comp_rules: comp::Rules,
    /// `true` where the tool-centre path is needed (a simulation, a program
    /// written with the compensation applied): a compensation register the
    /// tool table lacks is then an error. `false`: a warning, and radius 0.
    pub radii_required: bool,
    /// Work offsets G54 … G59, machine coordinates of each work zero.
    pub work_offsets: [Axes; 6],
    /// Additional work offsets G54.1 P (Fanuc has P1–P48, Haas G154 P1–P99; kezuri takes P1–P99),
    /// by P: machine coordinates of each work zero.
    pub extra_work_offsets: BTreeMap<u32, Axes>,
    /// Machine position of the reference point that G28 returns to.
    pub home: Axes,
    /// Whether the machine file gives G28's reference point (`home`) and
    /// G30's 2nd to 4th: a return there ends at a known place, and a `G53`
    /// move too where G28's is given (the machine described, its work
    /// offsets taken as given). Otherwise such a move ends at a machine
    /// position kezuri does not know ([`kezuri_geom::Move::unknown`]).
    pub reference_given: [bool; 4],
    /// Canned cycle parameters (peck retract and clearance, boring shift).
    pub cycles: CycleSettings,
    /// Rules of coordinate systems that depend on the control, and the
    /// 2nd to 4th reference points (`docs/coordinates.md`).
    pub coords: CoordSettings,
    /// Which common variables exist, which are kept over a reset, and the
    /// starting values of those.
    pub macro_variables: MacroVariables,
    /// Input signals by variable number: bits #1000–#1031 (0 or 1) and
    /// words #1033–#1035. One that is not here reads 0, with a warning.
    pub input_signals: BTreeMap<u32, f64>,
    /// Starting values of numbered parameters in the linuxcnc and grbl
    /// dialects (LinuxCNC's `.var` file): #5161… the G28 position, #5221…
    /// the work offsets, #5220 the coordinate system, … (docs/linuxcnc.md,
    /// "Parameters"). Lengths in mm.
    pub parameters: BTreeMap<u32, f64>,
    /// Largest difference (mm) between an I J K arc's radius at its start
    /// and at its end that the control runs: Fanuc's parameter 3410 (the
    /// whole rule on Fanuc and Haas), LinuxCNC's
    /// `CENTER_ARC_RADIUS_TOLERANCE_MM` (its absolute part; the 0.1 % of the
    /// radius stays). `None`: the control's default (`docs/gcode-support.md`).
    pub arc_tolerance: Option<f64>,
    /// A lathe's conventions (the machine file's `[machine] kind = "lathe"`
    /// or `"mill-turn"`). `None`: a mill, unless the dialect is a lathe's
    /// ([`Settings::lathe_conventions`]).
    pub lathe: Option<Lathe>,
    /// The spindle's top speed (rpm): where constant surface speed (`G96`)
    /// with no clamp runs to.
    pub max_rpm: Option<f64>,
    /// Turning tools' noses by tool number (nose radius compensation, the
    /// simulation).
    pub noses: BTreeMap<u32, Nose>,
    /// Where the run is in the main program's text: the byte offset of the
    /// block being run is stored here (relaxed), so a loop moves it back;
    /// blocks of other files leave it at their call. For a progress bar.
    pub progress: Option<Arc<AtomicU64>>,
}

impl Settings {
    /// The lathe's conventions the run starts with: the machine file's, else
    /// a lathe dialect's defaults (X a diameter, system A); `None` for a mill.
    pub fn lathe_conventions(&self) -> Option<Lathe> {
        self.lathe.or_else(|| self.dialect.is_lathe().then(Lathe::default))
    }

    /// Stores where the run is ([`Settings::progress`]): `at`'s first byte,
    /// where `at` is in the main program's file (`main`).
    #[inline]
    fn reached(&self, at: Span, main: impl FnOnce() -> crate::source::FileId) {
        if let Some(done) = &self.progress {
            if at.file == main() {
                done.store(u64::from(at.start), Ordering::Relaxed);
            }
        }
    }

    /// Checks what a machine file can get wrong: the macro variable ranges
    /// and the input signal values.
    pub fn check(&self) -> Result<(), String> {
        self.macro_variables.check().map_err(|m| format!("[macro]: {m}"))?;
        check_inputs(&self.input_signals).map_err(|m| format!("[signals]: {m}"))
    }
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            dialect: crate::Dialect::Fanuc,
            integer_input: IntegerInput::Increments,
            clock_seed: None,
            step_limit: 10_000_000,
            piece_moves: 4096,
            block_delete: false,
            tool_lengths: BTreeMap::new(),
            tool_radii: BTreeMap::new(),
            tool_file: None,
            length_owners: BTreeMap::new(),
            comp_rules: comp::Rules::default(),
            radii_required: false,
            work_offsets: [Axes::ZERO; 6],
            extra_work_offsets: BTreeMap::new(),
            home: Axes::ZERO,
            reference_given: [false; 4],
            cycles: CycleSettings::default(),
            coords: CoordSettings::default(),
            macro_variables: MacroVariables::default(),
            input_signals: BTreeMap::new(),
            parameters: BTreeMap::new(),
            arc_tolerance: None,
            lathe: None,
            max_rpm: None,
            noses: BTreeMap::new(),
            progress: None,
        }
    }
}

/// Where subprograms that are not in the parsed files come from (a folder of
/// `O####.nc` files, say). The interpreter asks only when a call needs one.
pub trait Library {
    /// The file holding program `number`, if there is one.
    fn load(&mut self, number: u32) -> Option<SourceFile>;

    /// The LinuxCNC subroutine file `<stem>.ngc`, if there is one: `o<name>
    /// call` looks for `name.ngc` (the name in lower case), `o123 call` for
    /// `123.ngc`, as LinuxCNC searches its SUBROUTINE_PATH. None by default.
    fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
        let _ = stem;
        None
    }
}

/// A library with no programs.
pub struct NoLibrary;

impl Library for NoLibrary {
    fn load(&mut self, _: u32) -> Option<SourceFile> {
        None
    }
}

/// What a run produced.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// The motions, in order: with cutter radius compensation (G41/G42)
    /// the tool-centre path.
    pub toolpath: Toolpath,
    /// With cutter radius compensation, the programmed contour (the tool
    /// tip as programmed) and the G41/G42 D and G40 blocks kept for a
    /// G-code writer ([`Kept`] blocks before the start-up and cancel
    /// moves), so the control applies its own D register. `None` when no
    /// move was made with compensation on: `toolpath` is then the
    /// programmed path.
    pub programmed: Option<Toolpath>,
    /// Warnings, and the error that stopped the run if it did not end.
    pub diagnostics: Vec<Diagnostic>,
    /// Lines written by `DPRNT`, and by LinuxCNC's `(debug,…)`,
    /// `(print,…)` and `(msg,…)` comments.
    pub prints: Vec<String>,
    /// The log files a LinuxCNC program writes (`(logopen,…)`,
    /// `(logappend,…)`, `(log,…)`), one entry for each opening, in order.
    /// kezuri writes no file: the caller decides what to do with them.
    pub logs: Vec<LogFile>,
    /// NC blocks executed (macro statements not counted).
    pub blocks: u64,
    /// Statements executed, macro statements included.
    pub statements: u64,
    /// `true` when the program reached its end without an error.
    pub completed: bool,
    /// Holes drilled by canned cycles.
    pub holes: u64,
    /// `true` when the program ended in inches (G20): the units a person
    /// reading its positions thinks in. Positions are mm all the same.
    pub inch: bool,
    /// Values the program read from the machine model rather than from
    /// itself (a work offset, a tool offset, the machine position, an input
    /// signal, the clock): the first read of each kind. An expanded program
    /// holds the value the model gave, which another machine may not.
    pub model_reads: Vec<ModelRead>,
    /// Warnings the run raised: those in `diagnostics` and those left out
    /// of it past the first few of a kind (said there in one line, `… and
    /// 10 more warnings like these`, which this does not count).
    pub warnings: u64,
    /// The threads cut, in order.
    pub threads: Vec<Thread>,
    /// What a Fanuc or Haas lathe's `T` words selected: the tool and the
    /// offset number, each pair once, in the order first selected
    /// (`T0101` is (1, 1), `T0100` (1, 0)).
    pub tool_offsets: Vec<(u32, u32)>,
}

/// A log file a LinuxCNC program opened, with the lines it wrote to it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LogFile {
    /// The file name, as the program wrote it.
    pub name: String,
    /// Opened with `logappend` (add to the file) rather than `logopen`
    /// (start it afresh).
    pub append: bool,
    /// The lines, parameters replaced.
    pub lines: Vec<String>,
}

/// A system variable read whose value came from the machine model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelRead {
    /// What it is: "work offset", "tool offset", "machine position",
    /// "input signal", "clock".
    pub what: &'static str,
    /// The variable, e.g. 5221.
    pub variable: u32,
    /// 1-based source line of the first read.
    pub line: u32,
}

/// Words of the block being executed that a macro may read back.
#[derive(Clone, Debug, Default)]
struct LastWords {
    b: f64,
    d: f64,
    e: f64,
    h: f64,
    m: f64,
    n: f64,
    o: f64,
}

/// An active G66/G66.1 call.
#[derive(Clone, Debug)]
struct ModalCall {
    program: u32,
    repeats: u32,
    args: Locals,
}

/// Everything the control remembers, apart from the program itself.
#[derive(Clone)]
struct State {
    settings: Settings,
    modal: Modal,
    /// Tool tip in machine coordinates, without length compensation.
    tip: Axes,
    /// G54 … G59, then the additional offsets (P1 at [`EXTRA_OFFSETS`]).
    work_offsets: Vec<Axes>,
    external_offset: Axes,
    g92_shift: Axes,
    /// G52, G68, G51, G51.1, G16 and the program position.
    coords: coords::Transforms,
    skip_position: Axes,
    /// The canned cycle's hole data.
    hole: cycle::HoleData,
    /// LinuxCNC's G33.1 is the motion mode (group 1).
    rigid_tap: bool,
    /// LinuxCNC's G76 threading cycle is the motion mode (group 1).
    threading: bool,
    /// LinuxCNC's G33 spindle-synchronised motion is the motion mode
    /// (group 1).
    spindle_sync: bool,
    /// A LinuxCNC lathe cycle (G70, G71, G72) reading its profile from
    /// its subroutine.
    profile: Option<Box<lathe::Capture>>,
    /// A block that changed LinuxCNC's X mode (its count in `blocks`) and
    /// what rs274 multiplies a G76's I J K by in it (0.5 for G7, 2 for G8).
    ijk_rescaled: Option<(u64, f64)>,
    /// LinuxCNC's spline (G5: 50, G5.1: 51) is this block's motion; the
    /// motion mode stays as it was (rs274 2.9).
    spline: Option<u32>,
    /// The last G5's P Q (mm): a G5 without I J leaves along that tangent.
    spline_pq: [f64; 2],
    /// Holes drilled by canned cycles.
    holes: u64,
    /// The threads cut ([`Outcome::threads`]).
    threads: Vec<Thread>,
    /// A lathe's tool and offset selections ([`Outcome::tool_offsets`]).
    tool_offsets: Vec<(u32, u32)>,
    /// What a lathe's cycles remember between blocks.
    cycles: lathe::single::CycleMemory,
    /// What the first blocks of the lathe's G71/G72/G73 left for the next.
    contour: lathe::contour::Memory,
    /// A lathe's state (`None` on a mill): how X is read, constant surface
    /// speed, the lathe's motion modes.
    turning: Option<lathe::Turning>,
    /// Tool length wear by H number (G10 L11, #10001…), added to the
    /// geometry in `settings.tool_lengths`.
    length_wear: BTreeMap<u32, f64>,
    /// Tool radius wear by D number (G10 L13, #12001…).
    radius_wear: BTreeMap<u32, f64>,
    /// LinuxCNC: the length G43 loaded from the tool table (mm). A G10
    /// L1/L10/L11 changes the table, not the offset in force, until the
    /// next G43. `None` elsewhere: the register is read as it is now.
    length_loaded: Option<f64>,
    /// LinuxCNC's G43.1 Z (mm) where it set the offset in force, and the
    /// G43.2 H registers added since ([`LengthOffset::added`]).
    length_given: Option<f64>,
    length_added: [u32; LengthOffset::ADDED],
    /// The units in force when the length offset was last set: LinuxCNC's
    /// G43.2 adds to its number unconverted.
    length_units: Units,
    model_reads: Vec<ModelRead>,
    /// System variables the program has written (no longer the model's).
    set_by_program: BTreeSet<u32>,
    /// #3003, #3004 (single block, feed hold) and #3901, #3902 (parts).
    panel: BTreeMap<u32, f64>,
    /// Axes whose work position comes from the machine model (where the
    /// run started, a reference point, a work offset), not from a position
    /// the program named since.
    guessed: AxisSet,
    /// The first axis word without a decimal point read as least
    /// increments: where, its letter and its value as written.
    first_integer: Option<(Span, u8, f64)>,
    /// Axes no move has named since the start ([`kezuri_geom::Move::unknown`]).
    unplaced: AxisSet,
    /// Axes at a machine position the machine file does not place, until an
    /// absolute move names them ([`kezuri_geom::Move::unknown`]).
    at_machine: AxisSet,
    feed_word: f64,
    feed_set: bool,
    /// Where the F word in force was written (a zero feed's error names it).
    feed_span: Span,
    speed: f64,
    /// Where the S word in force was written.
    speed_span: Option<Span>,
    spindle: Spindle,
    coolant: Coolant,
    tool: u32,
    pending_tool: u32,
    last: LastWords,
    modal_call: Option<ModalCall>,
    /// Modal macro frames on the call stack (their blocks are not called).
    modal_depth: u32,
    locals: Vec<Locals>,
    /// LinuxCNC named parameters `#<name>` of each call level (as `locals`).
    named: Vec<HashMap<String, f64>>,
    /// LinuxCNC global named parameters `#<_name>` set by the program.
    globals: HashMap<String, f64>,
    /// `#<_value>` and `#<_value_returned>`: what the last LinuxCNC
    /// subroutine returned.
    returned: Option<f64>,
    /// LinuxCNC subroutine calls open (`#<_call_level>`).
    call_level: u32,
    level: usize,
    /// Common variables #100–#999 (those the machine has).
    common: Box<[Value; 900]>,
    /// Every other common variable that holds a value.
    sparse: HashMap<u32, Value>,
    outputs: Outputs,
    /// Inputs whose "not in the machine file" warning was given.
    unset_inputs_warned: BTreeSet<u32>,
    /// The statement being executed, for warnings from inside expressions.
    at: Span,
    /// Its source line.
    at_line: u32,
    clock: Clock,
    toolpath: Toolpath,
    /// Whether the last frame pushed is the one in force and nothing run
    /// since could have changed it: the block of motion words only
    /// ([`State::block_plain`]) reuses it instead of building it again.
    frame_known: bool,
    /// Whether the block being run has motion words only (G00–G03, axis,
    /// arc, F and S words; no M code), which cannot change the frame.
    block_plain: bool,
    /// Cutter radius compensation: tags and spans of the moves.
    radius: radius::Radius,
    diagnostics: Vec<Diagnostic>,
    warned: HashMap<&'static str, u32>,
    prints: Vec<String>,
    print_open: bool,
    /// LinuxCNC log files; the last is being written while `log_open`.
    logs: Vec<LogFile>,
    log_open: bool,
    blocks: u64,
}

/// Geometry plus wear, where either is set.
fn sum(geometry: Option<&f64>, wear: Option<&f64>) -> Option<f64> {
    match (geometry, wear) {
        (None, None) => None,
        (g, w) => Some(g.copied().unwrap_or(0.0) + w.copied().unwrap_or(0.0)),
    }
}

/// Warnings of one kind shown before the rest are only counted.
const WARNINGS_PER_KIND: u32 = 5;

impl State {
    fn new(settings: Settings) -> State {
        // LinuxCNC's interpreter starts in G99 (canned cycles return to R).
        let mut modal = match settings.coords.control {
            Control::LinuxCnc => Modal { cycle_return: CycleReturn::R, ..Modal::default() },
            _ => Modal::default(),
        };
        let fanuc = settings.coords.control != Control::LinuxCnc;
        let turning = settings.lathe_conventions().map(|lathe| lathe::Turning::new(lathe, fanuc));
        if turning.is_some() && fanuc {
            // A Fanuc or Haas lathe powers on in G18, G99 (feed per
            // revolution) and G97.
            modal.plane = kezuri_geom::Plane::Zx;
            modal.feed_mode = FeedMode::PerRev;
        }
        State {
            work_offsets: (0..EXTRA_OFFSETS + EXTRA_OFFSET_COUNT)
                .map(|k| match k {
                    0..EXTRA_OFFSETS => settings.work_offsets[k],
                    _ => {
                        settings.extra_work_offsets.get(&((k - EXTRA_OFFSETS + 1) as u32)).copied().unwrap_or_default()
                    }
                })
                .collect(),
            clock: Clock::new(settings.clock_seed),
            settings,
            modal,
            tip: Axes::ZERO,
            external_offset: Axes::ZERO,
            g92_shift: Axes::ZERO,
            coords: coords::Transforms::default(),
            skip_position: Axes::ZERO,
            hole: cycle::HoleData::default(),
            rigid_tap: false,
            threading: false,
            spindle_sync: false,
            profile: None,
            ijk_rescaled: None,
            spline: None,
            spline_pq: [0.0; 2],
            holes: 0,
            threads: Vec::new(),
            tool_offsets: Vec::new(),
            cycles: lathe::single::CycleMemory::default(),
            contour: Default::default(),
            turning,
            length_wear: BTreeMap::new(),
            radius_wear: BTreeMap::new(),
            length_loaded: None,
            length_given: None,
            length_added: [0; LengthOffset::ADDED],
            length_units: Units::Mm,
            model_reads: Vec::new(),
            set_by_program: BTreeSet::new(),
            panel: BTreeMap::new(),
            guessed: AxisSet::ALL,
            first_integer: None,
            unplaced: AxisSet::ALL,
            at_machine: AxisSet::NONE,
            feed_word: 0.0,
            feed_set: false,
            feed_span: Span::default(),
            speed: 0.0,
            speed_span: None,
            spindle: Spindle::Off,
            coolant: Coolant::default(),
            tool: 0,
            pending_tool: 0,
            last: LastWords::default(),
            modal_call: None,
            modal_depth: 0,
            locals: vec![[Value::Vacant; 33]],
            named: vec![HashMap::new()],
            globals: HashMap::new(),
            returned: None,
            call_level: 0,
            level: 0,
            common: Box::new([Value::Vacant; 900]),
            sparse: HashMap::new(),
            outputs: Outputs::default(),
            unset_inputs_warned: BTreeSet::new(),
            at: Span::default(),
            at_line: 0,
            toolpath: Toolpath { unknown_start: true, ..Toolpath::default() },
            frame_known: false,
            block_plain: false,
            radius: radius::Radius::default(),
            diagnostics: Vec::new(),
            warned: HashMap::new(),
            prints: Vec::new(),
            print_open: false,
            logs: Vec::new(),
            log_open: false,
            blocks: 0,
        }
    }

    /// The addresses that are axes on this control ([`words::Words`]'s
    /// bits): X Y Z A B C, and U V W on LinuxCNC, which has nine axes
    /// (on a Fanuc or Haas lathe U W are the incremental X Z instead).
    fn axis_bits(&self) -> u32 {
        if self.settings.dialect == crate::Dialect::LinuxCnc {
            words::NINE_AXES
        } else {
            words::SIX_AXES
        }
    }

    /// Offset from work coordinates to machine coordinates of the tool tip.
    #[inline(always)]
    fn frame_offset(&self) -> Axes {
        let w = self.work_offsets[self.modal.work_offset].to_array();
        let e = self.external_offset.to_array();
        let g = self.g92_shift.to_array();
        let l = self.coords.local;
        Axes::from_array(std::array::from_fn(|i| w[i] + e[i] + g[i] + l[i]))
    }

    /// The current position in program coordinates (what #5001 reads):
    /// work coordinates less G52, G92 and the transforms of `coords.rs`.
    fn work_position(&self) -> Axes {
        self.program_position()
    }

    /// Length compensation applied to Z by G43/G44.
    fn length_offset(&self) -> f64 {
        match self.modal.length_comp {
            Some((sign, h)) => sign * self.length_in_force(h),
            None => 0.0,
        }
    }

    /// After the tool length offset changed from `before` (mm, as
    /// [`State::length_offset`]): on a Fanuc control the next Z move keeps
    /// the programmed Z (the spindle moves by the change); on LinuxCNC
    /// applying or changing an offset moves nothing: the spindle stays, and
    /// the tip's programmed position changes by the change of offset.
    fn length_changed(&mut self, before: f64) {
        if self.settings.coords.control == Control::LinuxCnc {
            self.tip.z += before - self.length_offset();
        }
        self.guessed = AxisSet(self.guessed.0 | 0b100);
    }

    /// The length of offset `h` as G43 applies it now: what it loaded
    /// (LinuxCNC), else the register.
    fn length_in_force(&self, h: u32) -> f64 {
        self.length_loaded.or_else(|| self.tool_length(h)).unwrap_or(0.0)
    }

    /// Tool length offset H`h`: its geometry (the tool table) and wear
    /// (set by the program) added; `None` where neither is set.
    fn tool_length(&self, h: u32) -> Option<f64> {
        sum(self.settings.tool_lengths.get(&h), self.length_wear.get(&h))
    }

    /// Tool radius offset D`d`, geometry and wear added, as [`State::tool_length`].
    fn tool_radius(&self, d: u32) -> Option<f64> {
        sum(self.settings.tool_radii.get(&d), self.radius_wear.get(&d))
    }

    /// The work offset and tool length offset in effect, for the toolpath.
    fn frame(&self) -> Frame {
        let (o, f) = (self.work_offsets[self.modal.work_offset].to_array(), self.frame_offset().to_array());
        Frame {
            work: self.modal.work_offset as u8,
            origin: self.work_offsets[self.modal.work_offset],
            shift: Axes::from_array(std::array::from_fn(|k| f[k] - o[k])),
            length: self.modal.length_comp.map(|(sign, register)| LengthOffset {
                register,
                negative: sign < 0.0,
                value: self.length_in_force(register),
                given: self.length_given,
                added: self.length_added,
            }),
        }
    }

    /// Machine position of the spindle gauge line (what #5021 reads).
    fn machine_position(&self) -> Axes {
        Axes { z: self.tip.z + self.length_offset(), ..self.tip }
    }

    /// Keeps a block for the writer before the next move (see
    /// [`kezuri_geom::Kept`]).
    fn keep(&mut self, text: String, moves: usize, sets_offsets: bool, line: u32) {
        let before = self.toolpath.moves.len();
        let kept = self.kept(before, moves, text, sets_offsets, line);
        self.toolpath.kept.push(kept);
    }

    /// A kept block with the tool, spindle and coolant in force now.
    fn kept(&self, before: usize, moves: usize, text: String, sets_offsets: bool, line: u32) -> Kept {
        let state = ToolState { tool: self.tool, speed: self.speed, spindle: self.spindle, coolant: self.coolant };
        Kept { before, moves, text, sets_offsets, line, state, cycle: None }
    }

    /// Adds a warning, showing at most [`WARNINGS_PER_KIND`] of each kind.
    fn warn(&mut self, kind: &'static str, span: Span, message: impl Into<String>) {
        let count = self.warned.entry(kind).or_insert(0);
        *count += 1;
        if *count <= WARNINGS_PER_KIND {
            self.diagnostics.push(Diagnostic::warning(span, message));
        }
    }
}
