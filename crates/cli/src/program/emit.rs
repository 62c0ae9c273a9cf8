//! Writing a toolpath through a post: `--post`, `--to`, `-o`, `--svg` and
//! `--view`, and the program, CSV or RML-1 they ask for.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::Cutter;
use kezuri_geom::{PathSink, Toolpath};
use kezuri_nc::write::WriteOptions;

use super::run::{options_from, run_written, Ran};
use super::streamed::Streamed;
use crate::files::Outputs;
use kezuri_machine::Machine;

/// What `run` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Emit {
    /// Fanuc G-code (`X10.` style, `%` and `O` framing): the fanuc post.
    Fanuc,
    /// LinuxCNC G-code: the linuxcnc post.
    Linuxcnc,
    /// GRBL G-code: the grbl post.
    Grbl,
    /// `line,kind,x,y,z,a,b,c,feed` rows, full precision.
    Csv,
    /// Roland RML-1 (CAMM-3, MODELA), steps of 0.01 mm; rapids travel tool-up at the
    /// highest point a rapid ends at.
    Rml,
}

/// How a program is written: G-code by a post, CSV or RML-1.
#[derive(Args, Clone, Debug)]
pub struct WriteArgs {
    /// G-code for this control: fanuc, haas, linuxcnc, grbl or mach3 [default: the
    /// machine file's [post] preset, else fanuc]. The machine file's [post] changes
    /// what it names.
    #[arg(long, value_name = "NAME")]
    post: Option<String>,
    /// Output format: G-code by a post (fanuc, linuxcnc and grbl are the posts of those
    /// names), csv or rml [default: G-code by --post].
    #[arg(long = "to", alias = "emit", value_enum, value_name = "FORMAT")]
    pub emit: Option<Emit>,
    /// Output file (default: standard output).
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,
    /// Decimals written in the program [default: the post's; 3 in mm, 4 in inches].
    #[arg(long, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub digits: Option<u8>,
    /// Write the program in inches (G20) instead of mm (G21).
    #[arg(long)]
    pub inch: bool,
    /// Number the blocks N10, N20, … (the step; 0 for none) [default: the post's].
    #[arg(long, value_name = "STEP")]
    line_numbers: Option<u32>,
    /// Write the moves after the first complete positioning in incremental
    /// coordinates (G91); G90 again before the end.
    #[arg(long)]
    incremental: bool,
    /// Also draw the toolpath (top and front view) to this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    svg: Option<PathBuf>,
    /// Also show the written program in 3D: one offline HTML page, as `kezuri view` makes
    /// of it (the tool, the program text, a playback slider).
    #[arg(long, value_name = "PAGE.html")]
    view: Option<PathBuf>,
    /// Write the tool-centre path of cutter radius compensation (G41/G42)
    /// with the compensation off (G40), the radii from the machine file's
    /// [tools] radii, for controls and simulators without compensation
    /// (GRBL, RML-1). Without it Fanuc and LinuxCNC output keeps G41/G42 D
    /// as programmed, for the control's own D register.
    #[arg(long)]
    pub apply_comp: bool,
}

/// Whether kezuri made the program (it gets the post's start, tool changes
/// and end) or transforms one (which keeps its own).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    Made,
    Transformed,
}

impl WriteArgs {
    /// These options for writing back a program read in `dialect` on
    /// `machine`: where nothing names a control (no `--post`, `--to`, `[post]
    /// preset` or telling extension of the output), a LinuxCNC or GRBL
    /// program is written for its own control, not Fanuc's.
    pub fn for_program(&self, machine: &Machine, dialect: kezuri_nc::Dialect) -> WriteArgs {
        let named = self.post.is_some()
            || self.emit.is_some()
            || machine.post.preset().is_some()
            || self.output.as_deref().and_then(|p| kezuri_nc::detect::by_extension(&p.to_string_lossy())).is_some();
        let own = match dialect {
            kezuri_nc::Dialect::LinuxCnc => Some(Emit::Linuxcnc),
            kezuri_nc::Dialect::Grbl => Some(Emit::Grbl),
            kezuri_nc::Dialect::Fanuc
            | kezuri_nc::Dialect::Haas
            | kezuri_nc::Dialect::FanucLathe
            | kezuri_nc::Dialect::HaasLathe => None,
        };
        WriteArgs { emit: if named { self.emit } else { own }, ..self.clone() }
    }

    /// Whether the output is a program or CSV alone (no drawing, no page,
    /// not RML-1): written as the run makes it.
    pub fn streams(&self) -> bool {
        self.view.is_none() && self.svg.is_none() && self.emit != Some(Emit::Rml)
    }

    /// Whether the output is G-code (not CSV or RML-1).
    pub fn is_gcode(&self) -> bool {
        !matches!(self.emit, Some(Emit::Csv | Emit::Rml))
    }

    /// Whether the output is Fanuc-style G-code (the fanuc or haas post).
    pub fn is_fanuc(&self, machine: &Machine) -> bool {
        self.is_gcode()
            && self.options(machine, Origin::Transformed).is_ok_and(|o| o.dialect == kezuri_nc::write::Dialect::Fanuc)
    }

    /// The output file (`None`: standard output).
    pub fn output(&self) -> Option<&Path> {
        self.output.as_deref()
    }

    /// How G-code is written: the post (`--post`, `--to fanuc|linuxcnc|grbl`,
    /// the machine file's `[post]`, the output's extension), then `--digits`, `--inch`,
    /// `--line-numbers` and `--incremental`. A transformed program keeps its
    /// own start, tool changes and end (no [`Setup`](kezuri_nc::write::Setup)).
    pub fn options(&self, machine: &Machine, origin: Origin) -> Result<WriteOptions> {
        let emit = match self.emit {
            Some(Emit::Fanuc) => Some("fanuc"),
            Some(Emit::Linuxcnc) => Some("linuxcnc"),
            Some(Emit::Grbl) => Some("grbl"),
            Some(Emit::Csv | Emit::Rml) if self.post.is_some() => {
                bail!("--post writes G-code: it cannot go with --to csv or rml")
            }
            _ => None,
        };
        let mut o = post_options(self.post.as_deref(), emit, machine, self.output.as_deref())?;
        if self.digits.is_some() || self.inch {
            o.digits = self.digits.unwrap_or(if self.inch { 4 } else { o.digits });
        }
        o.inch = self.inch;
        if let Some(step) = self.line_numbers {
            o.line_numbers = (step > 0).then_some(step);
        }
        o.incremental = self.incremental;
        if origin == Origin::Transformed {
            o.setup = None;
        }
        Ok(o)
    }
}

/// The write options of `--post NAME` or `--to DIALECT` (another name of
/// the fanuc, linuxcnc and grbl posts), else the machine file's `[post]
/// preset`, else fanuc; with the machine file's `[post]` on top.
pub fn post_options(
    post: Option<&str>,
    emit: Option<&str>,
    machine: &Machine,
    output: Option<&Path>,
) -> Result<WriteOptions> {
    let name = match (post, emit) {
        (Some(p), Some(e)) if !p.trim().eq_ignore_ascii_case(e) => {
            bail!("--post {p} and --to {e} ask for two different controls: give one")
        }
        (p, e) => p.or(e),
    };
    Ok(kezuri_machine::post::for_machine(machine, name, output)?)
}

/// Adds to `out` what `w` asks for `path`: a program by the post, CSV or
/// RML-1, the SVG and the `--view` page (its tools drawn with `cutters`).
pub fn stage_toolpath(
    out: &mut Outputs,
    path: &Toolpath,
    title: &str,
    w: &WriteArgs,
    machine: &Machine,
    origin: Origin,
    cutters: &[(u32, Cutter)],
) -> Result<()> {
    write_program(out, path, path, title, &[], w, machine, origin, cutters)
}

/// Warns where the machine file gives a tool number another shape than the
/// one the program is made for: the check of the program (`sim`, `view`
/// with the machine file) cuts with the machine file's.
fn warn_other_shapes(machine: &Machine, cutters: &[(u32, Cutter)]) {
    for (n, cutter) in cutters {
        let Some(shape) = machine.tools.get(n).and_then(|t| t.shape) else { continue };
        if shape.to_string() != cutter.to_string() {
            let name = machine.tools[n].name.as_deref().map(|s| format!(" ({s})")).unwrap_or_default();
            eprintln!(
                "warning: the machine file's T{n} is {shape}{name}, but this program is made for {cutter}: \
                 sim and view with the machine file cut with {shape}; give --tool {shape} or another tool number"
            );
        }
    }
}

/// [`stage_toolpath`] with the SVG drawing `drawn`; `cutters` are the
/// shapes of the tools (by number) the `--view` page draws.
#[allow(clippy::too_many_arguments)]
pub fn write_program(
    out: &mut Outputs,
    path: &Toolpath,
    drawn: &Toolpath,
    title: &str,
    notes: &[String],
    w: &WriteArgs,
    machine: &Machine,
    origin: Origin,
    cutters: &[(u32, Cutter)],
) -> Result<()> {
    warn_other_shapes(machine, cutters);
    let text = match w.emit {
        Some(Emit::Csv) => kezuri_nc::write::csv(path),
        Some(Emit::Rml) => {
            warn_rml_drops(title, path);
            kezuri_nc::rml::write_rml(path, &kezuri_nc::rml::RmlOptions::default())?
        }
        _ => {
            let options =
                WriteOptions { title: Some(title.to_string()), notes: notes.to_vec(), ..w.options(machine, origin)? };
            kezuri_nc::write::program(path, &options)?
        }
    };
    if let Some(page) = &w.view {
        let options = kezuri_picture::PageOptions::default();
        let html = if w.is_gcode() {
            let name = w.output.clone().unwrap_or_else(|| PathBuf::from("program.nc"));
            let ran = run_written(machine, &name, text.clone())?;
            crate::page::page(&ran, &name.display().to_string(), None, cutters, &options)?
        } else {
            crate::page::path_page(path, title, machine, cutters, &options)?
        };
        out.add(Some(page), &html)?;
    }
    out.add(w.output.as_deref(), text.as_bytes())?;
    if let Some(svg) = &w.svg {
        out.add(
            Some(svg),
            kezuri_picture::plot::svg(drawn, &svg_title(w.output.as_deref(), title, cutters)).as_bytes(),
        )?;
    }
    Ok(())
}

/// A program kezuri makes (of `file`, titled `title`, `notes` in its
/// header, for the tools `cutters`) written as `make` hands its path on,
/// into `out`, where `w` asks for a program or CSV alone
/// ([`WriteArgs::streams`]): the path is made on this thread and written
/// on another, and never held whole. What [`write_program`] writes of the
/// whole path, to the byte; the one-line summary of it.
#[allow(clippy::too_many_arguments)]
pub fn stream_made_program(
    out: &mut Outputs,
    file: &Path,
    title: &str,
    notes: &[String],
    w: &WriteArgs,
    machine: &Machine,
    cutters: &[(u32, Cutter)],
    make: impl FnOnce(&mut dyn PathSink) -> Result<()>,
) -> Result<String> {
    warn_other_shapes(machine, cutters);
    let mut tools: Vec<u32> = Vec::new();
    for &(n, _) in cutters.iter().filter(|c| c.0 != 0) {
        if tools.last() != Some(&n) {
            tools.push(n);
        }
    }
    let mut made: Option<Result<String>> = None;
    let staged = out.add_with(w.output(), |to| {
        let streamed = Streamed::made(w, machine, file, (title, notes), tools, &mut *to);
        let (result, streamed) = super::beside::with_sink_beside(streamed, make);
        let done = result.and_then(|()| streamed.finish().map(|(_, summary)| summary));
        let failed = done.is_err();
        made = Some(done);
        if failed {
            return Err(std::io::Error::other("the program was not made"));
        }
        Ok(())
    });
    match (made, staged) {
        (Some(Ok(summary)), Ok(())) => Ok(summary),
        (Some(Err(e)), _) | (_, Err(e)) => Err(e),
        (None, Ok(())) => Err(anyhow::anyhow!("the program was not written")),
    }
}

/// The title of a toolpath's drawing: the program written (`output`), its
/// `title` and the tools not named in it.
pub fn svg_title(output: Option<&Path>, title: &str, cutters: &[(u32, Cutter)]) -> String {
    let mut text = match output.and_then(Path::file_name) {
        Some(name) if name != "-" => format!("{}: {title}", name.to_string_lossy()),
        _ => title.to_string(),
    };
    let unnamed: Vec<String> =
        cutters.iter().filter(|(_, c)| !title.contains(&c.to_string())).map(|(n, c)| format!("T{n} {c}")).collect();
    if !unnamed.is_empty() {
        text += &format!(" ({})", unnamed.join(", "));
    }
    text
}

impl WriteArgs {
    /// The program's smallest increment in mm: a unit of the last decimal
    /// written (`--digits` or the post's, in inches with `--inch`), or
    /// RML-1's step.
    pub fn quantum(&self, machine: &Machine) -> Result<f64> {
        if let Some(Emit::Rml) = self.emit {
            return Ok(kezuri_nc::rml::RmlOptions::default().unit);
        }
        let digits = self.options(machine, Origin::Made)?.digits;
        Ok(10f64.powi(-i32::from(digits)) * if self.inch { 25.4 } else { 1.0 })
    }
}

/// Warns of the blocks kept as the program wrote them (M codes, G10, …)
/// that RML-1 has no command for: they are not written.
pub fn warn_rml_drops(name: &str, path: &Toolpath) {
    if let Some(k) = path.kept.first() {
        eprintln!(
            "warning: {name}: RML-1 has no M codes, offsets or the like: {} the program keeps {} not \
             written (the first at line {}: '{}')",
            crate::say::count(path.kept.len() as u64, "block"),
            if path.kept.len() == 1 { "is" } else { "are" },
            k.line,
            k.text.lines().next().unwrap_or("")
        );
    }
}

/// The toolpath `kezuri run` writes of `ran` (the program `file`) with `w`
/// (made [`WriteArgs::for_program`]): with cutter radius compensation the
/// programmed contour with its G41/G42 D and G40 blocks for Fanuc and
/// LinuxCNC G-code, the tool-centre path for CSV and with `--apply-comp`;
/// refused for GRBL and RML-1, which have no compensation, without
/// `--apply-comp`.
pub fn written_path<'a>(ran: &'a Ran, w: &WriteArgs, file: &Path) -> Result<&'a Toolpath> {
    let centre = &ran.outcome.toolpath;
    let without_comp = match w.emit {
        Some(Emit::Csv) => None,
        Some(Emit::Rml) => Some("RML-1"),
        _ => {
            (w.options(&ran.machine, Origin::Transformed)?.dialect == kezuri_nc::write::Dialect::Grbl).then_some("GRBL")
        }
    };
    Ok(match (&ran.outcome.programmed, without_comp) {
        (Some(_), Some(control)) if !w.apply_comp => return Err(comp_refusal(file, control)),
        (Some(p), None) if !w.apply_comp && w.is_gcode() => p,
        _ => centre,
    })
}

/// Why the program `file`, which uses cutter radius compensation, is not
/// written for `control`, which has none, as it stands.
pub fn comp_refusal(file: &Path, control: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}: the program uses cutter radius compensation (G41/G42), which {control} has not: give --apply-comp to \
         write the tool centre path (radii from the machine file's [tools] radii)",
        file.display(),
    )
}

/// `e` where it is: an error of the writer at a move or a line of the
/// program read (`move 2 (line 7): …`) as `file:line:column: …`, the column
/// that of the block's first character. Others as they are.
pub fn located(ran: &Ran, e: anyhow::Error) -> anyhow::Error {
    match place(ran, &e) {
        Some((at, message)) => anyhow::anyhow!("{at}: {message}"),
        None => e,
    }
}

/// `file:line:column` of an error of the writer at a line of the program
/// read, and its message without the place.
fn place(ran: &Ran, e: &anyhow::Error) -> Option<(String, String)> {
    let nc = e.downcast_ref::<kezuri_nc::Error>()?;
    let line = match nc.place {
        kezuri_nc::Place::Move { line, .. } | kezuri_nc::Place::Line(line) => line,
        kezuri_nc::Place::None | kezuri_nc::Place::Compensated(_) => 0,
    };
    if ran.sources.is_empty() || line == 0 {
        return None;
    }
    let file = ran.sources.get(0);
    if line as usize > file.text.lines().count() {
        return None;
    }
    let column = file.line_text(line).chars().take_while(|c| c.is_whitespace()).count() + 1;
    Some((format!("{}:{line}:{column}", file.name), nc.message.clone()))
}

/// The title `kezuri run` gives the program it writes of `file`: its name
/// in capitals.
pub fn program_title(file: &Path) -> String {
    file.file_name().map_or_else(|| "-".into(), |n| n.to_string_lossy().to_uppercase())
}

/// What `kezuri run` (with no option of how to write) would write of a
/// program, written to nowhere as the run hands its path on: whether it
/// refuses it, and why. `check` says the same.
pub struct RunTrial(Result<Streamed<std::io::Sink>>);

impl RunTrial {
    /// The trial of program `file` on `machine`, read in `dialect`.
    pub fn new(machine: &Machine, dialect: kezuri_nc::Dialect, file: &Path) -> RunTrial {
        RunTrial(options_from::<WriteArgs>(&[]).map(|w| {
            let w = w.for_program(machine, dialect);
            Streamed::new(&w, machine, file, &program_title(file), false, std::io::sink())
        }))
    }

    /// After the run `ran`: why `kezuri run` refuses it, as an error line
    /// (`file:line:column: error: …` where it has a place); `None` where it
    /// writes it.
    pub fn refusal(self, ran: &Ran) -> Option<String> {
        let e = self.0.and_then(|s| s.finish().map(|_| ())).err()?;
        Some(match place(ran, &e) {
            Some((at, message)) => format!("{at}: error: kezuri run refuses this: {message}"),
            None => format!("error: kezuri run refuses this: {e:#}"),
        })
    }
}

impl PathSink for RunTrial {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        if let Ok(s) = &mut self.0 {
            s.take(piece, programmed);
        }
    }
}
