//! Tool tables as `kezuri tool table` shows them: a table of text per
//! file, or one JSON object.

use serde_json::json;

use super::Table;
use crate::machine::ToolEntry;

/// One table to show: where it came from and what it holds.
pub struct Shown {
    /// The file it was read from, as the user named it.
    pub file: String,
    /// What the file gave.
    pub table: Table,
}

/// A tool's register values: (length, radius), mm.
fn values(t: &Table, e: &ToolEntry) -> (Option<f64>, Option<f64>) {
    (t.lengths.get(&e.h).copied(), e.d.and_then(|d| t.radii.get(&d)).copied())
}

/// The tables as one JSON object: `tables`, each with file, format, tools
/// (number, shape, h, d, length_mm, radius_mm, name, and a turning tool's
/// nose_radius_mm and tip), skipped and warnings.
pub fn json(shown: &[Shown]) -> String {
    let tables: Vec<_> = shown
        .iter()
        .map(|s| {
            let tools: Vec<_> = s
                .table
                .tools
                .iter()
                .map(|(n, e)| {
                    let (length, radius) = values(&s.table, e);
                    json!({"number": n, "shape": e.shape.map(|c| c.to_string()), "h": e.h, "d": e.d,
                           "length_mm": length, "radius_mm": radius, "name": e.name,
                           "nose_radius_mm": e.nose.map(|n| n.radius), "tip": e.nose.map(|n| n.tip)})
                })
                .collect();
            json!({"file": s.file, "format": s.table.format, "tools": tools,
                   "skipped": s.table.notes.skipped, "warnings": s.table.notes.warnings})
        })
        .collect();
    format!("{}\n", json!({ "tables": tables }))
}

/// The tables as text, a blank line between them: a line naming the file,
/// a column a value, then what was skipped and the warnings.
pub fn text(shown: &[Shown]) -> String {
    shown.iter().map(table_text).collect::<Vec<_>>().join("\n")
}

fn table_text(s: &Shown) -> String {
    let t = &s.table;
    let mut rows = vec![["tool", "shape", "H", "D", "length mm", "radius mm", "name"].map(String::from)];
    let or_dash = |v: Option<String>| v.unwrap_or_else(|| "-".into());
    for (n, e) in &t.tools {
        let (length, radius) = values(t, e);
        rows.push([
            format!("T{n}"),
            or_dash(e.shape.map(|c| c.to_string())),
            e.h.to_string(),
            or_dash(e.d.map(|d| d.to_string())),
            or_dash(length.map(|v| v.to_string())),
            or_dash(radius.map(|v| v.to_string())),
            e.name.clone().unwrap_or_default(),
        ]);
    }
    // A turning tool's nose, after its name.
    for (r, e) in rows[1..].iter_mut().zip(t.tools.values()) {
        if let Some(n) = e.nose {
            r[6] = format!("{}{}nose {} mm, tip {}", r[6], if r[6].is_empty() { "" } else { "; " }, n.radius, n.tip);
        }
    }
    let widths: Vec<usize> = (0..7).map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0)).collect();
    let n = t.tools.len();
    let bare = t.tools.values().filter(|e| e.shape.is_none()).count();
    let mut out =
        format!("{} ({}): {n} tool{}, {bare} without a shape\n", s.file, t.format, if n == 1 { "" } else { "s" });
    for r in &rows {
        let cells: Vec<String> = r.iter().zip(&widths).map(|(c, w)| format!("{c:<w$}")).collect();
        out += &format!("  {}\n", cells.join("  ").trim_end());
    }
    for (title, list) in [("skipped", &t.notes.skipped), ("warnings", &t.notes.warnings)] {
        if !list.is_empty() {
            out += &format!("{title}:\n");
            for line in list {
                out += &format!("  {line}\n");
            }
        }
    }
    out
}
