//! A line read as a block, in the first reading of a file and when a
//! dropped page of a program read in pages is read again.

use super::comment::with_comment;
use super::LineParser;
use crate::ast::{Block, PageInfo, Program, Statement};
use crate::source::{Diagnostic, Span};
use crate::Dialect;

/// Reads again the page `page` of `program` from `text`, its file's text
/// (the page's lines are its bytes `info.bytes`): the same blocks, words
/// and expressions with the same numbers, for a page of plain blocks that
/// was dropped.
pub(crate) fn read_page_again(program: &mut Program, page: usize, text: &str, info: &PageInfo) {
    program.blocks.rewrite(page);
    program.words.rewrite(page);
    program.exprs.rewrite(page);
    let bytes = &text.as_bytes()[..info.bytes.end as usize];
    let (mut pos, mut line) = (info.bytes.start as usize, info.line);
    let (mut notes, mut diagnostics) = (None, Vec::new());
    while pos < bytes.len() {
        line += 1;
        let end = memchr::memchr(b'\n', &bytes[pos..]).map_or(bytes.len(), |i| pos + i);
        let mut p =
            LineParser { b: bytes, pos, end, file: info.file, program, depth: 0, operators: 0, dialect: info.dialect };
        p.skip_blanks();
        let block = p.read_block(line, pos, false, &mut notes, &mut diagnostics);
        program.blocks.push(block);
        pos = end + 1;
    }
    program.blocks.rewritten();
    program.words.rewritten();
    program.exprs.rewritten();
}

impl LineParser<'_> {
    /// The block of this line, which begins at byte `pos` (its blanks
    /// skipped already): a parse error is reported and leaves an empty
    /// block, or after the program's end (`after_end`) a note, counted in
    /// `notes`.
    #[inline(always)]
    pub(super) fn read_block(
        &mut self,
        line: u32,
        pos: usize,
        after_end: bool,
        notes: &mut Option<(Span, u32)>,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Block {
        let end = self.end;
        let words_mark = self.program.words.len();
        let exprs_mark = self.program.exprs.len();
        match self.block(line) {
            Ok(mut block) => {
                if self.dialect == Dialect::LinuxCnc && !matches!(block.statement, Statement::OWord(_)) {
                    if let Some(command) = self.comment_command(pos) {
                        block.statement =
                            with_comment(std::mem::replace(&mut block.statement, Statement::Empty), command);
                    }
                }
                block
            }
            Err(d) => {
                self.program.words.truncate(words_mark);
                self.program.exprs.truncate(exprs_mark);
                let span = Span::new(self.file, pos, end);
                let statement = if after_end {
                    // Haas M97 targets live after M30, and so do notes
                    // about the setup: such a line is no error unless a
                    // jump reaches it.
                    notes.get_or_insert((span, 0)).1 += 1;
                    Statement::Unsupported(format!(
                        "this line after M30 was read as a note, not an NC block ({})",
                        d.message
                    ))
                } else {
                    diagnostics.push(d);
                    Statement::Empty
                };
                Block { span, line, number: None, delete: false, statement }
            }
        }
    }
}
