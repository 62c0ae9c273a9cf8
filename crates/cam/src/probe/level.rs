//! Reference-plane correction: making the model's reference surface
//! parallel to the machine table.
//!
//! A wooden master model's flat part is warped and never quite parallel
//! to the table, so the heights are corrected against a **reference region**
//! — points that should lie in one horizontal plane: the four corners, the
//! whole border, two rows, two columns, or a mask. Candidates:
//!
//! - **plane**: the least-squares plane through the reference points is
//!   turned horizontal: `z' = z − b·(x − x̄) − c·(y − ȳ)`.
//! - **lines** (the copy-milling paper's): a least-squares line along each of two
//!   reference rows (or columns); between and beyond them the correction
//!   is the straight line from one to the other, row by row. This takes out
//!   a tilt *and* a twist (the paper's ネジレ), which no plane can.
//!   With the border as reference both pairs (first/last rows, first/last
//!   columns — the paper's ①③ and ②④) are candidates; with the corners
//!   the lines are the rows through the corner pairs (bilinear).
//!
//! Every candidate keeps the mean height of the reference points, so a
//! levelled reference lies at its own average height, not at zero (the
//! paper's corrected files keep their first value too).
//!
//! The paper's table gives, for the raw data and every candidate, the count,
//! max, min, mean and standard deviation of the reference points; the
//! candidate with the smallest standard deviation is the one to keep
//! ([`Method::Auto`]). The standard deviation here is the population one
//! (divided by n). The paper's own table is inconsistent — its "変換 1" row
//! has a mean (19.33) above its max (19.007) — so it is a layout to follow,
//! not numbers to reproduce; its last column (変換係数, "conversion
//! coefficient") is not explained there and is left out.

use std::fmt::Write as _;

use super::data::{num, Format};
use super::{Grid, ProbeGrid};
use crate::error::{Error, ErrorKind};

/// The points that should lie in one horizontal plane.
#[derive(Clone, Debug, PartialEq)]
pub enum Reference {
    /// The four corner points.
    Corners,
    /// Every point on the outer border.
    Border,
    /// Two rows (along X), numbered from 1 (row 1 is the first measured).
    Rows(usize, usize),
    /// Two columns (along Y), numbered from 1.
    Cols(usize, usize),
    /// Any points: `mask[j·nx + i]`.
    Mask(Vec<bool>),
}

impl std::str::FromStr for Reference {
    type Err = String;

    /// `corners`, `border`, `rows:A,B`, `cols:A,B` (a mask comes from a file).
    fn from_str(s: &str) -> Result<Reference, String> {
        let pair = |v: &str| -> Result<(usize, usize), String> {
            let p: Vec<usize> =
                v.split(',').map(|t| t.trim().parse::<usize>()).collect::<Result<_, _>>().map_err(|_| {
                    format!("reference '{s}': expected two whole numbers A,B (rows and columns count from 1)")
                })?;
            match p[..] {
                [a, b] => Ok((a, b)),
                _ => Err(format!("reference '{s}': expected two numbers A,B")),
            }
        };
        match s.trim() {
            "corners" => Ok(Reference::Corners),
            "border" => Ok(Reference::Border),
            t if t.starts_with("rows:") => pair(&t[5..]).map(|(a, b)| Reference::Rows(a, b)),
            t if t.starts_with("cols:") => pair(&t[5..]).map(|(a, b)| Reference::Cols(a, b)),
            t => Err(format!("reference '{t}': expected corners, border, rows:A,B, cols:A,B or mask:FILE")),
        }
    }
}

impl Reference {
    /// The mask `text` gives an `nx × ny` grid: one line per row, row 1 (the
    /// first measured) first, a `0` or `1` per point (spaces and commas
    /// between them are ignored; blank lines and `#` lines are skipped).
    /// Errors name the line (from 1) and the column.
    pub fn mask(text: &str, nx: usize, ny: usize) -> Result<Reference, Error> {
        let fail = |line: Option<usize>, column: Option<usize>, message: String| {
            Err(Error::at(ErrorKind::Level, line, column, message))
        };
        let mut mask = Vec::with_capacity(nx * ny);
        let mut rows = 0;
        for (n, line) in text.lines().enumerate() {
            let t = line.trim();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            let cells: Vec<(usize, char)> =
                line.chars().enumerate().filter(|(_, c)| !(c.is_whitespace() || *c == ',')).collect();
            if let Some((column, c)) = cells.iter().find(|(_, c)| !matches!(c, '0' | '1')) {
                return fail(Some(n + 1), Some(column + 1), format!("'{c}' is not 0 or 1"));
            }
            if cells.len() != nx {
                return fail(Some(n + 1), None, format!("{} points, a row of the grid has {nx}", cells.len()));
            }
            rows += 1;
            if rows > ny {
                return fail(Some(n + 1), None, format!("more rows than the grid's {ny}"));
            }
            mask.extend(cells.iter().map(|&(_, c)| c == '1'));
        }
        if rows != ny {
            return fail(None, None, format!("{rows} rows, the grid has {ny}"));
        }
        Ok(Reference::Mask(mask))
    }
}

/// Which correction to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The least-squares plane.
    Plane,
    /// The copy-milling paper's least-squares lines (the better pair, where two).
    Lines,
    /// The candidate with the smallest standard deviation.
    Auto,
}

/// Count, max, min, mean and standard deviation of some heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Points.
    pub count: usize,
    /// Highest.
    pub max: f64,
    /// Lowest.
    pub min: f64,
    /// Mean.
    pub mean: f64,
    /// Population standard deviation.
    pub std: f64,
}

impl Stats {
    /// The statistics of `z` where `mask` is set.
    pub fn of(z: &[f64], mask: &[bool]) -> Stats {
        let v: Vec<f64> = z.iter().zip(mask).filter(|(_, &m)| m).map(|(&z, _)| z).collect();
        let n = v.len().max(1) as f64;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n;
        Stats {
            count: v.len(),
            max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            min: v.iter().copied().fold(f64::INFINITY, f64::min),
            mean,
            std: var.sqrt(),
        }
    }
}

/// One corrected version of the data.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// `plane`, `lines rows A,B` or `lines cols A,B`.
    pub name: String,
    /// `true` for a plane, `false` for lines.
    pub plane: bool,
    /// The corrected heights (by node, as [`ProbeGrid::z`]).
    pub z: Vec<f64>,
    /// Statistics of the reference points after the correction.
    pub stats: Stats,
}

/// Every candidate and the one the method keeps.
#[derive(Clone, Debug, PartialEq)]
pub struct Levelling {
    /// The reference points (by node).
    pub mask: Vec<bool>,
    /// Statistics of the raw reference points.
    pub raw: Stats,
    /// The candidates, plane first.
    pub candidates: Vec<Candidate>,
    /// Index of the kept candidate.
    pub chosen: usize,
}

impl Levelling {
    /// The kept candidate.
    pub fn kept(&self) -> &Candidate {
        &self.candidates[self.chosen]
    }

    /// The format to write the levelled data in, for data `read` in that
    /// format: the same, and a capture file's header gains a `# levelled`
    /// line with the kept candidate, the `reference` region and the
    /// standard deviation of its points before and after.
    pub fn written_as(&self, read: &Format, reference: &str) -> Format {
        let Format::Capture { header } = read else { return read.clone() };
        let kept = self.kept();
        let mut header = header.clone();
        header.push(format!(
            "# levelled: {} against {reference}, reference std {} -> {} mm",
            kept.name,
            num(self.raw.std, 6),
            num(kept.stats.std, 6)
        ));
        Format::Capture { header }
    }

    /// The copy-milling paper's table: count, max, min, mean, std for the raw data and
    /// every candidate, the kept one marked.
    pub fn table(&self) -> String {
        let mut t = String::new();
        let _ = writeln!(t, "{:<20} {:>6} {:>12} {:>12} {:>12} {:>10}", "data", "count", "max", "min", "mean", "std");
        let mut row = |name: &str, s: &Stats, mark: &str| {
            let _ = writeln!(
                t,
                "{:<20} {:>6} {:>12.6} {:>12.6} {:>12.6} {:>10.6}{mark}",
                name, s.count, s.max, s.min, s.mean, s.std
            );
        };
        row("raw", &self.raw, "");
        for (k, c) in self.candidates.iter().enumerate() {
            row(&c.name, &c.stats, if k == self.chosen { "  <- kept" } else { "" });
        }
        t
    }
}

/// The reference points of `reference` on `grid` (errors for rows or
/// columns outside it, a mask of the wrong size or an empty one).
pub fn reference_mask(grid: &Grid, reference: &Reference) -> Result<Vec<bool>, Error> {
    let (nx, ny) = (grid.nx, grid.ny);
    let mut mask = vec![false; nx * ny];
    let check = |a: usize, b: usize, n: usize, (one, what): (&str, &str)| {
        for v in [a, b] {
            if v == 0 || v > n {
                return Err(Error::new(ErrorKind::Level, format!("{one} {v} is outside the grid's {what} 1..{n}")));
            }
        }
        if a == b {
            return Err(Error::new(ErrorKind::Level, format!("{what} {a},{b}: two different {what} are needed")));
        }
        Ok(())
    };
    match reference {
        Reference::Corners => {
            for (i, j) in [(0, 0), (nx - 1, 0), (0, ny - 1), (nx - 1, ny - 1)] {
                mask[j * nx + i] = true;
            }
        }
        Reference::Border => {
            for j in 0..ny {
                for i in 0..nx {
                    mask[j * nx + i] = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
                }
            }
        }
        Reference::Rows(a, b) => {
            check(*a, *b, ny, ("row", "rows"))?;
            for j in [a - 1, b - 1] {
                mask[j * nx..(j + 1) * nx].iter_mut().for_each(|m| *m = true);
            }
        }
        Reference::Cols(a, b) => {
            check(*a, *b, nx, ("column", "columns"))?;
            for j in 0..ny {
                mask[j * nx + a - 1] = true;
                mask[j * nx + b - 1] = true;
            }
        }
        Reference::Mask(m) => {
            if m.len() != nx * ny {
                return Err(Error::new(
                    ErrorKind::Level,
                    format!("the mask has {} points, the grid {nx} × {ny} = {}", m.len(), nx * ny),
                ));
            }
            mask.clone_from(m);
        }
    }
    if mask.iter().filter(|&&m| m).count() < 3 {
        return Err(Error::new(ErrorKind::Level, "the reference region has fewer than 3 points"));
    }
    Ok(mask)
}

/// Levels `data` against `reference`: every candidate, and the one
/// `method` keeps.
pub fn level(data: &ProbeGrid, reference: &Reference, method: Method) -> Result<Levelling, Error> {
    let g = &data.grid;
    let mask = reference_mask(g, reference)?;
    let raw = Stats::of(&data.z, &mask);
    let mut candidates = Vec::new();
    match plane(data, &mask) {
        Ok(z) => candidates.push(Candidate { name: "plane".into(), plane: true, stats: Stats::of(&z, &mask), z }),
        Err(e) if method == Method::Plane => return Err(e),
        Err(_) => {}
    }
    let pairs: Vec<(bool, usize, usize)> = match reference {
        Reference::Corners => vec![(true, 0, g.ny - 1)],
        Reference::Border => vec![(true, 0, g.ny - 1), (false, 0, g.nx - 1)],
        Reference::Rows(a, b) => vec![(true, a - 1, b - 1)],
        Reference::Cols(a, b) => vec![(false, a - 1, b - 1)],
        Reference::Mask(_) => vec![],
    };
    if pairs.is_empty() && method == Method::Lines {
        return Err(Error::new(
            ErrorKind::Level,
            "--method lines needs two rows or columns: corners, border, rows:A,B or cols:A,B",
        ));
    }
    for (rows, a, b) in pairs {
        let z = lines(data, &mask, rows, a, b)?;
        let name = format!("lines {} {},{}", if rows { "rows" } else { "cols" }, a + 1, b + 1);
        candidates.push(Candidate { name, plane: false, stats: Stats::of(&z, &mask), z });
    }
    let best = |only: Option<bool>| {
        candidates
            .iter()
            .enumerate()
            .filter(|(_, c)| only.is_none_or(|p| c.plane == p))
            .min_by(|a, b| a.1.stats.std.total_cmp(&b.1.stats.std))
            .map(|(k, _)| k)
    };
    let chosen = match method {
        Method::Plane => best(Some(true)),
        Method::Lines => best(Some(false)),
        Method::Auto => best(None),
    }
    .ok_or_else(|| Error::new(ErrorKind::Level, "no correction could be made from the reference region"))?;
    Ok(Levelling { mask, raw, candidates, chosen })
}

/// The plane candidate.
fn plane(data: &ProbeGrid, mask: &[bool]) -> Result<Vec<f64>, Error> {
    let g = &data.grid;
    let pts: Vec<[f64; 3]> =
        (0..g.len()).filter(|&k| mask[k]).map(|k| [g.x(k % g.nx), g.y(k / g.nx), data.z[k]]).collect();
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p[0]).sum::<f64>() / n, pts.iter().map(|p| p[1]).sum::<f64>() / n);
    let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in &pts {
        let (dx, dy) = (p[0] - mx, p[1] - my);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
        sxz += dx * p[2];
        syz += dy * p[2];
    }
    let det = sxx * syy - sxy * sxy;
    if det.abs() <= 1e-12 * (sxx * syy).max(1e-300) {
        return Err(Error::new(
            ErrorKind::Level,
            "the reference points lie on one line: they do not determine a plane",
        ));
    }
    let b = (sxz * syy - syz * sxy) / det;
    let c = (syz * sxx - sxz * sxy) / det;
    Ok((0..g.len()).map(|k| data.z[k] - b * (g.x(k % g.nx) - mx) - c * (g.y(k / g.nx) - my)).collect())
}

/// The lines candidate: least-squares lines along rows (or columns) `a`
/// and `b` (from 0), through their reference points; the correction at
/// every point is the straight line between the two, across.
fn lines(data: &ProbeGrid, mask: &[bool], rows: bool, a: usize, b: usize) -> Result<Vec<f64>, Error> {
    let g = &data.grid;
    // In a frame where the lines run along u and lie at v = a, b.
    let (nu, nv) = if rows { (g.nx, g.ny) } else { (g.ny, g.nx) };
    let k = |u: usize, v: usize| if rows { v * g.nx + u } else { u * g.nx + v };
    let fit = |v: usize| -> Result<(f64, f64), Error> {
        let pts: Vec<(f64, f64)> = (0..nu).filter(|&u| mask[k(u, v)]).map(|u| (u as f64, data.z[k(u, v)])).collect();
        let n = pts.len() as f64;
        if pts.len() < 2 {
            return Err(Error::new(
                ErrorKind::Level,
                format!(
                    "{} {} has fewer than 2 reference points: no line through it",
                    if rows { "row" } else { "column" },
                    v + 1
                ),
            ));
        }
        let mu = pts.iter().map(|p| p.0).sum::<f64>() / n;
        let mz = pts.iter().map(|p| p.1).sum::<f64>() / n;
        let suu: f64 = pts.iter().map(|p| (p.0 - mu).powi(2)).sum();
        let suz: f64 = pts.iter().map(|p| (p.0 - mu) * p.1).sum();
        let slope = suz / suu;
        Ok((mz - slope * mu, slope))
    };
    let (la, lb) = (fit(a)?, fit(b)?);
    let line = |l: (f64, f64), u: usize| l.0 + l.1 * u as f64;
    let mut correction = vec![0.0; g.len()];
    for v in 0..nv {
        let t = (v as f64 - a as f64) / (b as f64 - a as f64);
        for u in 0..nu {
            correction[k(u, v)] = line(la, u) + t * (line(lb, u) - line(la, u));
        }
    }
    let n = mask.iter().filter(|&&m| m).count() as f64;
    // Adding back the correction's mean over the reference keeps the
    // reference's mean height.
    let mean_corr = (0..g.len()).filter(|&i| mask[i]).map(|i| correction[i]).sum::<f64>() / n;
    Ok((0..g.len()).map(|i| data.z[i] - correction[i] + mean_corr).collect())
}
