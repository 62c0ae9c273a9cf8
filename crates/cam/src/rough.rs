//! Roughing in levels: raster passes at depths `step_down` apart from the
//! stock top, each following the surface where the surface (plus an
//! allowance) is above its level and flat at the level elsewhere, and
//! cutting only where the level before left material.
//!
//! With the CL function `cl` of the roughing cutter, level `k` cuts at
//! `max(cl + allowance, z_k)`, `z_k = max(top − k·step_down, floor)`, over
//! the points where that is below `z_{k−1}` (the level above cut down to
//! `max(cl + allowance, z_{k−1})`: where `cl + allowance ≥ z_{k−1}` this
//! level has nothing to remove). So no pass takes a cut deeper than
//! `step_down`, and none comes closer to the surface than `allowance`
//! (within the raster's `gouge` band). Each level is a [`raster`] with its
//! own retracts between pieces; levels follow each other from the safe
//! height.

use kezuri_geom::Toolpath;

use crate::error::{Error, ErrorKind};
use crate::mill::{nothing_to_cut, raster, ClFn, Progress, RasterOptions, Region};

/// What [`levels`] needs besides the raster's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levels {
    /// The stock top, mm.
    pub top: f64,
    /// Depth of each level, mm (> 0).
    pub step_down: f64,
    /// Material left on the surface for finishing, mm (≥ 0).
    pub allowance: f64,
}

/// Most levels.
const MAX_LEVELS: usize = 10_000;

/// The roughing toolpath (module docs); `on_row` as in [`raster`], level
/// after level. The levels go down until one finds nothing to cut (every
/// deeper one then has nothing either).
pub fn levels(cl: &ClFn, region: Region, o: &RasterOptions, l: Levels, on_row: &Progress) -> Result<Toolpath, Error> {
    if !(l.step_down.is_finite() && l.step_down > 0.0) {
        return Err(Error::new(
            ErrorKind::Option,
            format!("the step-down must be a positive number, got {}", l.step_down),
        ));
    }
    if !(l.allowance.is_finite() && l.allowance >= 0.0) {
        return Err(Error::new(
            ErrorKind::Option,
            format!("the allowance must be zero or positive, got {}", l.allowance),
        ));
    }
    if !l.top.is_finite() {
        return Err(Error::new(ErrorKind::Option, format!("the stock top must be a finite height, got {}", l.top)));
    }
    let mut path = Toolpath::default();
    let mut k = 1;
    loop {
        if k > MAX_LEVELS {
            return Err(Error::new(
                ErrorKind::Option,
                format!("more than {MAX_LEVELS} levels of {} mm: raise the step-down", l.step_down),
            ));
        }
        let (above, level) = (l.top - (k - 1) as f64 * l.step_down, l.top - k as f64 * l.step_down);
        let cut = |x: f64, y: f64| {
            let z = (cl(x, y)? + l.allowance).max(level);
            (z < above - 1e-9).then_some(z)
        };
        match raster(&cut, region, o, None, on_row) {
            Ok(pass) => path.moves.extend(pass.moves),
            Err(e) if e.kind == ErrorKind::NothingToCut => break,
            Err(e) => return Err(e),
        }
        k += 1;
    }
    if path.moves.is_empty() {
        return Err(nothing_to_cut());
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mill::{Direction, Pattern};

    #[test]
    fn levels_step_down_and_keep_the_allowance() {
        // A bowl 5 mm deep: z = −5 + r²/20 up to the top at r = 10.
        let bowl = |x: f64, y: f64| Some((-5.0 + (x * x + y * y) / 20.0).min(0.0));
        let o = RasterOptions {
            direction: Direction::X,
            pattern: Pattern::ZigZag,
            stepover: 1.0,
            step: 0.5,
            tolerance: 0.01,
            gouge: 0.001,
            quantum: 0.0,
            safe_z: 5.0,
            feed: 1000.0,
            plunge_feed: 200.0,
            speed: 10000.0,
            tool: 1,
        };
        let region = Region { x0: -12.0, y0: -12.0, x1: 12.0, y1: 12.0 };
        let l = Levels { top: 0.0, step_down: 2.0, allowance: 0.5 };
        let path = levels(&bowl, region, &o, l, &|_, _| {}).unwrap();
        let cuts: Vec<_> = path.moves.iter().filter(|m| !m.is_rapid()).collect();
        let lowest = cuts.iter().map(|m| m.end.z).fold(f64::INFINITY, f64::min);
        // Levels at −2, −4 and the allowance above the bottom at −4.5.
        assert!((lowest - -4.5).abs() < 1e-9, "{lowest}");
        let mut depths: Vec<i64> = cuts.iter().map(|m| (m.end.z * 1000.0).round() as i64).collect();
        depths.sort();
        depths.dedup();
        assert!(depths.contains(&-2000) && depths.contains(&-4000), "{depths:?}");
        for m in &cuts {
            // Never closer to the bowl than the allowance (less the band).
            let surface = bowl(m.end.x, m.end.y).unwrap();
            assert!(m.end.z >= surface + 0.5 - 0.0011, "{:?} over {surface}", m.end);
            // The plunges come from the safe height or the level above.
            assert!(m.end.z >= -4.5 - 1e-9);
        }
        let e = |l: Levels| levels(&bowl, region, &o, l, &|_, _| {}).unwrap_err().to_string();
        assert!(e(Levels { step_down: 0.0, ..l }).contains("step-down"));
        assert!(e(Levels { allowance: -1.0, ..l }).contains("allowance"));
    }
}
