//! Probe data files, read and written back in the same format.
//!
//! - **Capture file** (`kezuri probe capture`): `#` lines are the header,
//!   one of them `# grid nx=85 ny=105 pitch=1 origin=0,0 pattern=zigzag`;
//!   the others (how a reading becomes the tip Z, times, …) are kept as they
//!   are. Then `No,Z` and one `No,Z` record per point, `No` from 1 in
//!   capture order, each ending with a line feed: a last record without
//!   one was cut off by a crash or a power loss while it was written (it
//!   may read as another number: `15,-5` of `15,-50.63`) and is refused.
//! - **Bare `No,Z`** (the copy-milling paper's files): the same records without a
//!   header; the grid comes from the caller ([`Hint`]). A record `No 0` is
//!   ignored (the paper's files begin with `0,0`) and written back.
//! - **CSV** `x,y,z` (an optional header line of names, then one point per
//!   line) and **LinuxCNC probe logs** (`x y z …` per line, whitespace
//!   between, further numbers ignored): the points themselves, which must
//!   lie on a regular grid of square cells, in any order.
//!
//! Every error names the line it is on (from 1) and, for a bad field, the
//! column (in characters, from 1), or says what does not add up (a point
//! count that does not match the grid). A UTF-8 byte-order mark (what
//! spreadsheet programs put first in a CSV file) is ignored.

use std::fmt::Write as _;

use kezuri_geom::limits;

use super::{Grid, Order, ProbeGrid};
use crate::error::{Error, ErrorKind};

/// What the caller knows of the grid (the command line's `--count`,
/// `--pitch`, `--pattern`, `--origin`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hint {
    /// `[nx, ny]`.
    pub count: Option<[usize; 2]>,
    /// Pitch, mm.
    pub pitch: Option<f64>,
    /// The first point, mm.
    pub origin: Option<[f64; 2]>,
    /// Capture order.
    pub order: Option<Order>,
}

/// The format a file was in, with what writing it back needs.
#[derive(Clone, Debug, PartialEq)]
pub enum Format {
    /// A capture file; its header lines (with their `#`).
    Capture {
        /// The header lines, verbatim.
        header: Vec<String>,
    },
    /// The copy-milling paper's bare `No,Z` records.
    Bare {
        /// The file began with the record `0,0`.
        zero_record: bool,
        /// The file had a `No,Z` title line.
        title: bool,
    },
    /// `x,y,z` CSV.
    Csv,
    /// LinuxCNC probe log, `x y z` per line.
    LinuxCnc,
}

impl Format {
    /// A short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            Format::Capture { .. } => "capture",
            Format::Bare { .. } => "No,Z",
            Format::Csv => "x,y,z CSV",
            Format::LinuxCnc => "LinuxCNC probe log",
        }
    }
}

/// A data file read.
#[derive(Clone, Debug, PartialEq)]
pub struct Data {
    /// The heights on their grid.
    pub grid: ProbeGrid,
    /// The format it came in.
    pub format: Format,
}

fn err<T>(line: Option<usize>, message: impl Into<String>) -> Result<T, Error> {
    Err(Error::at(ErrorKind::Data, line, None, message))
}

/// Blank lines, comments (`#`, `;`, `(`) and lines of nothing but control
/// characters and `%` (the DC2/DC4 and tape marks a control may send around
/// its DPRNT output, a DOS end-of-file mark).
fn is_comment(line: &str) -> bool {
    let t = line.trim_start_matches(|c: char| c.is_whitespace() || c.is_control());
    t.starts_with('#') || t.starts_with(';') || t.starts_with('(') || t.chars().all(|c| c == '%' || c.is_control())
}

/// A field of a line and the column (in characters, from 1) it starts at.
#[derive(Clone, Copy)]
struct Field<'a> {
    text: &'a str,
    column: usize,
}

/// The fields of a line, separated by commas, white space and control
/// characters.
fn fields(line: &str) -> Vec<Field<'_>> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, (at, c)) in line.char_indices().chain(std::iter::once((line.len(), ','))).enumerate() {
        let separator = c == ',' || c.is_whitespace() || c.is_control();
        match (start, separator) {
            (None, false) => start = Some((at, k + 1)),
            (Some((from, column)), true) => {
                out.push(Field { text: &line[from..at], column });
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The texts of `fields`.
fn texts<'a>(fields: &[Field<'a>]) -> Vec<&'a str> {
    fields.iter().map(|f| f.text).collect()
}

/// A coordinate (every number of a data file is in mm: within ±1000000),
/// or an error naming the line and column.
fn number(field: Field<'_>, n: usize) -> Result<f64, Error> {
    let message = match field.text.parse::<f64>() {
        Ok(v) => match limits::coordinate(v, &format!("'{}'", field.text)) {
            Ok(v) => return Ok(v),
            Err(e) => e,
        },
        Err(_) => format!("'{}' is not a number", field.text),
    };
    Err(Error::at(ErrorKind::Data, Some(n), Some(field.column), message))
}

/// Reads a data file of any of the formats (module docs).
pub fn read(text: &str, hint: &Hint) -> Result<Data, Error> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<&str> = text.lines().collect();
    let grid_line = lines.iter().position(|l| {
        let t = l.trim_start();
        t.starts_with('#') && t[1..].trim_start().to_ascii_lowercase().starts_with("grid")
    });
    if let Some(g) = grid_line {
        let grid = header_grid(lines[g], g + 1, hint)?;
        let header: Vec<String> =
            lines.iter().filter(|l| l.trim_start().starts_with('#')).map(|l| l.to_string()).collect();
        if let Some(last) = lines.last().filter(|l| !text.ends_with('\n') && !is_comment(l)) {
            return err(
                Some(lines.len()),
                format!(
                    "the last record '{}' has no end of line: the capture was cut off while writing it \
                     (`kezuri probe capture … --resume` drops it and measures that point again)",
                    last.trim()
                ),
            );
        }
        let (z, _, _) = records(&lines, &grid)?;
        return Ok(Data { grid: ProbeGrid { grid, z }, format: Format::Capture { header } });
    }
    let Some((first, line)) = lines.iter().enumerate().find(|(_, l)| !is_comment(l)) else {
        return err(None, "no data: the file has no points");
    };
    let f = texts(&fields(line));
    let numeric = f.first().is_some_and(|v| v.parse::<f64>().is_ok());
    let names: String = f.iter().map(|s| s.to_ascii_lowercase()).collect::<Vec<_>>().join(",");
    let bare = if numeric { f.len() == 2 } else { names == "no,z" };
    if bare {
        let Some([nx, ny]) = hint.count else {
            return err(None, "a bare No,Z file does not say its grid: give --count NX,NY and --pitch P");
        };
        let Some(pitch) = hint.pitch else {
            return err(None, "a bare No,Z file does not say its pitch: give --pitch P");
        };
        let grid = checked_grid(nx, ny, pitch, hint.origin.unwrap_or([0.0, 0.0]), hint.order.unwrap_or_default())?;
        let (z, zero_record, title) = records(&lines, &grid)?;
        return Ok(Data { grid: ProbeGrid { grid, z }, format: Format::Bare { zero_record, title } });
    }
    let xyz_title = f.len() >= 3 && f[..3].iter().zip(["x", "y", "z"]).all(|(a, b)| a.eq_ignore_ascii_case(b));
    if !numeric && !xyz_title {
        return err(
            Some(first + 1),
            format!("'{}': expected a `# grid …` header, `No,Z`, `x,y,z` or numbers", line.trim()),
        );
    }
    let csv = if numeric { line.contains(',') } else { true };
    let mut points = Vec::new();
    for (n, line) in lines.iter().enumerate().skip(if numeric { first } else { first + 1 }) {
        if is_comment(line) {
            continue;
        }
        let f = fields(line);
        if csv && f.len() != 3 {
            return err(Some(n + 1), format!("expected three numbers x,y,z, got '{}'", line.trim()));
        }
        if f.len() < 3 {
            return err(Some(n + 1), format!("expected numbers x y z, got '{}'", line.trim()));
        }
        points.push(([number(f[0], n + 1)?, number(f[1], n + 1)?, number(f[2], n + 1)?], n + 1));
    }
    let grid = points_grid(&points, hint)?;
    Ok(Data { grid, format: if csv { Format::Csv } else { Format::LinuxCnc } })
}

fn checked_grid(nx: usize, ny: usize, pitch: f64, origin: [f64; 2], order: Order) -> Result<Grid, Error> {
    if nx < 2 || ny < 2 {
        return err(None, format!("the grid needs at least 2 × 2 points, got {nx} × {ny}"));
    }
    if nx.checked_mul(ny).is_none_or(|n| n > 100_000_000) {
        return err(None, format!("a grid of {nx} × {ny} points is too large"));
    }
    if let Err(e) = limits::length(pitch, "the pitch") {
        return err(None, e);
    }
    if let Some(e) = origin.iter().find_map(|&v| limits::coordinate(v, "the origin").err()) {
        return err(None, e);
    }
    Ok(Grid { nx, ny, pitch, origin, order })
}

/// The grid of a `# grid key=value …` line; the hint fills in, and must
/// agree with, what the header says.
fn header_grid(line: &str, n: usize, hint: &Hint) -> Result<Grid, Error> {
    let mut nx = None;
    let mut ny = None;
    let mut pitch = None;
    let mut origin = None;
    let mut order = None;
    let body = line.trim_start().trim_start_matches('#').trim_start();
    for token in body.split_whitespace().skip(1) {
        let Some((key, value)) = token.split_once('=') else { continue };
        // `token` lies in `line`: its column is the characters before it, plus one.
        let column = Some(line[..token.as_ptr() as usize - line.as_ptr() as usize].chars().count() + 1);
        let bad = |what: &str| {
            Error::at(ErrorKind::Data, Some(n), column, format!("grid header: {key}={value} is not {what}"))
        };
        match key.to_ascii_lowercase().as_str() {
            "nx" => nx = Some(value.parse::<usize>().map_err(|_| bad("a count"))?),
            "ny" => ny = Some(value.parse::<usize>().map_err(|_| bad("a count"))?),
            "pitch" => pitch = Some(value.parse::<f64>().map_err(|_| bad("a number"))?),
            "origin" => {
                let v: Vec<f64> =
                    value.split(',').map(|s| s.parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad("X,Y"))?;
                if v.len() != 2 {
                    return Err(bad("X,Y"));
                }
                origin = Some([v[0], v[1]]);
            }
            "pattern" | "order" => {
                order = Some(
                    value.parse::<Order>().map_err(|message| Error::at(ErrorKind::Data, Some(n), column, message))?,
                )
            }
            _ => {}
        }
    }
    if let (Some([hx, hy]), Some(x), Some(y)) = (hint.count, nx, ny) {
        if (hx, hy) != (x, y) {
            return err(Some(n), format!("the header's grid is {x} × {y}, --count says {hx} × {hy}"));
        }
    }
    if let (Some(h), Some(p)) = (hint.pitch, pitch) {
        if (h - p).abs() > 1e-9 * p.abs().max(1.0) {
            return err(Some(n), format!("the header's pitch is {p}, --pitch says {h}"));
        }
    }
    let (Some(nx), Some(ny)) = (nx.or(hint.count.map(|c| c[0])), ny.or(hint.count.map(|c| c[1]))) else {
        return err(Some(n), "grid header without nx= and ny= (or give --count NX,NY)");
    };
    let Some(pitch) = pitch.or(hint.pitch) else {
        return err(Some(n), "grid header without pitch= (or give --pitch P)");
    };
    checked_grid(nx, ny, pitch, origin.or(hint.origin).unwrap_or([0.0, 0.0]), order.or(hint.order).unwrap_or_default())
        .map_err(|e| Error { line: Some(n), ..e })
}

/// The `No,Z` records of `lines` (header, comments and a leading No 0
/// skipped), placed on `grid`; also whether there was a No 0 record and a
/// `No,Z` title.
fn records(lines: &[&str], grid: &Grid) -> Result<(Vec<f64>, bool, bool), Error> {
    let mut z = vec![f64::NAN; grid.len()];
    let (mut count, mut zero_record, mut title) = (0usize, false, false);
    let mut last_line = 0;
    for (n, line) in lines.iter().enumerate().map(|(k, l)| (k + 1, l)) {
        if is_comment(line) {
            continue;
        }
        let f = fields(line);
        if !title && count == 0 && !zero_record && f.len() == 2 && f[0].text.eq_ignore_ascii_case("no") {
            title = true;
            continue;
        }
        if f.len() != 2 {
            return err(Some(n), format!("expected a record No,Z, got '{}'", line.trim()));
        }
        let Ok(no) = f[0].text.parse::<usize>() else {
            let message = format!("point number '{}' is not a whole number", f[0].text);
            return Err(Error::at(ErrorKind::Data, Some(n), Some(f[0].column), message));
        };
        let value = number(f[1], n)?;
        if no == 0 && count == 0 && !zero_record {
            zero_record = true;
            continue;
        }
        if no != count + 1 {
            return err(Some(n), format!("point No {no} where No {} was expected (a gap or a repeat)", count + 1));
        }
        if count == grid.len() {
            return err(Some(n), format!("more points than the {} × {} grid holds ({})", grid.nx, grid.ny, grid.len()));
        }
        let (i, j) = grid.node(count);
        z[j * grid.nx + i] = value;
        count += 1;
        last_line = n;
    }
    if count != grid.len() {
        return err(
            (last_line > 0).then_some(last_line),
            format!(
                "{count} points, but the {} × {} grid has {} (an unfinished capture, or the wrong --count)",
                grid.nx,
                grid.ny,
                grid.len()
            ),
        );
    }
    Ok((z, zero_record, title))
}

/// The regular grid the points lie on.
fn points_grid(points: &[([f64; 3], usize)], hint: &Hint) -> Result<ProbeGrid, Error> {
    if points.len() < 4 {
        return err(None, format!("{} points: a grid needs at least 2 × 2", points.len()));
    }
    let axis = |k: usize| {
        let mut v: Vec<f64> = points.iter().map(|p| p.0[k]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= 1e-6 * (1.0 + b.abs()));
        v
    };
    let (xs, ys) = (axis(0), axis(1));
    let (nx, ny) = (xs.len(), ys.len());
    if nx < 2 || ny < 2 || nx * ny != points.len() {
        return err(
            None,
            format!("the {} points are not a regular grid ({nx} distinct X by {ny} distinct Y)", points.len()),
        );
    }
    let pitch = xs[1] - xs[0];
    let even = |v: &[f64]| v.windows(2).all(|w| ((w[1] - w[0]) - pitch).abs() <= 1e-6 * (1.0 + pitch));
    if !(even(&xs) && even(&ys)) {
        return err(None, format!("the points are not on a grid of square {pitch} mm cells"));
    }
    if let Some([hx, hy]) = hint.count {
        if (hx, hy) != (nx, ny) {
            return err(None, format!("the points make a {nx} × {ny} grid, --count says {hx} × {hy}"));
        }
    }
    let grid = checked_grid(nx, ny, pitch, [xs[0], ys[0]], hint.order.unwrap_or_default())?;
    let find = |v: &[f64], x: f64| v.partition_point(|a| *a < x - 1e-6 * (1.0 + x.abs())).min(v.len() - 1);
    let mut z = vec![f64::NAN; nx * ny];
    for &(p, n) in points {
        let k = find(&ys, p[1]) * nx + find(&xs, p[0]);
        if !z[k].is_nan() {
            return err(Some(n), format!("a second height at ({}, {})", p[0], p[1]));
        }
        z[k] = p[2];
    }
    Ok(ProbeGrid { grid, z })
}

/// `v` with at most `digits` decimals, trailing zeros trimmed.
pub fn num(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// `v` as the shortest text that reads back to it (`0` for `-0`).
fn full(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        v.to_string()
    }
}

/// Writes `grid` in `format`: heights at full precision (the shortest
/// text that reads back to the same number, as kezuri asks of all its
/// data outputs), X and Y of the nominal grid to 6 decimals.
pub fn write(grid: &ProbeGrid, format: &Format) -> String {
    let mut out = String::new();
    let g = &grid.grid;
    match format {
        Format::Capture { .. } | Format::Bare { .. } => {
            match format {
                Format::Capture { header } => {
                    for line in header {
                        out.push_str(line);
                        out.push('\n');
                    }
                    out.push_str("No,Z\n");
                }
                Format::Bare { zero_record, title } => {
                    if *title {
                        out.push_str("No,Z\n");
                    }
                    if *zero_record {
                        out.push_str("0,0\n");
                    }
                }
                _ => unreachable!(),
            }
            for (k, z) in grid.in_capture_order().into_iter().enumerate() {
                let _ = writeln!(out, "{},{}", k + 1, full(z));
            }
        }
        Format::Csv | Format::LinuxCnc => {
            let csv = matches!(format, Format::Csv);
            if csv {
                out.push_str("x,y,z\n");
            }
            for j in 0..g.ny {
                for i in 0..g.nx {
                    let (x, y, z) = (num(g.x(i), 6), num(g.y(j), 6), full(grid.z(i, j)));
                    let _ = if csv { writeln!(out, "{x},{y},{z}") } else { writeln!(out, "{x} {y} {z}") };
                }
            }
        }
    }
    out
}

/// A capture-file header for `grid` (the `# grid …` line).
pub fn grid_header(grid: &Grid) -> String {
    format!(
        "# grid nx={} ny={} pitch={} origin={},{} pattern={}",
        grid.nx,
        grid.ny,
        num(grid.pitch, 6),
        num(grid.origin[0], 6),
        num(grid.origin[1], 6),
        grid.order.name()
    )
}
