//! No output over an input: before a command starts, every file its
//! outputs name is compared with every file the command line names by
//! device and inode, so `-o` naming the program read (by the same path,
//! `./path`, a link or a hard link) is refused before anything is read or
//! written.
//!
//! The check reads the parsed command line itself: every option or
//! argument clap parses as a path takes part, whatever the command, each
//! known as an output ([`OUTPUTS`]) or an input (a test holds that no path
//! argument is neither: a new output option cannot be left out); a text
//! that names a file (`--stock FILE.stl`, `mask:FILE`) counts as an input.
//! Two names of one argument (`tool table a.tbl ./a.tbl`) and two inputs
//! naming one file are no conflict; the commands that rewrite their own
//! input in place (`run FILE -o FILE`, `convert`, `probe level`) keep
//! doing so through their `-o`.

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use clap::{ArgMatches, Command};

/// A refusal of the command line as given: exit code 2, as clap's own.
#[derive(Debug)]
pub struct Usage(pub String);

impl std::fmt::Display for Usage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Usage {}

/// The commands (by subcommand names) whose `-o` may name their input
/// (the argument `input`): they read it whole before writing.
const IN_PLACE: [(&[&str], &str); 3] = [(&["run"], "file"), (&["convert"], "input"), (&["probe", "level"], "data")];

/// One existing file named on the command line.
struct Named {
    /// The argument's name as the user wrote it (`-o`, `--svg`, `FILE`).
    shown: String,
    id: String,
    path: PathBuf,
    file: (u64, u64),
    /// Parsed as a path (not a text that may name a file, as `--stock
    /// FILE.stl` or `--reference mask:FILE`).
    is_path: bool,
}

/// Refuses a command line that names one file for two of its arguments
/// (an output over an input), before anything is opened for writing.
pub fn refuse_same_files(command: &Command, matches: &ArgMatches) -> Result<(), Usage> {
    let mut named = Vec::new();
    let mut path = Vec::new();
    collect(command, matches, &mut path, &mut named);
    let in_place = IN_PLACE.iter().find(|(p, _)| *p == path.as_slice()).map(|(_, input)| *input);
    for (i, a) in named.iter().enumerate() {
        for b in &named[i + 1..] {
            if a.id == b.id || a.file != b.file || !(a.is_path || b.is_path) {
                continue;
            }
            // Two inputs may be one file (`sim --stock part.stl --compare
            // part.stl` shows only the gouges).
            if !is_output(&a.id) && !is_output(&b.id) {
                continue;
            }
            let pair = |x: &str, y: &str| (a.id == x && b.id == y) || (a.id == y && b.id == x);
            if in_place.is_some_and(|input| pair(input, "output")) {
                continue;
            }
            // The output is the one listed last, in the usual order
            // (inputs first, then -o and the other outputs).
            let (input, output) = if is_output(&a.id) && !is_output(&b.id) { (b, a) } else { (a, b) };
            return Err(Usage(format!(
                "{} {} names the same file as the input {} {}: kezuri never writes over an input; choose another \
                 output name",
                output.shown,
                output.path.display(),
                input.shown,
                input.path.display(),
            )));
        }
    }
    Ok(())
}

/// The arguments (by clap id) that name a file kezuri writes: outputs,
/// and the tool database (`tool db add` writes it).
const OUTPUTS: [&str; 12] =
    ["output", "svg", "png", "stl", "surface_stl", "view", "deviation_png", "dxf", "csv", "out", "dprnt", "db"];

/// The path arguments that kezuri only reads. Every path argument of the
/// command line is in one list or the other (the test below holds it: a
/// new output option cannot be left out of the check).
#[cfg(test)]
const INPUTS: [&str; 20] = [
    "file",
    "input",
    "data",
    "mesh",
    "surface",
    "model",
    "image",
    "images",
    "mask",
    "profile",
    "offsets",
    "files",
    "more",
    "machine",
    "lib",
    "var",
    "compare",
    "measurements",
    "index",
    "tool_profile",
];

fn is_output(id: &str) -> bool {
    OUTPUTS.contains(&id)
}

/// The existing files named by `matches` and its subcommands' matches;
/// `path` gets the subcommand names.
fn collect(command: &Command, matches: &ArgMatches, path: &mut Vec<String>, named: &mut Vec<Named>) {
    for id in matches.ids() {
        let id = id.as_str();
        // The arguments parsed as paths; and texts that name a file (a
        // `--stock FILE.stl`, a `mask:FILE`), compared with those only (a
        // number that happens to name a file is no input).
        let (values, is_path): (Vec<PathBuf>, bool) = match matches.try_get_many::<PathBuf>(id) {
            Ok(Some(v)) => (v.cloned().collect(), true),
            _ => match matches.try_get_many::<String>(id) {
                Ok(Some(v)) => {
                    let after_colon = |t: &String| t.split_once(':').map(|(_, f)| PathBuf::from(f));
                    (v.flat_map(|t| [Some(PathBuf::from(t)), after_colon(t)]).flatten().collect(), false)
                }
                _ => continue,
            },
        };
        let shown = command
            .get_arguments()
            .find(|a| a.get_id() == id)
            .map(|a| match (a.get_short(), a.get_long()) {
                (Some('o'), _) => "-o".to_string(),
                (_, Some(long)) => format!("--{long}"),
                (Some(s), None) => format!("-{s}"),
                _ => {
                    a.get_value_names().and_then(|v| v.first()).map(|v| v.to_string()).unwrap_or_else(|| id.to_string())
                }
            })
            .unwrap_or_else(|| id.to_string());
        for p in values {
            if let Some(file) = identity(&p) {
                named.push(Named { shown: shown.clone(), id: id.to_string(), path: p, file, is_path });
            }
        }
    }
    if let Some((name, sub)) = matches.subcommand() {
        path.push(name.to_string());
        if let Some(c) = command.find_subcommand(name) {
            collect(c, sub, path, named);
        }
    }
}

/// The device and inode of an existing plain file (past links); none for
/// standard input, a folder, a device or a file not there yet.
fn identity(p: &Path) -> Option<(u64, u64)> {
    if p == Path::new("-") {
        return None;
    }
    let m = std::fs::metadata(p).ok()?;
    m.is_file().then(|| (m.dev(), m.ino()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every argument parsed as a path, in every command, is a known input
    /// or a known output.
    #[test]
    fn every_path_argument_is_an_input_or_an_output() {
        fn walk(c: &Command, path: &str, unknown: &mut Vec<String>) {
            let path_parser = clap::value_parser!(PathBuf).type_id();
            for a in c.get_arguments() {
                let id = a.get_id().as_str();
                if a.get_value_parser().type_id() == path_parser && !OUTPUTS.contains(&id) && !INPUTS.contains(&id) {
                    unknown.push(format!("{path} {id}"));
                }
            }
            for s in c.get_subcommands() {
                walk(s, &format!("{path} {}", s.get_name()), unknown);
            }
        }
        let mut unknown = Vec::new();
        walk(&crate::Cli::command(), "kezuri", &mut unknown);
        assert!(unknown.is_empty(), "path arguments in neither OUTPUTS nor INPUTS of files/same.rs: {unknown:?}");
    }
}
