//! From the tool microscope's pictures to the tool's measured profile
//! (`kezuri tool profile`).
//!
//! 1. Each field of view: the envelope of its frames (the darkest value of
//!    each pixel while the tool turns, [`Envelope`]: one frame in memory at
//!    a time, for the thermal and wear report's ~1,000 frames).
//! 2. One threshold for all: [`otsu`] over the envelopes, unless given.
//! 3. Fields placed ([`stitch::place`]) and joined ([`stitch::composite`]).
//! 4. The silhouette of the joined picture: per pixel row from the lowest
//!    point of the tool up, the radius of the swept envelope is half the
//!    distance between its edges — the distance needs no axis.
//! 5. The runout ([`runout_mm`]), from the frames of every field that sees
//!    both sides of the tool: half the swing of their silhouettes' centres
//!    ([`frame_centre`], a second pass over the frames once the threshold is
//!    known).

use kezuri_geom::ToolProfile;

use crate::stitch::{self, Placement};
use crate::tool_image::{median, otsu, runout, silhouette, GrayImage};
use crate::{Error, ErrorKind};

/// The envelope of a field's frames, one frame at a time.
#[derive(Clone, Debug, Default)]
pub struct Envelope {
    image: Option<GrayImage>,
    frames: usize,
}

impl Envelope {
    /// Takes in one frame; frames of another size than the first are
    /// refused (their size returned).
    pub fn add(&mut self, frame: &GrayImage) -> Result<(), (usize, usize)> {
        match &mut self.image {
            None => self.image = Some(frame.clone()),
            Some(e) if (e.width, e.height) != (frame.width, frame.height) => return Err((e.width, e.height)),
            Some(e) => {
                for (o, &v) in e.pixels.iter_mut().zip(&frame.pixels) {
                    *o = o.min(v);
                }
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// The field at stage offset `at`; `None` before any frame.
    pub fn field(self, at: [f64; 2]) -> Option<Field> {
        Some(Field { envelope: self.image?, frames: self.frames, at })
    }
}

/// One field of view: the envelope of its frames and its stage offset.
#[derive(Clone, Debug)]
pub struct Field {
    /// The darkest value of each pixel over the frames.
    pub envelope: GrayImage,
    /// How many frames.
    pub frames: usize,
    /// Where the field's pixel `(0, 0)` lies in the common frame, pixels,
    /// x right, y down.
    pub at: [f64; 2],
}

/// How to measure.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Side of a pixel on the tool, mm (0.71 µm in the thermal and wear report: 0.00071).
    pub pixel_mm: f64,
    /// Gray level (0–1) at or below which a pixel is tool; Otsu's if `None`.
    pub threshold: Option<f32>,
    /// How far, in pixels, the pictures may be off the stage offsets.
    pub search: usize,
    /// The row of the first field where a new tool's tip sits (the
    /// tool-length reference); the lowest point seen if `None`.
    pub tip_row: Option<f64>,
}

/// What the pictures say.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The swept profile, z up from the tip reference (mm).
    pub profile: ToolProfile,
    /// The threshold used.
    pub threshold: f32,
    /// The fields' positions.
    pub placement: Placement,
    /// The joined envelope.
    pub picture: GrayImage,
    /// Where `picture`'s pixel `(0, 0)` lies in the common frame.
    pub origin: [f64; 2],
    /// Per profile sample, the picture's row and the left and right edges.
    pub edges: Vec<(usize, f64, f64)>,
    /// The picture's row of z = 0.
    pub zero_row: f64,
    /// What the user should know.
    pub warnings: Vec<String>,
}

/// Least contrast between tool and backlight, full scale: below it the
/// pictures show no tool.
const MIN_CONTRAST: f32 = 0.1;

/// The tool measured from `fields` (see the module).
pub fn measure(fields: &[Field], options: &Options) -> Result<Measured, Error> {
    let fail = |kind: ErrorKind, s: String| Err(Error::new(kind, s));
    if fields.is_empty() {
        return fail(ErrorKind::BadPictures, "no pictures".into());
    }
    if let Some(k) = fields.iter().position(|f| f.envelope.width < 3 || f.envelope.height < 3) {
        let e = &fields[k].envelope;
        return fail(ErrorKind::BadPictures, format!("field {}: {}×{} pixels is too small", k + 1, e.width, e.height));
    }
    let envelopes: Vec<&GrayImage> = fields.iter().map(|f| &f.envelope).collect();
    let threshold = match options.threshold {
        Some(t) => t,
        None => match otsu(envelopes.iter().copied()) {
            Some(s) if s.bright - s.dark >= MIN_CONTRAST => s.threshold,
            Some(s) => {
                return fail(
                    ErrorKind::NoTool,
                    format!(
                        "no tool in the pictures: gray levels only from {:.3} to {:.3} of full scale (a dark tool \
                         on a bright backlight expected)",
                        s.dark, s.bright
                    ),
                )
            }
            None => {
                return fail(ErrorKind::NoTool, "no tool in the pictures: every pixel has the same gray level".into())
            }
        },
    };
    let placed: Vec<(&GrayImage, [f64; 2])> = fields.iter().map(|f| (&f.envelope, f.at)).collect();
    let placement = stitch::place(&placed, options.search)?;
    let (picture, origin) = stitch::composite(&envelopes, &placement.at);
    let Some(tool) = silhouette(&picture, threshold) else {
        return fail(
            ErrorKind::NoTool,
            format!("no tool in the pictures: no pixel at or below the threshold {threshold:.3}"),
        );
    };
    if tool.rows[0].is_none() {
        return fail(
            ErrorKind::NoTool,
            "the dark region does not reach the top of the picture: not a tool (shank up, tip down)".into(),
        );
    }
    let Some(tip) = tool.tip_row() else { unreachable!("a silhouette has a row") };
    let mut warnings = placement.warnings.clone();
    let mut edges = Vec::new();
    for r in (0..=tip).rev() {
        match tool.rows[r] {
            Some((l, rr)) if l.is_finite() && rr.is_finite() => edges.push((r, l, rr)),
            // The shank leaving the picture at its top is what it should do.
            Some(_) if r <= 3 => break,
            Some(_) => {
                warnings.push(format!(
                    "the tool runs out of the picture {} pixels above its tip: the profile stops there",
                    tip - r
                ));
                break;
            }
            None => break,
        }
    }
    if edges.len() < 2 {
        return fail(
            ErrorKind::ToolOutOfView,
            "the tool's edges are not inside the picture at its tip: widen the field of view".into(),
        );
    }
    let zero_row = match options.tip_row {
        // Rows of the first picture that the pictures together cover.
        Some(row) if !(0.0..=picture.height as f64).contains(&(row + placement.at[0][1] - origin[1])) => {
            let first = origin[1] - placement.at[0][1];
            return fail(
                ErrorKind::TipRowOutside,
                format!(
                    "the tip row {row} is outside the pictures (rows {first:.0} to {:.0} of the first one): the \
                     tool-length reference must be a row they show",
                    first + picture.height as f64
                ),
            );
        }
        Some(row) => row + placement.at[0][1] - origin[1],
        None => tip as f64,
    };
    let px = options.pixel_mm;
    let z = edges.iter().map(|&(r, ..)| (zero_row - r as f64) * px).collect();
    let radius = edges.iter().map(|&(_, l, r)| 0.5 * (r - l) * px).collect();
    let profile = ToolProfile::new(z, radius).map_err(|e| Error::new(ErrorKind::BadProfile, e.to_string()))?;
    Ok(Measured { profile, threshold, placement, picture, origin, edges, zero_row, warnings })
}

/// The middle of the tool's silhouette in one frame (the median over the
/// rows where both edges are inside the picture), pixels; `None` where the
/// frame does not show both sides of the tool.
pub fn frame_centre(frame: &GrayImage, threshold: f32) -> Option<f64> {
    silhouette(frame, threshold)?.centre()
}

/// The eccentricity of the turning tool, mm, from each field's frames'
/// centres (`None` for a frame without both sides): the median over the
/// fields where more than half the frames, and at least 3, show both sides
/// of [`runout`]; `None` when no field does.
pub fn runout_mm(centres: &[Vec<Option<f64>>], pixel_mm: f64) -> Option<f64> {
    let mut per_field: Vec<f64> = centres
        .iter()
        .filter_map(|frames| {
            let seen: Vec<f64> = frames.iter().flatten().copied().collect();
            (seen.len() * 2 > frames.len()).then(|| runout(&seen)).flatten()
        })
        .collect();
    median(&mut per_field).map(|e| e * pixel_mm)
}

/// A warning for the user when the runout could not be measured.
pub const NO_RUNOUT: &str =
    "no runout: it needs a field that sees both sides of the tool in at least 3 frames of it turning";

/// [`measure`] and [`runout_mm`] for frames held in memory, per field
/// `(frames, stage offset)`.
pub fn measure_frames(
    fields: &[(Vec<GrayImage>, [f64; 2])],
    options: &Options,
) -> Result<(Measured, Option<f64>), Error> {
    let mut placed = Vec::with_capacity(fields.len());
    for (k, (frames, at)) in fields.iter().enumerate() {
        let mut e = Envelope::default();
        for (i, f) in frames.iter().enumerate() {
            e.add(f).map_err(|(w, h)| {
                Error::new(
                    ErrorKind::BadPictures,
                    format!("field {}: frame {} is {}×{} pixels, the first {w}×{h}", k + 1, i + 1, f.width, f.height),
                )
            })?;
        }
        placed.push(
            e.field(*at).ok_or_else(|| Error::new(ErrorKind::BadPictures, format!("field {}: no frames", k + 1)))?,
        );
    }
    let m = measure(&placed, options)?;
    let centres: Vec<Vec<Option<f64>>> =
        fields.iter().map(|(frames, _)| frames.iter().map(|f| frame_centre(f, m.threshold)).collect()).collect();
    let runout = runout_mm(&centres, options.pixel_mm);
    Ok((m, runout))
}
