//! Surfaces from files: an STL mesh, or a height grid of `x y z` lines;
//! and a height grid written as an STL.

use std::io::Read;
use std::path::Path;

use anyhow::{bail, Context, Result};
use clap::ValueEnum;
use kezuri_cam::cutter::Flat;
use kezuri_cam::dropcut::{drop_cutter, MeshSurface};
use kezuri_cam::Cutter;
use kezuri_geom::{read_binary_stl_mesh, read_stl, write_binary_stl_to, Heightfield, Mesh, Triangle, Vec3};

use crate::files::{read_bytes, Outputs};
use crate::progress::{ByteProgress, CountingReader};
use crate::say::note;

/// A surface to cut or to compare with.
pub enum Surface {
    /// Triangles with their XY index.
    Mesh(Box<MeshSurface>),
    /// A regular grid of square cells (the drop-cutter fast path).
    Grid(Heightfield),
}

impl Surface {
    /// The tip z of `cutter` resting on the surface at `(x, y)`.
    pub fn drop_cutter(&self, cutter: &Cutter, x: f64, y: f64) -> Option<f64> {
        match self {
            Surface::Mesh(m) => drop_cutter(cutter, m.as_ref(), x, y),
            Surface::Grid(g) => drop_cutter(cutter, g, x, y),
        }
    }

    /// The surface's height at `(x, y)`, `None` off it: a grid's between
    /// its nodes, a mesh's highest point within 0.05 µm (a needle dropped).
    pub fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        match self {
            Surface::Mesh(m) => drop_cutter(&Cutter::Flat(Flat::new(1e-4)), m.as_ref(), x, y),
            Surface::Grid(g) => g.z_at(x, y),
        }
    }

    /// `[min x, min y, max x, max y]`.
    pub fn xy_box(&self) -> [f64; 4] {
        match self {
            Surface::Mesh(m) => {
                let (lo, hi) = m.mesh().bounds().expect("a surface has triangles");
                [lo.x, lo.y, hi.x, hi.y]
            }
            Surface::Grid(g) => g.xy_box(),
        }
    }

    /// The highest point.
    pub fn top(&self) -> f64 {
        match self {
            Surface::Mesh(m) => m.mesh().bounds().expect("a surface has triangles").1.z,
            Surface::Grid(g) => g.heights().iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// The triangles, as corner coordinates.
    pub fn triangles(&self) -> Vec<[[f64; 3]; 3]> {
        let corners = |t: Triangle| t.v.map(|p| [p.x, p.y, p.z]);
        match self {
            Surface::Mesh(m) => m.mesh().iter().map(corners).collect(),
            Surface::Grid(g) => g.to_mesh().iter().map(corners).collect(),
        }
    }
}

/// The unit an STL (or a height grid) is drawn in: STL files carry none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Units {
    /// Millimetres (as kezuri works).
    #[default]
    Mm,
    /// Inches: every coordinate is multiplied by 25.4.
    Inch,
}

impl Units {
    /// Millimetres per unit.
    pub fn scale(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }
}

/// A model smaller than this in every direction, read as mm, may well be
/// drawn in inches.
const INCH_SUSPECT_MM: f64 = 13.0;

/// Says a model's size (`model: 120.0 × 80.0 × 30.0 mm`), with a note
/// where no unit was given and it is so small that it may be in inches.
fn say_size(name: &str, given: Option<Units>, lo: [f64; 3], hi: [f64; 3]) {
    let units = given.unwrap_or_default();
    let d: [f64; 3] = std::array::from_fn(|k| hi[k] - lo[k]);
    let from = if units == Units::Inch { " (from inches)" } else { "" };
    note!("{name}: model: {:.1} × {:.1} × {:.1} mm{from}", d[0], d[1], d[2]);
    if given.is_none() && d.iter().all(|d| *d < INCH_SUSPECT_MM) {
        note!(
            "note: {name}: the model is under {INCH_SUSPECT_MM} mm in every direction: if it was drawn in inches, \
             give --units inch"
        );
    }
}

/// Reads an STL mesh (binary or ASCII) in `units`: says its size, and
/// warns of degenerate triangles skipped and of an ASCII file cut short.
pub fn read_mesh(path: &Path, units: Option<Units>) -> Result<Mesh> {
    let name = path.display().to_string();
    if let Some((file, count)) = binary_stl_file(path) {
        let scale = units.unwrap_or_default().scale();
        // A large mesh takes seconds to read: a bar by bytes.
        let progress = ByteProgress::start("reading", 84 + 50 * u64::from(count));
        let mesh = read_binary_stl_mesh(CountingReader::new(file, 84, &progress), count, scale);
        progress.finish();
        return Ok(told(&name, mesh.with_context(|| name.clone())?, units));
    }
    let bytes = read_bytes(path)?;
    mesh_of(&name, &bytes, units)
}

/// A binary STL file (not standard input), opened past its 84-byte header,
/// and its triangle count: its size is the one the header announces. It is
/// then read a piece at a time, never held whole.
fn binary_stl_file(path: &Path) -> Option<(std::fs::File, u32)> {
    if path == Path::new("-") {
        return None;
    }
    let mut file = std::fs::File::open(path).ok()?;
    let size = file.metadata().ok().filter(|m| m.is_file())?.len();
    let mut header = [0u8; 84];
    file.read_exact(&mut header).ok()?;
    let count = u32::from_le_bytes([header[80], header[81], header[82], header[83]]);
    (84 + 50 * u64::from(count) == size).then_some((file, count))
}

fn mesh_of(name: &str, bytes: &[u8], given: Option<Units>) -> Result<Mesh> {
    let units = given.unwrap_or_default();
    if let Some(c) = bytes.get(80..84) {
        let count = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        if 84 + 50 * u64::from(count) == bytes.len() as u64 {
            let mesh = read_binary_stl_mesh(&bytes[84..], count, units.scale()).with_context(|| name.to_string())?;
            return Ok(told(name, mesh, given));
        }
    }
    let file = read_stl(bytes).map_err(|e| match e.at {
        Some((line, column)) => anyhow::anyhow!("{name}:{line}:{column}: {} (ASCII STL)", e.message),
        None => anyhow::Error::new(e).context(name.to_string()),
    })?;
    if let Some(line) = file.cut_short {
        eprintln!(
            "warning: {name}: the ASCII STL ends at line {line} without its `endsolid` line: the file may be cut \
             short ({} triangles read)",
            file.triangles.len()
        );
    }
    let k = units.scale();
    let triangles = match units {
        Units::Mm => file.triangles,
        Units::Inch => file.triangles.into_iter().map(|t| Triangle { v: t.v.map(|p| p * k) }).collect(),
    };
    let mesh = Mesh::from_stl_triangles(triangles).with_context(|| name.to_string())?;
    Ok(told(name, mesh, given))
}

/// `mesh`, once the user is told of degenerate triangles skipped and of its
/// size.
fn told(name: &str, mesh: Mesh, given: Option<Units>) -> Mesh {
    if mesh.skipped() > 0 {
        eprintln!("warning: {name}: skipped {} degenerate (zero-area) triangles", mesh.skipped());
    }
    if let Some((lo, hi)) = mesh.bounds() {
        say_size(name, given, [lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]);
    }
    mesh
}

/// Reads an STL (binary or ASCII) or a height grid (`x y z` or `x,y,z`
/// lines on a regular grid; lines that do not start with a number, headers
/// and comments, are skipped; a line that starts with one must be `x y z`),
/// in `units` (none: mm), and says its size.
pub fn read_surface(path: &Path, units: Option<Units>) -> Result<Surface> {
    if binary_stl_file(path).is_some() {
        return Ok(Surface::Mesh(Box::new(MeshSurface::new(read_mesh(path, units)?))));
    }
    let bytes = read_bytes(path)?;
    let name = path.display().to_string();
    let is_stl = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("stl"))
        || bytes.trim_ascii_start().get(..5).is_some_and(|h| h.eq_ignore_ascii_case(b"solid"))
        || bytes
            .get(80..84)
            .is_some_and(|c| 84 + 50 * u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])) == bytes.len() as u64);
    if is_stl {
        let mesh = mesh_of(&name, &bytes, units)?;
        drop(bytes);
        return Ok(Surface::Mesh(Box::new(MeshSurface::new(mesh))));
    }
    let surface =
        grid(&String::from_utf8_lossy(&bytes), units.unwrap_or_default().scale()).with_context(|| name.clone())?;
    let [x0, y0, x1, y1] = surface.xy_box();
    let (z0, z1) = match &surface {
        Surface::Grid(g) => {
            g.heights().iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| (a.min(*z), b.max(*z)))
        }
        Surface::Mesh(m) => m.mesh().bounds().map_or((0.0, 0.0), |(lo, hi)| (lo.z, hi.z)),
    };
    say_size(&name, units, [x0, y0, z0], [x1, y1, z1]);
    Ok(surface)
}

/// A regular height grid, its coordinates multiplied by `scale`: a
/// [`Heightfield`] when its cells are square, otherwise its triangles (each
/// cell split along the diagonal from its lowest corner, as the heightfield
/// does).
fn grid(text: &str, scale: f64) -> Result<Surface> {
    let mut points = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line.split(|c: char| c == ',' || c.is_whitespace()).filter(|f| !f.is_empty()).collect();
        // Headers and comments: lines that do not start with a number.
        if fields.first().is_none_or(|f| f.parse::<f64>().is_err()) {
            continue;
        }
        let v: Vec<f64> = fields.iter().filter_map(|f| f.parse::<f64>().ok()).collect();
        if v.len() != 3 || fields.len() != 3 {
            bail!("line {}: expected three numbers `x y z`, got `{}`", n + 1, line.trim());
        }
        if !v.iter().all(|v| v.is_finite()) {
            bail!("line {}: a coordinate is not a finite number", n + 1);
        }
        points.push([v[0] * scale, v[1] * scale, v[2] * scale]);
    }
    if points.len() < 4 {
        bail!("not an STL and not a height grid: {} `x y z` lines, need a grid of at least 2 × 2", points.len());
    }
    let axis = |k: usize| {
        let mut v: Vec<f64> = points.iter().map(|p| p[k]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * (1.0 + b.abs()));
        v
    };
    let (xs, ys) = (axis(0), axis(1));
    let (nx, ny) = (xs.len(), ys.len());
    if nx < 2 || ny < 2 || nx * ny != points.len() {
        bail!("the {} points are not a regular grid ({nx} distinct X by {ny} distinct Y)", points.len());
    }
    let find = |v: &[f64], x: f64| v.partition_point(|a| *a < x - 1e-9 * (1.0 + x.abs())).min(v.len() - 1);
    let mut z = vec![f64::NAN; nx * ny];
    for p in &points {
        let k = find(&ys, p[1]) * nx + find(&xs, p[0]);
        if !z[k].is_nan() {
            bail!("two heights at ({}, {}): not a grid", p[0], p[1]);
        }
        z[k] = p[2];
    }
    let step = xs[1] - xs[0];
    let even = |v: &[f64]| v.windows(2).all(|w| ((w[1] - w[0]) - step).abs() <= 1e-9 * (1.0 + step));
    if even(&xs) && even(&ys) {
        return Ok(Surface::Grid(Heightfield::new(xs[0], ys[0], step, nx, ny, z)?));
    }
    let node = |i: usize, j: usize| Vec3::new(xs[i], ys[j], z[j * nx + i]);
    let triangles = (0..ny - 1).flat_map(|j| {
        (0..nx - 1).flat_map(move |i| {
            let (a, b, c, d) = (node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1));
            [Triangle::new(a, b, c), Triangle::new(a, c, d)]
        })
    });
    Ok(Surface::Mesh(Box::new(MeshSurface::new(Mesh::from_triangles(triangles.collect::<Vec<_>>())))))
}

/// Adds the surface of `field` to `out` as a binary STL, a triangle at a
/// time (a 64-million-pixel relief is 128 million triangles, 6.4 GB of STL,
/// never in memory when written to a file).
pub fn stage_surface_stl(out: &mut Outputs, path: &Path, field: &Heightfield) -> Result<()> {
    out.add_with(Some(path), |w| write_binary_stl_to(w, field.triangles()))
}
