//! Machine files (`--machine M.toml`): every section read and checked, as
//! each command does before its work. No input may panic.
#![no_main]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use kezuri_machine::Machine;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // As the commands read it; no file is beside it, so a `tools.import`
    // finds nothing.
    let text = String::from_utf8_lossy(data);
    let _ = Machine::parse(&text, Path::new(""), &BTreeMap::<PathBuf, Vec<u8>>::new()).map_err(|e| e.to_string());
});
