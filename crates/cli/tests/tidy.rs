//! The house rules, read from the sources (as rust-analyzer's tidy test does): each failure
//! names the file and line that breaks a rule.
//!
//! - A command module (`crates/cli/src/cmd/NAME`) imports no other command's module; the
//!   plumbing the commands share (`crates/cli/src/*` outside `cmd/`) imports no command, but
//!   for `lib.rs`, the command line that dispatches to them.
//! - nc's stages run one way: nothing in `interp` imports `write`, nothing in `parse` imports
//!   `interp` or `write`; inside `write` each file imports only the layers before its own
//!   ([`WRITE_LAYERS`]).
//! - A library (every crate but the cli) opens no path, port or terminal: no `std::fs`, no
//!   `File`, no standard input, output or error, no printing, no network, no serial port, no
//!   environment, no clock.
//!   Libraries take `Read`/`Write` values and report progress through a callback.
//! - No file under `crates/*/src` longer than [`MAX_LINES`] lines (the viewer's script aside).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The longest a source file may grow before it is split along its seams.
const MAX_LINES: usize = 700;

/// The one file allowed past [`MAX_LINES`]: the 3D page's script, a single program for the browser.
const LONG_FILES: &[&str] = &["viewer.js"];

/// The layers of nc's writer, first to last: a file imports (`super::NAME`) only the layers
/// before its own, so the writer has no loop.
const WRITE_LAYERS: &[&[&str]] =
    &[&["dialect", "csv"], &["options"], &["blocks"], &["arcs", "frames", "kept", "post"], &["gcode"], &["parts"]];

/// The layer of nc's writer a module is in.
fn write_layer(name: &str) -> Option<usize> {
    WRITE_LAYERS.iter().position(|layer| layer.contains(&name))
}

/// The modules a line names through `super::NAME`.
fn supers_named(line: &str) -> impl Iterator<Item = &str> {
    line.match_indices("super::").map(move |(at, _)| {
        let after = &line[at + 7..];
        &after[..after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len())]
    })
}

/// What a library must not name: each a way to reach a file, a port or the terminal.
const OUTSIDE: &[&str] = &[
    "std::fs",
    "fs::",
    "File::",
    "OpenOptions",
    "std::io::stdin",
    "std::io::stdout",
    "std::io::stderr",
    "io::stdin",
    "io::stdout",
    "io::stderr",
    "println!",
    "eprintln!",
    "print!",
    "eprint!",
    "dbg!",
    "std::net",
    "serialport",
    "std::env",
    "std::process",
    "SystemTime::now",
    "Instant::now",
];

/// One source file: its path from the workspace root and its text.
struct Source {
    path: String,
    text: String,
}

/// Every file under `dir`, its path relative to `root`, sorted.
fn files(root: &Path, dir: &Path) -> Vec<Source> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if let Ok(text) = std::fs::read_to_string(&p) {
                let path = p.strip_prefix(root).unwrap_or(&p).to_string_lossy().replace('\\', "/");
                out.push(Source { path, text });
            }
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
    out
}

/// The code of a line: what comes before a `//` comment (a rough cut: `//` inside a string
/// ends the code early, which can only hide a violation written in a string).
fn code(line: &str) -> &str {
    match line.find("//") {
        Some(at) => &line[..at],
        None => line,
    }
}

/// The lines of a file's code outside its `#[cfg(test)]` items (unit tests may write files
/// of their own), numbered from 1. An item runs from its attribute to the line that closes
/// its braces (or ends it with `;`), counted roughly: braces in strings or comments can only
/// make it end late or early by a few lines.
fn code_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    // Inside a test item: the depth of its braces and whether its body has opened.
    let mut test_item: Option<(i32, bool)> = None;
    text.lines().enumerate().filter_map(move |(i, line)| {
        if test_item.is_none() && line.trim_start().starts_with("#[cfg(test)]") {
            test_item = Some((0, false));
            return None;
        }
        let Some((depth, opened)) = test_item.as_mut() else { return Some((i + 1, code(line))) };
        for c in code(line).chars() {
            match c {
                '{' => (*depth, *opened) = (*depth + 1, true),
                '}' => *depth -= 1,
                _ => {}
            }
        }
        if (*opened && *depth <= 0) || (!*opened && code(line).trim_end().ends_with(';')) {
            test_item = None;
        }
        None
    })
}

/// The crate a path under `crates/` is in, and the path inside its `src/`.
fn crate_and_inner(path: &str) -> Option<(&str, &str)> {
    let rest = path.strip_prefix("crates/")?;
    let (krate, rest) = rest.split_once('/')?;
    Some((krate, rest.strip_prefix("src/")?))
}

/// The command a cli source belongs to (`cmd/NAME.rs` or `cmd/NAME/…`), or None for shared plumbing.
fn command_of(inner: &str) -> Option<&str> {
    let rest = inner.strip_prefix("cmd/")?;
    let first = rest.split('/').next()?;
    Some(first.strip_suffix(".rs").unwrap_or(first))
}

/// The command names a line of code reaches through `cmd::NAME` or `cmd::{NAME, …}`.
fn commands_named(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("cmd::") {
        let before = rest[..at].chars().next_back();
        let after = &rest[at + 5..];
        rest = after;
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        let list = match after.strip_prefix('{') {
            Some(inside) => &inside[..inside.find('}').unwrap_or(inside.len())],
            None => after,
        };
        for item in list.split(',') {
            let item = item.trim_start();
            let end = item.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(item.len());
            if end > 0 {
                out.push(&item[..end]);
            }
            if !after.starts_with('{') {
                break;
            }
        }
    }
    out
}

/// How many folders below `cmd/` a command's file sits (`cmd/sim.rs` 0, `cmd/probe/mill.rs` 1).
fn depth_in_command(inner: &str) -> usize {
    inner.strip_prefix("cmd/").map_or(0, |r| r.matches('/').count())
}

/// The longest run of `super::` in a line: how far up the module tree it reaches.
fn supers(line: &str) -> usize {
    (1..).take_while(|k| line.contains(&"super::".repeat(*k))).last().unwrap_or(0)
}

/// Whether `word` occurs in `line` as a path start (not inside a longer name).
fn names(line: &str, word: &str) -> bool {
    line.match_indices(word).any(|(at, _)| {
        let before = line[..at].chars().next_back();
        !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
    })
}

/// Every broken rule in the workspace at `root`, one line each: `path:line: what`.
fn violations(root: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let sources = files(root, &root.join("crates"));
    for s in &sources {
        let Some((krate, inner)) = crate_and_inner(&s.path) else { continue };
        let name = inner.rsplit('/').next().unwrap_or(inner);
        let lines = s.text.lines().count();
        if lines > MAX_LINES && !LONG_FILES.contains(&name) {
            found.push(format!(
                "{}:{}: {lines} lines, over the limit of {MAX_LINES}: split it along its seams",
                s.path,
                MAX_LINES + 1
            ));
        }
        if !inner.ends_with(".rs") {
            continue;
        }
        for (n, line) in code_lines(&s.text) {
            if krate == "cli" && inner != "lib.rs" {
                let own = command_of(inner);
                for other in commands_named(line) {
                    if own != Some(other) {
                        let who = own.map_or("shared plumbing".to_string(), |c| format!("command `{c}`"));
                        found.push(format!("{}:{n}: {who} imports command `{other}`", s.path));
                    }
                }
                // `super::` enough times to climb out of a command reaches the other commands.
                if own.is_some() && supers(line) > depth_in_command(inner) {
                    found.push(format!("{}:{n}: a command reaches its sibling commands through `super::`", s.path));
                }
            } else {
                if krate == "nc" && inner.starts_with("interp") && names(line, "crate::write") {
                    found.push(format!("{}:{n}: interp imports write (`crate::write`)", s.path));
                }
                if let Some(own) =
                    inner.strip_prefix("write/").and_then(|f| f.strip_suffix(".rs")).and_then(write_layer)
                {
                    for name in supers_named(line) {
                        if write_layer(name).is_some_and(|l| l >= own) {
                            found.push(format!(
                                "{}:{n}: write's layers loop (`super::{name}` is not before this file)",
                                s.path
                            ));
                        }
                    }
                }
                if krate == "nc"
                    && inner.starts_with("parse")
                    && (names(line, "crate::interp") || names(line, "crate::write"))
                {
                    found.push(format!("{}:{n}: parse imports a later stage", s.path));
                }
                if let Some(what) = OUTSIDE.iter().find(|what| names(line, what)) {
                    found.push(format!("{}:{n}: a library reaches outside (`{what}`)", s.path));
                }
            }
        }
    }
    found
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

#[test]
fn the_house_keeps_its_rules() {
    let found = violations(&workspace());
    let mut said = String::new();
    for v in &found {
        let _ = writeln!(said, "{v}");
    }
    assert!(found.is_empty(), "{} broken rules:\n{said}", found.len());
}

/// A workspace of a few files in a temporary folder, for the rules' own tests.
fn planted(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (path, text) in files {
        let p = dir.path().join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    dir
}

#[test]
fn a_planted_violation_of_each_rule_is_named_at_its_line() {
    let long = "fn f() {}\n".repeat(MAX_LINES + 1);
    let dir = planted(&[
        ("crates/cli/src/cmd/sim.rs", "use std::fs;\nuse crate::cmd::view::page;\n"),
        ("crates/cli/src/cmd/view.rs", "use super::sim;\n"),
        (
            "crates/cli/src/cmd/probe/mill.rs",
            "use crate::cmd::probe::data;\nuse super::plan;\nuse super::super::sim;\n",
        ),
        ("crates/cli/src/cmd/probe/capture/port.rs", "use super::super::plan;\n"),
        ("crates/cli/src/files.rs", "fn f() { crate::cmd::run::run(); }\nuse crate::cmd::{check, sim::Sim};\n"),
        ("crates/cli/src/lib.rs", "use cmd::{check, sim};\n"),
        ("crates/nc/src/interp/cycle.rs", "// crate::write in a comment\nlet s = crate::write::number(1.0, 3);\n"),
        ("crates/nc/src/parse/expr.rs", "use crate::interp::Value;\n"),
        ("crates/nc/src/write/blocks.rs", "use super::dialect::Dialect;\nuse super::post::Setup;\n"),
        ("crates/cam/src/mill.rs", "fn f() {\n    let f = std::fs::File::open(\"x\");\n    eprintln!(\"hi\");\n}\n"),
        ("crates/geom/src/big.rs", long.as_str()),
        (
            "crates/cam/src/ok.rs",
            "fn f() {}\n#[cfg(test)]\nmod tests {\n    fn t() { std::fs::write(\"x\", \"\"); }\n}\n",
        ),
        (
            "crates/cam/src/after.rs",
            "#[cfg(test)]\nuse std::fs;\n#[cfg(test)]\nmod tests {\n}\nfn f() { println!(\"x\"); }\n",
        ),
        ("crates/picture/src/view/viewer.js", long.as_str()),
    ]);
    let found = violations(dir.path());
    let expected = [
        "crates/cam/src/mill.rs:2: a library reaches outside (`std::fs`)",
        "crates/cam/src/mill.rs:3: a library reaches outside (`eprintln!`)",
        "crates/cam/src/after.rs:6: a library reaches outside (`println!`)",
        "crates/cli/src/cmd/sim.rs:2: command `sim` imports command `view`",
        "crates/cli/src/cmd/view.rs:1: a command reaches its sibling commands through `super::`",
        "crates/cli/src/cmd/probe/mill.rs:3: a command reaches its sibling commands through `super::`",
        "crates/cli/src/files.rs:1: shared plumbing imports command `run`",
        "crates/cli/src/files.rs:2: shared plumbing imports command `check`",
        "crates/cli/src/files.rs:2: shared plumbing imports command `sim`",
        "crates/geom/src/big.rs:701: 701 lines, over the limit of 700: split it along its seams",
        "crates/nc/src/interp/cycle.rs:2: interp imports write (`crate::write`)",
        "crates/nc/src/parse/expr.rs:1: parse imports a later stage",
        "crates/nc/src/write/blocks.rs:2: write's layers loop (`super::post` is not before this file)",
    ];
    for e in expected {
        assert!(found.iter().any(|f| f == e), "not found: {e}\nfound:\n{}", found.join("\n"));
    }
    // The cli may use files; a command may use its own submodules (`probe/mill.rs` its
    // sibling `plan`, `probe/capture/port.rs` its command's `plan`); lib.rs dispatches to the
    // commands; tests may write files; comments are not code; the viewer's script may be long.
    assert_eq!(found.len(), expected.len(), "found:\n{}", found.join("\n"));
}
