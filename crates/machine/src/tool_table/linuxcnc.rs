//! LinuxCNC's tool table (`tool.tbl`), read as LinuxCNC 2.9 reads it
//! (`tooldata_read_entry`): one tool a line, words separated by spaces,
//! letters in either case; `;` starts the comment (the tool's name); a
//! line starting with `;` or blank is skipped. Words: T tool, P pocket,
//! X Y Z A B C U V W offsets, D diameter, I J front and back angle, Q
//! orientation (lathe). Numbers in the machine's units, which the file
//! does not say. A word LinuxCNC does not know, or a bad number, is an
//! error here (LinuxCNC skips such a line with a message, losing the tool).
//!
//! A lathe tool's line (an orientation Q 1–9) gives its nose: the radius is
//! half of D (LinuxCNC's tool nose diameter), the tip direction Q turned
//! into Fanuc's numbering (`TipNumbers::LinuxCnc`: the same corner of the
//! nose, numbered with X mirrored; Q2, the outside turning tool, is tip 3).

/// The start of the note a tool.tbl leaves: the machine file that imports
/// it names the tools its own entries leave without a shape instead.
pub(crate) const NO_SHAPES: &str = "a tool.tbl gives diameters, not shapes";

use std::path::Path;

use super::{Table, Units};
use crate::error::{fail, Result};
use crate::files::{read_text, Files};
use crate::machine::ToolEntry;
use kezuri_nc::interp::{Nose, TipNumbers};

/// Reads a `tool.tbl`.
pub fn read(path: &Path, units: Units, files: &dyn Files) -> Result<Table> {
    parse(&path.display().to_string(), &read_text(files, path)?, units)
}

/// One line's words, by letter.
#[derive(Default)]
struct Words {
    tool: Option<i64>,
    diameter: Option<f64>,
    z: Option<f64>,
    /// The lathe tool's orientation (Q), 0–9.
    orientation: Option<u8>,
    /// A lathe's X or a rotary offset, or a front or back angle, not zero.
    unused: bool,
}

fn parse(name: &str, text: &str, units: Units) -> Result<Table> {
    let mut table = Table::new("LinuxCNC tool table");
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let words_part = line.split(';').next().unwrap_or("");
        if line.starts_with(';') || words_part.trim().is_empty() {
            continue;
        }
        let w = words(name, n, line, words_part)?;
        let Some(t) = w.tool else { fail!(Syntax, "{name}:{n}: no tool number (T) on the line") };
        if t == 0 {
            table.notes.skipped.push(format!("line {n}: T0 is no tool (the empty spindle)"));
            continue;
        }
        let Ok(number) = u32::try_from(t) else { fail!(Invalid, "{name}:{n}: T{t} is not a tool number") };
        let comment = line.split_once(';').map(|(_, c)| c.trim()).filter(|c| !c.is_empty());
        // A lathe tool's nose: its orientation, and half its D.
        let nose = match (w.orientation, w.diameter) {
            (None | Some(0), _) => None,
            (Some(q), Some(d)) => Some(Nose { radius: units.mm(d) / 2.0, tip: TipNumbers::LinuxCnc.fanuc_tip(q) }),
            (Some(q), None) => {
                table.notes.warnings.push(format!(
                    "line {n}: T{number}: orientation Q{q} with no diameter D: no nose (add D, the nose diameter)"
                ));
                None
            }
        };
        let entry = ToolEntry { shape: None, h: number, d: Some(number), name: comment.map(String::from), nose };
        if table.add(number, entry, &format!("line {n}")) {
            if let Some(z) = w.z {
                table.lengths.insert(number, units.mm(z));
            }
            if let Some(d) = w.diameter {
                table.radii.insert(number, units.mm(d) / 2.0);
            }
            if w.unused {
                table.notes.warnings.push(format!(
                    "line {n}: T{number}: its X, Y or rotary offsets and front and back angles (I J) are not used"
                ));
            }
        }
    }
    if !table.tools.is_empty() {
        table.notes.warnings.push(format!(
            "{NO_SHAPES}: a tool's shape is written in the machine file ([tools.T1] shape = \"flat:6\")"
        ));
    }
    Ok(table)
}

/// The words of a line (before its comment).
fn words(name: &str, n: usize, line: &str, part: &str) -> Result<Words> {
    let mut w = Words::default();
    for token in part.split_whitespace() {
        let col = token.as_ptr() as usize - line.as_ptr() as usize + 1;
        let at = format!("{name}:{n}:{col}");
        let letter = token.chars().next().unwrap_or(' ').to_ascii_uppercase();
        let value = &token[letter.len_utf8()..];
        let first = token.as_ptr() == part.trim_start().as_ptr();
        if first && (token.bytes().all(|b| b.is_ascii_digit()) || ["TOOLNO", "POC"].contains(&&*token.to_uppercase())) {
            fail!(
                UnknownFormat,
                "{at}: this is the tool table of LinuxCNC before 2.4 (columns TOOLNO POCKET LENGTH \
                 DIAMETER), which LinuxCNC no longer reads: write it as T1 P1 Z0.511 D0.125 ;name"
            );
        }
        let number = || -> Result<f64> {
            match value.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => fail!(Syntax, "{at}: '{token}': {letter} takes a number"),
            }
        };
        // LinuxCNC reads these with %d: Q2.0 is 2 (and T1.5 would be T1, refused here).
        let whole = || -> Result<i64> {
            match value.parse::<f64>() {
                Ok(v) if v.fract() == 0.0 && v.abs() < 1e15 => Ok(v as i64),
                _ => fail!(Syntax, "{at}: '{token}': {letter} takes a whole number"),
            }
        };
        match letter {
            'T' => w.tool = Some(whole()?),
            'P' => {
                whole()?;
            }
            'Q' => match whole()? {
                q @ 0..=9 => w.orientation = Some(q as u8),
                _ => fail!(Invalid, "{at}: '{token}': a lathe tool's orientation Q is 0 to 9"),
            },
            'D' => {
                let d = number()?;
                if d < 0.0 {
                    fail!(Invalid, "{at}: '{token}': a diameter cannot be negative");
                }
                w.diameter = Some(d);
            }
            'Z' => w.z = Some(number()?),
            'X' | 'Y' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' | 'I' | 'J' => w.unused |= number()? != 0.0,
            _ => fail!(
                Syntax,
                "{at}: '{token}' is not a tool table word (T P X Y Z A B C U V W D I J Q; a comment starts with ;)"
            ),
        }
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_tools_lengths_and_diameters() {
        let text = "; my mill\nT1 P1 Z0.511 D0.125 ;1/8 end mill\n\nt2 p4 z+0.1 d0.0625 Q0.0\nT0 P0 ;empty\n\
                    T1 P7 D1 ;again\nT3 P3 X0.5 D0.2 Q6\n";
        let t = parse("a.tbl", text, Units::Inch).unwrap();
        assert_eq!(t.tools.len(), 3);
        let t1 = &t.tools[&1];
        assert_eq!((t1.shape, t1.h, t1.d, t1.name.as_deref()), (None, 1, Some(1), Some("1/8 end mill")));
        assert_eq!((t.lengths[&1], t.radii[&1]), (12.9794, 1.5875));
        assert_eq!((t.lengths[&2], t.radii[&2], t.tools[&2].name.as_deref()), (2.54, 0.79375, None));
        assert!(!t.lengths.contains_key(&3));
        assert!(t.notes.skipped[0].contains("line 5: T0"), "{:?}", t.notes.skipped);
        assert!(t.notes.skipped[1].contains("line 6: T1 again"));
        assert!(t.notes.warnings[0].contains("line 7: T3"), "{:?}", t.notes.warnings);
        assert!(t.notes.warnings[1].contains("not shapes"));
        let mm = parse("a.tbl", "T5 Z-10 D6", Units::Mm).unwrap();
        assert_eq!((mm.lengths[&5], mm.radii[&5]), (-10.0, 3.0));
    }

    #[test]
    fn bad_lines_say_where() {
        for (text, words) in [
            ("T1 P1 D0.1\nT2 P2 Dx ;bad", "a.tbl:2:7: 'Dx': D takes a number"),
            ("T1 P1 R3", "a.tbl:1:7: 'R3' is not a tool table word"),
            ("T1.5 P1", "a.tbl:1:1: 'T1.5': T takes a whole number"),
            ("P1 D3 ;no T", "a.tbl:1: no tool number"),
            ("T-2 P1", "a.tbl:1: T-2 is not a tool number"),
            ("T1 D-3", "a.tbl:1:4: 'D-3': a diameter cannot be negative"),
            (
                "TOOLNO POCKET\n     1      1    +0.511000    0.125000  1/8 end mill",
                "a.tbl:1:1: this is the tool table",
            ),
            (
                "     1      1    +0.511000    0.125000  1/8 end mill",
                "a.tbl:1:6: this is the tool table of LinuxCNC before 2.4",
            ),
        ] {
            let e = parse("a.tbl", text, Units::Mm).expect_err(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
