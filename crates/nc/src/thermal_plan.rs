//! Seed 003's measuring program for thermal drift (the paper's O2007,
//! `kezuri thermal plan`): at each indexed B angle the reference tool's
//! edge is brought into the two line sensors and stepped along each linear
//! axis in known steps, with a dwell at every stop while the sensors read.
//!
//! At each angle the program goes to the safe Z, indexes B, moves to the
//! start, and for each axis asked steps it `steps − 1` times by `pitch`
//! from there (the other axes where the last stop left them, as the
//! paper's program does: Z −74 … −94, then X −2 … −22 at Z −94).
//! [`ThermalPlan::stops`] lists the positions in order; the tests run the
//! program through kezuri's interpreter and compare.

use std::fmt::Write;

use crate::write::number;

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
    /// Program number (the paper's 2007).
    pub number: u32,
    /// The angles and their starts.
    pub stations: Vec<Station>,
    /// The axes stepped at each angle, in order (0 X, 1 Y, 2 Z).
    pub axes: Vec<usize>,
    /// Stops per axis (the first included).
    pub steps: usize,
    /// Step, mm (signed; the paper: −4).
    pub pitch: f64,
    /// Dwell at each stop, s.
    pub dwell: f64,
    /// Feed between stops, mm/min.
    pub feed: f64,
    /// Z for moves between angles.
    pub safe_z: f64,
}

/// Why no program.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanError(pub String);

impl std::fmt::Display for PlanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PlanError {}

/// A number as a program constant.
fn num(v: f64) -> String {
    number(v, 4)
}

impl ThermalPlan {
    /// Checks the numbers.
    pub fn check(&self) -> Result<(), PlanError> {
        let bad = |m: String| Err(PlanError(m));
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

    /// The program text (Fanuc, `%` framed).
    pub fn program(&self) -> Result<String, PlanError> {
        self.check()?;
        let mut t = String::new();
        let w = &mut t;
        let _ = writeln!(w, "%");
        let _ =
            writeln!(w, "O{:04} (THERMAL DRIFT MEASUREMENT, SEED 003: THE EDGE THROUGH THE LINE SENSORS)", self.number);
        let _ = writeln!(
            w,
            "({} STOPS PER AXIS, {} MM APART, {} S DWELL FOR THE SENSORS)",
            self.steps,
            num(self.pitch),
            num(self.dwell)
        );
        let _ = writeln!(w, "G21 G90 G17 G94");
        let per_station = 1 + self.axes.len() * (self.steps - 1);
        for (s, stops) in self.stations.iter().zip(self.stops().chunks(per_station)) {
            let _ = writeln!(w, "G00 Z{} (SAFE)", num(self.safe_z));
            let _ = writeln!(w, "G00 B{} (INDEX B)", num(s.b_deg));
            let _ = writeln!(w, "G00 X{} Y{}", num(s.start[0]), num(s.start[1]));
            let _ = writeln!(w, "G01 Z{} F{}", num(s.start[2]), num(self.feed));
            for (k, (_, at)) in stops.iter().enumerate() {
                if k > 0 {
                    let _ = writeln!(w, "G01 X{} Y{} Z{}", num(at[0]), num(at[1]), num(at[2]));
                }
                let _ = writeln!(w, "G04 X{} (SENSORS READ)", num(self.dwell));
            }
        }
        let _ = writeln!(w, "G00 Z{}", num(self.safe_z));
        let _ = writeln!(w, "M30");
        let _ = writeln!(w, "%");
        Ok(t)
    }
}
