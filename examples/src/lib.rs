//! Pieces the test firmwares share: UART0 polled at 115200 baud (U2X, UBRR0 16, with
//! UCSR0A and UCSR0C written before UBRR0, since the emulator applies the baud rate when
//! UBRR0 is written) and decimal printing. Each `src/bin` firmware shows one concept.
#![no_std]

/// The chip's peripherals, at the start of a fixture's `main`. `take` fails only on a
/// second call, which no fixture makes; it would spin here rather than panic.
pub fn peripherals() -> avr_device::atmega328p::Peripherals {
    match avr_device::atmega328p::Peripherals::take() {
        Some(p) => p,
        None => loop {
            avr_device::asm::nop();
        },
    }
}

/// Defines a fixture's panic handler: spin. The tests watch a fixture's UART and pins;
/// a fixture that panics stops answering, which they report.
#[macro_export]
macro_rules! spin_on_panic {
    () => {
        #[panic_handler]
        fn panic(_: &core::panic::PanicInfo) -> ! {
            loop {
                avr_device::asm::nop();
            }
        }
    };
}

/// `n` in decimal without leading zeros: the tail of `buf` that holds its digits.
pub fn decimal(mut n: u32, buf: &mut [u8; 10]) -> &[u8] {
    let mut start = buf.len();
    loop {
        start -= 1;
        buf[start] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            return &buf[start..];
        }
    }
}

/// Polled UART0 output for the fixtures' reports.
pub mod uart {
    use avr_device::atmega328p::USART0;

    /// Configures 115200 8N1, receiver and transmitter on, no interrupts.
    pub fn uart_init(uart: &USART0) {
        uart.ucsr0a().write(|w| w.u2x0().set_bit());
        uart.ucsr0c().write(|w| w.ucsz0().chr8());
        uart.ucsr0b()
            .write(|w| w.rxen0().set_bit().txen0().set_bit());
        uart.ubrr0().write(|w| w.set(16));
    }

    /// Configures UART0 as [`uart_init`] does and sends the fixture's `ready` line.
    pub fn start(uart: USART0, ready: &[u8]) -> USART0 {
        uart_init(&uart);
        put_str(&uart, ready);
        uart
    }

    /// Sends one byte, waiting for the data register.
    pub fn put(uart: &USART0, byte: u8) {
        while uart.ucsr0a().read().udre0().bit_is_clear() {}
        uart.udr0().write(|w| w.set(byte));
    }

    /// Sends every byte of `s`.
    pub fn put_str(uart: &USART0, s: &[u8]) {
        for &b in s {
            put(uart, b);
        }
    }

    /// Waits for one received byte.
    pub fn get(uart: &USART0) -> u8 {
        while uart.ucsr0a().read().rxc0().bit_is_clear() {}
        uart.udr0().read().bits()
    }

    /// Reads `N` bytes: one request of the fixtures that answer the host.
    pub fn get_request<const N: usize>(uart: &USART0) -> [u8; N] {
        let mut req = [0u8; N];
        req.iter_mut().for_each(|b| *b = get(uart));
        req
    }

    /// Sends two `u32`s, LSB first.
    pub fn put_pair(uart: &USART0, a: u32, b: u32) {
        put_str(uart, &a.to_le_bytes());
        put_str(uart, &b.to_le_bytes());
    }

    /// Prints `n` in decimal without leading zeros.
    pub fn put_dec(uart: &USART0, n: u16) {
        put_str(uart, crate::decimal(n.into(), &mut [0; 10]));
    }
}

/// EEPROM access for the fixtures that keep state across resets.
pub mod eeprom {
    use avr_device::atmega328p::EEPROM;

    /// Reads one EEPROM byte.
    pub fn ee_read(ee: &EEPROM, addr: u16) -> u8 {
        while ee.eecr().read().eepe().bit_is_set() {}
        // SAFETY: addresses below 1024 are valid EEAR values.
        ee.eear().write(|w| unsafe { w.bits(addr) });
        ee.eecr().write(|w| w.eere().set_bit());
        ee.eedr().read().bits()
    }

    /// Writes one EEPROM byte (erase and write), interrupts assumed off.
    pub fn ee_write(ee: &EEPROM, addr: u16, value: u8) {
        while ee.eecr().read().eepe().bit_is_set() {}
        // SAFETY: addresses below 1024 are valid EEAR values; any EEDR value is valid.
        ee.eear().write(|w| unsafe { w.bits(addr) });
        ee.eedr().write(|w| unsafe { w.bits(value) });
        ee.eecr().write(|w| w.eempe().set_bit());
        ee.eecr().write(|w| w.eempe().set_bit().eepe().set_bit());
        while ee.eecr().read().eepe().bit_is_set() {}
    }
}
