//! The view page: the job in 3D as one self-contained, offline HTML page —
//! the toolpath, the tool, the simulated part and its deviation (`kezuri
//! view`, and the `--view` output of `sim`, `mill`, `relief` and `probe mill`).
//!
//! # The page
//!
//! `page.html` (the body), `viewer.css` and `viewer.js` (hand-written
//! WebGL2, no library) are compiled in. The data follows them as three
//! inert script elements: `kz-meta`, JSON with `<`, `>` and `&` escaped;
//! `kz-data` and `kz-text`, base64 of gzip (the browser's
//! `DecompressionStream` unpacks them). The page's Content-Security-Policy
//! forbids every network request and lets only `viewer.js` run (by its
//! SHA-256), and the viewer puts program text and names on the page as text
//! only: an NC comment holding `</script>` is shown, never run.
//!
//! # kz-data
//!
//! Little-endian arrays, each from a multiple of four bytes: per move (N)
//! `kind: u8` (0 rapid, 1 feed, 2 arc, 3 plunge, 4 probe, 5 dwell, 6 to a
//! place the program does not give — a reference point or `G53` position
//! the machine file does not place, or an axis not yet named since the
//! start: no vertex, the tool not shown; a move from such a place to a
//! known one is its end alone, one vertex after a break),
//! `tool: u16` (index into meta.tools; number 0 there is the tool of a
//! program that loads none), `frame: u16` (index into
//! meta.frames, the work zeros), `line_delta: i32`, `feed: f32` (mm/min),
//! `seconds: f32`, `vertex_count: u32`; per vertex (V) `dx, dy, dz: i32`
//! (quanta of meta.quantum_mm from the previous vertex, the first from
//! meta.origin_mm) and `break: u8` (1: no segment from the vertex before);
//! with a simulation, `height: i32[nx·ny]` (delta coded, quanta above
//! sim.z0_mm), `block: u32[3·B]` (flat squares `i, j, size` of the vertex
//! grid) and with a target `deviation: i32[nx·ny]` (0.1 µm; i32::MIN where
//! the target does not reach).

mod blob;
pub mod detail;
mod drawing;
mod pack;
mod part;
pub mod stream;

use std::io::Write as _;

use base64::Engine as _;
use kezuri_cam::shorten::{shorten, ShortenOptions};
use kezuri_cam::sim::compare::Comparison;
use kezuri_cam::sim::{SimReport, Tool, ZMap};
use kezuri_cam::Cutter;
use kezuri_geom::{Dynamics, PathSink as _, Toolpath};
use serde_json::{json, Value};
use sha2::Digest as _;

use crate::sim::{DeviationScale, GOUGE_MM};
use crate::{Error, ErrorKind};
use blob::{Blob, Columns};
use pack::ToolLook;
use part::Part;
pub use stream::PathPage;

/// How the page is made.
#[derive(Debug, Clone)]
pub struct PageOptions {
    /// Largest sagitta of the chords arcs are drawn as, mm.
    pub arc_tol: f64,
    /// Merge moves within this distance first (said on the page).
    pub shorten: Option<f64>,
    /// Leave the program text out of the page (the view and the readouts stay).
    pub no_text: bool,
    /// Largest page to make, MB: a bigger one is refused.
    pub max_page_mb: f64,
    /// Most vertices of the simulated part's mesh (a finer grid is shown
    /// coarser, each vertex the lowest cell under it).
    pub mesh_vertices: usize,
}

impl Default for PageOptions {
    /// The defaults of `kezuri view`'s options.
    fn default() -> PageOptions {
        PageOptions { arc_tol: 0.01, shorten: None, no_text: false, max_page_mb: 32.0, mesh_vertices: 1_000_000 }
    }
}

/// What a page shows: a program's moves, its text, its units, how fast the
/// machine moves (for the cycle time) and the tools' shapes.
pub struct Job<'a> {
    /// The page's title: the program's file.
    pub title: &'a str,
    /// The moves.
    pub path: &'a Toolpath,
    /// The program text, where there is one.
    pub text: Option<&'a str>,
    /// Whether the program is in inches.
    pub inch: bool,
    /// The machine's rapids, feeds and acceleration.
    pub dynamics: &'a Dynamics,
    /// Tool number and shape where known: the first of a number counts (the
    /// command's own, then the machine file's).
    pub shapes: Vec<(u32, Cutter)>,
    /// The shape of every tool nothing else names.
    pub any: Option<Cutter>,
}

/// A simulation on the page: its cutters, the cut grid, its report and,
/// with a target, the comparison and how the deviation is coloured.
pub struct Simulation<'a> {
    /// Tool number and cutter, as the simulation cut with them.
    pub tools: &'a [(u32, Tool)],
    /// How each of `tools` is named: `flat:6`, `profile:FILE`.
    pub names: &'a [String],
    /// The simulated heights.
    pub zmap: &'a ZMap,
    /// What the cutting found: rapids into the stock, the tool that cut
    /// each cell last.
    pub report: &'a SimReport,
    /// With a target: the comparison and the target's height over each
    /// cell (`-inf` where it has none).
    pub comparison: Option<(&'a Comparison, &'a [f64])>,
    /// How the deviation is coloured (with a target).
    pub scale: Option<&'a DeviationScale>,
}

/// A page and what was left out to make it fit.
pub struct Page {
    /// The page.
    pub html: Vec<u8>,
    /// How it was made to fit, where it was (the path simplified, the text
    /// left out), as the page says it.
    pub fitted: Vec<String>,
}

/// The page of `job` (and of its simulation): the tools' shapes from the
/// simulation, else the job's.
pub fn page(job: &Job, sim: Option<&Simulation>, options: &PageOptions) -> Result<Vec<u8>, Error> {
    Ok(fitted_page(job, sim, options)?.html)
}

/// The page of `job` (and of its simulation) within `--max-page-mb`: the
/// level of detail is chosen before the page is built (see [`detail`] and
/// [`stream`]); the program text is left out where it would take more than
/// half the page. Refused only where even the coarsest tolerance does not
/// fit.
pub fn fitted_page(job: &Job, sim: Option<&Simulation>, options: &PageOptions) -> Result<Page, Error> {
    let original = job.path;
    let shortened;
    let mut notes = Vec::new();
    let path = match options.shorten {
        Some(tolerance) => {
            shortened = shorten(original, &ShortenOptions { tolerance, arcs: false });
            notes.push(format!(
                "shortened within {tolerance} mm: {} moves drawn as {}",
                original.moves.len(),
                shortened.moves.len()
            ));
            &shortened
        }
        None => original,
    };
    let mut builder = PathPage::new(job.dynamics, options, notes);
    builder.take(path, None);
    match job.text {
        Some(t) => builder.finish(
            job,
            sim,
            Some(&mut |piece: &mut dyn FnMut(&[u8]) -> bool| {
                piece(t.as_bytes());
            }),
        ),
        None => builder.finish(job, sim, None),
    }
}

/// What the page takes besides the path and the program text: the viewer,
/// the meta data and a part of `part` bytes (base64 of at most its own
/// size).
fn fixed_bytes(part: usize) -> f64 {
    (VIEWER_JS.len() + VIEWER_CSS.len() + BODY.len() + 16_384) as f64 + part as f64 * 4.0 / 3.0
}

/// The page from the levels of detail kept (full detail first, then each
/// of [`detail::TOLERANCES`]: its tolerance, its reckoned cost and its
/// drawing; `None` where it was let go): the part first, then the text
/// where it takes at most half of what is left, then the finest level that
/// fits the rest. `tools`: the numbers of the tools the path uses; `count`:
/// its moves.
#[allow(clippy::too_many_arguments)]
fn page_of_levels(
    job: &Job,
    sim: Option<&Simulation>,
    text: Option<stream::TextPieces>,
    options: &PageOptions,
    mut notes: Vec<String>,
    tools: &[u32],
    count: u64,
    levels: Vec<Option<(Option<f64>, f64, drawing::Drawing)>>,
) -> Result<Page, Error> {
    let file = job.title;
    // The part first: what it takes decides what is left for the path.
    let mut part_blob = Blob::default();
    let mut part_bounds = None;
    let sim_meta = match sim {
        Some(s) => {
            let part = Part {
                zmap: s.zmap,
                target: s.comparison.map(|c| c.1),
                scale: s.scale,
                max_vertices: options.mesh_vertices,
            };
            let (meta, bounds) = part.pack(&mut part_blob);
            if meta["cell_mm"].as_f64() != Some(s.zmap.res) {
                notes.push(format!(
                    "the part is shown at {:.3} mm cells (simulated at {} mm), each the lowest of its cells",
                    meta["cell_mm"].as_f64().unwrap_or(0.0),
                    s.zmap.res
                ));
            }
            part_bounds = Some(bounds);
            meta
        }
        None => Value::Null,
    };
    let limit = options.max_page_mb * 1e6;
    let fixed = fixed_bytes(part_blob.len());
    let mut fitted = Vec::new();
    let text = match text.filter(|_| !options.no_text).map(|t| packed_text(t, (limit - fixed) / 2.0)) {
        Some(Ok(packed)) => Some(packed),
        Some(Err((size, whole))) => {
            fitted.push(format!(
                "the program text is left out to fit {} MB (it takes {}{:.1} MB packed)",
                options.max_page_mb,
                if whole { "" } else { "more than " },
                size as f64 / 1e6
            ));
            None
        }
        None => None,
    };
    let budget = limit - fixed - text.as_ref().map_or(0.0, |p| p.len() as f64);
    let too_large = || too_large(file, options, text.is_some(), sim.is_some());
    let mut at =
        levels.iter().position(|l| l.as_ref().is_some_and(|(_, cost, _)| *cost <= budget)).ok_or_else(too_large)?;
    // The estimate of what a drawn move costs holds on the programs
    // measured; where a page comes out larger all the same, the next
    // coarser tolerance kept is drawn.
    loop {
        let Some((tolerance, _, drawing)) = &levels[at] else { return Err(too_large()) };
        let mut fitted = fitted.clone();
        if let Some(tolerance) = tolerance {
            fitted.push(format!(
                "simplified to {tolerance} mm to fit {} MB: {} moves drawn as {}",
                options.max_page_mb,
                thousands(count),
                thousands(drawing.moves)
            ));
        }
        let mut notes = notes.clone();
        notes.extend(fitted.iter().cloned());
        let layout = drawing.layout(tool_looks(job, tools, sim))?;
        let mut bounds = drawing.bounds;
        if let Some((lo, hi)) = part_bounds {
            bounds = Some(match bounds {
                Some((a, b)) => (std::array::from_fn(|k| a[k].min(lo[k])), std::array::from_fn(|k| b[k].max(hi[k]))),
                None => (lo, hi),
            });
        }
        let marks = match sim {
            Some(s) => sim_marks(s, job.path, drawing.moves as usize, s.scale.map_or(GOUGE_MM, |d| d.gouge)),
            None => Vec::new(),
        };
        let mut meta = layout.meta(drawing.moves, drawing.rotary);
        let extra = json!({
            "version": 1,
            "title": file,
            "units": if job.inch { "inch" } else { "mm" },
            "unit_mm": if job.inch { 25.4 } else { 1.0 },
            "bbox_mm": bounds.map(|(a, b)| [a, b]),
            "arc_tolerance_mm": options.arc_tol,
            "cycle_time_s": drawing.seconds,
            "notes": notes,
            "text": text.is_some(),
            "sim": sim_meta.clone(),
            "marks": marks,
        });
        if let (Value::Object(m), Value::Object(e)) = (&mut meta, extra) {
            m.extend(e);
        }
        let html = html(
            &meta,
            |page| {
                let b64 = base64::write::EncoderWriter::new(page, &base64::engine::general_purpose::STANDARD);
                let mut columns = Columns::new(flate2::write::GzEncoder::new(b64, flate2::Compression::new(3)));
                drawing.write(&layout, &mut columns)?;
                columns.append(&part_blob);
                let mut b64 = columns.finish().finish().expect("gzip into memory cannot fail");
                b64.finish().expect("base64 into memory cannot fail");
                Ok(())
            },
            text.as_deref(),
        )?;
        if html.len() as f64 <= limit {
            return Ok(Page { html, fitted });
        }
        at = (at + 1..levels.len()).find(|&k| levels[k].is_some()).ok_or_else(too_large)?;
    }
}

/// The refusal of a path that does not fit even at the coarsest tolerance.
fn too_large(file: &str, options: &PageOptions, text: bool, sim: bool) -> Error {
    Error::new(
        ErrorKind::PageTooLarge,
        format!(
            "{file}: the page would not fit {} MB (--max-page-mb) even with the path simplified to {} mm: \
             raise --max-page-mb{}{}",
            options.max_page_mb,
            detail::TOLERANCES[detail::TOLERANCES.len() - 1],
            if text { ", leave the program text out with --no-text" } else { "" },
            if sim { ", or show the part with fewer --mesh-vertices" } else { "" },
        ),
    )
}

/// `n` with its thousands apart: 9,000,000.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// How each of the tools `numbers` (in order, each once) looks: the
/// simulation's cutters, else the job's shapes, or its shape of any tool.
fn tool_looks(job: &Job, numbers: &[u32], sim: Option<&Simulation>) -> Vec<ToolLook> {
    let changes = numbers.iter().any(|&n| n != 0);
    numbers
        .iter()
        .map(|&number| {
            let simulated = sim.and_then(|s| {
                let k = s.tools.iter().position(|(n, _)| *n == number)?;
                Some((s.names[k].clone(), profile(&s.tools[k].1)))
            });
            let named = || job.shapes.iter().find(|(n, _)| *n == number).map(|(_, c)| *c);
            let (shape, outline) = match simulated {
                Some((name, outline)) => (Some(name), Some(outline)),
                None => match named().or(job.any) {
                    Some(c) => (Some(c.to_string()), Some(profile(&Tool::Cutter(c)))),
                    None => (None, None),
                },
            };
            let label = match (number, &shape) {
                (0, _) if changes => "before the first tool change".to_string(),
                (0, Some(s)) => format!("the tool, {s} (no tool change)"),
                (0, None) => "the tool (no tool change; shape not given)".to_string(),
                (n, Some(s)) => format!("T{n} {s}"),
                (n, None) => format!("T{n} (shape not given)"),
            };
            ToolLook { number, label, shape, profile: outline }
        })
        .collect()
}

/// The outline of a tool from its tip up, `(z, r)`: the cutting end
/// sampled over its radius, then the flutes as a cylinder three radii high.
fn profile(tool: &Tool) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = match tool {
        Tool::Cutter(c) => {
            let r = c.radius();
            (0..=24).map(|k| r * f64::from(k) / 24.0).map(|x| [c.height(x), x]).collect()
        }
        Tool::Measured(m) => m.corners().iter().map(|&(r, z)| [z, r]).collect(),
    };
    out.retain(|p| p[0].is_finite() && p[1].is_finite());
    let (top, r) = out.last().map_or((0.0, tool.radius()), |p| (p[0], p[1]));
    out.push([top + 3.0 * tool.radius().max(r), tool.radius().max(r)]);
    out
}

/// The marks of a simulation: the first rapid into the stock and the
/// worst gouge, if deeper than `gouge`. Move numbers are of the `drawn`
/// moves (the moves of `run`, or fewer where shortened or simplified: then
/// the rapid is marked without one).
fn sim_marks(s: &Simulation, run: &Toolpath, drawn: usize, gouge: f64) -> Vec<Value> {
    let mut marks = Vec::new();
    // (A path drawn as it came is not held: its rapid is not marked.)
    if let Some((hit, m)) = s.report.rapid_hits.first().and_then(|h| Some((h, run.moves.get(h.index)?))) {
        let index = (run.moves.len() == drawn).then_some(hit.index);
        marks.push(json!({
            "kind": "rapid",
            "label": format!("first rapid into the stock: line {}, {:.3} mm deep ({} in all)", hit.line, hit.depth, s.report.rapid_hits.len()),
            "at_mm": m.end.xyz(),
            "move": index,
            "line": hit.line,
        }));
    }
    if let Some((c, _)) = s.comparison {
        if let (Some(cell), true) = (c.gouge_cell, c.max_gouge > gouge) {
            let [x, y] = s.zmap.centre(cell % s.zmap.nx, cell / s.zmap.nx);
            let by = s.report.cut_by.get(cell).copied().filter(|&b| b != kezuri_cam::sim::UNCUT);
            // Tool 0 is the one tool of a program that changes none.
            let number = by.map(|b| s.report.tools[b as usize].number).filter(|&n| n != 0);
            let tool = number.map(|n| format!(", cut last by T{n}")).unwrap_or_default();
            marks.push(json!({
                "kind": "gouge",
                "label": format!("worst gouge {:.1} µm below the target at X{x:.3} Y{y:.3}{tool}", c.max_gouge * 1000.0),
                "at_mm": [x, y, s.zmap.height_at(cell)],
                "move": null,
                "line": null,
            }));
        }
    }
    marks
}

const VIEWER_JS: &str = include_str!("view/viewer.js");
const VIEWER_CSS: &str = include_str!("view/viewer.css");
const BODY: &str = include_str!("view/page.html");

/// A writer that keeps what it is given up to `max` bytes, and counts it
/// all (`len`, shared).
struct Bounded {
    kept: Vec<u8>,
    max: f64,
    len: std::rc::Rc<std::cell::Cell<usize>>,
}

impl std::io::Write for Bounded {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.len.set(self.len.get() + buf.len());
        if self.len.get() as f64 <= self.max {
            self.kept.extend_from_slice(buf);
        } else {
            self.kept = Vec::new();
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The program text `text` gives, gzipped and in base64, where that takes
/// at most `max` bytes; else its packed size and whether that is the whole
/// (the packing stops at eight times `max`: "more than" that).
fn packed_text(text: stream::TextPieces, max: f64) -> Result<String, (usize, bool)> {
    let len = std::rc::Rc::new(std::cell::Cell::new(0));
    let kept = Bounded { kept: Vec::new(), max, len: len.clone() };
    let b64 = base64::write::EncoderWriter::new(kept, &base64::engine::general_purpose::STANDARD);
    let mut gz = flate2::write::GzEncoder::new(b64, flate2::Compression::new(3));
    let stop = (8.0 * max).max(0.0);
    let mut whole = true;
    text(&mut |piece| {
        gz.write_all(piece).expect("gzip into memory cannot fail");
        whole = len.get() as f64 <= stop;
        whole
    });
    let mut b64 = gz.finish().expect("gzip into memory cannot fail");
    let kept = b64.finish().expect("base64 into memory cannot fail");
    match len.get() as f64 <= max {
        true => Ok(String::from_utf8(kept.kept).expect("base64 is ASCII")),
        false => Err((len.get(), whole)),
    }
}

/// The page: the viewer and the data (`data` writes it, gzipped and in
/// base64; `text`: the program text, packed likewise) as inert script
/// elements, a policy that lets only the viewer run and nothing load.
fn html(
    meta: &Value,
    data: impl FnOnce(&mut Vec<u8>) -> Result<(), Error>,
    text: Option<&str>,
) -> Result<Vec<u8>, Error> {
    let hash = base64::engine::general_purpose::STANDARD.encode(sha2::Sha256::digest(VIEWER_JS.as_bytes()));
    // JSON holds < > & only inside strings, where \u escapes mean the same.
    let meta = meta.to_string().replace('<', "\\u003c").replace('>', "\\u003e").replace('&', "\\u0026");
    let mut page = String::with_capacity(VIEWER_JS.len() + 4096);
    page.push_str("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n");
    page.push_str(&format!(
        "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'sha256-{hash}'; \
         style-src 'unsafe-inline'; img-src data: blob:\">\n"
    ));
    page.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    page.push_str("<title>kezuri view</title>\n<style>");
    page.push_str(VIEWER_CSS);
    page.push_str("</style>\n</head><body>\n");
    page.push_str(BODY);
    page.push_str("\n<script type=\"application/json\" id=\"kz-meta\">");
    page.push_str(&meta);
    page.push_str("</script>\n<script type=\"application/octet-stream\" id=\"kz-data\">");
    let mut page = page.into_bytes();
    data(&mut page)?;
    page.extend_from_slice(b"</script>\n");
    if let Some(text) = text {
        page.extend_from_slice(b"<script type=\"application/octet-stream\" id=\"kz-text\">");
        page.extend_from_slice(text.as_bytes());
        page.extend_from_slice(b"</script>\n");
    }
    page.extend_from_slice(b"<script>");
    page.extend_from_slice(VIEWER_JS.as_bytes());
    page.extend_from_slice(b"</script>\n</body></html>\n");
    Ok(page)
}
