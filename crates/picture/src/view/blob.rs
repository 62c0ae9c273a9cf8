//! The page's binary data: little-endian arrays one after another, each
//! starting at a multiple of four bytes (so the page can view them as typed
//! arrays in place).

/// Arrays laid end to end.
#[derive(Default, Clone)]
pub struct Blob {
    bytes: Vec<u8>,
}

impl Blob {
    /// An `i32` array.
    pub fn i32s(&mut self, v: impl IntoIterator<Item = i32>) {
        self.bytes.extend(v.into_iter().flat_map(i32::to_le_bytes));
    }

    /// A `u32` array.
    pub fn u32s(&mut self, v: impl IntoIterator<Item = u32>) {
        self.bytes.extend(v.into_iter().flat_map(u32::to_le_bytes));
    }

    /// Bytes so far.
    pub fn len(&self) -> usize {
        self.bytes.len()
    }
}

/// Arrays laid end to end as [`Blob`] lays them, written on as they come
/// (each array may come in parts; [`Columns::align`] ends a `u8` or `u16`
/// one).
pub struct Columns<W: std::io::Write> {
    out: W,
    /// Bytes not yet written on.
    buffer: Vec<u8>,
    /// Bytes so far.
    len: usize,
}

impl<W: std::io::Write> Columns<W> {
    /// Arrays written on to `out`.
    pub fn new(out: W) -> Columns<W> {
        Columns { out, buffer: Vec::with_capacity(1 << 16), len: 0 }
    }

    fn extend(&mut self, bytes: impl IntoIterator<Item = u8>) {
        for b in bytes {
            self.buffer.push(b);
            if self.buffer.len() == self.buffer.capacity() {
                self.flush();
            }
        }
    }

    fn flush(&mut self) {
        self.len += self.buffer.len();
        self.out.write_all(&self.buffer).expect("writing a page into memory cannot fail");
        self.buffer.clear();
    }

    /// Zero bytes up to the next multiple of four.
    pub fn align(&mut self) {
        while !(self.len + self.buffer.len()).is_multiple_of(4) {
            self.extend([0]);
        }
    }

    /// `u8`s.
    pub fn bytes(&mut self, v: impl IntoIterator<Item = u8>) {
        self.extend(v);
    }

    /// `u16`s.
    pub fn u16s(&mut self, v: impl IntoIterator<Item = u16>) {
        self.extend(v.into_iter().flat_map(u16::to_le_bytes));
    }

    /// `i32`s.
    pub fn i32s(&mut self, v: impl IntoIterator<Item = i32>) {
        self.extend(v.into_iter().flat_map(i32::to_le_bytes));
    }

    /// `u32`s.
    pub fn u32s(&mut self, v: impl IntoIterator<Item = u32>) {
        self.extend(v.into_iter().flat_map(u32::to_le_bytes));
    }

    /// `f32`s.
    pub fn f32s(&mut self, v: impl IntoIterator<Item = f32>) {
        self.extend(v.into_iter().flat_map(f32::to_le_bytes));
    }

    /// The arrays of `blob` after these (each still at a multiple of four).
    pub fn append(&mut self, blob: &Blob) {
        self.align();
        self.extend(blob.bytes.iter().copied());
    }

    /// Writes what is left; the writer.
    pub fn finish(mut self) -> W {
        self.flush();
        self.out
    }
}
