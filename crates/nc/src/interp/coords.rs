//! Coordinate systems between the program and the machine: the G52 local
//! offset, G68/G69 rotation, G51/G50 scaling, G51.1/G50.1 programmable
//! mirror, G16/G15 polar coordinates, G90.1/G91.1 arc centres, G30 P2–P4
//! and G53 under G91. `docs/coordinates.md` lists every rule and where it
//! comes from.
//!
//! A program point `p` (the words, in program units converted to mm) goes
//! to the machine as
//! `machine = rotate(scale(mirror(p))) + G52 + work offset + external + G92`:
//! mirror and scaling about their centres, then rotation about its centre
//! in its plane. Polar words (G16) are turned into the Cartesian `p` first.
//! Increments (G91) are increments of `p`: they move the tool by the
//! transformed vector from where it is.
//!
//! The position a program reads (`#5001…`) and builds on (unnamed axes,
//! increments) is the *program position*: the tool's position mapped back
//! through the transforms, plus `delta`, the difference a Fanuc control
//! keeps between its absolute-position register and the tool after G68 or
//! G51 is given away from its centre (the register is not recomputed then;
//! the next absolute move brings them together again).

use kezuri_geom::{Axes, AxisSet, MoveKind, Plane};

use super::modal::{Distance, GCode, Units};
use super::words::Words;
use super::{IntegerInput, State};
use crate::source::{Diagnostic, Span};

mod codes;

/// The control whose rules apply where controls differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Control {
    /// Fanuc.
    #[default]
    Fanuc,
    /// Haas: Fanuc's rules, but a G28 without axis words returns every
    /// axis, and G28 cancels the tool length offset.
    Haas,
    /// LinuxCNC: G52 shares the G92 offset, G53 under G91 is an error, G90.1
    /// and G91.1 are arc-centre modes; G68, G51, G51.1 and G16 do not exist.
    LinuxCnc,
}

/// The settings of coordinate systems that depend on the control or the
/// machine (parameters on a Fanuc control).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CoordSettings {
    /// Which control's rules apply.
    pub control: Control,
    /// `G68 R` follows G90/G91 (incremental under G91: added to the angle in
    /// effect) instead of being always absolute: bit 0 (RIN) of Fanuc
    /// parameter 5400. Off by default.
    pub rotation_incremental: bool,
    /// Machine positions of the 2nd, 3rd and 4th reference points
    /// (`G30 P2`, `P3`, `P4`; Fanuc parameters 1241, 1242, 1243).
    pub reference_points: [Axes; 3],
}

/// G51 scaling.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Scale {
    /// Centre in program coordinates (X Y Z, mm).
    centre: [f64; 3],
    /// Factor of each axis (negative: a mirror image).
    factor: [f64; 3],
}

/// G68 rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Rotation {
    plane: Plane,
    /// Centre on the plane's two axes, after mirror and scaling.
    centre: [f64; 2],
    /// Degrees, counter-clockwise from the plane's first axis to its second,
    /// as programmed (a mirror image reverses its sense).
    degrees: f64,
}

/// The transforms in effect, and the program-position register.
#[derive(Clone, Debug, Default)]
pub(super) struct Transforms {
    /// Fanuc G52 local offset (mm; on LinuxCNC G52 writes the G92 offset).
    pub(super) local: [f64; N],
    /// G16 polar coordinate mode.
    polar: bool,
    /// G51.1: the position of the mirror line on each of X Y Z.
    mirror: [Option<f64>; 3],
    scale: Option<Scale>,
    rotation: Option<Rotation>,
    /// G90.1: I J K are absolute positions.
    pub(super) arc_absolute: bool,
    /// Program position minus the tool's position mapped back.
    delta: [f64; N],
    /// The program point of the move being made (set with its target).
    pending: Option<[f64; N]>,
}

const LETTERS: &[u8; N] = &Axes::LETTERS;
/// How many axes a position has.
const N: usize = Axes::COUNT;

fn deg(v: f64) -> (f64, f64) {
    v.to_radians().sin_cos()
}

impl Transforms {
    /// Whether any transform between program and local coordinates is on.
    fn active(&self) -> bool {
        self.mirror.iter().any(Option::is_some) || self.scale.is_some() || self.rotation.is_some()
    }

    /// The factor mirror and scaling multiply axis `i` by.
    fn factor(&self, i: usize) -> f64 {
        if i >= 3 {
            return 1.0;
        }
        let m = if self.mirror[i].is_some() { -1.0 } else { 1.0 };
        m * self.scale.map_or(1.0, |s| s.factor[i])
    }

    /// Whether mirror and scaling turn the plane over (an odd number of its
    /// two axes reversed): arcs and compensation sides swap, G68 turns back.
    pub(super) fn reverses(&self, plane: Plane) -> bool {
        let (i, j, _) = plane.axes();
        self.factor(i) * self.factor(j) < 0.0
    }

    /// Mirror then scaling of a point.
    #[allow(clippy::needless_range_loop)]
    fn sm(&self, p: [f64; N]) -> [f64; N] {
        let mut q = p;
        for i in 0..3 {
            if let Some(m) = self.mirror[i] {
                q[i] = 2.0 * m - q[i];
            }
            if let Some(s) = self.scale {
                // The centre is a program point too: mirrored with the rest.
                let c = self.mirror[i].map_or(s.centre[i], |m| 2.0 * m - s.centre[i]);
                q[i] = c + s.factor[i] * (q[i] - c);
            }
        }
        q
    }

    #[allow(clippy::needless_range_loop)]
    fn sm_inverse(&self, q: [f64; N]) -> [f64; N] {
        let mut p = q;
        for i in 0..3 {
            if let Some(s) = self.scale {
                let c = self.mirror[i].map_or(s.centre[i], |m| 2.0 * m - s.centre[i]);
                p[i] = c + (p[i] - c) / s.factor[i];
            }
            if let Some(m) = self.mirror[i] {
                p[i] = 2.0 * m - p[i];
            }
        }
        p
    }

    /// The rotation's axes and angle as applied (reversed by a mirror image).
    fn turn(&self) -> Option<(usize, usize, [f64; 2], f64)> {
        let r = self.rotation?;
        let (i, j, _) = r.plane.axes();
        let sense = if self.reverses(r.plane) { -1.0 } else { 1.0 };
        Some((i, j, r.centre, sense * r.degrees))
    }

    /// Program point to local coordinates (work coordinates plus G52 and G92).
    fn forward(&self, p: [f64; N]) -> [f64; N] {
        let mut q = self.sm(p);
        if let Some((i, j, c, a)) = self.turn() {
            let (s, co) = deg(a);
            let (x, y) = (q[i] - c[0], q[j] - c[1]);
            q[i] = c[0] + co * x - s * y;
            q[j] = c[1] + s * x + co * y;
        }
        q
    }

    fn inverse(&self, q: [f64; N]) -> [f64; N] {
        let mut q = q;
        if let Some((i, j, c, a)) = self.turn() {
            let (s, co) = deg(-a);
            let (x, y) = (q[i] - c[0], q[j] - c[1]);
            q[i] = c[0] + co * x - s * y;
            q[j] = c[1] + s * x + co * y;
        }
        self.sm_inverse(q)
    }

    /// A vector (an increment, an arc's I J K) to local coordinates.
    fn linear(&self, v: [f64; N]) -> [f64; N] {
        let mut q: [f64; N] = std::array::from_fn(|i| v[i] * self.factor(i));
        if let Some((i, j, _, a)) = self.turn() {
            let (s, co) = deg(a);
            let (x, y) = (q[i], q[j]);
            q[i] = co * x - s * y;
            q[j] = s * x + co * y;
        }
        q
    }
}

fn sub(a: [f64; N], b: [f64; N]) -> [f64; N] {
    std::array::from_fn(|i| a[i] - b[i])
}

fn add(a: [f64; N], b: [f64; N]) -> [f64; N] {
    std::array::from_fn(|i| a[i] + b[i])
}

impl State {
    /// The tool tip in local coordinates: work coordinates with the G52 and
    /// G92 shifts, before rotation, scaling and mirror are undone.
    fn local_position(&self) -> [f64; N] {
        sub(self.tip.to_array(), self.frame_offset().to_array())
    }

    /// The position in program coordinates: what `#5001…` read and what
    /// unnamed axes and increments build on.
    pub(super) fn program_position(&self) -> Axes {
        if !self.coords.active() {
            return Axes::from_array(add(self.local_position(), self.coords.delta));
        }
        Axes::from_array(add(self.coords.inverse(self.local_position()), self.coords.delta))
    }

    /// A ratio or angle word: where it was written without a decimal point
    /// on a Fanuc control it counts 0.001 whatever the units (the reader
    /// divided inch words by 10,000).
    fn ratio(&self, w: &Words, letter: u8) -> Option<f64> {
        let v = w.get(letter)?;
        let inch_counts = self.modal.units == Units::Inch
            && self.settings.integer_input == IntegerInput::Increments
            && !w.decimal(letter);
        Some(if letter == b'P' && !w.decimal(b'P') && self.settings.integer_input == IntegerInput::Increments {
            v / 1000.0
        } else if inch_counts && letter != b'P' {
            v * 10.0
        } else {
            v
        })
    }

    /// LinuxCNC's polar words `@` (radius) and `^` (angle, degrees from +X,
    /// counter-clockwise): the X Y they name, in program coordinates (mm).
    /// Both are about the XY zero: under G90 the values themselves (a word
    /// left out keeps the tool's radius or angle), under G91 added to the
    /// tool's radius and angle. `None` where the block has neither.
    fn polar_point(&self, w: &Words) -> Option<[f64; 2]> {
        if !w.polar() {
            return None;
        }
        let p0 = self.program_position().to_array();
        let (r0, a0) = (p0[0].hypot(p0[1]), p0[1].atan2(p0[0]).to_degrees());
        let incremental = self.modal.distance == Distance::Incremental;
        let base = |v: f64| if incremental { v } else { 0.0 };
        let r = w.get(b'@').map_or(r0, |v| base(r0) + self.mm(v));
        let a = w.get(b'^').map_or(a0, |v| base(a0) + v);
        let (s, c) = deg(a);
        Some([r * c, r * s])
    }

    /// LinuxCNC's errors for polar words: an incremental polar move from
    /// the XY zero (its angle is undefined there).
    pub(super) fn polar_from_origin(&self, w: &Words, span: Span) -> Result<(), Diagnostic> {
        if !w.polar() || self.modal.distance != Distance::Incremental {
            return Ok(());
        }
        let p = self.program_position();
        if p.x.hypot(p.y) < 1e-9 {
            let at = if w.has(b'@') { w.span(b'@') } else { w.span(b'^') };
            let at = if at == Span::default() { span } else { at };
            return Err(Diagnostic::error(
                at,
                "an incremental (G91) polar move cannot start at the XY zero: its angle is undefined there (LinuxCNC stops too)",
            ));
        }
        Ok(())
    }

    /// The end point, in machine coordinates, that the axis words ask for;
    /// remembers the program point for [`State::settle_program`].
    pub(super) fn program_target(&mut self, w: &Words) -> Axes {
        if !self.coords.polar && !self.coords.active() && self.coords.delta == [0.0; N] {
            // No transform in force (most blocks of most programs): the
            // words on the work position, nothing to remember.
            let (t, o) = (self.tip.to_array(), self.frame_offset().to_array());
            let mut p = sub(t, o);
            let incremental = self.modal.distance == Distance::Incremental;
            for (i, v) in w.axis_words() {
                let v = if Axes::is_linear(i) { self.mm(v) } else { v };
                p[i] = if incremental { p[i] + v } else { v };
            }
            if let Some([x, y]) = self.polar_point(w) {
                (p[0], p[1]) = (x, y);
            }
            self.coords.pending = None;
            return Axes::from_array(add(p, o));
        }
        let p0 = self.program_position().to_array();
        let mut p = p0;
        let incremental = self.modal.distance == Distance::Incremental;
        let mut from_zero = !incremental;
        let plane = self.modal.plane.axes();
        for (i, v) in w.axis_words() {
            if self.coords.polar && (i == plane.0 || i == plane.1) {
                continue;
            }
            let v = if Axes::is_linear(i) { self.mm(v) } else { v };
            p[i] = if incremental { p[i] + v } else { v };
        }
        if let Some([x, y]) = self.polar_point(w) {
            (p[0], p[1]) = (x, y);
        }
        if self.coords.polar {
            let (i, j) = (plane.0, plane.1);
            let (radius, angle) = (w.get(LETTERS[i]).map(|v| self.mm(v)), w.get(LETTERS[j]));
            if radius.is_some() || angle.is_some() {
                // The radius measured from the work zero, or (an incremental
                // radius) from the tool; the angle from the plane's first
                // axis, or added to the tool's angle about the work zero.
                let (r0, a0) = (p0[i].hypot(p0[j]), p0[j].atan2(p0[i]).to_degrees());
                let a = match angle {
                    Some(a) if incremental => a0 + a,
                    Some(a) => a,
                    None => a0,
                };
                let (s, c) = deg(a);
                match radius {
                    Some(r) if incremental => {
                        p[i] = p0[i] + r * c;
                        p[j] = p0[j] + r * s;
                    }
                    _ => {
                        let r = radius.unwrap_or(r0);
                        p[i] = r * c;
                        p[j] = r * s;
                        from_zero = true;
                    }
                }
            }
        }
        let local = if from_zero && !incremental {
            self.coords.forward(p)
        } else if from_zero {
            // Polar from the work zero under G91: the plane's axes are
            // positions, the others increments.
            let mut q = add(self.local_position(), self.coords.linear(sub(p, p0)));
            let f = self.coords.forward(p);
            q[plane.0] = f[plane.0];
            q[plane.1] = f[plane.1];
            q
        } else {
            add(self.local_position(), self.coords.linear(sub(p, p0)))
        };
        self.coords.pending = Some(p);
        Axes::from_array(add(local, self.frame_offset().to_array()))
    }

    /// After a move to `end` of `kind` (the tip already there): the program
    /// position is the program point of a programmed move; after a return
    /// to a reference point or a G53 move it is the tool's, mapped back.
    pub(super) fn settle_program(&mut self, kind: MoveKind, start: Axes) {
        let pending = self.coords.pending.take();
        match kind {
            MoveKind::Rapid | MoveKind::Feed | MoveKind::Arc(_) | MoveKind::Probe => {
                if let Some(p) = pending {
                    self.coords.delta = sub(p, self.coords.inverse(self.local_position()));
                }
            }
            MoveKind::Dwell(_) => {}
            _ if self.tip != start => self.coords.delta = [0.0; N],
            _ => {}
        }
    }

    /// The axes a move names, for the writer: under rotation or polar
    /// coordinates every axis that moved.
    pub(super) fn moved_axes(&self, named: AxisSet, start: Axes, end: Axes) -> AxisSet {
        if !(self.coords.polar || self.coords.rotation.is_some()) || named == AxisSet::NONE {
            return named;
        }
        let (s, e) = (start.to_array(), end.to_array());
        (0..N).filter(|&i| s[i] != e[i]).fold(named, |set, i| set.with(i))
    }

    /// `G92`: the named axes of the program position take the words'
    /// values. On Fanuc the G52 local offset of those axes is cleared.
    pub(super) fn set_position(&mut self, w: &Words) {
        let mut p = self.program_position().to_array();
        for (i, v) in w.axis_words() {
            p[i] = if Axes::is_linear(i) { self.mm(v) } else { v };
            if self.settings.coords.control != Control::LinuxCnc {
                self.coords.local[i] = 0.0;
            }
        }
        let q = self.coords.forward(p);
        let (t, o) = (self.tip.to_array(), self.work_offsets[self.modal.work_offset].to_array());
        let (e, l) = (self.external_offset.to_array(), self.coords.local);
        let mut g = self.g92_shift.to_array();
        for (i, _) in w.axis_words() {
            g[i] = t[i] - o[i] - e[i] - l[i] - q[i];
        }
        self.g92_shift = Axes::from_array(g);
        self.coords.delta = [0.0; N];
        self.coords.delta = sub(p, self.program_position().to_array());
    }

    /// `G52`: on Fanuc the local offset of the named axes (added to it under
    /// G91); on LinuxCNC the G92 offset itself.
    pub(super) fn local_offset(&mut self, w: &Words) {
        let incremental = self.modal.distance == Distance::Incremental;
        for (i, v) in w.axis_words() {
            let v = if Axes::is_linear(i) { self.mm(v) } else { v };
            match self.settings.coords.control {
                Control::Fanuc | Control::Haas if incremental => self.coords.local[i] += v,
                Control::Fanuc | Control::Haas => self.coords.local[i] = v,
                Control::LinuxCnc => {
                    let mut g = self.g92_shift.to_array();
                    g[i] = v;
                    self.g92_shift = Axes::from_array(g);
                }
            }
        }
    }

    /// `G53` under G91: refused on LinuxCNC; on Fanuc the block is then an
    /// ordinary move, with a warning.
    pub(super) fn g53_incremental(&mut self, gspan: Span) -> Result<(), Diagnostic> {
        match self.settings.coords.control {
            Control::LinuxCnc => Err(Diagnostic::error(gspan, "Cannot use G53 incremental (LinuxCNC stops here)")),
            Control::Fanuc | Control::Haas => {
                self.warn(
                    "g53-g91",
                    gspan,
                    "G53 under G91: a Fanuc control ignores the G53 and moves by the words as increments in the work coordinates; write G90 G53",
                );
                Ok(())
            }
        }
    }

    /// The machine position `G28` (P1) or `G30 P2`…`P4` returns to.
    pub(super) fn reference_point(&self, code: GCode, w: &Words) -> Result<Axes, Diagnostic> {
        if code != GCode::OtherHome {
            return Ok(self.settings.home);
        }
        match w.get(b'P') {
            None => Ok(self.settings.coords.reference_points[0]),
            Some(1.0) => Ok(self.settings.home),
            Some(p) if [2.0, 3.0, 4.0].contains(&p) => Ok(self.settings.coords.reference_points[p as usize - 2]),
            Some(p) => {
                Err(Diagnostic::error(w.span(b'P'), format!("G30 P{p}: the reference points are P1 (G28's) to P4")))
            }
        }
    }

    /// A G30 return is kept for the writer, which would write G28 for it:
    /// `G91 G30 P3 X0. Y0.` stands for the return move that follows.
    pub(super) fn keep_other_return(&mut self, w: &Words, line: u32) {
        let mut text = String::from("G91 G30");
        if let Some(p) = w.get(b'P').filter(|&p| p != 2.0) {
            text.push_str(&format!(" P{p}"));
        }
        for (k, _) in w.axis_words() {
            text.push_str(&format!(" {}0.", LETTERS[k] as char));
        }
        self.keep(text, 1, false, line);
    }

    /// Whether a mirror image turns the plane over: arcs run the other
    /// way, and G41/G42 swap.
    pub(super) fn plane_reversed(&self) -> bool {
        self.coords.reverses(self.modal.plane)
    }

    /// Checks an arc against the transforms; the factor its R is scaled by.
    pub(super) fn arc_scale(&self, span: Span) -> Result<f64, Diagnostic> {
        let plane = self.modal.plane;
        if let Some(r) = self.coords.rotation {
            if r.plane != plane {
                return Err(Diagnostic::error(
                    span,
                    "an arc outside the plane of G68 rotation: the control stops (alarm: the rotation plane and the arc plane must be the same)",
                ));
            }
        }
        let (i, j, _) = plane.axes();
        let (a, b) = (self.coords.factor(i).abs(), self.coords.factor(j).abs());
        if (a - b).abs() > 1e-12 {
            return Err(Diagnostic::error(
                span,
                format!(
                    "an arc under G51 with unequal factors on its plane ({} ×{a}, {} ×{b}): the control cannot cut an ellipse; the scaled end is off the scaled circle and it stops with an alarm",
                    LETTERS[i] as char, LETTERS[j] as char
                ),
            ));
        }
        Ok(a)
    }

    /// The arc's centre (X Y Z, machine) from I J K, or `None` when the
    /// block has none.
    pub(super) fn arc_centre(&self, w: &Words, span: Span) -> Result<Option<[f64; 3]>, Diagnostic> {
        let mut v = [0.0; N];
        let mut any = false;
        for (k, letter) in [b'I', b'J', b'K'].into_iter().enumerate() {
            if let Some(x) = w.get(letter) {
                v[k] = self.mm(x);
                any = true;
            }
        }
        if !any {
            return Ok(None);
        }
        let local = if self.coords.arc_absolute {
            let (i, j, _) = self.modal.plane.axes();
            let need = [b"IJK"[i], b"IJK"[j]];
            if let Some(&l) = need.iter().find(|&&l| !w.has(l)) {
                return Err(Diagnostic::error(
                    span,
                    format!("G90.1 (absolute arc centre): the arc needs both centre words, {} is missing", l as char),
                ));
            }
            let mut p = self.program_position().to_array();
            p[i] = v[i];
            p[j] = v[j];
            self.coords.forward(p)
        } else {
            add(self.local_position(), self.coords.linear(v))
        };
        let m = add(local, self.frame_offset().to_array());
        Ok(Some([m[0], m[1], m[2]]))
    }
}
