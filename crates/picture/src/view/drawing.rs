//! The moves of one level of detail as the page will draw them, kept in
//! little room while the path is fed, then laid out as the page's columns
//! (see [`super`] for the layout).
//!
//! A [`Drawing`] takes drawn moves one at a time and keeps what the page's
//! columns need of each: kind, tool number, work zero, line, feed and
//! seconds as the page stores them, and the points it is drawn through, as
//! bytes (a flag where a value is the last one's; a coordinate that is a
//! whole number of 0.1 µm — as a program's decimals read — as its
//! difference from the last in a few bytes, any other as its 8). Nothing is
//! rounded: the positions come back bit for bit, so the page quantizes them
//! about the middle of the whole path as it always did, once the path is
//! known. A raster move takes some 12 bytes.

use std::io::Write;

use kezuri_geom::{Move, MoveKind};
use serde_json::{json, Value};

use super::blob::Columns;
use super::pack::{ToolLook, QUANTUM_MM, UNPLACED};
use crate::{Error, ErrorKind};

/// Largest distance from the packing origin, in quanta (±107 m), so that a
/// difference of two positions fits an `i32`.
const REACH: i64 = 1 << 30;

/// How a point of a move is drawn.
const POINT: u8 = 0;
/// The move's start, drawn (after a break) only where it is not where the
/// last drawn point is, once both are quantized.
const START: u8 = 1;
/// The end of a move from where the program does not say: after a break.
const ARRIVED: u8 = 2;

/// A coordinate's unit when kept as a whole number: 0.1 µm.
const STEPS_PER_MM: f64 = 1e4;

/// The moves drawn at one level of detail, in little room.
pub struct Drawing {
    /// Arcs drawn as chords within this sagitta, mm.
    arc_tol: f64,
    /// The moves, as bytes.
    bytes: Chunks,
    /// Moves kept.
    pub moves: u64,
    /// Their seconds summed in order, as the page's cycle time.
    pub seconds: f64,
    /// The box of what is drawn.
    pub bounds: Option<([f64; 3], [f64; 3])>,
    /// Whether a move turns a rotary axis.
    pub rotary: bool,
    /// The work zeros, by first use.
    zeros: Vec<[f64; 3]>,
    /// Whether the next move starts where the program does not say.
    from_unknown: bool,
    /// What the last move kept said, to say only what changes.
    last: Last,
    /// The last point kept.
    last_point: Option<[f64; 3]>,
    /// The last whole-number coordinates.
    steps: [i64; 3],
    /// Scratch: a move's points.
    through: Vec<[f64; 3]>,
}

/// What the last move said.
#[derive(Clone, Copy, Default)]
struct Last {
    tool: Option<u32>,
    zero: Option<usize>,
    /// The work zero's frame (the index the moves give), and its zero's index.
    frame: Option<(u32, usize)>,
    line: i64,
    feed: Option<u32>,
    seconds: Option<u32>,
}

/// One move read back.
#[derive(Clone, Copy, Default)]
struct Read {
    kind: u8,
    tool: u32,
    zero: usize,
    line_delta: i32,
    feed: f32,
    seconds: f32,
}

impl Drawing {
    /// An empty drawing; `unknown_start`: the first move starts where the
    /// program does not say; arcs as chords within `arc_tol`.
    pub fn new(unknown_start: bool, arc_tol: f64) -> Drawing {
        Drawing {
            arc_tol,
            bytes: Chunks::default(),
            moves: 0,
            // The sum of no seconds, as Rust's sum of f64 gives it.
            seconds: std::iter::empty::<f64>().sum(),
            bounds: None,
            rotary: false,
            zeros: Vec::new(),
            from_unknown: unknown_start,
            last: Last::default(),
            last_point: None,
            steps: [0; 3],
            through: Vec::new(),
        }
    }

    /// Bytes held.
    pub fn held(&self) -> usize {
        self.bytes.held()
    }

    /// Keeps the next move drawn: `m` of page kind `kind`, `seconds` long,
    /// its work zero `zero`.
    pub fn add(&mut self, m: &Move, kind: u8, seconds: f64, zero: [f64; 3]) {
        self.moves += 1;
        self.seconds += seconds;
        let from_unknown = std::mem::replace(&mut self.from_unknown, m.unknown.0 & 0b111 != 0);
        self.rotary |= m.start.a != m.end.a || m.start.b != m.end.b || m.start.c != m.end.c;
        let mut through = std::mem::take(&mut self.through);
        points(m, kind, from_unknown, self.arc_tol, &mut through);
        let start = (!from_unknown && !through.is_empty()).then(|| m.start.xyz());
        for p in start.iter().chain(&through) {
            let (lo, hi) = self.bounds.get_or_insert((*p, *p));
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let zero = match self.last.frame {
            Some((f, z)) if f == m.frame => z,
            _ => {
                let z = self.zeros.iter().position(|z0| *z0 == zero).unwrap_or_else(|| {
                    self.zeros.push(zero);
                    self.zeros.len() - 1
                });
                self.last.frame = Some((m.frame, z));
                z
            }
        };
        let feed = if kind == 0 || kind == 5 { 0.0 } else { m.feed as f32 }.to_bits();
        let secs = (seconds as f32).to_bits();
        let line_delta = i64::from(m.line) - self.last.line;
        let mut head = kind;
        head |= u8::from(self.last.tool != Some(m.tool)) << 3;
        head |= u8::from(self.last.zero != Some(zero)) << 4;
        head |= u8::from(self.last.feed != Some(feed)) << 5;
        head |= u8::from(line_delta != 1) << 6;
        head |= u8::from(self.last.seconds != Some(secs)) << 7;
        self.bytes.push(head);
        if head & 8 != 0 {
            self.bytes.varint(u64::from(m.tool));
        }
        if head & 16 != 0 {
            self.bytes.varint(zero as u64);
        }
        if head & 64 != 0 {
            self.bytes.varint(zigzag(line_delta));
        }
        if head & 32 != 0 {
            self.bytes.extend(&feed.to_le_bytes());
        }
        if head & 128 != 0 {
            self.bytes.extend(&secs.to_le_bytes());
        }
        self.last = Last {
            tool: Some(m.tool),
            zero: Some(zero),
            line: i64::from(m.line),
            feed: Some(feed),
            seconds: Some(secs),
            ..self.last
        };
        // Its points: where it arrives from an unknown place, its end
        // after a break; else its start where the last point is elsewhere,
        // then its points.
        let mut entries = Vec::with_capacity(through.len() + 1);
        if from_unknown && !through.is_empty() {
            entries.push((ARRIVED, through[0]));
        } else if let Some(s) = start {
            if self.last_point != Some(s) {
                entries.push((START, s));
            }
            entries.extend(through.iter().map(|p| (POINT, *p)));
        }
        self.bytes.varint(entries.len() as u64);
        for (role, p) in entries {
            self.point(role, p);
        }
        self.through = through;
    }

    /// Keeps one point: its role, then each coordinate.
    fn point(&mut self, role: u8, p: [f64; 3]) {
        let whole: [Option<i64>; 3] = std::array::from_fn(|k| {
            let n = (p[k] * STEPS_PER_MM).round();
            (n.abs() < 4e15 && (n / STEPS_PER_MM).to_bits() == p[k].to_bits()).then_some(n as i64)
        });
        let mut tag = role;
        for (k, w) in whole.iter().enumerate() {
            tag |= u8::from(w.is_none()) << (2 + k);
        }
        self.bytes.push(tag);
        for k in 0..3 {
            match whole[k] {
                Some(n) => {
                    self.bytes.varint(zigzag(n - self.steps[k]));
                    self.steps[k] = n;
                }
                None => self.bytes.extend(&p[k].to_le_bytes()),
            }
        }
        self.last_point = Some(p);
    }

    /// Reads the moves back in order: each move, with its points and
    /// their roles.
    fn each(&self, mut visit: impl FnMut(&Read, &[(u8, [f64; 3])]) -> Result<(), Error>) -> Result<(), Error> {
        let mut r = Reader { chunks: &self.bytes.0, chunk: 0, at: 0 };
        let mut read = Read::default();
        let mut steps = [0i64; 3];
        let mut points = Vec::new();
        while !r.done() {
            let head = r.byte();
            read.kind = head & 7;
            if head & 8 != 0 {
                read.tool = r.varint() as u32;
            }
            if head & 16 != 0 {
                read.zero = r.varint() as usize;
            }
            let delta = if head & 64 != 0 { unzigzag(r.varint()) } else { 1 };
            read.line_delta = delta as i32;
            if head & 32 != 0 {
                read.feed = f32::from_bits(r.u32());
            }
            if head & 128 != 0 {
                read.seconds = f32::from_bits(r.u32());
            }
            points.clear();
            for _ in 0..r.varint() {
                let tag = r.byte();
                let p: [f64; 3] = std::array::from_fn(|k| {
                    if tag & (4 << k) != 0 {
                        f64::from_bits(r.u64())
                    } else {
                        steps[k] += unzigzag(r.varint());
                        steps[k] as f64 / STEPS_PER_MM
                    }
                });
                points.push((tag & 3, p));
            }
            visit(&read, &points)?;
        }
        Ok(())
    }

    /// Lays the drawing out: the tools (by first use, looking as `looks`
    /// say), the work zeros, the origin and the vertices; refused where a
    /// position is too far from the middle or there are too many tools.
    pub fn layout(&self, looks: Vec<ToolLook>) -> Result<Layout, Error> {
        let origin = match self.bounds {
            Some((lo, hi)) => std::array::from_fn(|k| ((lo[k] + hi[k]) / 2.0 / QUANTUM_MM).round() * QUANTUM_MM),
            None => [0.0; 3],
        };
        let mut tools: Vec<ToolLook> = Vec::new();
        let mut looks = looks;
        let mut layout = Layout { origin, tools: Vec::new(), frames: self.zeros.clone(), vertices: 0 };
        if layout.frames.is_empty() {
            layout.frames.push([0.0; 3]);
        }
        let mut vertices = 0usize;
        let mut last = None;
        self.each(|m, points| {
            if !tools.iter().any(|t| t.number == m.tool) {
                if tools.len() >= usize::from(u16::MAX) {
                    return Err(Error::new(
                        ErrorKind::TooManyTools,
                        format!("the program uses more than {} tools: too many to show", u16::MAX),
                    ));
                }
                let look = match looks.iter().position(|l| l.number == m.tool) {
                    Some(i) => looks.swap_remove(i),
                    None => ToolLook { number: m.tool, label: format!("T{}", m.tool), shape: None, profile: None },
                };
                tools.push(look);
            }
            vertices += layout.quantized(points, &mut last, |_, _| {})? as usize;
            Ok(())
        })?;
        layout.tools = tools;
        layout.vertices = vertices;
        Ok(layout)
    }

    /// Writes the path's columns (sections 1 to 9) laid out as `layout`.
    pub fn write<W: Write>(&self, layout: &Layout, out: &mut Columns<W>) -> Result<(), Error> {
        let mut column: Vec<Read> = Vec::new();
        let batch = |out: &mut Columns<W>, write: &dyn Fn(&mut Columns<W>, &[Read]), column: &mut Vec<Read>| {
            self.each(|m, _| {
                column.push(*m);
                if column.len() == 1 << 14 {
                    write(out, column);
                    column.clear();
                }
                Ok(())
            })?;
            write(out, column);
            column.clear();
            Ok::<(), Error>(())
        };
        batch(out, &|o, c| o.bytes(c.iter().map(|m| m.kind)), &mut column)?;
        out.align();
        let tool = |n: u32| layout.tools.iter().position(|t| t.number == n).unwrap_or(0) as u16;
        batch(out, &|o, c| o.u16s(c.iter().map(|m| tool(m.tool))), &mut column)?;
        out.align();
        batch(out, &|o, c| o.u16s(c.iter().map(|m| u16::try_from(m.zero).unwrap_or(u16::MAX))), &mut column)?;
        out.align();
        batch(out, &|o, c| o.i32s(c.iter().map(|m| m.line_delta)), &mut column)?;
        batch(out, &|o, c| o.f32s(c.iter().map(|m| m.feed)), &mut column)?;
        batch(out, &|o, c| o.f32s(c.iter().map(|m| m.seconds)), &mut column)?;
        let mut last = None;
        self.each(|_, points| {
            let count = layout.quantized(points, &mut last, |_, _| {})?;
            out.u32s([count]);
            Ok(())
        })?;
        for k in 0..3 {
            let mut last = None;
            self.each(|_, points| {
                layout.quantized(points, &mut last, |d, _| out.i32s([d[k]]))?;
                Ok(())
            })?;
        }
        let mut last = None;
        self.each(|_, points| {
            layout.quantized(points, &mut last, |_, brk| out.bytes([u8::from(brk)]))?;
            Ok(())
        })?;
        out.align();
        Ok(())
    }
}

/// Where a drawing's columns start and what they index.
pub struct Layout {
    /// Where the vertex deltas start, mm.
    pub origin: [f64; 3],
    /// The tools, by the index the moves give.
    pub tools: Vec<ToolLook>,
    /// The work zeros, by the index the moves give.
    pub frames: Vec<[f64; 3]>,
    /// Vertices drawn.
    pub vertices: usize,
}

impl Layout {
    /// The meta entries of the path: `moves` drawn, `rotary` whether one
    /// turns a rotary axis.
    pub fn meta(&self, moves: u64, rotary: bool) -> Value {
        let tools: Vec<Value> = self
            .tools
            .iter()
            .map(|t| json!({"number": t.number, "label": t.label, "shape": t.shape, "profile": t.profile}))
            .collect();
        json!({
            "moves": moves,
            "vertices": self.vertices,
            "quantum_mm": QUANTUM_MM,
            "origin_mm": self.origin,
            "frames": self.frames,
            "tools": tools,
            "rotary": rotary,
        })
    }

    /// A move's points quantized about the origin: hands `vertex` each
    /// vertex drawn (its difference from the last, and whether it follows a
    /// break); `last` the last vertex drawn. Returns how many.
    fn quantized(
        &self,
        points: &[(u8, [f64; 3])],
        last: &mut Option<[i64; 3]>,
        mut vertex: impl FnMut([i32; 3], bool),
    ) -> Result<u32, Error> {
        let mut count = 0;
        for &(role, p) in points {
            let q = self.quantize(p)?;
            if role == START && *last == Some(q) {
                continue;
            }
            let before = last.unwrap_or([0; 3]);
            vertex(std::array::from_fn(|k| (q[k] - before[k]) as i32), role != POINT);
            *last = Some(q);
            count += 1;
        }
        Ok(count)
    }

    /// `p` in quanta from the origin.
    fn quantize(&self, p: [f64; 3]) -> Result<[i64; 3], Error> {
        let mut q = [0i64; 3];
        for k in 0..3 {
            let v = ((p[k] - self.origin[k]) / QUANTUM_MM).round();
            if !v.is_finite() || v.abs() >= REACH as f64 {
                return Err(Error::new(
                    ErrorKind::PositionOutOfReach,
                    format!(
                        "a position {:.3} mm from the middle of the program cannot be shown",
                        p[k] - self.origin[k]
                    ),
                ));
            }
            q[k] = v as i64;
        }
        Ok(q)
    }
}

/// The points a move is drawn through after its start: the end, or an
/// arc's chords within `tol`; none for a move of kind [`UNPLACED`], and
/// only the end for one whose start is not known (`from_unknown`).
fn points(m: &Move, kind: u8, from_unknown: bool, tol: f64, out: &mut Vec<[f64; 3]>) {
    out.clear();
    match m.kind {
        _ if kind == UNPLACED => {}
        MoveKind::Dwell(_) => {}
        _ if from_unknown => out.push(m.end.xyz()),
        MoveKind::Arc(arc) => {
            let n = arc.chords(m.start, m.end, tol);
            out.extend((1..n).map(|k| arc.point_at(m.start, m.end, k as f64 / n as f64).xyz()));
            out.push(m.end.xyz());
        }
        _ => out.push(m.end.xyz()),
    }
}

fn zigzag(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

fn unzigzag(v: u64) -> i64 {
    ((v >> 1) as i64) ^ -((v & 1) as i64)
}

/// Bytes in blocks of [`CHUNK`]: a drawing grows without being moved, and
/// holds at most one block more than it uses.
#[derive(Default)]
struct Chunks(Vec<Vec<u8>>);

/// Bytes a block of [`Chunks`] holds.
const CHUNK: usize = 1 << 20;

impl Chunks {
    fn push(&mut self, b: u8) {
        match self.0.last_mut() {
            Some(last) if last.len() < CHUNK => last.push(b),
            _ => {
                let mut block = Vec::with_capacity(CHUNK);
                block.push(b);
                self.0.push(block);
            }
        }
    }

    fn extend(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.push(b);
        }
    }

    fn varint(&mut self, mut v: u64) {
        while v >= 0x80 {
            self.push((v as u8) | 0x80);
            v >>= 7;
        }
        self.push(v as u8);
    }

    /// Bytes held.
    fn held(&self) -> usize {
        self.0.iter().map(Vec::capacity).sum()
    }
}

/// Bytes read back in order (the drawing wrote them: never short).
struct Reader<'a> {
    chunks: &'a [Vec<u8>],
    chunk: usize,
    at: usize,
}

impl Reader<'_> {
    fn done(&self) -> bool {
        self.chunks.get(self.chunk).is_none_or(|c| self.at >= c.len())
    }

    fn byte(&mut self) -> u8 {
        let Some(chunk) = self.chunks.get(self.chunk) else { return 0 };
        let b = chunk.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        if self.at >= chunk.len() && self.chunk + 1 < self.chunks.len() {
            self.chunk += 1;
            self.at = 0;
        }
        b
    }

    fn varint(&mut self) -> u64 {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let b = self.byte();
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                break;
            }
        }
        v
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(std::array::from_fn(|_| self.byte()))
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(std::array::from_fn(|_| self.byte()))
    }
}
