//! The temperature sensors on the OneWire bus (reference §9.1), wired to the decisions
//! of `shared::master::temperature`: the ROM search at boot, and each temperature tick's
//! read of sensor i and conversion on sensor i + 1.
//!
//! A tick's bus work (about 17 ms of OneWire slots) is done one step at a time, a step
//! being the reset pulse or one byte (at most ~1 ms), so idle serves the PC link and
//! the schedule's I2C traffic between steps; OneWire allows any pause between slots.

use drivers::onewire::OneWire;
use drivers::watchdog::Watchdog;
use shared::exception::MasterException;
use shared::master::temperature::{command, reading, Poller, RomSearch, Sensors, SCRATCHPAD_LEN};
use shared::master::LocalRegisters;

/// Steps of a read: reset, MATCH ROM, 8 ROM bytes, READ SCRATCHPAD, 9 scratchpad bytes.
const READ_STEPS: u8 = 20;
/// The first scratchpad byte's step.
const FIRST_PAD_STEP: u8 = 11;

/// The tick under way, if `active` (a plain flag rather than an `Option<Job>`, so the
/// idle state is all zeros and needs no start-up image).
struct Job {
    active: bool,
    /// Sensor to read, if it is on the bus.
    read: Option<u8>,
    /// Sensor to start a conversion on, if it is on the bus.
    convert: Option<u8>,
    /// The next step: 0..READ_STEPS the read, then the conversion's eleven (reset,
    /// MATCH ROM, 8 ROM bytes, CONVERT T).
    step: u8,
    pad: [u8; SCRATCHPAD_LEN],
}

impl Job {
    /// No tick under way.
    const IDLE: Job = Job {
        active: false,
        read: None,
        convert: None,
        step: 0,
        pad: [0; SCRATCHPAD_LEN],
    };
}

/// The sensors found at boot, the polling position and the tick under way; the bus
/// itself is passed in.
// In declaration order, the tick's state first: the AVR reaches it with a short
// displacement from the struct's address, where after the ROMs it needs its own pointer.
#[repr(C)]
pub struct Temperatures {
    job: Job,
    poller: Poller,
    sensors: Sensors,
}

impl Temperatures {
    /// Nothing discovered yet.
    pub const fn new() -> Self {
        Temperatures {
            sensors: Sensors::new(),
            poller: Poller::new(),
            job: Job::IDLE,
        }
    }

    /// Boot: finds the devices on the bus (SEARCH ROM, up to ten), then starts a
    /// conversion on sensor 0 so that the first tick reads a measurement (by the tick's
    /// own steps, as the second half of a tick that reads nothing: `local` is left as it
    /// is). The watchdog is fed once per search pass (~14 ms).
    // In line: its one call site, idle's boot (measured 120 B smaller).
    #[inline(always)]
    pub fn discover(
        &mut self,
        wire: &mut OneWire,
        watchdog: &Watchdog,
        local: &mut LocalRegisters,
    ) {
        let mut search = RomSearch::new();
        while !search.finished() {
            watchdog.feed();
            if !self.search_pass(wire, &mut search) {
                break;
            }
        }
        // The sensor the first tick reads: none found, and the steps do nothing. The job
        // is still `Job::IDLE` (nothing read, a zero pad), so only what differs is set.
        self.job.active = true;
        self.job.convert = Some(self.poller.next());
        self.job.step = READ_STEPS;
        while self.busy() {
            self.step(wire, local);
        }
    }

    /// One pass of the ROM search; false when it found nothing more to keep.
    fn search_pass(&mut self, wire: &mut OneWire, search: &mut RomSearch) -> bool {
        if !wire.reset() {
            return false;
        }
        wire.write_byte(command::SEARCH_ROM);
        for index in 0..64 {
            let bit = wire.read_bit();
            let complement = wire.read_bit();
            match search.step(index, bit, complement) {
                Ok(direction) => wire.write_bit(direction),
                Err(_) => return false,
            }
        }
        match search.finish() {
            Ok(rom) => self.sensors.push(rom),
            Err(_) => false,
        }
    }

    /// A temperature tick is due: decides what it reads and converts, and returns the
    /// exception to raise if a sensor it needs is missing (type 10).
    pub fn start_tick(&mut self) -> Option<MasterException> {
        let plan = self.poller.plan(&self.sensors);
        self.job = Job {
            active: true,
            read: plan.read,
            convert: plan.convert,
            step: 0,
            pad: [0; SCRATCHPAD_LEN],
        };
        plan.exception()
    }

    /// Whether a tick's bus work is under way.
    pub fn busy(&self) -> bool {
        self.job.active
    }

    /// Performs the next step of the tick under way, if any; a finished read lands in
    /// device 0's temperatures (ambient first, then controllers 1..9), or, with a wrong
    /// CRC, marks that sensor as holding no reading.
    #[inline(never)]
    pub fn step(&mut self, wire: &mut OneWire, local: &mut LocalRegisters) {
        let job = &mut self.job;
        if !job.active {
            return;
        }
        let step = job.step;
        job.step += 1;
        let (sensor, n) = if step < READ_STEPS {
            (job.read, step)
        } else {
            (job.convert, step - READ_STEPS)
        };
        let rom = sensor.and_then(|id| self.sensors.find(id));
        let Some((id, rom)) = sensor.zip(rom) else {
            // Nothing to do in this half: skip it.
            if step < READ_STEPS {
                job.step = READ_STEPS;
            } else {
                self.job.active = false;
            }
            return;
        };
        match n {
            0 => {
                wire.reset();
            }
            1 => wire.write_byte(command::MATCH_ROM),
            2..=9 => wire.write_byte(rom[usize::from(n - 2)]),
            10 if step < READ_STEPS => wire.write_byte(command::READ_SCRATCHPAD),
            10 => {
                start_conversion(wire);
                self.job.active = false;
            }
            _ => {
                let byte = wire.read_byte();
                let last = n + 1 == READ_STEPS;
                if let Some(slot) = job.pad.get_mut(usize::from(n - FIRST_PAD_STEP)) {
                    *slot = byte;
                }
                if last {
                    local.set_temperature(id, reading(&job.pad).ok());
                }
            }
        }
    }
}

/// CONVERT T on the addressed sensor, its last slot ending with the line driven high to
/// power the conversion (parasite power, within the datasheet's 10 µs) until the next
/// reset.
fn start_conversion(wire: &mut OneWire) {
    wire.write_byte_powered(command::CONVERT_T);
}
