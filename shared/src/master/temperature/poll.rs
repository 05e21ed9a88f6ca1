//! Which discovered device is which sensor, and which sensor each tick reads.
//!
//! At start-up the master collects up to ten devices (D in total, in search order). A
//! sensor is the first device whose ROM byte 1 is the sensor's entry in
//! [`SENSOR_ROM_BYTE1`]. Each temperature tick reads sensor i and starts a conversion on
//! sensor i + 1, wrapping to 0 when i + 1 = D, so sensor ids ≥ D are never read (as in the
//! original) and each sensor is refreshed every 2·D s.

use super::{Rom, SENSORS, SENSOR_ROM_BYTE1_FLASH};
use crate::exception::{ExceptionType, MasterException};

/// The devices the start-up search found (at most ten; later ones are ignored).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sensors {
    roms: [Rom; SENSORS],
    count: u8,
}

impl Default for Sensors {
    fn default() -> Self {
        Self::new()
    }
}

impl Sensors {
    /// No devices found yet.
    pub const fn new() -> Self {
        Sensors {
            roms: [[0; 8]; SENSORS],
            count: 0,
        }
    }

    /// Adds a device found by the search. Returns false (and ignores it) once ten are
    /// known, as the original collected at most ten.
    pub fn push(&mut self, rom: Rom) -> bool {
        match self.roms.get_mut(usize::from(self.count)) {
            Some(slot) => {
                *slot = rom;
                self.count += 1;
                true
            }
            None => false,
        }
    }

    /// D: how many devices were found.
    pub const fn count(&self) -> u8 {
        self.count
    }

    /// The devices found, in search order.
    pub fn roms(&self) -> &[Rom] {
        &self.roms[..usize::from(self.count)]
    }

    /// The ROM of sensor `sensor` (0 = ambient, n = controller n), if a device with its
    /// ROM byte 1 was found.
    pub fn locate(&self, sensor: u8) -> Option<Rom> {
        let byte1 = SENSOR_ROM_BYTE1_FLASH.get(usize::from(sensor))?;
        self.roms().iter().find(|rom| rom[1] == byte1).copied()
    }
}

/// What one temperature tick does on the OneWire bus.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tick {
    /// Read this sensor's scratchpad (sensor id, ROM) and store the reading in its
    /// register.
    pub read: Option<(u8, Rom)>,
    /// Then start a conversion on this sensor (sensor id, ROM).
    pub convert: Option<(u8, Rom)>,
    /// A sensor id this tick needed that is not on the bus: raise type 10 (slave 0,
    /// motor 0). Its read or conversion is skipped.
    pub missing: Option<u8>,
}

impl Tick {
    /// The exception to raise for this tick: type 10 (sensor missing), slave 0, motor 0,
    /// if a sensor it needed is missing. The firmware hands it to `Schedule::raise`,
    /// which latches it and spreads it to all nine slaves.
    pub const fn exception(&self) -> Option<MasterException> {
        match self.missing {
            Some(_) => Some(MasterException {
                kind: ExceptionType::SensorMissing,
                slave: 0,
                motor: 0,
            }),
            None => None,
        }
    }
}

/// The polling position: the sensor the next tick reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Poller {
    next: u8,
}

impl Poller {
    /// The first tick reads sensor 0.
    pub const fn new() -> Self {
        Poller { next: 0 }
    }

    /// The conversion to start right after the discovery, so that the first tick reads a
    /// measurement: sensor 0's, if it is on the bus.
    pub fn first_conversion(&self, sensors: &Sensors) -> Option<Rom> {
        sensors.locate(self.next)
    }

    /// The sensor the next tick reads.
    pub const fn next(&self) -> u8 {
        self.next
    }

    /// One temperature tick: read sensor i, start a conversion on sensor i + 1 (wrapping
    /// at D), and move on to i + 1.
    pub fn tick(&mut self, sensors: &Sensors) -> Tick {
        let count = sensors.count();
        if count == 0 {
            // Nothing was found, so the ambient sensor, read first, is missing.
            return Tick {
                read: None,
                convert: None,
                missing: Some(0),
            };
        }
        let read_id = self.next % count;
        let convert_id = (read_id + 1) % count;
        self.next = convert_id;
        let read = sensors.locate(read_id).map(|rom| (read_id, rom));
        let convert = sensors.locate(convert_id).map(|rom| (convert_id, rom));
        let missing = match (read, convert) {
            (None, _) => Some(read_id),
            (_, None) => Some(convert_id),
            _ => None,
        };
        Tick {
            read,
            convert,
            missing,
        }
    }
}
