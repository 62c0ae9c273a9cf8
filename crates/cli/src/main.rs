//! The `kezuri` process: its allocator, its signals and its exit code around
//! the commands of the library (`src/lib.rs`).

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches};

/// Huge pages for million-move programs (see BENCHMARKS.md).
#[global_allocator]
static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;

fn main() -> ExitCode {
    // Die quietly when the reader of our output goes away (`kezuri … | head`),
    // as command-line tools do, instead of panicking on a failed print.
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any other
    // thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        // A file past the size limit (`ulimit -f`) is a write error that
        // names the file, as a full disk is, not a killed process that
        // leaves its temporary files behind.
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    // A number out of its range is bad input (exit 1, as every other bad
    // value); a malformed command line stays clap's usage error (exit 2).
    let matches = kezuri::Cli::command().try_get_matches().unwrap_or_else(|e| {
        if e.kind() == clap::error::ErrorKind::ValueValidation {
            let _ = e.print();
            std::process::exit(1)
        }
        e.exit()
    });
    let cli = kezuri::Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    // An output naming an input is refused before any work (exit 2).
    if let Err(e) = kezuri::refuse_same_files(&matches) {
        eprintln!("error: {e:#}");
        return ExitCode::from(2);
    }
    match cli.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            // A refusal of the command line as given is a usage error.
            ExitCode::from(if e.downcast_ref::<kezuri::Usage>().is_some() { 2 } else { 1 })
        }
    }
}
