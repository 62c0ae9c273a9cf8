//! `kezuri tool`: a tool's measured profile, the database of its wear, other programs' tool tables.

pub mod db;
pub mod profile;
pub mod table;

use clap::Subcommand;

/// `kezuri tool …`.
#[derive(Subcommand, Debug)]
pub enum ToolCommand {
    /// A tool's cutting profile and runout from backlit pictures of it turning.
    Profile(Box<profile::ProfileArgs>),
    /// The database of each tool's measured profiles: add, list, show.
    #[command(subcommand)]
    Db(db::DbCommand),
    /// What a tool table file gives: LinuxCNC tool.tbl, FreeCAD .fctb/.fctl, Fusion 360 .json/.tools.
    Table(table::TableArgs),
}

/// Runs one `kezuri tool` subcommand.
pub fn run(command: &ToolCommand) -> anyhow::Result<()> {
    match command {
        ToolCommand::Profile(args) => profile::run(args),
        ToolCommand::Db(command) => db::run(command),
        ToolCommand::Table(args) => table::run(args),
    }
}
