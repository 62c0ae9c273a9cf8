//! Typed modal state: one enum per modal group, and the G codes that set them.

use kezuri_geom::Plane;

use crate::offsets::EXTRA_OFFSETS;

/// Group 1: how axis words move the tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// G00
    Rapid,
    /// G01
    Linear,
    /// G02
    Cw,
    /// G03
    Ccw,
}

/// Group 3: absolute or incremental axis words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    /// G90
    Absolute,
    /// G91
    Incremental,
}

/// Group 6: input units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// G21
    Mm,
    /// G20
    Inch,
}

/// Group 5: feed per minute or per revolution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedMode {
    /// G94
    PerMinute,
    /// G95
    PerRev,
    /// G93: inverse time, F = 1 / the move's time in minutes.
    InverseTime,
}

/// Group 7: cutter radius compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusComp {
    /// G40
    Off,
    /// G41
    Left,
    /// G42
    Right,
}

/// Group 12: modal macro call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModalCallKind {
    /// G66: call after each block that moves an axis.
    AfterMove,
    /// G66.1: call on every block, instead of it.
    EveryBlock,
}

/// Group 9: the canned cycle in force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cycle {
    /// G73 high-speed peck drilling: retracts by a small clearance.
    HighSpeedPeck,
    /// G74 left-hand tapping.
    LeftTap,
    /// G76 fine boring: oriented stop and shift before the retract.
    FineBore,
    /// G81 drilling.
    Drill,
    /// G82 drilling with a dwell at the bottom.
    DrillDwell,
    /// G83 peck drilling: back to R after every peck.
    Peck,
    /// G84 right-hand tapping.
    Tap,
    /// G85 boring: feed in, feed out.
    Bore,
    /// G86 boring: spindle stop at the bottom, rapid out.
    BoreStop,
    /// G87 back boring: from below, upwards.
    BackBore,
    /// G88 boring: dwell, spindle stop, the operator retracts.
    BoreManual,
    /// G89 boring: dwell at the bottom, feed out.
    BoreDwell,
    /// A Fanuc lathe's G87 side drilling: G83's pecks along X toward the
    /// spindle axis, the hole placed by Z and C.
    SideDrill,
    /// A Fanuc lathe's G88 side tapping: G84 along X.
    SideTap,
    /// A Fanuc lathe's G89 side boring: feed in along X, the dwell, feed
    /// out to R.
    SideBore,
}

impl Cycle {
    /// The G number.
    pub fn number(self) -> u32 {
        use Cycle::*;
        match self {
            HighSpeedPeck => 73,
            LeftTap => 74,
            FineBore => 76,
            Drill => 81,
            DrillDwell => 82,
            Peck => 83,
            Tap => 84,
            Bore => 85,
            BoreStop => 86,
            BackBore | SideDrill => 87,
            BoreManual | SideTap => 88,
            BoreDwell | SideBore => 89,
        }
    }

    fn from_number(n: u32) -> Option<Cycle> {
        use Cycle::*;
        Some(match n {
            73 => HighSpeedPeck,
            74 => LeftTap,
            76 => FineBore,
            81 => Drill,
            82 => DrillDwell,
            83 => Peck,
            84 => Tap,
            85 => Bore,
            86 => BoreStop,
            87 => BackBore,
            88 => BoreManual,
            89 => BoreDwell,
            _ => return None,
        })
    }

    /// Tapping (G74, G84): the spindle and the feed are synchronised by
    /// the control, so it is never written as plain moves.
    pub fn is_tapping(self) -> bool {
        matches!(self, Cycle::Tap | Cycle::LeftTap | Cycle::SideTap)
    }

    /// A lathe's side cycle (G87 G88 G89): the hole goes along X, toward
    /// the spindle axis, and Z and C place it.
    pub fn is_side(self) -> bool {
        matches!(self, Cycle::SideDrill | Cycle::SideTap | Cycle::SideBore)
    }
}

/// The lathe's multiple repetitive cycles that work from a finishing shape
/// (Fanuc G70–G73 in G code systems A and B, G72–G75 in C; Haas G70–G73).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContourCycle {
    /// G70: the shape itself, once.
    Finishing,
    /// G71: stock removal in turning (cuts along Z).
    Turning,
    /// G72: stock removal in facing (cuts along X).
    Facing,
    /// G73: pattern repeating (the shape again, each time nearer).
    Pattern,
}

/// Group 10: where a canned cycle returns after each hole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleReturn {
    /// G98: to the initial level, where the tool was when the cycle began.
    Initial,
    /// G99: to the R level.
    R,
}

/// A lathe's single cycle (group 1, modal: a block of axis words alone
/// repeats it). FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
/// lathe system, "G code list" and "Single repetitive cycle".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SingleCycle {
    /// Outer or inner diameter cutting: G90 (system A), G77 (B), G20 (C).
    Cutting,
    /// Threading: G92 (A), G78 (B), G21 (C).
    Threading,
    /// End face turning: G94 (A), G79 (B), G24 (C).
    Facing,
}

impl SingleCycle {
    /// The G number in the given G code system.
    pub fn number(self, system: crate::interp::GCodeSystem) -> u32 {
        use crate::interp::GCodeSystem::*;
        match (self, system) {
            (SingleCycle::Cutting, A) => 90,
            (SingleCycle::Threading, A) => 92,
            (SingleCycle::Facing, A) => 94,
            (SingleCycle::Cutting, B) => 77,
            (SingleCycle::Threading, B) => 78,
            (SingleCycle::Facing, B) => 79,
            (SingleCycle::Cutting, C) => 20,
            (SingleCycle::Threading, C) => 21,
            (SingleCycle::Facing, C) => 24,
        }
    }
}

/// A G code, decoded from its number (`G66.1` is `Code(66, 1)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GCode {
    /// G00 G01 G02 G03
    Motion(Motion),
    /// G04
    Dwell,
    /// G33.1 (LinuxCNC): rigid tapping to the end point and back, the
    /// feed synchronised with the spindle (K, the pitch). Group 1.
    RigidTap,
    /// G33 (LinuxCNC): spindle-synchronised motion, K the distance a turn
    /// along the move (threading). Group 1.
    SpindleSync,
    /// G70, G71, G72 and their .1 .2 (LinuxCNC): the lathe's finishing and
    /// roughing cycles along the profile of the subroutine Q, as ten times
    /// the number (711: G71.1). Group 1.
    LatheProfile(u32),
    /// G7 (LinuxCNC): lathe diameter mode, X words read as diameters (G8,
    /// radius mode, is decoded as [`GCode::Smoothing`]`(80)`, Fanuc's G08,
    /// and read by dialect).
    LatheDiameter,
    /// G10 (offsets by program)
    SetOffsets,
    /// G17 G18 G19
    Plane(Plane),
    /// G20 G21
    Units(Units),
    /// G28
    Home,
    /// G30 (P2 … P4: the 2nd to 4th reference points)
    OtherHome,
    /// G52 local coordinate system
    LocalOffset,
    /// G68 (`true`) / G69 coordinate rotation
    Rotation(bool),
    /// G51 (`true`) / G50 scaling
    Scaling(bool),
    /// G51.1 (`true`) / G50.1 programmable mirror image
    Mirror(bool),
    /// G16 (`true`) / G15 polar coordinates
    Polar(bool),
    /// G90.1 / G91.1: I J K absolute or incremental (LinuxCNC)
    ArcCentre(Distance),
    /// G31 skip; also G38.2 … G38.5, the LinuxCNC and GRBL probe moves
    Skip,
    /// G40 G41 G42
    RadiusComp(RadiusComp),
    /// G41.1 G42.1 (LinuxCNC): compensation with the cutter's diameter
    /// given in the block's `D` word instead of a tool table entry.
    RadiusCompDiameter(RadiusComp),
    /// G43 (`true`) G44 (`false`): tool length offset + or -.
    LengthComp(bool),
    /// G43.1 (LinuxCNC, GRBL): the tool length offset given in the block's
    /// Z, in place of a register's.
    LengthGiven,
    /// G43.2 (LinuxCNC): H's tool length added to the offset in force.
    LengthAdded,
    /// G49
    LengthCompOff,
    /// G53
    MachineCoords,
    /// G54 … G59 as 0 … 5; the additional offsets from [`EXTRA_OFFSETS`]
    /// (G54.1 P1 is 6)
    WorkOffset(usize),
    /// G54.1 P (Fanuc), G154 P (Haas): an additional work offset by P
    ExtraWorkOffset,
    /// G65
    MacroCall,
    /// G12 (`true`), G13: Haas's circular pocket milling.
    Pocket(bool),
    /// G66, G66.1
    ModalCall(ModalCallKind),
    /// G67
    ModalCallOff,
    /// G80: cancel canned cycle
    CycleOff,
    /// G98 G99
    CycleReturn(CycleReturn),
    /// G90 G91
    Distance(Distance),
    /// G92
    SetPosition,
    /// G94 G95
    FeedMode(FeedMode),
    /// G73 … G89 canned cycles
    CannedCycle(Cycle),
    /// A lathe's G70–G73: the cycles of a finishing shape (one-shot).
    Contour(ContourCycle),
    /// How the control smooths or looks ahead, not where it goes: Fanuc
    /// G05 P (high-speed machining), G05.1 Q (AI contour control), G08 P
    /// (look-ahead), Haas G103 P (look-ahead limit) and G187 (smoothness). Kept in written programs. The
    /// value is the G number × 10.
    Smoothing(u32),
    /// G09: exact stop at the end of this block's move (how the control
    /// ends the move, not where it goes).
    ExactStop,
    /// G97: spindle speed in rpm, the mill's usual state.
    ConstantSpeedOff,
    /// G96 (lathes): constant surface speed, S in m/min (ft/min under
    /// inch input); the spindle speed follows the tool's radius.
    ConstantSpeed,
    /// A lathe's single cycle: G90 G92 G94 (system A), G77 G78 G79 (B),
    /// G20 G21 G24 (C).
    SingleCycle(SingleCycle),
    /// A lathe's grooving cycle (`true`: G74 end face peck drilling and
    /// grooving; `false`: G75 outer/inner diameter grooving; G76, G77 in
    /// system C). One-shot.
    Grooving(bool),
    /// A lathe's multiple threading cycle: G76 (G78 in system C). One-shot.
    MultipleThreading,
    /// A lathe's threading move: G32 (system A), G33 (B, C). Group 1.
    Threading,
    /// A lathe's coordinate system setting and spindle speed clamp: G50
    /// (system A), G92 (B, C). X Z set the program position (X a
    /// diameter where X is one), S the top spindle speed.
    LatheSetPosition,
    /// G92.1 (Fanuc: preset of the work coordinates; LinuxCNC: G92 offsets
    /// reset) and LinuxCNC's G92.2: the G92 shift cancelled.
    ResetShift,
    /// G61 exact stop, G61.1, G62, G63 tapping, G64 cutting mode (LinuxCNC:
    /// path blending within `P`, `Q`): how the control joins moves, not
    /// where they go; kept for `#4015`. The value is the G number × 10.
    PathMode(u32),
}

impl GCode {
    /// Decodes a G number given as ten times its value (G1 is 10, G66.1 is 661).
    pub fn decode(tenths: u32) -> Option<GCode> {
        use GCode::*;
        Some(match tenths {
            0 => Motion(self::Motion::Rapid),
            10 => Motion(self::Motion::Linear),
            20 => Motion(self::Motion::Cw),
            30 => Motion(self::Motion::Ccw),
            40 => Dwell,
            331 => RigidTap,
            330 => SpindleSync,
            70 => LatheDiameter,
            700 | 710..=712 | 720..=722 => LatheProfile(tenths),
            100 => SetOffsets,
            170 => Plane(kezuri_geom::Plane::Xy),
            180 => Plane(kezuri_geom::Plane::Zx),
            190 => Plane(kezuri_geom::Plane::Yz),
            200 => Units(self::Units::Inch),
            210 => Units(self::Units::Mm),
            280 => Home,
            300 => OtherHome,
            520 => LocalOffset,
            680 => Rotation(true),
            690 => Rotation(false),
            510 => Scaling(true),
            500 => Scaling(false),
            // Haas G101/G100: mirror image about the work zero (coords/codes.rs).
            511 | 1010 => Mirror(true),
            501 | 1000 => Mirror(false),
            160 => Polar(true),
            150 => Polar(false),
            901 => ArcCentre(self::Distance::Absolute),
            911 => ArcCentre(self::Distance::Incremental),
            310..=314 | 382..=385 => Skip,
            400 => RadiusComp(self::RadiusComp::Off),
            410 => RadiusComp(self::RadiusComp::Left),
            420 => RadiusComp(self::RadiusComp::Right),
            411 => RadiusCompDiameter(self::RadiusComp::Left),
            421 => RadiusCompDiameter(self::RadiusComp::Right),
            430 => LengthComp(true),
            440 => LengthComp(false),
            431 => LengthGiven,
            432 => LengthAdded,
            490 => LengthCompOff,
            530 => MachineCoords,
            540..=590 if tenths.is_multiple_of(10) => WorkOffset(((tenths - 540) / 10) as usize),
            // Haas G110–G129 (G154 P1–P20), LinuxCNC G59.1–G59.3.
            1100..=1290 if tenths.is_multiple_of(10) => WorkOffset(EXTRA_OFFSETS + ((tenths - 1100) / 10) as usize),
            591..=593 => WorkOffset(EXTRA_OFFSETS + (tenths - 591) as usize),
            // Fanuc G54.1 P1–P48, Haas G154 P1–P99.
            541 | 1540 => ExtraWorkOffset,
            650 => MacroCall,
            120 => Pocket(true),
            130 => Pocket(false),
            660 => ModalCall(ModalCallKind::AfterMove),
            661 => ModalCall(ModalCallKind::EveryBlock),
            670 => ModalCallOff,
            800 => CycleOff,
            730 | 740 | 760 | 810..=890 if tenths.is_multiple_of(10) => CannedCycle(Cycle::from_number(tenths / 10)?),
            980 => CycleReturn(self::CycleReturn::Initial),
            990 => CycleReturn(self::CycleReturn::R),
            610 | 611 | 620 | 630 | 640 => PathMode(tenths),
            900 => Distance(self::Distance::Absolute),
            910 => Distance(self::Distance::Incremental),
            920 => SetPosition,
            921 | 922 => ResetShift,
            50 | 51 | 80 | 1030 | 1870 => Smoothing(tenths),
            90 => ExactStop,
            970 => ConstantSpeedOff,
            // LinuxCNC's constant surface speed (a Fanuc lathe's from its
            // own table; a mill refuses it where it is read).
            960 => ConstantSpeed,
            940 => FeedMode(self::FeedMode::PerMinute),
            950 => FeedMode(self::FeedMode::PerRev),
            930 => FeedMode(self::FeedMode::InverseTime),
            _ => return None,
        })
    }

    /// The modal group (Fanuc numbering); 0 for one-shot codes.
    pub fn group(self) -> u32 {
        use GCode::*;
        match self {
            Motion(_) | RigidTap | SpindleSync | LatheProfile(_) | SingleCycle(_) | Threading => 1,
            Plane(_) => 2,
            Distance(_) => 3,
            FeedMode(_) => 5,
            Units(_) => 6,
            RadiusComp(_) | RadiusCompDiameter(_) => 7,
            LengthComp(_) | LengthGiven | LengthAdded | LengthCompOff => 8,
            CycleOff | CannedCycle(_) => 9,
            CycleReturn(_) => 10,
            ModalCall(_) | ModalCallOff => 12,
            WorkOffset(_) | ExtraWorkOffset => 14,
            PathMode(_) => 15,
            Scaling(_) => 11,
            Rotation(_) => 16,
            Polar(_) => 17,
            Mirror(_) => 22,
            // Not a Fanuc group: LinuxCNC's arc distance mode.
            ArcCentre(_) => 101,
            // Not one-shots that exclude each other: a group of their own.
            // Each its own group: they do not exclude each other.
            Smoothing(tenths) => 1000 + tenths,
            ExactStop => 100,
            ConstantSpeedOff | ConstantSpeed => 13,
            // LinuxCNC's group 15 (G7/G8); not a Fanuc group.
            LatheDiameter => 102,
            Dwell | SetOffsets | Home | OtherHome | LocalOffset | Skip | MachineCoords | MacroCall | SetPosition
            | ResetShift | Pocket(_) | Contour(_) | LatheSetPosition | Grooving(_) | MultipleThreading => 0,
        }
    }
}

impl GCode {
    /// Decodes a G number (ten times its value) as a Fanuc or Haas lathe
    /// reads it in G code system `system`. FANUC Series 0i-TF Plus
    /// Operator's Manual (B-64604EN), lathe system, "G code list" (table of
    /// systems A, B and C):
    ///
    /// | A    | B    | C    | function                                   |
    /// |------|------|------|--------------------------------------------|
    /// | G20  | G20  | G70  | inch input                                 |
    /// | G21  | G21  | G71  | mm input                                   |
    /// | G32  | G33  | G33  | threading                                  |
    /// | G50  | G92  | G92  | coordinate system setting, spindle clamp   |
    /// | G50.3| G92.1| G92.1| workpiece coordinate system preset         |
    /// | G70–G76 | G70–G76 | G72–G78 | multiple repetitive cycles      |
    /// | G90  | G77  | G20  | outer/inner diameter cutting cycle         |
    /// | G92  | G78  | G21  | threading cycle                            |
    /// | G94  | G79  | G24  | end face turning cycle                     |
    /// | G96  | G96  | G96  | constant surface speed                     |
    /// | G97  | G97  | G97  | constant surface speed cancel              |
    /// | G98  | G94  | G94  | feed per minute                            |
    /// | G99  | G95  | G95  | feed per revolution                        |
    /// | –    | G90  | G90  | absolute programming                       |
    /// | –    | G91  | G91  | incremental programming                    |
    /// | –    | G98  | G98  | canned cycle return to the initial level   |
    /// | –    | G99  | G99  | canned cycle return to the R point level   |
    ///
    /// In system A absolute and incremental are told apart by the address
    /// (X Z C absolute, U W H incremental), so G90 G91 are no distance
    /// modes there. Haas lathes read system A's codes (Haas Lathe Operator's
    /// Manual, "G-codes"). The other codes are the mill's ([`GCode::decode`]).
    /// The multiple repetitive cycles and the lathe drilling cycles
    /// (G80–G89) are added by their own readers; until then they decode to
    /// nothing, so that a mill's drilling cycle is never run in their place.
    pub fn decode_lathe(tenths: u32, system: crate::interp::GCodeSystem) -> Option<GCode> {
        use crate::interp::GCodeSystem::{A, B, C};
        use GCode::*;
        Some(match (tenths, system) {
            (200, C) => SingleCycle(self::SingleCycle::Cutting),
            (210, C) => SingleCycle(self::SingleCycle::Threading),
            (240, C) => SingleCycle(self::SingleCycle::Facing),
            (700, C) => Units(self::Units::Inch),
            (710, C) => Units(self::Units::Mm),
            (320, A) => Threading,
            (330, B | C) => Threading,
            (500, A) => LatheSetPosition,
            (503, A) => ResetShift,
            (920, B | C) => LatheSetPosition,
            (900, A) => SingleCycle(self::SingleCycle::Cutting),
            (920, A) => SingleCycle(self::SingleCycle::Threading),
            (940, A) => SingleCycle(self::SingleCycle::Facing),
            (770, B) => SingleCycle(self::SingleCycle::Cutting),
            (780, B) => SingleCycle(self::SingleCycle::Threading),
            (790, B) => SingleCycle(self::SingleCycle::Facing),
            (910, A) => return None,
            (980, A) => FeedMode(self::FeedMode::PerMinute),
            (990, A) => FeedMode(self::FeedMode::PerRev),
            (960, _) => ConstantSpeed,
            // G93 (inverse time) is no lathe code.
            (930, _) => return None,
            // The cycles of a finishing shape (lathe/contour.rs).
            (700, A | B) | (720, C) => Contour(ContourCycle::Finishing),
            (710, A | B) | (730, C) => Contour(ContourCycle::Turning),
            (720, A | B) | (740, C) => Contour(ContourCycle::Facing),
            (730, A | B) | (750, C) => Contour(ContourCycle::Pattern),
            // The multiple repetitive cycles (G70–G76, system C G72–G78)
            // and the lathe's drilling cycles: their readers add them.
            (740, A | B) | (760, C) => Grooving(true),
            (750, A | B) | (770, C) => Grooving(false),
            (760, A | B) | (780, C) => MultipleThreading,
            // Face drilling, tapping and boring along Z (G83 G84 G85): the
            // mill's cycles with the hole along Z; side drilling, tapping and
            // boring (G87 G88 G89) the same along X (`cycle.rs`).
            (830 | 840 | 850, _) => return GCode::decode(tenths),
            (870, _) => CannedCycle(Cycle::SideDrill),
            (880, _) => CannedCycle(Cycle::SideTap),
            (890, _) => CannedCycle(Cycle::SideBore),
            (700..=790, _) | (810..=890, _) if tenths.is_multiple_of(10) => return None,
            _ => return GCode::decode(tenths),
        })
    }

    /// Whether a block with this code reads its own U W P Q R words:
    /// the lathe's cycles (single cycles, the multiple repetitive cycles)
    /// and the dwell (`G04 U1.5`, `G04 X1.5`: seconds). In such a block
    /// U and W are not the incremental X and Z of system A and X is not
    /// halved: the code's reader takes the words as written, and reads an
    /// end point with [`crate::interp`]'s lathe point reading where its
    /// X(U) Z(W) are one. Each cycle reader adds its codes here.
    pub fn takes_cycle_words(self) -> bool {
        matches!(
            self,
            GCode::Dwell | GCode::SingleCycle(_) | GCode::Contour(_) | GCode::Grooving(_) | GCode::MultipleThreading
        )
    }
}

/// The modal state of the control.
#[derive(Clone, Debug, PartialEq)]
pub struct Modal {
    /// Group 1.
    pub motion: Motion,
    /// Group 2.
    pub plane: Plane,
    /// Group 3.
    pub distance: Distance,
    /// Group 5.
    pub feed_mode: FeedMode,
    /// Group 6.
    pub units: Units,
    /// Group 7.
    pub radius_comp: RadiusComp,
    /// Group 8: `Some((sign, H number))` while G43/G44 is active.
    pub length_comp: Option<(f64, u32)>,
    /// Group 14: G54 … G59 as 0 … 5.
    pub work_offset: usize,
    /// Group 12: the active modal macro call kind.
    pub modal_call: Option<ModalCallKind>,
    /// Group 15: G61 … G64, as the G number × 10.
    pub path_mode: u32,
    /// LinuxCNC's G64 P (the blending tolerance) and Q (the naive CAM
    /// tolerance), mm, while G64 with P is in force.
    pub path_tolerance: Option<(f64, Option<f64>)>,
    /// Group 9: the canned cycle in force (`None`: G80).
    pub cycle: Option<Cycle>,
    /// Group 10: G98 or G99.
    pub cycle_return: CycleReturn,
}

impl Default for Modal {
    fn default() -> Modal {
        Modal {
            motion: Motion::Rapid,
            plane: Plane::Xy,
            distance: Distance::Absolute,
            feed_mode: FeedMode::PerMinute,
            units: Units::Mm,
            radius_comp: RadiusComp::Off,
            length_comp: None,
            work_offset: 0,
            modal_call: None,
            path_mode: 640,
            path_tolerance: None,
            cycle: None,
            cycle_return: CycleReturn::Initial,
        }
    }
}

impl Modal {
    /// The value `#4000+group` reads: the G number of the group's active code.
    pub fn group_value(&self, group: u32) -> Option<f64> {
        Some(match group {
            1 => match self.motion {
                Motion::Rapid => 0.0,
                Motion::Linear => 1.0,
                Motion::Cw => 2.0,
                Motion::Ccw => 3.0,
            },
            2 => match self.plane {
                Plane::Xy => 17.0,
                Plane::Zx => 18.0,
                Plane::Yz => 19.0,
            },
            3 => match self.distance {
                Distance::Absolute => 90.0,
                Distance::Incremental => 91.0,
            },
            4 => 22.0,
            5 => match self.feed_mode {
                FeedMode::PerMinute => 94.0,
                FeedMode::PerRev => 95.0,
                FeedMode::InverseTime => 93.0,
            },
            6 => match self.units {
                Units::Inch => 20.0,
                Units::Mm => 21.0,
            },
            7 => match self.radius_comp {
                RadiusComp::Off => 40.0,
                RadiusComp::Left => 41.0,
                RadiusComp::Right => 42.0,
            },
            8 => match self.length_comp {
                None => 49.0,
                Some((s, _)) if s > 0.0 => 43.0,
                Some(_) => 44.0,
            },
            9 => self.cycle.map_or(80.0, |c| f64::from(c.number())),
            10 => match self.cycle_return {
                CycleReturn::Initial => 98.0,
                CycleReturn::R => 99.0,
            },
            11 => 50.0,
            12 => match self.modal_call {
                None => 67.0,
                Some(ModalCallKind::AfterMove) => 66.0,
                Some(ModalCallKind::EveryBlock) => 66.1,
            },
            13 => 97.0,
            14 if self.work_offset >= EXTRA_OFFSETS => 54.1,
            14 => 54.0 + self.work_offset as f64,
            15 => f64::from(self.path_mode) / 10.0,
            16 => 69.0,
            17 => 15.0,
            18 => 40.1,
            19 => 25.0,
            20 => 160.0,
            21 => 13.1,
            22 => 50.1,
            _ => return None,
        })
    }
}

/// `G01`, `G66.1`: a G code as written, from ten times its number.
pub(super) fn g_name(tenths: u32) -> String {
    if tenths.is_multiple_of(10) {
        format!("G{:02}", tenths / 10)
    } else {
        format!("G{:02}.{}", tenths / 10, tenths % 10)
    }
}
