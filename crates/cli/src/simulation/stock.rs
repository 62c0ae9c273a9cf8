//! `sim --stock`: a box, an upright cylinder or a solid's top surface (STL),
//! as the grid the simulation starts from.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use kezuri_cam::sim::{Cylinder, Grid, SimOptions, Start, Stock, ZMap};
use serde_json::{json, Value};

/// What `--stock` says.
#[derive(Clone, Debug, PartialEq)]
pub enum StockSpec {
    /// `X0,Y0,X1,Y1,ZTOP`.
    Box(Stock),
    /// `cyl:D,H` (axis on X0 Y0, top at Z0) or `cyl:D,H,X,Y,ZTOP`.
    Cylinder(Cylinder),
    /// An STL (or height grid) whose top surface is the stock.
    Solid(PathBuf),
}

fn numbers(text: &str, what: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("--stock '{text}': expected {what}"))
}

/// Reads `--stock`.
pub fn parse(text: &str) -> Result<StockSpec> {
    if let Some(rest) = text.strip_prefix("cyl:") {
        let what = "cyl:D,H or cyl:D,H,X,Y,ZTOP (diameter, height, axis X Y, top Z)";
        let v = numbers(rest, what)?;
        let (x, y, top) = match v.len() {
            2 => (0.0, 0.0, 0.0),
            5 => (v[2], v[3], v[4]),
            n => bail!("--stock '{text}': expected {what}, got {n} numbers"),
        };
        if !(v[0] > 0.0 && v[1] > 0.0) {
            bail!("--stock '{text}': the diameter and the height must be positive");
        }
        return Ok(StockSpec::Cylinder(Cylinder { x, y, diameter: v[0], height: v[1], top }));
    }
    let is_file =
        Path::new(text).extension().is_some_and(|e| e.eq_ignore_ascii_case("stl")) || Path::new(text).is_file();
    if is_file {
        return Ok(StockSpec::Solid(PathBuf::from(text)));
    }
    let box_of = "five numbers X0,Y0,X1,Y1,ZTOP, cyl:D,H or an STL file";
    let v = numbers(text, box_of)?;
    if v.len() != 5 {
        bail!("--stock '{text}': expected {box_of}, got {} numbers", v.len());
    }
    if !(v[2] > v[0] && v[3] > v[1]) {
        bail!("--stock '{text}': need X0 < X1 and Y0 < Y1");
    }
    Ok(StockSpec::Box(Stock { x0: v[0], y0: v[1], x1: v[2], y1: v[3], top: v[4] }))
}

impl StockSpec {
    /// A solid stock's triangles (none for a box or a cylinder), read once
    /// for all the tiles of its grid.
    pub fn solid(&self, units: Option<crate::surface::Units>) -> Result<Option<Vec<[[f64; 3]; 3]>>> {
        match self {
            StockSpec::Solid(file) => Ok(Some(crate::surface::read_surface(file, units)?.triangles())),
            _ => Ok(None),
        }
    }

    /// What the grid and its tiles start from; `solid` from [`StockSpec::solid`].
    pub fn start<'a>(&self, solid: Option<&'a [[[f64; 3]; 3]]>) -> Start<'a> {
        match (self, solid) {
            (StockSpec::Box(s), _) => Start::Box(*s),
            (StockSpec::Cylinder(c), _) => Start::Cylinder(*c),
            (StockSpec::Solid(_), t) => Start::Solid(t.unwrap_or(&[])),
        }
    }

    /// The grid the simulation starts from.
    pub fn grid(&self, options: &SimOptions, units: Option<crate::surface::Units>) -> Result<ZMap> {
        Ok(match self {
            StockSpec::Box(s) => ZMap::new(s, options)?,
            StockSpec::Cylinder(c) => ZMap::cylinder(c, options)?,
            StockSpec::Solid(file) => {
                let triangles = crate::surface::read_surface(file, units)?.triangles();
                ZMap::top_of(&triangles, options).with_context(|| format!("--stock {}", file.display()))?
            }
        })
    }

    /// The `stock` of `sim --json`: the box as `x0 y0 x1 y1 top`; a
    /// cylinder or a solid adds what it is to its grid's box and its
    /// highest point `top` (before cutting).
    pub fn json(&self, grid: &Grid, top: f64) -> Value {
        let (x1, y1) = (grid.x0 + grid.nx as f64 * grid.res, grid.y0 + grid.ny as f64 * grid.res);
        let mut v = json!({"x0": grid.x0, "y0": grid.y0, "x1": x1, "y1": y1, "top": top});
        match self {
            StockSpec::Box(s) => v = json!({"x0": s.x0, "y0": s.y0, "x1": s.x1, "y1": s.y1, "top": s.top}),
            StockSpec::Cylinder(c) => {
                v["cylinder"] = json!({"x": c.x, "y": c.y, "diameter": c.diameter, "height": c.height})
            }
            StockSpec::Solid(file) => v["solid"] = json!(file.display().to_string()),
        }
        v
    }

    /// How the text report names it.
    pub fn describe(&self, grid: &Grid) -> String {
        let (x1, y1) = (grid.x0 + grid.nx as f64 * grid.res, grid.y0 + grid.ny as f64 * grid.res);
        match self {
            StockSpec::Box(s) => format!("X {} … {}, Y {} … {}, top {}", s.x0, s.x1, s.y0, s.y1, s.top),
            StockSpec::Cylinder(c) => {
                format!("a cylinder Ø{} × {} on X {} Y {}, top {}", c.diameter, c.height, c.x, c.y, c.top)
            }
            StockSpec::Solid(file) => {
                format!("the top of {} over X {:.3} … {x1:.3}, Y {:.3} … {y1:.3}", file.display(), grid.x0, grid.y0)
            }
        }
    }
}
