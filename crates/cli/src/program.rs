//! The plumbing the commands share: reading and running a program
//! (`run.rs`; the tool table of its comments where no machine file gives
//! one, `comment_tools.rs`), and writing a toolpath through a post (`emit.rs`).

mod beside;
mod comment_tools;
#[cfg(test)]
pub mod corpus;
mod emit;
mod run;
mod streamed;
pub use streamed::{staged, Streamed};
mod tally;

pub use emit::{
    located, post_options, program_title, stage_toolpath, stream_made_program, svg_title, warn_rml_drops,
    write_program, written_path, Origin, RunTrial, WriteArgs,
};
pub use run::{
    choose_dialect, comp_refused, dialect_settings, library_dir, model_notes, print_label, read_and_run,
    read_and_run_into, refuse_comp, report_logs, run_again_into, run_options, run_store, run_text, run_text_into,
    run_written, whole_units, DialectArg, Ran, RunOptions,
};
pub use tally::{missing_axes, MissingAxes, Report, Tallied, Tally};
