//! A program read in pages: runs of [`PAGE_BLOCKS`] lines of one file.
//! A page of plain blocks (words only: no macro statement, O-word, program
//! header or `%`) may be dropped once read, and is read again from its text
//! when the run comes back to it; every other page stays. So a program of
//! any size is held in the memory of its statements and a few pages.

use std::ops::Range;

use super::{Program, Statement};
use crate::source::{FileId, Sources};
use crate::Dialect;

/// How many lines a page holds by default (the last of a file may hold
/// fewer).
pub const PAGE_BLOCKS: usize = 4096;

/// Where a page was read from and what it holds.
#[derive(Clone, Debug)]
pub(crate) struct PageInfo {
    pub(crate) file: FileId,
    /// Its lines' bytes in the file.
    pub(crate) bytes: Range<u32>,
    /// The line before its first.
    pub(crate) line: u32,
    pub(crate) dialect: Dialect,
    /// It holds more than plain blocks, or a line that is not a block: it
    /// is never dropped.
    pub(crate) pinned: bool,
    /// The least and greatest N numbers of its blocks (for a jump's search).
    pub(crate) numbers: Option<(u32, u32)>,
    /// Still being read (its end not known yet).
    open: bool,
    /// When the run last needed it (a count of look-ups).
    used: u64,
}

/// The pages of a program read in pages (none for a program read whole).
#[derive(Clone, Debug, Default)]
pub(crate) struct Pages {
    /// One for each page of the arenas, once reading in pages began.
    pub(crate) info: Vec<PageInfo>,
    /// Most plain pages held at once; `None`: the program is read whole.
    keep: Option<usize>,
    /// Lines a page holds.
    pub(crate) lines: usize,
    clock: u64,
    /// The plain pages held now.
    held: Vec<usize>,
    /// The page of the block the run is at: never dropped.
    running: usize,
    /// How many times a dropped page was read again.
    read_again: u64,
    /// The page the last look-up found.
    last: usize,
}

impl Program {
    /// Reads the files parsed from now on in pages of `lines` lines (at
    /// least 1; [`PAGE_BLOCKS`] but to test), holding at most `keep` pages
    /// of plain blocks at once (at least 2). Call it before parsing. Not
    /// for a Fanuc or Haas lathe's programs: their cycles read the blocks
    /// of a contour ahead of the run.
    pub fn read_in_pages(&mut self, lines: usize, keep: usize) {
        self.pages.keep = Some(keep.max(2));
        self.pages.lines = lines.max(1);
        self.pages.last = usize::MAX;
        self.pages.running = usize::MAX;
    }

    /// Whether the program is read in pages.
    #[inline]
    pub(crate) fn paging(&self) -> bool {
        self.pages.keep.is_some()
    }

    /// How many times a dropped page was read again from its text.
    pub fn pages_read_again(&self) -> u64 {
        self.pages.read_again
    }

    /// The parser: a page begins at byte `byte` of `file`, after line
    /// `line`. The page before is closed (and may be dropped).
    pub(crate) fn page_begin(&mut self, file: FileId, byte: usize, line: u32, dialect: Dialect) {
        if !self.paging() {
            return;
        }
        let info = PageInfo {
            file,
            bytes: byte as u32..byte as u32,
            line,
            dialect,
            pinned: false,
            numbers: None,
            open: true,
            used: 0,
        };
        let last = self.blocks.pages() - 1;
        let empty = self.blocks.page_range(last).is_empty()
            && self.words.page_range(last).is_empty()
            && self.exprs.page_range(last).is_empty();
        if self.pages.info.len() < self.blocks.pages() {
            // Blocks read whole before paging began: a page of their own.
            self.pages.info.push(PageInfo { pinned: true, open: empty, ..info.clone() });
        }
        if empty {
            // Nothing read into it yet: it begins here instead.
            self.pages.info[last] = info;
            return;
        }
        self.page_end(byte);
        self.blocks.start_page();
        self.words.start_page();
        self.exprs.start_page();
        self.pages.info.push(info);
    }

    /// The parser: the page being read holds a line that is not a block.
    pub(crate) fn pin_page(&mut self) {
        if let Some(info) = self.pages.info.last_mut() {
            info.pinned = true;
        }
    }

    /// The parser: the page being read ends at byte `byte`.
    pub(crate) fn page_end(&mut self, byte: usize) {
        let Some(k) = self.pages.info.len().checked_sub(1) else { return };
        if !std::mem::take(&mut self.pages.info[k].open) {
            return;
        }
        let mut numbers: Option<(u32, u32)> = None;
        let mut plain = true;
        for i in self.blocks.page_range(k) {
            let b = &self.blocks[i];
            plain &= matches!(b.statement, Statement::Empty | Statement::Words { .. } | Statement::Line(_));
            if let Some(n) = b.number {
                numbers = Some(numbers.map_or((n, n), |(lo, hi)| (lo.min(n), hi.max(n))));
            }
        }
        let info = &mut self.pages.info[k];
        info.bytes.end = byte as u32;
        info.numbers = numbers;
        info.pinned |= !plain;
        if !info.pinned {
            self.pages.held.push(k);
        }
        self.tick(k);
        self.drop_pages(k);
    }

    /// The file block `block` was read from, held or not.
    pub(crate) fn block_file(&self, block: u32) -> FileId {
        match self.blocks.get(block as usize) {
            Some(b) => b.span.file,
            None => self.pages.info[self.page_of_block(block)].file,
        }
    }

    /// The page of block `block`.
    pub(crate) fn page_of_block(&self, block: u32) -> usize {
        self.blocks.page_of(block as usize)
    }

    /// Whether page `page` may hold a block numbered `n`.
    pub(crate) fn page_may_hold(&self, page: usize, n: u32) -> bool {
        match self.pages.info.get(page) {
            Some(info) => info.numbers.is_some_and(|(lo, hi)| lo <= n && n <= hi),
            None => true,
        }
    }

    /// Makes block `block` held, reading its page again from its text
    /// where it was dropped (and dropping the page needed least recently,
    /// to hold no more than the pages allowed).
    #[inline]
    pub fn ensure(&mut self, block: u32, sources: &Sources) {
        if !self.paging() {
            return;
        }
        let k = self.page_of_block(block);
        if k == self.pages.last {
            return;
        }
        if !self.blocks.is_loaded(k) {
            let info = self.pages.info[k].clone();
            let text = &sources.get(info.file).text;
            crate::parse::read_page_again(self, k, text, &info);
            text.forget(info.bytes.start as usize..info.bytes.end as usize);
            self.pages.held.push(k);
            self.pages.read_again += 1;
        }
        self.pages.last = k;
        self.tick(k);
        self.drop_pages(k);
    }

    /// [`Program::ensure`] for the block the run goes on with: its page
    /// stays held while the run looks elsewhere (a jump's search).
    #[inline]
    pub fn run_at(&mut self, block: u32, sources: &Sources) {
        if self.paging() {
            self.ensure(block, sources);
            self.pages.running = self.pages.last;
        }
    }

    fn tick(&mut self, page: usize) {
        if let Some(info) = self.pages.info.get_mut(page) {
            self.pages.clock += 1;
            info.used = self.pages.clock;
        }
    }

    /// Drops the plain pages needed least recently, but `keep_page`, until
    /// no more than the pages allowed are held.
    fn drop_pages(&mut self, keep_page: usize) {
        let Some(keep) = self.pages.keep else { return };
        let writing = self.blocks.pages() - 1;
        while self.pages.held.len() > keep {
            let info = &self.pages.info;
            let Some(at) = (0..self.pages.held.len())
                .filter(|&i| ![keep_page, writing, self.pages.running].contains(&self.pages.held[i]))
                .min_by_key(|&i| info[self.pages.held[i]].used)
            else {
                return;
            };
            let oldest = self.pages.held.swap_remove(at);
            self.blocks.drop_page(oldest);
            self.words.drop_page(oldest);
            self.exprs.drop_page(oldest);
            if self.pages.last == oldest {
                self.pages.last = usize::MAX;
            }
        }
    }
}
