//! LinuxCNC's synchronised motion modes: G33.1 rigid tapping and G76
//! lathe threading, each block made into the moves rs274 makes and kept as
//! written for a written program.

use kezuri_geom::{Axes, AxisSet, MoveKind, Spindle};

use super::modal::Units;
use super::words::Words;
use super::State;
use crate::number::number;
use crate::source::{Diagnostic, Span};

/// A G76 block's words and the depths of its passes, mm.
struct Thread {
    pitch: f64,
    i: f64,
    j: f64,
    k: f64,
    q: f64,
    /// The tapered ends (L): 1 the entry, 2 the exit, 3 both.
    ends: u8,
    taper: f64,
    entry: bool,
    exit: bool,
    depths: Vec<f64>,
}

impl State {
    /// A block in LinuxCNC's G33.1 mode (rigid tapping): from where the
    /// tool is, a feed to the end point synchronised with the spindle (K
    /// the distance a turn), the spindle reversed, the same feed back to
    /// the start, the spindle as it was. Kept as its G33.1 block for a
    /// written program; its two moves are the simulation's. Returns whether
    /// the tool moved.
    pub(super) fn rigid_tap_block(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        if !w.any_axis() {
            return Ok(false);
        }
        // rs274's refusals (K is not modal: each block gives it).
        let Some(k) = w.get(b'K') else {
            return Err(Diagnostic::error(span, "K word missing with G33.1: give the pitch, the distance a turn"));
        };
        let reverse = match self.spindle {
            Spindle::Cw => Spindle::Ccw,
            Spindle::Ccw => Spindle::Cw,
            Spindle::Off => return Err(Diagnostic::error(span, "Spindle not turning in G33.1: give M3 or M4 first")),
        };
        if self.comp_on() {
            return Err(Diagnostic::error(span, "G33.1 with cutter compensation on (G41/G42): give G40 first"));
        }
        if self.speed <= 0.0 {
            return Err(Diagnostic::error(
                span,
                "G33.1 with spindle speed 0: the feed is 0 and the tap never ends; give S greater than 0",
            ));
        }
        let (start, first, spindle) = (self.tip, self.toolpath.moves.len(), self.spindle);
        let end = self.target(w);
        let feed = (self.mm(k) * self.speed).abs();
        self.push_move(MoveKind::Feed, end, feed, w.axes(), line);
        self.spindle = reverse;
        self.push_move(MoveKind::Feed, start, feed, w.axes(), line);
        self.spindle = spindle;
        // The block in absolute program coordinates, its units with it.
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let (e, o) = (end.to_array(), self.frame_offset().to_array());
        let mut text = String::from(if unit == 1.0 { "G21 G90 G33.1" } else { "G20 G90 G33.1" });
        for (i, letter) in Axes::LETTERS.into_iter().enumerate().filter(|&(i, _)| w.axes().contains(i)) {
            let v = if Axes::is_linear(i) { (e[i] - o[i]) / unit } else { e[i] - o[i] };
            text.push_str(&format!(" {}{}", letter as char, number(v, 6)));
        }
        text.push_str(&format!(" K{}", number(k, 6)));
        let mut kept = self.kept(first, 2, text, false, line);
        kept.state = kezuri_geom::ToolState::of(&self.toolpath.moves[first]);
        self.toolpath.kept.push(kept);
        Ok(true)
    }

    /// A block in LinuxCNC's G76 mode (lathe threading, in XZ whatever the
    /// plane): from where the tool is (x₀, z₀), with d the sign of I and s
    /// that of the travel in Z, passes at the depths δₙ = J·n^(1/R) while
    /// under K, one at K, then H spring passes at K. Each pass: a rapid to
    /// (x₀ − d(K−δ), z₀ + s·δ·tan Q), a rapid to x₀ + I + d·δ, a feed
    /// synchronised with the spindle (P the distance a turn) to
    /// Z − s(K−δ)·tan Q, a rapid back to x₀ − d(K−δ); then a rapid to the
    /// block's end point. A tapered end (L1 the entry, L2 the exit, L3
    /// both) cuts E along Z from K shallower than the pass to its depth:
    /// at the entry the rapid in becomes a feed in to that shallower x and
    /// a feed along the taper, at the exit the last E of the feed rises
    /// back to it; both at the pitch P·√(E² + K²)/E, so that Z still
    /// advances P a turn. rs274's `G76`, motion for motion. Kept as its
    /// block for a written program. Returns whether the tool moved.
    pub(super) fn thread_block(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let given_here = w.g[..w.g_count].iter().any(|g| g.0 == 760);
        if !w.any_axis() {
            if given_here {
                return Err(Diagnostic::error(span, "All axes missing with G76: give Z, the end of the thread"));
            }
            return Ok(false);
        }
        let t = self.thread_words(w, span)?;
        let first = self.toolpath.moves.len();
        let end = self.thread_passes(&t, w, line)?;
        self.keep_thread(&t, w, end, first, line);
        Ok(true)
    }

    /// G76's words, checked as rs274 checks them, and the depths of its
    /// passes.
    fn thread_words(&mut self, w: &Words, span: Span) -> Result<Thread, Diagnostic> {
        // rs274's refusals. P, I, J, K are not modal: each block gives them.
        let pitch = match w.get(b'P') {
            Some(p) if p > 0.0 => p,
            _ => return Err(Diagnostic::error(span, "P word missing with G76: give the pitch, the distance a turn")),
        };
        let (Some(i), Some(j), Some(k)) = (w.get(b'I'), w.get(b'J'), w.get(b'K')) else {
            return Err(Diagnostic::error(span, "I J or K words missing with G76"));
        };
        // Under G7 (diameter mode) the depths are diameters, as X is.
        let half = self.g76_depth_scale(span);
        let (i, j, k) = (i * half, j * half, k * half);
        if i == 0.0 {
            return Err(Diagnostic::error(w.span(b'I'), "In G76, I must not be 0"));
        }
        if j <= 0.0 {
            return Err(Diagnostic::error(w.span(b'J'), "In G76, J must be greater than 0"));
        }
        if k <= j {
            return Err(Diagnostic::error(w.span(b'K'), "In G76, K must be greater than J"));
        }
        if let Some(l) = b"ABC".iter().find(|&&l| w.has(l)) {
            return Err(Diagnostic::error(w.span(*l), "Cannot move rotary axes with G76"));
        }
        if self.spindle == Spindle::Off {
            return Err(Diagnostic::error(span, "Spindle not turning in G76: give M3 or M4 first"));
        }
        if self.comp_on() {
            return Err(Diagnostic::error(span, "G76 with cutter compensation on (G41/G42): give G40 first"));
        }
        // rs274 also takes R ≤ 0 and H < 0; refused here rather than guessed.
        let r = w.get(b'R').unwrap_or(1.0);
        if r <= 0.0 {
            return Err(Diagnostic::error(w.span(b'R'), "G76 needs a depth degression R greater than 0"));
        }
        // rs274 cuts an R below 1 as R1 (R0.5 and R0.8 make R1's passes).
        let r = r.max(1.0);
        let h = w.get(b'H').unwrap_or(0.0);
        if h < 0.0 || h.fract() != 0.0 {
            return Err(Diagnostic::error(w.span(b'H'), "G76 needs a whole number of spring passes H, 0 or more"));
        }
        let q = w.get(b'Q').unwrap_or(0.0);
        // The tapered ends: L an integer as rs274 reads one (within
        // 0.0001); rs274 takes L over 3 bit by bit and E < 0 as no taper,
        // both refused here.
        const ENDS: &str = "G76 L is the tapered ends: 0 none, 1 entry, 2 exit, 3 both";
        let ends = match w.get(b'L') {
            None => 0,
            Some(l) if (l - l.round()).abs() > 0.0001 => {
                return Err(Diagnostic::error(w.span(b'L'), format!("Non integer value for integer: {ENDS}")))
            }
            Some(l) if l.round() < 0.0 => {
                return Err(Diagnostic::error(w.span(b'L'), format!("Negative L word used: {ENDS}")))
            }
            Some(l) if l.round() > 3.0 => return Err(Diagnostic::error(w.span(b'L'), format!("{ENDS}, not {l}"))),
            Some(l) => l.round() as u8,
        };
        let taper = w.get(b'E').unwrap_or(0.0);
        if taper < 0.0 {
            return Err(Diagnostic::error(w.span(b'E'), "G76 needs a taper length E of 0 or more"));
        }
        let (entry, exit) = if taper > 0.0 { (ends & 1 != 0, ends & 2 != 0) } else { (false, false) };
        // The passes, bounded.
        const MOST_PASSES: usize = 10_000;
        let mut depths = Vec::new();
        for n in 1.. {
            let depth = j * f64::from(n).powf(1.0 / r);
            if depth >= k {
                break;
            }
            if depths.len() >= MOST_PASSES {
                return Err(Diagnostic::error(span, format!("G76 would make more than {MOST_PASSES} passes")));
            }
            depths.push(self.mm(depth));
        }
        if depths.len() as f64 + h >= MOST_PASSES as f64 {
            return Err(Diagnostic::error(span, format!("G76 would make more than {MOST_PASSES} passes")));
        }
        depths.extend(std::iter::repeat_n(self.mm(k), 1 + h as usize));
        if self.speed <= 0.0 {
            return Err(Diagnostic::error(
                span,
                "G76 with spindle speed 0: the feed is 0 and the thread never ends; give S greater than 0",
            ));
        }
        Ok(Thread { pitch, i, j, k, q, ends, taper, entry, exit, depths })
    }

    /// G76's passes, then a rapid to the block's end point, which it returns.
    fn thread_passes(&mut self, t: &Thread, w: &Words, line: u32) -> Result<Axes, Diagnostic> {
        let Thread { pitch, i, k, q, taper, entry, exit, .. } = *t;
        let start = self.tip;
        let end = self.target(w);
        let (x0, z0) = (start.x, start.z);
        let (i_mm, k_mm) = (self.mm(i), self.mm(k));
        let d = i.signum();
        // rs274: toward -Z unless Z is above the start (Z at the start too).
        let s = if end.z > z0 { 1.0 } else { -1.0 };
        let tan = q.to_radians().tan();
        let feed = (self.mm(pitch) * self.speed).abs();
        // Along Z each pass runs s(Z − z₀) − K·tan Q; the tapers fit in it.
        let e_mm = self.mm(taper);
        let tapers = f64::from(u8::from(entry) + u8::from(exit)) * e_mm;
        if tapers > 0.0 && tapers > s * (end.z - z0) - k_mm * tan {
            return Err(Diagnostic::error(
                w.span(b'E'),
                "G76's tapers (E at each tapered end) are longer than the thread",
            ));
        }
        let taper_feed = if taper > 0.0 { feed * e_mm.hypot(k_mm) / e_mm } else { feed };
        let xz = AxisSet::NONE.with(0).with(2);
        let at = |x: f64, z: f64| Axes { x, z, ..start };
        for &depth in &t.depths {
            let out = x0 - d * (k_mm - depth);
            let (z_in, z_end) = (z0 + s * depth * tan, end.z - s * (k_mm - depth) * tan);
            let cut = x0 + i_mm + d * depth;
            // Where a taper starts or ends: K shallower than the pass.
            let shallow = cut - d * k_mm;
            self.push_move(MoveKind::Rapid, at(out, z_in), 0.0, xz, line);
            if entry {
                self.push_move(MoveKind::Feed, at(shallow, z_in), taper_feed, xz, line);
                self.push_move(MoveKind::Feed, at(cut, z_in + s * e_mm), taper_feed, xz, line);
            } else {
                self.push_move(MoveKind::Rapid, at(cut, z_in), 0.0, xz, line);
            }
            // The pass's thread: from the tool where the synchronised
            // motion begins to where it ends.
            let begins = if entry { at(out, z_in) } else { at(cut, z_in) };
            if exit {
                self.push_move(MoveKind::Feed, at(cut, z_end - s * e_mm), feed, xz, line);
                self.push_move(MoveKind::Feed, at(shallow, z_end), taper_feed, xz, line);
            } else {
                self.push_move(MoveKind::Feed, at(cut, z_end), feed, xz, line);
            }
            self.push_thread(self.mm(pitch), begins, self.tip, line);
            self.push_move(MoveKind::Rapid, at(out, z_end), 0.0, xz, line);
        }
        self.push_move(MoveKind::Rapid, end, 0.0, w.axes(), line);
        Ok(end)
    }

    /// G76's block in absolute program coordinates, kept for a written
    /// program, standing for the moves from `first` on.
    fn keep_thread(&mut self, t: &Thread, w: &Words, end: Axes, first: usize, line: u32) {
        let Thread { pitch, i, j, k, q, ends, .. } = *t;
        // The block in absolute program coordinates, its units with it (Q
        // always: LinuxCNC versions differ in its default).
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let (e, o) = (end.to_array(), self.frame_offset().to_array());
        let mut text = String::from(if unit == 1.0 { "G21 G90 G76" } else { "G20 G90 G76" });
        // Z always (the end of the thread), X and Y as given.
        for (n, &letter) in b"XYZ".iter().enumerate() {
            if w.has(letter) || letter == b'Z' {
                text.push_str(&format!(" {}{}", letter as char, number((e[n] - o[n]) / unit, 6)));
            }
        }
        for (letter, v) in [(b'P', Some(pitch)), (b'I', Some(i)), (b'J', Some(j)), (b'K', Some(k))].into_iter().chain([
            (b'R', w.get(b'R')),
            (b'Q', Some(q)),
            (b'H', w.get(b'H')),
            (b'E', w.get(b'E')),
        ]) {
            if let Some(v) = v {
                text.push_str(&format!(" {}{}", letter as char, number(v, 6)));
            }
        }
        if w.has(b'L') {
            text.push_str(&format!(" L{ends}"));
        }
        let moves = self.toolpath.moves.len() - first;
        let mut kept = self.kept(first, moves, text, false, line);
        kept.state = kezuri_geom::ToolState::of(&self.toolpath.moves[first]);
        self.toolpath.kept.push(kept);
    }
}
