//! The master's read-set store: 8 sets of up to 24 register ids, shared by all devices.

use super::{FrameError, READ_SETS, READ_SET_SIZE};

/// Eight read sets of up to 24 ids each; all start empty.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadSets {
    /// Per set: its length, then room for 24 ids (one row, so one bounds check finds
    /// both).
    sets: [[u8; 1 + READ_SET_SIZE]; READ_SETS],
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
            sets: [[0; 1 + READ_SET_SIZE]; READ_SETS],
        }
    }

    /// Replaces set `set` with `ids`. Fails, changing nothing, if `set` is 8 or more
    /// or there are more than 24 ids.
    pub fn set(&mut self, set: u8, ids: &[u8]) -> Result<(), FrameError> {
        let Some([len, slot @ ..]) = self.sets.get_mut(usize::from(set)) else {
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
        let [len, ids @ ..] = self.sets.get(usize::from(set))?;
        ids.get(..usize::from(*len))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_hold_what_was_set_and_refuse_what_does_not_fit() {
        let mut sets = ReadSets::new();
        assert_eq!(sets.get(0), Some(&[][..]));
        assert_eq!(sets.set(7, &[3, 1, 2]), Ok(()));
        assert_eq!(sets.get(7), Some(&[3, 1, 2][..]));
        assert_eq!(sets.set(8, &[1]), Err(FrameError::BadReadSet));
        assert_eq!(
            sets.set(7, &[0; READ_SET_SIZE + 1]),
            Err(FrameError::ReadSetTooLarge)
        );
        assert_eq!(sets.get(7), Some(&[3, 1, 2][..]));
        let full: [u8; READ_SET_SIZE] = core::array::from_fn(|i| i as u8);
        assert_eq!(sets.set(0, &full), Ok(()));
        assert_eq!(sets.get(0), Some(&full[..]));
        assert_eq!(sets.set(0, &[]), Ok(()));
        assert_eq!(sets.get(0), Some(&[][..]));
        assert_eq!(sets.get(8), None);
    }
}
