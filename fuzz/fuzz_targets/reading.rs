//! Instrument lines of `probe capture`: Mitutoyo records, Digimatic frames
//! and plain numbers, in each `--format`. No input may panic, and a reading
//! is a finite number.
#![no_main]

use kezuri_cam::probe::capture::{parse_reading, Format};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let line = String::from_utf8_lossy(data);
    for format in [Format::Auto, Format::Digimatic, Format::Number] {
        if let Ok(r) = parse_reading(&line, format) {
            assert!(r.mm.is_finite(), "{line:?} read as {}", r.mm);
        }
    }
});
