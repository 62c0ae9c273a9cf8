//! `kezuri convert`: G-code dialects and Roland RML-1 into each other,
//! scaled and shortened (with real units).

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::cutter::named::{cutter_warnings, in_comments};
use kezuri_cam::shorten::{shorten, ShortenOptions};
use kezuri_cam::Cutter;
use kezuri_geom::{Kept, MoveKind, Spindle, Toolpath};
use kezuri_nc::interp;
use kezuri_nc::rml::{self, RmlOptions};
use kezuri_nc::write::{program, WriteOptions};
use kezuri_nc::{comments_forgetting, parse_as, Detected, Diagnostic, Dialect, Program, SourceFile, Sources};

use crate::files::{read_program_text, Folder, Outputs};
use crate::machine::MachineArg;
use crate::program::{choose_dialect, dialect_settings, post_options, warn_rml_drops};

mod streamed;

/// A program format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Fanuc G-code (axis words without a decimal point are 0.001 mm).
    Fanuc,
    /// Haas G-code: Fanuc's with Haas's codes.
    Haas,
    /// LinuxCNC G-code (axis words without a decimal point are mm).
    Linuxcnc,
    /// GRBL G-code (axis words without a decimal point are mm).
    Grbl,
    /// Roland RML-1 (CAMM-3, MODELA MDX): steps of --rml-unit.
    Rml,
}

/// Options of `kezuri convert`.
#[derive(Args, Debug)]
#[command(after_help = "\
The input is a G-code program, run through kezuri's interpreter (macros, subprograms and loops
are expanded), or a Roland RML-1 program (CAMM-3, MODELA MDX). The output is one command per
move of the input: nothing is merged unless --shorten.

--dialect (formerly --from) defaults from the input: .rml and .prn files, or a text that starts
with ^IN, ;;^IN or another RML-1 command, are RML-1; any other input is G-code whose dialect
every command chooses by one rule (docs/linuxcnc.md, \"Choosing the dialect\"): markers in the
text (o100 sub, #<name>, G64 P: linuxcnc; an O1234 line, G65, GOTO, WHILE [..] DO1: fanuc;
G154, G187: haas; $H, $J=: grbl), else the extension (.ngc linuxcnc, .gcode and .gc grbl),
else fanuc. LinuxCNC and GRBL read axis words without a decimal point as whole millimetres,
Fanuc and Haas as 0.001 mm (X100 is 0.1 mm). A text with markers of both is refused. The
dialect used, and why, is said on standard error. --to defaults from the output's extension
(.rml/.prn, .ngc/.tap, .gcode/.gc), else fanuc.

RML-1 coordinates are steps of --rml-unit mm (0.01; the MDX-20 steps 0.025): the
line Z39,0,-240 is X0.39 Z-2.4, not X39. Z240. Reading RML-1, Z x,y,z is a G01, ^PU x,y a G00 at
the tool-up height (--safe-z, else the program's !PZ), ^PD a feed at the current down Z; V and
^VS are mm/s, and --feed gives the feed where the program sets none. Device commands (!RC, !NR,
...) are reported, not converted. Writing RML-1, rapids travel with the tool up (^PU) at
--safe-z (default: the highest point a rapid ends at), a rapid down is a fed Z plunge, arcs are
chords within half a step, and dwells and probing moves are errors.

--scale-xy K --scale-z S scale about the program zero. A program made for a cutter of diameter
D needs one of D x K once scaled: name the cutter (--tool ball:14, or a comment in a G-code
program such as (ball:14), (D=14), (DIA 14), (DIAMETER=14) or (φ14)) and kezuri warns when the
needed diameter is not a whole millimetre, or when a shaped tip is scaled unevenly.

--shorten TOL merges consecutive moves of one kind, feed and tool (never across a rapid, a feed
change, an arc or a tool or spindle change) while the merged path stays within TOL mm of the
original, both ways; --arcs also fits G02/G03 arcs in the XY plane at constant Z (G-code only).

Nothing is written when the input has an error.

Examples:
  kezuri run samples/nameplate-cam.nc --to rml -o plate.rml
  kezuri convert plate.rml --safe-z 5 --feed 600 -o plate.nc
  kezuri convert plate.rml --scale-xy 2 --scale-z 1.5 --tool ball:7 \\
      --shorten 0.005 -o big.nc
  kezuri convert samples/nameplate-cam.nc --safe-z 3 -o plate-3.rml
  kezuri convert samples/nameplate-cam.nc -o plate.ngc
  kezuri convert plate.ngc --to fanuc --shorten 0.002 --arcs -o plate-arcs.nc
  kezuri convert samples/nameplate-cam.nc --rml-unit 0.025 -o mdx20.prn
  kezuri convert mdx20.prn --rml-unit 0.025 --to grbl -o mdx20.gcode")]
pub struct ConvertArgs {
    /// The program to convert (`-` for standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output file (default: standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// The input's dialect, or rml [default: RML-1 by its extension or text,
    /// else the dialect rule of every command (docs/linuxcnc.md)]. `--from`
    /// is its older name.
    #[arg(long, alias = "from", value_enum, value_name = "DIALECT")]
    pub dialect: Option<Format>,
    /// Format of the output [default: from its extension, else fanuc].
    #[arg(long, alias = "emit", value_enum, value_name = "FORMAT")]
    pub to: Option<Format>,
    /// Millimetres per RML-1 step.
    #[arg(long, value_name = "MM", default_value_t = 0.01, value_parser = crate::numbers::length)]
    pub rml_unit: f64,
    /// Scale factor for X and Y (about the program zero).
    #[arg(long, value_name = "K", default_value_t = 1.0, value_parser = crate::numbers::positive)]
    pub scale_xy: f64,
    /// Scale factor for Z (about the program zero).
    #[arg(long, value_name = "S", default_value_t = 1.0, value_parser = crate::numbers::positive)]
    pub scale_z: f64,
    /// Merge consecutive moves while the path stays within TOL mm of the original.
    #[arg(long, value_name = "TOL", value_parser = crate::numbers::length_or_zero)]
    pub shorten: Option<f64>,
    /// With --shorten: also fit G02/G03 arcs (XY plane, constant Z).
    #[arg(long, requires = "shorten")]
    pub arcs: bool,
    /// Tool-up height, mm: where RML-1 ^PU travels (read) and where rapids travel (written).
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub safe_z: Option<f64>,
    /// Feed, mm/min, for cutting moves whose program sets none.
    #[arg(long, value_name = "MM/MIN", value_parser = crate::numbers::positive)]
    pub feed: Option<f64>,
    /// Spindle speed, rpm, where the spindle runs and the program gives no speed (RML-1 !MC1).
    #[arg(long, value_name = "RPM", value_parser = crate::numbers::positive)]
    pub speed: Option<f64>,
    /// The cutter the program was made for (flat:D, ball:D, bull:D,R, oval:D,RL, v:D,ANGLE).
    #[arg(
        long,
        value_name = "SPEC",
        value_parser = cutter,
        long_help = tool_help!("The cutter the program was made for (checked when scaled).")
    )]
    pub tool: Option<Cutter>,
    /// Decimals written in a G-code program.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub digits: u8,
    /// Folder of subprogram files `O1234.nc` [default: the input's folder].
    #[arg(long, value_name = "DIR")]
    pub lib: Option<PathBuf>,
    /// G-code for this control: fanuc, haas, linuxcnc, grbl or mach3 (its number
    /// format, arcs, line numbers; the program keeps its own start, tool changes
    /// and end) [default: --to, else the machine file's [post] preset, else fanuc].
    #[arg(long, value_name = "NAME")]
    pub post: Option<String>,
    #[command(flatten)]
    pub machine: MachineArg,
    /// Also show the converted program in 3D: one offline HTML page, as `kezuri view` makes of
    /// it (an RML-1 output as its moves, without the text).
    #[arg(long, value_name = "PAGE.html")]
    pub view: Option<PathBuf>,
}

fn cutter(s: &str) -> Result<Cutter, String> {
    s.parse::<Cutter>().map_err(|e| e.to_string())
}

/// Ends the run as bad usage: the message on stderr, exit code 2.
fn usage(message: &str) -> ! {
    clap::Error::raw(clap::error::ErrorKind::ArgumentConflict, format!("{message}\n")).exit()
}

/// The lower-case extension of a path.
fn extension(path: &Path) -> String {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default()
}

/// The format an extension names, if it names one.
fn format_of(extension: &str) -> Option<Format> {
    match extension {
        "rml" | "prn" => Some(Format::Rml),
        "ngc" | "tap" => Some(Format::Linuxcnc),
        "gcode" | "gc" => Some(Format::Grbl),
        _ => None,
    }
}

/// The input's format: `--dialect`, else RML-1 by its extension or text,
/// else the G-code dialect by the rule of every command; with why.
fn input_format(given: Option<Format>, input: &Path, text: &str) -> Result<(Format, Option<Detected>)> {
    let dialect = match given {
        Some(Format::Rml) => return Ok((Format::Rml, None)),
        Some(Format::Fanuc) => Some(Dialect::Fanuc),
        Some(Format::Haas) => Some(Dialect::Haas),
        Some(Format::Linuxcnc) => Some(Dialect::LinuxCnc),
        Some(Format::Grbl) => Some(Dialect::Grbl),
        None if matches!(extension(input).as_str(), "rml" | "prn") || rml::looks_like_rml(text) => {
            return Ok((Format::Rml, None))
        }
        None => None,
    };
    let detected = choose_dialect(dialect, input, text)?;
    let format = match detected.dialect {
        Dialect::Fanuc | Dialect::FanucLathe => Format::Fanuc,
        Dialect::Haas | Dialect::HaasLathe => Format::Haas,
        Dialect::LinuxCnc => Format::Linuxcnc,
        Dialect::Grbl => Format::Grbl,
    };
    Ok((format, Some(detected)))
}

/// `--to` by default: the output's extension, else fanuc.
fn guess_to(output: Option<&Path>) -> Format {
    output.and_then(|p| format_of(&extension(p))).unwrap_or(Format::Fanuc)
}

/// `kezuri convert`.
pub fn run(a: &ConvertArgs) -> Result<()> {
    let text = read_program_text(&a.input)?;
    let name = if a.input == Path::new("-") { "<stdin>".to_string() } else { a.input.display().to_string() };
    let (from, detected) = input_format(a.dialect, &a.input, text.text())?;
    if let Some(d) = &detected {
        crate::say::note!("{name}: {d}");
    }
    let to = a.to.unwrap_or_else(|| guess_to(a.output.as_deref()));
    if a.post.is_some() && to == Format::Rml {
        usage("--post writes G-code: it cannot go with an RML-1 output");
    }
    if a.arcs && to == Format::Rml {
        usage("--arcs fits G02/G03 arcs, which RML-1 has not: drop --arcs, or write G-code (--to fanuc)");
    }
    // G-code into G-code is written as the run makes it, but where the whole
    // path is needed: to shorten it or to draw it.
    if let (Some(d), false) = (&detected, to == Format::Rml || a.shorten.is_some() || a.view.is_some()) {
        if let Some(done) = streamed::convert(a, &name, d.dialect, to, text.clone()) {
            return done;
        }
    }
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::stored(name.clone(), text));
    let mut path = match from {
        Format::Rml => read_rml(a, &sources, id)?,
        _ => run_gcode(a, detected.map_or(Dialect::Fanuc, |d| d.dialect), &mut sources, id)?,
    };
    if !path.moves.iter().any(|m| !matches!(m.kind, MoveKind::Dwell(_))) {
        bail!("{name}: the program has no motion to convert; nothing written");
    }
    fill_feed_and_speed(&mut path, a.feed, a.speed);
    if to != Format::Rml && path.moves.iter().any(|m| m.spindle != Spindle::Off && m.speed == 0.0) {
        warn_no_speed(&name);
    }
    if a.scale_xy != 1.0 || a.scale_z != 1.0 {
        let text = (from != Format::Rml).then(|| sources.get(id).text.clone());
        warn_cutters(a, text.as_ref());
        if let Some(k) = path.kept.iter().find(|k| holds_positions(k)) {
            return Err(unscalable(&name, k));
        }
        path = path.scaled(a.scale_xy, a.scale_z);
    }
    if let Some(tolerance) = a.shorten {
        let before = path.moves.len();
        path = shorten(&path, &ShortenOptions { tolerance, arcs: a.arcs });
        crate::say::note!("shortened within {tolerance} mm: {before} moves -> {}", path.moves.len());
    }
    let machine = a.machine.load()?;
    let out = match to {
        Format::Rml => {
            let options = RmlOptions { unit: a.rml_unit, safe_z: a.safe_z, feed: a.feed, tolerance: a.rml_unit / 2.0 };
            warn_rml_drops(&name, &path);
            rml::write_rml(&path, &options)?
        }
        Format::Fanuc | Format::Haas | Format::Linuxcnc | Format::Grbl => {
            program(&path, &write_options(a, to, &machine)?)?
        }
    };
    let mut outputs = Outputs::new();
    if let Some(page) = &a.view {
        let options = kezuri_picture::PageOptions::default();
        // Every tool the program loads drawn as --tool.
        let tools: std::collections::BTreeSet<u32> = path.moves.iter().map(|m| m.tool).collect();
        let cutters: Vec<(u32, Cutter)> = a.tool.map(|c| tools.iter().map(|&n| (n, c)).collect()).unwrap_or_default();
        let html = match to {
            Format::Rml => crate::page::path_page(&path, &name, &machine, &cutters, &options)?,
            _ => {
                let written = a.output.clone().unwrap_or_else(|| PathBuf::from("program.nc"));
                let ran = crate::program::run_written(&machine, &written, out.clone())?;
                crate::page::page(&ran, &written.display().to_string(), None, &cutters, &options)?
            }
        };
        outputs.add(Some(page), &html)?;
    }
    outputs.add(a.output.as_deref(), out.as_bytes())?;
    outputs.commit()?;
    crate::say::wrote_program(a.output.as_deref(), &format!("{}; ", format_name(to)), &path, &machine);
    Ok(())
}

/// How the summary names the output's format.
fn format_name(to: Format) -> &'static str {
    match to {
        Format::Rml => "RML-1",
        Format::Fanuc => "Fanuc G-code",
        Format::Haas => "Haas G-code",
        Format::Linuxcnc => "LinuxCNC G-code",
        Format::Grbl => "GRBL G-code",
    }
}

/// How G-code `to` is written on `machine`: `--post`, else `--to` (or the
/// output's name), with `--digits`; the program keeps its own start, tool
/// changes and end.
fn write_options(a: &ConvertArgs, to: Format, machine: &kezuri_machine::Machine) -> Result<WriteOptions> {
    let name = |t: Format| match t {
        Format::Haas => "haas",
        Format::Linuxcnc => "linuxcnc",
        Format::Grbl => "grbl",
        _ => "fanuc",
    };
    // --to, or without --post the format the output's name says.
    let named = a.to.or(a.post.is_none().then_some(to)).map(name);
    let post = post_options(a.post.as_deref(), named, machine, None)?;
    let title = crate::program::program_title(&a.input);
    Ok(WriteOptions { digits: a.digits, title: Some(title), setup: None, ..post })
}

/// The warning of a spindle turned on with no speed.
fn warn_no_speed(name: &str) {
    eprintln!(
        "warning: {name}: the spindle is turned on with no speed (RML-1 !MC1, or M03 without S): the program says \
         M03 without S, so the control's S stands; give --speed RPM for one"
    );
}

/// The warnings of a scaled program's cutter (`--tool`, or one its G-code
/// `text` names in a comment).
fn warn_cutters(a: &ConvertArgs, text: Option<&kezuri_nc::source::Text>) {
    // A mapped program's pages let go of as its comments are read through.
    let named = text.map(|t| in_comments(comments_forgetting(t, &|r| t.forget(r)))).unwrap_or_default();
    for line in cutter_warnings(a.tool, &named, a.scale_xy, a.scale_z) {
        eprintln!("{line}");
    }
}

/// Whether a block kept as written holds positions (G10, G92, G52, a
/// tapping cycle) that scaling cannot reach.
fn holds_positions(k: &Kept) -> bool {
    k.sets_offsets || k.moves > 0
}

/// Why the program `name` cannot be scaled: the block `k`.
fn unscalable(name: &str, k: &Kept) -> anyhow::Error {
    anyhow::anyhow!(
        "{name}: line {} ('{}') holds positions kezuri keeps as written: the program cannot be scaled",
        k.line,
        k.text.lines().next().unwrap_or("")
    )
}

/// Prints the diagnostics, each followed by a blank line; returns the
/// errors among them.
fn print_diagnostics<'a>(sources: &Sources, diagnostics: impl IntoIterator<Item = &'a Diagnostic>) -> usize {
    let mut errors = 0;
    for d in diagnostics {
        eprintln!("{}\n", d.render(sources));
        errors += usize::from(d.is_error());
    }
    errors
}

/// Reads the RML-1 input; its diagnostics go to stderr.
fn read_rml(a: &ConvertArgs, sources: &Sources, id: u32) -> Result<Toolpath> {
    let file = sources.get(id);
    let options = RmlOptions { unit: a.rml_unit, safe_z: a.safe_z, feed: a.feed, ..RmlOptions::default() };
    let read = rml::read_rml(id, &file.text, &options);
    let errors = print_diagnostics(sources, &read.diagnostics);
    if errors > 0 {
        bail!("{}: {}; nothing written", file.name, crate::say::count(errors as u64, "error"));
    }
    Ok(read.toolpath)
}

/// Parses and runs the G-code input as `kezuri run` does; diagnostics and
/// DPRNT lines go to stderr.
fn run_gcode(a: &ConvertArgs, dialect: Dialect, sources: &mut Sources, id: u32) -> Result<Toolpath> {
    let machine = a.machine.load()?;
    let settings = dialect_settings(dialect, None, &machine);
    let text = sources.get(id).text.clone();
    let name = sources.get(id).name.clone();
    let mut program = Program::default();
    let parse_diagnostics = parse_as(&mut program, id, &text, dialect);
    if print_diagnostics(sources, &parse_diagnostics) > 0 {
        bail!("{name}: parse errors; nothing written");
    }
    if program.units.is_empty() {
        return Ok(Toolpath::default());
    }
    let dir = crate::program::library_dir(a.lib.as_deref(), &a.input);
    let outcome = interp::run(&mut program, sources, 0, &mut Folder::new(dir), &settings);
    for line in &outcome.prints {
        eprintln!("{}: {line}", crate::program::print_label(settings.dialect));
    }
    crate::program::report_logs(&outcome);
    let errors = print_diagnostics(sources, &outcome.diagnostics);
    if errors > 0 {
        bail!("{name}: {}; nothing written", crate::say::count(errors as u64, "error"));
    }
    Ok(outcome.toolpath)
}

/// `--feed` for cutting moves with no feed, `--speed` for a running spindle
/// with no speed.
fn fill_feed_and_speed(path: &mut Toolpath, feed: Option<f64>, speed: Option<f64>) {
    for m in &mut path.moves {
        if let Some(f) = feed {
            if m.feed == 0.0 && matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_) | MoveKind::Probe) {
                m.feed = f;
            }
        }
        if let Some(s) = speed {
            if m.speed == 0.0 && m.spindle != Spindle::Off {
                m.speed = s;
            }
        }
    }
}
