//! Machine files (`--machine M.toml`): every section read and checked, as
//! each command does before its work. No input may panic.
#![no_main]

use std::io::Write;

use kezuri::inputs::Machine;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // `Machine::read` reads a path, as the commands do; the file sits in a
    // folder of its own, so a `tools.import` finds nothing beside it.
    let Ok(dir) = tempfile::tempdir() else { return };
    let path = dir.path().join("m.toml");
    let Ok(mut file) = std::fs::File::create(&path) else { return };
    if file.write_all(data).is_err() {
        return;
    }
    let _ = Machine::read(&path).map_err(|e| format!("{e:#}"));
});
