//! A lathe's spindle: the clamp (`G50 S`, `G92 S` in systems B and C),
//! constant surface speed (`G96`/`G97`), the tool (`T0101`), and the time
//! of a move fed per revolution while the spindle speed follows the tool's
//! radius. FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Constant surface speed control (G96, G97)" and "Spindle speed
//! clamp (G50)": the spindle turns at `n = 1000·V / (π·D)` rpm for a
//! surface speed V m/min at the diameter D mm (`12·V/(π·D)` for V ft/min
//! and D inches), never past the clamp.

use std::f64::consts::{PI, TAU};

use kezuri_geom::{Move, MoveKind};

use super::super::modal::{FeedMode, GCode, Units};
use super::super::words::Words;
use super::super::State;
use crate::source::{Diagnostic, Span};

/// The spindle speed under constant surface speed `surface` (mm/min) at
/// radius `r` (mm), held to `limit` rpm: `None` where it has no bound (the
/// tool on the spindle axis and no limit known).
pub(super) fn css_rpm(surface: f64, r: f64, limit: Option<f64>) -> Option<f64> {
    let free = if r > 0.0 { surface / (TAU * r) } else { f64::INFINITY };
    match limit {
        Some(l) => Some(free.min(l)),
        None => free.is_finite().then_some(free),
    }
}

/// `∫₀¹ dt / n(t)` (minutes per revolution, averaged over the move) for a
/// move whose X (its distance from the spindle axis, signed) is `x(t)`,
/// under surface speed `surface` (mm/min) and `limit` rpm: `1/n = max(1/limit,
/// 2π|x|/surface)`. `breaks` are the parameters in (0, 1) where `x` is 0 or
/// ±the radius where the limit begins; between them `integral(t1, t2, sign)`
/// is `∫ sign·x dt` in closed form. Returns the integral and whether the
/// limit held the speed anywhere.
fn per_rev_time(
    x: impl Fn(f64) -> f64,
    integral: impl Fn(f64, f64) -> f64,
    mut breaks: Vec<f64>,
    surface: f64,
    limit: Option<f64>,
) -> (f64, bool) {
    breaks.retain(|t| *t > 0.0 && *t < 1.0);
    breaks.push(0.0);
    breaks.push(1.0);
    breaks.sort_by(f64::total_cmp);
    let (mut sum, mut limited) = (0.0, false);
    for pair in breaks.windows(2) {
        let (t1, t2) = (pair[0], pair[1]);
        if t2 <= t1 {
            continue;
        }
        let mid = x((t1 + t2) / 2.0);
        let free = TAU * mid.abs() / surface;
        match limit {
            Some(l) if free < 1.0 / l => {
                sum += (t2 - t1) / l;
                limited = true;
            }
            _ => sum += TAU / surface * mid.signum() * integral(t1, t2),
        }
    }
    (sum, limited)
}

/// The parameters where `a + b·t` is 0 or ±`rc`.
fn line_breaks(a: f64, b: f64, rc: Option<f64>) -> Vec<f64> {
    if b == 0.0 {
        return Vec::new();
    }
    let mut levels = vec![0.0];
    if let Some(rc) = rc {
        levels.extend([rc, -rc]);
    }
    levels.into_iter().map(|c| (c - a) / b).collect()
}

/// The parameters where `cx + R·cos(φ0 + dφ·t)` is 0 or ±`rc`.
fn arc_breaks(cx: f64, radius: f64, phi0: f64, dphi: f64, rc: Option<f64>) -> Vec<f64> {
    let mut levels = vec![0.0];
    if let Some(rc) = rc {
        levels.extend([rc, -rc]);
    }
    let mut out = Vec::new();
    if dphi == 0.0 || radius == 0.0 {
        return out;
    }
    let (lo, hi) = if dphi > 0.0 { (phi0, phi0 + dphi) } else { (phi0 + dphi, phi0) };
    for c in levels {
        let q = (c - cx) / radius;
        if q.abs() > 1.0 {
            continue;
        }
        let base = q.acos();
        for root in [base, -base] {
            let first = ((lo - root) / TAU).ceil() as i64;
            let last = ((hi - root) / TAU).floor() as i64;
            for k in first..=last {
                out.push((root + TAU * k as f64 - phi0) / dphi);
            }
        }
    }
    out
}

/// Minutes per millimetre fed per revolution, `∫₀¹ dt/n(t)`, over move `m`
/// whose X is measured from the spindle axis at machine X `axis`; with
/// whether the limit held the speed. `None` where the speed has no bound
/// on the way (the move reaches the spindle axis with no limit known).
pub(super) fn move_time(m: &Move, axis: f64, surface: f64, limit: Option<f64>) -> Option<(f64, bool)> {
    let rc = limit.map(|l| surface / (TAU * l));
    match m.kind {
        MoveKind::Arc(arc) => {
            let (i, j, _) = arc.plane.axes();
            let s = m.start.xyz();
            let radius = arc.radius(m.start);
            let a0 = (s[j] - arc.center[j]).atan2(s[i] - arc.center[i]);
            let sweep = arc.sweep(m.start, m.end);
            let dphi = if arc.ccw { sweep } else { -sweep };
            let cx = arc.center[0] - axis;
            // X along the arc: cx + R·cos(φ), φ = a0 + dφ·t less the X axis's
            // angle in the plane (0 as its first axis, π/2 as its second).
            let phase = if i == 0 {
                0.0
            } else if j == 0 {
                PI / 2.0
            } else {
                return line_time(m.start.x - axis, 0.0, surface, limit, rc);
            };
            let phi0 = a0 - phase;
            let x = move |t: f64| cx + radius * (phi0 + dphi * t).cos();
            let breaks = arc_breaks(cx, radius, phi0, dphi, rc);
            // With no limit the breaks are where X is 0: the arc reaches
            // the spindle axis.
            let touches = breaks.iter().any(|&t| (-1e-12..=1.0 + 1e-12).contains(&t));
            if limit.is_none() && (touches || x(0.0) == 0.0 || x(1.0) == 0.0) {
                return None;
            }
            let integral = move |t1: f64, t2: f64| {
                cx * (t2 - t1) + radius * ((phi0 + dphi * t2).sin() - (phi0 + dphi * t1).sin()) / dphi
            };
            Some(per_rev_time(x, integral, breaks, surface, limit))
        }
        _ => line_time(m.start.x - axis, m.end.x - m.start.x, surface, limit, rc),
    }
}

/// [`move_time`] of a straight move whose X runs from `a` by `b`.
fn line_time(a: f64, b: f64, surface: f64, limit: Option<f64>, rc: Option<f64>) -> Option<(f64, bool)> {
    let x = move |t: f64| a + b * t;
    // X crosses or touches the axis on the way.
    if limit.is_none() && (a == 0.0 || a + b == 0.0 || (a < 0.0) != (a + b < 0.0)) {
        return None;
    }
    let integral = move |t1: f64, t2: f64| a * (t2 - t1) + b * (t2 * t2 - t1 * t1) / 2.0;
    Some(per_rev_time(x, integral, line_breaks(a, b, rc), surface, limit))
}

impl State {
    /// `G50 S` (`G92 S` in systems B and C): the spindle speed clamp.
    pub(in super::super) fn set_clamp(&mut self, s: f64, span: Span) -> Result<(), Diagnostic> {
        if s.is_nan() || s <= 0.0 {
            return Err(Diagnostic::error(
                span,
                format!("spindle speed clamp S{s}: the clamp is the top spindle speed in rpm, greater than 0"),
            ));
        }
        if let Some(t) = &mut self.turning {
            t.clamp = Some(s);
        }
        Ok(())
    }

    /// `G96` (`on`) or `G97`: constant surface speed on or off. G96 takes
    /// the S in force as the surface speed until the block's own S (read
    /// after the modal codes) replaces it; G97 without S keeps the speed
    /// the spindle has reached.
    pub(in super::super) fn constant_speed(&mut self, on: bool, gspan: Span) -> Result<(), Diagnostic> {
        let unit = self.surface_unit();
        let Some(t) = &mut self.turning else {
            return Err(Diagnostic::error(gspan, "G96 (constant surface speed) is a lathe's: this machine is a mill"));
        };
        t.surface = on.then_some(t.s_word * unit);
        Ok(())
    }

    /// mm/min for one S unit of surface speed: m/min, or ft/min under G20.
    fn surface_unit(&self) -> f64 {
        if self.modal.units == Units::Inch {
            304.8
        } else {
            1000.0
        }
    }

    /// The top speed the spindle is held to: the clamp (`G50 S`) and the
    /// machine's top speed, the lower.
    fn speed_limit(&self) -> Option<f64> {
        let clamp = self.turning.as_ref().and_then(|t| t.clamp);
        match (clamp, self.settings.max_rpm) {
            (Some(c), Some(m)) => Some(c.min(m)),
            (c, m) => c.or(m),
        }
    }

    /// The machine X of the spindle axis: the work zero's (X 0 of the
    /// program's coordinates is the axis).
    fn spindle_axis(&self) -> f64 {
        self.frame_offset().x
    }

    /// A lathe block's S and T, after the mill's reading of them: under
    /// constant surface speed S is the surface speed and the spindle speed
    /// follows the tool; `T0101` selects tool 1 with offset 1 at once (a
    /// turret has no M06). The offset's length, where the tool table has
    /// one, is the tool's Z length, applied as a mill's G43 H applies its
    /// register: the tip stays where the program puts it; the machine
    /// position (#5021…) counts it. X offsets are not modelled.
    pub(in super::super) fn lathe_speed_tool(
        &mut self,
        w: &Words,
        codes: &[Option<(GCode, Span)>],
    ) -> Result<(), Diagnostic> {
        let unit = self.surface_unit();
        let fanuc = self.turning.as_ref().is_some_and(|t| t.fanuc);
        if let (Some(s), Some(t)) = (w.get(b'S'), &mut self.turning) {
            t.s_word = s;
            if t.surface.is_some() {
                t.surface = Some(s * unit);
            }
        }
        let g96 = codes.iter().flatten().any(|(c, _)| *c == GCode::ConstantSpeed);
        if let Some(surface) = self.turning.as_ref().and_then(|t| t.surface) {
            let at = if w.has(b'S') { w.span(b'S') } else { Span::default() };
            if surface.is_nan() || surface <= 0.0 {
                let s = surface / unit;
                return Err(Diagnostic::error(
                    at,
                    format!("constant surface speed S{s}: the spindle would not turn; give S greater than 0"),
                ));
            }
            if w.has(b'S') || g96 {
                self.speed = self.rpm_here(surface, at)?;
            }
        }
        if let Some(t) = w.get(b'T').filter(|_| fanuc) {
            self.lathe_tool(t, w.span(b'T'))?;
        }
        Ok(())
    }

    /// The spindle speed under surface speed `surface` with the tool where
    /// it is: 0 where X is at a place the program never named (the speed
    /// is reckoned at the next move's end).
    fn rpm_here(&mut self, surface: f64, at: Span) -> Result<f64, Diagnostic> {
        if self.unplaced.contains(0) || self.at_machine.contains(0) {
            return Ok(0.0);
        }
        let r = (self.tip.x - self.spindle_axis()).abs();
        let rpm = self.css_speed(surface, r, at)?;
        Ok(rpm)
    }

    /// The spindle speed at radius `r` under `surface`, warned of where the
    /// machine's top speed holds it with no clamp given; an error where it
    /// has no bound.
    fn css_speed(&mut self, surface: f64, r: f64, at: Span) -> Result<f64, Diagnostic> {
        let limit = self.speed_limit();
        let Some(rpm) = css_rpm(surface, r, limit) else {
            return Err(self.unbounded(surface, at));
        };
        self.warn_top_speed(surface, rpm, Some(r), at);
        Ok(rpm)
    }

    /// The warning that constant surface speed reached the machine's top
    /// speed with no clamp of the program's below it: at radius `r` (mm)
    /// where the speed is `rpm`, or (`r` `None`) somewhere on a move.
    fn warn_top_speed(&mut self, surface: f64, rpm: f64, r: Option<f64>, at: Span) {
        let clamp = self.turning.as_ref().and_then(|t| t.clamp);
        let Some(top) = self.settings.max_rpm else { return };
        if rpm < top || clamp.is_some_and(|c| c < top) {
            return;
        }
        let s = crate::number::number(surface / self.surface_unit(), 4);
        let place = match r {
            Some(r) if r > 0.0 => {
                let inch = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
                let d = crate::number::number(2.0 * r / inch, 4);
                format!("at X{d} (a diameter) asks for {:.0} rpm", surface / (TAU * r))
            }
            Some(_) => "at X0 asks for an unbounded speed".to_string(),
            None => "on this move asks for more".to_string(),
        };
        let code = self.clamp_code();
        self.warn(
            "css-top",
            at,
            format!(
                "constant surface speed S{s} {place}: with no {code} S clamp below it the spindle runs at its top \
                 speed, {top:.0} rpm (the machine's max_rpm)"
            ),
        );
    }

    /// `G50`, or `G92` in systems B and C: the code that clamps the speed.
    fn clamp_code(&self) -> &'static str {
        match self.turning.as_ref().map(|t| t.system) {
            Some(super::GCodeSystem::B | super::GCodeSystem::C) => "G92",
            _ => "G50",
        }
    }

    /// The error of constant surface speed with the tool on the spindle
    /// axis and no top speed known.
    fn unbounded(&self, surface: f64, at: Span) -> Diagnostic {
        let s = surface / self.surface_unit();
        let code = self.clamp_code();
        Diagnostic::error(
            at,
            format!(
                "constant surface speed (G96 S{s}) with the tool at X0, on the spindle axis: the spindle speed has no \
                 bound, and neither a clamp ({code} S) nor the machine's top speed (max_rpm) is known; give {code} \
                 S<rpm> before G96"
            ),
        )
    }

    /// After a lathe block's motion: under constant surface speed each new
    /// move's spindle speed is the one at its end, and a move fed per
    /// revolution gets the feed in mm/min whose time over its length is
    /// the exact `∫ ds / (f·n(s))`. `x_known`: whether the first move starts
    /// at an X the program named.
    pub(in super::super) fn lathe_moves(
        &mut self,
        first: usize,
        x_known: bool,
        w: &Words,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let Some(surface) = self.turning.as_ref().and_then(|t| t.surface) else { return Ok(()) };
        let at = if w.has(b'X') {
            w.span(b'X')
        } else if w.has(b'U') {
            w.span(b'U')
        } else {
            span
        };
        let axis = self.spindle_axis();
        let limit = self.speed_limit();
        let per_rev = self.modal.feed_mode == FeedMode::PerRev;
        let f_rev = self.mm(self.feed_word);
        let mut known = x_known;
        for k in first..self.toolpath.moves.len() {
            let m = self.toolpath.moves[k];
            let end_known = !m.unknown.contains(0);
            let r = (m.end.x - axis).abs();
            let rpm =
                if end_known { self.css_speed(surface, r, at)? } else { css_rpm(surface, r, limit).unwrap_or(0.0) };
            let thread = self.threads.iter().rev().find(|t| t.line == m.line && t.start == m.start && t.end == m.end);
            let fed = matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_) | MoveKind::Probe);
            let rate = match thread {
                Some(t) => Some(t.lead * thread_stretch(&m)),
                None if fed && per_rev => Some(f_rev),
                None => None,
            };
            let mut feed = m.feed;
            if let Some(rate) = rate.filter(|_| m.length() > 0.0) {
                match move_time(&m, axis, surface, limit) {
                    Some((minutes, limited)) => {
                        if limited && limit.is_some_and(|l| rpm < l) {
                            self.warn_top_speed(surface, limit.unwrap_or(0.0), None, at);
                        }
                        if minutes > 0.0 && rate > 0.0 {
                            feed = rate / minutes;
                        }
                    }
                    None if known => return Err(self.unbounded(surface, at)),
                    // From an X the program never named: the time is
                    // reckoned from the speed at the end.
                    None => feed = rate * rpm,
                }
            }
            let m = &mut self.toolpath.moves[k];
            m.speed = rpm;
            m.feed = feed;
            self.speed = rpm;
            known = end_known;
        }
        Ok(())
    }
}

impl State {
    /// `T0101`: tool 01 with geometry and wear offset 01 (the last two
    /// digits the offset, the others the tool; `T0100` cancels the offset).
    fn lathe_tool(&mut self, t: f64, span: Span) -> Result<(), Diagnostic> {
        if t.fract() != 0.0 || !(0.0..=9999.0).contains(&t) {
            return Err(Diagnostic::error(
                span,
                format!("T{t}: a lathe's T word is the tool number and the offset number, two digits each (T0101)"),
            ));
        }
        let t = t as u32;
        let (tool, offset) = (t / 100, t % 100);
        if (1..100).contains(&t) {
            self.warn(
                "lathe-t",
                span,
                format!(
                    "T{t}: a lathe's T word is the tool number then the offset number, two digits each; this selects \
                     tool 0 with offset {t}. Write T{t:02}{t:02} for tool {t} with its offset"
                ),
            );
        }
        self.tool = tool;
        self.pending_tool = tool;
        if let Some(turning) = &mut self.turning {
            turning.offset = offset;
        }
        if !self.tool_offsets.contains(&(tool, offset)) {
            self.tool_offsets.push((tool, offset));
        }
        let before = self.length_offset();
        self.modal.length_comp = (offset != 0 && self.tool_length(offset).is_some()).then_some((1.0, offset));
        if self.length_offset() != before {
            self.length_changed(before);
        }
        Ok(())
    }
}

/// How much longer a threading move's path is than its lead axis: the lead
/// is measured along the longer of Z and X (FANUC: along Z for a taper up
/// to 45°, along X past it), so the feed along the path is the lead × rpm ×
/// this.
pub(super) fn thread_stretch(m: &Move) -> f64 {
    let major = (m.end.z - m.start.z).abs().max((m.end.x - m.start.x).abs());
    if major > 0.0 {
        m.length() / major
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane};

    use super::*;

    /// `∫₀¹ dt/n(x(t))` by composite Simpson over `steps` intervals.
    fn simpson(x: impl Fn(f64) -> f64, surface: f64, limit: Option<f64>, steps: usize) -> f64 {
        let g = |t: f64| {
            let free = TAU * x(t).abs() / surface;
            limit.map_or(free, |l| free.max(1.0 / l))
        };
        let h = 1.0 / steps as f64;
        let mut sum = g(0.0) + g(1.0);
        for k in 1..steps {
            sum += g(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * h / 3.0
    }

    fn arc_move(start: (f64, f64), end: (f64, f64), center: (f64, f64), ccw: bool) -> Move {
        // (X, Z) pairs in the ZX plane.
        Move {
            kind: MoveKind::Arc(Arc { center: [center.0, 0.0, center.1], plane: Plane::Zx, ccw, turns: 0 }),
            start: Axes { x: start.0, z: start.1, ..Axes::ZERO },
            end: Axes { x: end.0, z: end.1, ..Axes::ZERO },
            ..Move::default()
        }
    }

    // Half circles of radius 10 about (X 12, Z 0) from X 2 to X 22, one
    // each way: X passes the clamp radius r_c = V/(2π·2000) = 15.9155 on
    // the way; one across the spindle axis; a quarter circle with the axis
    // at machine X 3.
    #[test]
    fn an_arcs_time_matches_simpson_to_1e_9() {
        let (v, limit) = (200_000.0, Some(2000.0));
        for (m, axis) in [
            (arc_move((2.0, 0.0), (22.0, 0.0), (12.0, 0.0), true), 0.0),
            (arc_move((2.0, 0.0), (22.0, 0.0), (12.0, 0.0), false), 0.0),
            // Across the spindle axis: X from 5 to -5 about (0, 0).
            (arc_move((5.0, 0.0), (-5.0, 0.0), (0.0, 0.0), true), 0.0),
            // A quarter circle, the spindle axis at machine X 3.
            (arc_move((23.0, 0.0), (13.0, -10.0), (13.0, 0.0), false), 3.0),
        ] {
            let MoveKind::Arc(arc) = m.kind else { unreachable!() };
            let x = |t: f64| arc.point_at(m.start, m.end, t).x - axis;
            let (exact, _) = move_time(&m, axis, v, limit).expect("bounded");
            let numeric = simpson(x, v, limit, 2_000_000);
            assert!((exact - numeric).abs() <= 1e-9 * numeric, "{exact} vs {numeric}");
        }
    }

    // A line through the clamp radius and across the axis.
    #[test]
    fn a_lines_time_matches_simpson() {
        let (v, limit) = (150_000.0, Some(3000.0));
        for (a, b) in [(20.0, -30.0), (4.0, 30.0), (-10.0, 5.0), (20.0, 0.0)] {
            let m = Move {
                kind: MoveKind::Feed,
                start: Axes { x: a, ..Axes::ZERO },
                end: Axes { x: a + b, z: -7.0, ..Axes::ZERO },
                ..Move::default()
            };
            let (exact, _) = move_time(&m, 0.0, v, limit).expect("bounded");
            let numeric = simpson(|t| a + b * t, v, limit, 2_000_000);
            assert!((exact - numeric).abs() <= 1e-9 * numeric, "{exact} vs {numeric}");
        }
        // With no limit the axis is unbounded.
        let m = Move { kind: MoveKind::Feed, end: Axes { x: 5.0, ..Axes::ZERO }, ..Move::default() };
        assert!(move_time(&m, 0.0, v, None).is_none());
    }
}
