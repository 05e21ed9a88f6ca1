//! DS18S20 temperature sensors on a OneWire pin of an emulated chip: the master's D6
//! (PD6) with the rover's ten sensors ([`OneWireBus::attach_rover_sensors`]), or any pin
//! and any ROMs.
//!
//! The firmware bit-bangs the pin as an open drain: DDR = 1 with PORT = 0 pulls the line
//! low; DDR = 0 releases it and the (modelled) external pull-up makes it high unless a
//! device holds it low. The model hooks the port's DDR and PORT writes, stamps them with
//! the chip's cycle count, and answers every read of the port's PIN register with the
//! line's level at that cycle.
//!
//! # Timing
//! - A low pulse of at least 480 µs is a **reset**. Every present sensor answers 30 µs
//!   after the release with a 120-µs **presence** pulse (datasheet: 15–60 µs, 60–240 µs;
//!   [`OneWireBus::set_presence_us`] sets others).
//! - A shorter low pulse is a **time slot**. Sensors sample the line 30 µs after the
//!   falling edge (datasheet: 15–60 µs): a low pulse under 30 µs writes a 1, a longer one
//!   a 0.
//! - In a **read slot** a sensor that sends 0 holds the line low for 30 µs from the
//!   falling edge; the firmware must sample before that (datasheet: within 15 µs).
//! - Pulses outside the datasheet's windows are still decided as above and recorded as
//!   [`TimingViolation`]s: a write slot low for 15–60 µs, a slot low for 120–480 µs, or a
//!   read slot held low by the master for 15 µs or more.
//!
//! # Commands
//! ROM commands SEARCH ROM (0xf0, any number of sensors), MATCH ROM (0x55), SKIP ROM
//! (0xcc) and READ ROM (0x33); function commands CONVERT T (0x44: read slots return 0
//! while converting, 1 when done; 750 ms by default) and READ SCRATCHPAD (0xbe: 9 bytes,
//! CRC last, then 1s). Other commands leave the sensors idle until the next reset. A
//! sensor's scratchpad holds 85 °C until its first conversion, as a real one does. A
//! chip reset drops the transaction under way; conversions go on.
//!
//! # Power
//! Parasite-powered sensors ([`OneWireBus::set_parasite_power`], the rover's) need the
//! master to drive the line high within 10 µs of the end of CONVERT T's last slot and to
//! hold it until the conversion is done (datasheet). A pull-up that comes late, ends
//! early (a slot, a reset, the chip's own reset) or never comes browns the converting
//! sensors out: their scratchpads fall back to 85 °C, and a [`TimingViolation`] says
//! which rule broke.
//!
//! # Example
//! ```no_run
//! use harness::onewire::OneWireBus;
//! use harness::Avr;
//!
//! let mut avr = Avr::firmware("fixture_onewire")?;
//! let sensors = OneWireBus::attach_rover_sensors(&mut avr);
//! sensors.set_half_degrees(3, 51); // controller 3's sensor reads 25.5 °C
//! sensors.set_present(7, false); // controller 7's sensor is unplugged
//! avr.run_us(2_000_000);
//! assert!(sensors.violations().is_empty());
//! # Ok::<(), harness::HarnessError>(())
//! ```

#[path = "onewire_device.rs"]
mod device;
#[path = "onewire_hook.rs"]
pub(crate) mod hook;
#[path = "onewire_rom.rs"]
mod rom;

use std::cell::{Cell, RefCell};
use std::ffi::c_void;
use std::rc::Rc;

use simavr_ffi as ffi;

use crate::avr::{ioctl_def, Shared};
use crate::{uno, Avr, Pin};
use device::Wire;
pub use device::{OneWireStats, TimingViolation, DEFAULT_CONVERSION_US, POWER_ON_HALF_DEGREES};
pub use hook::AttachError;
pub use rom::{crc8, ds18s20_rom, FAMILY_DS18S20, ROVER_SENSOR_ROMS};

/// The master's OneWire pin (D6 = PD6).
pub const MASTER_ONEWIRE_PIN: Pin = uno::D6;

/// Temperature of the rover's sensors when attached: 20.0 °C.
pub const DEFAULT_HALF_DEGREES: i16 = 40;

/// The ioport IRQs the model hooks.
#[derive(Clone, Copy)]
struct PortIrqs {
    ddr: *mut ffi::avr_irq_t,
    port: *mut ffi::avr_irq_t,
    pin_read: *mut ffi::avr_irq_t,
}

/// The model shared by the chip's hooks and the caller's handle.
struct Model {
    wire: RefCell<Wire>,
    /// The chip's core; NULL once the chip is gone.
    core: Cell<*mut ffi::avr_t>,
    /// The chip's monotonic clock; NULL once the chip is gone.
    clock: Cell<*const Shared>,
    /// The last cycle the model saw, for questions asked after the chip is gone.
    last_cycle: Cell<u64>,
    irqs: PortIrqs,
    /// Data-space addresses of the port's PIN, DDR and PORT registers.
    regs: (u16, u16, u16),
    mask: u8,
}

impl Model {
    fn param(self: &Rc<Self>) -> *const c_void {
        Rc::as_ptr(self).cast()
    }

    /// The chip's cycle count (monotonic across resets).
    fn now(&self) -> u64 {
        let clock = self.clock.get();
        if !clock.is_null() {
            // SAFETY: `clock` is the chip's boxed `Shared`, which lives until after the
            // core is terminated; `detach` clears the pointer before that.
            self.last_cycle.set(unsafe { (*clock).now() });
        }
        self.last_cycle.get()
    }

    /// One byte of the chip's data space.
    fn data(&self, addr: u16) -> u8 {
        let core = self.core.get();
        if core.is_null() {
            return 0;
        }
        // SAFETY: a live core's data array covers the I/O registers (addr < 0x100).
        unsafe { *(*core).data.add(usize::from(addr)) }
    }

    /// The master drives DDR and PORT: it pulls the line low when the pin is an output
    /// at 0, and drives it high (a strong pull-up) when the pin is an output at 1.
    fn master_drive(&self, ddr: u8, port: u8) {
        let output = ddr & self.mask != 0;
        let low = output && port & self.mask == 0;
        let high = output && port & self.mask != 0;
        let now = self.now();
        if let Ok(mut wire) = self.wire.try_borrow_mut() {
            // A slot that ends by driving the line high ends first, then powers it.
            wire.master(low, now);
            wire.drive_high(high, now);
        }
    }

    /// The firmware reads the PIN register: give it the line's level now.
    fn pin_read(&self) {
        let core = self.core.get();
        let (pin, ddr, _) = self.regs;
        if core.is_null() || self.data(ddr) & self.mask != 0 {
            return;
        }
        let now = self.now();
        let high = self.wire.try_borrow().is_ok_and(|w| w.line_high(now));
        let value = self.data(pin);
        let value = if high {
            value | self.mask
        } else {
            value & !self.mask
        };
        // SAFETY: as in `data`; simavr returns this byte to the reading instruction
        // after the hook.
        unsafe { *(*core).data.add(usize::from(pin)) = value };
    }
}

unsafe extern "C" fn on_ddr(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    // SAFETY: `param` is the `Model` the core owns (see `hook`); unhooked in `detach`.
    let model = unsafe { &*param.cast::<Model>() };
    model.master_drive(value as u8, model.data(model.regs.2));
}

unsafe extern "C" fn on_port(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    // SAFETY: as in `on_ddr`.
    let model = unsafe { &*param.cast::<Model>() };
    model.master_drive(model.data(model.regs.1), value as u8);
}

unsafe extern "C" fn on_pin_read(_irq: *mut ffi::avr_irq_t, _value: u32, param: *mut c_void) {
    // SAFETY: as in `on_ddr`.
    let model = unsafe { &*param.cast::<Model>() };
    model.pin_read();
}

impl hook::Device for Model {
    fn reset(&self, _avr: *mut ffi::avr_t) {
        // simavr zeroed DDR and PORT without telling their IRQs, which only notify on
        // change: make them agree, or the firmware's first write after the reset could
        // go unseen.
        for irq in [self.irqs.ddr, self.irqs.port] {
            if !irq.is_null() {
                // SAFETY: the IRQ belongs to the live core being reset.
                unsafe { (*irq).value = 0 };
            }
        }
        let now = self.now();
        if let Ok(mut wire) = self.wire.try_borrow_mut() {
            wire.chip_reset(now);
        }
    }

    fn detach(&self, _avr: *mut ffi::avr_t) {
        self.now();
        let param: *const c_void = std::ptr::from_ref(self).cast();
        // SAFETY: the core is still whole during `custom.deinit`; the hooks were
        // registered with these functions and this parameter.
        unsafe {
            hook::unhook(self.irqs.ddr, Some(on_ddr), param);
            hook::unhook(self.irqs.port, Some(on_port), param);
            hook::unhook(self.irqs.pin_read, Some(on_pin_read), param);
        }
        self.core.set(std::ptr::null_mut());
        self.clock.set(std::ptr::null());
    }
}

/// DS18S20 sensors on one OneWire pin of an emulated chip.
pub struct OneWireBus {
    model: Rc<Model>,
}

impl OneWireBus {
    /// Attaches an empty OneWire line with an external pull-up to `pin` of `avr`.
    pub fn attach(avr: &mut Avr, pin: Pin) -> Result<OneWireBus, AttachError> {
        let (Some(regs), port) = (pin.registers(), pin.port_name()) else {
            return Err(AttachError::NoSuchPin {
                port: pin.port,
                bit: pin.bit,
            });
        };
        let core = avr.as_ptr();
        let ctl = ioctl_def(b'i', b'o', b'g', port);
        // SAFETY: a live core; avr_io_getirq returns NULL for an unknown IRQ.
        let irq = |n: u32| unsafe { ffi::avr_io_getirq(core, ctl, n as i32) };
        let irqs = PortIrqs {
            ddr: irq(ffi::IOPORT_IRQ_DIRECTION_ALL),
            port: irq(ffi::IOPORT_IRQ_REG_PORT),
            pin_read: irq(ffi::IOPORT_IRQ_REG_PIN),
        };
        let model = Rc::new(Model {
            wire: RefCell::new(Wire::new()),
            core: Cell::new(core),
            clock: Cell::new(&*avr.shared),
            last_cycle: Cell::new(avr.cycles()),
            irqs,
            regs,
            mask: 1 << pin.bit,
        });
        let param = model.param();
        // SAFETY: the IRQs belong to the live core, and `param` points at the model,
        // which the core keeps alive (through `hook::attach`) until `detach` unhooks it.
        unsafe {
            hook::hook(irqs.ddr, Some(on_ddr), param);
            hook::hook(irqs.port, Some(on_port), param);
            hook::hook(irqs.pin_read, Some(on_pin_read), param);
        }
        hook::attach(core, Rc::clone(&model) as Rc<dyn hook::Device>);
        Ok(OneWireBus { model })
    }

    /// Attaches the rover's ten sensors ([`ROVER_SENSOR_ROMS`], index 0 ambient, n for
    /// controller n) to the master's D6, all at 20.0 °C and parasite-powered, as on the
    /// rover (reference §9.1): a conversion needs the strong pull-up.
    pub fn attach_rover_sensors(avr: &mut Avr) -> OneWireBus {
        let bus = match OneWireBus::attach(avr, MASTER_ONEWIRE_PIN) {
            Ok(bus) => bus,
            // D6 is on port D, which the ATmega328P has.
            Err(e) => unreachable!("{e}"),
        };
        for rom in ROVER_SENSOR_ROMS {
            bus.add_sensor(rom, DEFAULT_HALF_DEGREES);
        }
        bus.set_parasite_power(true);
        bus
    }

    /// Makes the sensors parasite-powered (`true`: each conversion needs the master to
    /// drive the line high within 10 µs of CONVERT T and hold it until the conversion is
    /// done; otherwise the sensors converting reset to 85 °C and a [`TimingViolation`]
    /// is recorded) or externally powered (`false`, the default of [`OneWireBus::attach`]:
    /// the master may poll read slots while they convert).
    pub fn set_parasite_power(&self, parasite: bool) {
        self.model.wire.borrow_mut().set_parasite(parasite);
    }

    /// Adds a DS18S20 with ROM `rom` that measures `half_degrees` (0.5 °C units); returns
    /// its index. Its scratchpad holds 85 °C until its first conversion.
    pub fn add_sensor(&self, rom: [u8; 8], half_degrees: i16) -> usize {
        self.model.wire.borrow_mut().add(rom, half_degrees)
    }

    /// Number of sensors added.
    pub fn len(&self) -> usize {
        self.model.wire.borrow().len()
    }

    /// Whether no sensor was added.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sensor `index`'s ROM.
    pub fn rom(&self, index: usize) -> Option<[u8; 8]> {
        self.model.wire.borrow().rom(index)
    }

    /// Sets the temperature sensor `index` measures, in 0.5 °C units (clamped to
    /// −55..125 °C); its next conversion picks it up.
    ///
    /// # Panics
    /// If no sensor has that index (a mistake in the calling test).
    pub fn set_half_degrees(&self, index: usize, half_degrees: i16) {
        let ok = self
            .model
            .wire
            .borrow_mut()
            .set_half_degrees(index, half_degrees);
        assert!(ok, "no OneWire sensor {index}");
    }

    /// The temperature sensor `index` measures, in 0.5 °C units (as set, clamped).
    pub fn half_degrees(&self, index: usize) -> Option<i16> {
        self.model.wire.borrow().half_degrees(index)
    }

    /// Puts sensor `index` on the line or takes it off (fault injection): a removed
    /// sensor answers nothing, not even a presence pulse.
    ///
    /// # Panics
    /// If no sensor has that index (a mistake in the calling test).
    pub fn set_present(&self, index: usize, present: bool) {
        let ok = self.model.wire.borrow_mut().set_present(index, present);
        assert!(ok, "no OneWire sensor {index}");
    }

    /// Sets when the presence pulse starts after a reset's release and how long it lasts
    /// (default 30 µs and 120 µs; the datasheet allows 15–60 µs and 60–240 µs).
    pub fn set_presence_us(&self, wait_us: u64, length_us: u64) {
        let us = crate::F_CPU / 1_000_000;
        self.model
            .wire
            .borrow_mut()
            .set_presence(wait_us.saturating_mul(us), length_us.saturating_mul(us));
    }

    /// Sets how long a conversion takes (default 750 ms).
    pub fn set_conversion_us(&self, us: u64) {
        self.model
            .wire
            .borrow_mut()
            .set_conversion_cycles(us.saturating_mul(crate::F_CPU / 1_000_000));
    }

    /// Sensor `index`'s scratchpad now (9 bytes, CRC last).
    pub fn scratchpad(&self, index: usize) -> Option<[u8; 9]> {
        let now = self.model.now();
        self.model.wire.borrow_mut().scratchpad(index, now)
    }

    /// Whether the line is high now.
    pub fn line_high(&self) -> bool {
        let now = self.model.now();
        self.model.wire.borrow().line_high(now)
    }

    /// Counts of resets, presence pulses, slots, conversions and scratchpad reads.
    pub fn stats(&self) -> OneWireStats {
        self.model.wire.borrow().stats()
    }

    /// Every slot or pulse so far that was outside the datasheet's timing.
    pub fn violations(&self) -> Vec<TimingViolation> {
        self.model.wire.borrow().violations().to_vec()
    }
}
