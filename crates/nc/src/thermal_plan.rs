//! The measuring program for thermal drift (O2007, `kezuri thermal plan`):
//! at each indexed B angle the reference tool's
//! edge is brought into the two line sensors and stepped along each linear
//! axis in known steps, with a dwell at every stop while the sensors read.
//!
//! At each angle the program goes to the safe Z, indexes B, moves to the
//! start, and for each axis asked steps it `steps − 1` times by `pitch`
//! from there (the other axes where the last stop left them, as the
//! paper's program does: Z −74 … −94, then X −2 … −22 at Z −94).
//! [`ThermalPlan::stops`] lists the positions in order; the tests run the
//! program through kezuri's interpreter and compare.
//!
//! The program begins and ends as the post ([`ThermalPlan::post`]) begins
//! and ends a program it makes ([`made_text`]): safe start, retract, change
//! to the reference tool ([`ThermalPlan::tool`]) with its length offset on
//! the first Z move, and the post's end. Its blocks are in the post's
//! dialect (`G00`/`G0`, the dwell `G04 X1.` on Fanuc, `G4 P1` elsewhere).
//! GRBL has no rotary axis to index, so it is refused.

use std::fmt::Write;

use crate::number::number;
use crate::write::{dwell_block, made_text, text_options, Dialect, WriteOptions};
use crate::{Error, ErrorKind};

/// One indexed angle's measurements.
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    /// The B angle, degrees.
    pub b_deg: f64,
    /// The first stop, X Y Z mm.
    pub start: [f64; 3],
}

/// The measuring program.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalPlan {
    /// Program number (the thermal and wear report's 2007).
    pub number: u32,
    /// The angles and their starts.
    pub stations: Vec<Station>,
    /// The axes stepped at each angle, in order (0 X, 1 Y, 2 Z).
    pub axes: Vec<usize>,
    /// Stops per axis (the first included).
    pub steps: usize,
    /// Step, mm (signed; the thermal and wear report: −4).
    pub pitch: f64,
    /// Dwell at each stop, s.
    pub dwell: f64,
    /// Feed between stops, mm/min.
    pub feed: f64,
    /// Z for moves between angles.
    pub safe_z: f64,
    /// How the program begins, changes to the reference tool and ends, and
    /// the dialect of its blocks.
    pub post: WriteOptions,
    /// The reference tool's number (its length register is the post's `H`).
    pub tool: u32,
}

/// A number as a program constant.
fn num(v: f64) -> String {
    number(v, 4)
}

impl ThermalPlan {
    /// Checks the numbers.
    pub fn check(&self) -> Result<(), Error> {
        let bad = |m: String| Err(Error::new(ErrorKind::Plan, m));
        if self.stations.is_empty() {
            return bad("at least one --at B:X,Y,Z is needed".into());
        }
        if self.axes.is_empty() || self.axes.iter().any(|&a| a > 2) {
            return bad("the axes to step are X, Y or Z".into());
        }
        if !(2..=1000).contains(&self.steps) {
            return bad(format!("--steps must be 2 to 1000, got {}", self.steps));
        }
        let finite = [self.pitch, self.dwell, self.feed, self.safe_z]
            .into_iter()
            .chain(self.stations.iter().flat_map(|s| [s.b_deg, s.start[0], s.start[1], s.start[2]]));
        if finite.into_iter().any(|v| !v.is_finite()) || self.pitch == 0.0 || self.dwell < 0.0 || self.feed <= 0.0 {
            return bad("--pitch must be non-zero, --dwell not negative, --feed positive, all finite".into());
        }
        if self.post.dialect == Dialect::Grbl {
            return bad(
                "GRBL has no rotary axis to index B: write the program for fanuc, haas, linuxcnc or mach3".into()
            );
        }
        if self.tool > 9999 {
            return bad(format!("the tool number must be 0 to 9999, got {}", self.tool));
        }
        Ok(())
    }

    /// The stops, in order: B angle and X Y Z.
    pub fn stops(&self) -> Vec<(f64, [f64; 3])> {
        let mut out = Vec::new();
        for s in &self.stations {
            let mut at = s.start;
            out.push((s.b_deg, at));
            for &axis in &self.axes {
                for _ in 1..self.steps {
                    at[axis] += self.pitch;
                    out.push((s.b_deg, at));
                }
            }
        }
        out
    }

    /// The program text, framed by the post.
    pub fn program(&self) -> Result<String, Error> {
        self.check()?;
        let options = WriteOptions {
            program_number: self.number,
            title: Some("THERMAL DRIFT MEASUREMENT: THE EDGE THROUGH THE LINE SENSORS".into()),
            notes: vec![format!(
                "{} STOPS PER AXIS, {} MM APART, {} S DWELL FOR THE SENSORS",
                self.steps,
                num(self.pitch),
                num(self.dwell)
            )],
            ..text_options(&self.post)
        };
        let made = made_text(&options, self.tool)?;
        let comment = |text: &str| if options.comments { format!(" ({text})") } else { String::new() };
        let (safe, index, read) = (comment("SAFE"), comment("INDEX B"), comment("SENSORS READ"));
        let [rapid, feed, ..] = self.post.dialect.codes().motion;
        let dwell = dwell_block(&options, self.dwell)?;
        let mut t = made.start;
        let w = &mut t;
        let mut length = made.length.map(|l| l + " ").unwrap_or_default();
        let per_station = 1 + self.axes.len() * (self.steps - 1);
        for (s, stops) in self.stations.iter().zip(self.stops().chunks(per_station)) {
            let _ = writeln!(w, "{rapid} {}Z{}{safe}", std::mem::take(&mut length), num(self.safe_z));
            let _ = writeln!(w, "{rapid} B{}{index}", num(s.b_deg));
            let _ = writeln!(w, "{rapid} X{} Y{}", num(s.start[0]), num(s.start[1]));
            let _ = writeln!(w, "{feed} Z{} F{}", num(s.start[2]), num(self.feed));
            for (k, (_, at)) in stops.iter().enumerate() {
                if k > 0 {
                    let _ = writeln!(w, "{feed} X{} Y{} Z{}", num(at[0]), num(at[1]), num(at[2]));
                }
                let _ = writeln!(w, "{dwell}{read}");
            }
        }
        let _ = writeln!(w, "{rapid} Z{}", num(self.safe_z));
        t.push_str(&made.end);
        Ok(t)
    }
}
