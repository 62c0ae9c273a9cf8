//! `kezuri texture`: a random "hand-carved" texture on the cutting
//! moves of a program, baked in or as a Fanuc Custom Macro B program.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::texture::{bake, check, is_textured, Dist, TextureOptions};
use kezuri_nc::texture_macro::{Blocks, TextureMacro};

use crate::files::read_text;
use crate::program::{run_text, stage_toolpath, Origin, RunOptions, WriteArgs};

/// How the texture is made.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Mode {
    /// Baked into the program: every stroke written out (any dialect).
    Bake,
    /// A Fanuc macro called by G66.1 on every cutting block
    /// draws each depth from the control's clock, so every part differs. The
    /// program is written as it was, with the calls and the macro added
    /// (--to, --digits, --line-numbers and --svg do not apply).
    Macro,
}

/// The depth distribution.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DistArg {
    /// A digit 0–9 onto nine depths, the middle twice as likely (as the original carving
    /// macro drew them).
    Digits,
    /// Every multiple of the quantum within the spread equally likely.
    Uniform,
    /// Normal, σ = spread / 2, clamped to the spread (bake only).
    Normal,
    /// Smooth noise over XY: neighbouring passes look like related strokes (bake only).
    Smooth,
}

/// `kezuri texture IN --seed N -o OUT`.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  kezuri texture samples/nameplate-cam.nc --seed 7 -o plate-textured.nc
  kezuri texture samples/nameplate-cam.nc --seed 7 --base -2 \\
      --step-range 0.2,1.6 --max-depth -2.8 -o plate-carved.nc
  kezuri texture samples/nameplate-cam.nc --seed 3 --dist smooth --spread 0.3 \\
      --quantum 0.05 -o plate-smooth.nc
  kezuri texture samples/nameplate-cam.nc --base -2 --mode macro \\
      -o plate-macro.nc
  kezuri run plate-macro.nc --clock-seed 11 -o one-part.nc")]
pub struct TextureArgs {
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub write: WriteArgs,
    /// Seed of the depths: the same seed gives the same program. Needed to
    /// bake; not with --mode macro, which draws from the control's clock.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Bake the texture into the program, or emit the macro.
    #[arg(long, value_enum, default_value = "bake")]
    pub mode: Mode,
    /// XY travel per stroke, mm: each ends at a new random depth.
    #[arg(long, value_name = "MM", default_value_t = 20.0, value_parser = crate::numbers::length)]
    pub segment: f64,
    /// A fixed depth the offsets are added to (for example -2.0) [default: the
    /// program's own Z on each move].
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub base: Option<f64>,
    /// Largest offset up or down, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.8, allow_negative_numbers = true)]
    pub spread: f64,
    /// Offsets are multiples of this, mm (0: any).
    #[arg(long, value_name = "MM", default_value_t = 0.2, allow_negative_numbers = true)]
    pub quantum: f64,
    /// How the offsets are drawn.
    #[arg(long, value_enum, default_value = "digits")]
    pub dist: DistArg,
    /// Successive depths differ by at least MIN and at most MAX mm (for example
    /// 0.2,1.6).
    #[arg(long, value_name = "MIN,MAX")]
    pub step_range: Option<String>,
    /// No textured point goes below this Z (a safety clamp).
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub max_depth: Option<f64>,
    /// The macro's program number (--mode macro).
    #[arg(long, value_name = "N", default_value_t = 7023)]
    pub macro_number: u32,
    /// The first of seven common variables the macro keeps its state in.
    #[arg(long, value_name = "N", default_value_t = 190)]
    pub macro_vars: u32,
}

/// Runs `kezuri texture`.
pub fn run(a: &TextureArgs) -> Result<()> {
    let seed = match (a.mode, a.seed) {
        (Mode::Bake, None) => {
            bail!("--seed N is needed to bake: the same seed gives the same texture (--mode macro needs none)")
        }
        (Mode::Macro, Some(_)) => {
            eprintln!("warning: --seed is not used: the macro draws each depth from the control's clock (#3001)");
            0
        }
        (_, seed) => seed.unwrap_or(0),
    };
    let options = TextureOptions {
        segment: a.segment,
        base: a.base,
        spread: a.spread,
        quantum: a.quantum,
        dist: match a.dist {
            DistArg::Digits => Dist::Digits,
            DistArg::Uniform => Dist::Uniform,
            DistArg::Normal => Dist::Normal,
            DistArg::Smooth => Dist::Smooth,
        },
        step_range: a.step_range.as_deref().map(step_range).transpose()?,
        max_depth: a.max_depth,
        seed,
    };
    check(&options)?;
    let name = a.run.file.display().to_string();
    let text = read_text(&a.run.file)?;
    let blocks = Blocks::parse(&text);
    if let Some(line) = blocks.modal_macro_line() {
        bail!(
            "{name}: line {line}: the program already calls a macro on its blocks (G66/G66.1); texture the \
             expanded program instead (kezuri run {name} -o expanded.nc)"
        );
    }
    let (mut ran, parse_diagnostics) = run_text(&a.run, text.clone())?;
    ran.shown(&parse_diagnostics, &a.run.file, "nothing written")?;
    crate::program::refuse_comp(&ran, &a.run.file, "texturing changes")?;
    // With the run's own outputs (the DPRNT file).
    let mut out = std::mem::take(&mut ran.outputs);
    let path = &ran.outcome.toolpath;
    let cutting: Vec<u32> = path.moves.iter().filter(|m| is_textured(m)).map(|m| m.line).collect();
    if cutting.is_empty() {
        eprintln!("warning: {name}: no straight cutting move with XY travel: the program is copied through unchanged");
        out.add(a.write.output(), text.as_bytes())?;
        return out.commit();
    }
    let summary = match a.mode {
        Mode::Bake => {
            let t = bake(path, &options).with_context(|| name.clone())?;
            let title = a.run.file.file_name().map_or_else(|| "-".into(), |n| n.to_string_lossy().to_uppercase());
            stage_toolpath(
                &mut out,
                &t.toolpath,
                &format!("{title} TEXTURED, SEED {seed}"),
                &a.write,
                &ran.machine,
                Origin::Transformed,
                &[],
            )?;
            let what = format!("{} cutting moves textured, {} strokes of {} mm; ", t.moves, t.knots, a.segment);
            what + &crate::say::program_summary(&t.toolpath, &ran.machine)
        }
        Mode::Macro => {
            if !a.write.is_fanuc(&ran.machine) {
                bail!("--mode macro writes a Fanuc Custom Macro B program: leave --to at fanuc");
            }
            let uniform = match a.dist {
                DistArg::Digits => false,
                DistArg::Uniform => true,
                DistArg::Normal | DistArg::Smooth => {
                    bail!("--mode macro draws from the control's clock: --dist digits or uniform")
                }
            };
            if a.quantum <= 0.0 {
                bail!("--mode macro needs a --quantum above 0 (the clock gives whole steps)");
            }
            if !(100..=193).contains(&a.macro_vars) && !(500..=993).contains(&a.macro_vars) {
                bail!(
                    "--macro-vars {}: the macro keeps its state in seven common variables, #100-#199 or \
                     #500-#999 (the first of them: 100-193 or 500-993)",
                    a.macro_vars
                );
            }
            if !(1..=9999).contains(&a.macro_number) || blocks.has_program(a.macro_number) {
                bail!("--macro-number {}: give 1-9999, not a program number the file has", a.macro_number);
            }
            if let Some(line) = blocks.incremental_line(last_line(&cutting)) {
                bail!("{name}: line {line}: G91: --mode macro textures absolute (G90) moves; use --mode bake");
            }
            if let Some((line, word)) = blocks.foreign_word(cutting[0] as usize, last_line(&cutting)) {
                bail!(
                    "{name}: line {line}: '{word}' inside the cutting section: under G66.1 every block there calls \
                     the macro, which passes on motion words only (X Y Z I J K R F); use --mode bake"
                );
            }
            if let Some(line) = blocks.call_line() {
                bail!(
                    "{name}: line {line}: --mode macro marks the cutting blocks in this file, and this one calls \
                     another program (M98/G65); use --mode bake"
                );
            }
            let (first, last) = (cutting[0] as usize, last_line(&cutting));
            let m = TextureMacro {
                number: a.macro_number,
                segment: a.segment,
                base: a.base,
                spread: a.spread,
                quantum: a.quantum,
                uniform,
                step_range: options.step_range,
                max_depth: a.max_depth,
                vars: a.macro_vars,
            };
            out.add(a.write.output(), m.wrap(&text, first, last).as_bytes())?;
            format!(
                "G66.1 P{:04} before line {first}, G67 after line {last}; the macro draws each depth from #3001",
                a.macro_number
            )
        }
    };
    out.commit()?;
    crate::say::note!("wrote {}: {summary}", crate::say::shown(a.write.output()));
    Ok(())
}

/// `MIN,MAX`.
fn step_range(s: &str) -> Result<[f64; 2]> {
    let v: Vec<f64> = s.split(',').map(|p| p.trim().parse::<f64>()).collect::<Result<_, _>>().ok().unwrap_or_default();
    match v[..] {
        [lo, hi] => Ok([lo, hi]),
        _ => bail!("--step-range '{s}': expected MIN,MAX in mm, e.g. 0.2,1.6"),
    }
}

/// The last of the cutting moves' lines.
fn last_line(cutting: &[u32]) -> usize {
    cutting.iter().copied().max().unwrap_or(0) as usize
}
