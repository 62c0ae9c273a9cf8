//! Cutters a program names: read from its comments' words (`D=14`,
//! `ball:14`, `Ø14`), and what cutter the program needs when it is scaled.

use super::Cutter;

/// A cutter a program names.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCutter {
    /// Diameter, mm.
    pub diameter: f64,
    /// The shape when known (`None`: a diameter alone).
    pub shape: Option<Cutter>,
    /// Where it was named: `--tool ball:14`, `line 3`.
    pub source: String,
}

/// The cutters named in a G-code program's comments, given with their
/// lines (as `kezuri_nc::comments` gives them, the command line reads
/// them): a tool SPEC (`ball:14`), `D=14`, `DIA 14`, `DIA=14`,
/// `DIAMETER 14`, `Ø14`, `φ14` or `⌀14` (an `mm` after the number is
/// allowed); the first form found in a comment counts; a comment that says
/// BALL makes a bare diameter a ball. Each cutter once, where it is first
/// named.
pub fn in_comments<'a>(comments: impl IntoIterator<Item = (usize, &'a str)>) -> Vec<NamedCutter> {
    let mut out: Vec<NamedCutter> = Vec::new();
    for (line, c) in comments {
        if let Some(found) = cutter_in(c) {
            let named = NamedCutter { source: format!("line {line}"), ..found };
            if !out.iter().any(|o| o.diameter == named.diameter && o.shape == named.shape) {
                out.push(named);
            }
        }
    }
    out
}

/// The number at the start of `s` (after blanks, `=` or `:`).
fn leading_number(s: &str) -> Option<f64> {
    let s = s.trim_start_matches([' ', '=', ':', '\t']);
    let len = s.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(s.len());
    s[..len].parse::<f64>().ok().filter(|d| d.is_finite() && *d > 0.0 && *d < 1000.0)
}

/// The cutter comment `comment` names, if any.
fn cutter_in(comment: &str) -> Option<NamedCutter> {
    let upper = comment.to_uppercase();
    let ball = upper.contains("BALL");
    // A SPEC: SHAPE:NUMBERS.
    for shape in ["FLAT:", "BALL:", "BULL:", "OVAL:", "V:", "DRILL:"] {
        let mut from = 0;
        while let Some(at) = upper[from..].find(shape).map(|p| p + from) {
            let word_start = at == 0 || !upper[..at].chars().next_back().is_some_and(char::is_alphanumeric);
            let numbers = &comment[at + shape.len()..];
            let len = numbers.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == ',')).unwrap_or(numbers.len());
            let spec = format!("{}{}", shape.to_lowercase(), numbers[..len].trim_end_matches(','));
            if word_start {
                if let Ok(c) = spec.parse::<Cutter>() {
                    return Some(NamedCutter { diameter: 2.0 * c.radius(), shape: Some(c), source: String::new() });
                }
            }
            from = at + shape.len();
        }
    }
    let bare = |d: f64| {
        let shape = if ball { format!("ball:{d}").parse::<Cutter>().ok() } else { None };
        NamedCutter { diameter: d, shape, source: String::new() }
    };
    for sign in ['Ø', 'ø', 'φ', 'Φ', '⌀'] {
        if let Some(at) = comment.find(sign) {
            if let Some(d) = leading_number(&comment[at + sign.len_utf8()..]) {
                return Some(bare(d));
            }
        }
    }
    for word in ["DIAMETER", "DIA", "D"] {
        let mut from = 0;
        while let Some(at) = upper[from..].find(word).map(|p| p + from) {
            let before = upper[..at].chars().next_back();
            let after = &upper[at + word.len()..];
            let word_start = !before.is_some_and(char::is_alphanumeric);
            let separated = if word == "D" { after.starts_with('=') } else { after.starts_with([' ', '=', ':', '.']) };
            if word_start && separated {
                if let Some(d) = leading_number(after.trim_start_matches('.')) {
                    return Some(bare(d));
                }
            }
            from = at + word.len();
        }
    }
    None
}

/// Millimetres for a message: at most three decimals, no trailing zeros.
fn mm(v: f64) -> String {
    let s = format!("{:.3}", v);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The warnings and notes of what cutter a program needs, scaled by `k` in
/// X/Y and `s` in Z, for the cutter `tool` it was made for and those its
/// `comments` name ([`in_comments`]): one line each, `warning: …` or
/// `note: …`.
pub fn cutter_warnings(tool: Option<Cutter>, comments: &[NamedCutter], k: f64, s: f64) -> Vec<String> {
    let mut named: Vec<NamedCutter> = Vec::new();
    if let Some(c) = tool {
        named.push(NamedCutter { diameter: 2.0 * c.radius(), shape: Some(c), source: "--tool".into() });
    }
    named.extend(comments.iter().cloned());
    if named.is_empty() {
        return vec![format!(
            "note: the program names no cutter (--tool SPEC, or a comment such as (D=14)): scaled by {} in X/Y, \
             it needs a cutter {} times the diameter it was made for",
            mm(k),
            mm(k)
        )];
    }
    let mut out = Vec::new();
    for c in named {
        let needed = c.diameter * k;
        let made_for = match c.shape {
            Some(shape) => shape.to_string(),
            None => format!("φ{}", mm(c.diameter)),
        };
        if (needed - needed.round()).abs() > 1e-6 {
            let (lo, hi) = (needed.floor(), needed.ceil());
            let nearest = if lo >= 1.0 { format!("φ{} and φ{}", mm(lo), mm(hi)) } else { format!("φ{}", mm(hi)) };
            out.push(format!(
                "warning: scaled by {} in X/Y, the program made for a {made_for} cutter ({}) needs a φ{} mm cutter, \
                 which is not a standard whole-millimetre diameter (nearest: {nearest})",
                mm(k),
                c.source,
                mm(needed)
            ));
        } else {
            out.push(format!(
                "note: scaled by {} in X/Y, the program made for a {made_for} cutter ({}) needs a φ{} mm cutter",
                mm(k),
                c.source,
                mm(needed)
            ));
        }
        let shaped = c.shape.is_some_and(|shape| !matches!(shape, Cutter::Flat(_)));
        if shaped && k != s {
            out.push(format!(
                "warning: scaled by {} in X/Y and {} in Z, the {made_for} cutter's tip is stretched: no cutter of \
                 that shape cuts the scaled program's surface exactly",
                mm(k),
                mm(s)
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cutters_named_in_comments() {
        let comments = [
            (1, "T1 D=6. CR=0. - FLAT END MILL"),
            (2, " ball:14 for the relief"),
            (3, "DIA 8MM"),
            (4, "TOOL Ø3 BALL"),
            (5, "ID=5"),
            (5, "DIAMETER: 12.5"),
            (6, "HEIGHT 10"),
            (7, "φ14"),
        ];
        let found: Vec<(f64, bool, String)> = in_comments(comments)
            .into_iter()
            .map(|c| (c.diameter, matches!(c.shape, Some(Cutter::Ball(_))), c.source))
            .collect();
        let want = [
            (6.0, false, "line 1"),
            (14.0, true, "line 2"),
            (8.0, false, "line 3"),
            (3.0, true, "line 4"),
            (12.5, false, "line 5"),
            (14.0, false, "line 7"),
        ];
        let want: Vec<(f64, bool, String)> = want.iter().map(|(d, b, s)| (*d, *b, s.to_string())).collect();
        assert_eq!(found, want);
    }

    #[test]
    fn the_paper_warning() {
        let ball: Cutter = "ball:14".parse().unwrap();
        let w = cutter_warnings(Some(ball), &[], 1.3, 1.3);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("warning:") && w[0].contains("needs a φ18.2 mm cutter") && w[0].contains("φ18 and φ19")
        );
        let w = cutter_warnings(Some(ball), &[], 1.5, 1.0);
        assert!(w[0].starts_with("note:") && w[0].contains("φ21 mm"), "{w:?}");
        assert!(w[1].contains("stretched"));
        let flat: Cutter = "flat:3".parse().unwrap();
        assert_eq!(cutter_warnings(Some(flat), &[], 2.0, 0.5).len(), 1);
        assert!(cutter_warnings(None, &[], 2.0, 1.0)[0].starts_with("note: the program names no cutter"));
    }
}
