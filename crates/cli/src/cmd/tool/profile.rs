//! `kezuri tool profile`: a tool's measured cutting profile from backlit
//! images. Its neighbours under `kezuri tool`, the database of each tool's
//! profiles as it wears (`tool db`, cmd/tool/db.rs) and the tool tables of other
//! programs' files (`tool table`, cmd/tool/table.rs, over `kezuri_machine::tool_table`),
//! are commands of their own.
//! The profile CSV (tool_profile.rs) is `z_mm,radius_mm` (and `wear_mm`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use kezuri_cam::Cutter;
use kezuri_correct::microscope::{frame_centre, measure, runout_mm, Envelope, Measured, Options, NO_RUNOUT};
use kezuri_correct::tool_image::GrayImage;
use kezuri_picture::figure::{Figure, Overlay, Panel, Raster};
use serde_json::json;

use crate::files::{read_text, Outputs};
use crate::table::Table;
use crate::tool_profile::profile_csv;

/// `kezuri tool profile IMAGE… --pixel-um UM -o PROFILE.csv`.
#[derive(Args, Debug)]
#[command(after_help = "The pictures: backlit, the tool axis vertical, tip down, the tool dark on a bright backlight
(PNG, TIFF, BMP, JPEG or PGM, 8 or 16 bit), many frames of the tool turning. Their envelope (the
darkest value of each pixel) is the swept cutting profile; the tool's edges are found to a fraction
of a pixel where the gray level crosses the threshold. The radius is half the width between the
edges, so it needs no axis; the runout is half the swing of the frames' silhouette centres.

A tool larger than the field of view: give each picture's stage position in --offsets, a CSV
`image,x_mm,z_mm` (x to the right of the picture, z up the tool; the pictures that share a
position are one field). Overlapping fields are matched to a fraction of a pixel (100 µm of
overlap across and 70 µm along the tool are plenty).

PROFILE.csv: z_mm,radius_mm (and wear_mm with --nominal: nominal + runout - measured), one row per
pixel row from the lowest point of the tool up; z from --tip-row, the row of the first picture
where a new tool's tip sits, so a worn tip starts above 0.

Examples:
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      --nominal ball:0.5 -o t7-new.csv --png t7-new.png
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      --nominal ball:0.5 -o t7-worn.csv --json")]
pub struct ProfileArgs {
    /// The pictures.
    #[arg(required = true, value_name = "IMAGE")]
    pub images: Vec<PathBuf>,
    /// Side of a pixel on the tool, micrometres (for example 0.71).
    #[arg(long, value_name = "UM", value_parser = crate::numbers::length)]
    pub pixel_um: f64,
    /// The row of the first picture where a new tool's tip sits (the tool-length reference);
    /// without it the lowest point seen is z = 0.
    #[arg(long, value_name = "ROW")]
    pub tip_row: Option<f64>,
    /// Stage positions of the pictures: CSV image,x_mm,z_mm.
    #[arg(long, value_name = "FILE")]
    pub offsets: Option<PathBuf>,
    /// How far the pictures may be off their stage positions, micrometres.
    #[arg(long, value_name = "UM", default_value_t = 15.0, value_parser = crate::numbers::length)]
    pub search_um: f64,
    /// Gray level at or below which a pixel is tool, 0-1 of full scale [default: the level that
    /// best splits the pictures' grays into tool and backlight, Otsu's method].
    #[arg(long, value_name = "LEVEL")]
    pub threshold: Option<f32>,
    /// The new tool, ball:D (ball end mill of diameter D) or bull:D,R (bull-nose, corner radius
    /// R), mm: adds the wear along the profile.
    #[arg(long, value_name = "SPEC")]
    pub nominal: Option<String>,
    /// The profile CSV [default: standard output].
    #[arg(short, long, value_name = "PROFILE.csv")]
    pub output: Option<PathBuf>,
    /// A picture of the joined envelope with the edges found (red) and the nominal tool
    /// (green, with the runout).
    #[arg(long, value_name = "FILE.png")]
    pub png: Option<PathBuf>,
    /// Print one JSON object: frames, runout_mm, max_radius_mm, fields, threshold, max_wear_mm,
    /// warnings.
    #[arg(long)]
    pub json: bool,
}

/// A picture as gray values 0-1.
fn read_picture(path: &Path) -> Result<GrayImage> {
    let g = crate::gray::read_gray(path)?;
    Ok(GrayImage { width: g.width, height: g.height, pixels: g.v.iter().map(|&v| v as f32).collect() })
}

/// The pictures grouped into fields by their stage positions (pixels).
fn fields(a: &ProfileArgs) -> Result<Vec<(Vec<&PathBuf>, [f64; 2])>> {
    let Some(file) = &a.offsets else { return Ok(vec![(a.images.iter().collect(), [0.0, 0.0])]) };
    let name = file.display().to_string();
    let t = Table::parse(&name, &read_text(file)?)?;
    let (ic, xc, zc) = (
        t.require("image", "image,x_mm,z_mm")?,
        t.require("x_mm", "image,x_mm,z_mm")?,
        t.require("z_mm", "image,x_mm,z_mm")?,
    );
    let mut at: BTreeMap<String, [f64; 2]> = BTreeMap::new();
    for r in 0..t.len() {
        let (x, z) = (t.number(r, xc)?, t.number(r, zc)?);
        at.insert(t.text(r, ic)?.to_string(), [x, z]);
    }
    let px = a.pixel_um / 1000.0;
    let mut groups: Vec<(Vec<&PathBuf>, [f64; 2])> = Vec::new();
    for image in &a.images {
        let by_name = image.file_name().map(|n| n.to_string_lossy().to_string());
        let Some(&[x, z]) = at.get(&image.display().to_string()).or_else(|| by_name.and_then(|n| at.get(&n))) else {
            bail!("{name}: no row for the picture {} (its path or file name in the image column)", image.display());
        };
        let p = [x / px, -z / px];
        match groups.iter_mut().find(|g| g.1 == p) {
            Some(g) => g.0.push(image),
            None => groups.push((vec![image], p)),
        }
    }
    Ok(groups)
}

/// Runs `kezuri tool profile`.
pub fn run(a: &ProfileArgs) -> Result<()> {
    if a.json && a.output.as_deref().is_none_or(|o| o == Path::new("-")) {
        bail!("--json prints to standard output: give the profile a file with -o");
    }
    if let Some(t) = a.threshold.filter(|t| !(0.0..=1.0).contains(t)) {
        bail!("--threshold is a gray level from 0 to 1 of full scale, got {t}");
    }
    let nominal: Option<Cutter> = a.nominal.as_deref().map(str::parse).transpose().context("--nominal")?;
    let groups = fields(a)?;
    let total: usize = groups.iter().map(|g| g.0.len()).sum();
    let bar = crate::progress::bar("reading", "pictures", 2 * total as u64, 50);
    let mut placed = Vec::with_capacity(groups.len());
    for (images, at) in &groups {
        let mut e = Envelope::default();
        for path in images {
            e.add(&read_picture(path)?).map_err(|(w, h)| {
                anyhow!("{}: not the size of the other pictures of its field ({w}×{h})", path.display())
            })?;
            if let Some(b) = &bar {
                b.inc(1);
            }
        }
        placed.push(e.field(*at).ok_or_else(|| anyhow!("a field without pictures"))?);
    }
    let px = a.pixel_um / 1000.0;
    let options = Options {
        pixel_mm: px,
        threshold: a.threshold,
        search: (a.search_um / a.pixel_um).ceil() as usize,
        tip_row: a.tip_row,
    };
    let m = measure(&placed, &options)?;
    // Second pass, one picture at a time: each frame's centre.
    let mut centres = Vec::with_capacity(groups.len());
    for (images, _) in &groups {
        let mut field = Vec::with_capacity(images.len());
        for path in images {
            field.push(frame_centre(&read_picture(path)?, m.threshold));
            if let Some(b) = &bar {
                b.inc(1);
            }
        }
        centres.push(field);
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let runout = runout_mm(&centres, px);
    let mut warnings = m.warnings.clone();
    if runout.is_none() {
        warnings.push(NO_RUNOUT.to_string());
    }
    let wear: Option<Vec<f64>> = nominal.map(|c| {
        let e = runout.unwrap_or(0.0);
        m.profile.z().iter().zip(m.profile.radius()).map(|(&z, &r)| c.radius_at(z) + e - r).collect()
    });
    // Everything made before anything is written.
    let title = format!(
        "{}: the profile of {total} picture{}",
        a.output.as_deref().and_then(Path::file_name).map_or_else(|| "-".into(), |n| n.to_string_lossy().into_owned()),
        if total == 1 { "" } else { "s" }
    );
    let spec = a.nominal.as_deref().unwrap_or_default();
    let picture = a
        .png
        .as_ref()
        .map(|_| overlay_png(&m, nominal.as_ref().map(|c| (spec, c)), runout.unwrap_or(0.0), px, &title))
        .transpose()?;
    let mut out = Outputs::new();
    out.add(a.output.as_deref(), profile_csv(&m.profile, wear.as_deref()).as_bytes())?;
    if let (Some(png), Some(picture)) = (&a.png, picture) {
        out.add(Some(png), &picture)?;
    }
    out.commit()?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let max_wear = wear.as_ref().map(|w| w.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    if a.json {
        let v = json!({
            "frames": total,
            "fields": groups.len(),
            "runout_mm": runout,
            "max_radius_mm": m.profile.max_radius(),
            "tip_z_mm": m.profile.tip(),
            "top_z_mm": m.profile.top(),
            "samples": m.profile.z().len(),
            "threshold": m.threshold,
            "field_offsets_px": m.placement.at,
            "max_wear_mm": max_wear,
            "warnings": warnings,
        });
        println!("{v}");
    } else {
        crate::say::note!(
            "wrote {}: {} samples from z {:.4} to {:.4} mm, largest radius {:.4} mm, runout {}{}",
            crate::say::shown(a.output.as_deref()),
            m.profile.z().len(),
            m.profile.tip(),
            m.profile.top(),
            m.profile.max_radius(),
            runout.map_or_else(|| "not measured".into(), |e| format!("{e:.4} mm")),
            max_wear.map_or_else(String::new, |w| format!(", largest wear {w:.4} mm")),
        );
    }
    Ok(())
}

/// The joined envelope in gray, the edges found in red, the nominal tool
/// with the runout in green (about the middle of the edges at the top),
/// framed: titled `title`, axes in mm from the axis and the tip, a legend.
fn overlay_png(m: &Measured, nominal: Option<(&str, &Cutter)>, runout: f64, px: f64, title: &str) -> Result<Vec<u8>> {
    let (w, h) = (m.picture.width, m.picture.height);
    let rgb: Vec<u8> = m
        .picture
        .pixels
        .iter()
        .flat_map(|&v| {
            let g = if v.is_nan() { 40 } else { (v.clamp(0.0, 1.0) * 255.0) as u8 };
            [g, g, g]
        })
        .collect();
    let mut mids: Vec<f64> = m.edges.iter().map(|&(_, l, r)| 0.5 * (l + r)).collect();
    let axis = kezuri_correct::tool_image::median(&mut mids).unwrap_or(w as f64 / 2.0);
    let (red, green) = ("rgb(230,0,0)", "rgb(0,170,0)");
    let mut overlays = Vec::new();
    let mut legend = vec![("rgb(70,70,70)".to_string(), "the tool: the envelope of the pictures (dark)".to_string())];
    if let Some((spec, c)) = nominal {
        let (mut left, mut right) = (Vec::new(), Vec::new());
        for &(r, ..) in &m.edges {
            let z = (m.zero_row - r as f64) * px;
            if z >= 0.0 {
                let half = (c.radius_at(z) + runout) / px;
                left.push((axis - half + 0.5, r as f64 + 0.5));
                right.push((axis + half + 0.5, r as f64 + 0.5));
            }
        }
        for points in [left, right] {
            overlays.push(Overlay { points, colour: green.into(), width: 4.0 });
        }
        legend.push((green.into(), format!("nominal {spec}, widened by the runout {:.4} mm", runout)));
    }
    let found = |side: fn(&(usize, f64, f64)) -> f64| -> Vec<(f64, f64)> {
        m.edges.iter().filter(|e| side(e).is_finite()).map(|e| (side(e) + 0.5, e.0 as f64 + 0.5)).collect()
    };
    overlays.push(Overlay { points: found(|e| e.1), colour: red.into(), width: 1.5 });
    overlays.push(Overlay { points: found(|e| e.2), colour: red.into(), width: 1.5 });
    legend.push((red.into(), "edges found: the profile written".into()));
    let top = m.zero_row * px;
    Ok(Figure {
        title: title.into(),
        subtitle: format!("{w} × {h} pixels of {:.2} µm; z up from the nominal tip", px * 1000.0),
        panels: vec![Panel {
            raster: Raster { width: w, height: h, rgb },
            extent: [-axis * px, (w as f64 - axis) * px, top - h as f64 * px, top],
            axes: ["from the axis, mm".into(), "z, mm".into()],
            caption: String::new(),
            overlays,
        }],
        stacked: false,
        bar: None,
        legend,
    }
    .png()?)
}
