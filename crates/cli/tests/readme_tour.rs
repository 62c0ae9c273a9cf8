//! The README's tour runs as written: every `sh` block after "Set up",
//! line by line, in a fresh folder holding a copy of `samples/`, with the
//! `kezuri` just built first on the PATH. Every command must succeed, and
//! none may change a file that was there before it ran (an input, or an
//! earlier line's result), but for the tool database, which `tool db add`
//! grows. A line marked `# needs hardware` (a serial measuring device) is
//! shown as skipped; a line naming LinuxCNC's installed examples runs where
//! they are installed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The commands of the README's shell blocks after the set-up one, a
/// command per logical line (`\` continuations joined).
fn tour(readme: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut block = false;
    let mut pending = String::new();
    for line in readme.lines() {
        if line.trim_start().starts_with("```") {
            block = !block && line.trim() == "```sh";
            continue;
        }
        if !block {
            continue;
        }
        let line = line.trim_end();
        if let Some(start) = line.strip_suffix('\\') {
            pending.push_str(start);
            continue;
        }
        pending.push_str(line);
        let command = std::mem::take(&mut pending);
        let trimmed = command.trim();
        if !trimmed.is_empty() && !trimmed.starts_with('#') && !trimmed.starts_with("cargo ") {
            out.push(trimmed.to_string());
        }
    }
    out
}

/// Every file under `dir` with its contents, by path.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for entry in std::fs::read_dir(&d).unwrap().flatten() {
            let p = entry.path();
            if p.is_dir() {
                todo.push(p);
            } else {
                files.insert(p.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&p).unwrap_or_default());
            }
        }
    }
    files
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let (p, q) = (entry.path(), to.join(entry.file_name()));
        if p.is_dir() {
            copy_dir(&p, &q);
        } else {
            std::fs::copy(&p, &q).unwrap();
        }
    }
}

#[test]
fn the_readme_tour_runs_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let commands = tour(&readme);
    assert!(commands.len() > 30, "{} commands found in the README's tour", commands.len());
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&root.join("samples"), &dir.path().join("samples"));
    let bin = Path::new(env!("CARGO_BIN_EXE_kezuri")).parent().unwrap().to_path_buf();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let mut failures = Vec::new();
    for command in &commands {
        if command.contains("# needs hardware") {
            eprintln!("skipped (needs a measuring device on a serial port): {command}");
            continue;
        }
        if command.contains("/usr/share/linuxcnc/") && !Path::new("/usr/share/linuxcnc").exists() {
            eprintln!("skipped (LinuxCNC's examples are not installed here): {command}");
            continue;
        }
        let before = snapshot(dir.path());
        let o = Command::new("sh").arg("-c").arg(command).current_dir(dir.path()).env("PATH", &path).output().unwrap();
        if !o.status.success() {
            failures
                .push(format!("{command}\n    {}", String::from_utf8_lossy(&o.stderr).trim().replace('\n', "\n    ")));
            continue;
        }
        let after = snapshot(dir.path());
        for (file, bytes) in &before {
            let grown = file.extension().is_some_and(|e| e == "sqlite");
            if !grown && after.get(file) != Some(bytes) {
                failures
                    .push(format!("{command}\n    changed or removed {}, which was there before it", file.display()));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} README commands failed:\n{}",
        failures.len(),
        commands.len(),
        failures.join("\n")
    );
}

#[test]
fn the_readme_installs_the_tested_versions() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    // The two set-up commands, as they are.
    for line in ["cargo run --release -- demo ", "cargo test --workspace "] {
        assert!(readme.lines().any(|l| l.starts_with(line)), "README's set-up lost `{line}`");
    }
    // `cargo install` builds with Cargo.lock's versions, not the newest ones.
    let installs: Vec<&str> = readme.lines().filter(|l| l.trim_start().starts_with("cargo install")).collect();
    assert!(!installs.is_empty(), "the README says how to install");
    for line in installs {
        assert!(line.split_whitespace().any(|w| w == "--locked"), "{line}: without --locked");
    }
    assert!(root.join("Cargo.lock").is_file());
}
