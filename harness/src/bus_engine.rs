//! Routing on the bus: which device a transaction addresses, what each event does to it, and the
//! log of it all. Master chips and the Rust master peer drive it through the same calls.

use std::collections::BTreeSet;

use super::trace::{Initiator, TraceEntry, TwiEvent};
use crate::twi::chip::{Listen, SlaveChip};
use crate::twi::{cond, I2cTarget, TwiError, TwiMsg};

/// The byte a master reads when nobody drives the bus (SDA pulled up).
const IDLE_BYTE: u8 = 0xFF;

/// A device that can be addressed on the bus.
pub(crate) enum Device {
    /// An emulated chip running slave firmware.
    Chip(SlaveChip),
    /// A slave model written in Rust.
    Target(Box<dyn I2cTarget>),
}

/// The transaction in progress.
struct Active {
    by: Initiator,
    addr: u8,
    /// Index into `devices`, if a device acknowledged the address.
    device: Option<usize>,
    read: bool,
    /// For a slave chip being read: the byte its firmware left in TWDR.
    pending: u8,
    /// Data bytes written so far in this transaction.
    written: usize,
}

/// The bus's routing state.
pub(crate) struct Engine {
    pub devices: Vec<Device>,
    active: Option<Active>,
    cut: BTreeSet<u8>,
    trace: Vec<TraceEntry>,
    pub tracing: bool,
    /// Longest a slave chip may take to release the bus, in its cycles.
    pub answer_budget: u64,
    /// Pass simavr's STOP-after-read on to slave chips (see the `twi` module docs).
    pub stop_after_read: bool,
    /// Clock of the last slave chip that answered, or 0.
    pub last_answer: u64,
    /// The slave chip holding SCL low (device index, address): it took an event and its
    /// firmware did not release the bus within the bounded wait. Nothing moves on the bus
    /// until it does ([`Engine::release_if_free`]).
    held: Option<(usize, u8)>,
}

impl Engine {
    pub fn new(answer_budget: u64) -> Engine {
        Engine {
            devices: Vec::new(),
            active: None,
            cut: BTreeSet::new(),
            trace: Vec::new(),
            tracing: true,
            answer_budget,
            stop_after_read: false,
            last_answer: 0,
            held: None,
        }
    }

    /// The address of the slave chip holding SCL low, if one does.
    pub fn held_by(&self) -> Option<u8> {
        self.held.map(|(_, addr)| addr)
    }

    /// Ends the hold once its chip lets SCL go (its firmware cleared TWINT, switched the
    /// TWI off, or the chip reset). The transaction in progress is abandoned: its master
    /// has given up the step it was waiting for. Returns whether the bus is free of a hold.
    pub fn release_if_free(&mut self, cycle: u64) -> bool {
        let Some((device, addr)) = self.held else {
            return true;
        };
        let holds = match self.devices.get(device) {
            Some(Device::Chip(chip)) => chip.holds_scl(),
            _ => false,
        };
        if holds {
            return false;
        }
        self.held = None;
        let by = self.active.take().map_or(Initiator::Peer, |a| a.by);
        self.log(cycle, by, TwiEvent::Released { addr });
        true
    }

    /// True while a transaction (begun by anyone) has not ended with STOP.
    pub fn busy(&self) -> bool {
        self.active.is_some()
    }

    pub fn cut(&mut self, addr: u8) {
        self.cut.insert(addr);
    }

    pub fn restore(&mut self, addr: u8) {
        self.cut.remove(&addr);
    }

    pub fn is_cut(&self, addr: u8) -> bool {
        self.cut.contains(&addr)
    }

    pub fn trace(&self) -> &[TraceEntry] {
        &self.trace
    }

    pub fn take_trace(&mut self) -> Vec<TraceEntry> {
        std::mem::take(&mut self.trace)
    }

    pub fn target_mut(&mut self, index: usize) -> Option<&mut dyn I2cTarget> {
        match self.devices.get_mut(index)? {
            Device::Target(t) => Some(t.as_mut()),
            Device::Chip(_) => None,
        }
    }

    fn log(&mut self, cycle: u64, by: Initiator, event: TwiEvent) {
        if self.tracing {
            self.trace.push(TraceEntry { cycle, by, event });
        }
    }

    /// Runs one delivery to a slave chip, noting when it answered.
    fn deliver(&mut self, device: usize, msg: TwiMsg, addr: u8) -> Result<TwiMsg, TwiError> {
        let Some(Device::Chip(chip)) = self.devices.get(device) else {
            return Err(TwiError::AddressNack { addr });
        };
        let result = chip.deliver(msg, addr, self.answer_budget);
        self.last_answer = self.last_answer.max(chip.cycles());
        if matches!(result, Err(TwiError::Timeout { .. })) && chip.holds_scl() {
            self.held = Some((device, addr));
        }
        result
    }

    /// START (or repeated START) and the address byte. Ok means acknowledged.
    pub fn start(
        &mut self,
        by: Initiator,
        addr: u8,
        read: bool,
        cycle: u64,
    ) -> Result<(), TwiError> {
        if self.active.as_ref().is_some_and(|a| a.by != by) {
            self.log(cycle, by, TwiEvent::Collision { addr });
            return Err(TwiError::AddressNack { addr });
        }
        if let Some(previous) = self.active.take() {
            self.release(previous, true, cycle);
        }
        let mut active = Active {
            by,
            addr,
            device: None,
            read,
            pending: IDLE_BYTE,
            written: 0,
        };
        let selected = self.select(addr, read);
        let result = match selected {
            Ok(Some((device, pending))) => {
                active.device = Some(device);
                active.pending = pending;
                Ok(())
            }
            Ok(None) => Err(TwiError::AddressNack { addr }),
            Err(e) => Err(e),
        };
        let ack = result.is_ok();
        self.log(cycle, by, TwiEvent::Start { addr, read, ack });
        if result.is_err() && !matches!(result, Err(TwiError::AddressNack { .. })) {
            self.log(cycle, by, TwiEvent::Timeout { addr });
        }
        self.active = Some(active);
        result
    }

    /// Finds the device that acknowledges `addr`, and for a slave chip hands it the START.
    /// Returns its index and, for a chip, the byte its firmware left in TWDR.
    fn select(&mut self, addr: u8, read: bool) -> Result<Option<(usize, u8)>, TwiError> {
        if self.is_cut(addr) {
            return Ok(None);
        }
        for index in 0..self.devices.len() {
            let listen = match &mut self.devices[index] {
                Device::Chip(chip) => chip.listens(addr),
                Device::Target(target) => {
                    let ack = if read {
                        target.start_read(addr)
                    } else {
                        target.start_write(addr)
                    };
                    if ack {
                        return Ok(Some((index, IDLE_BYTE)));
                    }
                    Listen::NotMe
                }
            };
            match listen {
                Listen::NotMe => {}
                Listen::Me { ack: false } => return Ok(None),
                Listen::Me { ack: true } => {
                    let dir = if read { 0 } else { cond::WRITE };
                    let msg = TwiMsg::new(cond::START | cond::ADDR | dir, addr, 0);
                    let answer = self.deliver(index, msg, addr)?;
                    return Ok(Some((index, answer.data)));
                }
            }
        }
        Ok(None)
    }

    /// The device of the caller's transaction, unless it is absent or cut off.
    fn addressed(&mut self, by: Initiator) -> Option<&mut Active> {
        let active = self.active.as_mut().filter(|a| a.by == by)?;
        if self.cut.contains(&active.addr) {
            active.device = None;
        }
        Some(active)
    }

    /// A data byte from the master. Ok means acknowledged.
    pub fn write(&mut self, by: Initiator, byte: u8, cycle: u64) -> Result<(), TwiError> {
        let Some(active) = self.addressed(by) else {
            return Err(TwiError::DataNack { addr: 0, index: 0 });
        };
        let (addr, index, device) = (active.addr, active.written, active.device);
        active.written += 1;
        let result = match device {
            None => Err(TwiError::DataNack { addr, index }),
            Some(d) => self.write_to(d, addr, byte, index),
        };
        let ack = result.is_ok();
        self.log(cycle, by, TwiEvent::Write { byte, ack });
        if let Err(TwiError::Timeout { .. }) = result {
            self.log(cycle, by, TwiEvent::Timeout { addr });
            self.drop_device(by);
        }
        result
    }

    fn write_to(
        &mut self,
        device: usize,
        addr: u8,
        byte: u8,
        index: usize,
    ) -> Result<(), TwiError> {
        let nack = TwiError::DataNack { addr, index };
        let ack = match self.devices.get_mut(device) {
            Some(Device::Target(target)) => target.write(byte),
            Some(Device::Chip(chip)) => {
                // A real TWI acknowledges by the TWEA its firmware set before the byte came.
                let ack = chip.acks();
                self.deliver(device, TwiMsg::new(cond::WRITE, addr, byte), addr)?;
                ack
            }
            None => false,
        };
        if ack {
            Ok(())
        } else {
            Err(nack)
        }
    }

    /// One byte read by the master; `ack` is the master's acknowledge (more bytes wanted).
    pub fn read(&mut self, by: Initiator, ack: bool, cycle: u64) -> Result<u8, TwiError> {
        let Some(active) = self.addressed(by) else {
            return Ok(IDLE_BYTE);
        };
        let (addr, device, pending) = (active.addr, active.device, active.pending);
        let result = match device.and_then(|d| self.devices.get_mut(d).map(|dev| (d, dev))) {
            Some((_, Device::Target(target))) => Ok(target.read()),
            Some((d, Device::Chip(_))) => {
                let flags = cond::READ | if ack { cond::ACK } else { 0 };
                let answer = self.deliver(d, TwiMsg::new(flags, addr, 0), addr);
                answer.map(|answer| {
                    if let Some(active) = self.active.as_mut() {
                        active.pending = answer.data;
                    }
                    pending
                })
            }
            None => Ok(IDLE_BYTE),
        };
        let byte = *result.as_ref().unwrap_or(&pending);
        self.log(cycle, by, TwiEvent::Read { byte, ack });
        if result.is_err() {
            self.log(cycle, by, TwiEvent::Timeout { addr });
            self.drop_device(by);
        }
        result
    }

    /// STOP from the master that owns the transaction.
    pub fn stop(&mut self, by: Initiator, cycle: u64) {
        if self.active.as_ref().is_some_and(|a| a.by == by) {
            if let Some(active) = self.active.take() {
                self.release(active, false, cycle);
            }
            self.log(cycle, by, TwiEvent::Stop);
        }
    }

    /// The end of one addressed part: STOP (`repeated` false) or a repeated START.
    fn release(&mut self, active: Active, repeated: bool, cycle: u64) {
        let Some(device) = active.device.filter(|_| !self.is_cut(active.addr)) else {
            return;
        };
        let is_chip = match self.devices.get_mut(device) {
            Some(Device::Target(target)) => {
                if !repeated {
                    target.stop();
                }
                false
            }
            Some(Device::Chip(_)) => true,
            None => false,
        };
        // A receiver sees STOP and repeated START as 0xA0; a transmitter (after the master's
        // final NACK) is no longer addressed and sees nothing, unless simavr's own behaviour
        // is asked for.
        if is_chip && (!active.read || (self.stop_after_read && !repeated)) {
            let msg = TwiMsg::new(cond::STOP, active.addr, 0);
            if self.deliver(device, msg, active.addr).is_err() {
                self.log(cycle, active.by, TwiEvent::Timeout { addr: active.addr });
            }
        }
    }

    /// Forgets the device of a transaction after it timed out.
    fn drop_device(&mut self, by: Initiator) {
        if let Some(active) = self.active.as_mut().filter(|a| a.by == by) {
            active.device = None;
        }
    }

    /// Handles one message from a master chip's TWI output; returns its answer.
    pub fn on_master_msg(&mut self, chip: usize, msg: TwiMsg, cycle: u64) -> Option<TwiMsg> {
        // SCL held low: nothing reaches any device, and the master chip's TWINT is held
        // back (`twi::port::gate_twint`), so this step never completes for it.
        if self.held.is_some() {
            return None;
        }
        let by = Initiator::Chip(chip);
        let ack = |ok: bool| Some(TwiMsg::new(cond::ACK, msg.addr, u8::from(ok)));
        if msg.has(cond::START) {
            let ok = self
                .start(by, msg.addr >> 1, msg.addr & 1 == 1, cycle)
                .is_ok();
            ack(ok)
        } else if msg.has(cond::STOP) {
            self.stop(by, cycle);
            None
        } else if msg.has(cond::WRITE) {
            let ok = self.write(by, msg.data, cycle).is_ok();
            ack(ok)
        } else if msg.has(cond::READ) {
            let byte = self
                .read(by, msg.has(cond::ACK), cycle)
                .unwrap_or(IDLE_BYTE);
            Some(TwiMsg::new(cond::READ, msg.addr, byte))
        } else {
            None
        }
    }
}
