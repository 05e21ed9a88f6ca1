//! A ready-made Rust slave: a register file that records everything it is told.

use super::I2cTarget;

/// One bus event as a [`RegisterTarget`] saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetEvent {
    /// Addressed for writing (and acknowledged).
    StartWrite,
    /// Addressed for reading (and acknowledged).
    StartRead,
    /// A data byte written by the master.
    Write(u8),
    /// A data byte the master read.
    Read(u8),
    /// STOP.
    Stop,
}

/// A register-file slave at one address, behaving like the `fixture_twi_slave` firmware for
/// its 16 byte registers: a write `[id, d0, d1, …]` selects register `id` (ids past the end
/// select 0) and stores from there on; a read returns bytes from the selected register on.
/// The pointer wraps at the end of the file.
#[derive(Debug, Clone)]
pub struct RegisterTarget {
    addr: u8,
    /// The register contents.
    pub regs: Vec<u8>,
    pointer: usize,
    fresh: bool,
    /// Every event of every transaction addressed to this target, in order.
    pub events: Vec<TargetEvent>,
}

impl RegisterTarget {
    /// A target at 7-bit address `addr` with `size` registers (at least one), all zero.
    pub fn new(addr: u8, size: usize) -> RegisterTarget {
        RegisterTarget {
            addr,
            regs: vec![0; size.max(1)],
            pointer: 0,
            fresh: false,
            events: Vec::new(),
        }
    }

    /// The bytes the master wrote, one vector per write transaction (register id first).
    pub fn writes(&self) -> Vec<Vec<u8>> {
        let mut out = Vec::new();
        let mut current: Option<Vec<u8>> = None;
        for event in &self.events {
            match *event {
                TargetEvent::StartWrite => {
                    out.extend(current.take());
                    current = Some(Vec::new());
                }
                TargetEvent::Write(b) => {
                    if let Some(bytes) = current.as_mut() {
                        bytes.push(b);
                    }
                }
                TargetEvent::StartRead | TargetEvent::Stop => out.extend(current.take()),
                TargetEvent::Read(_) => {}
            }
        }
        out.extend(current);
        out
    }

    fn advance(&mut self) {
        self.pointer = (self.pointer + 1) % self.regs.len();
    }
}

impl I2cTarget for RegisterTarget {
    fn start_write(&mut self, addr: u8) -> bool {
        if addr != self.addr {
            return false;
        }
        self.fresh = true;
        self.events.push(TargetEvent::StartWrite);
        true
    }

    fn write(&mut self, byte: u8) -> bool {
        self.events.push(TargetEvent::Write(byte));
        if self.fresh {
            self.fresh = false;
            let id = usize::from(byte);
            self.pointer = if id < self.regs.len() { id } else { 0 };
        } else {
            if let Some(reg) = self.regs.get_mut(self.pointer) {
                *reg = byte;
            }
            self.advance();
        }
        true
    }

    fn start_read(&mut self, addr: u8) -> bool {
        if addr != self.addr {
            return false;
        }
        self.events.push(TargetEvent::StartRead);
        true
    }

    fn read(&mut self) -> u8 {
        let byte = self.regs.get(self.pointer).copied().unwrap_or(0);
        self.advance();
        self.events.push(TargetEvent::Read(byte));
        byte
    }

    fn stop(&mut self) {
        self.events.push(TargetEvent::Stop);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_file_stores_and_reads_back() {
        let mut t = RegisterTarget::new(0x20, 4);
        assert!(!t.start_write(0x21));
        assert!(t.start_write(0x20));
        assert!(t.write(2));
        assert!(t.write(0xAA));
        assert!(t.write(0xBB));
        assert!(t.write(0xCC));
        t.stop();
        assert_eq!(t.regs, vec![0xCC, 0, 0xAA, 0xBB]);
        assert!(t.start_write(0x20));
        assert!(t.write(3));
        assert!(t.start_read(0x20));
        assert_eq!([t.read(), t.read()], [0xBB, 0xCC]);
        t.stop();
        assert_eq!(t.writes(), vec![vec![2, 0xAA, 0xBB, 0xCC], vec![3]]);
    }

    #[test]
    fn out_of_range_id_selects_register_zero() {
        let mut t = RegisterTarget::new(1, 2);
        t.regs = vec![7, 8];
        assert!(t.start_write(1));
        assert!(t.write(9));
        assert!(t.start_read(1));
        assert_eq!(t.read(), 7);
    }
}
