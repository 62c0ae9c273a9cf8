//! CSV tables with a header line, read by column name (the measurement
//! files of ../shared/CLI.md): every error names the line and column.

use anyhow::{bail, Result};

/// The rows of `text` (a CSV table whose first line, after blank lines and
/// `#` comments, names its columns), each the numbers of the columns
/// `names` asks for, in that order. `file` names the file in errors.
pub fn read_columns(file: &str, text: &str, names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else { bail!("{file}: empty: expected a header line {}", names.join(",")) };
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_ascii_lowercase()).collect();
    let at: Vec<usize> = names
        .iter()
        .map(|name| {
            columns.iter().position(|c| c == name).ok_or_else(|| {
                anyhow::anyhow!(
                    "{file}: line 1: no column '{name}' in the header '{}' (expected {})",
                    header.trim(),
                    names.join(",")
                )
            })
        })
        .collect::<Result<_>>()?;
    let mut rows = Vec::new();
    for (k, line) in lines {
        let fields: Vec<(usize, &str)> = field_columns(line);
        let mut row = Vec::with_capacity(at.len());
        for (&c, name) in at.iter().zip(names) {
            let Some(&(column, field)) = fields.get(c) else {
                bail!("{file}: line {}: no value for '{name}' (column {} of the header)", k + 1, c + 1)
            };
            match field.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => row.push(v),
                _ => bail!("{file}: line {}, column {column}: '{}' is not a number ({name})", k + 1, field.trim()),
            }
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The comma-separated fields of `line` with the column (in characters,
/// from 1) each starts at.
fn field_columns(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut column = 1;
    for field in line.split(',') {
        out.push((column, field));
        column += field.chars().count() + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_by_name_and_errors_with_their_place() {
        let t = "# a profile\nz_mm, x_mm\n1,2\n3, 4\n";
        assert_eq!(read_columns("p.csv", t, &["x_mm", "z_mm"]).unwrap(), vec![vec![2.0, 1.0], vec![4.0, 3.0]]);
        let e = read_columns("p.csv", "x_mm,z_mm\n1,2\n3,abc\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert_eq!(e, "p.csv: line 3, column 3: 'abc' is not a number (z_mm)");
        let e = read_columns("p.csv", "x,z\n1,2\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 1: no column 'x_mm'"), "{e}");
        let e = read_columns("p.csv", "x_mm,z_mm\n1\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 2: no value for 'z_mm'"), "{e}");
    }
}
