//! On a panic the master stops everything: interrupts off for good (no task runs again),
//! the status LED lit, and the watchdog, which always runs in this firmware, left to
//! expire. The reboot hard-resets every slave (reference §5), which stops every motor,
//! and sends the banner, so the PC sees the fault.
//!
//! An interrupt that no task binds takes the same path ([`drivers::fault_entry`]);
//! `tests/tests/master_panic.rs` runs it on the real image.

drivers::fault_entries!(halt);

/// Interrupts off, D13 lit, then wait for the watchdog.
#[inline(always)]
fn halt() -> ! {
    executor::freeze();
    // SAFETY: interrupts are off and nothing else runs again; D13 was taken in init, but
    // driving it high from here cannot conflict with code that no longer runs.
    let led = unsafe { drivers::pin::Output::<{ drivers::pin::PORTB }, 5>::take() };
    led.set_high();
    // The watchdog (125 ms, or 1 s during boot) resets the chip.
    #[allow(clippy::empty_loop)]
    loop {}
}
