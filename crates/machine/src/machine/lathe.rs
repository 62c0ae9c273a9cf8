//! The machine file's `[machine]`: what kind of machine it is, and a
//! lathe's conventions — how its X words are read, the Fanuc G code system
//! it follows, the spindle's top speed.

use std::fmt;

use kezuri_nc::interp::{GCodeSystem, Lathe, XMode};
use serde::Deserialize;

use crate::error::{fail, Result};

/// `[machine]`.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct MachineFile {
    /// `"mill"`, `"lathe"` or `"mill-turn"`.
    kind: Option<String>,
    /// `"diameter"` or `"radius"`: how X is read at power-on (lathes).
    x: Option<String>,
    /// `"A"`, `"B"` or `"C"`: the Fanuc lathe's G code system.
    gcode_system: Option<String>,
    /// The spindle's top speed, rpm.
    max_rpm: Option<f64>,
}

/// What kind of machine the file describes (`[machine] kind`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MachineKind {
    /// A milling machine: the tool turns (the default).
    #[default]
    Mill,
    /// A lathe: the part turns, the tool moves in X (its distance from the
    /// spindle axis) and Z (along it).
    Lathe,
    /// A lathe with driven tools (a turning centre, a Swiss-type): it runs
    /// lathe programs.
    MillTurn,
}

impl MachineKind {
    /// The name the machine file uses: `mill`, `lathe` or `mill-turn`.
    pub fn name(self) -> &'static str {
        match self {
            MachineKind::Mill => "mill",
            MachineKind::Lathe => "lathe",
            MachineKind::MillTurn => "mill-turn",
        }
    }

    /// Whether the machine turns (a lathe or a mill-turn): its Fanuc and
    /// Haas programs are read as a lathe's.
    pub fn turns(self) -> bool {
        self != MachineKind::Mill
    }
}

impl fmt::Display for MachineKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What `[machine]` says: the kind, a lathe's conventions (`None` for a
/// mill) and the spindle's top speed.
pub(super) struct Read {
    pub kind: MachineKind,
    pub lathe: Option<Lathe>,
    pub max_rpm: Option<f64>,
}

/// Reads `[machine]`. A mill has no lathe conventions: `x` or
/// `gcode_system` under `kind = "mill"` is an error.
pub(super) fn read(m: &MachineFile) -> Result<Read> {
    let kind = match m.kind.as_deref().map(|t| t.trim().to_ascii_lowercase()) {
        None => MachineKind::Mill,
        Some(t) => match t.as_str() {
            "mill" => MachineKind::Mill,
            "lathe" => MachineKind::Lathe,
            "mill-turn" => MachineKind::MillTurn,
            _ => fail!(Invalid, "machine.kind: '{t}' is not a kind of machine: \"mill\", \"lathe\" or \"mill-turn\""),
        },
    };
    let x = match m.x.as_deref().map(|t| t.trim().to_ascii_lowercase()) {
        None => XMode::Diameter,
        Some(t) => match t.as_str() {
            "diameter" => XMode::Diameter,
            "radius" => XMode::Radius,
            _ => fail!(Invalid, "machine.x: '{t}' is not how X is read: \"diameter\" or \"radius\""),
        },
    };
    let system = match m.gcode_system.as_deref().map(|t| t.trim().to_ascii_uppercase()) {
        None => GCodeSystem::A,
        Some(t) => match t.as_str() {
            "A" => GCodeSystem::A,
            "B" => GCodeSystem::B,
            "C" => GCodeSystem::C,
            _ => fail!(Invalid, "machine.gcode_system: '{t}' is not a G code system: \"A\", \"B\" or \"C\""),
        },
    };
    if !kind.turns() {
        for (key, given) in [("x", m.x.is_some()), ("gcode_system", m.gcode_system.is_some())] {
            if given {
                fail!(
                    Invalid,
                    "machine.{key} is a lathe's: the machine is a mill (kind = \"mill\", the default); \
                     say kind = \"lathe\" or \"mill-turn\""
                );
            }
        }
    }
    let max_rpm = match m.max_rpm {
        None => None,
        Some(v) if v.is_finite() && v > 0.0 && v <= MAX_RPM => Some(v),
        Some(v) => {
            fail!(Invalid, "machine.max_rpm: {v} is not a spindle speed: a positive number of rpm, at most {MAX_RPM}")
        }
    };
    let lathe = kind.turns().then_some(Lathe { x, system });
    Ok(Read { kind, lathe, max_rpm })
}

/// The highest top speed a machine file may give, rpm: above any spindle
/// made (high-speed spindles reach 60,000–100,000 rpm).
const MAX_RPM: f64 = 1_000_000.0;

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::path::{Path, PathBuf};

    use kezuri_nc::interp::Nose;

    use super::*;
    use crate::Machine;

    /// A machine file with nothing beside it.
    fn parse(text: &str) -> Result<Machine> {
        Ok(Machine::parse(text, Path::new(""), &BTreeMap::<PathBuf, Vec<u8>>::new())?.0)
    }

    fn read_text(text: &str) -> Result<Read> {
        read(
            &toml::from_str::<MachineFile>(text)
                .map_err(|e| crate::Error::new(crate::ErrorKind::Syntax, e.to_string()))?,
        )
    }

    #[test]
    fn a_lathe_powers_on_in_diameter_and_system_a() {
        let r = read_text("kind = \"lathe\"").unwrap();
        assert_eq!(r.kind, MachineKind::Lathe);
        assert_eq!(r.lathe, Some(Lathe { x: XMode::Diameter, system: GCodeSystem::A }));
        assert_eq!(r.max_rpm, None);
        let r = read_text("kind = \"Mill-Turn\"\nx = \"radius\"\ngcode_system = \"b\"\nmax_rpm = 4500").unwrap();
        assert_eq!((r.kind, r.kind.name(), r.kind.turns()), (MachineKind::MillTurn, "mill-turn", true));
        assert_eq!(r.lathe, Some(Lathe { x: XMode::Radius, system: GCodeSystem::B }));
        assert_eq!(r.max_rpm, Some(4500.0));
        let c = read_text("kind = \"lathe\"\ngcode_system = \"C\"\nmax_rpm = 3000.5").unwrap();
        assert_eq!((c.lathe.unwrap().system, c.max_rpm), (GCodeSystem::C, Some(3000.5)));
    }

    #[test]
    fn a_mill_has_no_lathe_conventions() {
        let r = read_text("").unwrap();
        assert_eq!((r.kind, r.lathe, r.max_rpm), (MachineKind::Mill, None, None));
        assert!(!r.kind.turns());
        // A mill's top speed is a spindle's too.
        let r = read_text("kind = \"mill\"\nmax_rpm = 24000").unwrap();
        assert_eq!((r.kind, r.lathe, r.max_rpm), (MachineKind::Mill, None, Some(24000.0)));
    }

    #[test]
    fn a_lathe_file_gives_its_conventions_and_noses() {
        let text = "[machine]\nkind = \"lathe\"\nmax_rpm = 3500\n\
                    [tools.T1]\nnose_radius = 0.8\ntip = 3\nname = \"CNMG 120408\"\n\
                    [tools.T2]\nnose_radius = 0.4\n\
                    [tools.T3]\ntip = 9\n\
                    [tools.T4]\nnose_radius = 0\ntip = 2\n\
                    [tools.T5]\nshape = \"drill:8,118\"\n";
        let m = parse(text).unwrap();
        assert_eq!(m.kind, MachineKind::Lathe);
        // A lathe powers on with X a diameter, in G code system A.
        assert_eq!(m.settings.lathe, Some(Lathe { x: XMode::Diameter, system: GCodeSystem::A }));
        assert_eq!(m.settings.max_rpm, Some(3500.0));
        let noses: Vec<(u32, f64, u8)> = m.settings.noses.iter().map(|(&t, n)| (t, n.radius, n.tip)).collect();
        // A radius with no tip is measured to the nose centre (tip 0); a
        // tip 9 with no radius is the centre of a sharp nose; a drill has none.
        assert_eq!(noses, [(1, 0.8, 3), (2, 0.4, 0), (3, 0.0, 9), (4, 0.0, 2)]);
        assert_eq!(m.tools[&1].nose, Some(Nose { radius: 0.8, tip: 3 }));
        assert_eq!(m.tools[&5].nose, None);
        // A mill-turn in system B, X a radius.
        let mt = parse("[machine]\nkind = \"mill-turn\"\nx = \"radius\"\ngcode_system = \"B\"").unwrap();
        assert_eq!(mt.kind, MachineKind::MillTurn);
        assert_eq!(mt.settings.lathe, Some(Lathe { x: XMode::Radius, system: GCodeSystem::B }));
        // A mill's file stays as it was: no lathe, no top speed, no noses.
        let mill = parse("[tools.T1]\nshape = \"flat:6\"").unwrap();
        assert_eq!((mill.kind, mill.settings.lathe, mill.settings.max_rpm), (MachineKind::Mill, None, None));
        assert!(mill.settings.noses.is_empty());
    }

    #[test]
    fn a_lathe_tool_table_gives_noses_in_fanuc_tips() {
        // Lines of LinuxCNC's sim lathe tool table (sample-configs/sim/axis/
        // lathe.tbl): D the nose diameter, Q the orientation.
        let dir = Path::new("lathe");
        let tbl = "T1 P1 D0.100000 Z+0.100000 I+95.000000 J+155.000000 Q1 ;\n\
                   T2 P2 D0.100000 I+85.000000 J+25.000000 Q2 ;\n\
                   T6 P6 D0.100000 X+0.500000 Z+0.500000 I+120.000000 J+60.000000 Q6 ;\n\
                   T9 P9 D0.100000 Q9 ;\n\
                   T10 P10 D0. ; demo zero diameter\n";
        let files = BTreeMap::from([(dir.join("lathe.tbl"), tbl.as_bytes().to_vec())]);
        let text = "[machine]\nkind = \"lathe\"\n[tools]\nimport = \"lathe.tbl\"\nunits = \"inch\"\n\
                    [tools.T2]\nnose_radius = 0.8\n[tools.T9]\ntip = 0\n";
        let (m, _) = Machine::parse(text, dir, &files).unwrap();
        let noses: Vec<(u32, f64, u8)> = m.settings.noses.iter().map(|(&t, n)| (t, n.radius, n.tip)).collect();
        // 0.1 inch is 2.54 mm: a 1.27 mm nose radius. LinuxCNC's Q1 (−X, +Z)
        // is Fanuc's tip 4, Q2 (−X, −Z, the outside turning tool) tip 3,
        // Q6 (−X) tip 8, Q9 the centre; T10 has no orientation, so no nose.
        // The machine file's nose radius and tip are over the table's.
        assert_eq!(noses, [(1, 1.27, 4), (2, 0.8, 3), (6, 1.27, 8), (9, 1.27, 0)]);
    }

    #[test]
    fn reads_the_example_of_docs_lathe_md() {
        let doc = include_str!("../../../../docs/lathe.md");
        let example: String = doc
            .lines()
            .skip_while(|l| !l.starts_with("```toml"))
            .skip(1)
            .take_while(|l| !l.starts_with("```"))
            .map(|l| l.to_string() + "\n")
            .collect();
        let m = parse(&example).unwrap();
        assert_eq!(m.kind, MachineKind::Lathe);
        assert_eq!(m.settings.lathe, Some(Lathe { x: XMode::Diameter, system: GCodeSystem::A }));
        assert_eq!(m.settings.max_rpm, Some(4000.0));
        let noses: Vec<(u32, f64, u8)> = m.settings.noses.iter().map(|(&t, n)| (t, n.radius, n.tip)).collect();
        assert_eq!(noses, [(1, 0.8, 3), (2, 0.4, 2)]);
    }

    #[test]
    fn bad_values_name_the_key_and_what_it_takes() {
        for (text, words) in [
            (
                "[machine]\nkind = \"drill\"",
                "machine.kind: 'drill' is not a kind of machine: \"mill\", \"lathe\" or \"mill-turn\"",
            ),
            (
                "[machine]\nkind = \"lathe\"\nx = \"dia\"",
                "machine.x: 'dia' is not how X is read: \"diameter\" or \"radius\"",
            ),
            (
                "[machine]\nkind = \"lathe\"\ngcode_system = \"D\"",
                "machine.gcode_system: 'D' is not a G code system: \"A\", \"B\" or \"C\"",
            ),
            ("[machine]\nx = \"radius\"", "machine.x is a lathe's: the machine is a mill"),
            ("[machine]\nkind = \"mill\"\ngcode_system = \"B\"", "machine.gcode_system is a lathe's"),
            (
                "[machine]\nkind = \"lathe\"\nmax_rpm = 0",
                "machine.max_rpm: 0 is not a spindle speed: a positive number of rpm",
            ),
            ("[machine]\nmax_rpm = -3000", "machine.max_rpm: -3000 is not a spindle speed"),
            ("[machine]\nmax_rpm = nan", "machine.max_rpm: NaN is not a spindle speed"),
            ("[machine]\nkind = \"lathe\"\nspeed = 3000", "unknown field `speed`"),
            ("[machine]\nkind = 3", "invalid type: integer `3`, expected a string"),
            ("[tools.T1]\ntip = 3", "tools.T1.tip = 3 with no tools.T1.nose_radius"),
            (
                "[tools.T1]\nnose_radius = 0.4\ntip = 10",
                "tools.T1.tip = 10: the imaginary tool tip direction is 0 to 9",
            ),
            (
                "[tools.T1]\nnose_radius = 0.4\ntip = -1",
                "tools.T1.tip = -1: the imaginary tool tip direction is 0 to 9",
            ),
            ("[tools.T1]\nnose_radius = -0.4\ntip = 3", "tools.T1.nose_radius must be zero or a length"),
            ("[tools.T1]\nnose_radius = inf", "tools.T1.nose_radius must be zero or a length"),
        ] {
            let e = parse(text).err().expect(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
