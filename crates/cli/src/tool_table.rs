//! Tool tables read from the files shops keep: LinuxCNC `tool.tbl`,
//! FreeCAD tool bits and libraries (`.fctb`, `.fctl`), Fusion 360 tool
//! libraries (`.json`, and `.tools`, a zip of that JSON). Each gives tool
//! table entries (`ToolEntry`, as `[tools.T5]` of the machine file) and,
//! where the file has them, the values of the H and D registers.
//! `kezuri tool table` shows what was read; the machine file's
//! `[tools] import` uses it. docs/tool-tables.md has each format's rules.

mod freecad;
mod fusion;
mod linuxcnc;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args;
use kezuri_cam::Cutter;
use serde_json::json;

use crate::files::write_output;
use crate::machine::{Machine, ToolEntry};

/// The units of a file that does not say them (LinuxCNC's `tool.tbl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    Mm,
    Inch,
}

impl Units {
    /// `mm` or `inch`.
    pub fn parse(text: &str) -> Result<Units> {
        match text.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimeters" => Ok(Units::Mm),
            "inch" | "in" | "inches" => Ok(Units::Inch),
            other => bail!("'{other}' is not a unit of length: mm or inch"),
        }
    }

    /// A length in these units, in mm (to the nanometre: 0.125 inch is
    /// 3.175 mm, not 3.1750000000000003).
    pub fn mm(self, v: f64) -> f64 {
        match self {
            Units::Mm => v,
            Units::Inch => (v * 25.4 * 1e6).round() / 1e6,
        }
    }
}

/// What a tool file gave.
#[derive(Debug, Default)]
pub struct Table {
    /// What the file is, in words.
    pub format: &'static str,
    /// The tools, by number.
    pub tools: BTreeMap<u32, ToolEntry>,
    /// Tool length register values (H), mm.
    pub lengths: BTreeMap<u32, f64>,
    /// Cutter radius register values (D), mm.
    pub radii: BTreeMap<u32, f64>,
    /// What was read and left out, and why.
    pub notes: Notes,
}

/// Entries left out of a table, and tools read with something missing.
#[derive(Debug, Default, Clone)]
pub struct Notes {
    /// Entries of the file that are not in the table, and why.
    pub skipped: Vec<String>,
    /// Tools in the table that lack something (a shape kezuri can cut with).
    pub warnings: Vec<String>,
}

impl Notes {
    pub fn is_empty(&self) -> bool {
        self.skipped.is_empty() && self.warnings.is_empty()
    }
}

impl Table {
    fn new(format: &'static str) -> Table {
        Table { format, ..Table::default() }
    }

    /// Adds tool `number`; a number already in the table keeps its first
    /// entry (as LinuxCNC finds the first), the second is noted as skipped.
    fn add(&mut self, number: u32, entry: ToolEntry, at: &str) -> bool {
        if self.tools.contains_key(&number) {
            self.notes.skipped.push(format!("{at}: T{number} again: the first T{number} is kept"));
            return false;
        }
        self.tools.insert(number, entry);
        true
    }
}

/// Reads a tool file; its format from its name's ending. `units` is for
/// the files that carry none.
pub fn read(path: &Path, units: Option<Units>) -> Result<Table> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let mut table = match ext.as_str() {
        "tbl" => {
            let Some(units) = units else {
                bail!(
                    "{}: a LinuxCNC tool table carries no units: say which with --units mm or --units inch \
                     (units = \"mm\" beside import in the machine file)",
                    path.display()
                )
            };
            return linuxcnc::read(path, units);
        }
        "fctb" => freecad::read_bit_file(path)?,
        "fctl" => freecad::read_library(path)?,
        "json" => fusion::read_json(path)?,
        "tools" => fusion::read_zip(path)?,
        _ => bail!(
            "{}: which tool file is it? kezuri reads LinuxCNC .tbl, FreeCAD .fctb and .fctl, \
             Fusion 360 .json and .tools",
            path.display()
        ),
    };
    if units.is_some() {
        table.notes.warnings.push("the units given are not used: the file says its own".into());
    }
    Ok(table)
}

/// The cutter a SPEC names, or a warning saying why there is none (a
/// corner radius larger than the radius, say).
fn cutter(spec: String, what: &str, warnings: &mut Vec<String>) -> Option<Cutter> {
    match spec.parse::<Cutter>() {
        Ok(c) => Some(c),
        Err(e) => {
            warnings.push(format!("{what}: no shape: {e}"));
            None
        }
    }
}

/// A JSON file read into `T`; a syntax error says its line and column.
fn from_json<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T> {
    serde_json::from_str(text).map_err(|e| {
        let message = e.to_string();
        let message = message.rsplit_once(" at line ").map_or(message.as_str(), |(m, _)| m);
        anyhow::anyhow!("{file}:{}:{}: {message}", e.line(), e.column())
    })
}

/// `kezuri tool table FILE… [--units mm|inch] [--machine M.toml] [--json]`.
#[derive(Args, Debug)]
#[command(after_help = "What each file gives (docs/tool-tables.md has the rules):
  LinuxCNC tool.tbl   T, diameter (D), length (Z); no units (--units is required), no shape:
                      H = D = the tool number; the length goes to H, half the diameter to D
  FreeCAD .fctb/.fctl the shape and its sizes; a library numbers its bits, found in the Bit folder
                      beside its Library folder (FreeCAD's layout) or beside the library
  Fusion 360 .json    type, sizes, number, length and diameter offset numbers (not their values);
  and .tools          holders and tools that are not milling tools are skipped
A shape kezuri cannot cut with (a thread mill, a V-bit with a flat tip) is read without a shape,
with a warning naming it.

Use a table in the machine file: [tools] import = \"tool.tbl\" (beside the machine file) and
units = \"mm\" where the format needs it; [tools.T5] written there overrides what it imports.

Examples (samples/tools/ holds one file of each kind):
  kezuri tool table samples/tools/tool.tbl --units inch
  kezuri tool table samples/tools/Library/shop.fctl
  kezuri tool table samples/tools/shop.tools --json
  kezuri tool table --machine samples/tools/mill.toml")]
pub struct TableArgs {
    /// Tool tables: .tbl, .fctb, .fctl, .json, .tools.
    #[arg(value_name = "FILE", required_unless_present = "machine")]
    pub files: Vec<PathBuf>,
    /// The units of a LinuxCNC tool table: mm or inch.
    #[arg(long, value_name = "mm|inch")]
    pub units: Option<String>,
    /// Also show the machine file's tool table: what it imports with its own [tools.T…] on top.
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// Print one JSON object: tables, each with file, format, tools (number, shape, h, d,
    /// length_mm, radius_mm, name), skipped and warnings.
    #[arg(long)]
    pub json: bool,
}

/// One table to show: where it came from and what it holds.
struct Shown {
    file: String,
    table: Table,
}

/// Runs `kezuri tool table`.
pub fn run(a: &TableArgs) -> Result<()> {
    let units = a.units.as_deref().map(Units::parse).transpose()?;
    let mut shown = Vec::new();
    for file in &a.files {
        shown.push(Shown { file: file.display().to_string(), table: read(file, units)? });
    }
    if let Some(path) = &a.machine {
        let (m, notes) = Machine::read(path)?;
        let table = Table {
            format: "machine file",
            tools: m.tools,
            lengths: m.settings.tool_lengths,
            radii: m.settings.tool_radii,
            notes,
        };
        shown.push(Shown { file: path.display().to_string(), table });
    }
    let text = if a.json { json_text(&shown) } else { shown.iter().map(plain_text).collect::<Vec<_>>().join("\n") };
    write_output(None, text.as_bytes())
}

/// A tool's register values: (length, radius), mm.
fn values(t: &Table, e: &ToolEntry) -> (Option<f64>, Option<f64>) {
    (t.lengths.get(&e.h).copied(), e.d.and_then(|d| t.radii.get(&d)).copied())
}

fn json_text(shown: &[Shown]) -> String {
    let tables: Vec<_> = shown
        .iter()
        .map(|s| {
            let tools: Vec<_> = s
                .table
                .tools
                .iter()
                .map(|(n, e)| {
                    let (length, radius) = values(&s.table, e);
                    json!({"number": n, "shape": e.shape.map(|c| c.to_string()), "h": e.h, "d": e.d,
                           "length_mm": length, "radius_mm": radius, "name": e.name})
                })
                .collect();
            json!({"file": s.file, "format": s.table.format, "tools": tools,
                   "skipped": s.table.notes.skipped, "warnings": s.table.notes.warnings})
        })
        .collect();
    format!("{}\n", json!({ "tables": tables }))
}

fn plain_text(s: &Shown) -> String {
    let t = &s.table;
    let mut rows = vec![["tool", "shape", "H", "D", "length mm", "radius mm", "name"].map(String::from)];
    let or_dash = |v: Option<String>| v.unwrap_or_else(|| "-".into());
    for (n, e) in &t.tools {
        let (length, radius) = values(t, e);
        rows.push([
            format!("T{n}"),
            or_dash(e.shape.map(|c| c.to_string())),
            e.h.to_string(),
            or_dash(e.d.map(|d| d.to_string())),
            or_dash(length.map(|v| v.to_string())),
            or_dash(radius.map(|v| v.to_string())),
            e.name.clone().unwrap_or_default(),
        ]);
    }
    let widths: Vec<usize> = (0..7).map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0)).collect();
    let n = t.tools.len();
    let bare = t.tools.values().filter(|e| e.shape.is_none()).count();
    let mut out =
        format!("{} ({}): {n} tool{}, {bare} without a shape\n", s.file, t.format, if n == 1 { "" } else { "s" });
    for r in &rows {
        let cells: Vec<String> = r.iter().zip(&widths).map(|(c, w)| format!("{c:<w$}")).collect();
        out += &format!("  {}\n", cells.join("  ").trim_end());
    }
    for (title, list) in [("skipped", &t.notes.skipped), ("warnings", &t.notes.warnings)] {
        if !list.is_empty() {
            out += &format!("{title}:\n");
            for line in list {
                out += &format!("  {line}\n");
            }
        }
    }
    out
}
