//! Which dialect a program is written in, when nobody says: one rule from
//! the file's extension and its content, the same for every command.
//!
//! The rule (docs/linuxcnc.md, "Choosing the dialect"):
//! 1. The evidence: the extension (`.ngc` says linuxcnc, `.gcode` and `.gc`
//!    say grbl; `.nc`, `.tap` and the rest say nothing) and the first
//!    *marker* of each dialect in the text — a construct that dialect has
//!    and the others refuse or read differently (`o100 sub`, `#<name>`,
//!    `G64 P` for LinuxCNC; an `O1234` program-number line, `G65`, `GOTO`,
//!    `IF […]`, `WHILE […] DO1` for Fanuc; `G154`, `G187` for Haas; `$H`,
//!    `$J=` for GRBL). Markers are looked for outside comments only: a
//!    Fanuc program may well say `(PRINT, SETUP SHEET)`, and LinuxCNC's
//!    comment commands (`(debug,` …) would turn it to whole millimetres.
//! 2. Evidence for both families — Fanuc or Haas on one side, LinuxCNC or
//!    GRBL (the extension included) on the other — is refused: the reader
//!    must say `--dialect`.
//! 3. Otherwise, first that applies: a Haas marker (haas), a Fanuc marker
//!    (fanuc), a LinuxCNC marker (linuxcnc), `.ngc` (linuxcnc), `.gcode` or
//!    `.gc` (grbl), a GRBL marker (grbl), the control a CAM system's header
//!    comment names (`(  vendor: Haas Automation)`, `(MACHINE: HAAS VF2)`,
//!    `( Posts processor: grbl.cps)`: [`cam_header`]), else fanuc, the
//!    default.

use std::fmt;
use std::ops::Range;

use crate::source::FORGET_EVERY;
use crate::Dialect;

/// A dialect found, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Detected {
    /// The dialect.
    pub dialect: Dialect,
    /// Why: `the extension .ngc`, `O1234 on line 1`, `given with --dialect`, `the
    /// default (no extension or marker of another dialect)`.
    pub reason: String,
}

impl fmt::Display for Detected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "dialect {}: {}", self.dialect, self.reason)
    }
}

/// A construct only one dialect has, where it was found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Marker {
    /// The dialect it belongs to.
    pub dialect: Dialect,
    /// The construct as written (trimmed): `o100 sub`, `G65`.
    pub text: String,
    /// 1-based line.
    pub line: u32,
}

impl fmt::Display for Marker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} on line {}", self.text, self.line)
    }
}

/// The dialect a file's name says by its extension: `.ngc` LinuxCNC,
/// `.gcode` and `.gc` GRBL; `None` for any other (`.nc`, `.tap`, …: the
/// content decides).
pub fn by_extension(name: &str) -> Option<Dialect> {
    match extension(name).as_str() {
        "ngc" => Some(Dialect::LinuxCnc),
        "gcode" | "gc" => Some(Dialect::Grbl),
        _ => None,
    }
}

/// The dialect `given` (`--dialect`), else the one the rule of this module
/// finds for a file named `name` (its extension counts; `-` or `<stdin>`
/// has none) holding `text`. `Err` is the refusal of a file with both
/// families' evidence, naming one piece of each.
pub fn detect(given: Option<Dialect>, name: &str, text: &str) -> Result<Detected, String> {
    detect_forgetting(given, name, text, &|_| {})
}

/// [`detect`], telling `forget` of each stretch of the text it has read
/// through (to let go of a mapped file's pages as it goes).
pub fn detect_forgetting(
    given: Option<Dialect>,
    name: &str,
    text: &str,
    forget: &dyn Fn(Range<usize>),
) -> Result<Detected, String> {
    if let Some(dialect) = given {
        return Ok(Detected { dialect, reason: "given with --dialect".to_string() });
    }
    let ext = extension(name);
    let by_extension = by_extension(name);
    let found = markers_forgetting(text, forget);
    let first = |d: Dialect| found.iter().find(|m| m.dialect == d);
    let fanuc_side = first(Dialect::Haas).or_else(|| first(Dialect::Fanuc));
    let fanuc_side = match (first(Dialect::Haas), first(Dialect::Fanuc)) {
        (Some(h), Some(f)) if f.line < h.line => Some(f),
        _ => fanuc_side,
    };
    let units_side = first(Dialect::LinuxCnc).or_else(|| first(Dialect::Grbl));
    if let Some(f) = fanuc_side {
        if let Some(u) = units_side {
            return Err(format!(
                "{f} is {}'s and {u} is {}'s: the program mixes dialects, so give --dialect fanuc|haas|linuxcnc|grbl",
                f.dialect, u.dialect
            ));
        }
        if let Some(d) = by_extension {
            return Err(format!(
                "the extension .{ext} says {d} but {f} is {}'s: give --dialect fanuc|haas|linuxcnc|grbl",
                f.dialect
            ));
        }
    }
    let from = |m: &Marker| Detected { dialect: m.dialect, reason: m.to_string() };
    if let Some(h) = first(Dialect::Haas) {
        return Ok(from(h));
    }
    if let Some(f) = first(Dialect::Fanuc) {
        // A Haas is a Fanuc-family control: a CAM header naming it says which.
        if let Some(h) = cam_header(text).filter(|h| h.dialect == Dialect::Haas) {
            return Ok(Detected { dialect: Dialect::Haas, reason: format!("{f} and {h}") });
        }
        return Ok(from(f));
    }
    if let Some(l) = first(Dialect::LinuxCnc) {
        return Ok(from(l));
    }
    if let Some(d) = by_extension {
        return Ok(Detected { dialect: d, reason: format!("the extension .{ext}") });
    }
    if let Some(g) = first(Dialect::Grbl) {
        return Ok(from(g));
    }
    if let Some(h) = cam_header(text) {
        return Ok(Detected { dialect: h.dialect, reason: h.to_string() });
    }
    Ok(Detected { dialect: Dialect::Fanuc, reason: "the default (no extension or marker of another dialect)".into() })
}

/// Lines of a program's head where a CAM system's header is looked for.
const HEADER_LINES: usize = 60;

/// What a CAM system's header comment says of the control, in the words
/// posts write: the machine's maker (`(  vendor: Haas Automation)`,
/// `(MACHINE: HAAS VF-2)`) or the post's name (`( Posts processor:
/// MPCNC21.cps)`, `(POST: grbl)`), each lower case, and the dialect it
/// names.
const CAM_NAMES: [(&str, Dialect); 12] = [
    ("haas", Dialect::Haas),
    ("fanuc", Dialect::Fanuc),
    ("linuxcnc", Dialect::LinuxCnc),
    ("emc2", Dialect::LinuxCnc),
    ("pathpilot", Dialect::LinuxCnc),
    ("mach3", Dialect::LinuxCnc),
    ("mach4", Dialect::LinuxCnc),
    ("grbl", Dialect::Grbl),
    ("mpcnc", Dialect::Grbl),
    ("marlin", Dialect::Grbl),
    ("shapeoko", Dialect::Grbl),
    ("carbide", Dialect::Grbl),
];

/// The control a CAM header names: in a comment of the first
/// [`HEADER_LINES`] lines that speaks of the machine or the post (`machine`,
/// `vendor`, `model`, `post`, `control`), the first name of [`CAM_NAMES`];
/// HAAS in any comment of the head. The text is the comment as written.
pub fn cam_header(text: &str) -> Option<Marker> {
    for (n, raw) in text.lines().take(HEADER_LINES).enumerate() {
        for comment in comments_of(raw) {
            let lower = comment.to_ascii_lowercase();
            let about = ["machine", "vendor", "model", "post", "control"].iter().any(|w| is_key(&lower, w));
            let found = CAM_NAMES
                .iter()
                .filter(|(name, _)| about || *name == "haas")
                .find(|(name, _)| contains_word(&lower, name));
            if let Some(&(_, dialect)) = found {
                let shown: String = comment.trim().chars().take(40).collect();
                return Some(Marker {
                    dialect,
                    text: format!("the CAM header's comment ({shown})"),
                    line: n as u32 + 1,
                });
            }
        }
    }
    None
}

/// Whether the comment `text` opens with `key` as a header's key: the key
/// (or a word that begins with it), at most two words more, then `:`, `=`
/// or `-` (`vendor: Haas`, `Posts processor: grbl.cps`, `MACHINE - HAAS
/// VF2`), not a word in a sentence (`AS ON A FANUC CONTROL: …`).
fn is_key(text: &str, key: &str) -> bool {
    let rest = text.trim_start();
    rest.starts_with(key) && rest.find([':', '=', '-']).is_some_and(|end| rest[..end].split_whitespace().count() <= 3)
}

/// Whether `name` stands in `text` as a word or the start of one
/// (`haas`, `haas-vf2`, `mach3mill`, `mpcnc21.cps`), not inside another.
fn contains_word(text: &str, name: &str) -> bool {
    text.match_indices(name).any(|(i, _)| i == 0 || !text.as_bytes()[i - 1].is_ascii_alphabetic())
}

/// The comments of a line: `( … )` and what follows `;`.
fn comments_of(raw: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = raw;
    while let Some(i) = rest.find(['(', ';']) {
        if rest.as_bytes()[i] == b';' {
            out.push(&rest[i + 1..]);
            break;
        }
        let after = &rest[i + 1..];
        let end = after.find(')').unwrap_or(after.len());
        out.push(&after[..end]);
        rest = &after[(end + 1).min(after.len())..];
    }
    out
}

/// The lower-case extension of a file name (`""` for none).
fn extension(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
    match base.rsplit_once('.') {
        Some((stem, ext)) if !stem.is_empty() => ext.to_ascii_lowercase(),
        _ => String::new(),
    }
}

/// LinuxCNC's O-word keywords: `o100 sub`, `o<name> call`.
const O_KEYWORDS: [&str; 15] = [
    "SUB",
    "ENDSUB",
    "CALL",
    "RETURN",
    "IF",
    "ELSEIF",
    "ELSE",
    "ENDIF",
    "WHILE",
    "ENDWHILE",
    "DO",
    "REPEAT",
    "ENDREPEAT",
    "BREAK",
    "CONTINUE",
];

/// The characters a line must hold to carry a marker (upper or lower case):
/// every marker has one (an O word, #<…>, **, a G code, @ ^, IF[ DPRNT[ …,
/// GOTO, a $ command).
const MARKER_BYTES: &[u8] = b"OoGg#[*@^$";

/// [`MARKER_BYTES`] as a table, one entry a byte.
static MARKER_BYTE: [bool; 256] = {
    let mut table = [false; 256];
    let mut i = 0;
    while i < MARKER_BYTES.len() {
        table[MARKER_BYTES[i] as usize] = true;
        i += 1;
    }
    table
};

/// The G codes that are a dialect's marker (see [`line_markers`]).
const MARKER_G_CODES: [f64; 12] = [64.0, 33.1, 43.2, 65.0, 66.0, 66.1, 54.1, 154.0, 187.0, 103.0, 47.0, 150.0];

/// The first marker of each dialect in `text` (at most one per dialect,
/// in the order of the lines).
///
/// The text is searched for the bytes a marker needs (`O`, `G`, `#`, `[`,
/// `*`, `@`, `^`, `$`): a line of axis words and numbers alone, most of a
/// program, is passed without being looked at, and so is a line whose only
/// such bytes begin G codes that are no marker (`G1 X5 Y2`). Any other line
/// is read in full.
pub fn markers(text: &str) -> Vec<Marker> {
    markers_forgetting(text, &|_| {})
}

/// [`markers`], telling `forget` of the text read through, a few megabytes
/// at a time.
fn markers_forgetting(text: &str, forget: &dyn Fn(Range<usize>)) -> Vec<Marker> {
    let b = text.as_bytes();
    let mut out: Vec<Marker> = Vec::new();
    // Lines before byte `counted`.
    let (mut lines, mut counted) = (0u32, 0usize);
    let (mut pos, mut forgotten) = (0, 0);
    while pos < b.len() {
        if pos - forgotten >= FORGET_EVERY {
            forget(forgotten..pos);
            forgotten = pos;
        }
        let window = (pos + FORGET_EVERY).min(b.len());
        let Some(hit) = b[pos..window].iter().position(|&c| MARKER_BYTE[c as usize]) else {
            pos = window;
            continue;
        };
        let hit = pos + hit;
        let start = memchr::memrchr(b'\n', &b[..hit]).map_or(0, |i| i + 1);
        let end = memchr::memchr(b'\n', &b[hit..]).map_or(b.len(), |i| hit + i);
        pos = end;
        if only_plain_g_codes(&b[start..end]) {
            continue;
        }
        lines += memchr::memchr_iter(b'\n', &b[counted..start]).count() as u32;
        counted = start;
        // As `str::lines` gives it: without the '\r' of a "\r\n".
        let raw = text[start..end].strip_suffix('\r').unwrap_or(&text[start..end]);
        for (dialect, what) in line_markers(raw) {
            if !out.iter().any(|m| m.dialect == dialect) {
                out.push(Marker { dialect, text: what, line: lines + 1 });
            }
        }
        if out.len() == 4 {
            break;
        }
    }
    forget(forgotten..pos.min(b.len()));
    out
}

/// Whether `line`'s only bytes of [`MARKER_BYTES`] are `G`s, each followed
/// at once by a number (ended by neither a digit nor a comment after
/// blanks) that is none of [`MARKER_G_CODES`]: then [`line_markers`] finds
/// nothing there. `false` sends the line to be read in full.
fn only_plain_g_codes(line: &[u8]) -> bool {
    let mut i = 0;
    while let Some(k) = line[i..].iter().position(|&c| MARKER_BYTE[c as usize]) {
        let at = i + k;
        if line[at] | 0x20 != b'g' {
            return false;
        }
        let number = &line[at + 1..];
        let digits = number.iter().take_while(|c| c.is_ascii_digit() || **c == b'.').count();
        let next = number[digits..].iter().find(|c| !matches!(c, b' ' | b'\t'));
        if digits == 0 || next.is_some_and(|c| c.is_ascii_digit() || matches!(c, b'.' | b'(')) {
            return false;
        }
        let value = std::str::from_utf8(&number[..digits]).ok().and_then(|s| s.parse::<f64>().ok());
        match value {
            Some(v) if !MARKER_G_CODES.iter().any(|g| (v - g).abs() < 1e-9) => {}
            _ => return false,
        }
        i = at + 1 + digits;
    }
    true
}

/// `raw` without its comments, upper case, blanks removed.
fn without_comments(raw: &str) -> String {
    let mut code = String::new();
    let mut chars = raw.chars();
    while let Some(c) = chars.next() {
        match c {
            '(' => chars.by_ref().take_while(|&c| c != ')').for_each(drop),
            ';' => break,
            c if c.is_whitespace() => {}
            c => code.push(c.to_ascii_uppercase()),
        }
    }
    code
}

/// The G codes of a compacted, upper-case line: `G64`, `G43.1`.
fn g_codes(code: &str) -> Vec<&str> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    for (i, _) in code.match_indices('G') {
        // Not a letter of a keyword (GOTO, ATAN …) nor after '#'.
        if i > 0 && (b[i - 1].is_ascii_alphabetic() || b[i - 1] == b'#') {
            continue;
        }
        let rest = &code[i + 1..];
        let len = rest.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(rest.len());
        if len > 0 && rest.as_bytes()[0].is_ascii_digit() {
            out.push(&code[i..i + 1 + len]);
        }
    }
    out
}

/// Whether G code `g` (`G064`, `G64.`) is `number`.
fn is_g(g: &str, number: f64) -> bool {
    g[1..].parse::<f64>().is_ok_and(|v| (v - number).abs() < 1e-9)
}

/// The markers of one line, each as written.
fn line_markers(raw: &str) -> Vec<(Dialect, String)> {
    let mut out = Vec::new();
    let trimmed = raw.trim();
    let code = without_comments(raw);
    // Block delete and a sequence number go before what matters.
    let body = code.trim_start_matches('/');
    let body = match body.strip_prefix('N') {
        Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.'),
        None => body,
    };
    // The line as written, without its comment (which may not close
    // within the quote), at most 24 characters.
    let shown = |s: &str| s.split(['(', ';']).next().unwrap_or("").trim_end().chars().take(24).collect::<String>();

    // LinuxCNC.
    if let Some(rest) = body.strip_prefix('O') {
        if rest.starts_with('<') {
            out.push((Dialect::LinuxCnc, shown(trimmed)));
        } else {
            let digits = rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(rest.len());
            let after = &rest[digits..];
            if digits > 0 && O_KEYWORDS.iter().any(|k| after.starts_with(k)) {
                out.push((Dialect::LinuxCnc, shown(trimmed)));
            } else if digits > 0 && after.is_empty() {
                // A program number alone: Fanuc's (LinuxCNC 2.9 reads it
                // only for Fanuc programs).
                out.push((Dialect::Fanuc, shown(trimmed)));
            }
        }
    }
    if code.contains("#<") {
        out.push((Dialect::LinuxCnc, "#<…>".to_string()));
    } else if code.contains("EXISTS[") {
        out.push((Dialect::LinuxCnc, "EXISTS[…]".to_string()));
    } else if code.contains("**") {
        out.push((Dialect::LinuxCnc, "**".to_string()));
    }
    let gs = g_codes(&code);
    if let Some(g) = gs.iter().find(|g| is_g(g, 64.0)) {
        if code.contains('P') || code.contains('Q') {
            out.push((Dialect::LinuxCnc, format!("{g} P")));
        }
    }
    if let Some(g) = gs.iter().find(|g| is_g(g, 33.1) || is_g(g, 43.2)) {
        out.push((Dialect::LinuxCnc, g.to_string()));
    }
    if (code.contains('@') || code.contains('^')) && !code.starts_with('$') {
        out.push((Dialect::LinuxCnc, if code.contains('@') { "@" } else { "^" }.to_string()));
    }

    // Fanuc (macro B) and Haas.
    if let Some(g) = gs.iter().find(|g| is_g(g, 65.0) || is_g(g, 66.0) || is_g(g, 66.1) || is_g(g, 54.1)) {
        out.push((Dialect::Fanuc, g.to_string()));
    }
    if body.starts_with("IF[") || body.starts_with("WHILE[") || code.contains("GOTO") {
        let word = ["GOTO", "IF[", "WHILE["].into_iter().find(|w| code.contains(w)).unwrap_or("IF[");
        out.push((Dialect::Fanuc, word.trim_end_matches('[').to_string()));
    }
    for word in ["DPRNT[", "BPRNT[", "POPEN", "PCLOS"] {
        if code.contains(word) {
            out.push((Dialect::Fanuc, word.trim_end_matches('[').to_string()));
        }
    }
    if let Some(g) = gs.iter().find(|g| [154.0, 187.0, 103.0, 47.0, 150.0].iter().any(|&n| is_g(g, n))) {
        out.push((Dialect::Haas, g.to_string()));
    }

    // GRBL's system commands: `$H`, `$X`, `$J=…`, `$$`, `$#`, `$G`, `$I`,
    // `$N`, `$C`, `$SLP`, `$RST=…` and settings `$110=…`. Other `$` lines
    // (a Haas control's, say) are no GRBL evidence.
    if let Some(rest) = code.strip_prefix('$') {
        let len = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '$')).map_or(rest.len(), |i| i + 1);
        let command = &rest[..len.min(rest.len())];
        let name = command.trim_end_matches('=');
        let setting = name.trim_start_matches('N');
        let grbl = ["H", "X", "J", "$", "#", "G", "I", "N", "C", "SLP", "RST", ""].contains(&name)
            && (name != "J" || command.ends_with('='))
            || (!setting.is_empty() && setting.bytes().all(|b| b.is_ascii_digit()) && command.ends_with('='));
        if grbl {
            out.push((Dialect::Grbl, format!("${command}")));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions() {
        assert_eq!(extension("a/b.NGC"), "ngc");
        assert_eq!(extension("-"), "");
        assert_eq!(extension(".hidden"), "");
        assert_eq!(extension("dir.x/file"), "");
    }

    #[test]
    fn lines_of_axis_words_alone_are_passed_and_markers_in_lower_case_still_found() {
        let text = "x10 y20 z-1.5\nX1 Y2\no100 sub\ng64 p0.01\nif [#1 gt 2] goto 5\n$H\n";
        let found: Vec<(Dialect, u32)> = markers(text).iter().map(|m| (m.dialect, m.line)).collect();
        assert_eq!(found, [(Dialect::LinuxCnc, 3), (Dialect::Fanuc, 5), (Dialect::Grbl, 6)]);
        let mut with_every_line = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            for (d, _) in line_markers(raw) {
                if !with_every_line.iter().any(|&(e, _)| e == d) {
                    with_every_line.push((d, n as u32 + 1));
                }
            }
        }
        assert_eq!(found, with_every_line);
    }

    #[test]
    fn g_codes_skip_keywords() {
        assert_eq!(g_codes("GOTO10G64P0.01"), vec!["G64"]);
        assert_eq!(g_codes("G43.1Z1#G1"), vec!["G43.1"]);
    }

    /// The first marker of each dialect, line by line over `str::lines`:
    /// what [`markers`] must find.
    fn every_line(text: &str) -> Vec<(Dialect, String, u32)> {
        let mut out: Vec<(Dialect, String, u32)> = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            for (d, what) in line_markers(raw) {
                if !out.iter().any(|m| m.0 == d) {
                    out.push((d, what, n as u32 + 1));
                }
            }
            if out.len() == 4 {
                break;
            }
        }
        out
    }

    #[test]
    fn the_g_codes_passed_at_once_are_those_no_dialect_marks() {
        for tenths in 0..2000 {
            let g = f64::from(tenths) / 10.0;
            let line = format!("G{g} P1 Q2");
            let marked = !line_markers(&line).is_empty();
            assert_eq!(marked, !only_plain_g_codes(line.as_bytes()), "{line}");
        }
    }

    proptest::proptest! {
        #[test]
        fn markers_are_those_of_every_line(
            lines in proptest::collection::vec(
                proptest::collection::vec(
                    proptest::sample::select(vec![
                        "G1", "g01", "G64", "G 64", "G6 4", "G6(x)4", "G33.1", "G43.2", "g65", "G66.1", "G154", "G103",
                        "G1.5.3", "G", "X1.5", " ", "\t", "(G64)", "(O100 sub)", "O100", "o100 sub", "#<a>=1", "#1=2",
                        "**", "IF[", "GOTO5", "DPRNT[", "@", "^", "$H", "$J=", "N10", "/", ";c", "P1", "\r", "%",
                    ]),
                    0..6,
                ),
                0..8,
            )
        ) {
            let text: String = lines.iter().map(|l| l.concat() + "\n").collect();
            let found: Vec<(Dialect, String, u32)> =
                markers(&text).into_iter().map(|m| (m.dialect, m.text, m.line)).collect();
            proptest::prop_assert_eq!(found, every_line(&text));
        }
    }

    #[test]
    fn a_long_text_is_let_go_of_as_it_is_read_through() {
        // 9 MB of axis words with markers near the start and the end.
        let mut text = String::from("O1000\n");
        while text.len() < 2 * FORGET_EVERY + 1_000_000 {
            text.push_str("X1.5 Y2.25 Z-0.5\nG1 X2. Y3.\n");
        }
        text.push_str("#<depth> = 2\n");
        let told = std::cell::RefCell::new(Vec::new());
        let found = markers_forgetting(&text, &|r| told.borrow_mut().push(r));
        let as_before: Vec<(Dialect, u32)> = markers(&text).iter().map(|m| (m.dialect, m.line)).collect();
        assert_eq!(found.iter().map(|m| (m.dialect, m.line)).collect::<Vec<_>>(), as_before);
        assert_eq!(as_before.len(), 2);
        // Told of every byte once, in order, a few megabytes at a time.
        let told = told.into_inner();
        assert!(told.len() >= 3, "{told:?}");
        assert_eq!((told[0].start, told.last().unwrap().end), (0, text.len()));
        assert!(told.windows(2).all(|w| w[0].end == w[1].start), "{told:?}");
        assert!(told.iter().all(|r| r.len() <= FORGET_EVERY + 64), "{told:?}");
    }
}
