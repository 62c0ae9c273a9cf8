//! CSV tables with a header line, read by column name (the measurement
//! files of thermal and tool): every error names the line and column.

use anyhow::{anyhow, bail, Result};

/// A table: its column names and rows.
pub struct Table {
    file: String,
    header: String,
    names: Vec<String>,
    rows: Vec<Row>,
}

/// A row: its line (1-based) and its fields with the column (in
/// characters, from 1) each starts at.
struct Row {
    line: usize,
    fields: Vec<(usize, String)>,
}

impl Table {
    /// The table in `text` (its first line, after blank lines and `#`
    /// comments, names the columns); `file` names it in errors.
    pub fn parse(file: &str, text: &str) -> Result<Table> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines =
            text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let Some((_, header)) = lines.next() else { bail!("{file}: empty: expected a header line") };
        let names = header.split(',').map(|c| c.trim().to_ascii_lowercase()).collect();
        let rows = lines
            .map(|(k, line)| {
                let mut column = 1;
                let fields = line
                    .split(',')
                    .map(|f| {
                        let at = column;
                        column += f.chars().count() + 1;
                        (at, f.trim().to_string())
                    })
                    .collect();
                Row { line: k + 1, fields }
            })
            .collect();
        Ok(Table { file: file.to_string(), header: header.trim().to_string(), names, rows })
    }

    /// Rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// The index of column `name`, if the header has it.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|c| c == name)
    }

    /// The index of column `name`, or an error naming what the header has.
    pub fn require(&self, name: &str, expected: &str) -> Result<usize> {
        self.column(name).ok_or_else(|| {
            anyhow!("{}: line 1: no column '{name}' in the header '{}' (expected {expected})", self.file, self.header)
        })
    }

    /// The text of row `r`, column `c`.
    pub fn text(&self, r: usize, c: usize) -> Result<&str> {
        let row = &self.rows[r];
        match row.fields.get(c) {
            Some((_, f)) => Ok(f),
            None => bail!(
                "{}: line {}: no value for '{}' (column {} of the header)",
                self.file,
                row.line,
                self.names[c],
                c + 1
            ),
        }
    }

    /// The finite number in row `r`, column `c`.
    /// A column in mm (its name ends `_mm`) holds coordinates within
    /// ±1000000 mm (`kezuri_geom::limits`).
    pub fn number(&self, r: usize, c: usize) -> Result<f64> {
        let text = self.text(r, c)?;
        let name = &self.names[c];
        match text.parse::<f64>() {
            Ok(v) if name.ends_with("_mm") => {
                kezuri_geom::limits::coordinate(v, &format!("'{text}' ({name})")).map_err(|e| self.error_at(r, c, &e))
            }
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error_at(r, c, &format!("'{text}' is not a number ({name})"))),
        }
    }

    /// An error at row `r`, column `c`.
    pub fn error_at(&self, r: usize, c: usize, message: &str) -> anyhow::Error {
        let row = &self.rows[r];
        let column = row.fields.get(c).map_or(1, |f| f.0);
        anyhow!("{}: line {}, column {column}: {message}", self.file, row.line)
    }
}

/// The rows of the table in `text`, each the numbers of the columns
/// `names` asks for, in that order.
pub fn read_columns(file: &str, text: &str, names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let t = Table::parse(file, text)?;
    let at: Vec<usize> = names.iter().map(|n| t.require(n, &names.join(","))).collect::<Result<_>>()?;
    (0..t.len()).map(|r| at.iter().map(|&c| t.number(r, c)).collect()).collect()
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
        let e = read_columns("p.csv", "x_mm,z_mm\n1,2\n3,1e307\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert_eq!(
            e,
            "p.csv: line 3, column 3: '1e307' (z_mm) must be a coordinate from -1000000 to 1000000 mm, got 1e307"
        );
        let e = read_columns("p.csv", "x,z\n1,2\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 1: no column 'x_mm'"), "{e}");
        let e = read_columns("p.csv", "x_mm,z_mm\n1\n", &["x_mm", "z_mm"]).unwrap_err().to_string();
        assert!(e.starts_with("p.csv: line 2: no value for 'z_mm'"), "{e}");
    }
}
