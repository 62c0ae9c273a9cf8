//! Cutters a program names: read from its comments' words (`D=14`,
//! `ball:14`, `Ø14`, the tool lines CAM posts write), and what cutter the
//! program needs when it is scaled.

use super::Cutter;

/// A cutter a program names.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCutter {
    /// Diameter, in the program's units (mm unless it runs in inches).
    pub diameter: f64,
    /// The shape when known (`None`: a diameter alone), in the numbers the
    /// comment gives.
    pub shape: Option<Cutter>,
    /// Where it was named: `--tool ball:14`, `line 3`.
    pub source: String,
    /// The tool a CAM post's tool line describes: its number and form.
    pub tool: Option<CamTool>,
}

/// A tool line of a CAM post: Fusion 360 / HSM's `(T9 D=2.5 CR=0.
/// TAPER=118deg - ZMIN=-4.751 - drill)`, Mastercam's `( 1/16 FLAT ENDMILL
/// TOOL - 1 DIA. OFF. - 1 LEN. - 1 DIA. - .0625)`.
#[derive(Clone, Debug, PartialEq)]
pub struct CamTool {
    /// The tool number (`T9`, `TOOL - 9`).
    pub number: u32,
    /// The corner radius (`CR=`), in the program's units.
    pub corner: Option<f64>,
    /// The taper angle (`TAPER=118deg`), degrees: a drill's point angle, a
    /// chamfer mill's half angle.
    pub taper: Option<f64>,
    /// What the post calls it: `flat end mill`, `drill`, `1/16 FLAT ENDMILL`.
    pub kind: String,
    /// The length register (Mastercam's `LEN. - 1`).
    pub h: Option<u32>,
    /// The radius register (Mastercam's `DIA. OFF. - 1`).
    pub d: Option<u32>,
}

/// A tool the program's comments give: what the tool table takes from them.
#[derive(Clone, Debug, PartialEq)]
pub struct CommentTool {
    /// The tool number.
    pub number: u32,
    /// Its shape as a cutter SPEC in mm (`drill:2.5,118`), where the comment
    /// says enough; else why not.
    pub spec: Result<String, String>,
    /// What the post calls it.
    pub kind: String,
    /// The length and radius registers the comment gives.
    pub h: Option<u32>,
    /// See `h`.
    pub d: Option<u32>,
    /// The line of the comment.
    pub line: usize,
}

/// The cutters named in a G-code program's comments, given with their
/// lines (as `kezuri_nc::comments` gives them, the command line reads
/// them): a tool SPEC (`ball:14`), a CAM post's tool line ([`CamTool`]),
/// `D=14`, `DIA 14`, `DIA=14`, `DIAMETER 14`, `Ø14`, `φ14` or `⌀14` (an
/// `mm` after the number is allowed); the first form found in a comment
/// counts; a comment that says BALL makes a bare diameter a ball. Each
/// cutter once, where it is first named.
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

/// The tools the tool lines of a program's comments describe (CAM posts
/// list every tool in the header and again at each change), the first line
/// of each number: their shapes in mm, the comments' numbers taken as
/// inches where `inch` (a program in G20).
pub fn tools_in_comments<'a>(comments: impl IntoIterator<Item = (usize, &'a str)>, inch: bool) -> Vec<CommentTool> {
    let mm = |v: f64| if inch { (v * 25.4 * 1e6).round() / 1e6 } else { v };
    let mut out: Vec<CommentTool> = Vec::new();
    for (line, c) in comments {
        let Some(NamedCutter { diameter, shape, tool: Some(t), .. }) = cutter_in(c) else { continue };
        if out.iter().any(|o| o.number == t.number) {
            continue;
        }
        let spec = tool_spec(mm(diameter), shape, &t, mm);
        out.push(CommentTool { number: t.number, spec, kind: t.kind, h: t.h, d: t.d, line });
    }
    out
}

/// The SPEC of a CAM post's tool of `diameter` mm: its form from the
/// corner radius, the taper and what the post calls it.
fn tool_spec(diameter: f64, shape: Option<Cutter>, t: &CamTool, mm: impl Fn(f64) -> f64) -> Result<String, String> {
    let kind = t.kind.to_lowercase();
    let has = |words: &[&str]| words.iter().any(|w| kind.contains(w));
    let d = number(diameter);
    if let Some(taper) = t.taper {
        let a = number(taper);
        return if has(&["chamfer"]) {
            Ok(format!("v:{d},{}", number(2.0 * taper)))
        } else if has(&["spot", "center", "centre"]) {
            Ok(format!("v:{d},{a}"))
        } else if has(&["drill", "taladr", "bohr", "foret", "punta", "ドリル"]) {
            Ok(format!("drill:{d},{a}"))
        } else {
            Err(format!("a {} with a {a}° taper: kezuri has no such cutter", t.kind))
        };
    }
    let corner = t.corner.map(&mm).unwrap_or(0.0);
    if has(&["drill", "taladr", "bohr", "foret", "punta", "ドリル", "chamfer"]) {
        return Err(format!("a {} without its point angle (TAPER)", t.kind));
    }
    let ball = has(&["ball"]) || matches!(shape, Some(Cutter::Ball(_))) || (corner - diameter / 2.0).abs() < 1e-9;
    if ball {
        Ok(format!("ball:{d}"))
    } else if corner > 0.0 {
        Ok(format!("bull:{d},{}", number(corner)))
    } else if t.corner.is_some() || has(&["flat", "end mill", "endmill", "face mill"]) {
        Ok(format!("flat:{d}"))
    } else {
        Err(format!("what a {} is: the comment does not say", t.kind))
    }
}

/// A number for a SPEC: at most six decimals, no trailing zeros.
fn number(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The whole number after `word` and the separators `-`, `=`, `:` and
/// blanks in `upper` (an upper-case comment).
fn count_after(upper: &str, word: &str) -> Option<u32> {
    let at = upper.find(word)? + word.len();
    let rest = upper[at..].trim_start_matches([' ', '-', '=', ':', '\t']);
    let len = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
    rest[..len].parse().ok()
}

/// A CAM post's tool line, with its diameter: Fusion 360 / HSM's `T9
/// D=2.5 CR=0. TAPER=118deg - ZMIN=-4.751 - drill` (the tool number
/// first), Mastercam's `1/16 FLAT ENDMILL TOOL - 1 DIA. OFF. - 1 LEN. - 1
/// DIA. - .0625`.
fn cam_tool(comment: &str) -> Option<(f64, CamTool)> {
    let upper = comment.to_uppercase();
    let trimmed = upper.trim_start();
    // Fusion 360 / HSM: T<n>, then D=.
    if let Some(rest) = trimmed.strip_prefix('T') {
        let len = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
        let number: u32 = rest[..len].parse().ok().filter(|&n| n > 0)?;
        if !rest[len..].starts_with([' ', '\t']) {
            return None;
        }
        let value = |key: &str| -> Option<f64> {
            let mut from = 0;
            while let Some(at) = upper[from..].find(key).map(|p| p + from) {
                if at == 0 || upper[..at].ends_with([' ', '\t']) {
                    let s = &upper[at + key.len()..];
                    let len = s.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-')).unwrap_or(s.len());
                    return s[..len].parse::<f64>().ok().filter(|v| v.is_finite());
                }
                from = at + key.len();
            }
            None
        };
        let diameter = value("D=").filter(|&d| d > 0.0)?;
        let kind = comment.rsplit(" - ").next().filter(|_| comment.contains(" - ")).unwrap_or("").trim().to_string();
        let tool = CamTool {
            number,
            corner: value("CR=").filter(|&r| r >= 0.0),
            taper: value("TAPER=").filter(|&a| a > 0.0 && a < 180.0),
            kind,
            h: None,
            d: None,
        };
        return Some((diameter, tool));
    }
    // Mastercam: TOOL - n DIA. OFF. - d LEN. - h DIA. - diameter.
    let at = upper.find("TOOL -")?;
    let number = count_after(&upper[at..], "TOOL").filter(|&n| n > 0)?;
    let last = upper.rfind("DIA. -")?;
    let diameter = leading_number(upper[last + "DIA. -".len()..].trim_start())?;
    let tool = CamTool {
        number,
        corner: None,
        taper: None,
        kind: comment[..at].trim().to_string(),
        h: count_after(&upper[at..], "LEN."),
        d: count_after(&upper[at..], "DIA. OFF."),
    };
    Some((diameter, tool))
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
    if let Some((diameter, tool)) = cam_tool(comment) {
        let spec = tool_spec(diameter, None, &tool, |v| v).ok();
        let shape = spec.and_then(|s| s.parse::<Cutter>().ok());
        return Some(NamedCutter { diameter, shape, source: String::new(), tool: Some(tool) });
    }
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
                    return Some(NamedCutter {
                        diameter: 2.0 * c.radius(),
                        shape: Some(c),
                        source: String::new(),
                        tool: None,
                    });
                }
            }
            from = at + shape.len();
        }
    }
    let bare = |d: f64| {
        let shape = if ball { format!("ball:{d}").parse::<Cutter>().ok() } else { None };
        NamedCutter { diameter: d, shape, source: String::new(), tool: None }
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
        named.push(NamedCutter { diameter: 2.0 * c.radius(), shape: Some(c), source: "--tool".into(), tool: None });
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
    fn cam_posts_tool_lines_are_a_tool_table() {
        // Real tool lines: Fusion 360 / HSM (English, Spanish, a Makera
        // library's long name, a header's tools table), Mastercam in inches.
        let comments = [
            (3, "T1 D=6. CR=0. - ZMIN=-3. - flat end mill"),
            (4, "T2 D=6. CR=3. - ZMIN=-3. - ball end mill"),
            (5, "T3 D=10. CR=1. - ZMIN=-2. - bull nose end mill"),
            (6, "T9 D=2.5 CR=0. TAPER=118deg - ZMIN=-4.751 - taladrar"),
            (7, "T5  3*12mm Drill  Makera    D=3. SD=3. TD=0. FL=12. SL=12. BL=26. TAPER=118deg - ZMIN=-25.67 - drill"),
            (8, "T4 D=8. CR=0. TAPER=45deg - ZMIN=-1. - chamfer mill"),
            (9, "T6 D=6. CR=0. TAPER=90deg - ZMIN=-1. - spot drill"),
            (10, "T7 D=6. CR=0. TAPER=5deg - ZMIN=-1. - tapered mill"),
            (11, "  T1 D=3.175 CR=0 TAPER=118deg - ZMIN=-13.392 - drill "),
            (12, "T1 - 90-DEG SPOT DRILL"),
        ];
        let tools = tools_in_comments(comments, false);
        let specs: Vec<(u32, Result<&str, ()>, usize)> =
            tools.iter().map(|t| (t.number, t.spec.as_deref().map_err(|_| ()), t.line)).collect();
        assert_eq!(
            specs,
            [
                (1, Ok("flat:6"), 3),
                (2, Ok("ball:6"), 4),
                (3, Ok("bull:10,1"), 5),
                (9, Ok("drill:2.5,118"), 6),
                (5, Ok("drill:3,118"), 7),
                (4, Ok("v:8,90"), 8),
                (6, Ok("v:6,90"), 9),
                (7, Err(()), 10),
            ]
        );
        assert_eq!(tools[3].kind, "taladrar");
        let inch = tools_in_comments([(5, " 1/16 FLAT ENDMILL TOOL - 1 DIA. OFF. - 21 LEN. - 11 DIA. - .0625")], true);
        assert_eq!(inch.len(), 1);
        let t = &inch[0];
        assert_eq!((t.number, t.spec.as_deref(), t.h, t.d), (1, Ok("flat:1.5875"), Some(11), Some(21)));
        assert_eq!(t.kind, "1/16 FLAT ENDMILL");
        // A tool line is a cutter of the scaling warnings too.
        let named = in_comments([(1, "T2 D=6. CR=3. - ZMIN=-3. - ball end mill")]);
        assert_eq!(named[0].shape, Some("ball:6".parse().unwrap()));
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
