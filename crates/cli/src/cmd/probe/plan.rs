//! `kezuri probe plan`: the measuring program for digitizing a model on a
//! grid (O1011/O1012/O1013 in samples/), as repeated subprograms, every point
//! written out, or G31 skip-signal probing.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kezuri_nc::probe_plan::{self, Pattern, Plan, Style};
use kezuri_nc::write::Dialect;

use crate::files::write_output;
use crate::machine::MachineArg;

/// Options of `kezuri probe plan`.
#[derive(Args, Debug)]
#[command(after_help = "\
The stylus travels at --safe-z and plunges by --plunge at each point (a G01 Z-50.
stroke, say): the bottom is safe-z - plunge. Rows run along X stepping +Y, the first row toward +X;
zigzag (default) runs every other row back toward -X, oneway returns at safe-z. Points are
numbered 1, 2, ... in that order, the order `probe capture` stores them in.

The program begins as --post begins a program it makes (safe start, retract, T<n> M06 for the
stylus, --tool-number), applies the stylus's length offset on its first Z move (G43 H<its H>
from the machine file's tool table, else H<n>; none on grbl), and ends as the post ends one
(retract, home, M30 or M2).

Styles:
  subprogram  (fanuc, haas) the classic shape: the main program positions in G90 at the origin and safe-z,
              then G91 and M98 P<row> L<rows>; the row subprogram measures its first point and
              repeats the point subprogram (a pitch in X, plunge, trigger, retract) nx-1 times.
              Zigzag repeats a pair of rows (+X, then -X); an odd last row is in the main
              program. Subprograms are numbered after the main one (O n+1 row or row pair,
              O n+2 the +X point, O n+3 the -X point). Load them all into the control's memory.
  expanded    every point written out in absolute coordinates (long: for DNC or small grids);
              the one style for linuxcnc, mach3 and grbl, in their words (G1, M7, G4 P0.5).
  g31         (fanuc, haas) for a touch probe: at each point G31 goes down toward the bottom and stops at the
              touch; the control writes one line `x y z` per point with DPRNT to the device
              opened by POPEN (the RS-232 port): #5061, #5062 and the tip Z (#5063 - #5083,
              the skip position less the length offset). No touch above the bottom: the line
              gives the bottom. No trigger (the skip signal is the trigger).

The trigger (subprogram and expanded) is given at every bottom: M07 (air blow on:
the PC reads the indicator), G04 X0.5, M09 by default (M7, G4 P0.5, M9 on linuxcnc, mach3 and
grbl; the dwell in ms where the machine file's [post] dwell_unit is ms). Each block may hold no
motion and no G code but G04. Lengths must be whole numbers of 10^-digits mm, so every grid
point is written exactly and the incremental steps add up to it.

Examples:
  kezuri probe plan --origin 0,0 --count 85,105 --pitch 1 --safe-z 30 \\
      --plunge 50 -o O1011.nc
  kezuri probe plan --origin 10,20 --count 40,30 --pitch 0.5 --safe-z -80 \\
      --plunge 25 --style expanded --pattern oneway --feed 3000 -o grid.nc
  kezuri probe plan --origin 0,0 --count 60,40 --pitch 1 --safe-z 5 \\
      --plunge 30 --style g31 --plunge-feed 150 -o probe.nc
  kezuri probe plan --origin 0,0 --count 4,3 --pitch 1 --safe-z 30 --plunge 50 \\
      --trigger \"M08,G04 X1.,M09\" --program-number 2000
  kezuri probe plan --origin 0,0 --count 40,30 --pitch 1 --safe-z 5 \\
      --plunge 20 --style expanded --post linuxcnc \\
      --machine samples/tools/mill.toml --tool-number 3 -o grid.ngc

Exit code 1 for a count below 1, a pitch or plunge that is not positive, a length with more
decimals than --digits, a trigger block that moves or changes modes, a program number or
repeat count the control cannot take, or the subprogram or g31 style with a post other than
fanuc or haas; nothing is written then.")]
pub struct PlanArgs {
    /// X and Y of the first point (grid index 0,0), mm.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub origin: String,
    /// Points along X and along Y.
    #[arg(long, value_name = "NX,NY")]
    pub count: String,
    /// Distance between points, in X and in Y, mm.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub pitch: f64,
    /// Height the stylus travels at, mm (work coordinates).
    #[arg(
        long,
        alias = "z-safe",
        value_name = "Z",
        allow_negative_numbers = true,
        value_parser = crate::numbers::coordinate
    )]
    pub safe_z: f64,
    /// Depth of each plunge below --safe-z, mm.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub plunge: f64,
    /// How the program is written.
    #[arg(long, value_enum, default_value = "subprogram")]
    pub style: PlanStyle,
    /// How rows follow each other.
    #[arg(long, value_enum, default_value = "zigzag")]
    pub pattern: PlanPattern,
    /// Feed of the plunge (G01, or G31), mm/min [default: 6000, for an indicator stylus;
    /// 200 for g31].
    #[arg(long, value_name = "MM/MIN", value_parser = crate::numbers::positive)]
    pub plunge_feed: Option<f64>,
    /// Feed of the retract and the moves between points, mm/min [default:
    /// rapid, G00].
    #[arg(long, value_name = "MM/MIN", value_parser = crate::numbers::positive)]
    pub feed: Option<f64>,
    /// Number of the main program (subprograms take the next three) [default: the
    /// machine file's [post] program_number, else 1011].
    #[arg(long, alias = "program", value_name = "N")]
    pub program_number: Option<u32>,
    /// Blocks given at each plunge bottom, separated by commas [default:
    /// "M07,G04 X0.5,M09"]; not for --style g31.
    #[arg(long, value_name = "BLOCKS")]
    pub trigger: Option<String>,
    /// Decimals of the coordinates (0 to 4).
    #[arg(long, value_name = "N", default_value_t = 3)]
    pub digits: u32,
    /// G-code for this control: fanuc, haas, linuxcnc, grbl or mach3 [default: the
    /// machine file's [post] preset, else fanuc].
    #[arg(long, value_name = "NAME")]
    pub post: Option<String>,
    #[command(flatten)]
    pub machine: MachineArg,
    /// The stylus's tool number: T<n> M06, and G43 H<its H register> on the first Z move.
    #[arg(long, value_name = "T", default_value_t = probe_plan::DEFAULT_TOOL)]
    pub tool_number: u32,
    /// The program file to write [default: standard output].
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Program styles on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PlanStyle {
    /// The main program and repeated incremental subprograms (fanuc, haas).
    Subprogram,
    /// Every point written out, absolute.
    Expanded,
    /// Skip-signal probing, touch points written with DPRNT.
    G31,
}

/// Row patterns on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PlanPattern {
    /// Every other row runs back toward -X.
    Zigzag,
    /// Every row runs toward +X.
    Oneway,
}

/// Two numbers `A,B`.
fn pair<T: std::str::FromStr>(text: &str, option: &str, what: &str) -> Result<[T; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if let [a, b] = parts[..] {
        if let (Ok(a), Ok(b)) = (a.parse(), b.parse()) {
            return Ok([a, b]);
        }
    }
    bail!("{option} takes {what}, got '{text}'")
}

/// The plan the arguments describe (not yet validated).
pub fn plan(args: &PlanArgs) -> Result<Plan> {
    let origin: [f64; 2] = pair(&args.origin, "--origin", "two numbers X,Y (mm)")?;
    let count: [u32; 2] = pair(&args.count, "--count", "two whole numbers NX,NY")?;
    let style = match args.style {
        PlanStyle::Subprogram => Style::Subprogram,
        PlanStyle::Expanded => Style::Expanded,
        PlanStyle::G31 => Style::G31,
    };
    let mut plan = Plan::new(origin, count, args.pitch, args.safe_z, args.plunge);
    plan.style = style;
    plan.pattern = match args.pattern {
        PlanPattern::Zigzag => Pattern::Zigzag,
        PlanPattern::Oneway => Pattern::OneWay,
    };
    plan.plunge_feed = args.plunge_feed.unwrap_or(if style == Style::G31 {
        probe_plan::DEFAULT_PROBE_FEED
    } else {
        probe_plan::DEFAULT_PLUNGE_FEED
    });
    plan.feed = args.feed;
    plan.digits = args.digits;
    let machine = args.machine.load()?;
    plan.post = kezuri_machine::post::for_machine(&machine, args.post.as_deref(), args.output.as_deref())?;
    plan.program = args.program_number.or(machine.post.program_number).unwrap_or(probe_plan::DEFAULT_PROGRAM);
    plan.tool = args.tool_number;
    plan.trigger = match &args.trigger {
        Some(_) if style == Style::G31 => {
            bail!("--trigger is for the subprogram and expanded styles: g31 records with the skip signal")
        }
        Some(t) => t.split(',').map(|b| b.trim().to_string()).collect(),
        None => probe_plan::default_trigger(&plan.post)?,
    };
    Ok(plan)
}

/// Runs `kezuri probe plan`.
pub fn run(args: &PlanArgs) -> Result<()> {
    let plan = plan(args)?;
    let text = plan.program().context("cannot write the measuring program")?;
    write_output(args.output.as_deref(), text.as_bytes())?;
    let [nx, ny] = plan.count;
    let name = crate::say::shown(args.output.as_deref());
    let number = if plan.post.dialect == Dialect::Fanuc { format!("O{:04}, ", plan.program) } else { String::new() };
    crate::say::note!(
        "wrote {name}: {number}{nx} x {ny} = {} points at pitch {} mm, {} style, {} rows, bottom Z{}",
        u64::from(nx) * u64::from(ny),
        plan.pitch,
        plan.style.name(),
        plan.pattern.name(),
        plan.bottom()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        plan: PlanArgs,
    }

    fn args(line: &[&str]) -> PlanArgs {
        Cli::try_parse_from(std::iter::once("plan").chain(line.iter().copied())).unwrap().plan
    }

    #[test]
    fn writes_the_paper_program() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("O1011.nc");
        let o = out.to_str().unwrap();
        let line =
            ["--origin", "0,0", "--count", "85,105", "--pitch", "1", "--safe-z", "30", "--plunge", "50", "-o", o];
        run(&args(&line)).unwrap();
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(text.starts_with("%\nO1011 ") && text.ends_with("%\n"), "{text}");
        assert!(text.contains("M98 P1012 L52") && text.contains("G01 Z-50. F6000.\nM07\nG04 X0.5\nM09\n"));
    }

    #[test]
    fn options_reach_the_plan() {
        let a = args(&[
            "--origin=-5.5,2",
            "--count",
            "4, 3",
            "--pitch",
            "0.5",
            "--safe-z",
            "-80",
            "--plunge",
            "20",
            "--style",
            "expanded",
            "--pattern",
            "oneway",
            "--feed",
            "3000",
            "--trigger",
            "M08, G04 X1., M09",
            "--program",
            "2000",
            "-o",
            "-",
        ]);
        let p = plan(&a).unwrap();
        assert_eq!((p.origin, p.count, p.pitch, p.z_safe, p.plunge), ([-5.5, 2.0], [4, 3], 0.5, -80.0, 20.0));
        assert_eq!(
            (p.style, p.pattern, p.feed, p.plunge_feed, p.program),
            (Style::Expanded, Pattern::OneWay, Some(3000.0), 6000.0, 2000)
        );
        assert_eq!(p.trigger, ["M08", "G04 X1.", "M09"]);
        let g = args(
            &["--origin", "0,0", "--count", "2,2", "--pitch", "1", "--safe-z", "5", "--plunge", "30"]
                .into_iter()
                .chain(["--style", "g31", "-o", "-"])
                .collect::<Vec<_>>(),
        );
        assert_eq!(plan(&g).unwrap().plunge_feed, 200.0);
    }

    #[test]
    fn bad_input_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("bad.nc");
        let o = out.to_str().unwrap();
        let base = ["--pitch", "1", "--safe-z", "30", "--plunge", "50", "-o", o];
        for (extra, want) in [
            (["--origin", "0", "--count", "4,3"], "--origin takes two numbers"),
            (["--origin", "0,0", "--count", "4,x"], "--count takes two whole numbers"),
            (["--origin", "0,0", "--count", "0,3"], "at least 1 point"),
            (["--origin", "0,0.0001", "--count", "4,3"], "not a whole number"),
        ] {
            let line: Vec<&str> = extra.iter().chain(base.iter()).copied().collect();
            let e = format!("{:#}", run(&args(&line)).unwrap_err());
            assert!(e.contains(want), "{want:?} in {e:?}");
            assert!(!out.exists(), "nothing written");
        }
        let line: Vec<&str> = ["--origin", "0,0", "--count", "4,3", "--style", "g31", "--trigger", "M07"]
            .iter()
            .chain(&base)
            .copied()
            .collect();
        assert!(run(&args(&line)).unwrap_err().to_string().contains("--trigger is for"));
        assert!(!out.exists());
    }
}
