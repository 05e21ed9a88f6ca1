//! [`Rover`]: the master and the nine slave images on one I²C bus, with the physics of every
//! wheel closed around the slaves, run together in emulated time; its serial line and views.
//! Fault injection is in [`crate::faults`].

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use harness::bus::Bus;
use harness::onewire::OneWireBus;
use harness::rc::RcReceiver;
use harness::Avr;
use physics::bridge::Bridge;
use physics::emulator::Plant;
use physics::wheel::{Motor, SlaveBoardModel};

use crate::leds::{Led, LedWatch};
use crate::serial::{Direction, SerialLine};
use crate::speed::{thread_cpu, RunStart};
use crate::wiring::{self, Axis, MASTER_CHIP};
use crate::{Config, Speed, TwinError};

/// The physical state of one wheel, as the models have it (not as the firmware measures it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelState {
    /// Wheel 1..=6.
    pub wheel: u8,
    /// Drive speed, encoder ticks per second (signed).
    pub drive_ticks_per_s: f64,
    /// Steer angle, degrees.
    pub steer_deg: f64,
    /// Lift angle, degrees.
    pub lift_deg: f64,
}

/// Temperature each sensor measures at start, in 0.5 °C units: the ambient sensor 20.0 °C,
/// controller n's sensor (20 + n/2) °C, so every reading is told apart.
pub fn start_half_degrees(sensor: u8) -> i16 {
    40 + i16::from(sensor)
}

/// The temperature sensors: 0 ambient, 1..=9 one per controller.
pub const SENSORS: std::ops::RangeInclusive<u8> = 0..=9;
/// The RC receiver's channels: 0 drive, 1 steer, 2 mode.
pub const RC_CHANNELS: std::ops::RangeInclusive<u8> = 0..=2;

/// The real rover, emulated: chip 0 is the master, chip n is controller n (1..=9).
pub struct Rover {
    // Field order is drop order: the sensor and receiver handles go before the chips.
    pub(crate) sensors: OneWireBus,
    pub(crate) rc: RcReceiver,
    pub(crate) removed_sensors: BTreeSet<u8>,
    pub(crate) bus: Bus,
    pub(crate) plant: Plant,
    pub(crate) serial: SerialLine,
    /// Master output already taken from the chip and not yet handed to the host.
    from_master: Vec<u8>,
    pub(crate) stalled: BTreeSet<(u8, Axis)>,
    names: Vec<String>,
    speed: Speed,
    leds: LedWatch,
}

impl Rover {
    /// The rover from the workspace's firmware images, with the default settings.
    pub fn new() -> Result<Rover, TwinError> {
        Rover::with_config(&Config::default())
    }

    /// The rover built as `config` says: the master image on chip 0, `slave-drive` on
    /// controllers 1, 2, 4, 5, 7, 8 and `slave-lift` on 3, 6, 9 (each with its address in
    /// EEPROM byte 0), a physics model on every slave, all at emulated time 0.
    pub fn with_config(config: &Config) -> Result<Rover, TwinError> {
        let mut bus = Bus::new();
        bus.set_quantum_us(config.quantum_us);
        bus.set_answer_timeout_us(config.answer_timeout_us);
        bus.set_tracing(false);
        bus.set_threads(config.threads);
        let mut names = vec!["master".to_owned()];
        let mut master = Avr::load(&config.image("master"))?;
        let sensors = OneWireBus::attach_rover_sensors(&mut master);
        for i in SENSORS {
            sensors.set_half_degrees(usize::from(i), start_half_degrees(i));
        }
        let rc = RcReceiver::attach(&mut master);
        bus.add_master(master)?;
        let mut plant = Plant::new();
        plant.set_slice_us(config.slice_us);
        for n in wiring::CONTROLLERS {
            let name = wiring::image_of(n);
            let mut avr = Avr::load(&config.image(name))?;
            avr.eeprom_write(0, &[n]);
            // The physics reads each motor's duty from the timer registers.
            avr.detach_pwm_waveforms();
            let chip = bus.add_slave(avr)?;
            plant.attach(chip, SlaveBoardModel::for_controller(n)?);
            names.push(format!("{name} {n}"));
        }
        Ok(Rover {
            sensors,
            rc,
            removed_sensors: BTreeSet::new(),
            bus,
            plant,
            serial: SerialLine::new(),
            from_master: Vec::new(),
            stalled: BTreeSet::new(),
            names,
            speed: Speed::default(),
            leds: LedWatch::default(),
        })
    }

    /// Emulated time since power-up, µs.
    pub fn micros(&self) -> u64 {
        self.bus.micros()
    }

    /// Threads the chips run on, the caller's included ([`Config::threads`]; fewer if the
    /// system refused some).
    pub fn threads(&self) -> usize {
        self.bus.threads()
    }

    /// Emulated time run so far against the wall-clock time it took.
    pub fn speed(&self) -> Speed {
        self.speed
    }

    /// Runs every chip and the physics for `us` µs of emulated time.
    pub fn run_us(&mut self, us: u64) -> Result<(), TwinError> {
        let start = self.run_start();
        let Rover {
            bus, plant, leds, ..
        } = self;
        plant.run_until(bus, us, |bus| {
            sample_leds(leds, bus);
            false
        })?;
        self.account(start);
        self.check_halted()
    }

    /// Runs until `pred` holds (checked every `step_us`, and first before running) or
    /// `max_us` pass. Returns whether `pred` became true.
    pub fn run_until(
        &mut self,
        max_us: u64,
        step_us: u64,
        mut pred: impl FnMut(&mut Rover) -> bool,
    ) -> Result<bool, TwinError> {
        let end = self.micros().saturating_add(max_us);
        loop {
            if pred(self) {
                return Ok(true);
            }
            let now = self.micros();
            if now >= end {
                return Ok(false);
            }
            self.run_us(step_us.max(1).min(end - now))?;
        }
    }

    fn run_start(&self) -> RunStart {
        RunStart {
            wall: Instant::now(),
            cpu: self.cpu(),
            at_us: self.bus.micros(),
        }
    }

    /// CPU time of this thread and the bus's worker threads so far.
    fn cpu(&self) -> Duration {
        thread_cpu() + self.bus.worker_cpu()
    }

    fn account(&mut self, start: RunStart) {
        self.speed.busy += start.wall.elapsed();
        self.speed.cpu += self.cpu().saturating_sub(start.cpu);
        self.speed.emulated += Duration::from_micros(self.bus.micros().saturating_sub(start.at_us));
    }

    /// Fails if a chip has halted (a crash the firmware cannot come back from).
    fn check_halted(&self) -> Result<(), TwinError> {
        for chip in 0..self.bus.chip_count() {
            if let Some(avr) = self.bus.chip(chip) {
                if avr.state().is_halted() {
                    return Err(TwinError::Halted {
                        chip,
                        name: self.names.get(chip).cloned().unwrap_or_default(),
                        at_us: self.bus.micros(),
                    });
                }
            }
        }
        Ok(())
    }

    // ---- the serial line -------------------------------------------------------------

    /// Resets the master as the Uno's DTR auto-reset does when a program opens its port:
    /// it reboots (and hard-resets the slaves, as its boot does); output not yet taken and
    /// input not yet received are lost.
    pub fn reset_master(&mut self) {
        if let Some(mut master) = self.bus.chip(MASTER_CHIP) {
            master.reset();
            master.uart_take();
            // What the last program sent and the master had not received yet dies with
            // the reset, as on the Uno: the next session starts from its banner.
            master.uart_discard_input();
        }
        self.from_master.clear();
    }

    /// Host bytes towards the master's UART, delivered at the line rate as the twin runs
    /// (minus any the line is set to lose).
    pub fn uart_send(&mut self, bytes: &[u8]) {
        let arriving = self.serial.pass(Direction::ToMaster, bytes);
        if let Some(mut master) = self.bus.chip(MASTER_CHIP) {
            master.uart_send(&arriving);
        }
    }

    /// The master's UART output since the last take (minus any the line lost).
    pub fn uart_take(&mut self) -> Vec<u8> {
        self.collect();
        std::mem::take(&mut self.from_master)
    }

    /// Moves the master's new output through the line into `from_master`.
    fn collect(&mut self) {
        collect(&mut self.bus, &mut self.serial, &mut self.from_master);
    }

    /// Runs until the master has sent `needle`; returns its output up to and including it
    /// (later bytes are kept for the next read).
    pub fn uart_read_until(&mut self, needle: &[u8], max_us: u64) -> Result<Vec<u8>, TwinError> {
        let start = self.micros();
        let found = self.run_collecting(max_us, |out| find(out, needle).is_some())?;
        match find(&self.from_master, needle) {
            Some(end) if found => Ok(self.from_master.drain(..end).collect()),
            _ => Err(TwinError::Timeout {
                what: format!("{:?}", String::from_utf8_lossy(needle)),
                waited_us: self.micros() - start,
                got: self.from_master.clone(),
            }),
        }
    }

    /// Runs until the master has sent `n` bytes; returns exactly those.
    pub fn uart_read_exact(&mut self, n: usize, max_us: u64) -> Result<Vec<u8>, TwinError> {
        let start = self.micros();
        if self.run_collecting(max_us, |out| out.len() >= n)? {
            return Ok(self.from_master.drain(..n).collect());
        }
        Err(TwinError::Timeout {
            what: format!("{n} reply bytes"),
            waited_us: self.micros() - start,
            got: self.from_master.clone(),
        })
    }

    /// Runs until the master has sent anything (or `max_us` pass); returns what it sent
    /// (empty after a timeout). This is a serial port's blocking read with a timeout.
    pub fn uart_read_some(&mut self, max_us: u64) -> Result<Vec<u8>, TwinError> {
        self.run_collecting(max_us, |out| !out.is_empty())?;
        Ok(std::mem::take(&mut self.from_master))
    }

    /// Runs the twin, collecting the master's output, until `done` says the output so far is
    /// enough (checked every physics slice) or `max_us` pass.
    fn run_collecting(
        &mut self,
        max_us: u64,
        mut done: impl FnMut(&[u8]) -> bool,
    ) -> Result<bool, TwinError> {
        let start = self.run_start();
        let Rover {
            bus,
            plant,
            serial,
            from_master,
            leds,
            ..
        } = self;
        let found = plant.run_until(bus, max_us, |bus| {
            sample_leds(leds, bus);
            collect(bus, serial, from_master);
            done(from_master)
        })?;
        self.account(start);
        self.check_halted()?;
        Ok(found)
    }

    /// The serial line, to inspect its losses.
    pub fn serial(&self) -> &SerialLine {
        &self.serial
    }

    // ---- views -----------------------------------------------------------------------

    /// The physical state of `wheel` (1..=6).
    pub fn wheel(&self, wheel: u8) -> Result<WheelState, TwinError> {
        let board = |axis| -> Result<(&SlaveBoardModel, wiring::Place), TwinError> {
            let place = wiring::place(wheel, axis).ok_or(TwinError::NoSuchWheel(wheel))?;
            let model = self
                .plant
                .model(place.chip())
                .ok_or(TwinError::NoSuchWheel(wheel))?;
            Ok((model, place))
        };
        let (ds, _) = board(Axis::Drive)?;
        let ds = ds.ds().ok_or(TwinError::NoSuchWheel(wheel))?;
        let (ll, lift) = board(Axis::Lift)?;
        let ll = ll.ll().ok_or(TwinError::NoSuchWheel(wheel))?;
        let lift_axis = match lift.motor {
            Motor::M1 => &ll.one,
            Motor::M2 => &ll.two,
        };
        Ok(WheelState {
            wheel,
            drive_ticks_per_s: ds.drive.ticks_per_s(),
            steer_deg: ds.steer.motor.angle_deg(),
            lift_deg: lift_axis.motor.angle_deg(),
        })
    }

    /// Chip `chip`'s two LEDs as sampled after the last run: LED1 and LED2 on a controller,
    /// the blue and status LEDs on the master (chip 0). None before the first run.
    pub fn leds(&self, chip: usize) -> Option<[Led; 2]> {
        self.leds.chip(chip)
    }

    /// Controller `n`'s bridge inputs (motor 0, motor 1) as the physics last read them from
    /// its pins. None for a controller outside 1..=9.
    pub fn bridges(&self, n: u8) -> Option<[Bridge; 2]> {
        let model = self.plant.model(usize::from(n))?;
        wiring::CONTROLLERS
            .contains(&n)
            .then(|| [Motor::M1, Motor::M2].map(|m| model.bridge(m)))
    }

    /// The bus, for tests that look at chips directly (chip 0 = master, n = controller n).
    pub fn bus(&mut self) -> &mut Bus {
        &mut self.bus
    }

    /// The physics models, one per slave chip.
    pub fn plant(&mut self) -> &mut Plant {
        &mut self.plant
    }

    /// Watchdog resets each chip has survived, chip 0 first.
    pub fn watchdog_resets(&self) -> Vec<u32> {
        (0..self.bus.chip_count())
            .map(|c| self.bus.chip(c).map_or(0, |a| a.watchdog_resets()))
            .collect()
    }

    /// The image a chip runs, e.g. `slave-lift 3`.
    pub fn chip_name(&self, chip: usize) -> Option<&str> {
        self.names.get(chip).map(String::as_str)
    }
}

/// Records every chip's LED levels now (each physics slice, so a level's age is right to
/// 50 µs).
fn sample_leds(leds: &mut LedWatch, bus: &Bus) {
    let levels = (0..bus.chip_count()).map(|chip| {
        let pins = if chip == MASTER_CHIP {
            wiring::MASTER_LEDS
        } else {
            wiring::SLAVE_LEDS
        };
        bus.chip(chip)
            .map_or([false; 2], |avr| pins.map(|pin| avr.pin(pin)))
    });
    leds.sample(levels, bus.micros());
}

/// The twin's serial port as a pty sees it: the master's UART behind the faulty line.
impl harness::SerialEnd for Rover {
    fn host_sent(&mut self, bytes: &[u8]) {
        self.uart_send(bytes);
    }

    fn firmware_output(&mut self) -> Vec<u8> {
        self.uart_take()
    }
}

/// Moves the master chip's new UART output through the serial line into `out`.
fn collect(bus: &mut Bus, serial: &mut SerialLine, out: &mut Vec<u8>) {
    let fresh = match bus.chip(MASTER_CHIP) {
        Some(mut master) => master.uart_take(),
        None => return,
    };
    if !fresh.is_empty() {
        out.extend(serial.pass(Direction::ToHost, &fresh));
    }
}

/// End index of the first `needle` in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() {
        return Some(0);
    }
    haystack
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + needle.len())
}
