//! A fixed-capacity FIFO of `Copy` values for the master's interrupt queues (received
//! bytes, reply bytes, RC edges): a power-of-two ring with one-byte indices, so each
//! operation is a few instructions on the AVR.

/// A first-in, first-out queue of at most `N` values (`N` a power of two, at most 128).
#[derive(Clone, Debug)]
pub struct Ring<T: Copy, const N: usize> {
    slots: [T; N],
    /// Index of the oldest value.
    head: u8,
    /// Number of values held.
    len: u8,
}

impl<T: Copy, const N: usize> Ring<T, N> {
    /// Index arithmetic wraps with a mask, and lengths fit a `u8`.
    const SHAPE_OK: () = assert!(N.is_power_of_two() && N <= 128, "N: a power of two <= 128");

    /// An empty queue; `fill` only initialises the unused slots.
    pub const fn new(fill: T) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::SHAPE_OK;
        Ring {
            slots: [fill; N],
            head: 0,
            len: 0,
        }
    }

    /// Slot index `i` places after the head.
    fn at(&self, i: u8) -> usize {
        usize::from(self.head.wrapping_add(i)) & (N - 1)
    }

    /// Appends `value`; gives it back if the queue is full.
    pub fn push_back(&mut self, value: T) -> Result<(), T> {
        if usize::from(self.len) == N {
            return Err(value);
        }
        let i = self.at(self.len);
        self.slots[i] = value;
        self.len += 1;
        Ok(())
    }

    /// Removes and returns the oldest value.
    pub fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let value = self.slots[self.at(0)];
        self.head = self.head.wrapping_add(1);
        self.len -= 1;
        Some(value)
    }

    /// Appends `value`; a full queue keeps its length and has its newest value replaced
    /// by `instead` (the receive task marks a byte it had no room for this way). One
    /// store either way, so the interrupt handler stays short.
    pub fn push_or_replace(&mut self, value: T, instead: T) {
        let full = usize::from(self.len) == N;
        if !full {
            self.len += 1;
        }
        // len ≥ 1 here.
        let i = self.at(self.len.wrapping_sub(1));
        self.slots[i] = if full { instead } else { value };
    }

    /// Whether the queue holds nothing.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of values held.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }
}

#[cfg(test)]
mod tests {
    use super::Ring;

    #[test]
    fn values_come_out_in_order_across_the_wrap() {
        let mut q: Ring<u8, 4> = Ring::new(0);
        assert_eq!(q.pop_front(), None);
        for round in 0..5u8 {
            for i in 0..3 {
                assert_eq!(q.push_back(round * 10 + i), Ok(()));
            }
            assert_eq!(q.len(), 3);
            for i in 0..3 {
                assert_eq!(q.pop_front(), Some(round * 10 + i));
            }
            assert!(q.is_empty());
        }
    }

    #[test]
    fn a_full_queue_refuses_and_push_or_replace_overwrites_the_newest() {
        let mut q: Ring<u16, 8> = Ring::new(0);
        q.push_or_replace(1, 99);
        assert_eq!(q.len(), 1, "room: the value is appended");
        assert_eq!(q.pop_front(), Some(1));
        // Start off the zero index so the back wraps.
        for v in 0..5 {
            q.push_back(v).unwrap();
            q.pop_front();
        }
        for v in 100..107 {
            assert_eq!(q.push_back(v), Ok(()));
        }
        q.push_or_replace(107, 99);
        assert_eq!(q.push_back(108), Err(108));
        assert_eq!(q.len(), 8);
        q.push_or_replace(109, 7);
        assert_eq!(q.len(), 8, "full: the length stays");
        let out: Vec<u16> = core::iter::from_fn(|| q.pop_front()).collect();
        assert_eq!(out, [100, 101, 102, 103, 104, 105, 106, 7]);
    }
}
