//! Fault injection on the [`Rover`]: stalled motors, current spikes, controllers cut off
//! the bus or rebooted, lost serial bytes, unplugged temperature sensors, and the RC receiver.

use crate::rover::{RC_CHANNELS, SENSORS};
use crate::serial::Direction;
use crate::wiring::{self, Axis, WHEELS};
use crate::{Rover, TwinError};

impl Rover {
    /// Holds `axis` of `wheel` still (`true`), as a jammed wheel or gear would, or lets it go.
    pub fn stall(&mut self, wheel: u8, axis: Axis, on: bool) -> Result<(), TwinError> {
        let place = wiring::place(wheel, axis).ok_or(TwinError::NoSuchWheel(wheel))?;
        let model = self
            .plant
            .model_mut(place.chip())
            .ok_or(TwinError::NoSuchWheel(wheel))?;
        model.set_stalled(place.motor, on);
        if on {
            self.stalled.insert((wheel, axis));
        } else {
            self.stalled.remove(&(wheel, axis));
        }
        Ok(())
    }

    /// Adds `amps` to the current sensed on `axis` of `wheel` for `ms` of emulated time.
    pub fn spike(&mut self, wheel: u8, axis: Axis, amps: f64, ms: f64) -> Result<(), TwinError> {
        let place = wiring::place(wheel, axis).ok_or(TwinError::NoSuchWheel(wheel))?;
        let model = self
            .plant
            .model_mut(place.chip())
            .ok_or(TwinError::NoSuchWheel(wheel))?;
        model.sense_mut(place.motor).inject_spike(amps, ms / 1000.0);
        Ok(())
    }

    /// Takes controller `n` off the I²C bus: it acknowledges nothing, as if unplugged.
    pub fn cut(&mut self, n: u8) -> Result<(), TwinError> {
        check_controller(n)?;
        self.bus.cut(n);
        Ok(())
    }

    /// Puts controller `n` back on the bus.
    pub fn restore(&mut self, n: u8) -> Result<(), TwinError> {
        check_controller(n)?;
        self.bus.restore(n);
        Ok(())
    }

    /// Resets controller `n`, as a brown-out or its own watchdog would: it restarts from
    /// its reset vector, back in its boot state on its power-up defaults (its motors stop),
    /// while the rest of the rover runs on. (The chip sees an external reset; the slave
    /// firmware treats every reset cause alike.)
    pub fn reboot(&mut self, n: u8) -> Result<(), TwinError> {
        check_controller(n)?;
        let mut chip = self
            .bus
            .chip(usize::from(n))
            .ok_or(TwinError::NoSuchController(n))?;
        chip.reset();
        Ok(())
    }

    /// Makes the serial line lose the next `n` bytes travelling `direction`.
    pub fn drop_serial(&mut self, direction: Direction, n: u64) {
        self.serial.drop_next(direction, n);
    }

    /// Cancels the serial losses still pending; returns them (to the master, to the host).
    pub fn clear_serial_drops(&mut self) -> (u64, u64) {
        self.serial.clear_pending()
    }

    /// Takes temperature sensor `index` (0 ambient, n for controller n) off the OneWire line
    /// (`present` false), as an unplugged sensor, or puts it back.
    pub fn set_sensor_present(&mut self, index: u8, present: bool) -> Result<(), TwinError> {
        check_sensor(index)?;
        self.sensors.set_present(usize::from(index), present);
        if present {
            self.removed_sensors.remove(&index);
        } else {
            self.removed_sensors.insert(index);
        }
        Ok(())
    }

    /// Sets the temperature sensor `index` measures, in 0.5 °C units (clamped to the
    /// sensor's −55..=125 °C).
    pub fn set_temperature(&mut self, index: u8, half_degrees: i16) -> Result<(), TwinError> {
        check_sensor(index)?;
        self.sensors
            .set_half_degrees(usize::from(index), half_degrees);
        Ok(())
    }

    /// What each temperature sensor measures (0 ambient, then controllers 1..9), 0.5 °C units.
    pub fn temperatures(&self) -> Vec<i16> {
        SENSORS
            .filter_map(|i| self.sensors.half_degrees(usize::from(i)))
            .collect()
    }

    /// The current spikes still running, as (wheel, axis, amperes, ms left).
    pub fn spikes(&self) -> Vec<(u8, Axis, f64, f64)> {
        WHEELS
            .flat_map(|w| Axis::ALL.map(|a| (w, a)))
            .filter_map(|(w, a)| {
                let place = wiring::place(w, a)?;
                let (amps, left_s) = self.plant.model(place.chip())?.sense(place.motor).spike()?;
                Some((w, a, amps, left_s * 1000.0))
            })
            .collect()
    }

    /// The sensors taken off the line.
    pub fn removed_sensors(&self) -> Vec<u8> {
        self.removed_sensors.iter().copied().collect()
    }

    /// Turns the RC receiver's pulses on or off (off at start).
    pub fn set_rc(&mut self, on: bool) {
        if on {
            self.rc.turn_on();
        } else {
            self.rc.turn_off();
        }
    }

    /// Whether the RC receiver is sending.
    pub fn rc_on(&self) -> bool {
        self.rc.is_on()
    }

    /// Sets RC channel `channel`'s pulse width, µs (the receiver clamps it to 500..=2500).
    pub fn set_rc_width(&mut self, channel: u8, us: u16) -> Result<(), TwinError> {
        if !RC_CHANNELS.contains(&channel) {
            return Err(TwinError::NoSuchChannel(channel));
        }
        self.rc.set_width(usize::from(channel), us);
        Ok(())
    }

    /// The RC receiver's channel widths, µs.
    pub fn rc_widths(&self) -> [u16; 3] {
        self.rc.widths()
    }

    /// The stalled axes, as (wheel, axis).
    pub fn stalled(&self) -> Vec<(u8, Axis)> {
        self.stalled.iter().copied().collect()
    }

    /// The controllers cut off the bus.
    pub fn cut_off(&self) -> Vec<u8> {
        wiring::CONTROLLERS
            .filter(|&n| self.bus.is_cut(n))
            .collect()
    }
}

fn check_sensor(index: u8) -> Result<(), TwinError> {
    if SENSORS.contains(&index) {
        Ok(())
    } else {
        Err(TwinError::NoSuchSensor(index))
    }
}

fn check_controller(n: u8) -> Result<(), TwinError> {
    if wiring::CONTROLLERS.contains(&n) {
        Ok(())
    } else {
        Err(TwinError::NoSuchController(n))
    }
}
