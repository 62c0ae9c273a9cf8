//! Reading and running a program: the options every command that runs one
//! takes, the dialect it is read in, the run's settings, what it made.

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use kezuri_geom::PathSink;
use kezuri_nc::ast::PAGE_BLOCKS;
use kezuri_nc::interp::comp::Rules;
use kezuri_nc::interp::{self, Control, CoordSettings, CycleSettings, IntegerInput, Outcome, Settings};
use kezuri_nc::source::TextStore;
use kezuri_nc::{
    detect_forgetting, parse_as, parse_counting, Detected, Diagnostic, Dialect, Program, SourceFile, Sources,
};

use crate::files::{read_program_text, read_text, Folder, Outputs};
use crate::progress::ByteProgress;
use kezuri_machine::Machine;

/// Pages of plain blocks a run holds at once (of [`PAGE_BLOCKS`] lines):
/// some 4 MB.
const PAGES_HELD: usize = 8;

/// How axis words without a decimal point are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NoDecimal {
    /// Counts of the least increment (0.001 mm): `X100` is 0.1 mm (Fanuc).
    Increments,
    /// Whole units: `X100` is 100 mm (LinuxCNC, GRBL).
    Units,
}

/// Options shared by every command that runs a program.
#[derive(Args, Clone, Debug)]
pub struct RunOptions {
    /// The program file (`-` for standard input).
    pub file: PathBuf,
    /// Folder of subprogram files `O1234.nc` [default: the program's folder].
    #[arg(long, value_name = "DIR")]
    pub lib: Option<PathBuf>,
    /// Machine file (TOML): what the machine is ([machine] kind mill, lathe
    /// or mill-turn; a lathe's x and gcode_system; max_rpm), rapids,
    /// acceleration, tool table ([tools] H and D registers, a turning tool's
    /// nose_radius and tip), offsets (G54…, G54.1 P, reference points), the
    /// control ([coordinates] fanuc, haas, linuxcnc), [cycles], [comp],
    /// [macro], [signals].
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// The language the program is written in: fanuc, haas, linuxcnc,
    /// grbl, fanuc-lathe or haas-lathe [default: from the file's extension
    /// and content; see docs/linuxcnc.md, "Choosing the dialect"]. On a
    /// machine file's lathe or mill-turn, fanuc and haas are read as
    /// fanuc-lathe and haas-lathe.
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
    /// Most statements run again (after a jump back, in a loop's next turn,
    /// in a subprogram or macro called again) before a run is stopped as a
    /// runaway loop. A program read straight through is never stopped,
    /// whatever its length.
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
    /// A Fanuc lathe (T series): from the start G18, feed per revolution,
    /// X a diameter (the machine file's x = "radius" says otherwise);
    /// G code system A (U W incremental X Z) unless the machine file's
    /// gcode_system says B or C; `X100` is 0.1 mm, as on the mill.
    FanucLathe,
    /// A Haas lathe: the Fanuc lathe with Haas's codes and one-block
    /// cycles; `X100` is 0.1 mm.
    HaasLathe,
}

impl From<DialectArg> for Dialect {
    fn from(d: DialectArg) -> Dialect {
        match d {
            DialectArg::Fanuc => Dialect::Fanuc,
            DialectArg::Haas => Dialect::Haas,
            DialectArg::Linuxcnc => Dialect::LinuxCnc,
            DialectArg::Grbl => Dialect::Grbl,
            DialectArg::FanucLathe => Dialect::FanucLathe,
            DialectArg::HaasLathe => Dialect::HaasLathe,
        }
    }
}

/// `--dialect`'s value for a dialect.
impl From<Dialect> for DialectArg {
    fn from(d: Dialect) -> DialectArg {
        match d {
            Dialect::Fanuc => DialectArg::Fanuc,
            Dialect::Haas => DialectArg::Haas,
            Dialect::LinuxCnc => DialectArg::Linuxcnc,
            Dialect::Grbl => DialectArg::Grbl,
            Dialect::FanucLathe => DialectArg::FanucLathe,
            Dialect::HaasLathe => DialectArg::HaasLathe,
        }
    }
}

/// The dialect of `file` holding `text`: `given` (`--dialect`), else the
/// rule of [`kezuri_nc::detect`]; a mixed program is refused.
pub fn choose_dialect(given: Option<Dialect>, file: &Path, text: &str) -> Result<Detected> {
    choose_dialect_forgetting(given, file, text, &|_| {})
}

/// [`choose_dialect`] telling `forget` of the text read through (a mapped
/// file's pages let go of as the markers are looked for).
fn choose_dialect_forgetting(
    given: Option<Dialect>,
    file: &Path,
    text: &str,
    forget: &dyn Fn(std::ops::Range<usize>),
) -> Result<Detected> {
    let name = if file == Path::new("-") { String::new() } else { file.display().to_string() };
    detect_forgetting(given, &name, text, forget).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

/// The dialect `detected` on `machine`: a lathe or a mill-turn (the machine
/// file's `[machine] kind`) reads a Fanuc program as a Fanuc lathe's and a
/// Haas program as a Haas lathe's, and the reason says so.
pub fn on_machine(detected: Detected, machine: &Machine) -> Detected {
    let lathe = match detected.dialect {
        Dialect::Fanuc => Dialect::FanucLathe,
        Dialect::Haas => Dialect::HaasLathe,
        _ => return detected,
    };
    if !machine.kind.turns() {
        return detected;
    }
    let reason = format!("{}; a lathe's, by the machine file's kind = \"{}\"", detected.reason, machine.kind);
    Detected { dialect: lathe, reason }
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
        eprint!("{}", self.rendered_diagnostics(parse_diagnostics));
    }

    /// Every diagnostic rendered, each followed by a blank line.
    pub fn rendered_diagnostics(&self, parse_diagnostics: &[Diagnostic]) -> String {
        parse_diagnostics.iter().chain(&self.outcome.diagnostics).map(|d| d.render(&self.sources) + "\n\n").collect()
    }

    /// What a command that goes on to use the run says first: every
    /// diagnostic and the dialect read (`file: dialect …`); a run with
    /// errors is refused, `file: N error(s); {nothing}`.
    pub fn shown(&self, parse_diagnostics: &[Diagnostic], file: &Path, nothing: &str) -> Result<()> {
        self.print_diagnostics(parse_diagnostics);
        crate::say::note!("{}: {}", file.display(), self.dialect);
        if self.errors() > 0 {
            bail!("{}: {}; {nothing}", file.display(), crate::say::count(self.errors() as u64, "error"));
        }
        Ok(())
    }
}

/// Reads, parses and runs the program; returns parse diagnostics apart.
/// A cutter compensation register the tool table lacks is a warning
/// (radius 0).
pub fn read_and_run(o: &RunOptions) -> Result<(Ran, Vec<Diagnostic>)> {
    run_store(o, read_program_text(&o.file)?, false)
}

/// [`read_and_run`] on the program's text, read already. `centre`: the
/// tool-centre path is asked for (`run --apply-comp`), so a cutter
/// compensation register the tool table lacks is an error (`sim` and
/// `view` warn of it, as `check` and `run` do).
pub fn run_store(o: &RunOptions, text: Arc<dyn TextStore>, centre: bool) -> Result<(Ran, Vec<Diagnostic>)> {
    run_program(o, text, centre, NO_SINK).map(|(ran, d, _)| (ran, d))
}

/// [`read_and_run`] handing the toolpath piece by piece as the run makes
/// it to the sink `make` gives once the machine, the dialect and the
/// program parsed are known (the sink is returned; the run's
/// `outcome.toolpath` is empty). `centre`: the tool-centre path is asked
/// for (as in [`run_store`]).
pub fn read_and_run_into<S: PathSink + Send>(
    o: &RunOptions,
    centre: bool,
    make: impl FnOnce(&Machine, Dialect, &Program) -> S,
) -> Result<(Ran, Vec<Diagnostic>, S)> {
    run_text_into(o, read_program_text(&o.file)?, centre, make)
}

/// [`read_and_run_into`] on the program's text, read already.
pub fn run_text_into<S: PathSink + Send>(
    o: &RunOptions,
    text: Arc<dyn TextStore>,
    centre: bool,
    make: impl FnOnce(&Machine, Dialect, &Program) -> S,
) -> Result<(Ran, Vec<Diagnostic>, S)> {
    let (ran, diagnostics, sink) = run_program(o, text, centre, Some(make))?;
    let sink = sink.ok_or_else(|| anyhow::anyhow!("{}: the run made no sink for its path", o.file.display()))?;
    Ok((ran, diagnostics, sink))
}

/// No sink: the run keeps its whole path.
const NO_SINK: Option<fn(&Machine, Dialect, &Program) -> kezuri_geom::WholePath> = None;

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
    run_program(o, Arc::new(text), false, NO_SINK).map(|(ran, d, _)| (ran, d))
}

/// Whether `dialect` reads whole units without a decimal point and
/// follows LinuxCNC's coordinate and compensation rules (LinuxCNC, GRBL).
pub fn whole_units(dialect: Dialect) -> bool {
    matches!(dialect, Dialect::LinuxCnc | Dialect::Grbl)
}

/// The settings of a run of a program in `dialect` on `machine`: axis words
/// without a decimal point by `no_decimal`, else by the dialect; LinuxCNC's
/// cutter compensation and coordinate rules for LinuxCNC and GRBL, Haas's
/// coordinate rules for Haas, the machine file's otherwise. A lathe's
/// dialects read like their mills' (`X100` is 0.1 mm on a Fanuc or Haas
/// lathe too), with the machine file's lathe conventions (X mode, G code
/// system), top speed and noses; LinuxCNC and GRBL take the top speed and
/// noses, and start as their controls do.
pub fn dialect_settings(dialect: Dialect, no_decimal: Option<NoDecimal>, machine: &Machine) -> Settings {
    let units = match no_decimal {
        Some(n) => n == NoDecimal::Units,
        None => whole_units(dialect),
    };
    let control = match dialect {
        Dialect::LinuxCnc | Dialect::Grbl => Control::LinuxCnc,
        Dialect::Haas | Dialect::HaasLathe => Control::Haas,
        Dialect::Fanuc | Dialect::FanucLathe => machine.settings.coords.control,
    };
    Settings {
        dialect,
        integer_input: if units { IntegerInput::Units } else { IntegerInput::Increments },
        // Cutter compensation by the dialect: LinuxCNC's, or Fanuc's with
        // the machine file's start-up type.
        comp_rules: if whole_units(dialect) { Rules::LinuxCnc } else { machine.settings.comp_rules },
        coords: CoordSettings { control, ..machine.settings.coords.clone() },
        // LinuxCNC turns by its own codes (G7, G8, G18) from its own
        // power-on state, whatever the machine file's lathe says.
        lathe: if whole_units(dialect) { None } else { machine.settings.lathe },
        ..machine.settings.clone()
    }
}

/// A LinuxCNC parameter file: each line with exactly two numbers is a
/// parameter and its value (others are skipped, as LinuxCNC does); the
/// numbers must ascend.
fn read_var_file(path: &Path) -> Result<BTreeMap<u32, f64>> {
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

fn run_program<S: PathSink + Send>(
    o: &RunOptions,
    text: Arc<dyn TextStore>,
    radii_required: bool,
    sink: Option<impl FnOnce(&Machine, Dialect, &Program) -> S>,
) -> Result<(Ran, Vec<Diagnostic>, Option<S>)> {
    run_on(machine_of(o)?, o, text, radii_required, sink, false)
}

/// The machine `o` runs the program on: its machine file's, or the default.
fn machine_of(o: &RunOptions) -> Result<Machine> {
    match &o.machine {
        Some(p) => crate::machine::load(p),
        None => Ok(Machine::default()),
    }
}

/// The program of `ran` (its first run, with `o`) run once more on the
/// same text and machine, its path handed piece by piece to `sink` on the
/// other core: another pass over its moves, the same moves (a run is
/// deterministic). What the program prints and logs, and the tools its
/// comments give, are not said again.
pub fn run_again_into<S: PathSink + Send>(o: &RunOptions, ran: &Ran, sink: S) -> Result<S> {
    let text = ran.sources.get(0).text.store();
    let make = |_: &Machine, _: Dialect, _: &Program| sink;
    let (_, _, sink) = run_on(machine_of(o)?, o, text, false, Some(make), true)?;
    sink.ok_or_else(|| anyhow::anyhow!("{}: the run made no sink for its path", o.file.display()))
}

/// A program kezuri wrote (`text`, to be saved as `name`) run on `machine`
/// as `kezuri view` would run the file: for the page of a writer's `--view`.
pub fn run_written(machine: &Machine, name: &Path, text: String) -> Result<Ran> {
    let o: RunOptions = options_from(&[OsStr::new("--"), name.as_os_str()])?;
    let (ran, parse_diagnostics, _) = run_on(machine.clone(), &o, Arc::new(text), false, NO_SINK, false)?;
    if ran.errors() > 0 {
        ran.print_diagnostics(&parse_diagnostics);
        bail!(
            "{}: the written program does not run back ({}): no page",
            name.display(),
            crate::say::count(ran.errors() as u64, "error")
        );
    }
    Ok(ran)
}

/// Options of type `T` as the command line gives them from `words`, clap's
/// defaults for the rest: one source for a default, the `--help` and the
/// code that needs the options without a command line.
pub(super) fn options_from<T: clap::Args + clap::FromArgMatches>(words: &[&OsStr]) -> Result<T> {
    let command = T::augment_args(clap::Command::new("kezuri"));
    let matches = command.try_get_matches_from(std::iter::once(OsStr::new("kezuri")).chain(words.iter().copied()))?;
    Ok(T::from_arg_matches(&matches)?)
}

/// [`run_program`] on a machine loaded already.
fn run_on<S: PathSink + Send>(
    machine: Machine,
    o: &RunOptions,
    text: Arc<dyn TextStore>,
    radii_required: bool,
    make_sink: Option<impl FnOnce(&Machine, Dialect, &Program) -> S>,
    again: bool,
) -> Result<(Ran, Vec<Diagnostic>, Option<S>)> {
    let given = o.dialect.map(Dialect::from);
    let detected = choose_dialect_forgetting(given, &o.file, text.text(), &|r| text.forget(r))?;
    let detected = on_machine(detected, &machine);
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
    let mut settings = Settings {
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
    let id = sources.add(SourceFile::stored(name, text));
    let mut program = Program::default();
    // A program is read in pages (those of plain blocks dropped once run, read
    // again where the run comes back), but a Fanuc or Haas lathe's, whose
    // cycles read the blocks of a contour ahead.
    if !detected.dialect.is_lathe() {
        program.read_in_pages(PAGE_BLOCKS, PAGES_HELD);
    }
    let text = sources.get(id).text.clone();
    // Reading and running a big program takes seconds: a bar by bytes.
    let progress = ByteProgress::start("reading", text.len() as u64);
    let parse_diagnostics = match progress.counter() {
        Some(done) => parse_counting(&mut program, id, &text, detected.dialect, &done),
        None => parse_as(&mut program, id, &text, detected.dialect),
    };
    let parse_errors = parse_diagnostics.iter().filter(|d| d.is_error()).count();
    let mut sink = make_sink.map(|make| make(&machine, detected.dialect, &program));
    let dir = library_dir(o.lib.as_deref(), &o.file);
    let outcome = if parse_errors > 0 || program.units.is_empty() {
        Outcome::default()
    } else {
        progress.stage("running");
        settings.progress = progress.counter();
        let mut library = Folder::new(dir);
        match sink.take() {
            // The path taken on the other core as the run makes it.
            Some(taker) => {
                let (outcome, taker) = super::beside::with_sink_beside(taker, |handing| {
                    interp::run_into(&mut program, &mut sources, 0, &mut library, &settings, handing)
                });
                sink = Some(taker);
                outcome
            }
            None => interp::run(&mut program, &mut sources, 0, &mut library, &settings),
        }
    };
    progress.finish();
    let mut outputs = Outputs::new();
    // A run again has said what it prints and logs the first time.
    if !outcome.prints.is_empty() && !again {
        match &o.dprnt {
            Some(p) => outputs.add(Some(p), (outcome.prints.join("\n") + "\n").as_bytes())?,
            None => outcome.prints.iter().for_each(|l| eprintln!("{}: {l}", print_label(settings.dialect))),
        }
    }
    let mut machine = machine;
    if !again {
        report_logs(&outcome);
        super::comment_tools::from_comments(&mut machine, &text, outcome.inch, &sources.get(id).name);
    }
    Ok((Ran { dialect: detected, sources, outcome, machine, parse_errors, outputs }, parse_diagnostics, sink))
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

/// One line per kind of value the run took from the machine file rather
/// than from the program: the written program holds this machine's value.
pub fn model_notes(outcome: &Outcome) -> Vec<String> {
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
    match ran.outcome.programmed {
        Some(_) => Err(comp_refused(file, what)),
        None => Ok(()),
    }
}

/// Why [`refuse_comp`] refuses the program `file`.
pub fn comp_refused(file: &Path, what: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}: the program uses cutter radius compensation (G41/G42): {what} the tool centre path, so write it first \
         with `kezuri run {} --apply-comp --machine M.toml -o centre.nc` and give that program",
        file.display(),
        file.display()
    )
}

/// The options of a run of the program `file` with every other option at
/// its default, for a command that has not all of them (`convert`).
pub fn run_options(file: &Path) -> Result<RunOptions> {
    options_from(&[OsStr::new("--"), file.as_os_str()])
}
