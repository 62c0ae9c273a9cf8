//! FreeCAD's tool bits and tool libraries (the Path workbench's, 0.19 on).
//! A bit (`.fctb`, JSON, `"version": 2`) names its shape file
//! (`endmill.fcstd`, `ballend.fcstd`, …) and gives the shape's parameters
//! as FreeCAD quantities ("6.0000 mm", "60.0000 °"). A library (`.fctl`,
//! `"version": 1`) numbers bits: `{"nr": 1, "path": "5mm_Endmill.fctb"}`,
//! a relative path found, as FreeCAD finds it, in the `Bit` folder beside
//! the library's folder (`Tools/Library/x.fctl` → `Tools/Bit/`), and here
//! also beside the library itself. A bit gives no register values.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use kezuri_cam::Cutter;
use serde::Deserialize;
use serde_json::Value;

use super::{cutter, from_json, Table};
use crate::error::{fail, Error, ErrorKind, Result};
use crate::files::{read_text, Files};
use crate::machine::ToolEntry;

#[derive(Deserialize)]
struct Bit {
    version: u32,
    name: Option<String>,
    shape: String,
    #[serde(default)]
    parameter: BTreeMap<String, Value>,
}

#[derive(Deserialize)]
struct Library {
    version: u32,
    tools: Vec<Numbered>,
}

#[derive(Deserialize)]
struct Numbered {
    nr: i64,
    path: String,
}

/// A bit file: its name and the cutter of its shape, where kezuri has one
/// (a warning, starting with `what`, where not).
fn read_bit(
    path: &Path,
    files: &dyn Files,
    what: &str,
    warnings: &mut Vec<String>,
) -> Result<(Option<String>, Option<Cutter>)> {
    let file = path.display().to_string();
    let bit: Bit = from_json(&file, &read_text(files, path)?)?;
    if bit.version != 2 {
        fail!(
            UnknownFormat,
            "{file}: tool bit format version {}: kezuri reads version 2 (FreeCAD 0.19 on)",
            bit.version
        );
    }
    let shape = shape_of(&file, &bit, what, warnings)?;
    Ok((bit.name, shape))
}

/// The cutter of a bit's shape, where kezuri has one (a warning, starting
/// with `what`, where not).
fn shape_of(file: &str, bit: &Bit, what: &str, warnings: &mut Vec<String>) -> Result<Option<Cutter>> {
    let length = |key: &str| quantity(file, bit, key, LENGTHS);
    let angle = |key: &str| quantity(file, bit, key, ANGLES);
    let shape = Path::new(&bit.shape).file_stem().map(|s| s.to_string_lossy().to_lowercase()).unwrap_or_default();
    let Some(d) = length("Diameter")? else {
        warnings.push(format!("{what}: no shape: the bit gives no Diameter"));
        return Ok(None);
    };
    let spec = match shape.as_str() {
        "endmill" => Some(format!("flat:{d}")),
        "ballend" => Some(format!("ball:{d}")),
        "bullnose" => match (length("CornerRadius")?, length("FlatRadius")?) {
            (Some(r), _) => Some(format!("bull:{d},{r}")),
            (None, Some(flat)) => Some(format!("bull:{d},{}", d / 2.0 - flat)),
            (None, None) => None,
        },
        "v-bit" | "chamfer" => match length("TipDiameter")?.unwrap_or(0.0) {
            tip if tip > 0.0 => {
                warnings.push(format!(
                    "{what}: no shape: a {shape} with a {tip} mm flat tip (kezuri's v cutter is pointed)"
                ));
                return Ok(None);
            }
            _ => angle("CuttingEdgeAngle")?.map(|a| format!("v:{d},{a}")),
        },
        "drill" => angle("TipAngle")?.map(|a| format!("v:{d},{a}")),
        other => {
            warnings.push(format!("{what}: no shape: kezuri cannot cut with a '{other}' ({})", bit.shape));
            return Ok(None);
        }
    };
    let Some(spec) = spec else {
        warnings.push(format!("{what}: no shape: the {shape} bit lacks the sizes of its shape"));
        return Ok(None);
    };
    Ok(cutter(spec, what, warnings))
}

/// Reads a bit alone: one tool, numbered 1 (a bit has no number).
pub fn read_bit_file(path: &Path, files: &dyn Files) -> Result<Table> {
    let mut table = Table::new("FreeCAD tool bit");
    let (name, shape) = read_bit(path, files, "T1", &mut table.notes.warnings)?;
    table.notes.warnings.push("a tool bit has no number: shown as T1 (a library .fctl numbers its bits)".into());
    table.add(1, ToolEntry { shape, h: 1, d: None, name, nose: None }, "");
    Ok(table)
}

/// Reads a library and the bits it numbers.
pub fn read_library(path: &Path, files: &dyn Files) -> Result<Table> {
    let file = path.display().to_string();
    let library: Library = from_json(&file, &read_text(files, path)?)?;
    if library.version != 1 {
        fail!(UnknownFormat, "{file}: tool library format version {}: kezuri reads version 1", library.version);
    }
    let mut table = Table::new("FreeCAD tool library");
    let dir = path.parent().unwrap_or(Path::new(""));
    for t in &library.tools {
        let Some(number) = u32::try_from(t.nr).ok().filter(|&n| n > 0) else {
            table.notes.skipped.push(format!("{}: nr {} is not a tool number", t.path, t.nr));
            continue;
        };
        let places = bit_places(dir, &t.path);
        let Some(bit) = places.iter().find(|p| files.is_file(p)) else {
            let looked: Vec<String> = places.iter().map(|p| p.display().to_string()).collect();
            table.notes.skipped.push(format!("T{number}: bit {} not found (looked for {})", t.path, looked.join(", ")));
            continue;
        };
        let what = format!("T{number} ({})", t.path);
        let (name, shape) = read_bit(bit, files, &what, &mut table.notes.warnings)?;
        table.add(number, ToolEntry { shape, h: number, d: None, name, nose: None }, &t.path);
    }
    Ok(table)
}

/// Where a library's bit may be: its path if absolute, else the `Bit`
/// folder beside the library's folder, then the library's folder.
fn bit_places(dir: &Path, bit: &str) -> Vec<PathBuf> {
    if Path::new(bit).is_absolute() {
        return vec![PathBuf::from(bit)];
    }
    let beside = dir.parent().map(|up| up.join("Bit")).unwrap_or_else(|| dir.join("..").join("Bit"));
    vec![beside.join(bit), dir.join(bit)]
}

/// Lengths FreeCAD may write, in mm.
const LENGTHS: &[(&str, f64)] = &[
    ("", 1.0),
    ("mm", 1.0),
    ("cm", 10.0),
    ("m", 1000.0),
    ("µm", 1e-3),
    ("um", 1e-3),
    ("in", 25.4),
    ("\"", 25.4),
    ("ft", 304.8),
    ("'", 304.8),
    ("thou", 0.0254),
    ("mil", 0.0254),
];
/// Angles FreeCAD may write, in degrees.
const ANGLES: &[(&str, f64)] = &[("", 1.0), ("°", 1.0), ("deg", 1.0)];

/// A parameter of the bit as a number in mm (or degrees): a FreeCAD
/// quantity, its decimal point a point or a comma as the user's locale
/// writes it; `None` where the bit lacks it.
fn quantity(file: &str, bit: &Bit, key: &str, units: &[(&str, f64)]) -> Result<Option<f64>> {
    let Some(v) = bit.parameter.get(key) else { return Ok(None) };
    let bad = || {
        let kind = if units == ANGLES { "an angle" } else { "a length" };
        Error::new(ErrorKind::Invalid, format!("{file}: parameter {key}: {v} is not {kind}"))
    };
    let text = match v {
        Value::Number(n) => return n.as_f64().map(Some).ok_or_else(bad),
        Value::String(s) => s.trim(),
        _ => return Err(bad()),
    };
    let end = text.find(|c: char| !(c.is_ascii_digit() || "+-.,eE".contains(c))).unwrap_or(text.len());
    let (number, unit) = text.split_at(end);
    let number = if number.contains('.') { number.replace(',', "") } else { number.replace(',', ".") };
    let scale = units.iter().find(|(u, _)| *u == unit.trim()).map(|(_, s)| *s).ok_or_else(bad)?;
    match number.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(Some((x * scale * 1e9).round() / 1e9)),
        _ => Err(bad()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bit(shape: &str, parameter: &str) -> Bit {
        from_json(
            "b.fctb",
            &format!("{{\"version\": 2, \"name\": \"x\", \"shape\": \"{shape}\", \"parameter\": {{{parameter}}}}}"),
        )
        .unwrap()
    }

    #[test]
    fn quantities_in_the_users_units_and_locale() {
        let b = bit(
            "endmill.fcstd",
            r#""A": "6.0000 mm", "B": "6,35 mm", "C": "0.2500 in", "D": "60.00 °", "E": 3, "F": "1,234.5 mm", "G": "six mm", "H": "3 furlong""#,
        );
        let q = |k: &str, u| quantity("b.fctb", &b, k, u);
        assert_eq!(q("A", LENGTHS).unwrap(), Some(6.0));
        assert_eq!(q("B", LENGTHS).unwrap(), Some(6.35));
        assert_eq!(q("C", LENGTHS).unwrap(), Some(6.35));
        assert_eq!(q("D", ANGLES).unwrap(), Some(60.0));
        assert_eq!(q("E", LENGTHS).unwrap(), Some(3.0));
        assert_eq!(q("F", LENGTHS).unwrap(), Some(1234.5));
        assert_eq!(q("Z", LENGTHS).unwrap(), None);
        let e = q("G", LENGTHS).unwrap_err().to_string();
        assert!(e.contains("b.fctb: parameter G: \"six mm\" is not a length"), "{e}");
        assert!(q("H", LENGTHS).is_err());
        assert!(q("A", ANGLES).unwrap_err().to_string().contains("is not an angle"));
    }

    #[test]
    fn shapes_map_to_cutters_or_warn() {
        let mut w = Vec::new();
        let mut spec =
            |shape: &str, p: &str| shape_of("b.fctb", &bit(shape, p), "T1", &mut w).unwrap().map(|c| c.to_string());
        assert_eq!(spec("endmill.fcstd", r#""Diameter": "5.00 mm""#).as_deref(), Some("flat:5"));
        assert_eq!(spec("ballend.fcstd", r#""Diameter": "6.00 mm""#).as_deref(), Some("ball:6"));
        assert_eq!(
            spec("bullnose.fcstd", r#""Diameter": "6 mm", "FlatRadius": "1.5 mm""#).as_deref(),
            Some("bull:6,1.5")
        );
        assert_eq!(
            spec("bullnose.fcstd", r#""Diameter": "6 mm", "CornerRadius": "0.5 mm""#).as_deref(),
            Some("bull:6,0.5")
        );
        assert_eq!(
            spec("v-bit.fcstd", r#""Diameter": "10 mm", "CuttingEdgeAngle": "60 °", "TipDiameter": "0 mm""#).as_deref(),
            Some("v:10,60")
        );
        assert_eq!(spec("drill.fcstd", r#""Diameter": "5 mm", "TipAngle": "118 °""#).as_deref(), Some("v:5,118"));
        assert_eq!(
            spec("v-bit.fcstd", r#""Diameter": "10 mm", "CuttingEdgeAngle": "60 °", "TipDiameter": "1 mm""#),
            None
        );
        assert_eq!(spec("thread-mill.fcstd", r#""Diameter": "5 mm""#), None);
        assert_eq!(spec("bullnose.fcstd", r#""Diameter": "6 mm", "CornerRadius": "4 mm""#), None);
        assert_eq!(spec("endmill.fcstd", r#""Length": "6 mm""#), None);
        assert!(w[0].contains("T1: no shape: a v-bit with a 1 mm flat tip"), "{w:?}");
        assert!(w[1].contains("kezuri cannot cut with a 'thread-mill'"), "{w:?}");
        assert!(w[2].contains("corner radius"), "{w:?}");
        assert!(w[3].contains("no Diameter"), "{w:?}");
    }
}
