//! The runtime routines the compiler calls on its own, small enough for this chip:
//! 32-bit division (`/` and `%` on `u32` and `i32`: `__udivmodsi4`, `__divmodsi4`, both
//! through one loop, `drivers_udivmod32`) and block copies and fills (`memcpy`, `memset`).
//!
//! The toolchain's versions are generic: 1.4 KB of flash for the division and 0.5 KB for
//! the copies, where these take about 190 bytes in all. The division is restoring long
//! division, one quotient bit per step (at most ~500 cycles); the copies move a byte per
//! loop, as fast per byte as a wide copy on an 8-bit core. The toolchain defines its
//! versions as weak symbols, so these replace them at link time. Each follows the C
//! calling convention the compiler uses for it: arguments from r25 down, results in r25
//! down (the division returns a `u64` in r18..r25 with the quotient in its low half and
//! the remainder in its high half), only call-clobbered registers changed, r1 left at
//! zero. Division by zero never gets here from `/` (Rust checks for it first); called
//! directly (`shared::slave::divide::div_rem`) it gives all ones and the dividend.
//!
//! They are macros, expanded in each image's bin crate: assembly in a library crate
//! reaches the link only through its bitcode, which is assembled without the chip's
//! instruction set. The crate that expands them needs `#![feature(asm_experimental_arch)]`.
//! `tests/tests/master_builtins.rs` checks all four against the host's arithmetic.

/// Defines `__udivmodsi4` and `__divmodsi4` in the invoking crate.
#[macro_export]
macro_rules! division_routines {
    () => {
        /// Unsigned `n / d` and `n % d`, packed (remainder in the high half): the loop
        /// below, its results moved to where the C calling convention wants them.
        #[no_mangle]
        // SAFETY: the body is a complete function in assembly that follows the C calling
        // convention: it reads its arguments from r18..r25, returns in r18..r25, clobbers only
        // call-clobbered registers (r18..r27, r30, r31) and leaves r1 at zero, as it found it.
        #[unsafe(naked)]
        pub extern "C" fn __udivmodsi4(n: u32, d: u32) -> u64 {
            core::arch::naked_asm!(
                "call drivers_udivmod32",
                // Quotient to r18..r21, remainder to r22..r25.
                "movw r18, r22",
                "movw r20, r24",
                "movw r22, r26",
                "movw r24, r30",
                "ret",
            )
        }

        /// The one 32-bit division loop, in registers: n in r25..r22 and d in r21..r18 in;
        /// the quotient in r25..r22 and the remainder in r31, r30, r27, r26 out. Changes
        /// only those registers and SREG; r1 counts the steps and is zero again on return.
        /// Called by [`__udivmodsi4`] and, on the slave, by `shared::slave::divide::div_rem`
        /// straight from an inline `asm!` block (no moves, no stack frame).
        #[no_mangle]
        // Placed by its section's name where an image links sorted by section name (the
        // slave): after the functions whose names are mangled (`_R…`), among them its
        // callers, and before the interrupt handlers (`__vector_…`), so their calls reach it
        // as RCALLs. Elsewhere the name changes nothing.
        #[link_section = ".text._S1_drivers_udivmod32"]
        // SAFETY: a complete function in assembly; it touches only the registers named in
        // its doc (all call-clobbered) and leaves r1 at zero, as it found it.
        #[unsafe(naked)]
        pub extern "C" fn drivers_udivmod32() {
            core::arch::naked_asm!(
                // Remainder r26:r27:r30:r31 = 0; r1 (zero on entry and on exit) counts 32 steps.
                "clr r26",
                "clr r27",
                "movw r30, r26",
                "ldi r26, 32",
                "mov r1, r26",
                "clr r26",
                "1:",
                // Shift the dividend's top bit into the remainder; the dividend's low bit is
                // then free for the quotient bit.
                "lsl r22",
                "rol r23",
                "rol r24",
                "rol r25",
                "rol r26",
                "rol r27",
                "rol r30",
                "rol r31",
                // A bit out of the remainder's top means it is above any divisor.
                "brcs 2f",
                "cp r26, r18",
                "cpc r27, r19",
                "cpc r30, r20",
                "cpc r31, r21",
                "brcs 3f",
                "2:",
                "sub r26, r18",
                "sbc r27, r19",
                "sbc r30, r20",
                "sbc r31, r21",
                "ori r22, 1",
                "3:",
                "dec r1",
                "brne 1b",
                "ret",
            )
        }

        /// Signed `a / b` and `a % b`, truncating toward zero (the remainder takes the dividend's
        /// sign), packed as for [`__udivmodsi4`]. `i32::MIN / -1` never gets here (Rust checks).
        #[no_mangle]
        // SAFETY: a complete function in assembly under the C calling convention: arguments in
        // r18..r25, result in r18..r25, only call-clobbered registers and SREG's T flag used
        // (r0 and T keep the signs across the call, which touches neither), r1 left at zero.
        #[unsafe(naked)]
        pub extern "C" fn __divmodsi4(a: i32, b: i32) -> u64 {
            core::arch::naked_asm!(
                // T = the dividend's sign (the remainder's); r0 bit 7 = the quotient's sign.
                "bst r25, 7",
                "mov r0, r25",
                "eor r0, r21",
                // Divide the magnitudes.
                "sbrs r25, 7",
                "rjmp 1f",
                "com r25",
                "com r24",
                "com r23",
                "neg r22",
                "sbci r23, 0xff",
                "sbci r24, 0xff",
                "sbci r25, 0xff",
                "1:",
                "sbrs r21, 7",
                "rjmp 2f",
                "com r21",
                "com r20",
                "com r19",
                "neg r18",
                "sbci r19, 0xff",
                "sbci r20, 0xff",
                "sbci r21, 0xff",
                "2:",
                "call __udivmodsi4",
                // Give the quotient and the remainder their signs.
                "sbrs r0, 7",
                "rjmp 3f",
                "com r21",
                "com r20",
                "com r19",
                "neg r18",
                "sbci r19, 0xff",
                "sbci r20, 0xff",
                "sbci r21, 0xff",
                "3:",
                "brtc 4f",
                "com r25",
                "com r24",
                "com r23",
                "neg r22",
                "sbci r23, 0xff",
                "sbci r24, 0xff",
                "sbci r25, 0xff",
                "4:",
                "ret",
            )
        }
    };
}

/// Defines `memcpy` and `memset` in the invoking crate.
#[macro_export]
macro_rules! mem_routines {
    () => {
        /// Copies `n` bytes from `src` to `dest` (which do not overlap); returns `dest`.
        ///
        /// # Safety
        /// As C's `memcpy`: both ranges valid for `n` bytes and disjoint.
        #[no_mangle]
        // Where an image links sorted by section name (the slave): after the functions whose
        // names are mangled (`_R…`), before the interrupt handlers (`__vector_…`), within an
        // RCALL's reach of both its callers there, the boot code and the tick.
        #[link_section = ".text._S0_memcpy"]
        // SAFETY: a complete function in assembly under the C calling convention: dest in
        // r24:r25 (also the result), src in r22:r23, n in r20:r21; it uses only r0, r20, r21 and
        // the X and Z pointers (r26, r27, r30, r31), all call-clobbered.
        #[unsafe(naked)]
        pub unsafe extern "C" fn memcpy(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
            core::arch::naked_asm!(
                "movw r30, r22",
                "movw r26, r24",
                "rjmp 2f",
                "1:",
                "ld r0, Z+",
                "st X+, r0",
                "2:",
                "subi r20, 1",
                "sbci r21, 0",
                "brcc 1b",
                "ret",
            )
        }

        /// Fills `n` bytes at `dest` with the low byte of `c`; returns `dest`.
        ///
        /// # Safety
        /// As C's `memset`: the range valid for `n` bytes.
        #[no_mangle]
        // First where an image links sorted by section name (the slave), next to the boot
        // code (`__exec_setup`, its one caller there), so its calls are RCALLs.
        #[link_section = ".text.0_memset"]
        // SAFETY: a complete function in assembly under the C calling convention: dest in
        // r24:r25 (also the result), c in r22:r23, n in r20:r21; it uses only r20, r21 and the X
        // pointer (r26, r27), all call-clobbered.
        #[unsafe(naked)]
        pub unsafe extern "C" fn memset(dest: *mut u8, c: i16, n: usize) -> *mut u8 {
            core::arch::naked_asm!(
                "movw r26, r24",
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
