//! Constant tables that the AVR keeps in flash instead of RAM.
//!
//! On the ATmega328P a `static` lives in RAM: the start-up code copies every initial
//! value from flash to `.data`, so a constant table costs its size twice, once of the
//! 2 KB of RAM. A table declared with [`flash_table!`](crate::flash_table) is placed in `.progmem.data`,
//! which the linker keeps in flash, and is read one element at a time with the `LPM`
//! instruction by [`Flash::get`]. On the host the same table is an ordinary static and
//! `get` indexes it, so the code that uses a table is tested on the host unchanged.
//!
//! This is the one module of `shared` allowed `unsafe` code: the `LPM` read and the
//! constructor whose contract keeps a table from ever being read that way from RAM.
#![allow(unsafe_code)]

/// A constant table (`Flash<[T; N]>`) kept in flash on the AVR; read it with
/// [`Flash::get`] through a `&'static Flash<[T]>`. Built only by [`flash_table!`](crate::flash_table).
#[repr(transparent)]
pub struct Flash<T: ?Sized>(T);

impl<T: Copy, const N: usize> Flash<[T; N]> {
    /// The table `items`.
    ///
    /// # Safety
    /// Only as the initial value of a `static` that is placed in `.progmem.data` when
    /// built for the AVR, as [`flash_table!`](crate::flash_table) does: [`Flash::get`] reads the table's
    /// address as a flash address there.
    #[doc(hidden)]
    pub const unsafe fn new(items: [T; N]) -> Self {
        Flash(items)
    }

    /// Element `index`, or `None` past the end (see [`Flash::get`] on `Flash<[T]>`).
    #[inline]
    pub fn get(&'static self, index: usize) -> Option<T> {
        self.as_slice().get(index)
    }

    /// The same table without its length in the type.
    pub const fn as_slice(&'static self) -> &'static Flash<[T]> {
        self
    }
}

impl<T: Copy> Flash<[T]> {
    /// Number of elements.
    pub const fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the table has no elements.
    pub const fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Element `index`, or `None` past the end.
    #[inline]
    pub fn get(&'static self, index: usize) -> Option<T> {
        #[cfg(target_arch = "avr")]
        {
            if index >= self.0.len() {
                return None;
            }
            // Only the address is computed here: the bytes are never loaded as data.
            let item = self.0.as_ptr().wrapping_add(index);
            // SAFETY: `Flash` is only built by `new`, whose contract places the static
            // that holds it in flash, so `item` (inside the table) is the flash address
            // of a valid `T`.
            Some(unsafe { avr::read(item) })
        }
        #[cfg(not(target_arch = "avr"))]
        {
            self.0.get(index).copied()
        }
    }

    /// The elements in order.
    pub fn iter(&'static self) -> impl Iterator<Item = T> {
        let mut next = 0;
        core::iter::from_fn(move || {
            let item = self.get(next)?;
            next += 1;
            Some(item)
        })
    }
}

#[cfg(target_arch = "avr")]
mod avr {
    use core::mem::{size_of, MaybeUninit};

    /// Reads the `T` at flash address `src`: in line for up to four bytes (one `LPM` per
    /// byte, straight into registers), else a call to the one copy loop, so each table
    /// read costs a few instructions at its call site.
    ///
    /// # Safety
    /// `src` is the address in flash (below 64 KB) of a valid `T`.
    #[inline(always)]
    pub unsafe fn read<T: Copy>(src: *const T) -> T {
        // Data and flash addresses are both 16 bits wide on this chip.
        let addr = src as usize as u16;
        if size_of::<T>() == 1 {
            // SAFETY: per the contract, `addr` holds a valid one-byte `T`.
            return unsafe { core::mem::transmute_copy(&byte(addr)) };
        }
        if size_of::<T>() == 2 {
            // SAFETY: per the contract, `addr` holds a valid two-byte `T`.
            return unsafe { core::mem::transmute_copy(&bytes2(addr)) };
        }
        if size_of::<T>() <= 4 {
            // SAFETY: per the contract, the first `size_of::<T>()` bytes at `addr` are a
            // valid `T`; `transmute_copy` reads only those from the four.
            return unsafe { core::mem::transmute_copy(&bytes4(addr)) };
        }
        let mut out = MaybeUninit::<T>::uninit();
        // SAFETY: `out` has room for the `size_of::<T>()` bytes read from a valid `T`
        // (per the contract), which makes it a valid `T`. Tables hold small elements.
        unsafe {
            copy(out.as_mut_ptr().cast::<u8>(), addr, size_of::<T>() as u8);
            out.assume_init()
        }
    }

    /// The byte at flash address `addr`.
    #[inline(always)]
    fn byte(addr: u16) -> u8 {
        let byte: u8;
        // SAFETY: LPM only reads program memory, at Z; it touches no data memory, no
        // stack and no flags.
        unsafe {
            core::arch::asm!(
                "lpm {byte}, Z",
                byte = out(reg) byte,
                in("Z") addr,
                options(pure, readonly, nostack, preserves_flags),
            );
        }
        byte
    }

    /// The two bytes at flash address `addr`.
    #[inline(always)]
    fn bytes2(addr: u16) -> [u8; 2] {
        let (a, b): (u8, u8);
        // SAFETY: LPM only reads program memory, at Z (post-incremented into a clobbered
        // copy); it touches no data memory, no stack and no flags.
        unsafe {
            core::arch::asm!(
                "lpm {a}, Z+",
                "lpm {b}, Z",
                a = out(reg) a,
                b = out(reg) b,
                inout("Z") addr => _,
                options(pure, readonly, nostack, preserves_flags),
            );
        }
        [a, b]
    }

    /// The four bytes at flash address `addr` (a three-byte item reads one byte past its
    /// end: reading flash has no effect, and the byte is dropped).
    #[inline(always)]
    fn bytes4(addr: u16) -> [u8; 4] {
        let (a, b, c, d): (u8, u8, u8, u8);
        // SAFETY: LPM only reads program memory, at Z (post-incremented into a clobbered
        // copy); it touches no data memory, no stack and no flags.
        unsafe {
            core::arch::asm!(
                "lpm {a}, Z+",
                "lpm {b}, Z+",
                "lpm {c}, Z+",
                "lpm {d}, Z",
                a = out(reg) a,
                b = out(reg) b,
                c = out(reg) c,
                d = out(reg) d,
                inout("Z") addr => _,
                options(pure, readonly, nostack, preserves_flags),
            );
        }
        [a, b, c, d]
    }

    /// Copies `len` bytes from flash address `src` to `dst`.
    ///
    /// # Safety
    /// `dst` is valid for `len` bytes of writes.
    #[inline(never)]
    unsafe fn copy(dst: *mut u8, src: u16, len: u8) {
        for i in 0..len {
            // SAFETY: `i` < `len`, inside `dst` per the contract.
            unsafe {
                dst.add(usize::from(i))
                    .write(byte(src.wrapping_add(u16::from(i))))
            };
        }
    }
}

/// Declares a constant table that the AVR keeps in flash (a [`Flash`]); on the host it
/// is an ordinary static.
///
/// ```
/// shared::flash_table! {
///     /// Squares of 0..4.
///     pub static SQUARES: [u16; 4] = [0, 1, 4, 9];
/// }
/// assert_eq!(SQUARES.get(3), Some(9));
/// assert_eq!(SQUARES.get(4), None);
/// ```
#[macro_export]
macro_rules! flash_table {
    ($(#[$meta:meta])* $vis:vis static $name:ident: [$t:ty; $n:expr] = $items:expr;) => {
        $(#[$meta])*
        #[allow(unsafe_code)]
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        $vis static $name: $crate::progmem::Flash<[$t; $n]> = {
            // Evaluated outside the `unsafe` block: the items are the caller's code.
            const ITEMS: [$t; $n] = $items;
            // SAFETY: the static is placed in `.progmem.data` on the AVR, just above.
            unsafe { $crate::progmem::Flash::new(ITEMS) }
        };
    };
}

#[cfg(test)]
mod tests {
    crate::flash_table! {
        /// Pairs of mixed width, as the setup tables hold.
        static PAIRS: [(u8, u16); 3] = [(1, 0x0102), (2, 0xfffe), (3, 0)];
    }

    #[test]
    fn get_reads_each_element_and_none_past_the_end() {
        assert_eq!(PAIRS.get(0), Some((1, 0x0102)));
        assert_eq!(PAIRS.get(1), Some((2, 0xfffe)));
        assert_eq!(PAIRS.get(2), Some((3, 0)));
        assert_eq!(PAIRS.get(3), None);
        assert_eq!(PAIRS.get(usize::MAX), None);
    }

    #[test]
    fn a_table_coerces_to_a_slice_table() {
        let table: &'static super::Flash<[(u8, u16)]> = &PAIRS;
        assert_eq!(table.len(), 3);
        assert!(!table.is_empty());
        let ids: Vec<u8> = table.iter().map(|(id, _)| id).collect();
        assert_eq!(ids, [1, 2, 3]);
    }
}
