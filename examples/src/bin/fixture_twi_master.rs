//! Test firmware: an I2C bus master driven by text commands on UART0 (115200 8N1).
//!
//! Demonstrates the master side of the emulated I2C bus (`harness::bus`). At boot it sets the bus
//! to 100 kHz (TWBR 72, prescaler 1) and prints `twi master`. Each command is one line of
//! hexadecimal tokens; every answer is one line:
//! - `w AA D0 D1 …` writes the bytes to 7-bit address AA in one transaction → `ok`
//! - `r AA NN` reads NN bytes (1..=32) from AA → `= B0 B1 …`
//! - `x AA RR NN` writes `[RR]`, STOP, then reads NN bytes (the rover's register read) → `= B0 …`
//! - `f BB P` sets TWBR = BB and the prescaler bits TWPS = P → `ok`
//!
//! Failures answer `nack` (address or data not acknowledged), `err` (bus error, lost
//! arbitration or no TWI status in time) or `?` (a line that does not parse).

#![no_std]
#![no_main]

use avr_device::atmega328p::{TWI, USART0};

/// UBRR0 for 115200 baud at 16 MHz with U2X0 set.
const UBRR_115200: u16 = 16;
/// TWBR for 100 kHz at 16 MHz with prescaler 1.
const TWBR_100K: u8 = 72;
/// Longest line and longest transfer (the Wire buffer size).
const MAX_LINE: usize = 80;
const MAX_DATA: usize = 32;
/// Polls of TWINT before a transfer step gives up (far longer than any byte at 3.9 kHz).
const TWINT_POLLS: u32 = 400_000;

/// TWI status codes (TWSR with the prescaler bits masked off).
mod status {
    pub const START: u8 = 0x08;
    pub const REP_START: u8 = 0x10;
    pub const MT_SLA_ACK: u8 = 0x18;
    pub const MT_DATA_ACK: u8 = 0x28;
    pub const MR_SLA_ACK: u8 = 0x40;
    pub const MR_DATA_ACK: u8 = 0x50;
    pub const MR_DATA_NACK: u8 = 0x58;
    /// NACK after SLA+W, data, or SLA+R.
    pub const NACKS: [u8; 3] = [0x20, 0x30, 0x48];
}

/// Why a transfer failed.
enum Fail {
    /// The slave did not acknowledge its address or a byte.
    Nack,
    /// Bus error, lost arbitration, or TWINT never came.
    Bus,
}

/// Polled UART0.
struct Serial(USART0);

impl Serial {
    fn new(usart: USART0) -> Self {
        // UCSR0A and UCSR0C first: the emulator applies the baud rate when UBRR0 is written.
        usart.ucsr0a().write(|w| w.u2x0().set_bit());
        usart.ucsr0c().write(|w| w.ucsz0().chr8());
        usart
            .ucsr0b()
            .write(|w| w.txen0().set_bit().rxen0().set_bit());
        usart.ubrr0().write(|w| w.set(UBRR_115200));
        Serial(usart)
    }

    fn put(&self, byte: u8) {
        while self.0.ucsr0a().read().udre0().bit_is_clear() {}
        self.0.udr0().write(|w| w.set(byte));
    }

    fn print(&self, text: &[u8]) {
        for &b in text {
            self.put(b);
        }
    }

    fn hex(&self, byte: u8) {
        const DIGITS: &[u8; 16] = b"0123456789ABCDEF";
        self.put(DIGITS[usize::from(byte >> 4)]);
        self.put(DIGITS[usize::from(byte & 0x0F)]);
    }

    /// Blocks until a whole line is in `buf`; returns its length (without the newline).
    fn line(&self, buf: &mut [u8; MAX_LINE]) -> usize {
        let mut len = 0;
        loop {
            while self.0.ucsr0a().read().rxc0().bit_is_clear() {}
            let b = self.0.udr0().read().bits();
            match b {
                b'\n' | b'\r' if len > 0 => return len,
                b'\n' | b'\r' => {}
                _ if len < MAX_LINE => {
                    buf[len] = b;
                    len += 1;
                }
                _ => {}
            }
        }
    }
}

/// Polled TWI master.
struct Master(TWI);

impl Master {
    fn new(twi: TWI) -> Self {
        let m = Master(twi);
        m.speed(TWBR_100K, 0);
        m
    }

    fn speed(&self, twbr: u8, prescaler: u8) {
        self.0.twbr().write(|w| w.set(twbr));
        // SAFETY: TWPS takes any 2-bit value; the status bits are read-only in hardware.
        self.0.twsr().write(|w| unsafe { w.bits(prescaler & 0x03) });
    }

    /// Waits for TWINT and returns the status code.
    fn wait(&self) -> Result<u8, Fail> {
        for _ in 0..TWINT_POLLS {
            if self.0.twcr().read().twint().bit_is_set() {
                return Ok(self.0.twsr().read().bits() & 0xF8);
            }
        }
        Err(Fail::Bus)
    }

    fn expect(&self, want: u8) -> Result<(), Fail> {
        match self.wait()? {
            code if code == want => Ok(()),
            code if status::NACKS.contains(&code) => Err(Fail::Nack),
            _ => Err(Fail::Bus),
        }
    }

    /// START (or repeated START) and the address byte.
    fn start(&self, addr: u8, read: bool) -> Result<(), Fail> {
        self.0
            .twcr()
            .write(|w| w.twint().set_bit().twsta().set_bit().twen().set_bit());
        match self.wait()? {
            status::START | status::REP_START => {}
            _ => return Err(Fail::Bus),
        }
        self.0.twdr().write(|w| w.set((addr << 1) | u8::from(read)));
        self.0
            .twcr()
            .write(|w| w.twint().set_bit().twen().set_bit());
        self.expect(if read {
            status::MR_SLA_ACK
        } else {
            status::MT_SLA_ACK
        })
    }

    fn stop(&self) {
        self.0
            .twcr()
            .write(|w| w.twint().set_bit().twsto().set_bit().twen().set_bit());
    }

    fn write(&self, addr: u8, data: &[u8]) -> Result<(), Fail> {
        let result = self.start(addr, false).and_then(|()| {
            for &b in data {
                self.0.twdr().write(|w| w.set(b));
                self.0
                    .twcr()
                    .write(|w| w.twint().set_bit().twen().set_bit());
                self.expect(status::MT_DATA_ACK)?;
            }
            Ok(())
        });
        self.stop();
        result
    }

    fn read(&self, addr: u8, out: &mut [u8]) -> Result<(), Fail> {
        let result = self.start(addr, true).and_then(|()| {
            let last = out.len().saturating_sub(1);
            for (i, slot) in out.iter_mut().enumerate() {
                let more = i < last;
                self.0
                    .twcr()
                    .write(|w| w.twint().set_bit().twea().bit(more).twen().set_bit());
                let want = if more {
                    status::MR_DATA_ACK
                } else {
                    status::MR_DATA_NACK
                };
                if self.wait()? != want {
                    return Err(Fail::Bus);
                }
                *slot = self.0.twdr().read().bits();
            }
            Ok(())
        });
        self.stop();
        result
    }
}

/// Parses the hexadecimal tokens after the command letter into `out`; returns how many.
fn parse_hex(text: &[u8], out: &mut [u8; MAX_DATA + 2]) -> Option<usize> {
    let mut count = 0;
    for token in text.split(|&c| c == b' ').filter(|t| !t.is_empty()) {
        if token.len() > 2 || count == out.len() {
            return None;
        }
        let mut value = 0u8;
        for &c in token {
            let digit = match c {
                b'0'..=b'9' => c - b'0',
                b'a'..=b'f' => c - b'a' + 10,
                b'A'..=b'F' => c - b'A' + 10,
                _ => return None,
            };
            value = (value << 4) | digit;
        }
        out[count] = value;
        count += 1;
    }
    Some(count)
}

/// What a command line asks for.
enum Command<'a> {
    Write(u8, &'a [u8]),
    Read(u8, usize),
    RegisterRead(u8, u8, usize),
    Speed(u8, u8),
}

fn parse<'a>(line: &[u8], args: &'a mut [u8; MAX_DATA + 2]) -> Option<Command<'a>> {
    let (&letter, rest) = line.split_first()?;
    let n = parse_hex(rest, args)?;
    let args = &args[..n];
    let count = |n: u8| {
        (1..=MAX_DATA)
            .contains(&usize::from(n))
            .then_some(usize::from(n))
    };
    match (letter, args) {
        (b'w', [addr, data @ ..]) if data.len() <= MAX_DATA => Some(Command::Write(*addr, data)),
        (b'r', &[addr, n]) => Some(Command::Read(addr, count(n)?)),
        (b'x', &[addr, reg, n]) => Some(Command::RegisterRead(addr, reg, count(n)?)),
        (b'f', &[twbr, ps]) => Some(Command::Speed(twbr, ps)),
        _ => None,
    }
}

fn answer(serial: &Serial, result: Result<&[u8], Fail>) {
    match result {
        Ok([]) => serial.print(b"ok"),
        Ok(bytes) => {
            serial.put(b'=');
            for &b in bytes {
                serial.put(b' ');
                serial.hex(b);
            }
        }
        Err(Fail::Nack) => serial.print(b"nack"),
        Err(Fail::Bus) => serial.print(b"err"),
    }
    serial.put(b'\n');
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let serial = Serial::new(dp.USART0);
    let master = Master::new(dp.TWI);
    serial.print(b"twi master\n");

    let mut line = [0u8; MAX_LINE];
    let mut args = [0u8; MAX_DATA + 2];
    let mut data = [0u8; MAX_DATA];
    loop {
        let len = serial.line(&mut line);
        match parse(&line[..len], &mut args) {
            Some(Command::Write(addr, bytes)) => {
                answer(&serial, master.write(addr, bytes).map(|()| &[][..]))
            }
            Some(Command::Read(addr, n)) => {
                let out = &mut data[..n];
                let result = master.read(addr, out);
                answer(&serial, result.map(|()| &*out));
            }
            Some(Command::RegisterRead(addr, reg, n)) => {
                let out = &mut data[..n];
                let result = master
                    .write(addr, &[reg])
                    .and_then(|()| master.read(addr, out));
                answer(&serial, result.map(|()| &*out));
            }
            Some(Command::Speed(twbr, ps)) => {
                master.speed(twbr, ps);
                answer(&serial, Ok(&[]));
            }
            None => serial.print(b"?\n"),
        }
    }
}

firmware_examples::spin_on_panic!();
