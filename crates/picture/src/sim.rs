//! A simulation's pictures (shaded heights, deviation), framed with their
//! title, axes in mm and colour bar, and its surface as triangles.

use kezuri_cam::sim::ZMap;
use kezuri_geom::{Triangle, Vec3};

use crate::figure::{colour_at, ColourBar, Figure, Panel, Raster};
use crate::Error;

/// Largest picture side; bigger grids are sampled every k-th cell.
const MAX_SIDE: usize = 4096;

/// The colour of no target.
const NO_TARGET: [u8; 3] = [128, 128, 128];
/// How deep below the target a cell is a gouge unless `--gouge-tol` says
/// otherwise, mm: the simulation is exact at the cell centres, so only
/// rounding is forgiven.
pub const GOUGE_MM: f64 = 0.001;

/// The colour of a gouge (deeper than the gouge limit below the target,
/// whatever the scale, as on the `--view` page) at the full scale; lighter
/// from the limit down to it.
pub const GOUGE: [u8; 3] = [200, 0, 200];
/// A gouge just over the limit: the gouge colour, light.
const GOUGE_LIGHT: [u8; 3] = [240, 160, 240];
/// Below the target within the gouge limit, at the limit.
const BELOW: [u8; 3] = [250, 215, 215];
const ON: [u8; 3] = [255, 255, 255];
const ABOVE: [u8; 3] = [30, 70, 210];
/// More material left than the scale holds: its own colour, not the
/// scale's full blue (1.13 mm left must not look like the scale's 10 µm).
pub const OVER_LEFT: [u8; 3] = [245, 160, 0];
/// A gouge deeper than the scale holds.
pub const OVER_GOUGE: [u8; 3] = [90, 0, 50];

/// The cells a picture shows: every `k`-th along both axes.
fn picture_grid(zmap: &ZMap) -> (usize, usize, usize) {
    let k = zmap.nx.max(zmap.ny).div_ceil(MAX_SIDE).max(1);
    (k, zmap.nx.div_ceil(k), zmap.ny.div_ceil(k))
}

/// What a picture of the grid covers, mm: left, right, bottom, top.
fn extent(zmap: &ZMap) -> [f64; 4] {
    let (k, w, h) = picture_grid(zmap);
    let cell = k as f64 * zmap.res;
    [zmap.x0, zmap.x0 + w as f64 * cell, zmap.y0, zmap.y0 + h as f64 * cell]
}

/// The tint of height `t` (0 lowest, 1 highest), fully lit.
fn tint(t: f64) -> [f64; 3] {
    [0.45 + 0.55 * t, 0.42 + 0.5 * t, 0.38 + 0.4 * t]
}

/// The light of the shaded pictures: from the north-west, 60° up.
const LIGHT_AZIMUTH_DEG: f64 = 315.0;
const LIGHT_ALTITUDE_DEG: f64 = 60.0;
/// The part of a face's tint that the light does not take away: a face
/// turned from the light is drawn at this share of its tint, never black.
const AMBIENT: f64 = 0.6;

/// How lit a face of slopes `gx`, `gy` (dZ/dX, dZ/dY) is: [`AMBIENT`] for a
/// face turned away from the light (or a wall), 1 for one facing it.
pub(crate) fn lit(gx: f64, gy: f64) -> f64 {
    let (az, alt) = (LIGHT_AZIMUTH_DEG.to_radians(), LIGHT_ALTITUDE_DEG.to_radians());
    let light = [alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin()];
    let n = (1.0 + gx * gx + gy * gy).sqrt();
    let lambert = ((-gx * light[0] - gy * light[1] + light[2]) / n).clamp(0.0, 1.0);
    AMBIENT + (1.0 - AMBIENT) * lambert
}

/// The simulated surface, hill-shaded (light from the north-west, 60° up,
/// a face turned from it at 60 % of its tint) and tinted by height; +Y up.
fn height_raster(zmap: &ZMap) -> Raster {
    let (k, w, h) = picture_grid(zmap);
    let (lo, hi) = zmap.range();
    let span = (hi - lo).max(1e-12);
    let z = |i: usize, j: usize| zmap.height(i.min(zmap.nx - 1), j.min(zmap.ny - 1));
    let d = k as f64 * zmap.res;
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let i = col * k;
            let gx =
                (z(i + k, j) - z(i.saturating_sub(k), j)) / (d * if i >= k && i + k < zmap.nx { 2.0 } else { 1.0 });
            let gy =
                (z(i, j + k) - z(i, j.saturating_sub(k))) / (d * if j >= k && j + k < zmap.ny { 2.0 } else { 1.0 });
            // Relief exaggerated twice, so gentle cusps show.
            let shade = lit(2.0 * gx, 2.0 * gy);
            for c in tint((z(i, j) - lo) / span) {
                rgb.push((255.0 * c * shade).round().clamp(0.0, 255.0) as u8);
            }
        }
    }
    Raster { width: w, height: h, rgb }
}

/// The axes of a picture of the grid.
fn xy() -> [String; 2] {
    ["X, mm".into(), "Y, mm".into()]
}

/// The simulated surface as a framed PNG titled `title`: hill-shaded and
/// tinted by height, with a colour bar of Z.
pub fn height_png(zmap: &ZMap, title: &str) -> Result<Vec<u8>, Error> {
    let (lo, hi) = zmap.range();
    let colour = |t: f64| tint(t).map(|c| (255.0 * c).round() as u8);
    Figure {
        title: title.into(),
        subtitle: format!("simulated surface, {:.3} mm cells, +Y up", zmap.res),
        panels: vec![Panel {
            raster: height_raster(zmap),
            extent: extent(zmap),
            axes: xy(),
            caption: String::new(),
            overlays: vec![],
        }],
        stacked: false,
        bar: Some(ColourBar {
            stops: vec![(lo, colour(0.0)), (hi.max(lo + 1e-9), colour(1.0))],
            label: "Z, mm".into(),
            notes: vec!["shaded as lit from the upper left".into(), "(slopes drawn twice as steep)".into()],
            swatches: vec![],
        }),
        legend: vec![],
    }
    .png()
}

/// How a deviation is coloured, in a picture and on the `--view` page:
/// full colour at ±`mm`, said as `basis`; deeper than `gouge` below the
/// target a gouge.
pub struct DeviationScale {
    /// The deviation shown in full colour, mm.
    pub mm: f64,
    /// What set it: `--deviation-scale` or the 99th percentile.
    pub basis: String,
    /// Deeper than this below the target is a gouge, mm.
    pub gouge: f64,
    /// The deepest gouge and the most material left over the cells drawn
    /// on this scale, mm, both as amounts (0 for none): what the bar says
    /// of the cells beyond it.
    pub extremes: [f64; 2],
}

impl DeviationScale {
    /// `given` (`--deviation-scale`), else the 99th percentile of
    /// |deviation| over the compared cells (at least the gouge limit
    /// `gouge`, `--gouge-tol`).
    pub fn new(zmap: &ZMap, target: &[f64], given: Option<f64>, gouge: f64) -> DeviationScale {
        let mut scale = match given {
            Some(mm) => DeviationScale::fixed(mm, "--deviation-scale", gouge),
            None => DeviationScale::fixed(
                percentile_99(zmap, target).max(gouge),
                "the 99th percentile of |deviation|",
                gouge,
            ),
        };
        scale.include(zmap, target);
        scale
    }

    /// Full colour at ±`mm`, said as `basis`, for pictures drawn on it
    /// after [`Self::include`] has seen their cells.
    pub fn fixed(mm: f64, basis: &str, gouge: f64) -> DeviationScale {
        DeviationScale { mm, basis: basis.into(), gouge, extremes: [0.0; 2] }
    }

    /// Takes in the cells of `zmap` against `target` (`-inf` where none):
    /// one scale for several pictures of a job, its bar saying the extremes
    /// of them all.
    pub fn include(&mut self, zmap: &ZMap, target: &[f64]) {
        for (z, t) in zmap.heights().zip(target).filter(|(_, &t)| t != f64::NEG_INFINITY) {
            let d = z - t;
            self.extremes = [self.extremes[0].max(-d), self.extremes[1].max(d)];
        }
    }

    /// Micrometres for a scale under 0.1 mm, else mm: the factor from mm
    /// and the unit's name.
    fn unit(&self) -> (f64, &'static str) {
        if self.mm < 0.1 {
            (1000.0, "µm")
        } else {
            (1.0, "mm")
        }
    }

    /// The bar's colours, in the unit of [`Self::unit`]: below the target
    /// white to pink down to the gouge limit, then the gouge colour from
    /// light to full; above it white to blue.
    fn stops(&self) -> Vec<(f64, [u8; 3])> {
        let f = self.unit().0;
        let (s, g) = (self.mm * f, self.gouge * f);
        if s > g {
            vec![(-s, GOUGE), (-g, GOUGE_LIGHT), (-g, BELOW), (0.0, ON), (s, ABOVE)]
        } else {
            vec![(-s, BELOW), (0.0, ON), (s, ABOVE)]
        }
    }

    /// The colour bar of pictures on this scale.
    pub fn bar(&self) -> ColourBar {
        let (factor, unit) = self.unit();
        let s = self.mm * factor;
        let notes = vec![format!("full colour at ±{}", short(s, unit)), format!("({})", self.basis)];
        let gouge = format!("gouge: over {} below the target", short(self.gouge * 1000.0, "µm"));
        // Where the bar holds the gouges they deepen in colour as they do.
        let mut swatches = vec![(GOUGE, gouge), (NO_TARGET, "no target".to_string())];
        let [deepest, most] = self.extremes;
        if most > self.mm {
            swatches.push((OVER_LEFT, format!("left over +{}: up to {}", short(s, unit), amount(most))));
        }
        if deepest > self.mm && self.mm > self.gouge {
            swatches.push((OVER_GOUGE, format!("gouge deeper than {}: down to {}", short(s, unit), amount(deepest))));
        }
        ColourBar { stops: self.stops(), label: format!("simulated − target, {unit}"), notes, swatches }
    }

    /// The colour of deviation `d` mm: a gouge's below the gouge limit
    /// however large the scale.
    fn colour(&self, d: f64) -> [u8; 3] {
        let f = self.unit().0;
        let (v, s, g) = (d * f, self.mm * f, self.gouge * f);
        if d > self.mm {
            OVER_LEFT
        } else if d < -self.mm && s > g {
            OVER_GOUGE
        } else if d < -self.gouge {
            if s > g {
                colour_at(&[(-s, GOUGE), (-g, GOUGE_LIGHT)], v)
            } else {
                GOUGE
            }
        } else {
            colour_at(&[(-s.min(g), BELOW), (0.0, ON), (s, ABOVE)], v)
        }
    }
}

/// The 99th percentile of |deviation| over the cells of `zmap` that
/// `target` covers (`-inf` where it does not), mm.
fn percentile_99(zmap: &ZMap, target: &[f64]) -> f64 {
    let mut all: Vec<f64> =
        zmap.heights().zip(target).filter(|(_, &t)| t != f64::NEG_INFINITY).map(|(z, t)| (z - t).abs()).collect();
    if all.is_empty() {
        return 0.0;
    }
    let k = ((all.len() - 1) as f64 * 0.99).round() as usize;
    *all.select_nth_unstable_by(k, f64::total_cmp).1
}

/// `v` with few digits and its unit: `3.2 µm`, `0.154 mm`.
fn short(v: f64, unit: &str) -> String {
    let digits = if v >= 10.0 {
        0
    } else if v >= 1.0 {
        1
    } else {
        3
    };
    format!("{v:.digits$} {unit}")
}

/// An amount of `mm`, in µm under 0.1 mm, else in mm: `25.3 µm`,
/// `1.130 mm`.
fn amount(mm: f64) -> String {
    if mm < 0.1 {
        format!("{:.1} µm", mm * 1000.0)
    } else {
        format!("{mm:.3} mm")
    }
}

/// The deviation simulated − `target` on `scale`: red below, white on it,
/// blue above, a gouge in its own colour; grey where there is no target.
fn deviation_raster(zmap: &ZMap, target: &[f64], scale: &DeviationScale) -> Raster {
    let (k, w, h) = picture_grid(zmap);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let c = j * zmap.nx + col * k;
            rgb.extend(if target[c] == f64::NEG_INFINITY {
                NO_TARGET
            } else {
                scale.colour(zmap.height_at(c) - target[c])
            });
        }
    }
    Raster { width: w, height: h, rgb }
}

/// The deviation as a panel of a figure, captioned `caption`.
pub fn deviation_panel(zmap: &ZMap, target: &[f64], scale: &DeviationScale, caption: &str) -> Panel {
    Panel {
        raster: deviation_raster(zmap, target, scale),
        extent: extent(zmap),
        axes: xy(),
        caption: caption.into(),
        overlays: vec![],
    }
}

/// The deviation picture, framed: titled `title`, `subtitle` under it, a
/// colour bar of the scale.
pub fn deviation_png(
    zmap: &ZMap,
    target: &[f64],
    scale: &DeviationScale,
    title: &str,
    subtitle: &str,
) -> Result<Vec<u8>, Error> {
    Figure {
        title: title.into(),
        subtitle: subtitle.into(),
        panels: vec![deviation_panel(zmap, target, scale, "")],
        stacked: false,
        bar: Some(scale.bar()),
        legend: vec![],
    }
    .png()
}

/// The simulated surface as triangles, one at a time: two per square of
/// four neighbouring cell centres, facing up, split as a height grid's
/// cells are.
pub fn surface_triangles(zmap: &ZMap) -> impl ExactSizeIterator<Item = Triangle> + '_ {
    let (cx, cy) = (zmap.nx.saturating_sub(1), zmap.ny.saturating_sub(1));
    let p = |i: usize, j: usize| {
        let [x, y] = zmap.centre(i, j);
        Vec3::new(x, y, zmap.height(i, j))
    };
    (0..2 * cx * cy).map(move |k| {
        let (i, j) = ((k / 2) % cx, k / 2 / cx);
        let (a, c) = (p(i, j), p(i + 1, j + 1));
        if k % 2 == 0 {
            Triangle::new(a, p(i + 1, j), c)
        } else {
            Triangle::new(a, c, p(i, j + 1))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use kezuri_cam::sim::{SimOptions, Stock};

    /// A 10 × 10 grid of 1 mm cells on a flat target at 0, cut to `dev`.
    fn grid(dev: impl Fn(usize) -> f64) -> (ZMap, Vec<f64>) {
        let stock = Stock { x0: 0.0, y0: 0.0, x1: 10.0, y1: 10.0, top: 1.0 };
        let mut z = ZMap::new(&stock, &SimOptions::new(1.0)).unwrap();
        for (k, h) in z.nm.iter_mut().enumerate() {
            *h = kezuri_cam::sim::to_nm(dev(k)).unwrap();
        }
        let target = vec![0.0; z.nm.len()];
        (z, target)
    }

    #[test]
    fn the_deviation_scale_is_the_99th_percentile_and_gouges_have_their_colour() {
        // 98 cells 2 µm above, one 4 µm above, one 0.5 mm above (an edge
        // left uncut): full colour at the 99th percentile, 4 µm, not 0.5 mm.
        let (z, target) = grid(|k| match k {
            0 => 0.5,
            1 => 0.004,
            _ => 0.002,
        });
        let scale = DeviationScale::new(&z, &target, None, GOUGE_MM);
        assert!((scale.mm - 0.004).abs() < 1e-12, "{}", scale.mm);
        let r = deviation_raster(&z, &target, &scale);
        // Row 0 of the picture is the grid's top row (+Y up): cell k is at
        // column k % 10, row 9 - k / 10.
        let pixel = |k: usize| {
            let i = 3 * ((9 - k / 10) * 10 + k % 10);
            [r.rgb[i], r.rgb[i + 1], r.rgb[i + 2]]
        };
        assert_eq!(pixel(1), ABOVE, "the 99th percentile in full colour");
        assert_eq!(pixel(0), OVER_LEFT, "beyond it its own colour: 0.5 mm left is not 4 µm");
        let bar = scale.bar();
        assert!(
            bar.swatches.iter().any(|(c, t)| *c == OVER_LEFT && t == "left over +4.0 µm: up to 0.500 mm"),
            "{:?}",
            bar.swatches
        );
        assert_eq!(pixel(5), [143, 163, 233], "half the scale, half way to blue");
        // A gouge deeper than 1 µm in its own colour; 0.5 µm below is red-ish.
        let (z, target) = grid(|k| match k {
            3 => -0.0015,
            4 => -0.0005,
            _ => 0.002,
        });
        let scale = DeviationScale::new(&z, &target, Some(0.001), GOUGE_MM);
        let r = deviation_raster(&z, &target, &scale);
        let i = 3 * (9 * 10 + 3);
        assert_eq!(r.rgb[i..i + 3], GOUGE);
        let i = 3 * (9 * 10 + 4);
        assert_eq!(r.rgb[i..i + 3], [253, 235, 235]);
        // On a larger scale a gouge's colour deepens with it: 2.5 µm below
        // on ±4 µm is half way from the limit's light magenta to full.
        let scale = DeviationScale::new(&z, &target, Some(0.004), GOUGE_MM);
        assert_eq!(scale.colour(-0.0025), [220, 80, 220]);
        assert_eq!(scale.colour(-0.001), BELOW);
        assert_eq!(scale.colour(-0.0010001), GOUGE_LIGHT);
        assert_eq!(scale.colour(-0.004), GOUGE);
        assert_eq!(scale.colour(-0.01), OVER_GOUGE, "deeper than the scale");
        assert_eq!(scale.bar().swatches.len(), 2, "no cell beyond ±4 µm here: nothing said of them");
        // The bar says the scale and its basis, in µm.
        let bar = DeviationScale::new(&z, &target, None, GOUGE_MM).bar();
        assert_eq!(bar.label, "simulated − target, µm");
        assert!(bar.notes[1].contains("99th percentile"), "{:?}", bar.notes);
    }

    #[test]
    fn a_steep_face_turned_from_the_light_keeps_its_tint_readable() {
        // A 10 × 10 mm block rising 3 mm per mm to the north-west: every
        // face turns from the light (the dome's far side, a pocket's wall).
        let (z, _) = grid(|k| 3.0 * ((k / 10) as f64 - (k % 10) as f64));
        let (lo, hi) = z.range();
        let r = height_raster(&z);
        for row in 0..10 {
            for col in 0..10 {
                let t = (z.height(col, 9 - row) - lo) / (hi - lo);
                let i = 3 * (row * 10 + col);
                for (c, full) in tint(t).into_iter().enumerate() {
                    let least = (0.55 * 255.0 * full).floor() as u8;
                    assert!(r.rgb[i + c] >= least, "cell {col},{row}: {:?} under 55 % of its tint", &r.rgb[i..i + 3]);
                }
            }
        }
        // Lit and flat faces stay lighter than those turned away.
        assert!(lit(0.0, 0.0) > 0.9 && lit(-1.0, 1.0) < lit(0.0, 0.0) && lit(1.0, -1.0) > lit(0.0, 0.0));
    }

    #[test]
    fn pictures_are_the_same_bytes_each_time() {
        let (z, target) = grid(|k| 0.001 * (k % 7) as f64 - 0.002);
        let scale = DeviationScale::new(&z, &target, None, GOUGE_MM);
        let a = deviation_png(&z, &target, &scale, "t.nc: ball:6", "against t.stl").unwrap();
        assert_eq!(a, deviation_png(&z, &target, &scale, "t.nc: ball:6", "against t.stl").unwrap());
        assert_eq!(height_png(&z, "t.nc").unwrap(), height_png(&z, "t.nc").unwrap());
        let img = image::load_from_memory(&a).unwrap();
        assert!(img.width() > 400 && img.height() > 300, "{} x {}", img.width(), img.height());
    }
}
