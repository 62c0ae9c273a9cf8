//! Reading gray pictures: a sketch, a mask, a microscope's frame, as gray
//! values 0–1, a picture too large or cut short refused before it is
//! decoded.

use std::path::Path;

use anyhow::{bail, Context, Result};
use kezuri_cam::relief::Gray;

/// Most pixels of a picture (8 bytes of height each, and the picture).
pub const MAX_PIXELS: u64 = 64_000_000;

/// The width and height a picture file declares, read from its header.
pub fn dimensions(path: &Path) -> Result<(u32, u32)> {
    let name = path.display();
    let reader = image::ImageReader::open(path)
        .with_context(|| format!("cannot open {name}"))?
        .with_guessed_format()
        .with_context(|| format!("cannot read {name}"))?;
    reader.into_dimensions().with_context(|| format!("{name}: not a picture kezuri can read"))
}

/// Refuses a JPEG cut short: its data must end with the end-of-image
/// marker (FF D9) after its last start of scan (FF DA). The decoder fills
/// a cut-short picture with gray and reports nothing, and a relief of that
/// gray is no carving of the picture (a 525-byte start of a 7900 × 7900
/// JPEG decoded to 62 million gray pixels).
fn cut_short_jpeg(path: &Path) -> Result<()> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let marker = |m: u8| bytes.windows(2).rposition(|w| w == [0xFF, m]);
    match (marker(0xDA), marker(0xD9)) {
        (Some(scan), Some(end)) if end > scan => Ok(()),
        _ => bail!(
            "{}: the JPEG ends before its picture does (no end-of-image marker after its data): the file was \
             cut short",
            path.display()
        ),
    }
}

/// Decodes `reader`, a decoder's panic on a damaged file (zune-jpeg
/// overflows on some damaged JPEGs where overflow checks are on) being
/// an error like any other damage.
fn decode_guarded(reader: image::ImageReader<std::io::BufReader<std::fs::File>>) -> Result<image::DynamicImage> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| reader.decode()));
    std::panic::set_hook(hook);
    match decoded {
        Ok(result) => Ok(result?),
        Err(_) => bail!("the picture's data is damaged (its decoder gave up)"),
    }
}

/// Reads a picture as gray values, refusing one too large to hold before
/// decoding it.
pub fn read_gray(path: &Path) -> Result<Gray> {
    let name = path.display();
    let (w, h) = dimensions(path)?;
    let pixels = u64::from(w) * u64::from(h);
    if pixels > MAX_PIXELS {
        bail!(
            "{name}: {w} × {h} = {pixels} pixels is more than {MAX_PIXELS}: scale the picture down \
             (0.1 mm pixels over 800 × 800 mm is 64 million)"
        );
    }
    let mut reader = image::ImageReader::open(path)?.with_guessed_format()?;
    if reader.format() == Some(image::ImageFormat::Jpeg) {
        cut_short_jpeg(path)?;
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_PIXELS * 8);
    reader.limits(limits);
    let picture = decode_guarded(reader).with_context(|| format!("{name}: not a picture kezuri can read"))?;
    let luma = picture.to_luma16();
    Ok(Gray {
        width: w as usize,
        height: h as usize,
        v: luma.as_raw().iter().map(|&v| f64::from(v) / 65535.0).collect(),
    })
}
