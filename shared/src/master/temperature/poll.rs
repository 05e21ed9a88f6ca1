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
// In declaration order, the count first: the AVR reaches it with a short displacement
// from the struct's address.
#[repr(C)]
pub struct Sensors {
    count: u8,
    roms: [Rom; SENSORS],
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
        // `count` ≤ the slots (`push` stops there).
        self.roms.get(..usize::from(self.count)).unwrap_or_default()
    }

    /// The ROM of sensor `sensor` (0 = ambient, n = controller n), if a device with its
    /// ROM byte 1 was found.
    pub fn locate(&self, sensor: u8) -> Option<Rom> {
        self.find(sensor).copied()
    }

    /// As [`Sensors::locate`], without copying the ROM.
    // Out of line: a tick's start and its read and conversion steps all look sensors up
    // (one copy).
    #[inline(never)]
    pub fn find(&self, sensor: u8) -> Option<&Rom> {
        let byte1 = SENSOR_ROM_BYTE1_FLASH.get(usize::from(sensor))?;
        self.roms().iter().find(|rom| rom[1] == byte1)
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
        missing_exception(self.missing)
    }
}

/// A tick by sensor ids only ([`Tick`] without the ROMs): what the firmware keeps, as it
/// finds each ROM again when it addresses the sensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    /// The sensor to read, if it is on the bus.
    pub read: Option<u8>,
    /// The sensor to start a conversion on, if it is on the bus.
    pub convert: Option<u8>,
    /// A sensor id the tick needed that is not on the bus (see [`Tick::missing`]).
    pub missing: Option<u8>,
}

impl Plan {
    /// The exception to raise for this tick, as [`Tick::exception`].
    pub const fn exception(&self) -> Option<MasterException> {
        missing_exception(self.missing)
    }
}

/// Type 10 (sensor missing) on the master, if a sensor is `missing`.
const fn missing_exception(missing: Option<u8>) -> Option<MasterException> {
    match missing {
        Some(_) => Some(MasterException {
            kind: ExceptionType::SensorMissing,
            slave: 0,
            motor: 0,
        }),
        None => None,
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
        let plan = self.plan(sensors);
        let with_rom = |id: u8| sensors.locate(id).map(|rom| (id, rom));
        Tick {
            read: plan.read.and_then(with_rom),
            convert: plan.convert.and_then(with_rom),
            missing: plan.missing,
        }
    }

    /// As [`Poller::tick`], by sensor ids only.
    pub fn plan(&mut self, sensors: &Sensors) -> Plan {
        let count = sensors.count();
        if count == 0 {
            // Nothing was found, so the ambient sensor, read first, is missing.
            return Plan {
                read: None,
                convert: None,
                missing: Some(0),
            };
        }
        // `next % count` and `(read_id + 1) % count` by subtraction: `next` is below
        // `count` whenever the sensors stay the same, so the loop rarely runs, and the
        // firmware needs no division routine.
        let mut read_id = self.next;
        while read_id >= count {
            read_id -= count;
        }
        let convert_id = if read_id + 1 == count { 0 } else { read_id + 1 };
        self.next = convert_id;
        let on_bus = |id: u8| sensors.find(id).map(|_| id);
        let read = on_bus(read_id);
        let convert = on_bus(convert_id);
        let missing = match (read, convert) {
            (None, _) => Some(read_id),
            (_, None) => Some(convert_id),
            _ => None,
        };
        Plan {
            read,
            convert,
            missing,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::master::temperature::SENSOR_ROM_BYTE1;

    /// A ROM whose byte 1 names `sensor`.
    fn rom_of(sensor: usize) -> Rom {
        [0x28, SENSOR_ROM_BYTE1[sensor], 0, 0, 0, 0, 0, 0]
    }

    #[test]
    fn the_plan_names_the_sensors_the_tick_addresses() {
        // Sensors 0, 1 and 3 of four devices; the fourth device is no sensor of ours.
        let mut sensors = Sensors::new();
        for rom in [
            rom_of(0),
            rom_of(1),
            rom_of(3),
            [0x28, 0xee, 0, 0, 0, 0, 0, 0],
        ] {
            assert!(sensors.push(rom));
        }
        assert_eq!(sensors.find(3), Some(&rom_of(3)));
        assert_eq!(sensors.find(2), None);
        let (mut by_plan, mut by_tick) = (Poller::new(), Poller::new());
        let mut seen = [0u8; 3];
        for _ in 0..8 {
            let plan = by_plan.plan(&sensors);
            let tick = by_tick.tick(&sensors);
            assert_eq!(plan.read, tick.read.map(|(id, _)| id));
            assert_eq!(plan.convert, tick.convert.map(|(id, _)| id));
            assert_eq!(plan.missing, tick.missing);
            assert_eq!(plan.exception(), tick.exception());
            if let Some(slot) = plan.missing.and_then(|m| seen.get_mut(usize::from(m))) {
                *slot += 1;
            }
        }
        // D = 4: ticks read 0, 1, 2, 3 in turn; sensor 2 is missing twice per round
        // (read, and converted by the tick before).
        assert_eq!(seen, [0, 0, 4]);
        let empty = Poller::new().plan(&Sensors::new());
        assert_eq!((empty.read, empty.missing), (None, Some(0)));
    }

    #[test]
    fn the_ids_are_the_polling_position_modulo_the_count_from_any_position() {
        for count in 1..=10u8 {
            let mut sensors = Sensors::new();
            for n in 0..count {
                assert!(sensors.push(rom_of(usize::from(n))));
            }
            for next in 0..=u8::MAX {
                let mut p = Poller { next };
                let plan = p.plan(&sensors);
                let read = next % count;
                let convert = (read + 1) % count;
                assert_eq!(plan.read, Some(read), "{count} {next}");
                assert_eq!(plan.convert, Some(convert), "{count} {next}");
                assert_eq!(p.next(), convert);
            }
        }
    }
}
