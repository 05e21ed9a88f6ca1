//! Read replies: their length and decoding, sized from the board's table.

use heapless::Vec;

use super::{DecodeError, READ_SET_SIZE};
use crate::regs::BoardKind;

/// Bytes the reply to a read of `ids` from a board of this kind has; `None` if an id
/// is not in its table.
pub fn read_reply_len(kind: BoardKind, ids: &[u8]) -> Option<usize> {
    ids.iter()
        .map(|&id| kind.size_of(id).map(usize::from))
        .sum()
}

/// Decodes a read reply into `(id, raw)` pairs (`out` is cleared first and stays
/// empty on error).
pub fn decode_read_reply(
    kind: BoardKind,
    ids: &[u8],
    bytes: &[u8],
    out: &mut Vec<(u8, u16), READ_SET_SIZE>,
) -> Result<(), DecodeError> {
    decode_sized(ids, bytes, |id| kind.size_of(id), out)
}

/// [`decode_read_reply`] with register sizes from `size_of`.
pub(crate) fn decode_sized(
    ids: &[u8],
    bytes: &[u8],
    size_of: impl Fn(u8) -> Option<u8>,
    out: &mut Vec<(u8, u16), READ_SET_SIZE>,
) -> Result<(), DecodeError> {
    out.clear();
    if ids.len() > READ_SET_SIZE {
        return Err(DecodeError::TooManyIds);
    }
    let mut expected = 0usize;
    for &id in ids {
        expected += usize::from(size_of(id).ok_or(DecodeError::UnknownRegister(id))?);
    }
    if bytes.len() != expected {
        return Err(DecodeError::WrongLength {
            expected,
            actual: bytes.len(),
        });
    }
    let mut rest = bytes;
    for &id in ids {
        let (raw, tail) = match (size_of(id), rest) {
            (Some(1), [lo, tail @ ..]) => (u16::from(*lo), tail),
            (_, [lo, hi, tail @ ..]) => (u16::from_le_bytes([*lo, *hi]), tail),
            _ => {
                out.clear();
                return Err(DecodeError::WrongLength {
                    expected,
                    actual: bytes.len(),
                });
            }
        };
        if out.push((id, raw)).is_err() {
            out.clear();
            return Err(DecodeError::TooManyIds);
        }
        rest = tail;
    }
    Ok(())
}
