//! Encoders for the frames the host sends, sized from the addressed device's table.

use heapless::Vec;

use super::{header, Command, EncodeError, Write, MAX_FRAME, READ_SETS, READ_SET_SIZE};
use crate::regs::BoardKind;

/// Encodes a write of `writes` (in order) to `device` into `out` (cleared first).
/// Fails on a device with no board, an id its table does not have, a raw value above
/// 0xff for a 1-byte register, or a frame longer than 255 bytes.
pub fn encode_write(
    device: u8,
    writes: &[Write],
    out: &mut Vec<u8, MAX_FRAME>,
) -> Result<(), EncodeError> {
    out.clear();
    let kind = BoardKind::of_device(device).ok_or(EncodeError::UnknownDevice)?;
    encode_write_sized(device, writes, |id| kind.size_of(id), out)
}

/// [`encode_write`] with register sizes from `size_of` instead of a real table.
pub(crate) fn encode_write_sized(
    device: u8,
    writes: &[Write],
    size_of: impl Fn(u8) -> Option<u8>,
    out: &mut Vec<u8, MAX_FRAME>,
) -> Result<(), EncodeError> {
    out.clear();
    let mut total: usize = 3;
    for w in writes {
        let size = size_of(w.id).ok_or(EncodeError::UnknownRegister(w.id))?;
        if size == 1 && w.raw > 0xff {
            return Err(EncodeError::ValueTooWide(w.id));
        }
        total += 1 + usize::from(size);
        if total > MAX_FRAME {
            return Err(EncodeError::TooLong);
        }
    }
    let (Ok(length), Ok(count)) = (u8::try_from(total), u8::try_from(writes.len())) else {
        return Err(EncodeError::TooLong);
    };
    let full = |_| EncodeError::TooLong;
    out.extend_from_slice(&[length, header(device, Command::Write), count])
        .map_err(full)?;
    for w in writes {
        let [lo, hi] = w.raw.to_le_bytes();
        out.push(w.id).map_err(|_| EncodeError::TooLong)?;
        out.push(lo).map_err(|_| EncodeError::TooLong)?;
        if size_of(w.id) != Some(1) {
            out.push(hi).map_err(|_| EncodeError::TooLong)?;
        }
    }
    Ok(())
}

/// The 3-byte frame that reads read set `set` from `device`.
pub fn encode_read(device: u8, set: u8) -> [u8; 3] {
    [3, header(device, Command::Read), set]
}

/// Encodes a set-read-set frame into `out` (cleared first). Fails on a device with no
/// board, a set index of 8 or more, or more than 24 ids. Ids are not checked: sets are
/// shared by all devices.
pub fn encode_set_read_set(
    device: u8,
    set: u8,
    ids: &[u8],
    out: &mut Vec<u8, MAX_FRAME>,
) -> Result<(), EncodeError> {
    out.clear();
    if BoardKind::of_device(device).is_none() {
        return Err(EncodeError::UnknownDevice);
    }
    if usize::from(set) >= READ_SETS {
        return Err(EncodeError::BadReadSet);
    }
    if ids.len() > READ_SET_SIZE {
        return Err(EncodeError::ReadSetTooLarge);
    }
    // At most 3 + 24 bytes, so the length fits a byte and the buffer.
    let length = (3 + ids.len()) as u8;
    out.extend_from_slice(&[length, header(device, Command::SetReadSet), set])
        .map_err(|_| EncodeError::TooLong)?;
    out.extend_from_slice(ids)
        .map_err(|_| EncodeError::TooLong)?;
    Ok(())
}
