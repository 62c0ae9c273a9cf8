//! The `kezuri` process: its allocator, its signals and its exit code around
//! the commands of the library (`src/lib.rs`).

use std::process::ExitCode;

use clap::Parser;

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
    }
    // A number out of its range is bad input (exit 1, as every other bad
    // value); a malformed command line stays clap's usage error (exit 2).
    let cli = kezuri::Cli::try_parse().unwrap_or_else(|e| {
        if e.kind() == clap::error::ErrorKind::ValueValidation {
            let _ = e.print();
            std::process::exit(1)
        }
        e.exit()
    });
    match cli.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
