//! `kezuri thermal …`: thermal-drift measurements.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use kezuri_correct::edge::find_edge;
use kezuri_correct::thermal::model_file;
use kezuri_correct::thermal::{self, correct_moves, fit, is_warm, linear_axis, stop_error, warm_less_cold};
use kezuri_correct::thermal::{Corrected, Correcting, Measurement, Summary};
use kezuri_geom::{set_ends, set_ends_after, ArcCentre, Axes, Toolpath};
use kezuri_machine::Machine;
use kezuri_nc::thermal_plan::{Station, ThermalPlan};
use serde_json::json;

use crate::corrected::{in_program, run_to_correct, stream_corrected, streams, write_corrected, Correction};
use crate::files::{read_text, write_output};
use crate::program::{RunOptions, WriteArgs};
use crate::table::{read_columns, Table};

/// The thermal commands.
#[derive(Subcommand, Debug)]
pub enum ThermalCommand {
    /// The measuring program (O2007): the reference tool's edge stepped through
    /// the line sensors along each linear axis at each indexed B angle, a dwell at every stop.
    Plan(PlanArgs),
    /// The reference tool's edge in a line-sensor profile: the profile split into its two
    /// sides, a robust least-squares line through each, their intersection and angle.
    Edge(EdgeArgs),
    /// The measurements CSV from the two line sensors' profiles: each row's edges found, the
    /// 3D edge from sensor 1's X–Z and sensor 2's Y–Z, less the command.
    Measure(MeasureArgs),
    /// Each linear axis's error functions (per indexed B angle) fitted to measurements:
    /// polynomials, degree by leave-one-out unless given; the model as JSON.
    Fit(FitArgs),
    /// The program corrected: every end point commanded where the warm machine puts the
    /// tool on the CAM target (Newton to 1 nm, or a grid search).
    Apply(Box<ApplyArgs>),
}

/// Which way the corrected command is found.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Solver {
    /// Newton's method to 1 nm.
    Newton,
    /// A grid search: ±50 candidates per axis 1 µm apart about the first-order estimate.
    Grid,
}

/// `kezuri thermal apply IN --model MODEL.json -o OUT`.
#[derive(Args, Debug)]
#[command(after_help = "The program is run (macros and subprograms expanded) and written again with every end point
corrected, in the dialect asked (--digits defaults to 4 here: three decimals cannot hold
0.1 µm). An arc keeps its turn: its centre moves with the correction of its end point (the
correction changes by well under a micrometre over an arc); the largest such change is
reported as arc_correction_change_mm.

A point beyond the measured range of its axis is corrected by extrapolating the fitted
curve: the count is printed, and a program with more than a tenth of its points there is
refused unless --allow-extrapolation (O2007's approach and retract at Z0 are: 5 of 28).

Examples:
  kezuri demo --only thermal -o demo
  kezuri thermal apply samples/o2007-thermal.nc \\
      --model demo/thermal-model.json --machine samples/mill-turn.toml \\
      --allow-extrapolation -o o2007-warm.nc
  kezuri thermal apply samples/o2007-thermal.nc \\
      --model demo/thermal-model.json --machine samples/mill-turn.toml \\
      --allow-extrapolation --to linuxcnc -o o2007-warm.ngc --json")]
pub struct ApplyArgs {
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub write: WriteArgs,
    /// The model (from `kezuri thermal fit`).
    #[arg(long, value_name = "MODEL.json")]
    pub model: PathBuf,
    /// How the corrected command is found.
    #[arg(long, value_enum, default_value = "newton")]
    pub solver: Solver,
    /// Print one JSON object: points, max_correction_mm, max_residual_mm, seconds.
    #[arg(long)]
    pub json: bool,
    /// Keep the program's own text — comments, words, layout, macro statements that make no
    /// move — and change only the numbers of X, Y, Z (and I, J, K of arcs), adding the axis
    /// words a corrected block needs; for G90 programs without calls or offsets.
    #[arg(long)]
    pub keep_text: bool,
    /// Correct the program even where more than a tenth of its points lie beyond the measured
    /// range of their axis (their correction is then extrapolated from the fitted curve).
    #[arg(long)]
    pub allow_extrapolation: bool,
}

/// `kezuri thermal measure INDEX.csv -o MEAS.csv`.
#[derive(Args, Debug)]
#[command(after_help = "INDEX.csv has the header axis,command_mm,b_deg,state,profile_1,profile_2: one row per stop
of the measuring program, cold and warm, naming the two sensors' profiles (x_mm,z_mm files,
relative to INDEX.csv's folder). Sensor 1 sees the machine's X-Z plane (its x is X), sensor 2
the Y-Z plane (its x is Y); the edge is (X, Y, the mean of the two Z). Each row of MEAS.csv is
that edge less the command along its axis; the sensors' own places cancel in warm - cold, so
give both states.

Examples:
  kezuri demo --only thermal -o demo
  kezuri thermal measure demo/thermal/index.csv -o meas.csv
  kezuri thermal fit meas.csv --machine samples/mill-turn.toml -o model.json")]
pub struct MeasureArgs {
    /// The index of profiles.
    pub index: PathBuf,
    /// The measurements CSV to write.
    #[arg(short, long, value_name = "MEAS.csv")]
    pub output: Option<PathBuf>,
}

fn measure(a: &MeasureArgs) -> Result<()> {
    let name = a.index.display().to_string();
    let t = Table::parse(&name, &read_text(&a.index)?)?;
    let expected = "axis,command_mm,b_deg,state,profile_1,profile_2";
    let [axis, command, b, state, p1, p2] =
        ["axis", "command_mm", "b_deg", "state", "profile_1", "profile_2"].map(|n| t.require(n, expected));
    let (axis, command, b, state, p1, p2) = (axis?, command?, b?, state?, p1?, p2?);
    let folder = a.index.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
    let edge_of = |r: usize, c: usize| -> Result<[f64; 2]> {
        let file = folder.join(t.text(r, c)?);
        let shown = file.display().to_string();
        let rows = read_columns(&shown, &read_text(&file)?, &["x_mm", "z_mm"])?;
        let points: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
        Ok(find_edge(&points, None).with_context(|| format!("{name}: line {}: {shown}", r + 2))?.edge)
    };
    let mut out = String::from("axis,command_mm,ex_mm,ey_mm,ez_mm,b_deg,state\n");
    for r in 0..t.len() {
        let letter = t.text(r, axis)?.to_ascii_uppercase();
        let k = linear_axis(&letter).map_err(|e| t.error_at(r, axis, &e.message))?;
        let c = t.number(r, command)?;
        let edge = stop_error(k, c, edge_of(r, p1)?, edge_of(r, p2)?);
        out += &format!(
            "{letter},{c},{},{},{},{},{}\n",
            edge[0],
            edge[1],
            edge[2],
            t.number(r, b)?,
            t.text(r, state)?.to_ascii_lowercase()
        );
    }
    write_output(a.output.as_deref(), out.as_bytes())
}

/// `kezuri thermal fit MEAS.csv -o MODEL.json`.
#[derive(Args, Debug)]
#[command(after_help = "MEAS.csv has the header axis,command_mm,ex_mm,ey_mm,ez_mm and optional b_deg and state
columns: one row per measurement of the edge, the error being where the
tool was less where it was commanded. With a state column (cold/warm) the error is warm - cold
at the same axis, angle and command.

Examples:
  kezuri demo --only thermal -o demo
  kezuri thermal fit demo/thermal-meas.csv -o model.json
  kezuri thermal fit demo/thermal-meas.csv --machine samples/mill-turn.toml \\
      --degree 2 -o model.json --json")]
pub struct FitArgs {
    /// The measurements CSV (`-` for standard input).
    pub measurements: PathBuf,
    /// Machine file (TOML) whose axes the model is for [default: a 3-axis mill].
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// Polynomial degree [default: the one with the least leave-one-out error, up to 5].
    #[arg(long, value_name = "N")]
    pub degree: Option<usize>,
    /// The model file (JSON) [default: standard output; the table of the fit then goes to
    /// standard error].
    #[arg(short, long, value_name = "MODEL.json")]
    pub output: Option<PathBuf>,
    /// Also print the fit as one JSON object (with -o FILE).
    #[arg(long)]
    pub json: bool,
}

/// `kezuri thermal plan -o O2007.nc`.
#[derive(Args, Debug)]
#[command(after_help = "Without --at, the standard stations: B 0 from X -2 Z -74, B -90 from X -145 Z -135; each
steps Z then X six times by -4 mm (Z -74 ... -94, then X -2 ... -22 at Z -94).

The program begins as --post begins a program it makes (safe start, retract, T<n> M06 for the
reference tool, --tool-number), applies the tool's length offset on its first Z move (G43 H<its
H> from the machine file's tool table, else H<n>), and ends as the post ends one (retract, home,
M30 or M2). The dwell is G04 X<s> on fanuc and haas, G4 P<s> on linuxcnc and mach3 (in ms where
the machine file's [post] dwell_unit is ms). GRBL has no B axis to index: --post grbl is refused.

Examples:
  kezuri thermal plan --machine samples/mill-turn.toml -o O2007.nc
  kezuri thermal plan --machine samples/mill-turn.toml --at 0:-2,0,-74 \\
      --at -90:-145,0,-135 -o O2007.nc
  kezuri thermal plan --at 0:10,20,-50 --axes x,y,z --steps 11 --pitch 2 \\
      --dwell 2 -o drift.nc
  kezuri thermal plan --machine samples/mill-turn.toml --post linuxcnc \\
      --tool-number 20 -o O2007.ngc")]
pub struct PlanArgs {
    /// A station: B angle and the first stop, `B:X,Y,Z` (repeat for each angle).
    #[arg(long = "at", value_name = "B:X,Y,Z", allow_hyphen_values = true)]
    pub stations: Vec<String>,
    /// The axes stepped at each station, in order.
    #[arg(long, value_name = "AXES", default_value = "z,x")]
    pub axes: String,
    /// Stops per axis (the first included).
    #[arg(long, value_name = "N", default_value_t = 6)]
    pub steps: usize,
    /// Step between stops, mm (signed).
    #[arg(long, value_name = "MM", default_value_t = -4.0, allow_negative_numbers = true, value_parser = crate::numbers::signed_length)]
    pub pitch: f64,
    /// Dwell at each stop for the sensors, s.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    pub dwell: f64,
    /// Feed between stops, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 500.0, value_parser = crate::numbers::positive)]
    pub feed: f64,
    /// Z for the moves between stations.
    #[arg(long, value_name = "Z", default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub safe_z: f64,
    /// Program number [default: the machine file's [post] program_number, else 2007].
    #[arg(long, alias = "number", value_name = "N")]
    pub program_number: Option<u32>,
    /// Machine file (TOML): the program may use only axes it has [default: a 3-axis mill];
    /// its [post] (how the program is written for the control) and tool table (the H register
    /// of G43 H).
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// G-code for this control: fanuc, haas, linuxcnc or mach3 [default: the machine file's
    /// [post] preset, else fanuc].
    #[arg(long, value_name = "NAME")]
    pub post: Option<String>,
    /// The reference tool's number: T<n> M06, and G43 H<its H register> on the first Z move.
    #[arg(long, value_name = "T", default_value_t = 1)]
    pub tool_number: u32,
    /// Output file (default: standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

fn plan(a: &PlanArgs) -> Result<()> {
    let station = |text: &str| -> Result<Station> {
        let parsed = text.split_once(':').and_then(|(b, rest)| {
            let v: Vec<f64> = rest.split(',').map(|p| p.trim().parse().ok()).collect::<Option<_>>()?;
            Some((b.trim().parse::<f64>().ok()?, v))
        });
        match parsed {
            Some((b_deg, v)) if v.len() == 3 => Ok(Station { b_deg, start: [v[0], v[1], v[2]] }),
            _ => bail!("--at '{text}': expected B:X,Y,Z, e.g. 0:-2,0,-74"),
        }
    };
    let stations = if a.stations.is_empty() {
        vec![Station { b_deg: 0.0, start: [-2.0, 0.0, -74.0] }, Station { b_deg: -90.0, start: [-145.0, 0.0, -135.0] }]
    } else {
        a.stations.iter().map(|s| station(s)).collect::<Result<_>>()?
    };
    let axes = a
        .axes
        .split(',')
        .map(|x| match x.trim().to_ascii_uppercase().as_str() {
            "X" => Ok(0),
            "Y" => Ok(1),
            "Z" => Ok(2),
            other => bail!("--axes: '{other}' is not X, Y or Z"),
        })
        .collect::<Result<Vec<usize>>>()?;
    let machine = match &a.machine {
        Some(p) => crate::machine::load(p)?,
        None => Machine::default(),
    };
    if let Some(s) = stations.iter().find(|s| s.b_deg != 0.0 && !machine.kinematics.has(4)) {
        if a.stations.is_empty() {
            bail!(
                "the standard stations index B to {}°, and the machine has no B axis: give --machine with one \
                 (a [kinematics] with B, as samples/mill-turn.toml), or stations at B 0 with --at 0:X,Y,Z",
                s.b_deg
            );
        }
        bail!("--at {}: the machine has no B axis to index (give --machine with one)", s.b_deg);
    }
    let p = ThermalPlan {
        number: a.program_number.or(machine.post.program_number).unwrap_or(2007),
        stations,
        axes,
        steps: a.steps,
        pitch: a.pitch,
        dwell: a.dwell,
        feed: a.feed,
        safe_z: a.safe_z,
        post: kezuri_machine::post::for_machine(&machine, a.post.as_deref(), a.output.as_deref())?,
        tool: a.tool_number,
    };
    let text = p.program()?;
    write_output(a.output.as_deref(), text.as_bytes())?;
    crate::say::note!(
        "wrote {}: {}{} stops at {}",
        crate::say::shown(a.output.as_deref()),
        if p.post.dialect == kezuri_nc::write::Dialect::Fanuc { format!("O{:04}, ", p.number) } else { String::new() },
        p.stops().len(),
        crate::say::count(p.stations.len() as u64, "B angle")
    );
    Ok(())
}

/// `kezuri thermal edge PROFILE.csv`.
#[derive(Args, Debug)]
#[command(after_help = "The profile is a CSV with the header x_mm,z_mm, one point per row in order across the
corner of the square reference tool. Points more than three robust
standard deviations off their side's line are left out.

Examples:
  kezuri demo --only thermal -o demo
  kezuri thermal edge demo/thermal/x0-b0-cold-1.csv
  kezuri thermal edge demo/thermal/x0-b0-warm-1.csv --json
  kezuri thermal edge demo/thermal/x0-b0-cold-1.csv --split -21.7")]
pub struct EdgeArgs {
    /// The profile CSV (`x_mm,z_mm`; `-` for standard input).
    pub profile: PathBuf,
    /// Where the second side starts, x in mm [default: where the two lines fit best].
    #[arg(long, value_name = "X", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub split: Option<f64>,
    /// Print one JSON object: edge, angle_deg, rms_residual_mm, inliers, outliers, sides.
    #[arg(long)]
    pub json: bool,
}

/// Runs a thermal command.
pub fn run(command: &ThermalCommand) -> Result<()> {
    match command {
        ThermalCommand::Plan(a) => plan(a),
        ThermalCommand::Edge(a) => edge(a),
        ThermalCommand::Fit(a) => fit_model(a),
        ThermalCommand::Measure(a) => measure(a),
        ThermalCommand::Apply(a) => apply(a),
    }
}

fn edge(a: &EdgeArgs) -> Result<()> {
    let name = a.profile.display().to_string();
    let rows = read_columns(&name, &read_text(&a.profile)?, &["x_mm", "z_mm"])?;
    let points: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
    let e = find_edge(&points, a.split).with_context(|| name.clone())?;
    if a.json {
        let side = |k: usize| {
            json!({
                "point": e.sides[k].point,
                "direction": e.sides[k].direction,
                "angle_deg": e.sides[k].angle_deg(),
                "inliers": e.inliers[k],
            })
        };
        let v = json!({
            "file": name,
            "points": points.len(),
            "edge": e.edge,
            "angle_deg": e.angle_deg,
            "rms_residual_mm": e.rms_residual_mm,
            "inliers": e.inliers[0] + e.inliers[1],
            "outliers": e.outliers,
            "split_index": e.split,
            "sides": [side(0), side(1)],
        });
        println!("{v}");
    } else {
        print!("{}", e.report(&name, points.len()));
    }
    Ok(())
}

/// The measurements of a table (module docs of `kezuri thermal fit`):
/// with a state column, the drift (warm less cold).
fn measurements(name: &str, t: &Table) -> Result<Vec<Measurement>> {
    let expected = "axis,command_mm,ex_mm,ey_mm,ez_mm[,b_deg][,state]";
    let [axis, command, ex, ey, ez] = ["axis", "command_mm", "ex_mm", "ey_mm", "ez_mm"].map(|n| t.require(n, expected));
    let (axis, command, e) = (axis?, command?, [ex?, ey?, ez?]);
    let (b, state) = (t.column("b_deg"), t.column("state"));
    // (measurement, warm?) per row.
    let mut rows: Vec<(Measurement, bool)> = Vec::new();
    for r in 0..t.len() {
        let a = linear_axis(t.text(r, axis)?).map_err(|e| t.error_at(r, axis, &e.message))?;
        let warm = match state {
            None => false,
            Some(c) => is_warm(t.text(r, c)?).map_err(|e| t.error_at(r, c, &e.message))?,
        };
        let error = [t.number(r, e[0])?, t.number(r, e[1])?, t.number(r, e[2])?];
        let b_deg = match b {
            Some(c) => t.number(r, c)?,
            None => 0.0,
        };
        rows.push((Measurement { axis: a, b_deg, command: t.number(r, command)?, error }, warm));
    }
    if state.is_none() {
        return Ok(rows.into_iter().map(|(m, _)| m).collect());
    }
    let drift = warm_less_cold(&rows).map_err(|(r, e)| t.error_at(r, command, &e.message))?;
    if drift.is_empty() {
        let cold = rows.iter().filter(|(_, warm)| !warm).count();
        bail!(
            "{name}: no warm measurement ({cold} cold, 0 warm): the drift is warm less cold at each stop, so a model needs \
             every stop measured cold and warm",
        );
    }
    Ok(drift)
}

fn fit_model(a: &FitArgs) -> Result<()> {
    let name = a.measurements.display().to_string();
    // The table of the fit goes to standard output unless the model went there.
    let model_to_stdout = a.output.as_deref().is_none_or(|o| o == std::path::Path::new("-"));
    if a.json && model_to_stdout {
        bail!("--json prints to standard output: give the model a file with -o");
    }
    let machine = match &a.machine {
        Some(p) => crate::machine::load(p)?,
        None => Machine::default(),
    };
    let table = Table::parse(&name, &read_text(&a.measurements)?)?;
    let ms = measurements(&name, &table)?;
    let model = fit(&ms, a.degree).with_context(|| name.clone())?;
    let v = model_file::to_json(&model, ms.len(), &machine.kinematics);
    write_output(a.output.as_deref(), (serde_json::to_string_pretty(&v)? + "\n").as_bytes())?;
    if a.json {
        println!("{v}");
        return Ok(());
    }
    let table = format!(
        "{name}: {} measurements, {} error functions -> {}\n{}",
        ms.len(),
        model.functions.len(),
        crate::say::shown(a.output.as_deref()),
        model.table()
    );
    // A summary: --quiet leaves it out wherever the model went.
    if crate::say::quiet() {
    } else if !model_to_stdout {
        write_output(None, table.as_bytes())?;
    } else {
        eprint!("{table}");
    }
    Ok(())
}

fn apply(a: &ApplyArgs) -> Result<()> {
    let name = a.run.file.display().to_string();
    if a.json && a.write.output().is_none_or(|o| o == std::path::Path::new("-")) {
        bail!("--json prints to standard output: give the program a file with -o");
    }
    let shown = a.model.display().to_string();
    let file = model_file::from_json(&read_text(&a.model)?).with_context(|| shown.clone())?;
    let solver = match a.solver {
        Solver::Newton => thermal::Solver::Newton,
        Solver::Grid => thermal::Solver::Grid,
    };
    // The model's machine is checked before the program's axes against it.
    let check = |ran: &crate::program::Ran| file.check_machine(&ran.machine.kinematics).with_context(|| shown.clone());
    let (points, summary, seconds) = if streams(&a.write, a.keep_text) {
        let (outputs, drift) = stream_corrected(
            &a.run,
            &a.write,
            WHAT,
            |machine| Drift {
                correcting: Correcting::new(&file.model, machine.kinematics.clone(), solver),
                before: None,
                points: 0,
                seconds: 0.0,
            },
            check,
            |drift| said_extrapolation(&drift.correcting.summary, a.allow_extrapolation, &name),
        )?;
        outputs.commit()?;
        (drift.points, drift.correcting.summary, drift.seconds)
    } else {
        let (text, mut ran) = run_to_correct(&a.run, check)?;
        let mut path = ran.outcome.toolpath.clone();
        let t0 = std::time::Instant::now();
        let Corrected { ends, summary } = correct_moves(&file.model, &ran.machine.kinematics, &path.moves, solver)
            .map_err(|e| in_program(&name, e))?;
        let seconds = t0.elapsed().as_secs_f64();
        said_extrapolation(&summary, a.allow_extrapolation, &name)?;
        set_ends(&mut path, &ends, ArcCentre::FollowsEnd);
        write_corrected(&a.run, &a.write, a.keep_text, &text, &path, WHAT, &mut ran)?;
        (ends.len(), summary, seconds)
    };
    let v = json!({
        "points": points,
        "max_correction_mm": summary.largest_correction,
        "max_residual_mm": summary.largest_residual,
        "arc_correction_change_mm": summary.arc_correction_change,
        "seconds": seconds,
        "solver": format!("{:?}", a.solver).to_lowercase(),
        "extrapolated_points": summary.extrapolated,
    });
    if a.json {
        println!("{v}");
    } else {
        crate::say::note!(
            "wrote {}: {name}, {} points corrected in {:.3} ms; largest correction {:.4} mm, largest residual \
             {:.2e} mm",
            crate::say::shown(a.write.output()),
            points,
            seconds * 1e3,
            summary.largest_correction,
            summary.largest_residual
        );
    }
    Ok(())
}

/// The title's words of a program corrected for thermal drift.
const WHAT: &str = "CORRECTED FOR THERMAL DRIFT";

/// The warning of the points whose correction is extrapolated, or the
/// refusal of too many.
fn said_extrapolation(summary: &Summary, allowed: bool, name: &str) -> Result<()> {
    if let Some(warning) = summary.extrapolation(allowed).with_context(|| name.to_string())? {
        eprintln!("warning: {name}: {warning}");
    }
    Ok(())
}

/// The thermal correction of a run's path, piece by piece.
struct Drift<'a> {
    correcting: Correcting<'a>,
    /// The last corrected end of the pieces so far.
    before: Option<Axes>,
    /// Moves corrected (returns to the reference point and dwells kept).
    points: usize,
    /// Time spent correcting.
    seconds: f64,
}

impl Correction for Drift<'_> {
    fn correct(&mut self, piece: &Toolpath) -> Result<Toolpath, kezuri_correct::Error> {
        let t0 = std::time::Instant::now();
        let ends = self.correcting.ends(&piece.moves)?;
        self.seconds += t0.elapsed().as_secs_f64();
        let mut corrected = piece.clone();
        self.before = set_ends_after(&mut corrected, &ends, ArcCentre::FollowsEnd, self.before);
        self.points += ends.len();
        Ok(corrected)
    }
}

#[cfg(test)]
mod tests {
    use kezuri_machine::Machine;

    use super::*;
    use crate::corrected::Joined;
    use crate::program::corpus::each_case;

    #[test]
    fn every_program_corrected_in_pieces_is_corrected_whole() {
        // A drift that grows along each axis, measured over ±100 mm.
        let mut ms = Vec::new();
        for axis in 0..3 {
            for k in -4..=4 {
                let command = 25.0 * f64::from(k);
                let error = [1e-4 * command, 5e-3 + 2e-7 * command * command, -3e-5 * command];
                ms.push(Measurement { axis, b_deg: 0.0, command, error });
            }
        }
        let model = thermal::fit(&ms, Some(2)).unwrap();
        let machine = Machine::default();
        let (mut compared, mut cut, mut failed) = (0, 0, 0);
        each_case(&machine, |mut case| {
            let k = machine.kinematics.clone();
            let correcting = Correcting::new(&model, k, thermal::Solver::Newton);
            let drift = Drift { correcting, before: None, points: 0, seconds: 0.0 };
            let mut joined = Joined::new(drift);
            case.run_into(&mut joined);
            let path = &case.whole.toolpath;
            let name = &case.name;
            match correct_moves(&model, &machine.kinematics, &path.moves, thermal::Solver::Newton) {
                Ok(Corrected { ends, summary }) => {
                    let mut whole = path.clone();
                    set_ends(&mut whole, &ends, ArcCentre::FollowsEnd);
                    // Debug writes every f64 to the bit.
                    assert_eq!(format!("{:?}", joined.path.path.moves), format!("{:?}", whole.moves), "{name}");
                    assert_eq!(joined.path.path.kept, whole.kept, "{name}");
                    assert_eq!(format!("{:?}", joined.correction.correcting.summary), format!("{summary:?}"), "{name}");
                    assert_eq!(joined.correction.points, ends.len(), "{name}");
                    compared += 1;
                }
                Err(e) => {
                    assert_eq!(joined.error, Some(e.to_string()), "{name}");
                    failed += 1;
                }
            }
            cut += usize::from(joined.pieces > 2);
        });
        // Pinned, so that the test cannot pass by comparing nothing.
        assert!(compared >= 150 && cut >= 100, "{compared} compared, {cut} cut, {failed} failed");
    }
}
