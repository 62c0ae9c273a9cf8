//! The machine file (`--machine M.toml`): rapids, acceleration, tool table,
//! work offsets and reference point.
//!
//! ```toml
//! [motion]
//! rapid_mm_min = [15000, 15000, 10000]   # X Y Z
//! rapid_deg_min = 3600                   # A B C
//! max_feed_mm_min = 10000
//! acceleration_mm_s2 = 1000
//! junction_deviation_mm = 0.01
//!
//! [tools]
//! lengths = { 1 = 100.5, 21 = 87.25 }    # H registers, mm
//! radii = { 1 = 3.0 }                    # D registers, mm
//!
//! [comp]                                 # cutter compensation (G41/G42)
//! startup = "A"                          # Fanuc start-up/cancel type A or B
//!
//! [offsets]
//! G54 = [0, 0, 0]                        # machine position of each work zero
//! home = [0, 0, 0]                       # G28 reference point (machine)
//!
//! [kinematics]                           # default: X, Y, Z carry the tool
//! tool = ["X", "Z", "B"]                 # axes carrying the tool, base out
//! work = ["Y", "C"]                      # axes carrying the part, base out
//! tip = [0, 0, 70]                       # tool tip, all axes at zero
//! [kinematics.axis.B]                    # default: along / about its own
//! axis = [0, 1, 0]                       #   letter's direction, pivot at 0
//! pivot = [0, 0, 120]
//! ```

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{bail, Context, Result};
use kezuri_geom::{Axes, Dynamics};
use kezuri_nc::interp::comp::{Approach, Rules};
use kezuri_nc::interp::Settings;
use kezuri_post::kinematics::{self, Axis, Kinematics, AXES};
use serde::Deserialize;

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    motion: Motion,
    #[serde(default)]
    tools: Tools,
    #[serde(default)]
    offsets: BTreeMap<String, Vec<f64>>,
    #[serde(default)]
    comp: CompFile,
    kinematics: Option<Chains>,
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
            .with_context(|| format!("kinematics: '{name}' is not an axis (X Y Z A B C)"))
    };
    if let Some(name) = c.axis.keys().find(|k| !c.tool.iter().chain(&c.work).any(|a| a.eq_ignore_ascii_case(k))) {
        bail!("kinematics.axis.{name}: the axis is in neither the tool nor the work chain");
    }
    let axis = |name: &String| -> Result<Axis> {
        let index = letter(name)?;
        let spec = c.axis.iter().find(|(k, _)| k.eq_ignore_ascii_case(name)).map(|(_, s)| s);
        let own = std::array::from_fn(|k| if k == index % 3 { 1.0 } else { 0.0 });
        let motion = if index < 3 {
            if spec.is_some_and(|s| s.axis.is_some() || s.pivot.is_some()) {
                bail!("kinematics.axis.{name}: a linear axis has a direction, not an axis or a pivot");
            }
            kinematics::Motion::Linear { direction: spec.and_then(|s| s.direction).unwrap_or(own) }
        } else {
            if spec.is_some_and(|s| s.direction.is_some()) {
                bail!("kinematics.axis.{name}: a rotary axis has an axis and a pivot, not a direction");
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
    k.check().map_err(|e| anyhow::anyhow!("kinematics: {e}"))?;
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
struct Tools {
    #[serde(default)]
    lengths: BTreeMap<String, f64>,
    #[serde(default)]
    radii: BTreeMap<String, f64>,
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
        Some(t) => bail!("comp.startup: '{t}' is not a start-up type: \"A\" or \"B\""),
    };
    Ok(Rules::Fanuc { startup })
}

/// A machine: its dynamics, what it tells the interpreter, its axes.
pub struct Machine {
    /// For the cycle time.
    pub dynamics: Dynamics,
    /// Tool table, offsets and reference point, on top of the defaults.
    pub settings: Settings,
    /// Which axes carry the tool and which the work.
    pub kinematics: Kinematics,
}

impl Default for Machine {
    fn default() -> Machine {
        Machine { dynamics: Dynamics::default(), settings: Settings::default(), kinematics: Kinematics::mill() }
    }
}

fn positive(name: &str, v: Option<f64>, default: f64) -> Result<f64> {
    match v {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => bail!("{name} must be a positive number, got {v}"),
    }
}

fn axes(name: &str, v: &[f64]) -> Result<Axes> {
    if v.is_empty() || v.len() > 6 || v.iter().any(|x| !x.is_finite()) {
        bail!("{name} must list 1 to 6 finite numbers (X Y Z A B C)");
    }
    let mut a = [0.0; 6];
    a[..v.len()].copy_from_slice(v);
    Ok(Axes::from_array(a))
}

fn registers(name: &str, map: &BTreeMap<String, f64>) -> Result<BTreeMap<u32, f64>> {
    map.iter()
        .map(|(k, &v)| {
            let n: u32 = k.parse().with_context(|| format!("{name}: '{k}' is not a register number"))?;
            if !v.is_finite() {
                bail!("{name}.{k} is not a finite number");
            }
            Ok((n, v))
        })
        .collect()
}

impl Machine {
    /// Reads a machine file.
    pub fn load(path: &Path) -> Result<Machine> {
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
        Machine::parse(&text).with_context(|| format!("in machine file {}", path.display()))
    }

    fn parse(text: &str) -> Result<Machine> {
        let file: File = toml::from_str(text)?;
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
            Some(_) => bail!("rapid_mm_min takes one rate, or three (X Y Z)"),
        };
        let dynamics = Dynamics {
            rapid_mm_min: rapid,
            rapid_deg_min: positive("rapid_deg_min", m.rapid_deg_min, d.rapid_deg_min)?,
            max_feed_mm_min: positive("max_feed_mm_min", m.max_feed_mm_min, d.max_feed_mm_min)?,
            acceleration_mm_s2: positive("acceleration_mm_s2", m.acceleration_mm_s2, d.acceleration_mm_s2)?,
            junction_deviation_mm: positive("junction_deviation_mm", m.junction_deviation_mm, d.junction_deviation_mm)?,
        };
        let mut settings = Settings {
            tool_lengths: registers("tools.lengths", &file.tools.lengths)?,
            tool_radii: registers("tools.radii", &file.tools.radii)?,
            comp_rules: comp_rules(&file.comp)?,
            ..Settings::default()
        };
        for (name, v) in &file.offsets {
            let a = axes(name, v)?;
            match name.to_uppercase().as_str() {
                "HOME" => settings.home = a,
                g => match g.strip_prefix('G').and_then(|n| n.parse::<usize>().ok()) {
                    Some(n @ 54..=59) => settings.work_offsets[n - 54] = a,
                    _ => bail!("offsets: '{name}' is not G54 … G59 or home"),
                },
            }
        }
        let kinematics = match &file.kinematics {
            Some(c) => chains(c)?,
            None => Kinematics::mill(),
        };
        Ok(Machine { dynamics, settings, kinematics })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let m = Machine::parse(&example).unwrap();
        assert_eq!(m.dynamics.rapid_mm_min, [15000.0, 15000.0, 10000.0]);
        assert_eq!(m.settings.tool_lengths[&21], 87.25);
        assert_eq!(m.settings.comp_rules, Rules::Fanuc { startup: Approach::A });
        let b = Machine::parse("[comp]\nstartup = \"b\"").unwrap();
        assert_eq!(b.settings.comp_rules, Rules::Fanuc { startup: Approach::B });
        // The mill-turn: B -90 swings the tip 50 mm below the pivot to +X.
        let tip = m.kinematics.forward(&[0.0, 0.0, 0.0, 0.0, -90.0, 0.0]);
        assert!((tip[0] - 50.0).abs() < 1e-9 && tip[1].abs() < 1e-9 && (tip[2] - 120.0).abs() < 1e-9, "{tip:?}");
        assert!(m.kinematics.has(5) && !m.kinematics.has(3));
        assert_eq!(Machine::parse("").unwrap().kinematics, Kinematics::mill());
    }

    #[test]
    fn rejects_nonsense() {
        assert!(Machine::parse("[motion]\nacceleration_mm_s2 = -1").is_err());
        assert!(Machine::parse("[motion]\nrapid = 1").is_err());
        assert!(Machine::parse("[offsets]\nG60 = [1]").is_err());
        assert!(format!("{:#}", Machine::parse("[comp]\nstartup = \"C\"").err().unwrap()).contains("'C'"));
        for (text, words) in [
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Q\"]", "'Q' is not an axis"),
            ("[kinematics]\ntool = [\"X\", \"Y\"]", "no Z axis"),
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n[kinematics.axis.B]\naxis = [0, 1, 0]", "in neither"),
            ("[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n[kinematics.axis.X]\npivot = [0, 1, 0]", "a linear axis"),
            ("[kinematics]\ntool = [\"X\", \"X\", \"Z\"]", "twice"),
        ] {
            let e = format!("{:#}", Machine::parse(text).err().expect(text));
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
