//! `kezuri demo`: every pipeline on bundled samples, into one folder.

use std::path::Path;

use anyhow::{bail, Context, Result};
use kezuri_nc::write::{csv, program, WriteOptions};

use crate::files::write_atomic;
use crate::plot;
use crate::program::{read_and_run, NoDecimal, Report, RunOptions};

/// The bundled samples: file name, what it shows, text.
const SAMPLES: [(&str, &str, &str); 3] = [
    (
        "o1011-digitize.nc",
        "seed 000: digitizing program O1011/O1012/O1013, 85 x 105 plunges",
        include_str!("../../../samples/o1011-digitize.nc"),
    ),
    (
        "o7023-texture.nc",
        "seed 004: CAM path under G66.1 P7023, random depths from #3001 (--clock-seed 7)",
        include_str!("../../../samples/o7023-texture.nc"),
    ),
    (
        "o2007-thermal.nc",
        "seed 003: thermal test moves O2007 with B indexing",
        include_str!("../../../samples/o2007-thermal.nc"),
    ),
];

pub fn run(out: &Path) -> Result<()> {
    let samples = out.join("samples");
    std::fs::create_dir_all(&samples).with_context(|| format!("cannot create {}", samples.display()))?;
    println!("kezuri demo -> {}", out.display());
    for (name, what, text) in SAMPLES {
        let file = samples.join(name);
        write_atomic(&file, text.as_bytes())?;
        let options = RunOptions {
            file: file.clone(),
            lib: None,
            machine: None,
            no_decimal: NoDecimal::Increments,
            clock_seed: Some(7),
            block_delete: false,
            step_limit: 10_000_000,
            dprnt: None,
        };
        let (ran, parse_diagnostics) = read_and_run(&options)?;
        if ran.errors() > 0 {
            ran.print_diagnostics(&parse_diagnostics);
            bail!("sample {name} did not run");
        }
        let stem = name.trim_end_matches(".nc");
        let path = &ran.outcome.toolpath;
        let expanded = out.join(format!("{stem}-expanded.nc"));
        let options = WriteOptions { title: Some(format!("{stem} expanded by kezuri")), ..WriteOptions::default() };
        write_atomic(&expanded, program(path, &options)?.as_bytes())?;
        write_atomic(&out.join(format!("{stem}.csv")), csv(path).as_bytes())?;
        write_atomic(&out.join(format!("{stem}.svg")), plot::svg(path, name).as_bytes())?;
        let r = Report::new(&ran);
        let warnings = parse_diagnostics.iter().chain(&ran.outcome.diagnostics).filter(|d| !d.is_error()).count();
        println!("\n{name}  ({what})");
        println!(
            "  {} blocks, {} motions, feed {:.1} mm, rapid {:.1} mm, cycle time {:.0} s, {} warnings",
            r.blocks, r.motions, r.feed_length_mm, r.rapid_length_mm, r.time_s, warnings
        );
        println!("  wrote {stem}-expanded.nc (Fanuc, macros expanded), {stem}.csv (motions), {stem}.svg (picture)");
    }
    Ok(())
}
