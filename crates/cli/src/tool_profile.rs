//! A tool's measured cutting profile as CSV: `z_mm,radius_mm` (and
//! `wear_mm`), as `kezuri tool profile` writes it and `tool db`, `wear`,
//! `sim` and the demo read it.

use std::path::Path;

use anyhow::{anyhow, Result};
use kezuri_geom::ToolProfile;

use crate::files::read_text;
use crate::table::Table;

/// The profile CSV in `text` (`file` names it in errors): columns
/// `z_mm,radius_mm` (others, such as `wear_mm`, ignored).
pub fn parse_profile(file: &str, text: &str) -> Result<ToolProfile> {
    let t = Table::parse(file, text)?;
    let (zc, rc) = (t.require("z_mm", "z_mm,radius_mm")?, t.require("radius_mm", "z_mm,radius_mm")?);
    let mut z = Vec::with_capacity(t.len());
    let mut radius = Vec::with_capacity(t.len());
    for r in 0..t.len() {
        z.push(t.number(r, zc)?);
        radius.push(t.number(r, rc)?);
    }
    ToolProfile::new(z, radius).map_err(|e| match e.sample {
        Some(i) => t.error_at(i, zc, &e.message),
        None => anyhow!("{file}: {}", e.message),
    })
}

/// The profile CSV at `path`.
pub fn read_profile(path: &Path) -> Result<ToolProfile> {
    parse_profile(&path.display().to_string(), &read_text(path)?)
}

/// The profile as CSV text, with a `wear_mm` column when `wear` is given
/// (one value per sample).
pub fn profile_csv(profile: &ToolProfile, wear: Option<&[f64]>) -> String {
    let mut out = String::from(if wear.is_some() { "z_mm,radius_mm,wear_mm\n" } else { "z_mm,radius_mm\n" });
    for (i, (z, r)) in profile.z().iter().zip(profile.radius()).enumerate() {
        match wear {
            Some(w) => out.push_str(&format!("{z:.5},{r:.5},{:.5}\n", w[i])),
            None => out.push_str(&format!("{z:.5},{r:.5}\n")),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_csv_round_trip_and_errors_with_their_place() {
        let p = ToolProfile::new(vec![0.0, 0.00071, 0.00142], vec![0.0, 0.03, 0.04]).unwrap();
        let text = profile_csv(&p, None);
        assert_eq!(parse_profile("p.csv", &text).unwrap(), p);
        let e = parse_profile("p.csv", "z_mm,radius_mm\n0,0\n0,0.1\n").unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 3, column 1: z 0 is not above"), "{e}");
        let e = parse_profile("p.csv", "z_mm,radius_mm\n0,0\n1,-0.1\n").unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 3, column 1: negative radius"), "{e}");
        let e = parse_profile("p.csv", "z_mm,radius_mm\n0,0\n").unwrap_err().to_string();
        assert!(e.contains("at least two"), "{e}");
    }
}
