//! CSV tables: the measurement tables of `thermal` and `tool profile`
//! (`table.rs` of the command line) and the probe data files of `probe`
//! (`kezuri_cam::probe::data`), with and without the grid from the command
//! line. No input may panic.
#![no_main]

use kezuri::inputs::read_columns;
use kezuri_cam::probe::data::{read, Hint};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    for names in [&["x_mm", "z_mm"][..], &["z_mm", "radius_mm", "wear_mm"]] {
        let _ = read_columns("fuzz.csv", &text, names).map_err(|e| e.to_string());
    }
    let _ = read(&text, &Hint::default()).map_err(|e| e.to_string());
    let hint = Hint { count: Some([3, 2]), pitch: Some(1.5), origin: Some([0.0, 0.0]), ..Hint::default() };
    let _ = read(&text, &hint).map_err(|e| e.to_string());
});
