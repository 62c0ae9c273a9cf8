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

pub(crate) use linuxcnc::NO_SHAPES;
pub mod listing;

use std::collections::BTreeMap;
use std::path::Path;

use kezuri_cam::Cutter;

use crate::error::{fail, Error, ErrorKind, Result};
use crate::files::Files;
use crate::machine::{Machine, ToolEntry};

/// The units of a file that does not say them (LinuxCNC's `tool.tbl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

impl Units {
    /// `mm` or `inch`.
    pub fn parse(text: &str) -> Result<Units> {
        match text.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimeters" => Ok(Units::Mm),
            "inch" | "in" | "inches" => Ok(Units::Inch),
            other => fail!(Invalid, "'{other}' is not a unit of length: mm or inch"),
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
    /// Whether nothing was left out and nothing lacks.
    pub fn is_empty(&self) -> bool {
        self.skipped.is_empty() && self.warnings.is_empty()
    }
}

impl Table {
    fn new(format: &'static str) -> Table {
        Table { format, ..Table::default() }
    }

    /// The tool table of a machine file: what it imports with its own
    /// `[tools.T…]` on top, and what the import left out or lacks.
    pub fn of_machine(machine: Machine, notes: Notes) -> Table {
        Table {
            format: "machine file",
            tools: machine.tools,
            lengths: machine.settings.tool_lengths,
            radii: machine.settings.tool_radii,
            notes,
        }
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

/// Reads the tool file `path` from `files`; its format from its name's
/// ending. `units` is for the files that carry none.
pub fn read(path: &Path, units: Option<Units>, files: &dyn Files) -> Result<Table> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let mut table = match ext.as_str() {
        "tbl" => {
            let Some(units) = units else {
                fail!(
                    NoUnits,
                    "{}: a LinuxCNC tool table carries no units: say which with --units mm or --units inch \
                     (units = \"mm\" beside import in the machine file)",
                    path.display()
                )
            };
            return linuxcnc::read(path, units, files);
        }
        "fctb" => freecad::read_bit_file(path, files)?,
        "fctl" => freecad::read_library(path, files)?,
        "json" => fusion::read_json(path, files)?,
        "tools" => fusion::read_zip(path, files)?,
        _ => fail!(
            UnknownFormat,
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
        Error::new(ErrorKind::Syntax, format!("{file}:{}:{}: {message}", e.line(), e.column()))
    })
}
