//! Fusion 360's tool library as it exports it: JSON `{"data": [tool…]}`,
//! each tool with its `type` ("flat end mill", "ball end mill", …), `unit`
//! ("millimeters" or "inches"), `geometry` (DC cutting diameter, RE corner
//! radius, TA taper angle from the axis, SIG point angle, tip-diameter),
//! `post-process` (number, length-offset and diameter-offset: register
//! numbers, not values) and `description`. A `.tools` file is a zip archive
//! holding that JSON. Holders and tools that are not milling tools
//! (turning, cutting heads) are skipped.

use std::io::Read;
use std::path::Path;

use kezuri_cam::Cutter;
use serde_json::Value;

use super::{cutter, from_json, Table, Units};
use crate::error::{fail, with_sources, Error, ErrorKind, Result};
use crate::files::{read_bytes, read_text, Files};
use crate::machine::ToolEntry;

/// Types kezuri cuts with, and the spindle tools it reads without a shape.
const SHAPED: &[&str] =
    &["flat end mill", "ball end mill", "bull nose end mill", "face mill", "chamfer mill", "spot drill", "drill"];
const UNSHAPED: &[&str] = &[
    "slot mill",
    "radius mill",
    "dovetail mill",
    "tapered mill",
    "lollipop mill",
    "thread mill",
    "form mill",
    "counter bore",
    "counter sink",
    "center drill",
    "reamer",
    "boring bar",
    "tap right hand",
    "tap left hand",
    "probe",
];

/// Reads a library exported as JSON.
pub fn read_json(path: &Path, files: &dyn Files) -> Result<Table> {
    let file = path.display().to_string();
    parse(&file, &read_text(files, path)?)
}

/// Reads a `.tools` file: a zip archive of the library's JSON.
pub fn read_zip(path: &Path, files: &dyn Files) -> Result<Table> {
    let file = path.display().to_string();
    let bytes = read_bytes(files, path)?;
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).map_err(|e| {
        let why = with_sources(&e);
        Error::new(ErrorKind::Syntax, format!("{file}: not a zip archive (a Fusion 360 .tools file is one): {why}"))
    })?;
    let names: Vec<String> = zip.file_names().filter_map(|n| n.ok()).map(|n| n.into_owned()).collect();
    let Some(json) = names.iter().find(|n| n.ends_with(".json")) else {
        fail!(UnknownFormat, "{file}: the archive holds no .json tool library");
    };
    let mut entry = zip.by_name(json).map_err(|e| {
        Error::new(ErrorKind::Syntax, format!("{file}: cannot read {json} in the archive: {}", with_sources(&e)))
    })?;
    let inner = format!("{file}/{json}");
    let mut text = String::new();
    entry.read_to_string(&mut text).map_err(|e| {
        Error::new(ErrorKind::Syntax, format!("{inner}: cannot read it (not UTF-8 JSON?): {}", with_sources(&e)))
    })?;
    parse(&inner, &text)
}

fn parse(file: &str, text: &str) -> Result<Table> {
    let library: Value = from_json(file, text)?;
    let Some(tools) = library.get("data").and_then(Value::as_array) else {
        fail!(UnknownFormat, "{file}: no \"data\" list of tools: not a Fusion 360 tool library");
    };
    let mut table = Table::new("Fusion 360 tool library");
    for (i, tool) in tools.iter().enumerate() {
        let kind = tool.get("type").and_then(Value::as_str).unwrap_or("").trim().to_lowercase();
        let name = ["description", "product-id"]
            .iter()
            .find_map(|k| tool.get(*k).and_then(Value::as_str).map(str::trim).filter(|s| !s.is_empty()))
            .map(String::from);
        let what = format!("tool {} ({kind}{})", i + 1, name.as_deref().map(|n| format!(", {n}")).unwrap_or_default());
        if !SHAPED.contains(&kind.as_str()) && !UNSHAPED.contains(&kind.as_str()) {
            table.notes.skipped.push(format!("{what}: not a milling tool"));
            continue;
        }
        let post = |key: &str| -> Result<Option<u32>> {
            match tool.get("post-process").and_then(|p| p.get(key)) {
                None | Some(Value::Null) => Ok(None),
                Some(v) => match v.as_u64().and_then(|n| u32::try_from(n).ok()) {
                    Some(n) => Ok(Some(n)),
                    None => fail!(Invalid, "{file}: {what}: post-process {key} {v} is not a register number"),
                },
            }
        };
        let Some(number) = post("number")?.filter(|&n| n > 0) else {
            table.notes.skipped.push(format!("{what}: no tool number"));
            continue;
        };
        let what = format!("T{number} {what}");
        let shape = if SHAPED.contains(&kind.as_str()) {
            shape(file, tool, &kind, &what, &mut table.notes.warnings)?
        } else {
            table.notes.warnings.push(format!("{what}: no shape: kezuri cannot cut with a {kind}"));
            None
        };
        let h = post("length-offset")?.filter(|&h| h > 0).unwrap_or(number);
        let d = post("diameter-offset")?.filter(|&d| d > 0);
        table.add(number, ToolEntry { shape, h, d, name, nose: None }, &what);
    }
    Ok(table)
}

/// The cutter of a tool whose type kezuri cuts with.
fn shape(file: &str, tool: &Value, kind: &str, what: &str, warnings: &mut Vec<String>) -> Result<Option<Cutter>> {
    let units = match tool.get("unit").and_then(Value::as_str) {
        Some("millimeters") => Units::Mm,
        Some("inches") => Units::Inch,
        other => fail!(
            Invalid,
            "{file}: {what}: the unit must be \"millimeters\" or \"inches\", not {}",
            other.map(|u| format!("\"{u}\"")).unwrap_or_else(|| "missing".into())
        ),
    };
    let number = |key: &str| -> Result<Option<f64>> {
        match tool.get("geometry").and_then(|g| g.get(key)) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => match v.as_f64() {
                Some(x) if x.is_finite() => Ok(Some(x)),
                _ => fail!(Invalid, "{file}: {what}: geometry {key} {v} is not a number"),
            },
        }
    };
    let Some(dc) = number("DC")?.map(|v| units.mm(v)) else {
        warnings.push(format!("{what}: no shape: no cutting diameter (DC)"));
        return Ok(None);
    };
    let re = number("RE")?.map(|v| units.mm(v)).unwrap_or(0.0);
    let tip = number("tip-diameter")?.map(|v| units.mm(v)).unwrap_or(0.0);
    let spec = match kind {
        "flat end mill" | "face mill" if re > 0.0 => format!("bull:{dc},{re}"),
        "flat end mill" | "face mill" => format!("flat:{dc}"),
        "ball end mill" => format!("ball:{dc}"),
        "bull nose end mill" => format!("bull:{dc},{re}"),
        "chamfer mill" if tip > 0.0 => {
            warnings.push(format!(
                "{what}: no shape: a chamfer mill with a {tip} mm flat tip (kezuri's v cutter is pointed)"
            ));
            return Ok(None);
        }
        "chamfer mill" => format!("v:{dc},{}", 2.0 * number("TA")?.unwrap_or(0.0)),
        _ => format!("v:{dc},{}", number("SIG")?.unwrap_or(0.0)),
    };
    Ok(cutter(spec, what, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mills_and_skips_holders() {
        let text = r#"{"data": [
            {"type": "flat end mill", "unit": "millimeters", "description": "4 mm 3 flute",
             "geometry": {"DC": 4, "RE": 0}, "post-process": {"number": 3, "length-offset": 13, "diameter-offset": 23}},
            {"type": "ball end mill", "unit": "inches", "geometry": {"DC": 0.25}, "post-process": {"number": 4}},
            {"type": "bull nose end mill", "unit": "millimeters", "geometry": {"DC": 10, "RE": 1}, "post-process": {"number": 5}},
            {"type": "chamfer mill", "unit": "millimeters", "geometry": {"DC": 8.3, "TA": 45, "tip-diameter": 2}, "post-process": {"number": 8}},
            {"type": "spot drill", "unit": "millimeters", "geometry": {"DC": 6, "SIG": 90}, "post-process": {"number": 9}},
            {"type": "thread mill", "unit": "millimeters", "geometry": {"DC": 6}, "post-process": {"number": 10}},
            {"type": "holder", "description": "BT40"},
            {"type": "turning general", "post-process": {"number": 11}},
            {"type": "flat end mill", "unit": "millimeters", "geometry": {"DC": 2}, "post-process": {"number": 0}}
        ], "version": 1}"#;
        let t = parse("lib.json", text).unwrap();
        let spec = |n: u32| t.tools[&n].shape.map(|c| c.to_string());
        assert_eq!(t.tools.keys().copied().collect::<Vec<_>>(), [3, 4, 5, 8, 9, 10]);
        assert_eq!((spec(3).as_deref(), t.tools[&3].h, t.tools[&3].d), (Some("flat:4"), 13, Some(23)));
        assert_eq!((spec(4).as_deref(), t.tools[&4].h, t.tools[&4].d), (Some("ball:6.35"), 4, None));
        assert_eq!(spec(5).as_deref(), Some("bull:10,1"));
        assert_eq!((spec(8), spec(9).as_deref(), spec(10)), (None, Some("v:6,90"), None));
        assert_eq!(t.tools[&3].name.as_deref(), Some("4 mm 3 flute"));
        assert!(t.lengths.is_empty() && t.radii.is_empty());
        assert_eq!(t.notes.skipped.len(), 3, "{:?}", t.notes.skipped);
        assert!(t.notes.skipped[0].contains("tool 7 (holder, BT40): not a milling tool"));
        assert!(t.notes.skipped[2].contains("no tool number"));
        assert!(t.notes.warnings[0].contains("T8 tool 4 (chamfer mill): no shape: a chamfer mill with a 2 mm flat tip"));
        assert!(t.notes.warnings[1].contains("T10 tool 6 (thread mill): no shape"));
    }

    #[test]
    fn bad_libraries_say_where() {
        for (text, words) in [
            ("{\"data\": [\n{\"type\": 3,}]}", "lib.json:2:12: trailing comma"),
            ("{\"tools\": []}", "no \"data\" list"),
            (r#"{"data": [{"type": "drill", "unit": "furlongs", "post-process": {"number": 1}}]}"#, "not \"furlongs\""),
            (
                r#"{"data": [{"type": "drill", "unit": "inches", "geometry": {"DC": "x"}, "post-process": {"number": 1}}]}"#,
                "geometry DC \"x\" is not a number",
            ),
            (r#"{"data": [{"type": "drill", "post-process": {"number": -1}}]}"#, "number -1 is not a register number"),
        ] {
            let e = parse("lib.json", text).expect_err(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
