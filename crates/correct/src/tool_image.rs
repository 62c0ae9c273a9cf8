//! A tool's silhouette in backlit images (the thermal and wear
//! report, the tool microscope).
//!
//! Convention (`kezuri tool profile`): the tool axis is vertical, tip down, the
//! tool dark on a bright backlight. Gray values are `0.0` (black) to `1.0`
//! (full scale); pixel `(c, r)` covers `[c − ½, c + ½] × [r − ½, r + ½]`,
//! row 0 at the top.
//!
//! - [`otsu`]: the threshold between tool and backlight that best splits
//!   the gray levels into two classes (Otsu 1979, on 4096 levels).
//! - [`silhouette`]: the tool in one image: the largest connected dark
//!   region (specks of dust or noise elsewhere ignored), and in each of its
//!   rows the left and right edges to a fraction of a pixel, where the gray
//!   level crosses the threshold between the last bright and first dark
//!   pixel.
//! - [`runout`]: how far the tool's axis swings as it turns, from the
//!   centres of the frames' silhouettes.

/// A gray image, `0.0` black to `1.0` full scale, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct GrayImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` values, row by row.
    pub pixels: Vec<f32>,
}

impl GrayImage {
    /// A `width × height` image of `value`.
    pub fn filled(width: usize, height: usize, value: f32) -> GrayImage {
        GrayImage { width, height, pixels: vec![value; width * height] }
    }

    /// The value at column `c`, row `r`.
    #[inline]
    pub fn at(&self, c: usize, r: usize) -> f32 {
        self.pixels[r * self.width + c]
    }

    /// The value at `(x, y)` in pixel coordinates, bilinear between pixel
    /// centres; `None` outside the centres' span.
    #[inline]
    pub fn sample(&self, x: f64, y: f64) -> Option<f64> {
        let (cx, cy) = (x.floor(), y.floor());
        if cx < 0.0 || cy < 0.0 || cx + 1.0 >= self.width as f64 || cy + 1.0 >= self.height as f64 {
            // The last row or column itself, exactly.
            if x == (self.width - 1) as f64 || y == (self.height - 1) as f64 {
                let (c, r) = (x as usize, y as usize);
                if x.fract() == 0.0 && y.fract() == 0.0 && c < self.width && r < self.height {
                    return Some(f64::from(self.at(c, r)));
                }
            }
            return None;
        }
        let (c, r) = (cx as usize, cy as usize);
        let (tx, ty) = (x - cx, y - cy);
        let p = |dc: usize, dr: usize| f64::from(self.pixels[(r + dr) * self.width + c + dc]);
        let top = p(0, 0) + tx * (p(1, 0) - p(0, 0));
        let bottom = p(0, 1) + tx * (p(1, 1) - p(0, 1));
        Some(top + ty * (bottom - top))
    }
}

/// Levels of the histogram [`otsu`] splits.
const LEVELS: usize = 4096;

/// Otsu's split of gray levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// The threshold: at or below it, tool.
    pub threshold: f32,
    /// Mean level of the dark class.
    pub dark: f32,
    /// Mean level of the bright class.
    pub bright: f32,
}

/// The gray levels of `images` (pixels without a value, `NaN`, left out)
/// split into the two classes of largest between-class variance (Otsu),
/// and the threshold halfway between the classes' medians; `None` when
/// every pixel has the same level.
pub fn otsu<'a>(images: impl IntoIterator<Item = &'a GrayImage>) -> Option<Split> {
    let mut histogram = vec![0u64; LEVELS];
    for image in images {
        for &v in image.pixels.iter().filter(|v| !v.is_nan()) {
            histogram[((v.clamp(0.0, 1.0) * (LEVELS - 1) as f32).round()) as usize] += 1;
        }
    }
    let total: u64 = histogram.iter().sum();
    let sum: f64 = histogram.iter().enumerate().map(|(i, &n)| i as f64 * n as f64).sum();
    let (mut below, mut below_sum) = (0u64, 0.0);
    let mut best: Option<(f64, usize)> = None;
    for (i, &n) in histogram.iter().enumerate().take(LEVELS - 1) {
        below += n;
        below_sum += i as f64 * n as f64;
        let above = total - below;
        if below == 0 || above == 0 {
            continue;
        }
        let (m0, m1) = (below_sum / below as f64, (sum - below_sum) / above as f64);
        let between = below as f64 * above as f64 * (m0 - m1) * (m0 - m1);
        if best.is_none_or(|(b, _)| between > b) {
            best = Some((between, i));
        }
    }
    let (_, split, ..) = best?;
    // The edge lies where the level is halfway between tool and backlight:
    // halfway between the classes' medians (edge pixels, half one and half
    // the other, would pull their means).
    let median_of = |from: usize, to: usize| {
        let count: u64 = histogram[from..to].iter().sum();
        let mut seen = 0;
        for (i, &n) in histogram[from..to].iter().enumerate() {
            seen += n;
            if 2 * seen >= count {
                return (from + i) as f32 / (LEVELS - 1) as f32;
            }
        }
        to as f32 / (LEVELS - 1) as f32
    };
    let (dark, bright) = (median_of(0, split + 1), median_of(split + 1, LEVELS));
    Some(Split { threshold: 0.5 * (dark + bright), dark, bright })
}

/// The tool in one image: per row, its left and right edges (pixel
/// coordinates, to a fraction of a pixel), `None` where the row does not
/// cross it. An edge at the image's border or beside a pixel with no
/// value (`NaN`: no field of view covers it) is `NaN`: the tool runs out
/// of the picture there.
#[derive(Clone, Debug, PartialEq)]
pub struct Silhouette {
    /// Per row, `(left, right)`.
    pub rows: Vec<Option<(f64, f64)>>,
    /// Pixels of the region.
    pub pixels: usize,
}

impl Silhouette {
    /// The lowest row the tool reaches.
    pub fn tip_row(&self) -> Option<usize> {
        self.rows.iter().rposition(Option::is_some)
    }

    /// The median, over the rows where both edges are inside the image, of
    /// the middle between the edges; `None` if no row has both.
    pub fn centre(&self) -> Option<f64> {
        let mut mids: Vec<f64> = self
            .rows
            .iter()
            .flatten()
            .filter(|(l, r)| l.is_finite() && r.is_finite())
            .map(|(l, r)| 0.5 * (l + r))
            .collect();
        median(&mut mids)
    }
}

/// The median of `v` (reordered); `None` when empty.
pub fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) })
}

/// The silhouette of the tool in `image`: the largest 4-connected region of
/// pixels at or below `threshold`; `None` when no pixel is.
pub fn silhouette(image: &GrayImage, threshold: f32) -> Option<Silhouette> {
    let (w, h) = (image.width, image.height);
    let dark: Vec<bool> = image.pixels.iter().map(|&v| v <= threshold).collect();
    let mut label = vec![0u32; w * h];
    let (mut best, mut best_size, mut next) = (0u32, 0usize, 0u32);
    let mut stack = Vec::new();
    for start in 0..w * h {
        if !dark[start] || label[start] != 0 {
            continue;
        }
        next += 1;
        label[start] = next;
        stack.push(start);
        let mut size = 0;
        while let Some(p) = stack.pop() {
            size += 1;
            let (c, r) = (p % w, p / w);
            let mut visit = |q: usize| {
                if dark[q] && label[q] == 0 {
                    label[q] = next;
                    stack.push(q);
                }
            };
            if c > 0 {
                visit(p - 1);
            }
            if c + 1 < w {
                visit(p + 1);
            }
            if r > 0 {
                visit(p - w);
            }
            if r + 1 < h {
                visit(p + w);
            }
        }
        if size > best_size {
            (best, best_size) = (next, size);
        }
    }
    if best_size == 0 {
        return None;
    }
    let t = f64::from(threshold);
    let value = |c: usize, r: usize| f64::from(image.at(c, r));
    let rows = (0..h)
        .map(|r| {
            let row = &label[r * w..(r + 1) * w];
            let first = row.iter().position(|&l| l == best)?;
            let last = row.iter().rposition(|&l| l == best)?;
            // Where the gray level crosses the threshold between the bright
            // pixel outside and the dark one inside.
            let outside = |c: usize| image.at(c, r).is_nan();
            let left = if first == 0 || outside(first - 1) {
                f64::NAN
            } else {
                let (b, d) = (value(first - 1, r), value(first, r));
                (first - 1) as f64 + ((b - t) / (b - d)).clamp(0.0, 1.0)
            };
            let right = if last + 1 == w || outside(last + 1) {
                f64::NAN
            } else {
                let (d, b) = (value(last, r), value(last + 1, r));
                last as f64 + ((t - d) / (b - d)).clamp(0.0, 1.0)
            };
            Some((left, right))
        })
        .collect();
    Some(Silhouette { rows, pixels: best_size })
}

/// The eccentricity of the turning tool in pixels (the radius of the
/// circle its axis describes): half the spread of the frames' silhouette
/// centres, from the 2.5th to the 97.5th percentile when there are 40
/// frames or more (a frame spoiled by a chip does not count; for angles
/// spread evenly around the turn those percentiles lie within 0.4 % of the
/// extremes), from the least to the largest otherwise. `None` with fewer
/// than 3 centres.
pub fn runout(centres: &[f64]) -> Option<f64> {
    if centres.len() < 3 {
        return None;
    }
    let mut v = centres.to_vec();
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let at = p * (v.len() - 1) as f64;
        let (i, t) = (at.floor() as usize, at.fract());
        v[i] + t * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    let (lo, hi) = if v.len() >= 40 { (q(0.025), q(0.975)) } else { (v[0], v[v.len() - 1]) };
    Some(0.5 * (hi - lo))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bar of `dark` from column `left` to `right` (fractions covered at
    /// its edges), in rows `top..bottom`, on a backlight of 0.9.
    fn bar(w: usize, h: usize, left: f64, right: f64, rows: std::ops::Range<usize>) -> GrayImage {
        let mut img = GrayImage::filled(w, h, 0.9);
        for r in rows {
            for c in 0..w {
                let (a, b) = (c as f64 - 0.5, c as f64 + 0.5);
                let cover = (b.min(right) - a.max(left)).max(0.0);
                img.pixels[r * w + c] = (0.9 - 0.8 * cover) as f32;
            }
        }
        img
    }

    #[test]
    fn otsu_splits_tool_from_backlight() {
        let img = bar(40, 10, 10.0, 30.0, 0..10);
        let s = otsu([&img]).unwrap();
        assert!(s.threshold > 0.1 && s.threshold < 0.9, "{s:?}");
        assert!((s.dark - 0.1).abs() < 0.01 && (s.bright - 0.9).abs() < 0.01, "{s:?}");
        assert_eq!(otsu([&GrayImage::filled(5, 5, 0.5)]), None);
    }

    #[test]
    fn edges_to_a_fraction_of_a_pixel_and_specks_ignored() {
        let mut img = bar(40, 12, 10.3, 29.6, 0..9);
        img.pixels[11 * 40 + 2] = 0.0; // a speck of dust
        let s = silhouette(&img, 0.5).unwrap();
        assert_eq!(s.tip_row(), Some(8));
        let (l, r) = s.rows[4].unwrap();
        assert!((l - 10.3).abs() < 0.1 && (r - 29.6).abs() < 0.1, "{l} {r}");
        assert!((s.centre().unwrap() - 19.95).abs() < 0.1);
        // A tool running out of the picture: no edge there.
        let s = silhouette(&bar(40, 4, -3.0, 20.0, 0..4), 0.5).unwrap();
        assert!(s.rows[0].unwrap().0.is_nan());
        assert_eq!(silhouette(&GrayImage::filled(4, 4, 0.9), 0.5), None);
    }

    #[test]
    fn runout_is_half_the_swing_of_the_centre() {
        let centres: Vec<f64> = (0..360).map(|k| 100.0 + 14.0 * (k as f64).to_radians().cos()).collect();
        assert!((runout(&centres).unwrap() - 14.0).abs() < 0.06);
        assert_eq!(runout(&[1.0, 2.0]), None);
    }
}
