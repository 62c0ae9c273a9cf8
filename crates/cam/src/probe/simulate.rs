//! The readings a ball stylus would give on a model (`kezuri probe
//! simulate`), for trying the pipeline (level, export, mill) before a night
//! on the machine: each reading is where the stylus's tip (its lowest
//! point) stops when it is lowered onto the model at a grid point —
//! drop-cutter of the stylus on the model, the same convention as a real
//! capture — with the model set down out of level (a tilt) and noise.

use std::fmt::Write as _;

use super::data::{grid_header, num};
use super::{Grid, Order};
use crate::error::{Error, ErrorKind};
use crate::Cutter;

/// A capture to simulate. Lengths mm.
#[derive(Clone, Copy)]
pub struct Simulation<'a> {
    /// The model: where the stylus's tip stops lowered onto it at `(x, y)`
    /// (drop-cutter); `None` off it.
    pub model: &'a dyn Fn(f64, f64) -> Option<f64>,
    /// The model's `[min x, min y, max x, max y]`.
    pub model_box: [f64; 4],
    /// Its name, for the file's header and messages.
    pub name: &'a str,
    /// The stylus, for the file's header.
    pub stylus: Cutter,
    /// Points along X and Y.
    pub count: [usize; 2],
    /// Grid pitch.
    pub pitch: f64,
    /// The first point's X,Y; `None`: the grid centred on the model.
    pub origin: Option<[f64; 2]>,
    /// The capture order.
    pub order: Order,
    /// Slope of the model's base along X and Y (mm per mm), a plane through
    /// the grid's centre.
    pub tilt: [f64; 2],
    /// Uniform noise added to each reading, ± mm.
    pub noise: f64,
    /// Seed of the noise: the same seed, the same readings.
    pub seed: u64,
}

/// The simulated capture.
#[derive(Clone, Debug, PartialEq)]
pub struct Simulated {
    /// Where the points are.
    pub grid: Grid,
    /// The capture file: a header with the grid, then `No,Z` in capture
    /// order.
    pub text: String,
}

/// The readings of `s`; an error where the stylus would find no model
/// under a point.
pub fn simulate(s: &Simulation) -> Result<Simulated, Error> {
    let [nx, ny] = s.count;
    let [x0, y0, x1, y1] = s.model_box;
    let (width, depth) = ((nx - 1) as f64 * s.pitch, (ny - 1) as f64 * s.pitch);
    let origin = s.origin.unwrap_or([0.5 * (x0 + x1 - width), 0.5 * (y0 + y1 - depth)]);
    let grid = Grid { nx, ny, pitch: s.pitch, origin, order: s.order };
    let centre = [origin[0] + 0.5 * width, origin[1] + 0.5 * depth];
    let mut noise = Noise(s.seed);
    let mut text = format!(
        "# kezuri probe simulate\n{}\n# simulated: stylus {} on {}, tilt {},{} mm/mm, noise ±{} mm, seed {}\n\
         # z: the stylus tip's height (its lowest point), mm\nNo,Z\n",
        grid_header(&grid),
        s.stylus,
        s.name,
        num(s.tilt[0], 9),
        num(s.tilt[1], 9),
        num(s.noise, 6),
        s.seed,
    );
    for k in 0..grid.len() {
        let (i, j) = grid.node(k);
        let (x, y) = (grid.x(i), grid.y(j));
        let Some(z) = (s.model)(x, y) else {
            return Err(Error::new(
                ErrorKind::OffModel,
                format!(
                    "point {} at ({}, {}) is off the model ({}): the stylus would find nothing there",
                    k + 1,
                    num(x, 4),
                    num(y, 4),
                    s.name
                ),
            ));
        };
        let z = z + s.tilt[0] * (x - centre[0]) + s.tilt[1] * (y - centre[1]) + s.noise * noise.next();
        let _ = writeln!(text, "{},{}", k + 1, num(z, 4));
    }
    Ok(Simulated { grid, text })
}

/// Uniform numbers in [−1, 1) from a 64-bit linear congruential generator
/// (Knuth's MMIX constants): the same seed, the same readings.
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}
