//! The parts of a split program: `part.nc` → `part-1.nc`, `part-2.nc`, …,
//! and the parts of an earlier job that this one would leave behind.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// `part.nc` → `part-3.nc`.
pub fn part_name(path: &Path, k: usize) -> PathBuf {
    let (stem, ext) = stem_ext(path);
    let name = match ext {
        Some(e) => format!("{stem}-{k}.{e}"),
        None => format!("{stem}-{k}"),
    };
    path.with_file_name(name)
}

fn stem_ext(path: &Path) -> (String, Option<String>) {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    (stem, path.extension().map(|e| e.to_string_lossy().into_owned()))
}

/// The parts of `output`'s name beside it that a run writing `count` parts
/// would not replace (a run of one part writes `output` itself, no part),
/// in order.
fn left_over(output: &Path, count: usize) -> Vec<PathBuf> {
    let (stem, ext) = stem_ext(output);
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let number = |name: &str| -> Option<usize> {
        let rest = name.strip_prefix(&stem)?.strip_prefix('-')?;
        let digits = match &ext {
            Some(e) => rest.strip_suffix(e.as_str())?.strip_suffix('.')?,
            None => rest,
        };
        (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())).then(|| digits.parse().ok())?
    };
    let mut found: Vec<(usize, PathBuf)> = entries
        .flatten()
        .filter_map(|e| Some((number(&e.file_name().to_string_lossy())?, output.with_file_name(e.file_name()))))
        .filter(|&(k, _)| count == 1 || k > count)
        .collect();
    found.sort();
    found.into_iter().map(|(_, p)| p).collect()
}

/// Refuses to write `count` parts of `output` beside parts of an earlier
/// job that would be left, unless `overwrite`: then returns them, to be
/// removed once the new parts are written.
pub fn check_left_over(output: &Path, count: usize, overwrite: bool) -> Result<Vec<PathBuf>> {
    let old = left_over(output, count);
    if old.is_empty() || overwrite {
        return Ok(old);
    }
    let names: Vec<String> = old.iter().map(|p| p.display().to_string()).collect();
    let writes = match count {
        1 => output.display().to_string(),
        n => format!("{} to {}", part_name(output, 1).display(), part_name(output, n).display()),
    };
    bail!(
        "{} from an earlier job would be left beside this one ({writes}), and the control could run it as a part: \
         remove it, or give --overwrite-parts to have it removed",
        names.join(", ")
    )
}

/// Removes the parts an earlier job left (after the new ones are written).
pub fn remove_left_over(old: &[PathBuf]) -> Result<()> {
    for p in old {
        std::fs::remove_file(p)
            .with_context(|| format!("the new parts are written, but cannot remove {}", p.display()))?;
        crate::say::note!("removed {}, a part of an earlier job", p.display());
    }
    Ok(())
}
