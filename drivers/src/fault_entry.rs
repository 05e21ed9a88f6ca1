//! The two ways into a board's stop-everything path: a panic, and an interrupt that no task
//! binds (avr-libc's crt jumps to `__vector_default`, whose default is a jump to address 0:
//! a restart that would skip the watchdog and leave the last outputs on the pins).
//!
//! [`fault_entries!`](crate::fault_entries) defines both in the invoking image, each calling
//! that image's own `halt` (which outputs to stop differs per board). No call in the
//! firmware can panic today, so the linker drops the panic handler, and the emulator tests
//! (`master_panic`, `slave_panic`) run `halt` through the vector; they fail once an image
//! links core's panic code, so that the handler gets a test of its own. The invoking crate
//! needs `#![feature(abi_avr_interrupt)]`.

/// Defines `#[panic_handler]` and `__vector_default` in the invoking crate, both calling
/// `$halt`, a `fn() -> !` that stops the board's outputs and waits for the watchdog.
#[macro_export]
macro_rules! fault_entries {
    ($halt:path) => {
        #[panic_handler]
        fn panic(_info: &core::panic::PanicInfo) -> ! {
            $halt()
        }

        /// The vector every unbound interrupt jumps to (avr-libc's crt calls it by this
        /// name).
        #[no_mangle]
        extern "avr-interrupt" fn __vector_default() {
            $halt()
        }
    };
}
