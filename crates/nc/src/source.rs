//! Source files, byte spans and located diagnostics.
//!
//! Spans are byte offsets into one file of a [`Sources`] set; line and column
//! are computed only when a diagnostic is rendered.

use std::fmt;
use std::ops::{Deref, Range};
use std::sync::{Arc, OnceLock};

/// Index of a file in a [`Sources`] set.
pub type FileId = u32;

/// A byte range in one source file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Span {
    /// The file.
    pub file: FileId,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
}

impl Span {
    /// A span from `start` to `end` in `file`.
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        Span { file, start: start as u32, end: end as u32 }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span { file: self.file, start: self.start.min(other.start), end: self.end.max(other.end) }
    }
}

/// How far a scan through a text reads before it lets go of what it read
/// ([`TextStore::forget`]).
pub const FORGET_EVERY: usize = 4 << 20;

/// Where a source file's text is kept: a `String`, or the caller's store
/// (a file mapped into memory) that can let go of what has been read, to
/// read it again when asked.
pub trait TextStore: Send + Sync {
    /// The whole text.
    fn text(&self) -> &str;

    /// The bytes `range` will not be needed again soon (they stay
    /// readable).
    fn forget(&self, range: Range<usize>) {
        let _ = range;
    }
}

impl TextStore for String {
    fn text(&self) -> &str {
        self
    }
}

/// A source file's text, shared.
#[derive(Clone)]
pub struct Text(Arc<dyn TextStore>);

impl Text {
    /// The text.
    pub fn as_str(&self) -> &str {
        self.0.text()
    }

    /// Tells the store the bytes `range` will not be needed again soon.
    pub fn forget(&self, range: Range<usize>) {
        self.0.forget(range);
    }

    /// The store the text is read from, to read the program again.
    pub fn store(&self) -> Arc<dyn TextStore> {
        Arc::clone(&self.0)
    }
}

impl Deref for Text {
    type Target = str;

    fn deref(&self) -> &str {
        self.0.text()
    }
}

impl fmt::Debug for Text {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Text({} bytes)", self.len())
    }
}

/// One line start in this many is kept for rendering diagnostics.
const LINES_APART: usize = 256;

/// One source file: its name as the user gave it and its text.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// Name shown in diagnostics (usually the path).
    pub name: String,
    /// The text; invalid UTF-8 was replaced before it got here.
    pub text: Text,
    /// The start of every [`LINES_APART`]th line, made when first needed.
    line_starts: OnceLock<Vec<u32>>,
}

impl SourceFile {
    /// A file from its name and text.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        SourceFile::stored(name, Arc::new(text.into()))
    }

    /// A file whose text `store` keeps (a file mapped into memory).
    pub fn stored(name: impl Into<String>, store: Arc<dyn TextStore>) -> SourceFile {
        SourceFile { name: name.into(), text: Text(store), line_starts: OnceLock::new() }
    }

    /// Every [`LINES_APART`]th line's start, read a megabyte at a time
    /// (each let go of once counted).
    fn line_starts(&self) -> &[u32] {
        self.line_starts.get_or_init(|| {
            let bytes = self.text.as_bytes();
            let mut starts = vec![0];
            let mut lines = 0usize;
            for from in (0..bytes.len()).step_by(1 << 20) {
                let to = (from + (1 << 20)).min(bytes.len());
                for i in memchr::memchr_iter(b'\n', &bytes[from..to]) {
                    lines += 1;
                    if lines.is_multiple_of(LINES_APART) {
                        starts.push((from + i + 1) as u32);
                    }
                }
                self.text.forget(from..to);
            }
            starts
        })
    }

    /// The start of 1-based line `line` (the text's end past its last).
    fn line_start(&self, line: usize) -> usize {
        let (k, more) = ((line - 1) / LINES_APART, (line - 1) % LINES_APART);
        let starts = self.line_starts();
        let Some(&from) = starts.get(k) else { return self.text.len() };
        let from = from as usize;
        match more {
            0 => from,
            _ => memchr::memchr_iter(b'\n', &self.text.as_bytes()[from..])
                .nth(more - 1)
                .map_or(self.text.len(), |i| from + i + 1),
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: u32) -> (u32, u32) {
        let starts = self.line_starts();
        let k = starts.partition_point(|&s| s <= offset) - 1;
        let from = starts[k] as usize;
        let end = (offset as usize).min(self.text.len());
        let before = &self.text.as_bytes()[from.min(end)..end];
        let more = memchr::memchr_iter(b'\n', before).count();
        let line = k * LINES_APART + more;
        let start = memchr::memrchr(b'\n', before).map_or(from, |i| from + i + 1);
        let col = self.text.get(start..end).map_or(end - start, |s| s.chars().count());
        (line as u32 + 1, col as u32 + 1)
    }

    /// The text of a 1-based line, without its line break.
    pub fn line_text(&self, line: u32) -> &str {
        let start = self.line_start(line as usize);
        let end = memchr::memchr(b'\n', &self.text.as_bytes()[start..]).map_or(self.text.len(), |i| start + i + 1);
        self.text[start..end].trim_end_matches(['\n', '\r'])
    }
}

/// The files a run reads: the main program and any subprogram files.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    files: Vec<SourceFile>,
}

impl Sources {
    /// Adds a file and returns its id.
    pub fn add(&mut self, file: SourceFile) -> FileId {
        self.files.push(file);
        (self.files.len() - 1) as FileId
    }

    /// The file with this id.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id as usize]
    }

    /// Number of files.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// `true` when no file was added.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Severity {
    /// The program cannot be run past this point.
    Error,
    /// The program runs, but probably not as its author meant.
    Warning,
}

/// A located message about a program.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// What is wrong, in a machinist's words.
    pub message: String,
    /// Where.
    pub span: Span,
    /// Macro and subprogram calls that led here, innermost last: each a
    /// description and the span of the calling block.
    pub call_chain: Vec<(String, Span)>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn error(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic { severity: Severity::Error, message: message.into(), span, call_chain: Vec::new() }
    }

    /// A warning at `span`.
    pub fn warning(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic { severity: Severity::Warning, message: message.into(), span, call_chain: Vec::new() }
    }

    /// `true` for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// One line: `file:line:col: error: message`.
    pub fn headline(&self, sources: &Sources) -> String {
        let file = sources.get(self.span.file);
        let (line, col) = file.line_col(self.span.start);
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        format!("{}:{}:{}: {}: {}", file.name, line, col, kind, self.message)
    }

    /// The headline, the source line with a caret under the span, and the
    /// call chain.
    pub fn render(&self, sources: &Sources) -> String {
        RenderedDiagnostic { diagnostic: self, sources }.to_string()
    }
}

/// Most characters of a source line shown under a diagnostic.
const SNIPPET: usize = 100;

struct RenderedDiagnostic<'a> {
    diagnostic: &'a Diagnostic,
    sources: &'a Sources,
}

impl fmt::Display for RenderedDiagnostic<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = self.diagnostic;
        let file = self.sources.get(d.span.file);
        let (line, col) = file.line_col(d.span.start);
        writeln!(f, "{}", d.headline(self.sources))?;
        let text: Vec<char> = file.line_text(line).chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
        let width = text.len();
        let (end_line, end_col) = file.line_col(d.span.end.max(d.span.start));
        let at = (col as usize - 1).min(width);
        let carets =
            if end_line == line { end_col.saturating_sub(col) as usize } else { (width + 1).saturating_sub(at + 1) };
        // A long line (binary garbage, a generated expression) is shown as a
        // window around the column.
        let first = if width > SNIPPET { at.saturating_sub(SNIPPET * 2 / 3).min(width - SNIPPET) } else { 0 };
        let last = width.min(first + SNIPPET);
        let lead = if first > 0 { "…" } else { "" };
        let tail = if last < width { "…" } else { "" };
        let shown: String = text[first..last].iter().collect();
        let gutter = line.to_string();
        writeln!(f, "{gutter} | {lead}{shown}{tail}")?;
        let offset = at - first + lead.chars().count();
        let carets = carets.clamp(1, (last + 1).saturating_sub(at).max(1));
        write!(f, "{} | {}{}", " ".repeat(gutter.len()), " ".repeat(offset), "^".repeat(carets))?;
        for (what, span) in d.call_chain.iter().rev() {
            let file = self.sources.get(span.file);
            let (l, c) = file.line_col(span.start);
            write!(f, "\n  in {} called at {}:{}:{}", what, file.name, l, c)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_line_column_and_caret() {
        let mut sources = Sources::default();
        let id = sources.add(SourceFile::new("a.nc", "G01 X1.\nG01 X[1+]\n"));
        let d = Diagnostic::error(Span::new(id, 16, 17), "expected a value after '+'");
        expect_test::expect![[r#"
            a.nc:2:9: error: expected a value after '+'
            2 | G01 X[1+]
              |         ^"#]]
        .assert_eq(&d.render(&sources));
    }

    #[test]
    fn long_lines_show_a_window_around_the_column() {
        let mut sources = Sources::default();
        let line = format!("#1=1{}@{}", "+1".repeat(200), "+1".repeat(200));
        let id = sources.add(SourceFile::new("a.nc", line.clone()));
        let at = line.find('@').unwrap();
        let d = Diagnostic::error(Span::new(id, at, at + 1), "unexpected '@'");
        let rendered = d.render(&sources);
        let lines: Vec<&str> = rendered.lines().collect();
        assert_eq!(lines[0], "a.nc:1:405: error: unexpected '@'");
        assert!(lines[1].starts_with("1 | …+1+1") && lines[1].ends_with('…'), "{}", lines[1]);
        assert_eq!(lines[1].chars().count(), 4 + 1 + SNIPPET + 1);
        let caret = lines[2].find('^').unwrap();
        assert_eq!(lines[1].chars().nth(caret), Some('@'));
        assert_eq!(lines[2].matches('^').count(), 1);
    }

    #[test]
    fn lines_and_columns_past_the_kept_line_starts() {
        // 2,000 lines of varied lengths (some blank, one with a 3-byte
        // character), checked at every byte against a plain count.
        let text: String = (0..2000).map(|k| format!("N{k} {}X1.\r\n", "é ".repeat(k % 5))).collect::<String>() + "M30";
        let file = SourceFile::new("long.nc", text.as_str());
        let (mut line, mut start) = (1, 0);
        for (i, c) in text.char_indices() {
            let col = text[start..i].chars().count() as u32 + 1;
            assert_eq!(file.line_col(i as u32), (line, col), "at byte {i}");
            if c == '\n' {
                assert_eq!(file.line_text(line), text[start..i].trim_end_matches('\r'));
                (line, start) = (line + 1, i + 1);
            }
        }
        assert_eq!((file.line_col(text.len() as u32), file.line_text(2001)), ((2001, 4), "M30"));
    }
}
