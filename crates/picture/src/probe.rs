//! A probed grid's picture (`kezuri probe export --png`): hill-shaded and
//! tinted by height, framed with its title, axes in mm and a colour bar
//! of Z.

use kezuri_cam::probe::export::shade;
use kezuri_cam::probe::ProbeGrid;

use crate::figure::{ColourBar, Figure, Panel, Raster};
use crate::Error;

/// The grid hill-shaded and tinted by height (`scale` pixels per pitch),
/// framed and titled with the data's `name`, as PNG.
pub fn probed(grid: &ProbeGrid, scale: usize, name: &str) -> Result<Vec<u8>, Error> {
    let (w, h, rgb) = shade(grid, scale);
    let g = &grid.grid;
    let px = g.pitch / scale.max(1) as f64;
    let [x0, y0] = g.origin;
    let (lo, hi) = grid.range();
    // The tint of the lowest and highest point, fully lit (as `shade`'s).
    let tint = |t: f64| [255.0 * (0.55 + 0.45 * t), 255.0 * 0.8, 255.0 * (1.0 - 0.45 * t)].map(|c| c.round() as u8);
    Figure {
        title: format!("{name}: probed surface"),
        subtitle: format!("{} × {} points at {} mm, +Y up", g.nx, g.ny, g.pitch),
        panels: vec![Panel {
            raster: Raster { width: w, height: h, rgb },
            extent: [x0 - px / 2.0, x0 + (w as f64 - 0.5) * px, y0 - px / 2.0, y0 + (h as f64 - 0.5) * px],
            axes: ["X, mm".into(), "Y, mm".into()],
            caption: String::new(),
            overlays: vec![],
        }],
        stacked: false,
        bar: Some(ColourBar {
            stops: vec![(lo, tint(0.0)), (hi.max(lo + 1e-9), tint(1.0))],
            label: "Z, mm".into(),
            notes: vec!["shaded as lit from the upper left".into()],
            swatches: vec![],
        }),
        legend: vec![],
    }
    .png()
}

#[cfg(test)]
mod tests {
    use kezuri_cam::probe::export::shade;
    use kezuri_cam::probe::{Grid, Order, ProbeGrid};

    #[test]
    fn a_steep_side_of_a_probed_pocket_is_not_drawn_black() {
        // A mould's side rising 2 mm per mm to the north-west (the far side
        // of the plum pocket): turned from the light, still 60 % of its tint.
        let grid = Grid { nx: 8, ny: 8, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag };
        let z = (0..64).map(|k| 2.0 * ((k / 8) as f64 - (k % 8) as f64)).collect();
        let (w, h, rgb) = shade(&ProbeGrid { grid, z }, 1);
        assert_eq!((w, h), (8, 8));
        // The green channel's tint is 0.8 at every height.
        let least = (0.55 * 255.0 * 0.8) as u8;
        for (k, px) in rgb.chunks(3).enumerate() {
            assert!(px[1] >= least, "pixel {k}: {px:?} darker than 55 % of its tint");
        }
    }
}
