//! The machine file (`--machine M.toml`): rapids, acceleration, tool table,
//! work offsets and reference point, macro variables and input signals.
//!
//! ```toml
//! [machine]
//! kind = "mill"                          # or "lathe", "mill-turn"
//! max_rpm = 12000                        # the spindle's top speed
//! # x = "diameter"                       # lathes: X a diameter or "radius"
//! # gcode_system = "A"                   # lathes: Fanuc's G code system A, B, C
//!
//! [motion]
//! rapid_mm_min = [15000, 15000, 10000]   # X Y Z
//! rapid_deg_min = 3600                   # A B C
//! max_feed_mm_min = 10000
//! acceleration_mm_s2 = 1000
//! junction_deviation_mm = 0.01
//!
//! [tools]
//! # import = "tool.tbl"                  # a tool table, beside this file:
//! # units = "inch"                       #   LinuxCNC .tbl (needs units),
//!                                        #   FreeCAD .fctl/.fctb, Fusion 360
//!                                        #   .json/.tools; what this file
//!                                        #   says overrides what it gives
//! lengths = { 21 = 87.25 }               # old form: H registers, mm
//! radii = { 1 = 3.0 }                    # old form: D registers, mm
//!
//! [tools.T1]                             # the tool in pocket 1
//! shape = "flat:6"                       # cutter SPEC (what sim cuts with)
//! length = 100.5                         # mm: the value of its H register
//!
//! [tools.T5]
//! shape = "ball:6"
//! h = 5                                  # its length register [default: 5]
//! d = 25                                 # its radius register [default:
//! radius = 3.0                           #   5 with a radius, else none]
//! name = "6 mm ball, 2 flutes"           # mm: the value of its D register
//!
//! [tools.T2]                             # a turning tool (lathes)
//! nose_radius = 0.4                      # mm
//! tip = 3                                # imaginary tool tip direction 0-9
//!
//! [post]                                 # how programs are written: a preset
//! preset = "fanuc"                       # and what to change (`kezuri mill --help`)
//!
//! [comp]                                 # cutter compensation (G41/G42)
//! startup = "A"                          # Fanuc start-up/cancel type A or B
//!
//! [offsets]
//! G54 = [0, 0, 0]                        # machine position of each work zero
//! home = [0, 0, 0]                       # G28 reference point (machine); given,
//!                                        #   returns and G53 moves are drawn and
//!                                        #   counted (docs/coordinates.md)
//! "G54.1 P1" = [10, 0, -50]              # additional offsets (G154 P1 on Haas)
//! ref2 = [0, 0, -10]                     # G30 P2 … P4 reference points
//!
//! [coordinates]                          # docs/coordinates.md
//! control = "fanuc"                      # or "haas", "linuxcnc": G28, G52, G53, G90.1
//! rotation_incremental = false           # G68 R follows G91 (Fanuc RIN)
//! arc_tolerance_mm = 0.02                # I J K arc: end radius off the start's
//!                                        #   (Fanuc parameter 3410)
//!
//! [cycles]                               # canned cycles
//! peck_retract_mm = 0.1                  # G73 retract (Fanuc parameter 5114)
//! peck_clearance_mm = 0.1                # G83 clearance (Fanuc parameter 5115)
//! shift = "+X"                           # G76/G87 shift direction for Q
//!
//! [kinematics]                           # default: X, Y, Z carry the tool
//! tool = ["X", "Z", "B"]                 # axes carrying the tool, base out
//! work = ["Y", "C"]                      # axes carrying the part, base out
//! tip = [0, 0, 70]                       # tool tip, all axes at zero
//! [kinematics.axis.B]                    # default: along / about its own
//! axis = [0, 1, 0]                       #   letter's direction, pivot at 0
//! pivot = [0, 0, 120]
//!
//! [macro]                                # default: the broadest set
//! common = ["100-199", "500-999", "900000-999999"]   # common variables
//! kept = ["500-999"]                     # kept over a reset and power off
//! values = { 500 = 12.5 }                # kept variables at the start
//!
//! [signals]
//! inputs = { 1000 = 1, 1005 = 0 }        # bits #1000-#1031, words #1033-#1035
//! ```
//!
//! Every key, its unit, default and the commands that read it are in
//! `docs/machine.md`; the rules for macro variables and signals, and
//! where each comes from, in `docs/macro-variables.md`.

use std::collections::BTreeMap;
use std::path::Path;

use kezuri_correct::kinematics::{self, Axis, Kinematics, AXES};
use kezuri_geom::{Axes, Dynamics};
use kezuri_nc::interp::comp::{Approach, Rules};
use kezuri_nc::interp::{Control, CycleSettings, MacroVariables, Settings};
use serde::Deserialize;

use crate::error::{fail, with_sources, Error, ErrorKind, Result};
use crate::files::Files;
use crate::post::PostFile;
use crate::tool_table::Notes;

mod lathe;
mod tools;

pub use lathe::MachineKind;
pub use tools::ToolEntry;

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    machine: lathe::MachineFile,
    #[serde(default)]
    motion: Motion,
    #[serde(default)]
    tools: tools::Tools,
    #[serde(default)]
    offsets: BTreeMap<String, Vec<f64>>,
    #[serde(default)]
    comp: CompFile,
    kinematics: Option<Chains>,
    #[serde(default, rename = "macro")]
    macro_variables: Macro,
    #[serde(default)]
    signals: Signals,
    #[serde(default)]
    cycles: Cycles,
    #[serde(default)]
    coordinates: Coordinates,
    #[serde(default)]
    post: PostFile,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Coordinates {
    control: Option<String>,
    #[serde(default)]
    rotation_incremental: bool,
    /// How far an I J K arc's end may be off its circle (Fanuc parameter 3410).
    arc_tolerance_mm: Option<f64>,
}

/// `[cycles]`: the canned cycles' parameters.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Cycles {
    /// G73's retract between pecks (Fanuc parameter 5114).
    peck_retract_mm: Option<f64>,
    /// G83's clearance above the last depth (Fanuc parameter 5115).
    peck_clearance_mm: Option<f64>,
    /// Direction of the G76/G87 shift given by Q: "+X", "-X", "+Y" or "-Y".
    shift: Option<String>,
}

/// The canned cycle settings of `[cycles]`.
fn cycle_settings(c: &Cycles) -> Result<CycleSettings> {
    let d = CycleSettings::default();
    let shift_direction = match c.shift.as_deref().map(|s| s.trim().to_ascii_uppercase()) {
        None => d.shift_direction,
        Some(s) => match s.as_str() {
            "+X" | "X" => [1.0, 0.0],
            "-X" => [-1.0, 0.0],
            "+Y" | "Y" => [0.0, 1.0],
            "-Y" => [0.0, -1.0],
            _ => fail!(Invalid, "cycles.shift must be \"+X\", \"-X\", \"+Y\" or \"-Y\", not \"{s}\""),
        },
    };
    Ok(CycleSettings {
        peck_retract: positive("cycles.peck_retract_mm", c.peck_retract_mm, d.peck_retract)?,
        peck_clearance: positive("cycles.peck_clearance_mm", c.peck_clearance_mm, d.peck_clearance)?,
        shift_direction,
        keep: false,
    })
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Macro {
    common: Option<Vec<String>>,
    kept: Option<Vec<String>>,
    #[serde(default)]
    values: BTreeMap<String, f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Signals {
    #[serde(default)]
    inputs: BTreeMap<String, f64>,
}

/// The macro variables of `[macro]`. Without `kept`, the default kept
/// ranges (#500–#999) that the machine has are kept.
fn macro_variables(m: &Macro) -> Result<MacroVariables> {
    let ranges = |name: &str, list: &[String]| -> Result<Vec<_>> {
        list.iter()
            .map(|t| {
                MacroVariables::parse_range(t).map_err(|e| Error::new(ErrorKind::Invalid, format!("macro.{name}: {e}")))
            })
            .collect()
    };
    let default = MacroVariables::default();
    let common = match &m.common {
        Some(list) => ranges("common", list)?,
        None => default.common,
    };
    let kept = match &m.kept {
        Some(list) => ranges("kept", list)?,
        None => default
            .kept
            .into_iter()
            .filter(|r| common.iter().any(|c| c.start() <= r.start() && r.end() <= c.end()))
            .collect(),
    };
    let values = variables("macro.values", &m.values)?;
    Ok(MacroVariables { common, kept, values })
}

/// A table keyed by variable number (`{ 500 = 12.5 }`, `#` allowed).
fn variables(name: &str, map: &BTreeMap<String, f64>) -> Result<BTreeMap<u32, f64>> {
    map.iter()
        .map(|(k, &v)| {
            let n: u32 = k
                .trim_start_matches('#')
                .parse()
                .map_err(|e| Error::new(ErrorKind::Invalid, format!("{name}: '{k}' is not a variable number: {e}")))?;
            if !v.is_finite() {
                fail!(Invalid, "{name}.{k} is not a finite number");
            }
            Ok((n, v))
        })
        .collect()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Chains {
    tool: Vec<String>,
    #[serde(default)]
    work: Vec<String>,
    #[serde(default)]
    tip: Option<[f64; 3]>,
    #[serde(default)]
    axis: BTreeMap<String, AxisSpec>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct AxisSpec {
    direction: Option<[f64; 3]>,
    axis: Option<[f64; 3]>,
    pivot: Option<[f64; 3]>,
}

/// The machine's chains from the file's `[kinematics]`.
fn chains(c: &Chains) -> Result<Kinematics> {
    let letter = |name: &str| -> Result<usize> {
        let up = name.trim().to_ascii_uppercase();
        AXES.iter()
            .position(|a| up.len() == 1 && up.starts_with(*a))
            .ok_or_else(|| Error::new(ErrorKind::Invalid, format!("kinematics: '{name}' is not an axis (X Y Z A B C)")))
    };
    if let Some(name) = c.axis.keys().find(|k| !c.tool.iter().chain(&c.work).any(|a| a.eq_ignore_ascii_case(k))) {
        fail!(Invalid, "kinematics.axis.{name}: the axis is in neither the tool nor the work chain");
    }
    let axis = |name: &String| -> Result<Axis> {
        let index = letter(name)?;
        let spec = c.axis.iter().find(|(k, _)| k.eq_ignore_ascii_case(name)).map(|(_, s)| s);
        let own = std::array::from_fn(|k| if k == index % 3 { 1.0 } else { 0.0 });
        let motion = if index < 3 {
            if spec.is_some_and(|s| s.axis.is_some() || s.pivot.is_some()) {
                fail!(Invalid, "kinematics.axis.{name}: a linear axis has a direction, not an axis or a pivot");
            }
            kinematics::Motion::Linear { direction: spec.and_then(|s| s.direction).unwrap_or(own) }
        } else {
            if spec.is_some_and(|s| s.direction.is_some()) {
                fail!(Invalid, "kinematics.axis.{name}: a rotary axis has an axis and a pivot, not a direction");
            }
            kinematics::Motion::Rotary {
                axis: spec.and_then(|s| s.axis).unwrap_or(own),
                pivot: spec.and_then(|s| s.pivot).unwrap_or([0.0; 3]),
            }
        };
        Ok(Axis { index, motion })
    };
    let k = Kinematics {
        tool: c.tool.iter().map(axis).collect::<Result<_>>()?,
        work: c.work.iter().map(axis).collect::<Result<_>>()?,
        tip: c.tip.unwrap_or([0.0; 3]),
    };
    k.check().map_err(|e| Error::new(ErrorKind::Invalid, format!("kinematics: {e}")))?;
    Ok(k)
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Motion {
    rapid_mm_min: Option<Vec<f64>>,
    rapid_deg_min: Option<f64>,
    max_feed_mm_min: Option<f64>,
    acceleration_mm_s2: Option<f64>,
    junction_deviation_mm: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct CompFile {
    /// Fanuc's start-up and cancel type: "A" or "B".
    startup: Option<String>,
}

/// The Fanuc compensation rules the file's `[comp] startup` asks for
/// (type A when it names none).
fn comp_rules(c: &CompFile) -> Result<Rules> {
    let startup = match c.startup.as_deref().map(str::trim) {
        None => Approach::A,
        Some(t) if t.eq_ignore_ascii_case("A") => Approach::A,
        Some(t) if t.eq_ignore_ascii_case("B") => Approach::B,
        Some(t) => fail!(Invalid, "comp.startup: '{t}' is not a start-up type: \"A\" or \"B\""),
    };
    Ok(Rules::Fanuc { startup })
}

/// A machine: its dynamics, what it tells the interpreter, its axes.
#[derive(Clone)]
pub struct Machine {
    /// What kind of machine it is (`[machine] kind`): a lathe or a
    /// mill-turn reads Fanuc and Haas programs as a lathe's.
    pub kind: MachineKind,
    /// For the cycle time.
    pub dynamics: Dynamics,
    /// Tool table, offsets and reference point, on top of the defaults.
    pub settings: Settings,
    /// Which axes carry the tool and which the work.
    pub kinematics: Kinematics,
    /// The tool table, by tool number.
    pub tools: BTreeMap<u32, ToolEntry>,
    /// Where the tool table came from, in words: the machine file's, or a
    /// program's comments where no machine file gave one.
    pub tools_from: &'static str,
    /// How programs are written for this machine (`[post]`).
    pub post: PostFile,
}

impl Default for Machine {
    fn default() -> Machine {
        Machine {
            kind: MachineKind::Mill,
            dynamics: Dynamics::default(),
            settings: Settings::default(),
            kinematics: Kinematics::mill(),
            tools: BTreeMap::new(),
            tools_from: Machine::TOOLS_FROM_FILE,
            post: PostFile::default(),
        }
    }
}

fn positive(name: &str, v: Option<f64>, default: f64) -> Result<f64> {
    match v {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => fail!(Invalid, "{name} must be a positive number, got {v}"),
    }
}

fn axes(name: &str, v: &[f64]) -> Result<Axes> {
    if v.is_empty() || v.len() > Axes::COUNT || v.iter().any(|x| !x.is_finite()) {
        fail!(Invalid, "{name} must list 1 to 9 finite numbers (X Y Z A B C U V W)");
    }
    let mut a = [0.0; Axes::COUNT];
    a[..v.len()].copy_from_slice(v);
    Ok(Axes::from_array(a))
}

impl Machine {
    /// [`Machine::tools_from`] for the machine file's own table.
    pub const TOOLS_FROM_FILE: &'static str = "the machine file's tool table";

    /// Reads a machine file's text, with what its imported tool table left
    /// out or lacks; `dir` is the folder the file is in, where `files`
    /// finds the tool table it imports.
    pub fn parse(text: &str, dir: &Path, files: &dyn Files) -> Result<(Machine, Notes)> {
        let file: File = toml::from_str(text).map_err(|e| Error::new(ErrorKind::Syntax, with_sources(&e)))?;
        let tools::Read { tools, lengths, radii, notes } = tools::read(&file.tools, dir, files)?;
        let lathe::Read { kind, lathe, max_rpm } = lathe::read(&file.machine)?;
        let d = Dynamics::default();
        let m = &file.motion;
        let rapid = match &m.rapid_mm_min {
            None => d.rapid_mm_min,
            Some(v) if v.len() == 1 => [positive("rapid_mm_min", Some(v[0]), 0.0)?; 3],
            Some(v) if v.len() == 3 => [
                positive("rapid_mm_min", Some(v[0]), 0.0)?,
                positive("rapid_mm_min", Some(v[1]), 0.0)?,
                positive("rapid_mm_min", Some(v[2]), 0.0)?,
            ],
            Some(_) => fail!(Invalid, "rapid_mm_min takes one rate, or three (X Y Z)"),
        };
        let dynamics = Dynamics {
            rapid_mm_min: rapid,
            rapid_deg_min: positive("rapid_deg_min", m.rapid_deg_min, d.rapid_deg_min)?,
            max_feed_mm_min: positive("max_feed_mm_min", m.max_feed_mm_min, d.max_feed_mm_min)?,
            acceleration_mm_s2: positive("acceleration_mm_s2", m.acceleration_mm_s2, d.acceleration_mm_s2)?,
            junction_deviation_mm: positive("junction_deviation_mm", m.junction_deviation_mm, d.junction_deviation_mm)?,
        };
        let mut settings = Settings {
            tool_lengths: lengths,
            tool_radii: radii,
            // The warning of a length the table lacks names the tool's entry.
            length_owners: tools.iter().filter(|(&n, e)| e.h != n).map(|(&n, e)| (e.h, n)).collect(),
            macro_variables: macro_variables(&file.macro_variables)?,
            input_signals: variables("signals.inputs", &file.signals.inputs)?,
            cycles: cycle_settings(&file.cycles)?,
            comp_rules: comp_rules(&file.comp)?,
            lathe,
            max_rpm,
            noses: tools.iter().filter_map(|(&n, e)| e.nose.map(|nose| (n, nose))).collect(),
            ..Settings::default()
        };
        settings.check().map_err(|e| Error::new(ErrorKind::Invalid, e.to_string()))?;
        for (name, v) in &file.offsets {
            let a = axes(name, v)?;
            let upper = name.to_uppercase().replace(' ', "");
            // G54.1 P1 … (Fanuc) or G154 P1 … (Haas): an additional offset.
            let extra = upper.strip_prefix("G54.1P").or_else(|| upper.strip_prefix("G154P")).map(str::parse::<u32>);
            if let Some(p) = extra {
                match p {
                    Ok(p @ 1..=99) => settings.extra_work_offsets.insert(p, a),
                    _ => fail!(Invalid, "offsets: '{name}': the additional work offsets are G54.1 P1 … P99"),
                };
                continue;
            }
            match upper.as_str() {
                "HOME" => (settings.home, settings.reference_given[0]) = (a, true),
                "REF2" | "REF3" | "REF4" => {
                    let k = usize::from(upper.as_bytes()[3] - b'2');
                    (settings.coords.reference_points[k], settings.reference_given[k + 1]) = (a, true)
                }
                g => match g.strip_prefix('G').and_then(|n| n.parse::<usize>().ok()) {
                    Some(n @ 54..=59) => settings.work_offsets[n - 54] = a,
                    _ => fail!(
                        Invalid,
                        "offsets: '{name}' is not G54 … G59, \"G54.1 P1\" … \"G54.1 P99\", home or ref2 … ref4"
                    ),
                },
            }
        }
        settings.coords.control = match file.coordinates.control.as_deref().map(str::to_ascii_lowercase).as_deref() {
            None | Some("fanuc") => Control::Fanuc,
            Some("haas") => Control::Haas,
            Some("linuxcnc") => Control::LinuxCnc,
            Some(other) => fail!(Invalid, "coordinates.control: '{other}' is not fanuc, haas or linuxcnc"),
        };
        settings.coords.rotation_incremental = file.coordinates.rotation_incremental;
        if let Some(t) = file.coordinates.arc_tolerance_mm {
            settings.arc_tolerance = Some(positive("coordinates.arc_tolerance_mm", Some(t), 0.0)?);
        }
        let kinematics = match &file.kinematics {
            Some(c) => chains(c)?,
            None => Kinematics::mill(),
        };
        // Any mistake in [post] is found now, not when a program is written.
        crate::post::options(&file.post, None, &tools)?;
        let tools_from = Machine::TOOLS_FROM_FILE;
        Ok((Machine { kind, dynamics, settings, kinematics, tools, tools_from, post: file.post }, notes))
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use kezuri_nc::interp::Nose;

    use super::*;

    /// A machine file with nothing beside it.
    fn parse(text: &str) -> Result<Machine> {
        Ok(Machine::parse(text, Path::new(""), &BTreeMap::<PathBuf, Vec<u8>>::new())?.0)
    }

    #[test]
    fn reads_the_documented_example() {
        let doc = include_str!("machine.rs");
        let example: String = doc
            .lines()
            .skip_while(|l| !l.contains("```toml"))
            .skip(1)
            .take_while(|l| !l.contains("```"))
            .map(|l| l.trim_start_matches("//!").trim_start().to_string() + "\n")
            .collect();
        let m = parse(&example).unwrap();
        assert_eq!(m.dynamics.rapid_mm_min, [15000.0, 15000.0, 10000.0]);
        assert_eq!((m.kind, m.settings.lathe, m.settings.max_rpm), (MachineKind::Mill, None, Some(12000.0)));
        assert_eq!(m.settings.noses.get(&2), Some(&Nose { radius: 0.4, tip: 3 }));
        assert_eq!(m.settings.tool_lengths[&21], 87.25);
        // Each tool's length and radius go to its registers.
        assert_eq!(
            (m.settings.tool_lengths[&1], m.settings.tool_radii[&25], m.settings.tool_radii[&1]),
            (100.5, 3.0, 3.0)
        );
        let t5 = &m.tools[&5];
        assert_eq!((t5.shape, t5.h, t5.d), (Some("ball:6".parse().unwrap()), 5, Some(25)));
        let h_is_not_t = parse("[tools]\nT3 = { shape = \"flat:10\", h = 13 }").unwrap();
        assert_eq!((h_is_not_t.tools[&3].h, h_is_not_t.tools[&3].d), (13, None));
        assert_eq!(m.settings.coords.reference_points[0], Axes { z: -10.0, ..Axes::ZERO });
        assert_eq!(m.settings.coords.control, Control::Fanuc);
        let l =
            parse("[coordinates]\ncontrol = \"LinuxCNC\"\nrotation_incremental = true\n[offsets]\nref4 = [1]").unwrap();
        // A key written with a space is the same key (it panicked on the space).
        let spaced = parse("[offsets]\n\"ref 3\" = [7]").unwrap();
        assert_eq!(spaced.settings.coords.reference_points[1].x, 7.0);
        assert_eq!(l.settings.coords.control, Control::LinuxCnc);
        assert!(l.settings.coords.rotation_incremental);
        assert_eq!(l.settings.coords.reference_points[2].x, 1.0);
        assert!(parse("[coordinates]\ncontrol = \"okuma\"").is_err());
        assert_eq!((m.settings.arc_tolerance, l.settings.arc_tolerance), (Some(0.02), None));
        assert!(parse("[coordinates]\narc_tolerance_mm = 0").is_err());
        assert!(parse("[offsets]\nref5 = [1]").is_err());
        assert_eq!(m.settings.comp_rules, Rules::Fanuc { startup: Approach::A });
        let b = parse("[comp]\nstartup = \"b\"").unwrap();
        assert_eq!(b.settings.comp_rules, Rules::Fanuc { startup: Approach::B });
        // The mill-turn: B -90 swings the tip 50 mm below the pivot to +X.
        let tip = m.kinematics.forward(&[0.0, 0.0, 0.0, 0.0, -90.0, 0.0]);
        assert!((tip[0] - 50.0).abs() < 1e-9 && tip[1].abs() < 1e-9 && (tip[2] - 120.0).abs() < 1e-9, "{tip:?}");
        assert!(m.kinematics.has(5) && !m.kinematics.has(3));
        let vars = &m.settings.macro_variables;
        assert!(vars.is_common(901_200) && !vars.is_common(250) && vars.is_kept(999) && !vars.is_kept(100));
        assert_eq!(vars.values[&500], 12.5);
        assert_eq!(m.settings.input_signals[&1000], 1.0);
        let empty = parse("").unwrap();
        assert_eq!(empty.kinematics, Kinematics::mill());
        assert_eq!(empty.settings.macro_variables, MacroVariables::default());
        // Without `kept`, #500-#999 is kept where the machine has it.
        let haas = parse("[macro]\ncommon = [\"100-199\", \"500-999\", \"10000-10999\"]").unwrap();
        assert_eq!(haas.settings.macro_variables.kept, [500..=999]);
        let small = parse("[macro]\ncommon = [\"100-149\"]").unwrap();
        assert!(small.settings.macro_variables.kept.is_empty());
    }

    #[test]
    fn a_tool_holds_its_registers_and_their_values() {
        let m = parse("[tools.T1]\nh = 1\nlength = 127.0\n[tools.T5]\nh = 15\nlength = 80\nradius = 3\n").unwrap();
        assert_eq!((m.settings.tool_lengths[&1], m.settings.tool_lengths[&15]), (127.0, 80.0));
        // A radius without d is the tool number's D register.
        assert_eq!((m.tools[&5].h, m.tools[&5].d, m.settings.tool_radii[&5]), (15, Some(5), 3.0));
        assert_eq!(m.tools[&1].d, None);
        // The same value by both forms is no conflict.
        let both = parse("[tools]\nlengths = { 1 = 50 }\n[tools.T1]\nlength = 50").unwrap();
        assert_eq!(both.settings.tool_lengths[&1], 50.0);
        // A tool's length is over the imported table's.
        let dir = Path::new("samples/tools");
        let files =
            BTreeMap::from([(dir.join("tool.tbl"), include_bytes!("../../../samples/tools/tool.tbl").to_vec())]);
        let text = "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n[tools.T1]\nlength = 30\nradius = 3\n";
        let (m, _) = Machine::parse(text, dir, &files).unwrap();
        assert_eq!((m.settings.tool_lengths[&1], m.settings.tool_lengths[&2]), (30.0, 47.625));
        assert_eq!(m.settings.tool_radii[&1], 3.0);
    }

    #[test]
    fn imports_a_tool_table_under_its_own_entries() {
        let dir = Path::new("samples/tools");
        let files =
            BTreeMap::from([(dir.join("tool.tbl"), include_bytes!("../../../samples/tools/tool.tbl").to_vec())]);
        let text = "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\nlengths = { 2 = 50 }\n\
                    [tools.T1]\nshape = \"flat:6.35\"\n[tools.T7]\nh = 17\n[tools.T8]\nshape = \"ball:2\"\n";
        let (m, notes) = Machine::parse(text, dir, &files).unwrap();
        assert_eq!(m.tools.keys().copied().collect::<Vec<_>>(), [1, 2, 3, 7, 8]);
        let t1 = &m.tools[&1];
        assert_eq!((t1.shape, t1.h, t1.d), (Some("flat:6.35".parse().unwrap()), 1, Some(1)));
        assert_eq!(t1.name.as_deref(), Some("1/4 flat end mill"));
        assert_eq!((m.tools[&7].h, m.tools[&7].d, m.tools[&7].name.as_deref()), (17, Some(7), Some("3/16 drill")));
        assert_eq!((m.tools[&8].h, m.tools[&8].d), (8, None));
        assert_eq!((m.settings.tool_lengths[&1], m.settings.tool_lengths[&2]), (31.75, 50.0));
        assert_eq!(m.settings.tool_radii[&7], 2.38125);
        // The tool.tbl's tools this file leaves without a shape, each named.
        let unshaped: Vec<&str> = notes.warnings.iter().map(|w| &w[..3]).collect();
        assert_eq!(unshaped, ["T2 ", "T3 ", "T7 "], "{notes:?}");
        assert!(notes.warnings[2].contains("T7 (3/16 drill): the tool.tbl gives no shape: add `shape"), "{notes:?}");
        for (text, words) in [
            ("[tools]\nimport = \"tool.tbl\"", "no units"),
            ("[tools]\nunits = \"mm\"", "tools.import names none"),
            ("[tools]\nimport = \"tool.tbl\"\nunits = \"furlong\"", "tools.units: 'furlong' is not a unit"),
            ("[tools]\nimport = \"missing.fctl\"", "tools.import: cannot read"),
            ("[tools]\nimport = \"mill.toml\"", "which tool file is it?"),
        ] {
            let e = Machine::parse(text, dir, &files).err().expect(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }

    #[test]
    fn rejects_nonsense() {
        assert!(parse("[motion]\nacceleration_mm_s2 = -1").is_err());
        assert!(parse("[motion]\nrapid = 1").is_err());
        assert!(parse("[offsets]\nG60 = [1]").is_err());
        assert!(parse("[comp]\nstartup = \"C\"").err().unwrap().to_string().contains("'C'"));
        for (text, words) in [
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Q\"]", "'Q' is not an axis"),
            ("[kinematics]\ntool = [\"X\", \"Y\"]", "no Z axis"),
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n[kinematics.axis.B]\naxis = [0, 1, 0]", "in neither"),
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n[kinematics.axis.X]\npivot = [0, 1, 0]", "a linear axis"),
            ("[kinematics]\ntool = [\"X\", \"X\", \"Z\"]", "twice"),
            ("[macro]\ncommon = [\"100-1999\"]", "[macro]: #100–#1999 overlaps the system variables"),
            ("[macro]\ncommon = [\"100 to 199\"]", "macro.common: '100 to 199' is not a variable range"),
            ("[macro]\nvalues = { 100 = 1 }", "[macro]: #100 is not kept over a reset"),
            ("[macro]\nsharp = true", "unknown field `sharp`"),
            ("[tools]\nT0 = { shape = \"ball:6\" }", "'T0' is not a tool"),
            ("[tools]\nT1 = { shape = \"ball:-6\" }", "tools.T1.shape"),
            ("[tools]\nT1 = { shape = \"ball:6\", lenght = 3 }", "unknown field `lenght`"),
            ("[tools]\nlengths = { 1 = 50 }\n[tools.T1]\nlength = 127", "tools.lengths 1 = 50 both set H1"),
            ("[tools.T1]\nlength = 127\n[tools.T2]\nh = 1\nlength = 12", "both set H1, to different values"),
            ("[tools.T1]\nlength = inf", "tools.T1.length"),
            ("[signals]\ninputs = { 1000 = 3 }", "[signals]: input #1000 is one bit"),
            ("[signals]\ninputs = { door = 1 }", "signals.inputs: 'door' is not a variable number"),
        ] {
            let e = parse(text).err().expect(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
