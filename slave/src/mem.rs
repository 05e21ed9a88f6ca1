//! `memcpy` and `memset` for the slave images: byte loops of some 20 bytes each.
//!
//! The compiler moves the large structs `init` hands to the executor (and zeroes some
//! arrays) through these two functions. The core library's own versions are weak
//! symbols of some 520 bytes together, tuned for wide registers; on this 8-bit core a
//! byte loop is as fast per byte, so these strong definitions replace them at link time.
//!
//! Both follow the AVR C calling convention: arguments in r25:r24, r23:r22, r21:r20;
//! the destination is returned in r25:r24 (where it came in); only call-clobbered
//! registers (r0, r20, r21, r26, r27, r30, r31) change, and r1 stays zero.

/// Defines `memcpy` and `memset` in the crate that invokes it (each image's bin, through
/// [`crate::firmware!`]): assembly in a library crate reaches the link only through its
/// bitcode, which is assembled without the chip's instruction set.
#[doc(hidden)]
#[macro_export]
macro_rules! mem_routines {
    () => {
        /// Copies `n` bytes from `src` to `dest` (regions that do not overlap); returns `dest`.
        ///
        /// # Safety
        /// As C's `memcpy`: both ranges valid for `n` bytes, and disjoint.
        #[no_mangle]
        // SAFETY: the body is a whole function in assembly that keeps the C calling convention
        // above: it reads r20..r25, writes only r0, r20, r21, r26, r27, r30, r31 and memory in
        // dest..dest+n, which the caller guarantees is valid, and returns with r25:r24 intact.
        #[unsafe(naked)]
        pub unsafe extern "C" fn memcpy(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
            core::arch::naked_asm!(
                "movw r30, r22", // Z: source
                "movw r26, r24", // X: destination
                "rjmp 2f",
                "1:",
                "ld r0, Z+",
                "st X+, r0",
                // n -= 1 in 16 bits: a borrow out of the high byte (n was 0) ends the loop.
                "2:",
                "subi r20, 1",
                "sbci r21, 0",
                "brcc 1b",
                "ret",
            )
        }

        /// Stores the low byte of `c` in `n` bytes from `dest`; returns `dest`.
        ///
        /// # Safety
        /// As C's `memset`: the range valid for `n` bytes.
        #[no_mangle]
        // SAFETY: as for `memcpy`: registers r20..r25 read, only r20, r21, r26, r27 and
        // dest..dest+n written, r25:r24 returned intact.
        #[unsafe(naked)]
        pub unsafe extern "C" fn memset(dest: *mut u8, c: i16, n: usize) -> *mut u8 {
            core::arch::naked_asm!(
                "movw r26, r24", // X: destination
                "rjmp 2f",
                "1:",
                "st X+, r22",
                "2:",
                "subi r20, 1",
                "sbci r21, 0",
                "brcc 1b",
                "ret",
            )
        }
    };
}
