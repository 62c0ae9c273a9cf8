//! The holes of a canned cycle kept for the writer as cycle blocks, each
//! standing for the moves it makes.

use kezuri_geom::{CycleBlock, MoveKind};

use super::RunHole;
use crate::interp::modal::{Cycle, CycleReturn, Units};
use crate::interp::{IntegerInput, State};
use crate::number::number;

impl State {
    /// After a hole: tapping (and every cycle with `keep`, or a return to an
    /// initial level the program never named) is kept for the writer as one
    /// cycle block standing for the hole's moves.
    pub(super) fn end_hole(&mut self, cycle: Cycle, start: usize, line: u32) {
        self.holes += 1;
        let moves = self.toolpath.moves.len() - start;
        if moves == 0 {
            return;
        }
        let lcnc_back = cycle == Cycle::BackBore && self.settings.dialect == crate::Dialect::LinuxCnc;
        let to_initial = (cycle == Cycle::BackBore && !lcnc_back) || self.modal.cycle_return == CycleReturn::Initial;
        // What its block is made of, written only if the hole is kept.
        let hole = RunHole {
            start,
            moves,
            line,
            // The state the hole began in (a tap's spindle reversals are its own).
            state: kezuri_geom::ToolState::of(&self.toolpath.moves[start]),
            cycle,
            ret: self.modal.cycle_return,
            plane: self.cycle_plane(),
            inch: self.modal.units == Units::Inch,
            origin: self.frame_offset().to_array(),
            q: self.hole.q,
            dwell: self.hole.dwell,
            rigid_speed: (cycle.is_tapping() && self.hole.rigid).then_some(self.speed),
            seconds: self.settings.integer_input == IntegerInput::Units,
            initial: self.hole.initial,
            back_shift: self.hole.shift.filter(|_| lcnc_back),
        };
        let keep = cycle.is_tapping()
            || self.settings.cycles.keep
            || (to_initial && self.hole.initial_guessed)
            || self.hole.kept_open;
        if !keep {
            self.hole.run.push(hole);
            return;
        }
        // Once one hole of a cycle is kept, all are: the cycle and with it
        // its initial level go on from the first hole (and rigid tapping
        // from its M29), so a G98 hole returns where the cycle began.
        let earlier = std::mem::take(&mut self.hole.run);
        let sorted = earlier.is_empty();
        let mut last_end = if self.hole.kept_open { self.hole.kept_end } else { usize::MAX };
        for h in earlier.into_iter().chain([hole]) {
            // A hole right after the last one goes on in its cycle.
            let next = h.start == last_end;
            let (head, body) = self.cycle_text(&h);
            let text = if next { body } else { head + &body };
            let mut kept = self.kept(h.start, h.moves, text, false, h.line);
            kept.state = h.state;
            kept.cycle = Some(if next { CycleBlock::Next } else { CycleBlock::Start });
            self.toolpath.kept.push(kept);
            last_end = h.start + h.moves;
        }
        if !sorted {
            // The earlier holes' blocks go before what was kept since.
            self.toolpath.kept.sort_by_key(|k| k.before);
        }
        self.hole.kept_open = true;
        self.hole.kept_end = last_end;
    }

    /// The hole as a cycle block in absolute program coordinates (the
    /// writer's: machine less the program's zero): the head the first hole
    /// of a cycle has (units, G90, and `M29 S` for rigid tapping), and the
    /// cycle's words.
    fn cycle_text(&self, h: &RunHole) -> (String, String) {
        let (i, j, n) = h.plane.axes();
        let unit = if h.inch { 25.4 } else { 1.0 };
        let moves = &self.toolpath.moves[h.start..h.start + h.moves];
        let first = moves.iter().find(|m| !matches!(m.kind, MoveKind::Dwell(_))).map_or(moves[0].start, |m| m.end);
        let place = first.to_array();
        let r_level = hole_r_level(moves, n);
        let levels = moves.iter().map(|m| m.end.to_array()[n]);
        let bottom = if h.back_shift.is_some() {
            // LinuxCNC's G87 ends its bore where it went down to.
            moves.iter().rev().find(|m| m.kind == MoveKind::Feed).map_or(r_level, |m| m.end.to_array()[n])
        } else if h.cycle == Cycle::BackBore {
            levels.fold(f64::NEG_INFINITY, f64::max).min(h.initial)
        } else {
            levels.fold(f64::INFINITY, f64::min)
        };
        let value = |v: f64, k: usize| number((v - h.origin[k]) / unit, 6);
        let letters = ['X', 'Y', 'Z'];
        let units = if h.inch { "G20" } else { "G21" };
        let ret = match h.ret {
            CycleReturn::Initial => "G98",
            CycleReturn::R => "G99",
        };
        let head = match h.rigid_speed {
            Some(s) => format!("M29 S{}\n{units} G90 ", number(s, 0).trim_end_matches('.')),
            None => format!("{units} G90 "),
        };
        let mut text = format!(
            "{ret} G{} {}{} {}{} {}{} R{}",
            h.cycle.number(),
            letters[i],
            value(place[i], i),
            letters[j],
            value(place[j], j),
            letters[n],
            value(bottom, n),
            value(r_level, n),
        );
        if let Some([si, sj]) = h.back_shift {
            // The top of the back bore: where the first feed ends.
            let top = moves.iter().find(|m| m.kind == MoveKind::Feed).map_or(bottom, |m| m.end.to_array()[n]);
            let k = value(top, n);
            text.push_str(&format!(" I{} J{} K{k}", number(si / unit, 6), number(sj / unit, 6)));
        } else if let Some(q) = h.q {
            text.push_str(&format!(" Q{}", number(q / unit, 6)));
        }
        if h.dwell > 0.0 {
            let p = if h.seconds { number(h.dwell, 3) } else { format!("{}", (h.dwell * 1000.0).round()) };
            text.push_str(&format!(" P{p}"));
        }
        let feed = moves.iter().find(|m| m.kind == MoveKind::Feed).map_or(0.0, |m| m.feed);
        text.push_str(&format!(" F{}", number(feed / unit, 4)));
        (head, text)
    }
}

/// The R level of a hole's moves: where its first rapid along the depth
/// axis `n` ends (or where its first feed along it starts).
fn hole_r_level(moves: &[kezuri_geom::Move], n: usize) -> f64 {
    let depth_move = moves.iter().find(|m| {
        let (s, e) = (m.start.to_array(), m.end.to_array());
        (0..3).all(|k| k == n || s[k] == e[k]) && s[n] != e[n]
    });
    match depth_move {
        Some(m) if m.kind == MoveKind::Rapid => m.end.to_array()[n],
        Some(m) => m.start.to_array()[n],
        None => moves[0].start.to_array()[n],
    }
}
