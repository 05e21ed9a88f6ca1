#![no_std]
#![no_main]

use avr_device::atmega328p::Peripherals;

#[avr_device::entry]
fn main() -> ! {
    let dp = Peripherals::take().unwrap();
    dp.USART0.ubrr0().write(|w| unsafe { w.bits(16) });
    loop {}
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
