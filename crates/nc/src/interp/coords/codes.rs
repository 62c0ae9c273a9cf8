//! The G codes that set the transforms: G68/G69 rotation, G51/G50
//! scaling, G51.1/G50.1 mirror, G16/G15 polar coordinates and G90.1/G91.1
//! arc centres, and the modal groups `#4011`… read back.

use super::{Control, Rotation, Scale, LETTERS};
use crate::interp::modal::{Distance, GCode};
use crate::interp::words::Words;
use crate::interp::State;
use crate::source::{Diagnostic, Span};

impl State {
    /// The G codes of these transforms, from `apply_modal`: `true` when `code` is
    /// one of them (then applied). Also refuses a plane change under G68.
    pub(in crate::interp) fn coords_modal(&mut self, code: GCode, w: &Words, gspan: Span) -> Result<bool, Diagnostic> {
        let linuxcnc = self.settings.coords.control == Control::LinuxCnc;
        match code {
            GCode::Plane(p) => {
                if self.coords.rotation.is_some_and(|r| r.plane != p) {
                    return Err(Diagnostic::error(gspan, "the plane cannot change under G68 rotation: give G69 first"));
                }
                return Ok(false);
            }
            GCode::Rotation(_) | GCode::Scaling(_) | GCode::Mirror(_) | GCode::Polar(_) if linuxcnc => {
                return Err(Diagnostic::error(
                    gspan,
                    "LinuxCNC has no G68/G69, G51/G50, G51.1/G50.1 or G15/G16: it stops with \"Unknown g code used\"",
                ));
            }
            GCode::ArcCentre(d) => {
                if !linuxcnc {
                    let name = if d == Distance::Absolute { "G90.1" } else { "G91.1" };
                    self.warn(
                        "arc-centre-mode",
                        gspan,
                        format!("{name} is not a Fanuc G code: a Fanuc control stops with alarm PS0010 (improper G code); read here as LinuxCNC reads it (I J K {})", if d == Distance::Absolute { "absolute" } else { "incremental, the Fanuc default" }),
                    );
                }
                self.coords.arc_absolute = d == Distance::Absolute;
            }
            GCode::Polar(on) => self.coords.polar = on,
            GCode::Rotation(false) => self.coords.rotation = None,
            GCode::Rotation(true) => self.rotate(w, gspan)?,
            GCode::Scaling(false) => self.coords.scale = None,
            GCode::Scaling(true) => self.scaling(w, gspan)?,
            GCode::Mirror(on) => {
                // Haas G101 X… mirrors the named axes about the work zero
                // (the words' values do not matter), G100 ends it.
                let haas = w.g[..w.g_count].iter().any(|&(t, _)| t == 1010 || t == 1000);
                let name = match (haas, on) {
                    (true, true) => "G101",
                    (true, false) => "G100",
                    (false, true) => "G51.1",
                    (false, false) => "G50.1",
                };
                if haas && self.settings.coords.control != Control::Haas {
                    return Err(Diagnostic::error(
                        gspan,
                        format!(
                            "{name} is Haas's mirror image: read the program with --dialect haas (Fanuc: G51.1/G50.1)"
                        ),
                    ));
                }
                let named: Vec<usize> = (0..3).filter(|&i| w.has(LETTERS[i])).collect();
                for (i, &letter) in LETTERS[..3].iter().enumerate() {
                    if on {
                        if let Some(v) = w.get(letter) {
                            self.coords.mirror[i] = Some(if haas { 0.0 } else { self.mm(v) });
                        }
                    } else if named.is_empty() || named.contains(&i) {
                        self.coords.mirror[i] = None;
                    }
                }
                if on && named.is_empty() {
                    let what = if haas { "the axes to mirror" } else { "the mirror line" };
                    return Err(Diagnostic::error(gspan, format!("{name} needs {what}: X, Y or Z")));
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// `G68 α β R`: centre on the plane's axes (absolute; omitted: where the
    /// tool is), R degrees (omitted: 0, parameter 5410).
    fn rotate(&mut self, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        let plane = self.modal.plane;
        let (i, j, _) = plane.axes();
        self.centre_known(w, &[i, j], gspan, "G68")?;
        let mut c = self.program_position().to_array();
        for k in [i, j] {
            if let Some(v) = w.get(LETTERS[k]) {
                c[k] = self.mm(v);
            }
        }
        let c = self.coords.sm(c);
        let r = self.ratio(w, b'R').unwrap_or(0.0);
        // Parameter 5400 bit 0 (RIN): R under G91 adds to the angle in effect.
        let degrees = match self.coords.rotation {
            Some(old) if self.settings.coords.rotation_incremental && self.modal.distance == Distance::Incremental => {
                old.degrees + r
            }
            _ => r,
        };
        self.coords.rotation = Some(Rotation { plane, centre: [c[i], c[j]], degrees });
        Ok(())
    }

    /// A centre left out is the tool's position (Fanuc); where the program
    /// has not named that position yet, it is only the machine model's
    /// guess: an error rather than a rotation about an unknown point.
    fn centre_known(&self, w: &Words, axes: &[usize], gspan: Span, code: &str) -> Result<(), Diagnostic> {
        let unknown: String = axes
            .iter()
            .filter(|&&k| !w.has(LETTERS[k]) && self.guessed.contains(k))
            .map(|&k| LETTERS[k] as char)
            .collect();
        if unknown.is_empty() {
            return Ok(());
        }
        Err(Diagnostic::error(
            gspan,
            format!(
                "{code} without its centre in {unknown} takes the tool's position for it, which the program has not named yet: give the centre"
            ),
        ))
    }

    /// `G51 X Y Z P` or `G51 X Y Z I J K`: centre (absolute; omitted: where
    /// the tool is) and factors.
    fn scaling(&mut self, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        let (i, j, _) = self.modal.plane.axes();
        self.centre_known(w, &[i, j], gspan, "G51")?;
        let p0 = self.program_position().to_array();
        let centre: [f64; 3] = std::array::from_fn(|i| w.get(LETTERS[i]).map_or(p0[i], |v| self.mm(v)));
        let mut factor = [1.0; 3];
        if let Some(p) = self.ratio(w, b'P') {
            factor = [p; 3];
        }
        for (i, letter) in [b'I', b'J', b'K'].into_iter().enumerate() {
            if let Some(v) = self.ratio(w, letter) {
                factor[i] = v;
            }
        }
        if !(w.has(b'P') || w.has(b'I') || w.has(b'J') || w.has(b'K')) {
            self.warn("scale-default", gspan, "G51 without P or I J K: the factor is parameter 5411's, read as 1");
        }
        for letter in [b'P', b'I', b'J', b'K'] {
            if self.ratio(w, letter).is_some_and(|v| v == 0.0 || !v.is_finite()) {
                return Err(Diagnostic::error(
                    w.span(letter),
                    format!("G51 {}0: a scale factor of 0 would put every point on the centre", letter as char),
                ));
            }
        }
        self.coords.scale = Some(Scale { centre, factor });
        Ok(())
    }

    /// `#4011`, `#4016`, `#4017`, `#4022`: the modal groups of these
    /// transforms.
    pub(in crate::interp) fn coords_group(&self, group: u32) -> Option<f64> {
        Some(match group {
            11 => {
                if self.coords.scale.is_some() {
                    51.0
                } else {
                    50.0
                }
            }
            16 => {
                if self.coords.rotation.is_some() {
                    68.0
                } else {
                    69.0
                }
            }
            17 => {
                if self.coords.polar {
                    16.0
                } else {
                    15.0
                }
            }
            22 => {
                if self.coords.mirror.iter().any(Option::is_some) {
                    51.1
                } else {
                    50.1
                }
            }
            _ => return None,
        })
    }
}
