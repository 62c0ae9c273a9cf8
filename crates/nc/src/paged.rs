//! An arena kept in pages: items numbered from 0 in the order they were
//! pushed, each page a run of them that can be dropped and given back
//! (read again from the program's text) without renumbering any item.

use std::cell::Cell;
use std::ops::{Index, IndexMut, Range};

/// Items in numbered pages. The page being written (the last one, or the
/// one [`Paged::rewrite`] opened) is kept apart, where a program read whole
/// has every item: a look-up there is one comparison.
#[derive(Clone, Debug)]
pub struct Paged<T> {
    /// Each page's first item number.
    firsts: Vec<u32>,
    /// Each page's items but the page being written's (empty there, and
    /// for a page that was dropped).
    pages: Vec<Vec<T>>,
    /// The page being written: its number, its first item's, its items.
    writing: usize,
    first: usize,
    items: Vec<T>,
    /// The page the last look-up elsewhere found.
    hint: Cell<usize>,
}

impl<T> Default for Paged<T> {
    fn default() -> Self {
        Paged { firsts: vec![0], pages: vec![Vec::new()], writing: 0, first: 0, items: Vec::new(), hint: Cell::new(0) }
    }
}

impl<T> Paged<T> {
    /// How many items have been pushed (the number the next one gets, in
    /// the page being written).
    #[inline]
    pub fn len(&self) -> usize {
        self.first + self.items.len()
    }

    /// Whether nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends an item to the page being written.
    #[inline]
    pub fn push(&mut self, item: T) {
        self.items.push(item);
    }

    /// The items of the page being written, to push to in bulk.
    pub fn writing_mut(&mut self) -> &mut Vec<T> {
        &mut self.items
    }

    /// Drops the items numbered `len` and on, in the page being written.
    pub fn truncate(&mut self, len: usize) {
        self.items.truncate(len.saturating_sub(self.first));
    }

    /// Room for `more` items in the page being written.
    pub fn reserve(&mut self, more: usize) {
        self.items.reserve(more);
    }

    /// Starts a new page after the last one (the pages' numbers match in
    /// the arenas of one program: each starts its pages together).
    pub fn start_page(&mut self) {
        let end = self.len();
        self.pages[self.writing] = std::mem::take(&mut self.items);
        self.firsts.push(end as u32);
        self.pages.push(Vec::new());
        self.writing = self.pages.len() - 1;
        self.first = end;
    }

    /// How many pages there are.
    pub fn pages(&self) -> usize {
        self.pages.len()
    }

    /// The item numbers of page `page`.
    pub fn page_range(&self, page: usize) -> Range<usize> {
        let end = match self.firsts.get(page + 1) {
            Some(&next) => next as usize,
            None => self.len(),
        };
        self.firsts[page] as usize..end
    }

    /// Whether page `page` holds its items (it was not dropped, or was
    /// given back).
    pub fn is_loaded(&self, page: usize) -> bool {
        page == self.writing || self.page_range(page).is_empty() || !self.pages[page].is_empty()
    }

    /// Drops the items of page `page` (not the page being written).
    pub fn drop_page(&mut self, page: usize) {
        if page != self.writing {
            self.pages[page] = Vec::new();
        }
    }

    /// Makes dropped page `page` the page being written, empty, so that it
    /// is read again item by item; [`Paged::rewritten`] goes back to the
    /// last page.
    pub fn rewrite(&mut self, page: usize) {
        self.pages[self.writing] = std::mem::take(&mut self.items);
        self.writing = page;
        self.first = self.firsts[page] as usize;
        self.items = std::mem::take(&mut self.pages[page]);
        self.items.clear();
    }

    /// After [`Paged::rewrite`]: writing goes on in the last page.
    pub fn rewritten(&mut self) {
        let last = self.pages.len() - 1;
        self.pages[self.writing] = std::mem::take(&mut self.items);
        self.writing = last;
        self.first = self.firsts[last] as usize;
        self.items = std::mem::take(&mut self.pages[last]);
    }

    /// The page item `i` is in.
    #[inline]
    pub fn page_of(&self, i: usize) -> usize {
        if i.wrapping_sub(self.first) < self.items.len() {
            return self.writing;
        }
        let k = self.hint.get();
        let i = i as u32;
        if self.firsts[k] <= i && self.firsts.get(k + 1).is_none_or(|&next| i < next) {
            return k;
        }
        let k = self.firsts.partition_point(|&f| f <= i).saturating_sub(1);
        self.hint.set(k);
        k
    }

    /// The page holding item `i` and where in it.
    #[inline]
    fn place(&self, i: usize) -> (&[T], usize) {
        if i.wrapping_sub(self.first) < self.items.len() {
            return (&self.items, i - self.first);
        }
        let k = self.page_of(i);
        (&self.pages[k], i - self.firsts[k] as usize)
    }

    /// Item `i`, where its page holds it.
    #[inline]
    pub fn get(&self, i: usize) -> Option<&T> {
        let (page, at) = self.place(i);
        page.get(at)
    }

    /// The items `range` (all in one page, which must hold them).
    #[inline]
    pub fn slice(&self, range: Range<usize>) -> &[T] {
        if range.is_empty() {
            return &[];
        }
        let (page, at) = self.place(range.start);
        &page[at..at + range.len()]
    }

    /// The items held, in order (a program read whole holds them all).
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &T> {
        let (before, after) = self.pages.split_at(self.writing);
        before.iter().flatten().chain(self.items.iter()).chain(after[1..].iter().flatten())
    }
}

impl<T> Index<usize> for Paged<T> {
    type Output = T;

    #[inline]
    fn index(&self, i: usize) -> &T {
        let (page, at) = self.place(i);
        &page[at]
    }
}

impl<T> IndexMut<usize> for Paged<T> {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut T {
        if i.wrapping_sub(self.first) < self.items.len() {
            let first = self.first;
            return &mut self.items[i - first];
        }
        let k = self.page_of(i);
        let first = self.firsts[k] as usize;
        &mut self.pages[k][i - first]
    }
}

impl<T> Index<Range<usize>> for Paged<T> {
    type Output = [T];

    fn index(&self, range: Range<usize>) -> &[T] {
        self.slice(range)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_keep_their_numbers_through_a_dropped_page() {
        let mut p: Paged<u32> = Paged::default();
        for i in 0..5 {
            p.push(i);
        }
        p.start_page();
        for i in 5..9 {
            p.push(i);
        }
        p.start_page();
        p.push(9);
        assert_eq!((p.len(), p.pages(), p.page_of(6), p[7]), (10, 3, 1, 7));
        assert_eq!(&p[5..8], &[5, 6, 7]);
        p.drop_page(1);
        assert!(!p.is_loaded(1) && p.get(6).is_none() && p.is_loaded(0));
        p.rewrite(1);
        assert_eq!(p.len(), 5);
        for i in 5..9 {
            p.push(i);
        }
        p.rewritten();
        assert_eq!((p.len(), p[6], p[9], p[2]), (10, 6, 9, 2));
        assert_eq!(p.iter().copied().collect::<Vec<_>>(), (0..10).collect::<Vec<_>>());
    }
}
