//! Pictures (`relief`, `relief --mask`, `tool profile`): whatever the file
//! says about its size, reading it ends in a picture or an error, within
//! libFuzzer's memory limit. No input may panic.
#![no_main]

use std::io::Write;

use kezuri::inputs::read_gray;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // `read_gray` reads a path, as the commands do: the bytes go to a file.
    let Ok(mut file) = tempfile::NamedTempFile::new() else { return };
    if file.write_all(data).is_err() {
        return;
    }
    if let Ok(gray) = read_gray(file.path()) {
        assert_eq!(gray.v.len(), gray.width * gray.height);
    }
});
