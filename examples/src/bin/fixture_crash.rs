//! Fixture: prints `crash\r\n`, then jumps past the end of flash, which the
//! emulator reports as a crash. Used by the harness's crashed-CPU test.
#![no_std]
#![no_main]

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"crash\r\n");
    while uart.ucsr0a().read().txc0().bit_is_clear() {}
    // Word address 0x4000 is byte address 0x8000, one past the 32 KiB flash.
    // SAFETY: deliberately unsound: this image exists only to crash the emulated
    // CPU, and is never flashed to a board.
    let past_flash: extern "C" fn() = unsafe { core::mem::transmute(0x4000usize) };
    past_flash();
    loop {
        avr_device::asm::nop();
    }
}

firmware_examples::spin_on_panic!();
