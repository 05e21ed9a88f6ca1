//! Naming of the ATmega328P's GPIO pins, with the Arduino Uno's D/A numbering.

/// One GPIO pin: a port letter (`'B'`, `'C'` or `'D'`) and a bit number 0..=7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Pin {
    /// Port letter, upper case.
    pub port: char,
    /// Bit within the port, 0..=7.
    pub bit: u8,
}

impl Pin {
    /// The pin `bit` of `port`, e.g. `Pin::new('B', 5)` for the Uno's D13.
    pub const fn new(port: char, bit: u8) -> Pin {
        Pin { port, bit }
    }

    /// The Arduino Uno's digital pin `n` (0..=13): D0..D7 are PD0..PD7, D8..D13 are PB0..PB5.
    ///
    /// # Panics
    /// If `n` is above 13 (a mistake in the calling test).
    pub const fn d(n: u8) -> Pin {
        match n {
            0..=7 => Pin::new('D', n),
            8..=13 => Pin::new('B', n - 8),
            _ => panic!("the Uno has digital pins D0..D13 only"),
        }
    }

    /// The Arduino Uno's analog pin `n` (0..=5) used as GPIO: A0..A5 are PC0..PC5.
    ///
    /// # Panics
    /// If `n` is above 5 (a mistake in the calling test).
    pub const fn a(n: u8) -> Pin {
        match n {
            0..=5 => Pin::new('C', n),
            _ => panic!("the Uno has analog pins A0..A5 only"),
        }
    }

    /// Data-space addresses of this pin's (PINx, DDRx, PORTx) registers, if the port exists.
    pub(crate) fn registers(self) -> Option<(u16, u16, u16)> {
        let base = match self.port {
            'B' | 'b' => 0x23,
            'C' | 'c' => 0x26,
            'D' | 'd' => 0x29,
            _ => return None,
        };
        (self.bit < 8).then_some((base, base + 1, base + 2))
    }

    /// The upper-case port letter as simavr names it.
    pub(crate) fn port_name(self) -> u8 {
        self.port.to_ascii_uppercase() as u8
    }
}

/// Uno digital pins D0..D13.
#[allow(missing_docs)]
pub mod uno {
    use super::Pin;
    pub const D0: Pin = Pin::d(0);
    pub const D1: Pin = Pin::d(1);
    pub const D2: Pin = Pin::d(2);
    pub const D3: Pin = Pin::d(3);
    pub const D4: Pin = Pin::d(4);
    pub const D5: Pin = Pin::d(5);
    pub const D6: Pin = Pin::d(6);
    pub const D7: Pin = Pin::d(7);
    pub const D8: Pin = Pin::d(8);
    pub const D9: Pin = Pin::d(9);
    pub const D10: Pin = Pin::d(10);
    pub const D11: Pin = Pin::d(11);
    pub const D12: Pin = Pin::d(12);
    pub const D13: Pin = Pin::d(13);
    pub const A0: Pin = Pin::a(0);
    pub const A1: Pin = Pin::a(1);
    pub const A2: Pin = Pin::a(2);
    pub const A3: Pin = Pin::a(3);
    pub const A4: Pin = Pin::a(4);
    pub const A5: Pin = Pin::a(5);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uno_numbering() {
        assert_eq!(Pin::d(0), Pin::new('D', 0));
        assert_eq!(Pin::d(9), Pin::new('B', 1));
        assert_eq!(Pin::d(13), Pin::new('B', 5));
        assert_eq!(Pin::a(2), Pin::new('C', 2));
        assert_eq!(uno::A5, Pin::new('C', 5));
    }

    #[test]
    fn register_addresses() {
        assert_eq!(Pin::d(13).registers(), Some((0x23, 0x24, 0x25)));
        assert_eq!(Pin::a(0).registers(), Some((0x26, 0x27, 0x28)));
        assert_eq!(Pin::d(2).registers(), Some((0x29, 0x2A, 0x2B)));
        assert_eq!(Pin::new('E', 0).registers(), None);
        assert_eq!(Pin::new('B', 8).registers(), None);
    }
}
