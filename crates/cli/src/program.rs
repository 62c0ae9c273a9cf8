//! `kezuri check` and `kezuri run`: read a program, run it, report or write.

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::Cutter;
use kezuri_correct::kinematics::{Kinematics, AXES};
use kezuri_geom::{cycle_time, LengthOffset, MoveKind, Toolpath};
use kezuri_nc::interp::comp::Rules;
use kezuri_nc::interp::{self, Control, CoordSettings, CycleSettings, IntegerInput, Outcome, Settings};
use kezuri_nc::write::WriteOptions;
use kezuri_nc::{detect, parse_as, Detected, Diagnostic, Dialect, Program, SourceFile, Sources};
use serde_json::json;

use crate::files::{read_text, write_output, Folder, Outputs};
use crate::machine::{Machine, ToolEntry};

/// How axis words without a decimal point are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NoDecimal {
    /// Counts of the least increment (0.001 mm): `X100` is 0.1 mm (Fanuc).
    Increments,
    /// Whole units: `X100` is 100 mm (LinuxCNC, GRBL).
    Units,
}

/// Options shared by every command that runs a program.
#[derive(Args, Debug)]
pub struct RunOptions {
    /// The program file (`-` for standard input).
    pub file: PathBuf,
    /// Folder of subprogram files `O1234.nc` [default: the program's folder].
    #[arg(long, value_name = "DIR")]
    pub lib: Option<PathBuf>,
    /// Machine file (TOML): rapids, acceleration, tool table ([tools] H and D
    /// registers), offsets (G54…, G54.1 P, reference points), the control
    /// ([coordinates] fanuc, haas, linuxcnc), [cycles], [comp], [macro],
    /// [signals].
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// The language the program is written in: fanuc, haas, linuxcnc or
    /// grbl [default: from the file's extension and content; see
    /// docs/linuxcnc.md, "Choosing the dialect"].
    #[arg(long, value_enum, value_name = "DIALECT")]
    pub dialect: Option<DialectArg>,
    /// LinuxCNC's parameter file (`NUMBER VALUE` lines, as `rs274 -v` reads
    /// it): the starting values of #5161… (G28, G30), #5211… (G92), #5220
    /// (the coordinate system), #5221… (G54 …), lengths in mm. The
    /// linuxcnc and grbl dialects only.
    #[arg(long, value_name = "FILE.var")]
    pub var: Option<PathBuf>,
    /// How axis words without a decimal point are read [default: units in
    /// LinuxCNC and GRBL, increments in Fanuc and Haas].
    #[arg(long, value_enum)]
    pub no_decimal: Option<NoDecimal>,
    /// Seed for the #3001 clock: each read advances it a reproducible
    /// pseudo-random 1–1000 ms (default: one 16 ms tick per read).
    #[arg(long, value_name = "N")]
    pub clock_seed: Option<u64>,
    /// Skip blocks that start with `/` (block delete switch on).
    #[arg(long)]
    pub block_delete: bool,
    /// Most statements executed before a run is stopped as a runaway loop.
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    pub step_limit: u64,
    /// Write DPRNT lines to this file (default: standard error).
    #[arg(long, value_name = "FILE")]
    pub dprnt: Option<PathBuf>,
    /// Write canned cycles (G73, G76, G81–G89) as cycle blocks, as the
    /// program gave them, instead of the moves they make. Tapping (G74,
    /// G84) is always kept as a cycle.
    #[arg(long)]
    pub keep_cycles: bool,
}

/// The language a program is read in (`--dialect`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DialectArg {
    /// Fanuc with Custom Macro B: `X100` is 0.1 mm (least increments).
    Fanuc,
    /// Haas: Fanuc with Haas's codes (G154 P, G187, G103, G47).
    Haas,
    /// LinuxCNC (rs274ngc): O-word subroutines, `#<name>`, `@ ^`; `X100` is 100 mm.
    Linuxcnc,
    /// GRBL 1.1: `X100` is 100 mm.
    Grbl,
}

impl From<DialectArg> for Dialect {
    fn from(d: DialectArg) -> Dialect {
        match d {
            DialectArg::Fanuc => Dialect::Fanuc,
            DialectArg::Haas => Dialect::Haas,
            DialectArg::Linuxcnc => Dialect::LinuxCnc,
            DialectArg::Grbl => Dialect::Grbl,
        }
    }
}

/// The dialect of `file` holding `text`: `given` (`--dialect`), else the
/// rule of [`kezuri_nc::detect`]; a mixed program is refused.
pub fn choose_dialect(given: Option<Dialect>, file: &Path, text: &str) -> Result<Detected> {
    let name = if file == Path::new("-") { String::new() } else { file.display().to_string() };
    detect(given, &name, text).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

/// A program read and run.
pub struct Ran {
    /// The dialect it was read in, and why.
    pub dialect: Detected,
    pub sources: Sources,
    pub outcome: Outcome,
    pub machine: Machine,
    pub parse_errors: usize,
    /// The outputs of the run (the DPRNT file), written with the command's
    /// others.
    pub outputs: Outputs,
}

impl Ran {
    /// Errors in the parse and in the run.
    pub fn errors(&self) -> usize {
        self.parse_errors + self.outcome.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    /// Renders every diagnostic to standard error.
    pub fn print_diagnostics(&self, parse_diagnostics: &[Diagnostic]) {
        for d in parse_diagnostics.iter().chain(&self.outcome.diagnostics) {
            eprintln!("{}\n", d.render(&self.sources));
        }
    }

    /// What a command that goes on to use the run says first: every
    /// diagnostic and the dialect read (`file: dialect …`); a run with
    /// errors is refused, `file: N error(s); {nothing}`.
    pub fn shown(&self, parse_diagnostics: &[Diagnostic], file: &Path, nothing: &str) -> Result<()> {
        self.print_diagnostics(parse_diagnostics);
        crate::say::note!("{}: {}", file.display(), self.dialect);
        if self.errors() > 0 {
            bail!("{}: {} error(s); {nothing}", file.display(), self.errors());
        }
        Ok(())
    }
}

/// Reads, parses and runs the program; returns parse diagnostics apart.
/// A cutter compensation register the tool table lacks is a warning
/// (radius 0).
pub fn read_and_run(o: &RunOptions) -> Result<(Ran, Vec<Diagnostic>)> {
    run_text(o, read_text(&o.file)?)
}

/// [`read_and_run`] where the tool-centre path is needed (a simulation, a
/// program written with the compensation applied): a cutter compensation
/// register the tool table lacks is an error.
pub fn read_and_run_centre(o: &RunOptions) -> Result<(Ran, Vec<Diagnostic>)> {
    run_program(o, read_text(&o.file)?, true)
}

/// The folder subprograms and subroutine files come from: `--lib`, else
/// the program's own folder (the working folder for standard input).
pub fn library_dir(lib: Option<&Path>, file: &Path) -> PathBuf {
    lib.map(Path::to_path_buf).unwrap_or_else(|| match file.parent() {
        Some(p) if !p.as_os_str().is_empty() && file != Path::new("-") => p.to_path_buf(),
        _ => PathBuf::from("."),
    })
}

/// How a program's printed lines are shown on standard error: Fanuc's
/// `DPRNT`, LinuxCNC's `(debug,…)`, `(print,…)` and `(msg,…)` messages.
pub fn print_label(dialect: kezuri_nc::Dialect) -> &'static str {
    if dialect.is_fanuc() {
        "DPRNT"
    } else {
        "MESSAGE"
    }
}

/// [`read_and_run`] on the program's text, read already.
pub fn run_text(o: &RunOptions, text: String) -> Result<(Ran, Vec<Diagnostic>)> {
    run_program(o, text, false)
}

/// Whether `dialect` reads whole units without a decimal point and
/// follows LinuxCNC's coordinate and compensation rules (LinuxCNC, GRBL).
fn whole_units(dialect: Dialect) -> bool {
    matches!(dialect, Dialect::LinuxCnc | Dialect::Grbl)
}

/// The settings of a run of a program in `dialect` on `machine`: axis words
/// without a decimal point by `no_decimal`, else by the dialect; LinuxCNC's
/// cutter compensation and coordinate rules for LinuxCNC and GRBL, Haas's
/// coordinate rules for Haas, the machine file's otherwise.
pub fn dialect_settings(dialect: Dialect, no_decimal: Option<NoDecimal>, machine: &Machine) -> Settings {
    let units = match no_decimal {
        Some(n) => n == NoDecimal::Units,
        None => whole_units(dialect),
    };
    let control = match dialect {
        Dialect::LinuxCnc | Dialect::Grbl => Control::LinuxCnc,
        Dialect::Haas => Control::Haas,
        Dialect::Fanuc => machine.settings.coords.control,
    };
    Settings {
        dialect,
        integer_input: if units { IntegerInput::Units } else { IntegerInput::Increments },
        // Cutter compensation by the dialect: LinuxCNC's, or Fanuc's with
        // the machine file's start-up type.
        comp_rules: if whole_units(dialect) { Rules::LinuxCnc } else { machine.settings.comp_rules },
        coords: CoordSettings { control, ..machine.settings.coords.clone() },
        ..machine.settings.clone()
    }
}

/// A LinuxCNC parameter file: each line with exactly two numbers is a
/// parameter and its value (others are skipped, as LinuxCNC does); the
/// numbers must ascend.
pub fn read_var_file(path: &Path) -> Result<BTreeMap<u32, f64>> {
    let text = read_text(path)?;
    let mut out = BTreeMap::new();
    let mut last = 0;
    for (k, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [n, v] = fields[..] else { continue };
        let (Ok(n), Ok(v)) = (n.parse::<u32>(), v.parse::<f64>()) else { continue };
        if !v.is_finite() || n == 0 {
            bail!("{}:{}: '{line}' is not a parameter and a finite value", path.display(), k + 1);
        }
        if n <= last {
            bail!("{}:{}: parameter #{n} after #{last}: a parameter file is in ascending order", path.display(), k + 1);
        }
        last = n;
        out.insert(n, v);
    }
    Ok(out)
}

fn run_program(o: &RunOptions, text: String, radii_required: bool) -> Result<(Ran, Vec<Diagnostic>)> {
    let machine = match &o.machine {
        Some(p) => Machine::load(p)?,
        None => Machine::default(),
    };
    run_on(machine, o, text, radii_required)
}

/// A program kezuri wrote (`text`, to be saved as `name`) run on `machine`
/// as `kezuri view` would run the file: for the page of a writer's `--view`.
pub fn run_written(machine: &Machine, name: &Path, text: String) -> Result<Ran> {
    let o: RunOptions = options_from(&[OsStr::new("--"), name.as_os_str()])?;
    let (ran, parse_diagnostics) = run_on(machine.clone(), &o, text, false)?;
    if ran.errors() > 0 {
        ran.print_diagnostics(&parse_diagnostics);
        bail!("{}: the written program does not run back ({} errors): no page", name.display(), ran.errors());
    }
    Ok(ran)
}

/// Options of type `T` as the command line gives them from `words`, clap's
/// defaults for the rest: one source for a default, the `--help` and the
/// code that needs the options without a command line.
pub fn options_from<T: clap::Args + clap::FromArgMatches>(words: &[&OsStr]) -> Result<T> {
    let command = T::augment_args(clap::Command::new("kezuri"));
    let matches = command.try_get_matches_from(std::iter::once(OsStr::new("kezuri")).chain(words.iter().copied()))?;
    Ok(T::from_arg_matches(&matches)?)
}

/// [`run_program`] on a machine loaded already.
fn run_on(machine: Machine, o: &RunOptions, text: String, radii_required: bool) -> Result<(Ran, Vec<Diagnostic>)> {
    let detected = choose_dialect(o.dialect.map(Dialect::from), &o.file, &text)?;
    let base = dialect_settings(detected.dialect, o.no_decimal, &machine);
    let parameters = match &o.var {
        Some(_) if !whole_units(detected.dialect) => bail!(
            "{}: --var is LinuxCNC's parameter file, and the program is read as {} ({}): give --dialect linuxcnc",
            o.file.display(),
            detected.dialect,
            detected.reason
        ),
        Some(p) => read_var_file(p)?,
        None => base.parameters.clone(),
    };
    let settings = Settings {
        parameters,
        radii_required,
        clock_seed: o.clock_seed,
        step_limit: o.step_limit,
        block_delete: o.block_delete,
        cycles: CycleSettings { keep: o.keep_cycles, ..machine.settings.cycles },
        ..base
    };
    let mut sources = Sources::default();
    let name = if o.file == Path::new("-") { "<stdin>".to_string() } else { o.file.display().to_string() };
    let id = sources.add(SourceFile::new(name, text));
    let mut program = Program::default();
    let text = sources.get(id).text.clone();
    let parse_diagnostics = parse_as(&mut program, id, &text, detected.dialect);
    let parse_errors = parse_diagnostics.iter().filter(|d| d.is_error()).count();
    let dir = library_dir(o.lib.as_deref(), &o.file);
    let outcome = if parse_errors > 0 || program.units.is_empty() {
        Outcome::default()
    } else {
        interp::run(&mut program, &mut sources, 0, &mut Folder::new(dir), &settings)
    };
    let mut outputs = Outputs::new();
    if !outcome.prints.is_empty() {
        match &o.dprnt {
            Some(p) => outputs.add(Some(p), (outcome.prints.join("\n") + "\n").as_bytes())?,
            None => outcome.prints.iter().for_each(|l| eprintln!("{}: {l}", print_label(settings.dialect))),
        }
    }
    report_logs(&outcome);
    Ok((Ran { dialect: detected, sources, outcome, machine, parse_errors, outputs }, parse_diagnostics))
}

/// Reports the lines a LinuxCNC program logs (`(log,…)`) on standard error,
/// each with its file: kezuri writes no file a program names.
pub fn report_logs(outcome: &Outcome) {
    for log in &outcome.logs {
        for line in &log.lines {
            eprintln!("LOG {}: {line}", log.name);
        }
    }
}

/// The axes `path` moves that `machine` does not have, each with the first
/// source line that moves it.
pub fn missing_axes(path: &Toolpath, machine: &Kinematics) -> Vec<(char, u32)> {
    let mut out: Vec<(char, u32)> = Vec::new();
    for m in &path.moves {
        for (k, (a, b)) in m.start.to_array().into_iter().zip(m.end.to_array()).enumerate() {
            if a != b && !machine.has(k) && !out.iter().any(|&(axis, _)| axis == AXES[k]) {
                out.push((AXES[k], m.line));
            }
        }
    }
    out
}

/// The `check` report.
pub struct Report {
    pub blocks: u64,
    pub holes: u64,
    pub statements: u64,
    pub motions: usize,
    pub feed_length_mm: f64,
    pub rapid_length_mm: f64,
    pub time_s: f64,
    pub bounds: Option<([f64; 3], [f64; 3])>,
    /// The tools that make moves, in the order they first do (0: none
    /// loaded), each with what the machine file's tool table says of it.
    pub tools: Vec<(u32, Option<ToolEntry>)>,
}

impl Report {
    pub fn new(ran: &Ran) -> Report {
        let path: &Toolpath = &ran.outcome.toolpath;
        Report {
            blocks: ran.outcome.blocks,
            holes: ran.outcome.holes,
            statements: ran.outcome.statements,
            motions: path.moves.iter().filter(|m| !matches!(m.kind, MoveKind::Dwell(_))).count(),
            feed_length_mm: path.feed_length(),
            rapid_length_mm: path.rapid_length(),
            time_s: cycle_time(path, &ran.machine.dynamics).0,
            bounds: path.bounds(),
            tools: tools_used(path).into_iter().map(|t| (t, ran.machine.tools.get(&t).cloned())).collect(),
        }
    }
}

/// Whether `check` looks for Z moves without a length offset: on a Fanuc
/// or Haas control (length offsets are how their tools are set), unless
/// the machine file's `[post]` says otherwise (its `length_offset`, or its
/// preset's: GRBL has none).
fn uses_length_offsets(dialect: Dialect, machine: &Machine) -> bool {
    machine
        .post
        .length_offset()
        .unwrap_or(!whole_units(dialect) && machine.settings.coords.control != Control::LinuxCnc)
}

/// The first move that changes Z after each tool change with no tool
/// length offset of its own in force: none (or H0), the one the last tool
/// had (G43 is modal across M06), or a register other than the tool
/// table's for that tool. On a machine whose tools are set with length
/// offsets that Z is not the new tool's tip.
pub fn unoffset_z_moves(path: &Toolpath, tools: &BTreeMap<u32, ToolEntry>) -> Vec<String> {
    let mut out = Vec::new();
    let (mut tool, mut armed) = (0, false);
    let mut before: Option<LengthOffset> = None;
    let mut last: Option<LengthOffset> = None;
    for m in &path.moves {
        if m.tool != tool {
            tool = m.tool;
            armed = tool != 0;
            before = last;
        }
        // Returns and G53 moves are in machine coordinates: no offset needed.
        let machine_coordinates = matches!(m.kind, MoveKind::Home | MoveKind::Machine | MoveKind::Dwell(_));
        let length = path.frame(m).length.filter(|l| l.register != 0);
        if !machine_coordinates {
            last = length;
        }
        if !armed || machine_coordinates || (m.start.z == m.end.z && !m.named.contains(2)) {
            continue;
        }
        armed = false;
        let what = match (length, tools.get(&tool)) {
            (None, _) => "no tool length offset (G43 H) in force".to_string(),
            (Some(l), _) if before.is_some_and(|b| b.register == l.register) => {
                format!("the last tool's length offset (H{}) still in force", l.register)
            }
            (Some(l), Some(e)) if e.h != l.register => {
                format!("H{} in force where the tool table gives T{tool} H{}", l.register, e.h)
            }
            _ => continue,
        };
        out.push(format!(
            "line {}: Z moves after the change to T{tool} with {what}: on a machine whose tools are set with \
             length offsets this Z is not the tool tip's",
            m.line
        ));
    }
    out
}

/// The tool numbers that make moves in `path`, in the order they first do.
pub fn tools_used(path: &Toolpath) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    for m in &path.moves {
        if !out.contains(&m.tool) {
            out.push(m.tool);
        }
    }
    out
}

/// How a report names tool `t`: `T5 ball:6 H5 D25 (name)`, `T5 (not in the
/// tool table)`, or `no tool (T0)`.
fn tool_line(t: u32, entry: &Option<ToolEntry>) -> String {
    match entry {
        _ if t == 0 => "no tool (T0)".to_string(),
        None => format!("T{t} (not in the tool table)"),
        Some(e) => {
            let mut s = format!("T{t}");
            if let Some(c) = e.shape {
                s += &format!(" {c}");
            }
            s += &format!(" H{}", e.h);
            if let Some(d) = e.d {
                s += &format!(" D{d}");
            }
            if let Some(n) = &e.name {
                s += &format!(" ({n})");
            }
            s
        }
    }
}

fn hms(s: f64) -> String {
    let t = s.round() as u64;
    format!("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
}

/// `kezuri check`.
pub fn check(o: &RunOptions, as_json: bool) -> Result<()> {
    let (mut ran, parse_diagnostics) = read_and_run(o)?;
    std::mem::take(&mut ran.outputs).commit()?;
    let report = Report::new(&ran);
    let all: Vec<&Diagnostic> = parse_diagnostics.iter().chain(&ran.outcome.diagnostics).collect();
    // Axes the program commands that the machine file's chains lack.
    let missing: Vec<String> = match &o.machine {
        Some(file) => missing_axes(&ran.outcome.toolpath, &ran.machine.kinematics)
            .into_iter()
            .map(|(axis, line)| {
                format!("{}: the machine has no {axis} axis, and the program commands it (line {line})", file.display())
            })
            .collect(),
        None => Vec::new(),
    };
    let missing: Vec<String> = if uses_length_offsets(ran.dialect.dialect, &ran.machine) {
        let file = o.file.display();
        missing
            .into_iter()
            .chain(
                unoffset_z_moves(&ran.outcome.toolpath, &ran.machine.tools).into_iter().map(|w| format!("{file}: {w}")),
            )
            .collect()
    } else {
        missing
    };
    if as_json {
        let (lo, hi) = report.bounds.unwrap_or(([0.0; 3], [0.0; 3]));
        let headlines = |errors: bool| -> Vec<String> {
            all.iter().filter(|d| d.is_error() == errors).map(|d| d.headline(&ran.sources)).collect()
        };
        let value = json!({
            "file": o.file.display().to_string(),
            "dialect": ran.dialect.dialect.name(),
            "dialect_reason": ran.dialect.reason,
            "completed": ran.outcome.completed && ran.errors() == 0,
            "blocks": report.blocks,
            "statements": report.statements,
            "motions": report.motions,
            "holes": report.holes,
            "feed_length_mm": report.feed_length_mm,
            "rapid_length_mm": report.rapid_length_mm,
            "time_s": report.time_s,
            "bounds": {"min": lo, "max": hi},
            "tools": report.tools.iter().map(|(t, e)| json!({
                "number": t,
                "shape": e.as_ref().and_then(|e| e.shape).map(|c| c.to_string()),
                "h": e.as_ref().map(|e| e.h),
                "d": e.as_ref().and_then(|e| e.d),
                "name": e.as_ref().and_then(|e| e.name.clone()),
            })).collect::<Vec<_>>(),
            "errors": headlines(true),
            "warnings": headlines(false).into_iter().chain(missing.iter().cloned()).collect::<Vec<_>>(),
            "machine_values": model_notes(&ran.outcome),
        });
        write_output(None, (value.to_string() + "\n").as_bytes())?;
    } else {
        ran.print_diagnostics(&parse_diagnostics);
        let mut text = format!(
            "{}: {} blocks ({} statements), {} motions\n  feed  {:.3} mm\n  rapid {:.3} mm\n  time  {} ({:.1} s)\n",
            o.file.display(),
            report.blocks,
            report.statements,
            report.motions,
            report.feed_length_mm,
            report.rapid_length_mm,
            hms(report.time_s),
            report.time_s
        );
        text += &format!("  {}\n", ran.dialect);
        if report.holes > 0 {
            text += &format!("  holes {} (canned cycles)\n", report.holes);
        }
        for (t, e) in &report.tools {
            text += &format!("  tool  {}\n", tool_line(*t, e));
        }
        if let Some((lo, hi)) = report.bounds {
            for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
                text += &format!("  {axis} {:>10.3} … {:>10.3}\n", lo[k], hi[k]);
            }
        }
        for m in &missing {
            eprintln!("warning: {m}");
        }
        for note in model_notes(&ran.outcome) {
            text += &format!("  note: {note}\n");
        }
        let warnings = all.iter().filter(|d| !d.is_error()).count() + missing.len();
        text += &format!("  {} errors, {} warnings\n", ran.errors(), warnings);
        write_output(None, text.as_bytes())?;
    }
    if ran.errors() > 0 {
        bail!("{}: {} error(s)", o.file.display(), ran.errors());
    }
    Ok(())
}

/// What `run` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Emit {
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
    emit: Option<Emit>,
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
    /// Whether the output is G-code (not CSV or RML-1).
    fn is_gcode(&self) -> bool {
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

/// `kezuri run`: the motions of the program, as a program again or as CSV.
///
/// With cutter radius compensation, Fanuc and LinuxCNC output is the
/// programmed contour with its G41/G42 D and G40 blocks; CSV, the SVG and
/// `--apply-comp` output the tool-centre path; GRBL and RML-1, which have
/// no compensation, need `--apply-comp`.
pub fn run(o: &RunOptions, w: &WriteArgs) -> Result<()> {
    let (mut ran, parse_diagnostics) = if w.apply_comp { read_and_run_centre(o)? } else { read_and_run(o)? };
    ran.shown(&parse_diagnostics, &o.file, "nothing written")?;
    let title = o.file.file_name().map_or_else(|| "-".into(), |n| n.to_string_lossy().to_uppercase());
    let centre = &ran.outcome.toolpath;
    // Which of the programmed contour and the tool-centre path is written.
    let without_comp = match w.emit {
        Some(Emit::Csv) => None,
        Some(Emit::Rml) => Some("RML-1"),
        _ => {
            (w.options(&ran.machine, Origin::Transformed)?.dialect == kezuri_nc::write::Dialect::Grbl).then_some("GRBL")
        }
    };
    let written = match (&ran.outcome.programmed, without_comp) {
        (Some(_), Some(control)) if !w.apply_comp => bail!(
            "{}: the program uses cutter radius compensation (G41/G42), which {control} has not: give --apply-comp to \
             write the tool centre path (radii from the machine file's [tools] radii)",
            o.file.display(),
        ),
        (Some(p), None) if !w.apply_comp && w.is_gcode() => p,
        _ => centre,
    };
    let notes = model_notes(&ran.outcome);
    for note in &notes {
        eprintln!("warning: {}: {note}", o.file.display());
    }
    let mut out = std::mem::take(&mut ran.outputs);
    write_program(&mut out, written, centre, &title, &notes, w, &ran.machine, Origin::Transformed, &[])?;
    out.commit()?;
    crate::say::wrote_program(w.output(), "", written, &ran.machine);
    Ok(())
}

/// One line per kind of value the run took from the machine file rather
/// than from the program: the written program holds this machine's value.
fn model_notes(outcome: &Outcome) -> Vec<String> {
    outcome
        .model_reads
        .iter()
        .map(|r| {
            format!(
                "#{}, the {} read at line {}, came from the machine file: this program holds that machine's value",
                r.variable, r.what, r.line
            )
        })
        .collect()
}

/// Refuses a program that uses cutter radius compensation for a command
/// (`what`) that changes its motions: they are the tool-centre path, which
/// `kezuri run --apply-comp` writes out first.
pub fn refuse_comp(ran: &Ran, file: &Path, what: &str) -> Result<()> {
    if ran.outcome.programmed.is_some() {
        bail!(
            "{}: the program uses cutter radius compensation (G41/G42): {what} the tool centre path, so write it first \
             with `kezuri run {} --apply-comp --machine M.toml -o centre.nc` and give that program",
            file.display(),
            file.display()
        );
    }
    Ok(())
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
    crate::post::for_machine(machine, name, output)
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

/// [`stage_toolpath`] with the SVG drawing `drawn`; `cutters` are the
/// shapes of the tools (by number) the `--view` page draws.
#[allow(clippy::too_many_arguments)]
fn write_program(
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
    let text = match w.emit {
        Some(Emit::Csv) => kezuri_nc::write::csv(path),
        Some(Emit::Rml) => {
            crate::convert::warn_rml_drops(title, path);
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
