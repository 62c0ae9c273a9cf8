//! The lines a dial indicator sends to `kezuri probe capture`, read on a
//! table of formats: Mitutoyo records, Digimatic frames and plain numbers,
//! and the damaged lines that must never become a reading.

use kezuri_cam::probe::capture::{parse_reading, Format};

#[test]
fn parser_table() {
    use Format::*;
    // (line, format, value in mm, decimals, channel)
    let good: &[(&str, Format, f64, u32, Option<u32>)] = &[
        ("01A+0012.345", Auto, 12.345, 3, Some(1)),
        ("01A+0012.345\r", Digimatic, 12.345, 3, Some(1)),
        ("01A+00012.35", Auto, 12.35, 2, Some(1)),
        ("01A+000012.3", Auto, 12.3, 1, Some(1)),
        ("01A+00.12345", Auto, 0.12345, 5, Some(1)), // 99MAF600B, inch 0.00005
        ("01A-001.2340", Auto, -1.234, 4, Some(1)),  // GageMux manual's Mux-10 example
        ("01A+0000.123", Auto, 0.123, 3, Some(1)),   // Mitutoyo 99MAF600B, mm 0.001
        ("01A+000.1234", Digimatic, 0.1234, 4, Some(1)), // same, inch resolution digits
        ("07A-00000.00", Auto, -0.0, 2, Some(7)),
        ("10A+00019.16", Auto, 19.16, 2, Some(10)),
        ("FFFF8012345 30", Auto, -12.345, 3, None), // 99MBA043A example frame, mm
        ("FFFF0210765 40", Digimatic, 21.0765, 4, None), // LSM-6200 manual example
        ("FFFF0001234 41", Auto, 0.1234 * 25.4, 5, None), // inch → mm
        ("-12.345", Auto, -12.345, 3, None),
        ("+19.16", Number, 19.16, 2, None),
        ("19.16 mm", Auto, 19.16, 2, None),
        ("  - 3.5mm ", Auto, -3.5, 1, None),
        ("42", Auto, 42.0, 0, None),
        (".5", Number, 0.5, 1, None),
    ];
    for &(line, format, mm, decimals, channel) in good {
        let r = parse_reading(line, format).unwrap_or_else(|e| panic!("{line:?}: {e}"));
        assert!((r.mm - mm).abs() < 1e-12, "{line:?}: {} ≠ {mm}", r.mm);
        assert_eq!((r.decimals, r.channel), (decimals, channel), "{line:?}");
    }
    let bad: &[(&str, Format)] = &[
        ("", Auto),
        ("   ", Auto),
        ("01A+001?.345", Auto),
        ("01A+0001345", Auto),   // the point lost: not 1345 mm
        ("01A+0001", Auto),      // the rest lost: not 1 mm
        ("01A+00012.345", Auto), // one digit too many
        ("01A+.0012345", Auto),  // no digit before the point
        ("01A+0012345.", Auto),  // no digit after it
        ("01A+0012.3.5", Auto),
        ("01A+00123456", Auto), // no point
        ("01A", Auto),
        ("01A00012.345", Auto),
        ("01A+", Auto),
        ("01A+12.3.4", Auto),
        ("01A++0012.345", Auto),
        ("01A+00012.345", Number),
        ("-12.345", Digimatic),
        ("FFFF4012345 30", Auto), // bad sign nibble
        ("FFFF0012345 70", Auto), // decimal point past 5
        ("FFFF0012345 39", Auto), // unknown unit
        ("FFFF00A2345 30", Digimatic),
        ("FFFF0021076540", Auto), // 14 nibbles is not a frame
        ("nan", Auto),
        ("inf", Auto),
        ("1e5", Auto),
        ("12,345", Auto),
        ("1,19.16", Auto), // a No,Z record is not a reading
        ("12.3.4", Auto),
        ("--1", Auto),
        ("\u{1}#@!", Auto),
        ("ERR", Auto),
    ];
    for &(line, format) in bad {
        assert!(parse_reading(line, format).is_err(), "{line:?} ({format:?}) should be rejected");
    }
}
