//! The master's read-set store: 8 sets of up to 24 register ids, shared by all devices.

use super::{FrameError, READ_SETS, READ_SET_SIZE};

/// Eight read sets of up to 24 ids each; all start empty.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadSets {
    ids: [[u8; READ_SET_SIZE]; READ_SETS],
    lens: [u8; READ_SETS],
}

impl Default for ReadSets {
    fn default() -> Self {
        Self::new()
    }
}

impl ReadSets {
    /// Eight empty sets.
    pub const fn new() -> Self {
        ReadSets {
            ids: [[0; READ_SET_SIZE]; READ_SETS],
            lens: [0; READ_SETS],
        }
    }

    /// Replaces set `set` with `ids`. Fails, changing nothing, if `set` is 8 or more
    /// or there are more than 24 ids.
    pub fn set(&mut self, set: u8, ids: &[u8]) -> Result<(), FrameError> {
        let index = usize::from(set);
        let (Some(slot), Some(len)) = (self.ids.get_mut(index), self.lens.get_mut(index)) else {
            return Err(FrameError::BadReadSet);
        };
        let Some(dest) = slot.get_mut(..ids.len()) else {
            return Err(FrameError::ReadSetTooLarge);
        };
        dest.copy_from_slice(ids);
        // ids.len() <= 24 here.
        *len = ids.len() as u8;
        Ok(())
    }

    /// The ids of set `set`, or `None` if `set` is 8 or more.
    pub fn get(&self, set: u8) -> Option<&[u8]> {
        let index = usize::from(set);
        let len = usize::from(*self.lens.get(index)?);
        self.ids.get(index)?.get(..len)
    }
}
