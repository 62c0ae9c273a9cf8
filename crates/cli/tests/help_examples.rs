//! Every example in every command's help, run: each help's examples in
//! order, in a fresh folder holding the bundled samples/ (and what the
//! examples before make), `kezuri` on the PATH; each must exit 0. So a help
//! cannot show a command line that no longer works.
//!
//! Examples are the indented lines of a section headed `Examples…:`,
//! `Example…:` or `The pipeline…:`; a line ending in ` \` goes on on the
//! next. Each is at most 80 columns, so a terminal does not wrap it and
//! copying it works. A section whose header names a serial port
//! (`… on a serial port …`) needs the instrument: its examples are only
//! parsed, as the command line reads them.
//!
//! `KEZURI_HELP_EXAMPLES="probe mill,tool db"` runs those helps only.

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::CommandFactory;

/// Widest example line, in columns.
const WIDTH: usize = 80;

/// One help: its command path and the text after the options.
struct Help {
    path: String,
    text: String,
}

/// Every help of `command`, its own first.
fn helps(command: &clap::Command, path: &str, out: &mut Vec<Help>) {
    let text = command.get_after_long_help().or(command.get_after_help()).map(|s| s.to_string()).unwrap_or_default();
    out.push(Help { path: path.to_string(), text });
    for s in command.get_subcommands().filter(|s| s.get_name() != "help") {
        let p = if path.is_empty() { s.get_name().to_string() } else { format!("{path} {}", s.get_name()) };
        helps(s, &p, out);
    }
}

fn all_helps() -> Vec<Help> {
    let mut command = kezuri::Cli::command();
    command.build();
    let mut out = Vec::new();
    helps(&command, "", &mut out);
    out
}

/// An example: its lines as shown, and whether it needs an instrument.
struct Example {
    lines: Vec<String>,
    hardware: bool,
}

/// The examples of a help text.
fn examples(text: &str) -> Vec<Example> {
    let mut out: Vec<Example> = Vec::new();
    let mut section: Option<bool> = None;
    let mut going_on = false;
    for line in text.lines() {
        let header = line.trim_end().ends_with(':') && ["Example", "The pipeline"].iter().any(|h| line.starts_with(h));
        if header {
            section = Some(line.contains("serial port"));
            going_on = false;
            continue;
        }
        let Some(hardware) = section else { continue };
        if !line.starts_with("  ") || line.trim().is_empty() {
            section = None;
            continue;
        }
        if going_on {
            out.last_mut().expect("an example goes on").lines.push(line.to_string());
        } else {
            out.push(Example { lines: vec![line.to_string()], hardware });
        }
        going_on = line.ends_with(" \\");
    }
    out
}

#[test]
fn every_example_line_fits_80_columns() {
    let mut wide = Vec::new();
    for help in all_helps() {
        for e in examples(&help.text) {
            for line in &e.lines {
                if line.chars().count() > WIDTH {
                    wide.push(format!("kezuri {} --help: {} columns: {line}", help.path, line.chars().count()));
                }
            }
        }
    }
    assert!(wide.is_empty(), "example lines wider than {WIDTH} columns:\n{}", wide.join("\n"));
}

#[test]
fn no_help_shows_an_escaped_quote_or_a_file_outside_the_repository() {
    let mut command = kezuri::Cli::command();
    command.build();
    fn walk(c: &mut clap::Command, path: &str, out: &mut Vec<(String, String)>) {
        out.push((path.to_string(), c.render_long_help().to_string()));
        let names: Vec<String> = c.get_subcommands().map(|s| s.get_name().to_string()).collect();
        for n in names {
            walk(c.find_subcommand_mut(&n).unwrap(), &format!("{path} {n}"), out);
        }
    }
    let mut all = Vec::new();
    walk(&mut command, "kezuri", &mut all);
    for (path, text) in all {
        for bad in ["\\\"", "../shared", "CLI.md", "the paper", "seed 00", "SEED 00"] {
            assert!(!text.contains(bad), "{path} --help shows {bad}:\n{text}");
        }
    }
}

/// The repository's samples folder.
fn samples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples").canonicalize().unwrap()
}

/// A folder with `kezuri` in it, for the PATH.
fn bin_dir(root: &Path) -> PathBuf {
    let bin = root.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_kezuri"), bin.join("kezuri")).unwrap();
    bin
}

/// The words of a shell command line (quotes and backslash-newlines; no
/// expansions), for the examples that are only parsed.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word: Option<String> = None;
    let mut quote: Option<char> = None;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.get_or_insert_with(String::new).push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                word.get_or_insert_with(String::new);
            }
            (None, '\\') if chars.peek() == Some(&'\n') => {
                chars.next();
            }
            (None, '#') if word.is_none() => break,
            (None, c) if c.is_whitespace() => out.extend(word.take()),
            (None, c) => word.get_or_insert_with(String::new).push(c),
        }
    }
    out.extend(word);
    out
}

/// Runs the examples of one help in its own folder under `root`: the
/// failure, if one fails (the rest of that help is not run: it may need what
/// the failed one should have made), and each run's seconds and first line.
fn run_help(help: &Help, k: usize, root: &Path, path: &str) -> (Option<String>, Vec<(f64, String)>) {
    let dir = root.join(format!("help-{k}"));
    std::fs::create_dir_all(&dir).unwrap();
    std::os::unix::fs::symlink(samples(), dir.join("samples")).unwrap();
    let mut times = Vec::new();
    for e in examples(&help.text) {
        let script = e.lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join("\n");
        if e.hardware {
            let w = words(&script);
            assert_eq!(w.first().map(String::as_str), Some("kezuri"), "{script}");
            if let Err(err) = kezuri::Cli::command().try_get_matches_from(&w) {
                return (Some(format!("kezuri {} --help: does not parse: {script}\n{err}", help.path)), times);
            }
            continue;
        }
        let t0 = std::time::Instant::now();
        let o = Command::new("sh").arg("-c").arg(&script).current_dir(&dir).env("PATH", path).output().unwrap();
        times.push((t0.elapsed().as_secs_f64(), script.lines().next().unwrap_or("").to_string()));
        if !o.status.success() {
            let stderr = String::from_utf8_lossy(&o.stderr);
            let said = stderr.lines().take(12).collect::<Vec<_>>().join("\n");
            return (Some(format!("kezuri {} --help: exit {:?}: {script}\n{said}", help.path, o.status.code())), times);
        }
    }
    (None, times)
}

#[test]
fn every_example_in_every_help_runs() {
    let only: Option<Vec<String>> =
        std::env::var("KEZURI_HELP_EXAMPLES").ok().map(|v| v.split(',').map(|s| s.trim().to_string()).collect());
    let root = tempfile::tempdir().unwrap();
    let bin = bin_dir(root.path());
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let helps: Vec<(usize, Help)> = all_helps()
        .into_iter()
        .enumerate()
        .filter(|(_, h)| only.as_ref().is_none_or(|o| o.contains(&h.path)))
        .collect();
    // The helps share out among a few workers, the slowest (the demo's) first.
    let queue = std::sync::Mutex::new(helps.iter().rev().collect::<Vec<_>>());
    let results = std::sync::Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().clamp(2, 4));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let Some((k, help)) = queue.lock().unwrap().pop() else { break };
                let done = run_help(help, *k, root.path(), &path);
                results.lock().unwrap().push(done);
            });
        }
    });
    let results = results.into_inner().unwrap();
    let failed: Vec<&String> = results.iter().filter_map(|r| r.0.as_ref()).collect();
    let mut times: Vec<&(f64, String)> = results.iter().flat_map(|r| &r.1).collect();
    times.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (t, line) in times.iter().take(15) {
        eprintln!("{t:7.2} s  {line}");
    }
    assert!(
        failed.is_empty(),
        "{} failed:\n\n{}",
        failed.len(),
        failed.iter().map(|f| f.as_str()).collect::<Vec<_>>().join("\n\n")
    );
    assert!(only.is_some() || times.len() > 100, "only {} examples ran", times.len());
}
