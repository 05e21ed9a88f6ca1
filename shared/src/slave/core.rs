//! [`Core`]: every decision of one slave board, run from the control tick.
//!
//! A tick has three phases, so the register file (shared with the TWI interrupt) is
//! locked only for copying:
//!
//! 1. [`Core::take_writes`] (register file locked): applies every register the bus
//!    changed since the previous tick, in id order, and clears the marks.
//! 2. [`Core::step`] (no lock): sensors, control updates, faults, exception state,
//!    outputs.
//! 3. [`Core::publish`] (register file locked): writes the monitoring registers.
//!
//! [`Core::tick`] runs all three.
//!
//! **Timing.** The firmware calls the tick every [`TICK_US`] (1 ms) with its µs clock.
//! Position controllers update every [`POSITION_PERIOD_US`] (2 ms, 500 Hz; on a
//! lift/lift board ONE and TWO on alternate ticks). The drive updates per its mode
//! (see [`super::encoder`]): on the first tick more than 150 ms after its previous
//! update, or every 10 ms. The current filters step once per tick; the overcurrent rule
//! sees every sample through the per-tick peak. REG_TIMER, INTERVALI2C, STATUS,
//! EXCEPTIONDATA, DEBUG, CURRENT and ODO are written every tick; a motor's mapped
//! monitoring registers (ACTUAL…INTERVALCTRL) and CHASSIS at most every 10 ms, from the
//! update at hand, since mapping is the costliest arithmetic on the AVR.
//!
//! **Cost on the ATmega328P** (measured in the emulator, 16 MHz): a tick without a
//! controller update takes about 2,000 cycles (125 µs), a position update about 2,700
//! more with the calibrate() gains and about 4,000 with every gain non-zero, a drive
//! update about 7,000. A drive/steer board spends about 23 % of the CPU here, a
//! lift/lift board about 36 % with every gain non-zero.

use super::board::{bus_address, Layout, Monitor, MotorId, Variant};
use super::clock::Clock;
use super::encoder::{DriveMode, Odometer, SpeedMeter};
use super::fault::FAULT_TIME_POWER_ON_MS;
use super::io::{Inputs, MotorOutput, Outputs, Watchdog};
use super::leds::{self, LedLevels, Leds};
use super::motor::{Kind, Motor, UpdateContext};
use super::registers::RegisterFile;
use super::scale::Scale;
use super::state::{Cause, Event, LocalFault, ResetBits, State};
use crate::pid::Fix;
use crate::regs::{id, DS};

/// The tick period the firmware must keep, µs.
pub const TICK_US: u32 = 1_000;
/// The update period of the position controllers, µs.
pub const POSITION_PERIOD_US: u32 = 2_000;

/// REGDS_CHASSIS: the raw ADC7 reading mapped over 0..1024.
const CHASSIS: Scale = Scale::of(&DS, id::REGDS_CHASSIS);
/// REGDS_CHASSIS is refreshed this often, ms.
const CHASSIS_PERIOD_MS: u32 = 10;

/// What the bus asked for that takes effect in [`Core::step`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
struct Pending {
    ping: bool,
    debug_led: Option<u8>,
}

/// One slave board's logic.
#[derive(Clone, Debug)]
pub struct Core {
    variant: Variant,
    address: Option<u8>,
    state: State,
    disabled: u16,
    fault_time_ms: u16,
    drive_mode: DriveMode,
    clock: Clock,
    leds: Leds,
    motors: [Motor; 2],
    next_position_us: [u32; 2],
    speed: SpeedMeter,
    odometer: Odometer,
    /// REGDS_CHASSIS, raw.
    chassis: u16,
    chassis_at_ms: u32,
    pending: Pending,
}

impl Core {
    /// The logic of a board of `variant` whose EEPROM byte 0 is `eeprom_byte`, at
    /// power-up: in the boot exception, every parameter at its default (reference §8.1).
    /// With an address outside 1..9 the board stays off the bus: the firmware must not
    /// enable the TWI (see [`Core::address`]), and every tick stops the motors and shows
    /// the bad-address LED pattern.
    pub fn new(variant: Variant, eeprom_byte: u8) -> Core {
        let m1 = if variant.has_drive() {
            Kind::Drive
        } else {
            Kind::Position
        };
        Core {
            variant,
            address: bus_address(eeprom_byte),
            state: State::POWER_UP,
            disabled: 0,
            fault_time_ms: FAULT_TIME_POWER_ON_MS,
            drive_mode: DriveMode::Window,
            clock: Clock::new(),
            leds: Leds::new(0),
            motors: [Motor::new(m1), Motor::new(Kind::Position)],
            next_position_us: [0; 2],
            speed: SpeedMeter::new(0),
            odometer: Odometer::new(),
            chassis: 0,
            chassis_at_ms: 0,
            pending: Pending {
                ping: false,
                debug_led: None,
            },
        }
    }

    /// The I2C address to listen on, or `None`: then the TWI must stay off.
    pub fn address(&self) -> Option<u8> {
        self.address
    }

    /// The board's variant.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// The exception state.
    pub fn state(&self) -> State {
        self.state
    }

    /// A motor, for inspection.
    pub fn motor(&self, motor: MotorId) -> &Motor {
        &self.motors[motor.index()]
    }

    /// The drive's control mode.
    pub fn drive_mode(&self) -> DriveMode {
        self.drive_mode
    }

    /// Uptime in ms, as REG_TIMER counts it.
    pub fn uptime_ms(&self) -> u32 {
        self.clock.ms()
    }

    /// Runs a whole tick: [`Core::take_writes`], [`Core::step`], [`Core::publish`].
    pub fn tick(&mut self, now_us: u32, inputs: &Inputs, regs: &mut RegisterFile) -> Outputs {
        self.take_writes(regs);
        let outputs = self.step(now_us, inputs);
        self.publish(regs);
        outputs
    }

    /// Phase 1: applies the registers the bus changed since the previous tick, lowest id
    /// first, and clears their marks.
    pub fn take_writes(&mut self, regs: &mut RegisterFile) {
        if self.address.is_none() {
            return;
        }
        while let Some(reg) = regs.take_changed() {
            let raw = regs.get(reg);
            self.apply(reg, raw, regs);
        }
    }

    fn apply(&mut self, reg: u8, raw: u16, regs: &mut RegisterFile) {
        let low = raw.to_le_bytes()[0];
        match reg {
            id::REG_RESET => {
                regs.set(id::REG_RESET, 0);
                let bits = ResetBits(low);
                if let Some(event) = bits.event() {
                    self.state.handle(event, self.disabled);
                }
                if bits.zero_odometer() {
                    self.odometer.clear();
                }
            }
            id::REG_DEBUGLED => self.pending.debug_led = Some(low),
            id::REG_EXCEPTIONDATA => {
                self.state.handle(Event::RemoteWrite, self.disabled);
            }
            id::REG_DISABLEDEXCEPTIONS => self.disabled = raw,
            id::REG_PING => self.pending.ping = true,
            _ if reg == self.fault_time_id() => self.fault_time_ms = raw,
            id::REGDS_DRIVE_MODE if self.variant.has_drive() => {
                self.drive_mode = DriveMode::from_register(raw)
            }
            _ => {
                for motor in MotorId::BOTH {
                    let layout = Layout::of(self.variant, motor);
                    if let Some(param) = layout.param(reg) {
                        let m = &mut self.motors[motor.index()];
                        m.params.set(m.kind, param, raw);
                    }
                }
            }
        }
    }

    fn fault_time_id(&self) -> u8 {
        match self.variant {
            Variant::DriveSteer => id::REGDS_FAULTTIME,
            Variant::LiftLift => id::REGLL_FAULTTIME,
        }
    }

    /// Phase 2: one control tick at `now_us` (a wrapping µs clock).
    pub fn step(&mut self, now_us: u32, inputs: &Inputs) -> Outputs {
        let first = self.clock.advance(now_us);
        let now_ms = self.clock.ms();
        let Some(address) = self.address else {
            return Outputs {
                motors: [MotorOutput::Stop; 2],
                leds: leds::bad_address(now_ms),
                watchdog: Watchdog::Feed,
            };
        };
        if first {
            self.start(now_us, now_ms);
        }
        if let State::Restarting { .. } = self.state {
            return Outputs {
                motors: [MotorOutput::Stop; 2],
                leds: LedLevels::OFF,
                watchdog: Watchdog::Reset,
            };
        }
        self.take_pending(now_ms);

        for motor in MotorId::BOTH {
            let i = motor.index();
            let fault =
                self.motors[i].sense_current(inputs.adc.current[i], inputs.adc.current_peak[i]);
            self.raise(fault, motor);
        }
        if self.variant.has_drive() {
            self.odometer.add(inputs.edges.rising);
            self.speed.accumulate(&inputs.edges);
            if now_ms.wrapping_sub(self.chassis_at_ms) >= CHASSIS_PERIOD_MS {
                // A mapping costs some 400 cycles on the AVR: refreshed every 10 ms.
                self.chassis_at_ms = now_ms;
                self.chassis = CHASSIS.map_int(inputs.adc.ch7);
            }
            if self.speed.due(now_us, self.drive_mode) {
                let speed = self.speed.measure(now_us, self.drive_mode);
                self.update_motor(MotorId::M1, speed, now_us, now_ms);
            }
        }
        for motor in MotorId::BOTH {
            if self.motors[motor.index()].kind == Kind::Position && self.position_due(motor, now_us)
            {
                let reading = match (self.variant, motor) {
                    (Variant::LiftLift, MotorId::M2) => inputs.adc.ch7,
                    _ => inputs.adc.ch6,
                };
                let m = &self.motors[motor.index()];
                let angle = m.params.calibration.angle(reading);
                self.update_motor(motor, angle, now_us, now_ms);
            }
        }

        let motors = [self.output(MotorId::M1), self.output(MotorId::M2)];
        let [m1, m2] = &mut self.motors;
        m1.set_applied(motors[0].duty());
        m2.set_applied(motors[1].duty());
        Outputs {
            motors,
            leds: self.leds.levels(now_ms, address, self.variant, &self.state),
            watchdog: Watchdog::Feed,
        }
    }

    /// Phase 3: writes the monitoring registers, STATUS, TIMER, INTERVALI2C,
    /// EXCEPTIONDATA and DEBUG. A motor's mapped monitoring registers (read-only to the
    /// bus) are written only when they were remapped since the previous publish, so
    /// `regs` must be the same file every tick.
    pub fn publish(&mut self, regs: &mut RegisterFile) {
        if self.address.is_none() {
            return;
        }
        regs.set(id::REG_TIMER, self.clock.ms() as u16);
        regs.set(id::REG_INTERVALI2C, self.clock.interval_us() as u16);
        let exception = if self.state.in_exception() { 1 } else { 0 };
        regs.set(id::REG_STATUS, self.variant.status_bit() | exception);
        regs.set(id::REG_EXCEPTIONDATA, self.state.data());
        let debug = match self.variant {
            Variant::DriveSteer => 0,
            Variant::LiftLift => self.motors[0].monitors().interval_ms,
        };
        regs.set(id::REG_DEBUG, debug);
        for motor in MotorId::BOTH {
            let layout = Layout::of(self.variant, motor);
            let m = &mut self.motors[motor.index()];
            if m.take_fresh() {
                regs.set_run(layout.monitor_id(Monitor::Actual), &m.monitors().raw);
            }
            regs.set(layout.monitor_id(Monitor::Current), u16::from(m.current()));
        }
        if self.variant.has_drive() {
            regs.set(id::REGDS_DRIVE_ODO, self.odometer.reading());
            regs.set(id::REGDS_CHASSIS, self.chassis);
        }
    }

    fn start(&mut self, now_us: u32, now_ms: u32) {
        self.leds = Leds::new(now_ms);
        self.speed = SpeedMeter::new(now_us);
        self.chassis_at_ms = now_ms.wrapping_sub(CHASSIS_PERIOD_MS);
        for m in &mut self.motors {
            m.start(now_us);
        }
        let first = now_us.wrapping_add(POSITION_PERIOD_US);
        self.next_position_us = match self.variant {
            Variant::DriveSteer => [first, first],
            // ONE and TWO on alternate ticks.
            Variant::LiftLift => [first, first.wrapping_add(TICK_US)],
        };
    }

    fn take_pending(&mut self, now_ms: u32) {
        if core::mem::take(&mut self.pending.ping) {
            self.leds.ping(now_ms);
        }
        if let Some(value) = self.pending.debug_led.take() {
            self.leds.debug(now_ms, value);
        }
    }

    fn position_due(&mut self, motor: MotorId, now_us: u32) -> bool {
        let Some(next) = self.next_position_us.get_mut(motor.index()) else {
            return false;
        };
        if (now_us.wrapping_sub(*next) as i32) < 0 {
            return false;
        }
        *next = next.wrapping_add(POSITION_PERIOD_US);
        if (now_us.wrapping_sub(*next) as i32) >= 0 {
            // More than a period late (a stalled tick): start again from now.
            *next = now_us.wrapping_add(POSITION_PERIOD_US);
        }
        true
    }

    fn update_motor(&mut self, motor: MotorId, actual: Fix, now_us: u32, now_ms: u32) {
        let cx = UpdateContext {
            now_us,
            now_ms,
            in_exception: self.state.in_exception(),
            fault_time_ms: self.fault_time_ms,
        };
        let fault = self.motors[motor.index()].update(actual, &cx);
        self.raise(fault, motor);
    }

    fn raise(&mut self, fault: Option<LocalFault>, motor: MotorId) {
        if let Some(fault) = fault {
            self.state
                .handle(Event::Fault { fault, motor }, self.disabled);
        }
    }

    fn output(&self, motor: MotorId) -> MotorOutput {
        match self.state {
            State::Running { .. } => MotorOutput::Drive(self.motors[motor.index()].demand()),
            State::Exception(Cause::Boot) => MotorOutput::BOOT,
            State::Exception(_) | State::Restarting { .. } => MotorOutput::Stop,
        }
    }
}
