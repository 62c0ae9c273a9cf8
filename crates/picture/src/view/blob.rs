//! The page's binary data: little-endian arrays one after another, each
//! starting at a multiple of four bytes (so the page can view them as typed
//! arrays in place).

/// Arrays laid end to end.
#[derive(Default, Clone)]
pub struct Blob {
    bytes: Vec<u8>,
}

impl Blob {
    /// Zero bytes up to the next multiple of four.
    fn align(&mut self) {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
    }

    /// A `u8` array.
    pub fn bytes(&mut self, v: impl IntoIterator<Item = u8>) {
        self.bytes.extend(v);
        self.align();
    }

    /// A `u16` array.
    pub fn u16s(&mut self, v: impl IntoIterator<Item = u16>) {
        self.bytes.extend(v.into_iter().flat_map(u16::to_le_bytes));
        self.align();
    }

    /// An `i32` array.
    pub fn i32s(&mut self, v: impl IntoIterator<Item = i32>) {
        self.bytes.extend(v.into_iter().flat_map(i32::to_le_bytes));
    }

    /// A `u32` array.
    pub fn u32s(&mut self, v: impl IntoIterator<Item = u32>) {
        self.bytes.extend(v.into_iter().flat_map(u32::to_le_bytes));
    }

    /// An `f32` array.
    pub fn f32s(&mut self, v: impl IntoIterator<Item = f32>) {
        self.bytes.extend(v.into_iter().flat_map(f32::to_le_bytes));
    }

    /// Bytes so far.
    pub fn len(&self) -> usize {
        self.bytes.len()
    }

    /// The arrays of `other` after these (each still at a multiple of four).
    pub fn append(&mut self, other: Blob) {
        self.align();
        self.bytes.extend(other.bytes);
    }

    /// The bytes so far.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }
}
