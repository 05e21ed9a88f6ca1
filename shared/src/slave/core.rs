//! [`Core`]: every decision of one slave board, run from the control tick.
//!
//! A tick has three phases:
//!
//! 1. the registers the bus changed since the previous tick, applied in id order
//!    ([`Core::apply`]). The firmware takes one changed register at a time under a short
//!    lock of the register file (shared with the TWI interrupt) and applies it with the
//!    file unlocked (`slave/src/registers.rs`); [`Core::take_writes`] is the same for a
//!    file the caller holds, as host tests do;
//! 2. [`Core::step`] (no lock): sensors, control updates, faults, exception state,
//!    outputs;
//! 3. [`Core::publish`] (register file locked): writes the monitoring registers.
//!
//! [`Core::tick`] runs all three on a file the caller holds (the host's composition).
//!
//! **Timing.** The firmware calls the tick every [`TICK_US`] (1 ms) with its µs clock.
//! Position controllers update every [`POSITION_PERIOD_US`] (2 ms, 500 Hz; on a
//! lift/lift board ONE and TWO on alternate ticks). The drive updates per its mode
//! (see [`super::encoder`]): on the first tick more than 150 ms after its previous
//! update, or every 10 ms. The current filters step once per tick; the overcurrent rule
//! sees every sample through the per-tick peak. REG_TIMER, INTERVALI2C, STATUS,
//! EXCEPTIONDATA, DEBUG, CURRENT and ODO are written every tick; a motor's mapped
//! monitoring registers (ACTUAL…INTERVALCTRL) and CHASSIS at most every 10 ms, from the
//! update at hand, since mapping is the costliest arithmetic on the AVR (and a motor's
//! only where the value changed since it was last mapped).
//!
//! **Cost on the ATmega328P.** Measured figures (tick means and maxima, sizes, what was
//! tried and dropped) are in `docs/benchmarks.md`, section "Slave". What keeps the
//! common tick short: each motor's two current filters share one step while they agree;
//! the LED levels are kept until a deadline or the exception latch changes them; a pot
//! reading equal to the last one reuses its angle; a position motor at rest (a step whose
//! error, integral and output are 0: [`Motor::holds`]) skips its controller; a motor's
//! monitoring values are remapped only where they changed, at most every 10 ms; 32-bit
//! products come from the hardware multiplier ([`super::product`]). What keeps the image
//! small: the core powers up as zeroed memory plus its nonzero bytes, written at boot
//! from a flash table that [`Core::image`] lays out at compile time (`Core::POWER_UP`,
//! rebuilt from it in a host test); time in the speed meter and a motor's update record
//! is 16-bit, in 4-µs units; the two PID forms share one update; the PID's saturating product,
//! sum and difference, the division, the monitoring mapping, the current filter's step
//! and the clock's ms count are short assembly routines ([`super::product::fixed`],
//! [`crate::pid::sum`], [`super::divide`], [`super::scale`], [`super::current`],
//! [`super::clock`]), each checked on the emulated chip against the host's arithmetic
//! (`tests/tests/slave_maths.rs`); no 32-bit library multiplication is linked; ms deadlines are
//! 16-bit where a check every tick keeps the wrap from showing; the lift/lift board's
//! two position updates are one out-of-line copy, and its image has no encoder task.
//!
//! **Variant at build time.** `Core<B: Board>`: the firmware builds with a zero-sized
//! board type, so every `match` on the variant and on a motor's [`Kind`] folds away and
//! the lift image carries no drive code; host tests use [`Variant`] itself.

use super::board::{
    bus_address, Board, DriveSteerBoard, Layout, LiftLiftBoard, Monitor, MotorId, Param, Variant,
};
use super::clock::{self, Clock};
use super::encoder::{DriveMode, Odometer, SpeedMeter};
use super::fault::FAULT_TIME_POWER_ON_MS;
use super::image::Image;
use super::io::{Inputs, MotorOutput, Outputs, Watchdog};
use super::leds::{self, LedLevels, Leds};
use super::motor::{Kind, Motor, UpdateContext};
use super::registers::RegisterFile;
use super::scale::{Mapping, Scale};
use super::silence::{SilenceWatch, BUS_TIMEOUT_POWER_ON_MS};
use super::state::{Cause, Event, LocalFault, ResetBits, State, Transition};
use crate::pid::Fix;
use crate::progmem::Flash;
use crate::regs::{id, DS, LL};
use core::mem::{offset_of, size_of};

/// The tick period the firmware must keep, µs.
pub const TICK_US: u32 = 1_000;
/// The update period of the position controllers, µs.
pub const POSITION_PERIOD_US: u32 = 2_000;
// The 16-bit deadlines ([`due_every`]) keep `next` at most 2·period + a tick ahead: exact
// only while that is below 2^15 µs.
const _: () = assert!(2 * POSITION_PERIOD_US + TICK_US < 1 << 15);

/// REGDS_CHASSIS: the raw ADC7 reading mapped over 0..1024.
static CHASSIS: Mapping = Scale::of(&DS, id::REGDS_CHASSIS).mapping();
/// REGDS_CHASSIS is refreshed this often, ms.
const CHASSIS_PERIOD_MS: u16 = 10;

/// What the bus asked for that takes effect in [`Core::step`]: bits of one byte, so
/// that a tick with nothing pending tests one byte.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
struct Pending {
    /// [`PING`], [`HEARD`], [`DEBUG_LED`].
    flags: u8,
    /// REG_DEBUGLED's value, while [`DEBUG_LED`] is set.
    debug_led: u8,
}

/// REG_PING was written.
const PING: u8 = 1;
/// A bus transaction addressed this board (see [`Core::bus_heard`]).
const HEARD: u8 = 2;
/// REG_DEBUGLED was written.
const DEBUG_LED: u8 = 4;

/// One slave board's logic, for a variant `B` chosen at run time ([`Variant`], the
/// default) or at build time (see [`Board`]).
#[derive(Clone, Debug)]
pub struct Core<B: Board = Variant> {
    board: B,
    address: Option<u8>,
    state: State,
    /// DISABLEDEXCEPTIONS, FAULTTIME (ms) and BUSTIMEOUT (ms, 0 = off), the registers
    /// [`Core::apply`] stores as they are, by their index ([`word`]).
    words: [u16; 3],
    silence: SilenceWatch,
    drive_mode: DriveMode,
    clock: Clock,
    leds: Leds,
    motors: [Motor; 2],
    next_position_us: [u16; 2],
    speed: SpeedMeter,
    odometer: Odometer,
    /// REGDS_CHASSIS, raw.
    chassis: u16,
    /// When it was mapped: the ms clock's low 16 bits (checked every tick, so the
    /// 16-bit difference never wraps unseen).
    chassis_at_ms: u16,
    pending: Pending,
}

impl Core<DriveSteerBoard> {
    /// A drive/steer board at power-up without its address ([`Core::set_eeprom`] sets
    /// it): built at compile time, so the firmware keeps only its nonzero bytes
    /// ([`Core::image`]) and writes them over zeroed memory at boot.
    pub const POWER_UP: Core<DriveSteerBoard> =
        Core::build(DriveSteerBoard, Variant::DriveSteer, None);
}

impl Core<LiftLiftBoard> {
    /// A lift/lift board at power-up without its address ([`Core::set_eeprom`] sets
    /// it), built at compile time.
    pub const POWER_UP: Core<LiftLiftBoard> = Core::build(LiftLiftBoard, Variant::LiftLift, None);
}

impl<B: Board> Core<B> {
    /// The logic of a board of variant `board` whose EEPROM byte 0 is `eeprom_byte`, at
    /// power-up: in the boot exception, every parameter at its default (reference §8.1).
    /// With an address outside 1..9 the board stays off the bus: the firmware must not
    /// enable the TWI (see [`Core::address`]), and every tick stops the motors and shows
    /// the bad-address LED pattern.
    pub fn new(board: B, eeprom_byte: u8) -> Core<B> {
        Core::build(board, board.variant(), bus_address(eeprom_byte))
    }

    /// Sets the address from EEPROM byte 0, as [`Core::new`] does: for a core built at
    /// compile time (`Core::POWER_UP`), before its first tick.
    pub fn set_eeprom(&mut self, eeprom_byte: u8) {
        self.address = bus_address(eeprom_byte);
    }

    /// [`Core::new`] for `variant` (the board's) and `address`, in a `const` context.
    const fn build(board: B, variant: Variant, address: Option<u8>) -> Core<B> {
        // One motor built and copied: the two differ only in their kind.
        let mut motors = [Motor::new(Kind::Position); 2];
        motors[0].kind = Kind::of(variant, MotorId::M1);
        Core {
            board,
            address,
            state: State::POWER_UP,
            words: [0, FAULT_TIME_POWER_ON_MS, BUS_TIMEOUT_POWER_ON_MS],
            silence: SilenceWatch::new(),
            drive_mode: DriveMode::Window,
            clock: Clock::new(),
            leds: Leds::new(0),
            motors,
            next_position_us: [0; 2],
            speed: SpeedMeter::new(),
            odometer: Odometer::new(),
            chassis: 0,
            chassis_at_ms: 0,
            pending: Pending {
                flags: 0,
                debug_led: 0,
            },
        }
    }

    /// Where the core's clock is: the firmware adds the clock's power-up bytes there
    /// (see [`Core::image`]).
    pub const CLOCK_AT: usize = offset_of!(Core<B>, clock);

    /// This power-up core's bytes for zeroed memory (see [`super::image`]), `N` its size:
    /// the state's ([`State::POWER_UP_BYTES`]) and each field that may be nonzero at
    /// power-up but the clock's, whose fields are private to its module (the firmware
    /// lays out a whole [`Clock::new`] at [`Core::CLOCK_AT`]). The other fields are zero
    /// at power-up: the host test checks that zeroed memory, this image and a new clock
    /// make `Core::POWER_UP`, field for field, and the firmware that these bytes are a
    /// valid core, at compile time.
    pub const fn image<const N: usize>(&self) -> Image<N> {
        assert!(N == size_of::<Core<B>>(), "N must be the core's size");
        let motors = offset_of!(Core<B>, motors);
        let pending = offset_of!(Core<B>, pending);
        assert!(matches!(self.state, State::Exception(Cause::Boot)));
        let image = Image::ZERO
            .bytes_at(offset_of!(Core<B>, state), &State::POWER_UP_BYTES)
            .u16(word_at::<B>(word::DISABLED), self.words[word::DISABLED])
            .u16(word_at::<B>(word::FAULT_TIME), self.words[word::FAULT_TIME])
            .u16(
                word_at::<B>(word::BUS_TIMEOUT),
                self.words[word::BUS_TIMEOUT],
            )
            .byte(offset_of!(Core<B>, drive_mode), self.drive_mode as u8)
            .u16(offset_of!(Core<B>, chassis), self.chassis)
            .byte(pending + offset_of!(Pending, flags), self.pending.flags)
            .byte(
                pending + offset_of!(Pending, debug_led),
                self.pending.debug_led,
            );
        let image = self.leds.put(image, offset_of!(Core<B>, leds));
        let image = self.motors[0].put(image, motors);
        self.motors[1].put(image, motors + size_of::<Motor>())
    }

    /// The I2C address to listen on, or `None`: then the TWI must stay off.
    pub fn address(&self) -> Option<u8> {
        self.address
    }

    /// The board's variant.
    #[inline(always)]
    pub fn variant(&self) -> Variant {
        self.board.variant()
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

    /// A bus transaction addressed this board (SLA+W or SLA+R) since the previous tick:
    /// the firmware's TWI task notes it and the tick passes it on before
    /// [`Core::step`], which restarts the bus-silence count (see [`super::silence`]).
    pub fn bus_heard(&mut self) {
        self.pending.flags |= HEARD;
    }

    /// The bus-silence watch, for inspection.
    pub fn silence(&self) -> SilenceWatch {
        self.silence
    }

    /// Runs a whole tick: [`Core::take_writes`], [`Core::step`], [`Core::publish`].
    pub fn tick(&mut self, now_us: u32, inputs: &Inputs, regs: &mut RegisterFile<B>) -> Outputs {
        self.take_writes(regs);
        let outputs = self.step(now_us, inputs);
        self.publish(regs);
        outputs
    }

    /// Phase 1: applies the registers the bus changed since the previous tick, lowest id
    /// first, and clears their marks.
    pub fn take_writes(&mut self, regs: &mut RegisterFile<B>) {
        if self.address.is_none() {
            return;
        }
        while let Some(reg) = regs.take_changed() {
            let raw = regs.get(reg);
            if reg == id::REG_RESET {
                regs.set(id::REG_RESET, 0);
            }
            self.apply(reg, raw);
        }
    }

    /// Applies one register the bus wrote, as [`Core::take_writes`] does for each: for
    /// firmware that takes one change mark and its register's value at a time. The
    /// caller clears REG_RESET in the file after reading it. Ignored without an address.
    #[inline(never)]
    pub fn apply(&mut self, reg: u8, raw: u16) {
        if self.address.is_none() {
            return;
        }
        let low = raw.to_le_bytes()[0];
        // What the register does, from the variant's table (ids past it do nothing).
        let Some(action) = actions(self.variant()).get(usize::from(reg)) else {
            return;
        };
        // A word stored as it is: one indexed store for the three.
        if let Some(word) = self
            .words
            .get_mut(usize::from(action.wrapping_sub(act::WORD)))
        {
            *word = raw;
            return;
        }
        match action {
            act::RESET => {
                let bits = ResetBits(low);
                if let Some(event) = bits.event() {
                    self.handle(event);
                }
                if bits.zero_odometer() && self.variant().has_drive() {
                    self.odometer.clear();
                }
            }
            act::DEBUG_LED => {
                self.pending.debug_led = low;
                self.pending.flags |= DEBUG_LED;
            }
            act::EXCEPTION_DATA => {
                self.handle(Event::RemoteWrite);
            }
            act::PING => self.pending.flags |= PING,
            act::DRIVE_MODE if self.variant().has_drive() => {
                self.drive_mode = DriveMode::from_register(raw)
            }
            _ => {
                if let Some(param) = Param::from_index(action & !act::M2) {
                    // The motor by a choice of two addresses, not an index product.
                    let [m1, m2] = &mut self.motors;
                    let (m, motor) = if action & act::M2 != 0 {
                        (m2, MotorId::M2)
                    } else {
                        (m1, MotorId::M1)
                    };
                    m.set_param(Kind::of(self.board.variant(), motor), param, raw);
                }
            }
        }
    }

    /// Phase 2: one control tick at `now_us` (a wrapping µs clock).
    pub fn step(&mut self, now_us: u32, inputs: &Inputs) -> Outputs {
        let first = self.clock.advance(now_us);
        let now_ms = self.clock.ms();
        let Some(address) = self.address else {
            return Outputs::stopped(leds::bad_address(now_ms), Watchdog::Feed);
        };
        if first {
            // In line on both boards (measured: a call through an out-of-line copy was
            // 20 B larger on the lift/lift board, 2 B on the drive/steer board).
            self.start(now_us, now_ms);
        }
        if let State::Restarting { .. } = self.state {
            return Outputs::stopped(LedLevels::OFF, Watchdog::Reset);
        }
        self.take_pending(now_ms);
        if matches!(self.state, State::Running { .. })
            && self.silence.expired(now_ms, self.words[word::BUS_TIMEOUT])
        {
            self.handle(Event::BusSilence);
        }

        // Per motor, written out twice rather than looped: each motor's fields are then
        // at fixed addresses on the AVR, with no index arithmetic.
        self.sense_current(MotorId::M1, inputs);
        self.sense_current(MotorId::M2, inputs);
        if self.variant().has_drive() {
            self.odometer.add(inputs.edges.rising);
            self.speed.accumulate(&inputs.edges, self.clock.gap());
            let now = now_ms as u16;
            if now.wrapping_sub(self.chassis_at_ms) >= CHASSIS_PERIOD_MS {
                // A mapping costs some 400 cycles on the AVR: refreshed every 10 ms.
                self.chassis_at_ms = now;
                self.chassis = CHASSIS.map_int(inputs.adc.ch7);
            }
            if self.speed.due(self.drive_mode) {
                let speed = self.speed.measure(clock::units(now_us), self.drive_mode);
                self.update_motor(MotorId::M1, speed, now_us, now_ms);
            }
        }
        self.update_position(MotorId::M1, inputs, now_us, now_ms);
        self.update_position(MotorId::M2, inputs, now_us, now_ms);

        let motors = [self.output(MotorId::M1), self.output(MotorId::M2)];
        let [m1, m2] = &mut self.motors;
        m1.set_applied(motors[0].duty());
        m2.set_applied(motors[1].duty());
        Outputs {
            motors,
            leds: self
                .leds
                .levels(now_ms, address, self.variant(), &self.state),
            watchdog: Watchdog::Feed,
        }
    }

    /// Phase 3: writes the monitoring registers, STATUS, TIMER, INTERVALI2C,
    /// EXCEPTIONDATA and DEBUG. A motor's mapped monitoring registers (read-only to the
    /// bus) are written only when they were remapped since the previous publish, so
    /// `regs` must be the same file every tick.
    pub fn publish(&mut self, regs: &mut RegisterFile<B>) {
        if self.address.is_none() {
            return;
        }
        regs.set(id::REG_TIMER, self.clock.ms() as u16);
        regs.set(id::REG_INTERVALI2C, self.clock.interval_us());
        let exception = if self.state.in_exception() { 1 } else { 0 };
        regs.set(id::REG_STATUS, self.variant().status_bit() | exception);
        regs.set(id::REG_EXCEPTIONDATA, self.state.data());
        let debug = match self.variant() {
            Variant::DriveSteer => 0,
            Variant::LiftLift => self.motors[0].monitors().interval_ms,
        };
        regs.set(id::REG_DEBUG, debug);
        self.publish_motor(MotorId::M1, regs);
        self.publish_motor(MotorId::M2, regs);
        if self.variant().has_drive() {
            regs.set(id::REGDS_DRIVE_ODO, self.odometer.reading());
            regs.set(id::REGDS_CHASSIS, self.chassis);
        }
    }

    /// A motor's monitoring registers (see [`Core::publish`]).
    #[inline(always)]
    fn publish_motor(&mut self, motor: MotorId, regs: &mut RegisterFile<B>) {
        let layout = Layout::of(self.variant(), motor);
        let m = &mut self.motors[motor.index()];
        if m.take_fresh() {
            let first = layout.monitor_id(Monitor::Actual);
            // One out-of-line copy for both motors.
            regs.set_run_outlined(first, &m.monitors().raw);
        }
        regs.set(layout.monitor_id(Monitor::Current), u16::from(m.current()));
    }

    /// A tick's current readings into a motor's filters and the overcurrent rule.
    #[inline(always)]
    fn sense_current(&mut self, motor: MotorId, inputs: &Inputs) {
        let i = motor.index();
        let fault = self.motors[i].sense_current(inputs.adc.current[i], inputs.adc.current_peak[i]);
        self.raise(fault, motor);
    }

    /// A position motor's update, when due.
    #[inline(always)]
    fn update_position(&mut self, motor: MotorId, inputs: &Inputs, now_us: u32, now_ms: u32) {
        if Kind::of(self.variant(), motor) == Kind::Position && self.position_due(motor, now_us) {
            let reading = match (self.variant(), motor) {
                (Variant::LiftLift, MotorId::M2) => inputs.adc.ch7,
                _ => inputs.adc.ch6,
            };
            match self.variant() {
                // Two position motors: one copy of their update serves both.
                Variant::LiftLift => self.position_update_outlined(motor, reading, now_us, now_ms),
                // One: its update in line (no call on the tick).
                Variant::DriveSteer => self.position_update(motor, reading, now_us, now_ms),
            }
        }
    }

    /// [`Core::position_update`], not inlined, with the pot reading's conversion in line
    /// ([`Motor::angle_in_line`]).
    #[inline(never)]
    fn position_update_outlined(&mut self, motor: MotorId, reading: u16, now_us: u32, now_ms: u32) {
        self.motors[motor.index()].angle_in_line(reading);
        self.position_update(motor, reading, now_us, now_ms);
    }

    /// A due position update from a pot reading.
    #[inline(always)]
    fn position_update(&mut self, motor: MotorId, reading: u16, now_us: u32, now_ms: u32) {
        let cx = self.context(now_us, now_ms);
        let m = &mut self.motors[motor.index()];
        let angle = m.angle(reading);
        if m.holds(angle, &cx) {
            // At rest: no controller arithmetic, no fault check (see `Motor::holds`).
            m.hold(Kind::Position, &cx);
        } else {
            self.update_motor(motor, angle, now_us, now_ms);
        }
    }

    /// The first tick's setup: the LEDs', the motors' and the position updates' times
    /// (the speed meter counts ages from the first tick as `new` made it).
    #[inline(always)]
    fn start(&mut self, now_us: u32, now_ms: u32) {
        // The LEDs are as `new` made them (this is the first tick): only their times move.
        self.leds.start(now_ms);
        if self.variant().has_drive() {
            // Drive state only: a lift/lift board never reads it.
            self.chassis_at_ms = (now_ms as u16).wrapping_sub(CHASSIS_PERIOD_MS);
        }
        for m in &mut self.motors {
            m.start(now_us);
        }
        let first = (now_us as u16).wrapping_add(POSITION_PERIOD_US as u16);
        match self.variant() {
            // The steer only: the drive (M1) has no position deadline.
            Variant::DriveSteer => self.next_position_us[1] = first,
            // ONE and TWO on alternate ticks.
            Variant::LiftLift => {
                self.next_position_us = [first, first.wrapping_add(TICK_US as u16)]
            }
        }
    }

    #[inline(always)]
    fn take_pending(&mut self, now_ms: u32) {
        if self.pending.flags != 0 {
            match self.variant() {
                // In line on the lift/lift board (34 B smaller), a call on the
                // drive/steer board, whose tick is larger (4 B smaller): measured.
                Variant::LiftLift => self.take_requests(now_ms),
                Variant::DriveSteer => self.take_requests_outlined(now_ms),
            }
        }
    }

    /// [`Core::take_requests`], not inlined.
    #[inline(never)]
    fn take_requests_outlined(&mut self, now_ms: u32) {
        self.take_requests(now_ms);
    }

    /// What the bus asked for since the previous tick (most ticks: nothing, and a
    /// branch past this).
    #[inline(always)]
    fn take_requests(&mut self, now_ms: u32) {
        let flags = core::mem::take(&mut self.pending.flags);
        if flags & PING != 0 {
            self.leds.ping(now_ms);
            self.silence.ping(now_ms);
        }
        if flags & HEARD != 0 {
            self.silence.heard(now_ms);
        }
        if flags & DEBUG_LED != 0 {
            self.leds.debug(now_ms, self.pending.debug_led);
        }
    }

    fn position_due(&mut self, motor: MotorId, now_us: u32) -> bool {
        let long_gap = self.clock.long_gap();
        let Some(next) = self.next_position_us.get_mut(motor.index()) else {
            return false;
        };
        clock::due_every(next, now_us as u16, long_gap, POSITION_PERIOD_US as u16)
    }

    #[inline(always)]
    fn context(&self, now_us: u32, now_ms: u32) -> UpdateContext {
        UpdateContext {
            now_us,
            now_ms,
            in_exception: self.state.in_exception(),
            fault_time_ms: self.words[word::FAULT_TIME],
        }
    }

    fn update_motor(&mut self, motor: MotorId, actual: Fix, now_us: u32, now_ms: u32) {
        let cx = self.context(now_us, now_ms);
        let kind = Kind::of(self.variant(), motor);
        // Not held: the drive never holds, and a position update asked first.
        let fault = self.motors[motor.index()].update_unheld(kind, actual, &cx);
        self.raise(fault, motor);
    }

    /// DISABLEDEXCEPTIONS.
    #[inline(always)]
    fn disabled(&self) -> u16 {
        self.words[word::DISABLED]
    }

    /// An event for the state machine ([`State::handle`]) with this board's
    /// DISABLEDEXCEPTIONS. One out-of-line copy that reads the word itself, so that
    /// each caller passes only the event.
    #[inline(never)]
    fn handle(&mut self, event: Event) {
        if self.state.handle(event, self.disabled()) == Transition::Left {
            // Leaving the exception drops both demands, as an update in exception does, and
            // restarts both controllers from 0 ([`Motor::leave_exception`]): a demand written
            // in exception, or one from before it, never survives the reset, even where no
            // update came between (a drive updates every 150 ms), and no drive resumes at
            // its old output. A demand written after the reset is kept.
            let variant = self.board.variant();
            let [m1, m2] = &mut self.motors;
            m1.leave_exception(Kind::of(variant, MotorId::M1));
            m2.leave_exception(Kind::of(variant, MotorId::M2));
        }
    }

    fn raise(&mut self, fault: Option<LocalFault>, motor: MotorId) {
        if let Some(fault) = fault {
            self.handle(Event::Fault { fault, motor });
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

/// What a write to a register does in [`Core::apply`]: one byte per register id, in a
/// table per variant built at compile time ([`action_of`]) and kept in flash, where the
/// firmware compared the id with each parameter's of both motors.
mod act {
    /// A motor's parameter is its [`super::Param`]'s index, plus this bit for M2's.
    pub const M2: u8 = 0x10;
    /// A word the core stores as it is ([`super::Core`]'s `words`): this plus its
    /// [`super::word`] index.
    pub const WORD: u8 = 0x80;
    /// REG_DISABLEDEXCEPTIONS.
    pub const DISABLED: u8 = WORD + super::word::DISABLED as u8;
    /// The variant's FAULTTIME.
    pub const FAULT_TIME: u8 = WORD + super::word::FAULT_TIME as u8;
    /// The variant's BUSTIMEOUT.
    pub const BUS_TIMEOUT: u8 = WORD + super::word::BUS_TIMEOUT as u8;
    /// REG_RESET.
    pub const RESET: u8 = 0x83;
    /// REG_DEBUGLED.
    pub const DEBUG_LED: u8 = 0x84;
    /// REG_EXCEPTIONDATA.
    pub const EXCEPTION_DATA: u8 = 0x85;
    /// REG_PING.
    pub const PING: u8 = 0x86;
    /// REGDS_DRIVE_MODE (drive/steer only).
    pub const DRIVE_MODE: u8 = 0x87;
    /// Nothing.
    pub const NONE: u8 = 0xff;
}

/// Indices of [`Core`]'s `words`.
mod word {
    /// DISABLEDEXCEPTIONS.
    pub const DISABLED: usize = 0;
    /// FAULTTIME, ms.
    pub const FAULT_TIME: usize = 1;
    /// BUSTIMEOUT, ms (0 = off).
    pub const BUS_TIMEOUT: usize = 2;
}

/// Where word `index` of a `Core<B>`'s `words` is in it.
const fn word_at<B: Board>(index: usize) -> usize {
    offset_of!(Core<B>, words) + 2 * index
}

/// The [`act`] of a write to `reg` on a board of `variant`: the special registers by id
/// first, then the parameter of the motor whose block may hold it.
const fn action_of(variant: Variant, reg: u8) -> u8 {
    let (fault_time, bus_timeout) = match variant {
        Variant::DriveSteer => (id::REGDS_FAULTTIME, id::REGDS_BUSTIMEOUT),
        Variant::LiftLift => (id::REGLL_FAULTTIME, id::REGLL_BUSTIMEOUT),
    };
    match reg {
        id::REG_RESET => act::RESET,
        id::REG_DEBUGLED => act::DEBUG_LED,
        id::REG_EXCEPTIONDATA => act::EXCEPTION_DATA,
        id::REG_DISABLEDEXCEPTIONS => act::DISABLED,
        id::REG_PING => act::PING,
        _ if reg == fault_time => act::FAULT_TIME,
        _ if reg == bus_timeout => act::BUS_TIMEOUT,
        id::REGDS_DRIVE_MODE if variant.has_drive() => act::DRIVE_MODE,
        _ => {
            let motor = motor_of(variant, reg);
            match Layout::of(variant, motor).param(reg) {
                Some(param) => {
                    param as u8
                        | match motor {
                            MotorId::M1 => 0,
                            MotorId::M2 => act::M2,
                        }
                }
                None => act::NONE,
            }
        }
    }
}

/// [`action_of`] for every register of a table of `N`.
const fn actions_of<const N: usize>(variant: Variant) -> [u8; N] {
    let mut table = [act::NONE; N];
    let mut reg = 0;
    while reg < N {
        table[reg] = action_of(variant, reg as u8);
        reg += 1;
    }
    table
}

crate::flash_table! {
    /// [`action_of`] for each drive/steer register.
    static DS_ACTIONS: [u8; DS.len()] = actions_of(Variant::DriveSteer);
}

crate::flash_table! {
    /// [`action_of`] for each lift/lift register.
    static LL_ACTIONS: [u8; LL.len()] = actions_of(Variant::LiftLift);
}

/// The [`act`] table of a variant.
#[inline(always)]
fn actions(variant: Variant) -> &'static Flash<[u8]> {
    match variant {
        Variant::DriveSteer => DS_ACTIONS.as_slice(),
        Variant::LiftLift => LL_ACTIONS.as_slice(),
    }
}

/// The motor whose parameter block may hold register `reg`: M2 from its first
/// register on, else M1.
#[inline(always)]
const fn motor_of(variant: Variant, reg: u8) -> MotorId {
    if reg >= Layout::of(variant, MotorId::M2).base {
        MotorId::M2
    } else {
        MotorId::M1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_register_is_found_in_its_own_motor_s_block() {
        let mut found = 0;
        for variant in [Variant::DriveSteer, Variant::LiftLift] {
            for reg in 0..=u8::MAX {
                for motor in MotorId::BOTH {
                    if Layout::of(variant, motor).param(reg).is_some() {
                        assert_eq!(motor_of(variant, reg), motor, "{variant:?} {reg}");
                        found += 1;
                    }
                }
            }
        }
        // 2 × (7 + stall check + dead zone) + calibration on the three position motors.
        assert_eq!(found, 4 * 9 + 3 * 2);
    }

    /// What the firmware did before the table: the special registers by id, then the
    /// parameter lookup of the motor whose block may hold the id.
    fn action_by_compares(variant: Variant, reg: u8) -> u8 {
        let (fault_time, bus_timeout) = match variant {
            Variant::DriveSteer => (id::REGDS_FAULTTIME, id::REGDS_BUSTIMEOUT),
            Variant::LiftLift => (id::REGLL_FAULTTIME, id::REGLL_BUSTIMEOUT),
        };
        if reg == id::REG_RESET {
            act::RESET
        } else if reg == id::REG_DEBUGLED {
            act::DEBUG_LED
        } else if reg == id::REG_EXCEPTIONDATA {
            act::EXCEPTION_DATA
        } else if reg == id::REG_DISABLEDEXCEPTIONS {
            act::DISABLED
        } else if reg == id::REG_PING {
            act::PING
        } else if reg == fault_time {
            act::FAULT_TIME
        } else if reg == bus_timeout {
            act::BUS_TIMEOUT
        } else if reg == id::REGDS_DRIVE_MODE && variant.has_drive() {
            act::DRIVE_MODE
        } else {
            let motor = if reg >= Layout::of(variant, MotorId::M2).base {
                MotorId::M2
            } else {
                MotorId::M1
            };
            let m2 = if motor == MotorId::M2 { act::M2 } else { 0 };
            Layout::of(variant, motor)
                .param(reg)
                .map_or(act::NONE, |param| param as u8 | m2)
        }
    }

    #[test]
    fn the_action_tables_hold_each_register_s_action_and_end_with_the_table() {
        let mut params = 0;
        for variant in [Variant::DriveSteer, Variant::LiftLift] {
            let len = variant.board().len();
            for reg in 0..=u8::MAX {
                let action = actions(variant).get(usize::from(reg));
                if reg < len {
                    assert_eq!(
                        action,
                        Some(action_by_compares(variant, reg)),
                        "{variant:?} {reg}"
                    );
                    let action = action.unwrap();
                    if action < act::WORD {
                        params += 1;
                        // A parameter's index decodes to the parameter.
                        let motor = if action & act::M2 != 0 {
                            MotorId::M2
                        } else {
                            MotorId::M1
                        };
                        let param = Param::from_index(action & !act::M2).unwrap();
                        assert_eq!(Layout::of(variant, motor).param(reg), Some(param));
                    }
                } else {
                    assert_eq!(action, None, "{variant:?} {reg}");
                }
            }
        }
        // 2 × (7 + stall check + dead zone) + calibration on the three position motors.
        assert_eq!(params, 4 * 9 + 3 * 2);
        let ds = |reg| actions(Variant::DriveSteer).get(usize::from(reg));
        let ll = |reg| actions(Variant::LiftLift).get(usize::from(reg));
        assert_eq!(ds(id::REG_RESET), Some(act::RESET));
        assert_eq!(ds(id::REG_PING), Some(act::PING));
        assert_eq!(ds(id::REGDS_FAULTTIME), Some(act::FAULT_TIME));
        assert_eq!(ds(id::REGDS_BUSTIMEOUT), Some(act::BUS_TIMEOUT));
        assert_eq!(ds(id::REGDS_DRIVE_MODE), Some(act::DRIVE_MODE));
        assert_eq!(ds(id::REGDS_DRIVE_REQSPEED), Some(0));
        assert_eq!(ds(id::REGDS_DRIVE_PGAIN), Some(1));
        assert_eq!(ds(id::REGDS_DRIVE_DEADZONE), Some(8));
        assert_eq!(ds(id::REGDS_STEER_REQPOS), Some(act::M2));
        assert_eq!(ds(id::REGDS_STEER_STALLCHECK), Some(act::M2 | 7));
        assert_eq!(ds(id::REGDS_STEER_CALIBMIN), Some(act::M2 | 9));
        assert_eq!(ds(id::REGDS_STEER_CALIBMAX), Some(act::M2 | 10));
        assert_eq!(ds(id::REGDS_DRIVE_ACTUALSPEED), Some(act::NONE));
        assert_eq!(ds(id::REG_STATUS), Some(act::NONE));
        assert_eq!(ll(id::REGLL_FAULTTIME), Some(act::FAULT_TIME));
        assert_eq!(ll(id::REGLL_ONE_REQPOS), Some(0));
        assert_eq!(ll(id::REGLL_ONE_CALIBMAX), Some(10));
        assert_eq!(ll(id::REGLL_TWO_REQPOS), Some(act::M2));
        assert_eq!(ll(id::REGLL_TWO_CALIBMAX), Some(act::M2 | 10));
        assert_eq!(ll(id::REGLL_TWO_DEADZONE), Some(act::M2 | 8));
        for index in 0..=u8::MAX {
            assert_eq!(
                Param::from_index(index).map(|p| p as u8),
                (index <= 10).then_some(index)
            );
        }
    }

    #[test]
    fn the_three_words_are_stored_as_written_and_read_where_their_fields_were() {
        for (variant, fault_time, bus_timeout) in [
            (
                Variant::DriveSteer,
                id::REGDS_FAULTTIME,
                id::REGDS_BUSTIMEOUT,
            ),
            (Variant::LiftLift, id::REGLL_FAULTTIME, id::REGLL_BUSTIMEOUT),
        ] {
            let mut core = Core::new(variant, 3);
            assert_eq!(
                core.words,
                [0, FAULT_TIME_POWER_ON_MS, BUS_TIMEOUT_POWER_ON_MS]
            );
            core.apply(id::REG_DISABLEDEXCEPTIONS, 0x1234);
            core.apply(fault_time, 0x2345);
            core.apply(bus_timeout, 0x3456);
            assert_eq!(core.words, [0x1234, 0x2345, 0x3456]);
            assert_eq!(core.disabled(), 0x1234);
            assert_eq!(core.context(0, 0).fault_time_ms, 0x2345);
            // Without an address nothing is applied.
            let mut off = Core::new(variant, 0);
            off.apply(fault_time, 7);
            assert_eq!(off.words[word::FAULT_TIME], FAULT_TIME_POWER_ON_MS);
        }
    }

    #[test]
    fn a_new_board_s_motors_are_new_motors_of_its_kinds() {
        for variant in [Variant::DriveSteer, Variant::LiftLift] {
            let core = Core::new(variant, 3);
            for motor in MotorId::BOTH {
                assert_eq!(core.motor(motor), &Motor::new(Kind::of(variant, motor)));
            }
        }
        let core = Core::new(Variant::DriveSteer, 3);
        assert_eq!(core.motor(MotorId::M1).kind, Kind::Drive);
    }

    /// Zeroed memory with `B`'s power-up image and a new clock written over it: as the
    /// firmware makes its core at boot.
    #[allow(unsafe_code)]
    fn from_zeros<B: Board, const N: usize>(image: &Image<N>) -> Core<B> {
        assert_eq!(N, size_of::<Core<B>>());
        let mut pairs = vec![[0u8; 2]; image.len()];
        image.fill(&mut pairs);
        let mut memory = core::mem::MaybeUninit::<Core<B>>::zeroed();
        // SAFETY: the N bytes of `memory`, all initialised (zero), borrowed once.
        let bytes = unsafe { std::slice::from_raw_parts_mut(memory.as_mut_ptr().cast::<u8>(), N) };
        super::super::image::apply(&pairs, bytes);
        // SAFETY: the image's bytes are a valid core: the firmware checks that at compile
        // time (every field of a core is valid as zero bytes but the state, whose bytes
        // the image writes, as it writes whole fields' values over the others).
        let mut core = unsafe { memory.assume_init() };
        core.clock = Clock::new();
        core
    }

    #[test]
    fn the_power_up_image_over_zeros_makes_the_power_up_core_field_for_field() {
        const DS_SIZE: usize = size_of::<Core<DriveSteerBoard>>();
        const LL_SIZE: usize = size_of::<Core<LiftLiftBoard>>();
        let drive = Core::<DriveSteerBoard>::POWER_UP;
        let lift = Core::<LiftLiftBoard>::POWER_UP;
        // The firmware lays out a new clock's bytes: the power-up cores have one.
        assert_eq!(format!("{:?}", drive.clock), format!("{:?}", Clock::new()));
        assert_eq!(format!("{:?}", lift.clock), format!("{:?}", Clock::new()));
        let drive_image = drive.image::<DS_SIZE>();
        assert_eq!(
            format!("{:?}", from_zeros::<DriveSteerBoard, DS_SIZE>(&drive_image)),
            format!("{drive:?}")
        );
        let lift_image = lift.image::<LL_SIZE>();
        assert_eq!(
            format!("{:?}", from_zeros::<LiftLiftBoard, LL_SIZE>(&lift_image)),
            format!("{lift:?}")
        );
        // Not so with the state's bytes alone: the thresholds, the steer's kind, the LED
        // deadlines... are not 0.
        let state_only = Image::ZERO.bytes_at(
            offset_of!(Core<DriveSteerBoard>, state),
            &State::POWER_UP_BYTES,
        );
        assert_ne!(
            format!("{:?}", from_zeros::<DriveSteerBoard, DS_SIZE>(&state_only)),
            format!("{drive:?}")
        );
        // The drive's kind (0) and the steer's (1): the image has the steer's only.
        let motors = offset_of!(Core<DriveSteerBoard>, motors);
        let kind = offset_of!(Motor, kind);
        let bytes = drive_image.bytes();
        assert_eq!(bytes[motors + kind], 0);
        assert_eq!(bytes[motors + size_of::<Motor>() + kind], 1);
        let fault_time = word_at::<DriveSteerBoard>(word::FAULT_TIME);
        assert_eq!(
            bytes[fault_time..fault_time + 2],
            FAULT_TIME_POWER_ON_MS.to_le_bytes()
        );
    }

    #[test]
    fn the_compile_time_cores_equal_new_ones_once_addressed() {
        for byte in [0, 1, 9, 10, 0xff] {
            let mut drive = Core::<DriveSteerBoard>::POWER_UP;
            assert_eq!(drive.address(), None);
            drive.set_eeprom(byte);
            assert_eq!(
                format!("{drive:?}"),
                format!("{:?}", Core::new(DriveSteerBoard, byte))
            );
            let mut lift = Core::<LiftLiftBoard>::POWER_UP;
            lift.set_eeprom(byte);
            assert_eq!(
                format!("{lift:?}"),
                format!("{:?}", Core::new(LiftLiftBoard, byte))
            );
            assert_eq!(lift.address(), bus_address(byte));
        }
    }
}
