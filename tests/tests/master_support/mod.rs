//! What the master's emulator tests share: the real master image on an I2C bus with nine
//! Rust slave models, optionally with the rover's OneWire sensors and an RC receiver, and
//! helpers to talk to it as a PC program does.
#![allow(dead_code)]

use std::cell::RefMut;

use harness::bus::{Bus, TargetId, TraceEntry, TwiEvent};
use harness::onewire::OneWireBus;
use harness::rc::RcReceiver;
use harness::twi::I2cTarget;
use harness::Avr;
use shared::regs::{id, BoardKind};

/// Emulated time of one byte at 115200 baud (simavr counts 11 bit times).
pub const BYTE_US: f64 = 93.5;
/// Data-space address of WDTCSR.
pub const WDTCSR: u16 = 0x60;
/// Registers in a slave's table.
const SLAVE_REGS: usize = 45;
/// The paint byte `drivers::stack::paint` fills free RAM with.
const PAINT: u8 = 0xc5;
/// Last SRAM address of the ATmega328P.
const RAMEND: u16 = 0x8ff;

/// A slave board as the master sees it over I2C: the register table of its kind (sizes
/// from `shared`), with the exception behaviour of reference §6: boot exception at power
/// up and after a hard reset (REG_RESET bit 1), left with REG_RESET bit 0, REMOTESLAVE
/// (type 3, motor 5) on any write to REG_EXCEPTIONDATA, only the first exception kept.
/// A read returns the registers from the pointer on, each sized by the table, LSB first.
#[derive(Debug, Clone)]
pub struct Slave {
    addr: u8,
    kind: BoardKind,
    /// Register values (raw), by id; STATUS and EXCEPTIONDATA come from the state below.
    pub regs: [u16; SLAVE_REGS],
    /// In exception (STATUS bit 0).
    pub in_exception: bool,
    /// EXCEPTIONDATA: (motor << 8) | type; kept after a reset.
    pub exception_data: u16,
    /// Every write transaction: the register id, then the value bytes.
    pub writes: Vec<Vec<u8>>,
    /// Read transactions served.
    pub reads: usize,
    pointer: u8,
    fresh: bool,
    buf: Vec<u8>,
    out: Vec<u8>,
}

impl Slave {
    /// Controller `addr` (1..9) at power-up: in its boot exception.
    pub fn new(addr: u8) -> Slave {
        let kind = BoardKind::of_device(addr).expect("a slave address 1..9");
        let mut s = Slave {
            addr,
            kind,
            regs: [0; SLAVE_REGS],
            in_exception: false,
            exception_data: 0,
            writes: Vec::new(),
            reads: 0,
            pointer: 0,
            fresh: false,
            buf: Vec::new(),
            out: Vec::new(),
        };
        s.boot();
        s
    }

    fn boot(&mut self) {
        self.in_exception = true;
        self.exception_data = 0x0502;
    }

    /// Raises an exception on the board (a local fault, or REMOTESLAVE): kept only if
    /// none is.
    pub fn raise(&mut self, kind: u8, motor: u8) {
        if !self.in_exception {
            self.in_exception = true;
            self.exception_data = u16::from(motor) << 8 | u16::from(kind);
        }
    }

    /// REG_STATUS: 8 (DS) or 4 (LL), plus 1 in exception.
    pub fn status(&self) -> u16 {
        let board = if self.kind == BoardKind::DriveSteer {
            8
        } else {
            4
        };
        board | u16::from(self.in_exception)
    }

    fn value(&self, reg: u8) -> u16 {
        match reg {
            id::REG_STATUS => self.status(),
            id::REG_EXCEPTIONDATA => self.exception_data,
            _ => self.regs[usize::from(reg)],
        }
    }

    /// Applies the bytes written after the register id, if any.
    fn apply(&mut self) {
        if self.buf.is_empty() {
            return;
        }
        let mut record = vec![self.pointer];
        record.extend_from_slice(&self.buf);
        self.writes.push(record);
        let mut raw = [0u8; 2];
        for (r, b) in raw.iter_mut().zip(&self.buf) {
            *r = *b;
        }
        let value = u16::from_le_bytes(raw);
        match self.pointer {
            id::REG_RESET => {
                if value & 2 != 0 {
                    self.boot();
                }
                if value & 1 != 0 {
                    self.in_exception = false;
                }
            }
            id::REG_EXCEPTIONDATA => self.raise(3, 5),
            reg => self.regs[usize::from(reg)] = value,
        }
        self.buf.clear();
    }

    /// The writes to register `reg`, value bytes only, in order.
    pub fn writes_to(&self, reg: u8) -> Vec<Vec<u8>> {
        self.writes
            .iter()
            .filter(|w| w[0] == reg)
            .map(|w| w[1..].to_vec())
            .collect()
    }
}

impl I2cTarget for Slave {
    fn start_write(&mut self, addr: u8) -> bool {
        if addr != self.addr {
            return false;
        }
        self.apply();
        self.fresh = true;
        true
    }

    fn write(&mut self, byte: u8) -> bool {
        if self.fresh {
            self.fresh = false;
            self.pointer = if usize::from(byte) < SLAVE_REGS {
                byte
            } else {
                0
            };
        } else {
            self.buf.push(byte);
        }
        true
    }

    fn start_read(&mut self, addr: u8) -> bool {
        if addr != self.addr {
            return false;
        }
        self.apply();
        self.reads += 1;
        self.out.clear();
        for reg in self.pointer..SLAVE_REGS as u8 {
            let size = self.kind.size_of(reg).unwrap_or(1);
            let bytes = self.value(reg).to_le_bytes();
            self.out.extend_from_slice(&bytes[..usize::from(size)]);
        }
        self.out.reverse();
        true
    }

    fn read(&mut self) -> u8 {
        self.out.pop().unwrap_or(0xff)
    }

    fn stop(&mut self) {
        self.apply();
    }
}

/// What to attach to the master besides the slaves.
#[derive(Clone, Copy)]
pub struct Options {
    /// The rover's ten DS18S20s on D6, all at 20.0 °C unless `temps` says otherwise (on
    /// by default: without them every temperature tick raises type 10 once the master's
    /// exception is cleared).
    pub sensors: bool,
    /// Sensors to set before boot: (index, half degrees).
    pub temps: &'static [(usize, i16)],
    /// Sensors missing from the bus at boot.
    pub absent: &'static [usize],
    /// An RC receiver on D2..D4 (off).
    pub rc: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            sensors: true,
            temps: &[],
            absent: &[],
            rc: false,
        }
    }
}

/// The master on a bus with slaves 1..9, booted to `Ready`.
pub struct Rig {
    /// The bus; chip 0 is the master.
    pub bus: Bus,
    /// The slave models, at index address − 1.
    pub slaves: Vec<TargetId<Slave>>,
    /// The temperature sensors, if attached.
    pub sensors: Option<OneWireBus>,
    /// The RC receiver, if attached.
    pub rc: Option<RcReceiver>,
    /// The banner, `Starting` to `Ready`.
    pub banner: String,
    /// Serial bytes received and not yet consumed.
    rx: Vec<u8>,
}

impl Rig {
    /// Slaves and sensors.
    pub fn new() -> Rig {
        Rig::with(Options::default())
    }

    /// With `opts`.
    pub fn with(opts: Options) -> Rig {
        let mut avr = Avr::firmware("master")
            .unwrap_or_else(|e| panic!("master: {e} (build it with scripts/firmware.sh)"));
        let sensors = opts.sensors.then(|| {
            let s = OneWireBus::attach_rover_sensors(&mut avr);
            for &(i, half) in opts.temps {
                s.set_half_degrees(i, half);
            }
            for &i in opts.absent {
                s.set_present(i, false);
            }
            s
        });
        let rc = opts.rc.then(|| RcReceiver::attach(&mut avr));
        let mut bus = Bus::new();
        bus.add_master(avr).unwrap();
        let slaves = (1..=9).map(|a| bus.add_target(Slave::new(a))).collect();
        let mut rig = Rig {
            bus,
            slaves,
            sensors,
            rc,
            banner: String::new(),
            rx: Vec::new(),
        };
        let banner = rig.read_until(b"Ready\r\n", 2_000_000);
        rig.banner = String::from_utf8(banner).unwrap();
        rig
    }

    /// The master chip.
    pub fn avr(&self) -> RefMut<'_, Avr> {
        self.bus.chip(0).unwrap()
    }

    /// Slave model `addr`.
    pub fn slave(&self, addr: u8) -> RefMut<'_, Slave> {
        self.bus
            .target(&self.slaves[usize::from(addr - 1)])
            .unwrap()
    }

    /// Forgets what every slave model recorded.
    pub fn clear_records(&mut self) {
        for addr in 1..=9 {
            let mut s = self.slave(addr);
            s.writes.clear();
            s.reads = 0;
        }
    }

    /// Emulated µs since load.
    pub fn micros(&self) -> u64 {
        self.bus.micros()
    }

    /// Runs for `us`, collecting serial output.
    pub fn run_us(&mut self, us: u64) {
        self.bus.run_us(us);
        self.collect();
    }

    /// Runs until `until_us` (emulated µs since load).
    pub fn run_to(&mut self, until_us: u64) {
        let now = self.micros();
        if until_us > now {
            self.run_us(until_us - now);
        }
    }

    fn collect(&mut self) {
        let fresh = self.avr().uart_take();
        self.rx.extend(fresh);
    }

    /// Runs until the serial output holds `needle`; returns the output up to it.
    pub fn read_until(&mut self, needle: &[u8], max_us: u64) -> Vec<u8> {
        let end = self.micros() + max_us;
        loop {
            self.collect();
            if let Some(at) = self.rx.windows(needle.len()).position(|w| w == needle) {
                return self.rx.drain(..at + needle.len()).collect();
            }
            assert!(
                self.micros() < end,
                "no {:?} within {max_us} us; got {:02x?}",
                String::from_utf8_lossy(needle),
                self.rx
            );
            self.bus.run_us(100);
        }
    }

    /// Runs until `n` serial bytes have arrived (at most `max_us`); returns them.
    pub fn read_exact(&mut self, n: usize, max_us: u64) -> Vec<u8> {
        let end = self.micros() + max_us;
        loop {
            self.collect();
            if self.rx.len() >= n {
                return self.rx.drain(..n).collect();
            }
            assert!(
                self.micros() < end,
                "only {:02x?} of {n} bytes within {max_us} us",
                self.rx
            );
            self.bus.run_cycles(160);
        }
    }

    /// Sends a frame and returns its `n`-byte reply; nothing more may follow within 5 ms.
    pub fn exchange(&mut self, frame: &[u8], n: usize) -> Vec<u8> {
        self.bus.uart_send(0, frame);
        let reply = self.read_exact(n, 500_000);
        self.run_us(5_000);
        assert!(self.rx.is_empty(), "extra bytes {:02x?}", self.rx);
        reply
    }

    /// Sends a frame that must get no reply within 50 ms.
    pub fn silence(&mut self, frame: &[u8]) {
        self.bus.uart_send(0, frame);
        self.run_us(50_000);
        assert!(self.rx.is_empty(), "reply {:02x?} to {frame:02x?}", self.rx);
    }

    /// Reads master registers `ids` through read set 7 (`len` reply bytes).
    pub fn master_regs(&mut self, ids: &[u8], len: usize) -> Vec<u8> {
        let mut frame = vec![3 + ids.len() as u8, 0x04, 7];
        frame.extend_from_slice(ids);
        assert_eq!(self.exchange(&frame, 1), [ids.len() as u8]);
        self.exchange(&[0x03, 0x03, 0x07], len)
    }

    /// REGMASTER_EXCEPTIONDATA.
    pub fn master_exception(&mut self) -> u16 {
        let v = self.master_regs(&[11], 2);
        u16::from_le_bytes([v[0], v[1]])
    }

    /// Writes REGMASTER_RESET: leaves the master's exception.
    pub fn reset_master(&mut self) {
        assert_eq!(self.exchange(&[0x05, 0x02, 0x01, 0x00, 0x01], 1), [0x00]);
    }

    /// The watchdog's prescaler selection (WDP3..0) and whether it resets the chip (WDE).
    pub fn watchdog(&self) -> (u8, bool) {
        watchdog(&self.avr())
    }

    /// Static RAM and the deepest the stack has reached so far, bytes.
    pub fn ram(&self) -> Ram {
        ram(&self.avr())
    }
}

/// The watchdog's prescaler selection and WDE, from WDTCSR.
pub fn watchdog(avr: &Avr) -> (u8, bool) {
    let v = avr.read_data(WDTCSR);
    ((v & 0b111) | ((v >> 2) & 0b1000), v & 0b1000 != 0)
}

/// The master's RAM use: static data and the stack's high-water mark.
#[derive(Debug, Clone, Copy)]
pub struct Ram {
    /// `.data` + `.bss`, bytes.
    pub statics: u16,
    /// RAMEND down to the deepest byte the stack has written, bytes.
    pub stack: u16,
}

impl Ram {
    /// Both together.
    pub fn total(&self) -> u16 {
        self.statics + self.stack
    }
}

/// Reads the master's RAM use: the paint `init` laid from the end of static data up to
/// its stack is still intact below the deepest point the stack reached.
pub fn ram(avr: &Avr) -> Ram {
    let heap = avr.symbol("__heap_start").expect("__heap_start") as u16;
    let deepest = (heap..=RAMEND)
        .find(|&a| avr.read_data(a) != PAINT)
        .unwrap_or(RAMEND);
    Ram {
        statics: heap - 0x100,
        stack: RAMEND + 1 - deepest,
    }
}

/// One I2C transaction from the master, from its bus trace.
#[derive(Debug, Clone)]
pub struct Transaction {
    /// Emulated µs of its START.
    pub start_us: f64,
    /// Emulated µs of its STOP (or of the next START).
    pub end_us: f64,
    /// 7-bit address.
    pub addr: u8,
    /// A read (SLA+R).
    pub read: bool,
    /// The address was acknowledged.
    pub ack: bool,
    /// Bytes written or read.
    pub bytes: Vec<u8>,
}

/// Groups a bus trace into transactions (a repeated START begins a new one).
pub fn transactions(trace: &[TraceEntry]) -> Vec<Transaction> {
    let mut out: Vec<Transaction> = Vec::new();
    let mut open = false;
    for e in trace {
        match e.event {
            TwiEvent::Start { addr, read, ack } => {
                if open {
                    if let Some(t) = out.last_mut() {
                        t.end_us = e.micros();
                    }
                }
                out.push(Transaction {
                    start_us: e.micros(),
                    end_us: e.micros(),
                    addr,
                    read,
                    ack,
                    bytes: Vec::new(),
                });
                open = true;
            }
            TwiEvent::Write { byte, .. } | TwiEvent::Read { byte, .. } => {
                if let Some(t) = out.last_mut() {
                    t.bytes.push(byte);
                    t.end_us = e.micros();
                }
            }
            TwiEvent::Stop => {
                if let Some(t) = out.last_mut() {
                    t.end_us = e.micros();
                }
                open = false;
            }
            _ => {}
        }
    }
    out
}
