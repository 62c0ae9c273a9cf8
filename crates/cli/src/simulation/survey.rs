//! What a simulation must know of a program before it cuts, gathered from
//! its path as a run hands it on ([`PathSink`]): the tools it cuts with,
//! the extent the stock is taken from where `--stock` does not give it,
//! a move of U V W (refused), and each tool's time. Fed the whole path or
//! its pieces, it says the same.

use anyhow::{bail, Result};
use kezuri_cam::sim::{sideways_top, Extent};
use kezuri_geom::{CycleClock, Dynamics, PathSink, Toolpath};

/// A program's path surveyed.
pub struct Survey {
    /// The numbers of the tools that cut, in the order they first do (a
    /// move before the first tool change is the first tool's); empty until
    /// a tool is loaded.
    pub loaded: Vec<u32>,
    /// Moves taken.
    pub moves: usize,
    /// The first move that moves U, V or W: its line and which (0 1 2).
    pub uvw: Option<(u32, usize)>,
    /// The box of the cutting moves (of all, where none cuts).
    pub extent: Extent,
    /// The highest sideways feed of each tool (by number; 0 before the
    /// first tool change).
    tops: Vec<(u32, f64)>,
    dynamics: Dynamics,
    /// Each tool's seconds (by number), its runs of moves each from a stop.
    seconds: Vec<(u32, f64)>,
    /// The run of one tool's moves under way: its tool (0 before the
    /// first is loaded) and clock.
    run: Option<(u32, CycleClock)>,
}

impl Survey {
    /// Before the first piece; times on `dynamics`.
    pub fn new(dynamics: &Dynamics) -> Survey {
        Survey {
            loaded: Vec::new(),
            moves: 0,
            uvw: None,
            extent: Extent::default(),
            tops: Vec::new(),
            dynamics: dynamics.clone(),
            seconds: Vec::new(),
            run: None,
        }
    }

    /// Refuses a program that moves U, V or W (of `file`): the tool cuts at
    /// X Y Z, and what those axes carry (a quill that moves the tool, a
    /// second head, a foam cutter's other wire end) no machine file says,
    /// so a part cut from X Y Z alone could be wrong without a sign of it.
    pub fn refuse_uvw(&self, file: &str) -> Result<()> {
        if let Some((line, k)) = self.uvw {
            bail!(
                "{file}: line {line} moves {}: the simulation cuts with the tool at X Y Z and does not know what U V \
                 W carry (a quill, a second head, a wire's other end), so it simulates no program that moves them",
                ['U', 'V', 'W'][k]
            );
        }
        Ok(())
    }

    /// The numbers of the tools that cut, in the order they first do (a
    /// single 0 for a program that loads none).
    pub fn numbers(&self) -> Vec<u32> {
        match (self.loaded.is_empty(), self.moves) {
            (_, 0) => Vec::new(),
            (true, _) => vec![0],
            (false, _) => self.loaded.clone(),
        }
    }

    /// The first tool the program loads (0 for none): it cuts the moves
    /// before.
    pub fn first(&self) -> u32 {
        self.loaded.first().copied().unwrap_or(0)
    }

    /// The highest sideways feed of the tools `tells_top` keeps (by
    /// number): the top of the material the program cuts.
    pub fn top(&self, tells_top: &dyn Fn(u32) -> bool) -> Option<f64> {
        let number = |n: u32| if n == 0 { self.first() } else { n };
        let tops = self.tops.iter().filter(|(n, _)| tells_top(number(*n))).map(|(_, z)| *z);
        tops.reduce(f64::max).filter(|z| z.is_finite())
    }

    /// Seconds each of `tools` (by number) takes.
    pub fn times(mut self, tools: &[u32]) -> Vec<f64> {
        self.end_run();
        let first = self.first();
        let of = |n: u32| {
            let each = self.seconds.iter().filter(|(m, _)| (if *m == 0 { first } else { *m }) == n);
            each.fold(0.0, |sum, (_, s)| sum + s)
        };
        tools.iter().map(|&n| of(n)).collect()
    }

    /// The run of moves under way ended: its seconds counted.
    fn end_run(&mut self) {
        if let Some((n, clock)) = self.run.take() {
            let s = clock.finish().0;
            match self.seconds.iter_mut().find(|(m, _)| *m == n) {
                Some(t) => t.1 += s,
                None => self.seconds.push((n, s)),
            }
        }
    }
}

impl PathSink for Survey {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        for m in &piece.moves {
            let tool = match self.run.as_ref().map(|r| r.0) {
                _ if m.tool == 0 => self.run.as_ref().map_or(0, |r| r.0),
                // The first tool loaded takes on the moves before it.
                Some(0) => {
                    if let Some(run) = self.run.as_mut() {
                        run.0 = m.tool;
                    }
                    m.tool
                }
                _ => m.tool,
            };
            if m.tool != 0 && !self.loaded.contains(&m.tool) {
                self.loaded.push(m.tool);
            }
            if self.run.as_ref().is_some_and(|r| r.0 != tool) {
                self.end_run();
            }
            let dynamics = &self.dynamics;
            let (_, clock) = self.run.get_or_insert_with(|| (tool, CycleClock::new(dynamics)));
            clock.add(std::slice::from_ref(m));
            if self.uvw.is_none() {
                self.uvw = (0..3).find(|&k| m.start.uvw()[k] != m.end.uvw()[k]).map(|k| (m.line, k));
            }
            self.extent.add(m);
            if let Some(z) = sideways_top(m) {
                match self.tops.iter_mut().find(|(n, _)| *n == tool) {
                    Some(t) => t.1 = t.1.max(z),
                    None => self.tops.push((tool, z)),
                }
            }
        }
        self.moves += piece.moves.len();
    }
}
