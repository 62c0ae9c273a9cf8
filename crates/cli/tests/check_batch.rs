//! `kezuri check --jobs N FILE...`: many programs checked at once, each
//! report what `check` alone says of that file, in the order given.

mod common;

use std::path::Path;

use common::{kezuri, path};
use serde_json::Value;

/// A small program that differs by `k`: its length and bounds name it.
fn program(k: usize) -> String {
    let mut s = format!("%\nO{:04}\nG21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z-1. F300.\n", 1000 + k);
    for i in 0..(k % 7 + 1) * 40 {
        s += &format!("X{}. Y{}.\n", k + i % 5, i);
    }
    s + "G0 Z5.\nM30\n%\n"
}

/// Writes `n` programs into `dir`, every fifth with a feed of zero (an
/// error), and returns their paths in order.
fn library(dir: &Path, n: usize) -> Vec<String> {
    (0..n)
        .map(|k| {
            let name = format!("p{k:03}.nc");
            let text = if k % 5 == 3 { program(k).replace("F300.", "F0") } else { program(k) };
            std::fs::write(dir.join(&name), text).unwrap();
            path(dir, &name)
        })
        .collect()
}

fn json_lines(out: &[u8]) -> Vec<Value> {
    String::from_utf8_lossy(out).lines().map(|l| serde_json::from_str(l).expect("one JSON object a line")).collect()
}

#[test]
fn each_line_is_what_check_alone_says_in_the_order_given() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = library(dir.path(), 24);
    files.insert(7, path(dir.path(), "absent.nc"));
    let mut args = vec!["check", "--jobs", "3", "--json"];
    args.extend(files.iter().map(String::as_str));
    let batch = kezuri(&args);
    assert_eq!(batch.status.code(), Some(1), "a failed program makes the batch fail");
    let lines = json_lines(&batch.stdout);
    assert_eq!(lines.len(), files.len());
    let mut failed = 0;
    for (file, line) in files.iter().zip(&lines) {
        assert_eq!(line["file"], Value::String(file.clone()), "lines in the order the files were given");
        if file.ends_with("absent.nc") {
            let error = line["error"].as_str().expect("an unreadable file's error");
            assert!(error.contains("cannot read") && error.contains("absent.nc"), "{error}");
            assert_eq!(line["completed"], Value::Bool(false));
            failed += 1;
            continue;
        }
        // The same keys and values as `check --json` of that file alone.
        let alone = kezuri(&["check", "--json", file]);
        let mut expected = json_lines(&alone.stdout).remove(0);
        let error = match alone.status.success() {
            true => Value::Null,
            false => {
                failed += 1;
                Value::String(format!("{file}: 1 error"))
            }
        };
        expected.as_object_mut().unwrap().insert("error".into(), error);
        assert_eq!(line, &expected, "{file}");
    }
    assert_eq!(failed, 1 + (0..24).filter(|k| k % 5 == 3).count(), "the unreadable file and every fifth program");
    let stderr = String::from_utf8_lossy(&batch.stderr);
    assert!(stderr.contains(&format!("{failed} programs of {} failed", files.len())), "{stderr}");
}

#[test]
fn text_reports_come_in_the_order_given_and_a_clean_batch_succeeds() {
    let dir = tempfile::tempdir().unwrap();
    let files: Vec<String> =
        library(dir.path(), 12).into_iter().enumerate().filter(|(k, _)| k % 5 != 3).map(|(_, f)| f).collect();
    let mut args = vec!["check", "--jobs", "2"];
    args.extend(files.iter().map(String::as_str));
    let out = kezuri(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let heads: Vec<&str> = text.lines().filter(|l| !l.starts_with(' ')).collect();
    assert_eq!(heads.len(), files.len());
    for (head, file) in heads.iter().zip(&files) {
        assert!(head.starts_with(&format!("{file}: ")), "{head} for {file}");
    }
}

#[test]
fn what_cannot_be_shared_between_programs_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let files = library(dir.path(), 2);
    let refused = |args: &[&str], why: &str| {
        let out = kezuri(args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing checked");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(why), "{args:?}: {stderr}");
    };
    refused(&["check", "--jobs", "0", &files[0], &files[1]], "--jobs must be at least 1");
    // The most jobs there can be: as many threads as files, no more.
    let out = kezuri(&["check", "--jobs", &usize::MAX.to_string(), &files[0], &files[1]]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let dprnt = path(dir.path(), "printed.txt");
    refused(&["check", &files[0], &files[1], "--dprnt", &dprnt], "--dprnt names one file");
    refused(&["check", &files[0], "-"], "standard input (-) can be checked alone only");
}
