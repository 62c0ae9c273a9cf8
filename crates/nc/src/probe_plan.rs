//! Measuring programs for digitizing a model on a grid (the copy-milling
//! paper, `kezuri probe plan`).
//!
//! A [`Plan`] is a grid of `nx × ny` points at one pitch from an origin, a
//! travel height (`z_safe`) and a plunge depth: the stylus travels at
//! `z_safe` and goes down by `plunge` at every point, so the bottom of each
//! plunge is `z_safe − plunge`. Rows run along X and step +Y; the first row
//! runs toward +X, and with [`Pattern::Zigzag`] every other row runs back
//! toward −X ([`order`] gives the points in the order they are measured: the
//! order a capture numbers them, 1-based).
//!
//! [`Plan::program`] writes the program in one of three [`Style`]s, with a
//! decimal point on every axis word. It begins and ends as the post
//! ([`Plan::post`]) begins and ends a program it makes
//! ([`made_text`](crate::write::made_text)): its header (with the comments below), safe start,
//! retract and change to the stylus ([`Plan::tool`]); the tool length offset
//! on the first Z move (`G00 G43 H1 Z30.`); and its end (retract, home,
//! `M30`). The moves between are in the post's dialect (`G00`, or `G0` for
//! LinuxCNC, Mach3 and GRBL).
//!
//! - [`Style::Subprogram`] (Fanuc and Haas): the O1011/O1012/O1013 shape. The main
//!   program positions at the origin and `z_safe` in G90, then switches to
//!   G91 and repeats a row subprogram with `M98 P… L…`; the row subprogram
//!   measures its first point and repeats a point subprogram (step one pitch,
//!   plunge, trigger, retract) `nx − 1` times, so every repeat really steps.
//!   Zig-zag repeats a row-pair subprogram (a +X row, a −X row); an odd last
//!   row is written in the main program. Subprograms are numbered after the
//!   main one: `O n+1` row (one-way) or row pair (zig-zag), `O n+2` the +X
//!   point, `O n+3` the −X point (zig-zag). `G90` comes back before the end.
//! - [`Style::Expanded`] (every dialect): every point written out in absolute
//!   coordinates.
//! - [`Style::G31`] (Fanuc and Haas, custom macro B): for a touch probe. At each point `G31` goes down toward
//!   the bottom and stops at the touch; the control then writes the touch
//!   point with `DPRNT` to the I/O device opened by `POPEN` (the RS-232 port
//!   a capture listens on), one line `x y z` per point: `#5061`, `#5062` and
//!   the tip's Z, `#5063 − #5083` (the skip position less the tool length
//!   offset). Where the probe meets nothing the line gives the bottom.
//!
//! The subprogram and expanded styles give the trigger at every bottom (by
//! default [`default_trigger`]: `M07`, `G04 X0.5`, `M09` on Fanuc, the air-blow
//! signal that tells the PC to read the indicator). Measuring programs give
//! their dwells in seconds (Fanuc `G04 X0.5`, others `G4 P0.5`) unless the
//! post's dwell unit is set to milliseconds ([`text_options`]).
//!
//! All coordinates are integers of `10^-digits` mm inside, so the grid points
//! are written exactly and the incremental steps add up to them.

mod program;

use crate::write::{dwell_block, text_options, Dialect, WriteOptions};
use crate::{interp, parse, Error, ErrorKind, Program, SourceFile, Sources};

/// The dwell of the default trigger, s.
pub const TRIGGER_DWELL: f64 = 0.5;
/// The default stylus (tool) number.
pub const DEFAULT_TOOL: u32 = 1;
/// The copy-milling paper's main program number.
pub const DEFAULT_PROGRAM: u32 = 1011;
/// The copy-milling paper's plunge feed (mm/min), for an indicator stylus.
pub const DEFAULT_PLUNGE_FEED: f64 = 6000.0;
/// The default probing feed (mm/min) of [`Style::G31`], for a touch probe.
pub const DEFAULT_PROBE_FEED: f64 = 200.0;
/// The largest repeat count of `M98 P… L…` on a Fanuc control.
pub const MAX_REPEATS: u32 = 9999;
/// The most points a plan may have.
pub const MAX_POINTS: u64 = 1_000_000;
/// The most decimals of a coordinate.
pub const MAX_DIGITS: u32 = 4;

/// How the program is written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// The copy-milling paper's main program and repeated subprograms, incremental moves.
    #[default]
    Subprogram,
    /// Every point written out, absolute.
    Expanded,
    /// Skip-signal probing (`G31`), touch points written with `DPRNT`.
    G31,
}

impl Style {
    /// `subprogram`, `expanded` or `g31`.
    pub fn name(self) -> &'static str {
        match self {
            Style::Subprogram => "subprogram",
            Style::Expanded => "expanded",
            Style::G31 => "g31",
        }
    }
}

/// How rows follow each other.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Pattern {
    /// Every other row runs back toward −X.
    #[default]
    Zigzag,
    /// Every row runs toward +X; the stylus returns at `z_safe`.
    OneWay,
}

impl Pattern {
    /// `zigzag` or `oneway`.
    pub fn name(self) -> &'static str {
        match self {
            Pattern::Zigzag => "zigzag",
            Pattern::OneWay => "oneway",
        }
    }
}

/// Grid indices `[i, j]` (column along X, row along Y, from 0) of the
/// `nx × ny` points in the order they are measured.
pub fn order(count: [u32; 2], pattern: Pattern) -> impl Iterator<Item = [u32; 2]> {
    let [nx, ny] = count;
    (0..ny).flat_map(move |j| {
        (0..nx).map(move |k| {
            let back = pattern == Pattern::Zigzag && j % 2 == 1;
            [if back { nx - 1 - k } else { k }, j]
        })
    })
}

/// Grid indices `[i, j]` of the `k`-th point measured (from 0), or `None`
/// past the last.
pub fn grid_index(k: u64, count: [u32; 2], pattern: Pattern) -> Option<[u32; 2]> {
    let [nx, ny] = count;
    if nx == 0 || k >= u64::from(nx) * u64::from(ny) {
        return None;
    }
    let (j, c) = ((k / u64::from(nx)) as u32, (k % u64::from(nx)) as u32);
    let back = pattern == Pattern::Zigzag && j % 2 == 1;
    Some([if back { nx - 1 - c } else { c }, j])
}

/// A measuring program to write.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// X and Y of the first point (grid index `[0, 0]`), mm.
    pub origin: [f64; 2],
    /// Points along X and along Y.
    pub count: [u32; 2],
    /// Distance between neighbouring points, mm, in X and in Y.
    pub pitch: f64,
    /// Height the stylus travels at, mm.
    pub z_safe: f64,
    /// Depth of each plunge below `z_safe`, mm.
    pub plunge: f64,
    /// How the program is written.
    pub style: Style,
    /// How rows follow each other.
    pub pattern: Pattern,
    /// Feed of the plunge (`G01` or `G31`), mm/min.
    pub plunge_feed: f64,
    /// Feed of the retract and of the moves between points, mm/min; `None`:
    /// rapid (`G00`), as the copy-milling paper's `G00 X1.`.
    pub feed: Option<f64>,
    /// Number of the main program; subprograms take the next numbers.
    pub program: u32,
    /// Blocks given at each plunge bottom (not used by [`Style::G31`]).
    pub trigger: Vec<String>,
    /// Decimals of the coordinates, 0 to [`MAX_DIGITS`]: every given length
    /// must be a whole number of `10^-digits` mm.
    pub digits: u32,
    /// How the program begins, changes to the stylus and ends, and the
    /// dialect of its blocks (default: the fanuc preset).
    pub post: WriteOptions,
    /// The stylus's tool number (its length register is the post's `H`).
    pub tool: u32,
}

/// A plan that cannot be written: the value that is wrong and why.
fn err<T>(message: impl Into<String>) -> Result<T, Error> {
    Err(Error::new(ErrorKind::Plan, message))
}

/// The largest magnitude of a coordinate: eight digits, as a Fanuc control.
const MAX_UNITS: i64 = 99_999_999;

impl Plan {
    /// A plan with the defaults: subprogram style, zig-zag, the copy-milling paper's feed
    /// and program number, the fanuc post and its trigger, 3 decimals, T1.
    pub fn new(origin: [f64; 2], count: [u32; 2], pitch: f64, z_safe: f64, plunge: f64) -> Plan {
        let post = WriteOptions::preset("fanuc").unwrap_or_default();
        Plan {
            origin,
            count,
            pitch,
            z_safe,
            plunge,
            style: Style::default(),
            pattern: Pattern::default(),
            plunge_feed: DEFAULT_PLUNGE_FEED,
            feed: None,
            program: DEFAULT_PROGRAM,
            trigger: default_trigger(&post).unwrap_or_default(),
            digits: 3,
            post,
            tool: DEFAULT_TOOL,
        }
    }

    /// Z of every plunge bottom: `z_safe − plunge`.
    pub fn bottom(&self) -> f64 {
        self.z_safe - self.plunge
    }

    /// The plunge bottoms `[x, y, z]` in the order they are measured.
    pub fn points(&self) -> Vec<[f64; 3]> {
        let (x0, y0, p, z) = (self.origin[0], self.origin[1], self.pitch, self.bottom());
        order(self.count, self.pattern).map(|[i, j]| [x0 + f64::from(i) * p, y0 + f64::from(j) * p, z]).collect()
    }

    /// Checks the plan; the error says which value is wrong and why.
    pub fn validate(&self) -> Result<(), Error> {
        self.layout().map(|_| ())
    }

    /// The program text (`\n` line ends), framed by the post.
    pub fn program(&self) -> Result<String, Error> {
        program::text(self, self.layout()?)
    }

    /// Validates and converts to integer units.
    fn layout(&self) -> Result<Grid, Error> {
        let [nx, ny] = self.count;
        if nx < 1 || ny < 1 {
            return err(format!("the grid needs at least 1 point each way, got {nx} x {ny}"));
        }
        let total = u64::from(nx) * u64::from(ny);
        if total > MAX_POINTS {
            return err(format!("{nx} x {ny} = {total} points is more than {MAX_POINTS}"));
        }
        if self.digits > MAX_DIGITS {
            return err(format!("digits must be 0 to {MAX_DIGITS}, got {}", self.digits));
        }
        let scale = 10i64.pow(self.digits);
        let units = |v: f64, what: &str| -> Result<i64, Error> {
            if !v.is_finite() {
                return err(format!("{what} must be a finite number, got {v}"));
            }
            let u = v * scale as f64;
            if u.abs() > MAX_UNITS as f64 {
                return err(format!("{what} {v} has more than 8 digits at {} decimals", self.digits));
            }
            let r = u.round();
            if (u - r).abs() > 1e-6 {
                return err(format!(
                    "{what} {v} is not a whole number of {} mm: give it with at most {} decimals (or raise the digits)",
                    1.0 / scale as f64,
                    self.digits
                ));
            }
            Ok(r as i64)
        };
        let x0 = units(self.origin[0], "origin X")?;
        let y0 = units(self.origin[1], "origin Y")?;
        if !(self.pitch.is_finite() && self.pitch > 0.0) {
            return err(format!("the pitch must be a positive number, got {}", self.pitch));
        }
        if !(self.plunge.is_finite() && self.plunge > 0.0) {
            return err(format!("the plunge depth must be a positive number, got {}", self.plunge));
        }
        let pitch = units(self.pitch, "the pitch")?;
        let plunge = units(self.plunge, "the plunge depth")?;
        let z_safe = units(self.z_safe, "z-safe")?;
        let check = |u: i64, what: &str| -> Result<i64, Error> {
            if u.abs() > MAX_UNITS {
                return err(format!("{what} is beyond 8 digits at {} decimals", self.digits));
            }
            Ok(u)
        };
        // The farthest the stylus goes: one pitch past the last row and column
        // (the return moves of the subprogram style) and the bottom.
        check(x0 + i64::from(nx) * pitch, "the last column (X)")?;
        check(y0 + i64::from(ny) * pitch, "the last row (Y)")?;
        check(i64::from(nx) * pitch, "a row's length")?;
        let bottom = check(z_safe - plunge, "the plunge bottom")?;
        for (feed, what) in [(Some(self.plunge_feed), "the plunge feed"), (self.feed, "the feed")] {
            if let Some(f) = feed {
                if !(f.is_finite() && f > 0.0 && f < 100_000.0) {
                    return err(format!("{what} must be above 0 and below 100000 mm/min, got {f}"));
                }
            }
        }
        let last = match self.style {
            Style::Subprogram => self.program.checked_add(3),
            _ => Some(self.program),
        };
        let dialect = self.post.dialect;
        if dialect != Dialect::Fanuc && self.style != Style::Expanded {
            let (style, what) = match self.style {
                Style::G31 => ("g31", "G31 and DPRNT (Fanuc custom macro B)"),
                _ => ("subprogram", "M98 P… L… subprograms"),
            };
            let controls = if dialect == Dialect::Grbl { "GRBL" } else { "LinuxCNC and Mach3" };
            return err(format!(
                "the {style} style writes {what}, which only Fanuc and Haas controls run; for {controls} write \
                 the expanded style (--style expanded)"
            ));
        }
        if self.tool > 9999 {
            return err(format!("the stylus's tool number must be 0 to 9999, got {}", self.tool));
        }
        if self.program < 1 || !matches!(last, Some(l) if l <= 9999) {
            let what = if self.style == Style::Subprogram { " (it and the 3 after it)" } else { "" };
            return err(format!("the program number{what} must be 1 to 9999, got {}", self.program));
        }
        if self.style == Style::Subprogram {
            let rows = if self.pattern == Pattern::Zigzag { ny / 2 } else { ny };
            if rows > MAX_REPEATS || nx - 1 > MAX_REPEATS {
                return err(format!(
                    "M98 repeats at most L{MAX_REPEATS}: {nx} x {ny} points need the expanded or g31 style"
                ));
            }
        }
        if self.style != Style::G31 {
            if self.trigger.is_empty() {
                return err("the trigger needs at least one block (default M07, G04 X0.5, M09)");
            }
            for (k, block) in self.trigger.iter().enumerate() {
                check_trigger(block, dialect).or_else(|m| err(format!("trigger block {} '{block}': {m}", k + 1)))?;
            }
        }
        Ok(Grid { x0, y0, pitch, plunge, z_safe, bottom })
    }
}

/// The plan in integer units of `10^-digits` mm.
#[derive(Clone, Copy, Debug)]
struct Grid {
    x0: i64,
    y0: i64,
    pitch: i64,
    plunge: i64,
    z_safe: i64,
    bottom: i64,
}

/// A trigger block must be one plain block that does not move the stylus,
/// change a modal G code or end, call or leave the program: only `G04` may
/// appear as a G code, and the block is run between two moves to prove it.
fn check_trigger(block: &str, dialect: Dialect) -> Result<(), String> {
    let b = block.trim();
    if b.is_empty() {
        return Err("an empty block".into());
    }
    if let Some(c) = b.chars().find(|&c| !(c == ' ' || c.is_ascii_graphic()) || matches!(c, '%' | ';')) {
        return Err(format!("the character {c:?} cannot be in a block"));
    }
    if b.starts_with(['O', 'o', ':']) {
        return Err("a program number starts a new program".into());
    }
    // G codes outside comments: G04 only.
    let bytes = b.as_bytes();
    let mut depth = 0;
    for (k, &c) in bytes.iter().enumerate() {
        match c {
            b'(' => depth += 1,
            b')' => depth -= 1,
            b'G' | b'g' if depth == 0 => {
                let number: String = bytes[k + 1..]
                    .iter()
                    .skip_while(|c| **c == b' ')
                    .take_while(|c| c.is_ascii_digit() || **c == b'.')
                    .map(|&c| c as char)
                    .collect();
                if number.parse::<f64>() != Ok(4.0) {
                    return Err(format!("only G04 may be in a trigger block, found G{number}"));
                }
            }
            _ => {}
        }
    }
    // Run it between two absolute moves: it must neither move nor change how
    // the next move is read, and the program must go on to its M30.
    let text = format!("G90 G0 X5. Y0. Z0.\n{b}\nG0 X1.\nM30\n");
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("trigger", text.clone()));
    let mut program = Program::default();
    if let Some(d) = parse(&mut program, file, &text).first() {
        return Err(d.message.clone());
    }
    let settings = read_as(dialect);
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings);
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        return Err(d.message.clone());
    }
    let moves = &outcome.toolpath.moves;
    let between = moves.get(1..moves.len().saturating_sub(1)).unwrap_or(&[]);
    let last = moves.last().map(|m| (m.end.x, m.end.y, m.end.z));
    if !outcome.completed || outcome.blocks != 4 || moves.len() < 2 || last != Some((1.0, 0.0, 0.0)) {
        return Err("it must not end, call or leave the program, or change how positions are read".into());
    }
    if between.iter().any(|m| !matches!(m.kind, kezuri_geom::MoveKind::Dwell(_))) {
        return Err("it moves the stylus".into());
    }
    Ok(())
}

/// The trigger at each plunge bottom in `post`'s words: air blow on
/// (`M07`), a dwell of [`TRIGGER_DWELL`] s, off (`M09`).
pub fn default_trigger(post: &WriteOptions) -> Result<Vec<String>, Error> {
    let codes = post.dialect.codes();
    let dwell = dwell_block(&text_options(post), TRIGGER_DWELL)?;
    Ok(vec![codes.mist.to_string(), dwell, codes.coolant_off.to_string()])
}

/// How kezuri's interpreter reads a program of `dialect`: a LinuxCNC or
/// GRBL `P` of `G4` is seconds, and a number without a point is mm.
pub fn read_as(dialect: Dialect) -> interp::Settings {
    let mut settings = interp::Settings::default();
    if dialect != Dialect::Fanuc {
        settings.integer_input = interp::IntegerInput::Units;
        settings.coords.control = interp::Control::LinuxCnc;
    }
    settings
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_index_follows_order() {
        for pattern in [Pattern::Zigzag, Pattern::OneWay] {
            let all: Vec<[u32; 2]> = order([4, 3], pattern).collect();
            for (k, ij) in all.iter().enumerate() {
                assert_eq!(grid_index(k as u64, [4, 3], pattern), Some(*ij));
            }
            assert_eq!(grid_index(12, [4, 3], pattern), None);
        }
        let zig: Vec<[u32; 2]> = order([3, 2], Pattern::Zigzag).collect();
        assert_eq!(zig, [[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]]);
    }

    #[test]
    fn triggers_are_checked() {
        for ok in ["M07", "G04 X0.5", "M09", "G4 P500", "M00", "M07 (AIR ON)"] {
            assert_eq!(check_trigger(ok, Dialect::Fanuc), Ok(()), "{ok}");
        }
        for bad in ["", "G91", "G01 X1.", "M07 X5.", "M30", "M98 P1234", "O1234", "M99", "G20", "G04 X0.5 %"] {
            assert!(check_trigger(bad, Dialect::Fanuc).is_err(), "{bad} is refused");
        }
        for ok in ["M7", "G4 P0.5", "M9"] {
            assert_eq!(check_trigger(ok, Dialect::LinuxCnc), Ok(()), "{ok}");
        }
    }
}
