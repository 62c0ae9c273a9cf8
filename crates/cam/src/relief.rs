//! A grayscale sketch as a relief surface (the relief paper): gray values become
//! heights, the picture gets a size in millimetres, and the result is a
//! [`Heightfield`] that drop-cutter places any cutter on.
//!
//! # Heights
//! The stock top is `z = 0` and the relief goes down from it. With
//! [`Mapping::Depth`], white is the top and black `depth` below it (or the
//! other way round with `invert`), in between `z = −depth·(1 − v^gamma)`
//! for the gray value `v` in `[0, 1]`. With [`Mapping::Levels`], the
//! paper's way, ranges of gray (on the 0–255 scale, 16-bit pictures scaled
//! to it) get explicit heights above the relief's floor; the highest level
//! is the stock top. Smoothing (a Gaussian of `smooth` pixels) rounds the
//! steps between levels.
//!
//! # Where the pixels are
//! Pixel `(column, row)` of a `w × h` picture of pixel size `p` is the
//! node at `x = x0 + (column + ½)·p`, `y = y0 + (h − 1 − row + ½)·p`: the
//! picture seen from above, its top row at the largest Y, and `[x0,
//! x0 + w·p] × [y0, y0 + h·p]` the carving's extent.
//!
//! # Carving
//! [`carve`] makes the toolpath of a relief: roughing in levels, raster
//! finishing with drop-cutter on it, and [`crate::mill::reach`]'s check of where the
//! finishing cutter cannot reach.

mod carve;

pub use carve::{carve, Carved, Event, Job, Roughing, Stage};

use kezuri_geom::Heightfield;

use crate::error::{Error, ErrorKind};

/// A grayscale picture: `width × height` values in `[0, 1]` (0 black),
/// row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Gray {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Values, `v[row·width + column]`.
    pub v: Vec<f64>,
}

/// One range of gray and its height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// Lowest gray of the range (0–255).
    pub from: f64,
    /// Highest gray of the range (0–255).
    pub to: f64,
    /// Height above the relief's floor, mm.
    pub height: f64,
}

/// How gray becomes height.
#[derive(Clone, Debug, PartialEq)]
pub enum Mapping {
    /// Continuous: white at the top, black `depth` below (`invert` swaps
    /// them), with a gamma on the gray value.
    Depth {
        /// Depth of black, mm (> 0).
        depth: f64,
        /// Dark high, light low.
        invert: bool,
        /// Exponent on the gray value (1: linear).
        gamma: f64,
    },
    /// The relief paper's per-region heights.
    Levels(Vec<Level>),
}

fn error<T>(message: String) -> Result<T, Error> {
    Err(Error::new(ErrorKind::Relief, message))
}

/// Reads `--levels`: `FROM-TO:HEIGHT` ranges separated by commas, which
/// together must cover every gray from 0 to 255 once.
pub fn parse_levels(text: &str) -> Result<Vec<Level>, Error> {
    let mut levels = Vec::new();
    for part in text.split(',').map(str::trim) {
        let parsed = part.split_once(':').and_then(|(range, h)| {
            let (a, b) = range.split_once('-').unwrap_or((range, range));
            Some((a.trim().parse::<u16>().ok()?, b.trim().parse::<u16>().ok()?, h.trim().parse::<f64>().ok()?))
        });
        let Some((from, to, height)) = parsed.filter(|(a, b, h)| a <= b && *b <= 255 && h.is_finite()) else {
            return error(format!(
                "level '{part}': expected FROM-TO:HEIGHT with 0 ≤ FROM ≤ TO ≤ 255 and a height in mm"
            ));
        };
        levels.push(Level { from: f64::from(from), to: f64::from(to), height });
    }
    levels.sort_by(|a, b| a.from.total_cmp(&b.from));
    cover(&levels)?;
    Ok(levels)
}

/// Checks that `levels`, sorted by `from`, give every gray from 0 to 255
/// one height.
fn cover(levels: &[Level]) -> Result<(), Error> {
    let mut next = 0.0;
    for l in levels {
        if l.from != next {
            return error(if l.from > next {
                format!("--levels leaves gray {next}–{} without a height", l.from - 1.0)
            } else {
                format!("--levels gives gray {} two heights", l.from)
            });
        }
        if !(l.to >= l.from && l.height.is_finite()) {
            return error(format!("level {}-{}:{}: not a range of gray and a height", l.from, l.to, l.height));
        }
        next = l.to + 1.0;
    }
    if next != 256.0 {
        return error(format!("--levels leaves gray {next}–255 without a height"));
    }
    Ok(())
}

impl Mapping {
    /// Checks the numbers.
    pub fn check(&self) -> Result<(), Error> {
        match self {
            Mapping::Depth { depth, gamma, .. } => {
                if !(depth.is_finite() && *depth > 0.0 && *depth <= 1000.0) {
                    return error(format!("the depth must be a positive number of mm up to 1000, got {depth}"));
                }
                if !(gamma.is_finite() && *gamma > 0.0) {
                    return error(format!("the gamma must be a positive number, got {gamma}"));
                }
                Ok(())
            }
            Mapping::Levels(levels) if levels.is_empty() => error("--levels is empty".into()),
            Mapping::Levels(levels) => {
                let mut sorted = levels.clone();
                sorted.sort_by(|a, b| a.from.total_cmp(&b.from));
                cover(&sorted)
            }
        }
    }

    /// The height (z ≤ 0) of gray `v` in `[0, 1]`.
    pub fn z(&self, v: f64) -> f64 {
        match self {
            Mapping::Depth { depth, invert, gamma } => {
                let v = if *invert { 1.0 - v } else { v };
                -depth * (1.0 - v.clamp(0.0, 1.0).powf(*gamma))
            }
            Mapping::Levels(levels) => {
                let top = levels.iter().map(|l| l.height).fold(f64::NEG_INFINITY, f64::max);
                let g = (v.clamp(0.0, 1.0) * 255.0).round();
                // A gray no level covers (check() refuses such levels)
                // stays at the stock top.
                levels.iter().find(|l| g >= l.from && g <= l.to).map_or(0.0, |l| l.height - top)
            }
        }
    }
}

/// Where and how big the carving is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Pixel size, mm.
    pub pixel: f64,
    /// The picture's lower-left corner, mm.
    pub origin: [f64; 2],
}

/// The relief of `picture`: heights by `mapping`, smoothed by a Gaussian
/// of `smooth` pixels (0: none), placed by `placement`. Pixels where
/// `mask` (same size) is dark (below ½) stay at the stock top.
pub fn surface(
    picture: &Gray,
    mapping: &Mapping,
    smooth: f64,
    mask: Option<&Gray>,
    placement: Placement,
) -> Result<Heightfield, Error> {
    mapping.check()?;
    let (w, h) = (picture.width, picture.height);
    if w < 2 || h < 2 {
        return error(format!("a {w} × {h} picture is too small for a relief: it needs 2 × 2 pixels or more"));
    }
    if let Some(m) = mask {
        if (m.width, m.height) != (w, h) {
            return error(format!("the mask is {} × {} pixels, the picture {w} × {h}", m.width, m.height));
        }
    }
    check_smoothing(smooth, w, h)?;
    let mut z: Vec<f64> = picture.v.iter().map(|&v| mapping.z(v)).collect();
    if smooth > 0.0 {
        z = gaussian(&z, w, h, smooth);
    }
    if let Some(m) = mask {
        for (z, &inside) in z.iter_mut().zip(&m.v) {
            if inside < 0.5 {
                *z = 0.0;
            }
        }
    }
    // Heightfield rows run up in Y: the picture's last row first.
    let rows: Vec<f64> = (0..h).rev().flat_map(|row| z[row * w..(row + 1) * w].iter().copied()).collect();
    let p = placement.pixel;
    Heightfield::new(placement.origin[0] + 0.5 * p, placement.origin[1] + 0.5 * p, p, w, h, rows)
        .map_err(|e| Error::new(ErrorKind::Relief, e.to_string()))
}

/// Whether the mask lets the cutter's axis stand at `(x, y)` (inside a
/// light pixel); always without a mask.
pub fn inside(mask: Option<&Gray>, placement: Placement, x: f64, y: f64) -> bool {
    let Some(m) = mask else { return true };
    let column = ((x - placement.origin[0]) / placement.pixel).floor();
    let up = ((y - placement.origin[1]) / placement.pixel).floor();
    if !(column >= 0.0 && up >= 0.0 && column < m.width as f64 && up < m.height as f64) {
        return false;
    }
    let row = m.height - 1 - up as usize;
    m.v[row * m.width + column as usize] >= 0.5
}

/// Most products a smoothing may take (some seconds).
const MAX_SMOOTHING: f64 = 1e10;

/// Refuses a smoothing of `smooth` pixels outside 0 to 100, or one whose
/// work over a `w` × `h` picture is more than [`MAX_SMOOTHING`] products:
/// weighed from the picture's size, before it is read.
pub fn check_smoothing(smooth: f64, w: usize, h: usize) -> Result<(), Error> {
    if !(smooth.is_finite() && (0.0..=100.0).contains(&smooth)) {
        return error(format!("the smoothing must be 0 to 100 pixels, got {smooth}"));
    }
    // Each pixel, twice, times the kernel's width.
    let products = (w * h) as f64 * 2.0 * (2.0 * (3.0 * smooth).ceil() + 1.0);
    if smooth > 0.0 && products > MAX_SMOOTHING {
        return error(format!(
            "smoothing {smooth} pixels over {w} × {h} pixels is {products:.1e} products, more than {MAX_SMOOTHING:.0e}: \
             smooth less or scale the picture down"
        ));
    }
    Ok(())
}

/// A Gaussian blur of standard deviation `sigma` pixels, rows then
/// columns, edges held.
fn gaussian(z: &[f64], w: usize, h: usize, sigma: f64) -> Vec<f64> {
    let r = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f64> = (-r..=r).map(|k| (-((k * k) as f64) / (2.0 * sigma * sigma)).exp()).collect();
    let sum: f64 = kernel.iter().sum();
    let kernel: Vec<f64> = kernel.iter().map(|k| k / sum).collect();
    let pass = |src: &[f64], n: usize, len: usize, at: &dyn Fn(usize, usize) -> usize| -> Vec<f64> {
        let mut out = vec![0.0; src.len()];
        for line in 0..n {
            for i in 0..len {
                out[at(line, i)] = kernel
                    .iter()
                    .enumerate()
                    .map(|(k, c)| c * src[at(line, (i as isize + k as isize - r).clamp(0, len as isize - 1) as usize)])
                    .sum();
            }
        }
        out
    };
    let rows = pass(z, h, w, &|row, i| row * w + i);
    pass(&rows, w, h, &|column, i| i * w + column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_cover_the_grays_once() {
        let l = parse_levels("0-63:0, 64-191:2.5,192-255:5").unwrap();
        let m = Mapping::Levels(l);
        assert_eq!((m.z(0.0), m.z(100.0 / 255.0), m.z(1.0)), (-5.0, -2.5, 0.0));
        let e = |t: &str| parse_levels(t).unwrap_err().message;
        assert_eq!(e("0-63:0,65-255:1"), "--levels leaves gray 64–64 without a height");
        assert_eq!(e("0-63:0,60-255:1"), "--levels gives gray 60 two heights");
        assert_eq!(e("0-200:0"), "--levels leaves gray 201–255 without a height");
        assert!(e("0-300:1").starts_with("level '0-300:1': expected"));
        assert!(e("a-b:1").starts_with("level 'a-b:1'"));
        // Levels made in code are checked as those read: an error, not a
        // panic, for a gray without a height.
        let partial = Mapping::Levels(vec![Level { from: 0.0, to: 100.0, height: 1.0 }]);
        assert_eq!(partial.check().unwrap_err().message, "--levels leaves gray 101–255 without a height");
        let g = Gray { width: 2, height: 2, v: vec![1.0; 4] };
        assert!(surface(&g, &partial, 0.0, None, Placement { pixel: 1.0, origin: [0.0, 0.0] }).is_err());
        assert_eq!((partial.z(0.0), partial.z(1.0)), (0.0, 0.0));
    }

    #[test]
    fn depth_gamma_and_invert() {
        let m = Mapping::Depth { depth: 4.0, invert: false, gamma: 1.0 };
        assert_eq!((m.z(1.0), m.z(0.0), m.z(0.25)), (0.0, -4.0, -3.0));
        let m = Mapping::Depth { depth: 4.0, invert: true, gamma: 2.0 };
        assert_eq!((m.z(0.0), m.z(1.0), m.z(0.5)), (0.0, -4.0, -3.0));
    }

    #[test]
    fn the_picture_is_seen_from_above() {
        // 3 × 2: the top row dark on the left.
        let g = Gray { width: 3, height: 2, v: vec![0.0, 1.0, 1.0, 1.0, 1.0, 1.0] };
        let m = Mapping::Depth { depth: 1.0, invert: false, gamma: 1.0 };
        let f = surface(&g, &m, 0.0, None, Placement { pixel: 2.0, origin: [10.0, 20.0] }).unwrap();
        assert_eq!(f.xy_box(), [11.0, 21.0, 15.0, 23.0]);
        // The dark pixel is the top-left: the largest Y, the smallest X.
        assert_eq!((f.z(0, 1), f.z(0, 0), f.z(2, 1)), (-1.0, 0.0, 0.0));
        let mask = Gray { width: 3, height: 2, v: vec![0.0, 1.0, 1.0, 1.0, 1.0, 1.0] };
        let masked = surface(&g, &m, 0.0, Some(&mask), Placement { pixel: 2.0, origin: [10.0, 20.0] }).unwrap();
        assert_eq!(masked.z(0, 1), 0.0);
        let at = Placement { pixel: 2.0, origin: [10.0, 20.0] };
        assert!(!inside(Some(&mask), at, 11.0, 23.0) && inside(Some(&mask), at, 11.0, 21.0));
        assert!(!inside(Some(&mask), at, 9.0, 21.0));
    }

    #[test]
    fn smoothing_keeps_the_mean_and_softens_a_step() {
        let (w, h) = (20, 5);
        let z: Vec<f64> = (0..w * h).map(|k| if k % w < 10 { -2.0 } else { 0.0 }).collect();
        let s = gaussian(&z, w, h, 1.5);
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean(&s) - mean(&z)).abs() < 1e-12);
        assert!(s[9] > -1.9 && s[10] < -0.1 && (s[0] + 2.0).abs() < 1e-12 && s[19].abs() < 1e-12);
    }
}
