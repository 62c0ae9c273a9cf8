//! `kezuri wear apply`: the program moved so the measured (worn, eccentric)
//! tool cuts what the new tool would have.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use kezuri_cam::Cutter;
use kezuri_correct::kinematics::Kinematics;
use kezuri_correct::wear::{correct_moves, Corrected, Nominal, Options, Summary, Surface};
use kezuri_geom::{set_ends_after, ArcCentre, Axes, MoveKind, ToolProfile, Toolpath};
use serde_json::json;

use crate::corrected::{in_program, run_to_correct, stream_corrected, streams, write_corrected, Correction};
use crate::program::{RunOptions, WriteArgs};

/// `kezuri wear …`.
#[derive(Subcommand, Debug)]
pub enum WearCommand {
    /// Move every cutting point so the measured tool touches the finished surface where the
    /// new tool would: the cutting point and normal on the surface, the surface there taken
    /// as a plane, the tool translated normal to the feed.
    Apply(Box<ApplyArgs>),
}

/// `kezuri wear apply IN --profile P --nominal SPEC --surface PART.stl -o OUT`.
#[derive(Args, Debug)]
#[command(after_help = "For each end point of a cutting move: the point where the new tool (--nominal, ball or
bull-nose) touches the finished surface (--surface, the part as an STL in program coordinates)
and the surface normal there; the measured tool (its profile in tool coordinates, so a tilted B
axis needs nothing more; the machine's rotary axes from --machine) is translated until its gap
to that plane is the new tool's: in the plane normal to the feed, or along the tool axis where
the feed runs within 30° of the normal (plunges, ramps). Rapids, and points whose new tool is
farther than --reach from the surface (moves in the air), are kept as programmed; an arc keeps
its turn: its centre moves the least that puts it halfway between the corrected ends. --digits
defaults to 4.

Examples:
  kezuri relief samples/plum-sketch.png --width 20 --depth 1 --smooth 2 \\
      --tool ball:0.5 --stepover 0.5 --post grbl --surface-stl plum.stl \\
      -o plum.gcode
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-new.csv
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-worn.csv
  kezuri tool db add T7 t7-new.csv --at 2026-05-01T08:00:00Z \\
      --note \"new, 0.5 mm ball\"
  kezuri tool db add T7 t7-worn.csv
  kezuri wear apply plum.gcode --profile t7-worn.csv --nominal ball:0.5 \\
      --surface plum.stl -o plum-worn.gcode
  kezuri wear apply plum.gcode --tool-name T7 --nominal ball:0.5 \\
      --surface plum.stl -o plum-T7.gcode --json")]
pub struct ApplyArgs {
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub write: WriteArgs,
    /// The measured tool (from `kezuri tool profile`).
    #[arg(long, value_name = "PROFILE.csv", required_unless_present = "tool_id", conflicts_with = "tool_id")]
    pub profile: Option<PathBuf>,
    /// The latest profile of this tool in the tool database: its name there (as on its holder:
    /// T12, ball6-a, …; `kezuri tool db list` lists them).
    #[arg(long = "tool-name", alias = "tool-id", value_name = "NAME")]
    pub tool_id: Option<String>,
    /// The tool database (with --tool-name).
    #[arg(long, value_name = "FILE", default_value = "kezuri-tools.sqlite")]
    pub db: PathBuf,
    /// The new tool the program was made for: ball:D (ball end mill of diameter D) or bull:D,R
    /// (bull-nose, corner radius R), mm.
    #[arg(long, value_name = "SPEC")]
    pub nominal: String,
    /// The part as designed, finished: the surface the program was made to cut (an STL in program
    /// coordinates, such as relief's --surface-stl), where the new tool touches it.
    #[arg(long, value_name = "PART.stl")]
    pub surface: PathBuf,
    /// The unit the --surface STL is drawn in (STL files carry none): `inch` multiplies it by 25.4.
    /// [default: mm, with a note where the model is under 13 mm in every direction]
    #[arg(long, value_enum, value_name = "mm|inch")]
    pub units: Option<crate::surface::Units>,
    /// Points whose new tool is farther than this from the surface are kept (mm).
    #[arg(long, value_name = "MM", default_value_t = 0.05, value_parser = crate::numbers::length)]
    pub reach: f64,
    /// Print one JSON object: points, max_correction_mm, max_residual_mm, seconds, and the
    /// counts of corrected and kept points.
    #[arg(long)]
    pub json: bool,
    /// Keep the program's own text and change only the numbers of X, Y, Z (and I, J, K).
    #[arg(long)]
    pub keep_text: bool,
}

/// Runs a `wear` command.
pub fn run(command: &WearCommand) -> Result<()> {
    match command {
        WearCommand::Apply(a) => apply(a),
    }
}

/// The new tool as the correction sees it.
fn nominal(spec: &str) -> Result<Nominal> {
    let cutter: Cutter = spec.parse().context("--nominal")?;
    match cutter {
        Cutter::Ball(_) => Ok(Nominal { radius: cutter.radius(), corner: cutter.radius() }),
        Cutter::Bull(b) if b.corner > 0.0 => Ok(Nominal { radius: cutter.radius(), corner: b.corner }),
        _ => bail!(
            "--nominal {spec}: wear apply corrects ball and bull-nose end mills (a flat bottom touches a whole disc, \
             not a point)"
        ),
    }
}

/// Runs `kezuri wear apply`.
fn apply(a: &ApplyArgs) -> Result<()> {
    let name = a.run.file.display().to_string();
    if a.json && a.write.output().is_none_or(|o| o == std::path::Path::new("-")) {
        bail!("--json prints to standard output: give the program a file with -o");
    }
    let nominal = nominal(&a.nominal)?;
    let worn: ToolProfile = match (&a.profile, &a.tool_id) {
        (Some(p), _) => crate::tool_profile::read_profile(p)?,
        (None, Some(id)) => crate::tool_store::latest_profile(&a.db, id)?,
        (None, None) => bail!("give --profile or --tool-name"),
    };
    let stl = a.surface.display().to_string();
    let mesh = crate::surface::read_mesh(&a.surface, a.units)?;
    let surface = Surface::new(&mesh);
    let options = Options { reach: a.reach };
    // Refused where nothing was corrected: the surface is not where the program cuts.
    let judge = |totals: &Totals| {
        if totals.corrected == 0 && totals.gouges.count > 0 && totals.far.count == 0 {
            bail!(
                "{name}: every cutting point cuts into {stl}: do its triangles face inward (check the STL's winding)?"
            );
        }
        if totals.corrected == 0 {
            bail!("{name}: no cutting point within {} mm of {stl}: is the part in program coordinates?", a.reach);
        }
        Ok(())
    };
    let wear = |k| Wear {
        surface: &surface,
        nominal,
        worn: &worn,
        k,
        options,
        before: None,
        totals: Totals::default(),
        turned: None,
        seconds: 0.0,
    };
    let wear = if streams(&a.write, a.keep_text) {
        let judged =
            |w: &Wear| judge(&w.totals).and_then(|()| w.turned.as_ref().map_or(Ok(()), |t| Err(t.refusal(&name))));
        let (outputs, wear) =
            stream_corrected(&a.run, &a.write, WHAT, |machine| wear(machine.kinematics.clone()), |_| Ok(()), judged)?;
        outputs.commit()?;
        wear
    } else {
        let (text, mut ran) = run_to_correct(&a.run, |_| Ok(()))?;
        let mut wear = wear(ran.machine.kinematics.clone());
        let path = wear.correct(&ran.outcome.toolpath).map_err(|e| in_program(&name, e))?;
        judge(&wear.totals)?;
        if let Some(turned) = &wear.turned {
            return Err(turned.refusal(&name));
        }
        write_corrected(&a.run, &a.write, a.keep_text, &text, &path, WHAT, &mut ran)?;
        wear
    };
    let Totals { corrected, along_axis, largest, worst, worst_before, far, gouges, square } = wear.totals;
    let seconds = wear.seconds;
    if let Some(&(line, d)) = gouges.first.first() {
        eprintln!(
            "warning: {name}: {} point(s) where the new tool itself cuts more than {} mm into the surface (first at \
             line {line}, {d:.4} mm): kept as programmed",
            gouges.count, a.reach
        );
    }
    if let Some(&(line, e)) = square.first.first() {
        eprintln!(
            "warning: {name}: {} point(s) fed square into a wall along the tool (first at line {line}, error \
             {e:.4} mm): no short correction normal to the feed; kept as programmed",
            square.count
        );
    }
    if let Some(&line) = far.first.first() {
        eprintln!(
            "warning: {name}: {} cutting point(s) farther than {} mm from the surface (first at line {line}): kept as \
             programmed",
            far.count, a.reach
        );
    }
    if a.json {
        let v = json!({
            "points": corrected,
            "max_correction_mm": largest,
            "max_residual_mm": worst,
            "max_error_before_mm": worst_before,
            "seconds": seconds,
            "along_axis_points": along_axis,
            "kept_far_points": far.count,
            "kept_gouging_points": gouges.count,
            "kept_square_points": square.count,
            "far_lines": far.first,
        });
        println!("{v}");
    } else {
        crate::say::note!(
            "wrote {}: {name}, {corrected} points corrected in {:.3} ms ({:.2} µs each); largest correction {:.4} \
             mm, error before up to {:.4} mm, residual {:.1e} mm",
            crate::say::shown(a.write.output()),
            seconds * 1e3,
            seconds * 1e6 / corrected as f64,
            largest,
            worst_before,
            worst
        );
    }
    Ok(())
}

/// The title's words of a program corrected for tool wear.
const WHAT: &str = "CORRECTED FOR TOOL WEAR";

/// Points kept as programmed, of one kind: how many, and the first few
/// (those `--json` lists).
#[derive(Debug)]
struct KeptPoints<T> {
    count: usize,
    first: Vec<T>,
}

impl<T> Default for KeptPoints<T> {
    fn default() -> Self {
        KeptPoints { count: 0, first: Vec::new() }
    }
}

impl<T> KeptPoints<T> {
    /// Most points listed.
    const LISTED: usize = 20;

    fn add(&mut self, found: Vec<T>) {
        self.count += found.len();
        let room = Self::LISTED.saturating_sub(self.first.len());
        self.first.extend(found.into_iter().take(room));
    }
}

/// What the correction came to, over the pieces so far.
#[derive(Debug, Default)]
struct Totals {
    corrected: usize,
    along_axis: usize,
    largest: f64,
    worst: f64,
    worst_before: f64,
    far: KeptPoints<u32>,
    gouges: KeptPoints<(u32, f64)>,
    square: KeptPoints<(u32, f64)>,
}

impl Totals {
    fn add(&mut self, s: Summary) {
        self.corrected += s.corrected;
        self.along_axis += s.along_axis;
        self.largest = self.largest.max(s.largest_correction);
        self.worst = self.worst.max(s.largest_residual);
        self.worst_before = self.worst_before.max(s.largest_error_before);
        self.far.add(s.far);
        self.gouges.add(s.gouging);
        self.square.add(s.square);
    }
}

/// An arc whose corrected ends would make it turn another angle: its line,
/// and the turns after and before, radians.
struct Turned(u32, f64, f64);

impl Turned {
    fn refusal(&self, name: &str) -> anyhow::Error {
        let Turned(line, turn, old_turn) = *self;
        anyhow::anyhow!(
            "{name}: line {line}: the arc's ends need different corrections and it would turn {:.2}° instead of \
             {:.2}°: program the full circle as two arcs, or this arc as lines",
            turn.to_degrees(),
            old_turn.to_degrees()
        )
    }
}

/// The wear correction of a run's path, piece by piece (or whole).
struct Wear<'a> {
    surface: &'a Surface<'a>,
    nominal: Nominal,
    worn: &'a ToolProfile,
    k: Kinematics,
    options: Options,
    /// The last corrected end of the pieces so far.
    before: Option<Axes>,
    totals: Totals,
    /// The first arc that would turn another angle.
    turned: Option<Turned>,
    /// Time spent correcting.
    seconds: f64,
}

impl Correction for Wear<'_> {
    fn correct(&mut self, piece: &Toolpath) -> Result<Toolpath, kezuri_correct::Error> {
        let t0 = std::time::Instant::now();
        let Corrected { ends, summary } =
            correct_moves(self.surface, self.nominal, self.worn, &self.k, piece, &self.options)?;
        self.seconds += t0.elapsed().as_secs_f64();
        self.totals.add(summary);
        let mut path = piece.clone();
        self.before = set_ends_after(&mut path, &ends, ArcCentre::OnChordBisector, self.before);
        // An arc whose ends are corrected differently must still turn the same
        // way by about the same angle (a full circle entered from a lead-in
        // would otherwise shrink to a sliver).
        for (m, was) in path.moves.iter().zip(&piece.moves) {
            if let (MoveKind::Arc(arc), MoveKind::Arc(old), None) = (m.kind, was.kind, &self.turned) {
                let (turn, old_turn) = (arc.sweep(m.start, m.end), old.sweep(was.start, was.end));
                if (turn - old_turn).abs() > 0.01 * old_turn.max(0.1) {
                    self.turned = Some(Turned(m.line, turn, old_turn));
                }
            }
        }
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use kezuri_geom::{Mesh, Triangle, Vec3};
    use kezuri_machine::Machine;

    use super::*;
    use crate::corrected::Joined;
    use crate::program::corpus::each_case;

    #[test]
    fn every_program_corrected_in_pieces_is_corrected_whole() {
        // A tilted plane under every program, a worn 6 mm ball.
        let at = |x: f64, y: f64| Vec3::new(x, y, -1.0 + 0.01 * x - 0.02 * y);
        let (a, b, c, d) = (at(-2e3, -2e3), at(2e3, -2e3), at(2e3, 2e3), at(-2e3, 2e3));
        let mesh = Mesh::from_triangles([Triangle { v: [a, b, c] }, Triangle { v: [a, c, d] }]);
        let surface = Surface::new(&mesh);
        let z: Vec<f64> = (0..=30).map(|i| 0.1 * f64::from(i)).collect();
        let radius: Vec<f64> = z.iter().map(|&z| (2.95f64.powi(2) - (2.95 - z.min(2.95)).powi(2)).sqrt()).collect();
        let worn = ToolProfile::new(z, radius).unwrap();
        let nominal = Nominal { radius: 3.0, corner: 3.0 };
        let machine = Machine::default();
        let wear = || Wear {
            surface: &surface,
            nominal,
            worn: &worn,
            k: machine.kinematics.clone(),
            options: Options { reach: 5.0 },
            before: None,
            totals: Totals::default(),
            turned: None,
            seconds: 0.0,
        };
        let (mut compared, mut cut, mut corrected) = (0, 0, 0);
        each_case(&machine, |mut case| {
            let mut joined = Joined::new(wear());
            case.run_into(&mut joined);
            let mut whole = wear();
            let name = &case.name;
            match whole.correct(&case.whole.toolpath) {
                Ok(path) => {
                    // Debug writes every f64 to the bit.
                    assert_eq!(format!("{:?}", joined.path.path.moves), format!("{:?}", path.moves), "{name}");
                    assert_eq!(format!("{:?}", joined.correction.totals), format!("{:?}", whole.totals), "{name}");
                    let turned = |w: &Wear| w.turned.as_ref().map(|t| t.refusal(name).to_string());
                    assert_eq!(turned(&joined.correction), turned(&whole), "{name}");
                    corrected += usize::from(whole.totals.corrected > 0);
                    compared += 1;
                }
                Err(e) => assert_eq!(joined.error, Some(e.to_string()), "{name}"),
            }
            cut += usize::from(joined.pieces > 2);
        });
        // Pinned, so that the test cannot pass by comparing nothing.
        assert!(
            compared >= 100 && cut >= 100 && corrected >= 50,
            "{compared} compared, {cut} cut, {corrected} corrected"
        );
    }
}
