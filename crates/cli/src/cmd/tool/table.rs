//! `kezuri tool table`: other programs' tool files (LinuxCNC, FreeCAD,
//! Fusion 360) read into kezuri's tool table and shown; the readers and the
//! listing are kezuri-machine's (`crates/machine/src/tool_table.rs`).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use kezuri_machine::tool_table::listing::{self, Shown};
use kezuri_machine::tool_table::{self, Table, Units};

use crate::files::write_output;
use crate::machine::Disk;

/// `kezuri tool table FILE… [--units mm|inch] [--machine M.toml] [--json]`.
#[derive(Args, Debug)]
#[command(after_help = "What each file gives (docs/tool-tables.md has the rules):
  LinuxCNC tool.tbl   T, diameter (D), length (Z); no units (--units is required), no shape:
                      H = D = the tool number; the length goes to H, half the diameter to D;
                      a lathe tool (orientation Q 1-9) has a nose: radius D/2, Q as Fanuc's tip
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
    /// length_mm, radius_mm, name; a turning tool's nose_radius_mm, tip),
    /// skipped and warnings.
    #[arg(long)]
    pub json: bool,
}

/// Runs `kezuri tool table`.
pub fn run(a: &TableArgs) -> Result<()> {
    let units = a.units.as_deref().map(Units::parse).transpose()?;
    let mut shown = Vec::new();
    for file in &a.files {
        shown.push(Shown { file: file.display().to_string(), table: tool_table::read(file, units, &Disk)? });
    }
    if let Some(path) = &a.machine {
        let (m, notes) = crate::machine::read(path)?;
        shown.push(Shown { file: path.display().to_string(), table: Table::of_machine(m, notes) });
    }
    let text = if a.json { listing::json(&shown) } else { listing::text(&shown) };
    write_output(None, text.as_bytes())
}
