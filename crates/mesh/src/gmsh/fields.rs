//! The values of an MSH 4.1 section, read one by one from its ASCII text or
//! its binary data (`size_t` of the header's size, `int` of 4 bytes,
//! `double` of 8, in the file's byte order).

use super::{find_section, find_section_span, uint_of_bytes};

/// A cursor over the values of one section of an MSH 4.1 file.
pub(super) struct Fields<'a> {
    data: &'a [u8],
    /// Offset of `data` in the file.
    base: usize,
    /// Offset of the section's header line in the file.
    header: usize,
    pos: usize,
    /// `None` for ASCII; else the size of `size_t` and the byte order.
    binary: Option<(usize, bool)>,
}

impl<'a> Fields<'a> {
    /// The values of section `$NAME` of `bytes`, from just after its header
    /// line, ASCII or (with the size of `size_t`) binary; `None` when the
    /// file has no such section or a binary file's byte order cannot be told.
    pub(super) fn of_section(
        bytes: &'a [u8],
        name: &str,
        size_t: Option<usize>,
    ) -> Option<Fields<'a>> {
        let (header, start) = find_section_span(bytes, name)?;
        let binary = match size_t {
            None => None,
            Some(size) => Some((size, binary_is_big_endian(bytes)?)),
        };
        Some(Fields {
            data: &bytes[start..],
            base: start,
            header,
            pos: 0,
            binary,
        })
    }

    /// Offset in the file of the section's header line.
    pub(super) fn header(&self) -> usize {
        self.header
    }

    /// Offset in the file of the next value.
    pub(super) fn offset(&self) -> usize {
        self.base + self.pos
    }

    /// The next ASCII token.
    fn token(&mut self) -> Option<&'a str> {
        let rest = self.data.get(self.pos..)?;
        let skip = rest.iter().position(|b| !b.is_ascii_whitespace())?;
        let len = rest[skip..]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len() - skip);
        self.pos += skip + len;
        std::str::from_utf8(&rest[skip..skip + len]).ok()
    }

    /// The next `len` bytes of binary data as an unsigned integer.
    fn raw(&mut self, len: usize, big_endian: bool) -> Option<u64> {
        let b = self.data.get(self.pos..self.pos.checked_add(len)?)?;
        self.pos += len;
        Some(uint_of_bytes(b, big_endian))
    }

    /// The next `size_t` (a count or a node tag).
    pub(super) fn size_t(&mut self) -> Option<u64> {
        match self.binary {
            None => self.token()?.parse().ok(),
            Some((size, big_endian)) if size <= 8 => self.raw(size, big_endian),
            Some(_) => None,
        }
    }

    /// The next `size_t` as a count.
    pub(super) fn count(&mut self) -> Option<usize> {
        usize::try_from(self.size_t()?).ok()
    }

    /// The next `int` (a tag or a dimension, possibly negative).
    pub(super) fn int(&mut self) -> Option<i32> {
        match self.binary {
            None => self.token()?.parse().ok(),
            Some((_, big_endian)) => Some(self.raw(4, big_endian)? as u32 as i32),
        }
    }

    /// The next `double`.
    pub(super) fn double(&mut self) -> Option<f64> {
        match self.binary {
            None => self.token()?.parse().ok(),
            Some((_, big_endian)) => Some(f64::from_bits(self.raw(8, big_endian)?)),
        }
    }

    /// Skips `n` doubles.
    pub(super) fn skip_doubles(&mut self, n: usize) -> Option<()> {
        match self.binary {
            None => (0..n).try_for_each(|_| self.token().map(drop)),
            Some(_) => {
                let len = n.checked_mul(8)?;
                self.data.get(self.pos..self.pos.checked_add(len)?)?;
                self.pos += len;
                Some(())
            }
        }
    }
}

/// Byte order of a binary MSH 4.1 file: the int 1 written right after the
/// `$MeshFormat` line.
fn binary_is_big_endian(bytes: &[u8]) -> Option<bool> {
    let start = find_section(bytes, "MeshFormat")?;
    let eol = bytes[start..].iter().position(|&b| b == b'\n')?;
    let one = bytes.get(start + eol + 1..start + eol + 5)?;
    match one {
        [0, 0, 0, 1] => Some(true),
        [1, 0, 0, 0] => Some(false),
        _ => None,
    }
}
