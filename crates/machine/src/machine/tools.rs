//! The machine file's `[tools]`: one entry a tool (`[tools.T5]`: its
//! shape, its H and D registers and their values), the old register tables
//! (`lengths`, `radii`), and the tool table it imports.

use std::collections::BTreeMap;
use std::path::Path;

use kezuri_cam::Cutter;
use kezuri_geom::limits;
use kezuri_nc::interp::Nose;
use serde::Deserialize;

use crate::error::{fail, with_sources, Error, ErrorKind, Result};
use crate::files::Files;
use crate::tool_table::{self, Notes, Units};

/// `[tools]`: no `deny_unknown_fields` (serde cannot have it with
/// `flatten`): a key that is not `lengths`, `radii`, `import` or `units`
/// must name a tool.
#[derive(Deserialize, Default)]
pub(super) struct Tools {
    /// H register values by register (the old form: `[tools.T1] length`).
    #[serde(default)]
    lengths: BTreeMap<String, f64>,
    /// D register values by register (the old form: `[tools.T1] radius`).
    #[serde(default)]
    radii: BTreeMap<String, f64>,
    /// A tool table file to import (docs/tool-tables.md), relative to the
    /// machine file.
    import: Option<String>,
    /// The units of an imported table that does not say them: mm or inch.
    units: Option<String>,
    /// `T5 = { shape, h, d, length, radius, name }`: the tool table, one
    /// entry a tool.
    #[serde(flatten)]
    table: BTreeMap<String, ToolFile>,
}

/// `[tools.T5]`: one tool of the table.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct ToolFile {
    shape: Option<String>,
    h: Option<u32>,
    d: Option<u32>,
    /// The tool's length, mm: the value of its H register.
    length: Option<f64>,
    /// The tool's radius for cutter compensation, mm: the value of its D
    /// register (the tool number's when `d` is not given).
    radius: Option<f64>,
    name: Option<String>,
    /// A turning tool's nose radius, mm.
    nose_radius: Option<f64>,
    /// Its imaginary tool tip direction, 0–9.
    tip: Option<i64>,
}

/// One tool of the machine's tool table (`[tools.T5]`).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolEntry {
    /// The cutter, where the table says its shape.
    pub shape: Option<Cutter>,
    /// The tool length offset register (`G43 H`): the tool number unless
    /// the table says otherwise.
    pub h: u32,
    /// The cutter radius register (`G41 D`), where the table gives one.
    pub d: Option<u32>,
    /// What the shop calls it.
    pub name: Option<String>,
    /// A turning tool's nose: its radius and imaginary tool tip direction
    /// (`nose_radius`, `tip`), for nose radius compensation.
    pub nose: Option<Nose>,
}

/// What `[tools]` gives: the tool table, the H and D register values, and
/// what its import left out or lacks.
pub(super) struct Read {
    pub tools: BTreeMap<u32, ToolEntry>,
    pub lengths: BTreeMap<u32, f64>,
    pub radii: BTreeMap<u32, f64>,
    pub notes: Notes,
}

/// Reads `[tools]`, importing the table it names from `dir` (through
/// `files`): the import first, `lengths` and `radii` over it, each tool's
/// entry over both.
pub(super) fn read(tools: &Tools, dir: &Path, files: &dyn Files) -> Result<Read> {
    let imported = import_tools(tools, dir, files)?;
    let mut lengths = registers(imported.as_ref().map(|t| &t.lengths), "tools.lengths", &tools.lengths)?;
    let mut radii = registers(imported.as_ref().map(|t| &t.radii), "tools.radii", &tools.radii)?;
    let (imported_tools, mut notes) = imported.map(|t| (t.tools, t.notes)).unwrap_or_default();
    let from_import: Vec<u32> = imported_tools.keys().copied().collect();
    let table = tool_table(&tools.table, imported_tools)?;
    // A tool.tbl's note that it gives no shapes becomes the tools this
    // file leaves without one, each with the line to add.
    if let Some(k) = notes.warnings.iter().position(|w| w.starts_with(tool_table::NO_SHAPES)) {
        notes.warnings.remove(k);
        for (n, e) in table.iter().filter(|(n, e)| e.shape.is_none() && from_import.contains(n)) {
            let name = e.name.as_deref().map(|s| format!(" ({s})")).unwrap_or_default();
            notes.warnings.push(format!(
                "T{n}{name}: the tool.tbl gives no shape: add `shape = \"SPEC\"` under [tools.T{n}] \
                 (flat:D, ball:D, bull:D,R, v:D,ANGLE) for sim and view to cut with it"
            ));
        }
    }
    // Each tool's length and radius, into its registers.
    let mut set_by: BTreeMap<(char, u32), String> = BTreeMap::new();
    for (key, t) in &tools.table {
        let number = tool_number(key)?;
        let entry = &table[&number];
        for (letter, value, register, old, values) in [
            ('H', t.length, Some(entry.h), &tools.lengths, &mut lengths),
            ('D', t.radius, entry.d, &tools.radii, &mut radii),
        ] {
            let Some(v) = value else { continue };
            let what = if letter == 'H' { "length" } else { "radius" };
            let Some(register) = register else { unreachable!("a radius gives the tool a D register") };
            limits::coordinate(v, &format!("tools.{key}.{what}"))
                .map_err(|e| Error::new(ErrorKind::Invalid, e.to_string()))?;
            if let Some(o) = old.get(&register.to_string()).filter(|&&o| o != v) {
                let list = if letter == 'H' { "lengths" } else { "radii" };
                fail!(
                    Invalid,
                    "tools.{key}.{what} = {v} and tools.{list} {register} = {o} both set {letter}{register}: \
                     keep the tool's {what} (tools.{list} is the old form)"
                );
            }
            if let Some(other) = set_by.get(&(letter, register)).filter(|_| values.get(&register) != Some(&v)) {
                fail!(
                    Invalid,
                    "tools.{key}.{what} and tools.{other}.{what} both set {letter}{register}, to different values"
                );
            }
            set_by.insert((letter, register), key.clone());
            values.insert(register, v);
        }
    }
    Ok(Read { tools: table, lengths, radii, notes })
}

/// The number a `[tools]` key names: `T5` or `5`.
fn tool_number(key: &str) -> Result<u32> {
    key.trim().trim_start_matches(['T', 't']).parse().ok().filter(|&n| n > 0).ok_or_else(|| {
        Error::new(
            ErrorKind::Invalid,
            format!("tools: '{key}' is not a tool (T1, T2, …) nor lengths, radii, import or units"),
        )
    })
}

/// The tool table of `[tools]`: keys `T1`, `T2`, … (or `1`, `2`, …), each
/// on top of the imported entry of its number where there is one (what
/// the machine file says overrides what the import gives).
fn tool_table(
    table: &BTreeMap<String, ToolFile>,
    mut imported: BTreeMap<u32, ToolEntry>,
) -> Result<BTreeMap<u32, ToolEntry>> {
    for (key, t) in table {
        let number = tool_number(key)?;
        let shape = match &t.shape {
            Some(spec) => Some(
                spec.parse::<Cutter>()
                    .map_err(|e| Error::new(ErrorKind::Invalid, format!("tools.{key}.shape: {}", with_sources(&e))))?,
            ),
            None => None,
        };
        let base = imported.remove(&number);
        // A radius with no D register is the tool number's.
        let d = t.d.or(base.as_ref().and_then(|b| b.d)).or(t.radius.map(|_| number));
        let entry = ToolEntry {
            shape: shape.or(base.as_ref().and_then(|b| b.shape)),
            h: t.h.or(base.as_ref().map(|b| b.h)).unwrap_or(number),
            d,
            nose: nose(key, t, base.as_ref().and_then(|b| b.nose))?,
            name: t.name.clone().or(base.and_then(|b| b.name)),
        };
        imported.insert(number, entry);
    }
    Ok(imported)
}

/// The nose of tool `key`: its `nose_radius` and `tip`, each over the
/// imported entry's. A tip with no nose radius is the nose centre's (0, 9)
/// or an error (1–8: the tip is a corner of the nose); a nose radius with
/// no tip is measured to the nose centre (tip 0), as a Fanuc offset page
/// holds it.
fn nose(key: &str, t: &ToolFile, base: Option<Nose>) -> Result<Option<Nose>> {
    if let Some(r) = t.nose_radius {
        limits::length_or_zero(r, &format!("tools.{key}.nose_radius"))
            .map_err(|e| Error::new(ErrorKind::Invalid, e.to_string()))?;
    }
    let tip = match t.tip {
        None => base.map(|b| b.tip),
        Some(tip @ 0..=9) => Some(tip as u8),
        Some(tip) => fail!(
            Invalid,
            "tools.{key}.tip = {tip}: the imaginary tool tip direction is 0 to 9 \
             (1-8 a corner of the nose, 0 and 9 its centre)"
        ),
    };
    let radius = t.nose_radius.or(base.map(|b| b.radius));
    Ok(match (radius, tip) {
        (None, None) => None,
        (Some(radius), tip) => Some(Nose { radius, tip: tip.unwrap_or(0) }),
        (None, Some(tip @ (0 | 9))) => Some(Nose { radius: 0.0, tip }),
        (None, Some(tip)) => fail!(
            Invalid,
            "tools.{key}.tip = {tip} with no tools.{key}.nose_radius: tip {tip} is a point on the nose, \
             which needs its radius (mm); tips 0 and 9 are the nose centre"
        ),
    })
}

/// The tool table `[tools] import` names, read from beside the machine file.
fn import_tools(tools: &Tools, dir: &Path, files: &dyn Files) -> Result<Option<tool_table::Table>> {
    let Some(file) = &tools.import else {
        if tools.units.is_some() {
            fail!(Invalid, "tools.units: the units of an imported table, but tools.import names none");
        }
        return Ok(None);
    };
    let units = tools.units.as_deref().map(Units::parse).transpose().map_err(|e| e.context("tools.units"))?;
    tool_table::read(&dir.join(file), units, files).map_err(|e| e.context("tools.import")).map(Some)
}

/// The registers an import gives, with the machine file's on top.
fn registers(
    imported: Option<&BTreeMap<u32, f64>>,
    name: &str,
    map: &BTreeMap<String, f64>,
) -> Result<BTreeMap<u32, f64>> {
    let mut all = imported.cloned().unwrap_or_default();
    for (k, &v) in map {
        let n: u32 = k
            .parse()
            .map_err(|e| Error::new(ErrorKind::Invalid, format!("{name}: '{k}' is not a register number: {e}")))?;
        all.insert(n, v);
    }
    // Lengths and radii in mm, imported or given.
    for (n, &v) in &all {
        limits::coordinate(v, &format!("{name}.{n}")).map_err(|e| Error::new(ErrorKind::Invalid, e.to_string()))?;
    }
    Ok(all)
}
