//! One motor of a slave: its parameters, its controller and its monitoring values.

use super::board::{Monitor, MotorId, Param, Variant};
use super::clock::{units, US_PER_UNIT};
use super::current::CurrentFilter;
use super::fault::{FaultDetector, Limits, Motion, STALL_CHECK_POWER_ON};
use super::image::Image;
use super::pot::{Calibration, ADC_MAX};
use super::product::wide;
use super::scale::{Mapping, Scale, Unmapping};
use super::state::LocalFault;
use crate::pid::{Duty, Fix, Form, Gains, Pid, Step};
use crate::regs::{id, DS};
use core::mem::{offset_of, size_of};

/// The monitoring registers of a motor are refreshed at most this often, µs.
pub const MONITOR_PERIOD_US: u32 = 10_000;
/// The same in units of 4 µs ([`super::clock::US_PER_UNIT`]).
const MONITOR_PERIOD: u16 = (MONITOR_PERIOD_US / US_PER_UNIT) as u16;
const _: () = assert!(MONITOR_PERIOD_US.is_multiple_of(US_PER_UNIT));

/// The power-on overcurrent threshold of every motor, raw ADC counts.
pub const THRESHOLD_POWER_ON: u16 = 300;

/// How a motor is controlled.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Kind {
    /// Speed from the encoder, incremental PID (DS M1).
    Drive,
    /// Angle from a pot, position PID (DS M2, LL M1 and M2).
    Position,
}

// Scales of the drive's and of a position motor's registers, from the DS table (the LL
// motor blocks have the same ranges; a test checks).
const DRIVE_REQUIRED: Scale = Scale::of(&DS, id::REGDS_DRIVE_REQSPEED);
const DRIVE_P: Scale = Scale::of(&DS, id::REGDS_DRIVE_PGAIN);
const POSITION_REQUIRED: Scale = Scale::of(&DS, id::REGDS_STEER_REQPOS);
const POSITION_P: Scale = Scale::of(&DS, id::REGDS_STEER_PGAIN);
const I_GAIN: Scale = Scale::of(&DS, id::REGDS_DRIVE_IGAIN);
const D_GAIN: Scale = Scale::of(&DS, id::REGDS_DRIVE_DGAIN);
const CAP: Scale = Scale::of(&DS, id::REGDS_DRIVE_INTEGRALCAP);
const DECAY: Scale = Scale::of(&DS, id::REGDS_DRIVE_INTEGRALDECAY);
const THRESHOLD: Scale = Scale::of(&DS, id::REGDS_DRIVE_OVERCURRENTTHRESH);
const STALL_CHECK: Scale = Scale::of(&DS, id::REGDS_DRIVE_STALLCHECK);
const DEAD_ZONE: Scale = Scale::of(&DS, id::REGDS_DRIVE_DEADZONE);
const CALIB: Scale = Scale::of(&DS, id::REGDS_STEER_CALIBMIN);

/// A position motor's [`Kind::param_scale`] as a table in [`Param`] order, for
/// [`Params::set`]. Read from RAM (44 B of `.data`), it costs less flash than a `match`
/// whose every arm loads its scale as immediates. (The drive's two own scales stay
/// immediates: a table entry would cost as much as their loads.)
const PARAM_UNMAPPINGS: [Unmapping; 11] = [
    POSITION_REQUIRED.unmapping(),
    POSITION_P.unmapping(),
    I_GAIN.unmapping(),
    D_GAIN.unmapping(),
    CAP.unmapping(),
    DECAY.unmapping(),
    THRESHOLD.unmapping(),
    STALL_CHECK.unmapping(),
    DEAD_ZONE.unmapping(),
    CALIB.unmapping(),
    CALIB.unmapping(),
];

const DRIVE_ACTUAL: Scale = Scale::of(&DS, id::REGDS_DRIVE_ACTUALSPEED);
const DRIVE_ERROR: Scale = Scale::of(&DS, id::REGDS_DRIVE_ERROR);
const POSITION_ACTUAL: Scale = Scale::of(&DS, id::REGDS_STEER_ACTUALPOS);
const POSITION_ERROR: Scale = Scale::of(&DS, id::REGDS_STEER_ERROR);
const INTEGRAL: Scale = Scale::of(&DS, id::REGDS_DRIVE_ERRORINTEGRAL);
const DERIV: Scale = Scale::of(&DS, id::REGDS_DRIVE_ERRORDERIV);
const CONTROL: Scale = Scale::of(&DS, id::REGDS_DRIVE_CONTROL);
const INTERVAL: Scale = Scale::of(&DS, id::REGDS_DRIVE_INTERVALCTRL);

// The monitoring scales as `static`s, for [`Kind::monitor_mapping`]: one per distinct
// mapping (7 B of `.data` each), so registers with the same range share one: the
// drive's ERROR and every ERRORINTEGRAL (±1000), a position motor's ACTUALPOS and ERROR
// and every ERRORDERIV (±200). The build fails if the tables ever give those different
// scales.
static DRIVE_ACTUAL_MAP: Mapping = DRIVE_ACTUAL.mapping();
static DRIVE_ERROR_MAP: Mapping = DRIVE_ERROR.mapping();
static POSITION_ACTUAL_MAP: Mapping = POSITION_ACTUAL.mapping();
static CONTROL_MAP: Mapping = CONTROL.mapping();
static INTERVAL_MAP: Mapping = INTERVAL.mapping();
const _: () = assert!(
    INTEGRAL.maps_as(DRIVE_ERROR)
        && POSITION_ERROR.maps_as(POSITION_ACTUAL)
        && DERIV.maps_as(POSITION_ACTUAL)
);

impl Kind {
    /// How a motor of a variant is controlled: the drive/steer board's M1 is the drive,
    /// every other motor a position motor.
    #[inline(always)]
    pub const fn of(variant: Variant, motor: MotorId) -> Kind {
        match (variant, motor) {
            (Variant::DriveSteer, MotorId::M1) => Kind::Drive,
            _ => Kind::Position,
        }
    }

    /// The scale of a mapped parameter register of this kind of motor.
    #[inline(always)]
    pub fn param_scale(self, param: Param) -> Scale {
        match (self, param) {
            (Kind::Drive, Param::Required) => DRIVE_REQUIRED,
            (Kind::Position, Param::Required) => POSITION_REQUIRED,
            (Kind::Drive, Param::P) => DRIVE_P,
            (Kind::Position, Param::P) => POSITION_P,
            (_, Param::I) => I_GAIN,
            (_, Param::D) => D_GAIN,
            (_, Param::Cap) => CAP,
            (_, Param::Decay) => DECAY,
            (_, Param::Threshold) => THRESHOLD,
            (_, Param::StallCheck) => STALL_CHECK,
            (_, Param::DeadZone) => DEAD_ZONE,
            (_, Param::CalibMin | Param::CalibMax) => CALIB,
        }
    }

    /// [`Kind::param_scale`]'s [`Unmapping`], from a table in RAM (`PARAM_UNMAPPINGS`).
    #[inline(always)]
    pub fn param_unmapping(self, param: Param) -> Unmapping {
        match (self, param) {
            (Kind::Drive, Param::Required) => DRIVE_REQUIRED.unmapping(),
            (Kind::Drive, Param::P) => DRIVE_P.unmapping(),
            // `Param` has 11 values: no bounds-check failure path is kept.
            _ => PARAM_UNMAPPINGS[param as usize],
        }
    }

    /// [`Kind::monitor_scale`]'s [`Mapping`], a `static` (what the firmware maps with).
    #[inline(always)]
    pub fn monitor_mapping(self, monitor: Monitor) -> Option<&'static Mapping> {
        Some(match (self, monitor) {
            (Kind::Drive, Monitor::Actual) => &DRIVE_ACTUAL_MAP,
            (Kind::Position, Monitor::Actual) => &POSITION_ACTUAL_MAP,
            (Kind::Drive, Monitor::Error) => &DRIVE_ERROR_MAP,
            // The statics shared by equal scales (see their definitions).
            (Kind::Position, Monitor::Error) => &POSITION_ACTUAL_MAP,
            (_, Monitor::Integral) => &DRIVE_ERROR_MAP,
            (_, Monitor::Deriv) => &POSITION_ACTUAL_MAP,
            (_, Monitor::Control) => &CONTROL_MAP,
            (_, Monitor::Interval) => &INTERVAL_MAP,
            (_, Monitor::Current) => return None,
        })
    }

    /// The scale of a mapped monitoring register of this kind of motor (`None` for
    /// CURRENT, which is unmapped).
    #[inline(always)]
    pub fn monitor_scale(self, monitor: Monitor) -> Option<Scale> {
        Some(match (self, monitor) {
            (Kind::Drive, Monitor::Actual) => DRIVE_ACTUAL,
            (Kind::Position, Monitor::Actual) => POSITION_ACTUAL,
            (Kind::Drive, Monitor::Error) => DRIVE_ERROR,
            (Kind::Position, Monitor::Error) => POSITION_ERROR,
            (_, Monitor::Integral) => INTEGRAL,
            (_, Monitor::Deriv) => DERIV,
            (_, Monitor::Control) => CONTROL,
            (_, Monitor::Interval) => INTERVAL,
            (_, Monitor::Current) => return None,
        })
    }
}

/// A motor's parameters as the slave acts on them.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Params {
    /// Gains, integral cap and decay, dead zone.
    pub gains: Gains,
    /// The demand: ticks/s or degrees.
    pub required: Fix,
    /// OVERCURRENTTHRESH, raw ADC counts.
    pub threshold: u16,
    /// STALLCHECK, duty.
    pub stall_check: u8,
    /// CALIBMIN/CALIBMAX (position motors).
    pub calibration: Calibration,
}

impl Params {
    /// The power-on parameters (reference §8.1).
    pub const POWER_ON: Params = Params {
        gains: Gains::ZERO,
        required: Fix::ZERO,
        threshold: THRESHOLD_POWER_ON,
        stall_check: STALL_CHECK_POWER_ON,
        calibration: Calibration::POWER_ON,
    };

    /// Applies a written register. Never inlined: the tick applies writes to either
    /// motor, and one copy of the eleven conversions serves both.
    #[inline(never)]
    pub fn set(&mut self, kind: Kind, param: Param, raw: u16) {
        // One conversion for every parameter, then one store.
        let value = kind.param_unmapping(param).unmap(raw);
        match param {
            Param::Threshold => self.threshold = Scale::whole(value),
            Param::StallCheck => {
                self.stall_check = u8::try_from(Scale::whole(value)).unwrap_or(u8::MAX)
            }
            Param::CalibMin | Param::CalibMax => {
                // One rebuild for both ends: the other end kept.
                let c = &mut self.calibration;
                let (min, max) = match param {
                    Param::CalibMin => (value, c.max()),
                    _ => (c.min(), value),
                };
                *c = Calibration::new(min, max);
            }
            // The seven plain values through one store at the parameter's offset, from
            // a table, where a `match` choosing the field took a tree of compares.
            _ => {
                let at = PLAIN_AT.get(param as usize).unwrap_or(PLAIN_AT_NONE);
                self.put_plain(at, value);
            }
        }
    }

    /// Stores `value` in the plain value at offset `at` ([`PLAIN_AT`]).
    #[allow(unsafe_code)]
    #[inline(always)]
    fn put_plain(&mut self, at: u8, value: Fix) {
        // The offset of a plain value, not past the parameters' end (also for a table
        // entry that `set` never reads).
        debug_assert!(usize::from(at) + size_of::<Fix>() <= size_of::<Params>());
        // SAFETY: every `PLAIN_AT` entry (and `PLAIN_AT_NONE`) is the offset of a `Fix`
        // field of `Params` (a host test checks each against the field), so the write
        // stays inside `*self` and replaces one field's value with another valid value
        // (a `Fix` is valid for any bits); unaligned, as the fields may be on the host.
        unsafe {
            core::ptr::from_mut(self)
                .cast::<u8>()
                .add(usize::from(at))
                .cast::<Fix>()
                .write_unaligned(value)
        }
    }
}

/// [`PLAIN_AT`]'s value for a parameter that is not plain: [`Params::required`]'s offset
/// (never used so; an offset inside the parameters all the same).
const PLAIN_AT_NONE: u8 = offset_of!(Params, required) as u8;

/// The offset in [`Params`] of each plain parameter's value (indexed by [`Param`]; the
/// threshold's, the stall check's and the calibration's entries are
/// [`PLAIN_AT_NONE`]), for [`Params::set`].
const fn plain_at() -> [u8; 11] {
    let gains = offset_of!(Params, gains);
    let mut table = [PLAIN_AT_NONE; 11];
    table[Param::Required as usize] = offset_of!(Params, required) as u8;
    table[Param::P as usize] = (gains + offset_of!(Gains, p)) as u8;
    table[Param::I as usize] = (gains + offset_of!(Gains, i)) as u8;
    table[Param::D as usize] = (gains + offset_of!(Gains, d)) as u8;
    table[Param::Cap as usize] = (gains + offset_of!(Gains, cap)) as u8;
    table[Param::Decay as usize] = (gains + offset_of!(Gains, decay)) as u8;
    table[Param::DeadZone as usize] = (gains + offset_of!(Gains, dead_zone)) as u8;
    table
}

crate::flash_table! {
    /// [`plain_at`], in flash.
    static PLAIN_AT: [u8; 11] = plain_at();
}

/// The raw monitoring values of a motor, refreshed from its updates.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Monitors {
    /// ACTUAL…, ERROR, ERRORINTEGRAL, ERRORDERIV, CONTROL, INTERVALCTRL (raw), in table
    /// order: the registers from the motor's [`Monitor::Actual`] on.
    pub raw: [u16; 6],
    /// INTERVALCTRL in ms, unmapped (LL's REG_DEBUG shows lift ONE's).
    pub interval_ms: u16,
}

/// [`Motor::angle`] has no reading: above any the ADC gives (the first such value, with
/// one nonzero byte where `u16::MAX` had two: the power-up core's image is the shorter).
const NO_READING: u16 = ADC_MAX + 1;

/// Raw 0 in a symmetric range.
const MID: u16 = 0x7fff;

/// [`Motor::record`]'s control in exception: no duty (above any), its low byte the duty
/// applied then, 0.
const NO_CONTROL: u16 = 0xff00;

impl Monitors {
    /// Before the first update: every value 0.
    pub const POWER_ON: Monitors = Monitors {
        raw: [MID, MID, MID, MID, MID, 0],
        interval_ms: 0,
    };

    /// The raw value of a monitoring register (`None` for CURRENT).
    pub fn get(&self, monitor: Monitor) -> Option<u16> {
        let index = match monitor {
            Monitor::Actual => 0,
            Monitor::Error => 1,
            Monitor::Integral => 2,
            Monitor::Deriv => 3,
            Monitor::Control => 4,
            Monitor::Interval => 5,
            Monitor::Current => return None,
        };
        self.raw.get(index).copied()
    }
}

/// What a motor's update needs besides its own state.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct UpdateContext {
    /// Now, µs.
    pub now_us: u32,
    /// Now, ms since boot.
    pub now_ms: u32,
    /// The slave is in exception: demands are overwritten and the output not applied.
    pub in_exception: bool,
    /// FAULTTIME, ms.
    pub fault_time_ms: u16,
}

/// One motor. `repr(C)`, in this order: what the update reaches (the fault detector,
/// the parameters and the controller) within the AVR's 64-byte `LDD`/`STD` reach of its
/// start.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(C)]
pub struct Motor {
    /// How it is controlled.
    pub kind: Kind,
    fault: FaultDetector,
    /// The last update was a position update outside an exception after which the
    /// same measurement gives [`Step::REST`] ([`Step::rests`]), and no parameter was set
    /// since.
    at_rest: bool,
    /// The duty the controller last asked for.
    demand: Duty,
    /// Its parameters: read them here, set them through [`Motor::set_param`] (which
    /// forgets what depends on them).
    pub params: Params,
    /// The controller and the monitoring record's state.
    track: Track,
    /// The CURRENT register's filter (with the original's wrap).
    current: CurrentFilter,
    /// The same filter without the wrap, for the fault detector.
    level: CurrentFilter,
    /// The last pot reading [`Motor::angle`] converted (clamped to the ADC's range;
    /// [`NO_READING`] when none), and its angle.
    angle_reading: u16,
    angle: Fix,
    /// The duty applied to the motor now (0 when stopped).
    applied: u8,
}

impl Motor {
    /// A motor at power-up.
    pub const fn new(kind: Kind) -> Motor {
        Motor {
            kind,
            params: Params::POWER_ON,
            track: Track {
                pid: Pid::new(),
                last_update: 0,
                since_mapped: 0,
                monitors: Monitors::POWER_ON,
                mapped_from: MappedFrom::POWER_ON,
                fresh: true,
                last_duty: 0,
            },
            current: CurrentFilter::new(),
            level: CurrentFilter::new(),
            fault: FaultDetector::new(),
            angle_reading: NO_READING,
            angle: Fix::ZERO,
            at_rest: false,
            demand: Duty::IDLE,
            applied: 0,
        }
    }

    /// This motor's bytes into `image` at `at` (see [`super::image`]): each field that
    /// may be nonzero at power-up; the others (the controller's, the filters' and the
    /// fault detector's state, the times) are zero there, as the core's host test checks.
    pub(crate) const fn put<const N: usize>(&self, image: Image<N>, at: usize) -> Image<N> {
        let params = at + offset_of!(Motor, params);
        let track = at + offset_of!(Motor, track);
        let monitors = track + offset_of!(Track, monitors);
        let mut image = self.params.calibration.put(
            image
                .byte(at + offset_of!(Motor, kind), self.kind as u8)
                .bool(at + offset_of!(Motor, at_rest), self.at_rest)
                .u16(
                    params + offset_of!(Params, threshold),
                    self.params.threshold,
                )
                .byte(
                    params + offset_of!(Params, stall_check),
                    self.params.stall_check,
                )
                .i32(
                    params + offset_of!(Params, required),
                    self.params.required.to_bits(),
                )
                .u16(
                    monitors + offset_of!(Monitors, interval_ms),
                    self.track.monitors.interval_ms,
                )
                .bool(track + offset_of!(Track, fresh), self.track.fresh)
                .u16(at + offset_of!(Motor, angle_reading), self.angle_reading)
                .i32(at + offset_of!(Motor, angle), self.angle.to_bits())
                .byte(at + offset_of!(Motor, applied), self.applied),
            params + offset_of!(Params, calibration),
        );
        let raw = &self.track.monitors.raw;
        let mut i = 0;
        while i < raw.len() {
            image = image.u16(monitors + offset_of!(Monitors, raw) + 2 * i, raw[i]);
            i += 1;
        }
        image
    }

    /// Applies a written parameter register ([`Params::set`]).
    pub fn set_param(&mut self, kind: Kind, param: Param, raw: u16) {
        self.params.set(kind, param, raw);
        self.angle_reading = NO_READING;
        self.at_rest = false;
    }

    /// Replaces the demand as an update in exception does (position: required := the
    /// last measured angle; drive: required := 0), and restarts the controller's output
    /// and integral from 0 ([`Pid::restart`]), with duty 0 until the next update: the
    /// board does it as it leaves an
    /// exception, since a drive updates only every 150 ms and a demand written in
    /// exception would otherwise survive a reset that came before the next update, and a
    /// drive would resume at the output it had when it stopped.
    #[inline(never)]
    pub fn leave_exception(&mut self, kind: Kind) {
        self.params.required = match kind {
            Kind::Position => self.track.pid.last_actual(),
            Kind::Drive => Fix::ZERO,
        };
        self.track.pid.restart();
        // The duty of the last update in exception is not applied either.
        self.demand = Duty::IDLE;
    }

    /// The angle of a pot reading, by the calibration ([`Calibration::angle`]). The last
    /// conversion is kept, so a motor at rest (the same reading again) costs none; it
    /// is forgotten when a parameter is set through [`Motor::set_param`], so the
    /// calibration must change only through it.
    #[inline(always)]
    pub fn angle(&mut self, reading: u16) -> Fix {
        // The angle treats every reading above the ADC's range as its top.
        let reading = reading.min(ADC_MAX);
        if reading == self.angle_reading {
            return self.angle;
        }
        self.convert(reading)
    }

    /// [`Motor::angle`] with the conversion in line, for a caller that is itself the one
    /// out-of-line copy of a position update (the lift/lift board's): a [`Motor::angle`]
    /// of the same reading right after it finds the conversion kept, so that caller
    /// needs no call to `Motor::convert` (98 B less on that board; in the drive/steer
    /// board's tick the call is smaller).
    #[inline(always)]
    pub fn angle_in_line(&mut self, reading: u16) {
        let reading = reading.min(ADC_MAX);
        if reading != self.angle_reading {
            self.keep_angle(reading);
        }
    }

    /// [`Motor::angle`] of a new reading.
    #[inline(never)]
    fn convert(&mut self, reading: u16) -> Fix {
        self.keep_angle(reading);
        self.angle
    }

    /// Converts `reading` and keeps it with its angle.
    #[inline(always)]
    fn keep_angle(&mut self, reading: u16) {
        self.angle = self.params.calibration.angle(reading);
        self.angle_reading = reading;
    }

    /// Starts the interval clock at the board's first tick.
    pub fn start(&mut self, now_us: u32) {
        self.track.last_update = units(now_us);
        // The first update maps.
        self.track.since_mapped = MONITOR_PERIOD;
    }

    /// Feeds a tick's current readings; returns an overcurrent fault if the peak is above
    /// the threshold.
    #[inline(always)]
    pub fn sense_current(&mut self, latest: u16, peak: u16) -> Option<LocalFault> {
        if latest <= 255 && self.current == self.level {
            // The usual case: both filters hold the same value and get the same sample
            // (no wrap, no saturation), so one step serves both.
            self.current.push(latest);
            self.level = self.current;
        } else {
            self.push_apart(latest);
        }
        super::current::overcurrent(peak, self.params.threshold, self.applied)
    }

    /// Feeds both filters, each its own way.
    #[inline(never)]
    fn push_apart(&mut self, latest: u16) {
        self.current.push_outlined(latest);
        self.level.push_saturating(latest);
    }

    /// One control update with the measured value (ticks/s or degrees). In exception the
    /// demand is overwritten first (position: required := actual; drive: required := 0)
    /// and CONTROL keeps the last applied duty. Returns a stall or sensor fault.
    pub fn update(&mut self, actual: Fix, cx: &UpdateContext) -> Option<LocalFault> {
        self.update_as(self.kind, actual, cx)
    }

    /// [`Motor::update`] for a motor of `kind` (its own): the board passes the kind its
    /// variant fixes, so that a build-time variant resolves it at compile time.
    #[inline(always)]
    pub fn update_as(&mut self, kind: Kind, actual: Fix, cx: &UpdateContext) -> Option<LocalFault> {
        if self.holds(actual, cx) {
            self.hold(kind, cx);
            return None;
        }
        self.update_unheld(kind, actual, cx)
    }

    /// [`Motor::update_as`] for an update that does not hold ([`Motor::holds`] false):
    /// for a caller that has just asked, or for the drive, which never holds (only a
    /// position update rests). The board's updates come through here, so the image
    /// carries one hold test, the caller's.
    #[inline(always)]
    pub fn update_unheld(
        &mut self,
        kind: Kind,
        actual: Fix,
        cx: &UpdateContext,
    ) -> Option<LocalFault> {
        let position = kind == Kind::Position;
        // The demand, overwritten in exception: stored either way, so that the paths
        // join before the controller's one call for both forms.
        // In exception the actual angle or 0: the angle masked by the kind, in bits (a
        // branch on the kind would give each case its own copy of the call below).
        let required = if cx.in_exception {
            Fix::from_bits(actual.to_bits() & i32::from(position).wrapping_neg())
        } else {
            self.params.required
        };
        self.params.required = required;
        let form = if position {
            Form::Position
        } else {
            Form::Speed
        };
        let step = self
            .track
            .pid
            .update(form, &self.params.gains, required, actual);
        // `&` on the kind, not `&&`: a branch on it here would let the optimiser split the
        // drive/steer board's update by kind from the controller's form on and carry the
        // duty's conversion twice (54 B).
        self.at_rest = position & (!cx.in_exception && step.rests());
        self.demand = step.duty;
        let control = if cx.in_exception {
            NO_CONTROL
        } else {
            u16::from(step.duty.magnitude)
        };
        // The duty applied: 0 in exception (NO_CONTROL's low byte).
        let duty = control as u8;
        self.track.record(kind, step.error, step.deriv, control, cx);
        let motion = match kind {
            Kind::Drive => Motion::Speed(actual),
            Kind::Position => Motion::Angle(actual),
        };
        let limits = Limits {
            stall_check: self.params.stall_check,
            fault_time_ms: cx.fault_time_ms,
        };
        self.fault
            .update(cx.now_ms, duty, motion, self.level.reading(), &limits)
    }

    /// Whether an update with `actual` holds the motor at rest: the last update was a
    /// position update outside an exception after which the same measurement gives
    /// [`Step::REST`] ([`Step::rests`]), no parameter was set since, and the measurement
    /// is the same. Such an update returns [`Step::REST`]
    /// again and leaves the controller, the demand (duty 0) and the fault detector (which
    /// a duty of 0 keeps reset) as they are: [`Motor::hold`], the interval and the
    /// monitoring values, is all that is left of it.
    #[inline(always)]
    pub fn holds(&self, actual: Fix, cx: &UpdateContext) -> bool {
        self.at_rest && !cx.in_exception && !differ(self.track.pid.last_actual(), actual)
    }

    /// An update that [`Motor::holds`]: only the interval and the monitoring values (its
    /// measurement is the controller's last, [`Pid::last_actual`]).
    #[inline(always)]
    pub fn hold(&mut self, kind: Kind, cx: &UpdateContext) {
        // At rest the controller holds this measurement and I = 0 ([`Step::rests`]).
        self.track
            .record(kind, Step::REST.error, Step::REST.deriv, 0, cx);
    }

    /// The output for the motor while the slave runs normally.
    pub fn demand(&self) -> Duty {
        self.demand
    }

    /// Records the duty the firmware applies (0 when stopped).
    pub fn set_applied(&mut self, duty: u8) {
        self.applied = duty;
    }

    /// CURRENT: the filtered current, 0..255.
    pub fn current(&self) -> u8 {
        self.current.reading()
    }

    /// The wrap-free filtered current the fault detector uses.
    pub fn current_level(&self) -> u8 {
        self.level.reading()
    }

    /// The monitoring values.
    pub fn monitors(&self) -> &Monitors {
        &self.track.monitors
    }

    /// Whether the mapped monitoring values changed since the previous call (true at
    /// power-up), clearing the mark: they need writing to the register file only then.
    pub fn take_fresh(&mut self) -> bool {
        core::mem::take(&mut self.track.fresh)
    }

    /// The controller's state.
    pub fn pid(&self) -> &Pid {
        &self.track.pid
    }
}

/// A motor's controller with what its monitoring record keeps, together (`repr(C)`, 42
/// B): [`Track::record`] reaches every field at a displacement below 64 from one pointer
/// (the AVR's `LDD`/`STD` reach), where from the motor's start most of them took an
/// address sum each.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(C)]
struct Track {
    pid: Pid,
    /// When the previous update ran (or the board started), in wrapping 16-bit units of
    /// 4 µs ([`units`]): the interval to the next is exact below 2^16 units (262,144 µs;
    /// a motor updates at least every 150 ms and a tick, see [`Track::record`]).
    last_update: u16,
    /// Units from the last mapping of the monitoring values to the previous update (or
    /// to the start): below [`MONITOR_PERIOD`] after each update.
    since_mapped: u16,
    monitors: Monitors,
    /// What the monitoring values were last mapped from (at power-up: what
    /// [`Monitors::POWER_ON`] maps from).
    mapped_from: MappedFrom,
    /// The mapped monitoring values changed since [`Motor::take_fresh`] last ran.
    fresh: bool,
    /// The duty of the last update outside an exception: what CONTROL shows, also through
    /// an exception that began between two mappings.
    last_duty: u8,
}

// On the AVR (every field 1-aligned) a field's last byte is within `LDD`/`STD` reach,
// and so is the motor's controller from the motor's start.
#[cfg(target_arch = "avr")]
const _: () = {
    use core::mem::{offset_of, size_of};
    assert!(size_of::<Track>() <= 64);
    assert!(offset_of!(Motor, track) + offset_of!(Track, pid) + size_of::<Pid>() <= 64);
};

impl Track {
    /// The interval since the previous update, and the monitoring values when due, for
    /// an update whose step had the error `error` and the derivative `deriv` (both 0 for
    /// an update that holds: [`Step::REST`]). One copy for [`Motor::update_as`] and
    /// [`Motor::hold`]. The measurement and the integral are the controller's own after
    /// the update ([`Pid::last_actual`], [`Pid::integral`]: an update that holds has
    /// just checked the one and rests with the other 0), so the step's four values
    /// that do change pass in registers, not through memory. `control` is the duty
    /// applied, or [`NO_CONTROL`] in exception (CONTROL keeps its value): one argument
    /// where a duty and the exception flag took two register pairs, so every argument
    /// fits the registers the AVR passes them in (48 / 6 B less than with the context's
    /// values passed on the stack).
    #[inline(never)]
    fn record(&mut self, kind: Kind, error: Fix, deriv: Fix, control: u16, cx: &UpdateContext) {
        // The interval in 16-bit units: the same as the µs form's (a 32-bit timestamp)
        // while updates are less than 2^16 units apart, which they are on the board: a
        // motor updates at least every 150 ms and a tick (the drive's window; the position
        // motors every 2 ms), and ticks are 1 ms apart (the clock flags a gap of 2^15 µs,
        // and the watchdog resets a board whose tick stalls for 1.024 s). Tested against
        // the µs form.
        let now = units(cx.now_us);
        let gap = now.wrapping_sub(self.last_update);
        let interval_ms = interval_ms(gap);
        self.last_update = now;
        self.monitors.interval_ms = interval_ms;
        // Mapping six values costs more than the update itself on the AVR, so the
        // monitoring registers are refreshed from every update at most every 10 ms: the
        // time since the last mapping (saturating, so at least the period whenever the
        // exact sum is).
        // A duty, not NO_CONTROL: the last one applied.
        if let Ok(duty) = u8::try_from(control) {
            self.last_duty = duty;
        }
        let since = self.since_mapped.saturating_add(gap);
        self.since_mapped = since;
        if since >= MONITOR_PERIOD {
            self.since_mapped = 0;
            self.fresh = true;
            // A value equal to the one last mapped keeps its raw value: a motor at rest
            // maps nothing. Before the first mapping the raw values are those of 0
            // (tested), so the first maps only what is not 0.
            let actual = self.pid.last_actual();
            let integral = self.pid.integral();
            let from = &mut self.mapped_from;
            let raw = &mut self.monitors.raw;
            let scale = |monitor| kind.monitor_mapping(monitor);
            if from.actual != actual {
                from.actual = actual;
                raw[0] = map_by(scale(Monitor::Actual), actual);
            }
            // The three values' bits OR-ed, folded to 16 bits: 0 exactly when all are 0.
            // Unless they and the last mapped ones are all 0, map them.
            let bits = (error.to_bits() | integral.to_bits() | deriv.to_bits()) as u32;
            let terms = bits as u16 | (bits >> 16) as u16;
            if terms | from.terms != 0 {
                from.terms = terms;
                raw[1] = map_by(scale(Monitor::Error), error);
                raw[2] = map_by(scale(Monitor::Integral), integral);
                raw[3] = map_by(scale(Monitor::Deriv), deriv);
            }
            if from.interval_ms != interval_ms {
                from.interval_ms = interval_ms;
                raw[5] = INTERVAL_MAP.map_int(interval_ms);
            }
            let duty = self.last_duty;
            if from.duty != duty {
                from.duty = duty;
                raw[4] = CONTROL_MAP.map_int(u16::from(duty));
            }
        }
    }
}

/// The values a motor's monitoring registers were last mapped from.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct MappedFrom {
    actual: Fix,
    /// 0 exactly when ERROR, ERRORINTEGRAL and ERRORDERIV were all 0 (as at rest).
    terms: u16,
    interval_ms: u16,
    /// CONTROL's duty (not mapped in exception).
    duty: u8,
}

impl MappedFrom {
    /// What [`Monitors::POWER_ON`]'s raw values are the mapping of: every value 0.
    const POWER_ON: MappedFrom = MappedFrom {
        actual: Fix::ZERO,
        terms: 0,
        interval_ms: 0,
        duty: 0,
    };
}

/// Whether `a` ≠ `b`, by their bits' difference folded to 16 bits (lo | hi of a ^ b):
/// the AVR's 32-bit comparison materialises a flag, this is four XORs, two ORs and one
/// 16-bit test.
#[inline(always)]
fn differ(a: Fix, b: Fix) -> bool {
    let bits = (a.to_bits() ^ b.to_bits()) as u32;
    (bits as u16 | (bits >> 16) as u16) != 0
}

/// [`map`] by a monitoring register's [`Mapping`].
#[inline(always)]
fn map_by(mapping: Option<&Mapping>, value: Fix) -> u16 {
    mapping.map_or(0, |mapping| mapping.map(value))
}

/// ⌊4·units/1000⌋ = ⌊units/250⌋ = ⌊y/125⌋ for y = ⌊units/2⌋ < 2^15: ⌊y·33,555/2^22⌋
/// for every such y (tested exhaustively), one 16×16 product's high half shifted.
#[inline(always)]
fn interval_ms(units: u16) -> u16 {
    ((wide(units >> 1, 33_555) >> 16) as u16) >> 6
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Params::set`] as it was before [`PLAIN_AT`]: a `match` choosing the field.
    fn set_by_match(params: &mut Params, kind: Kind, param: Param, raw: u16) {
        let value = kind.param_unmapping(param).unmap(raw);
        let g = &mut params.gains;
        let slot = match param {
            Param::Threshold => return params.threshold = Scale::whole(value),
            Param::StallCheck => {
                return params.stall_check = u8::try_from(Scale::whole(value)).unwrap_or(u8::MAX)
            }
            Param::CalibMin | Param::CalibMax => {
                let c = &mut params.calibration;
                let (min, max) = match param {
                    Param::CalibMin => (value, c.max()),
                    _ => (c.min(), value),
                };
                return *c = Calibration::new(min, max);
            }
            Param::Required => &mut params.required,
            Param::P => &mut g.p,
            Param::I => &mut g.i,
            Param::D => &mut g.d,
            Param::Cap => &mut g.cap,
            Param::Decay => &mut g.decay,
            Param::DeadZone => &mut g.dead_zone,
        };
        *slot = value;
    }

    #[test]
    fn set_stores_each_parameter_where_the_match_did_for_every_raw_value() {
        // Each plain parameter's table entry is its own field's offset.
        let gains = offset_of!(Params, gains);
        let expected = [
            (Param::Required, offset_of!(Params, required)),
            (Param::P, gains + offset_of!(Gains, p)),
            (Param::I, gains + offset_of!(Gains, i)),
            (Param::D, gains + offset_of!(Gains, d)),
            (Param::Cap, gains + offset_of!(Gains, cap)),
            (Param::Decay, gains + offset_of!(Gains, decay)),
            (Param::DeadZone, gains + offset_of!(Gains, dead_zone)),
        ];
        for (param, at) in expected {
            assert_eq!(PLAIN_AT.get(param as usize), Some(at as u8), "{param:?}");
        }
        assert_eq!(PLAIN_AT.get(11), None);
        // Every parameter, both kinds, every raw value, from a start where every field
        // differs from the others: the same parameters as the match gave.
        let mut start = Params::POWER_ON;
        set_by_match(&mut start, Kind::Position, Param::P, 0x1111);
        set_by_match(&mut start, Kind::Position, Param::I, 0x2222);
        set_by_match(&mut start, Kind::Position, Param::D, 0x3333);
        set_by_match(&mut start, Kind::Position, Param::Cap, 0x4444);
        set_by_match(&mut start, Kind::Position, Param::Decay, 0x5555);
        set_by_match(&mut start, Kind::Position, Param::DeadZone, 0x6666);
        set_by_match(&mut start, Kind::Position, Param::Required, 0x7777);
        let mut changed = 0u32;
        for kind in [Kind::Drive, Kind::Position] {
            for index in 0..11 {
                let param = Param::from_index(index).unwrap();
                for raw in 0..=u16::MAX {
                    let mut a = start;
                    let mut b = start;
                    a.set(kind, param, raw);
                    set_by_match(&mut b, kind, param, raw);
                    assert_eq!(a, b, "{kind:?} {param:?} {raw:#x}");
                    changed += u32::from(a != start);
                }
            }
        }
        assert!(changed > 2 * 11 * 30_000, "{changed}");
    }

    /// A monitoring value's raw value by its [`Scale`] (0 for CURRENT, which has none).
    fn map(scale: Option<Scale>, value: Fix) -> u16 {
        scale.map_or(0, |scale| scale.map(value))
    }

    #[test]
    fn the_monitoring_statics_are_each_kind_and_monitor_s_scale() {
        let values = [
            -5_000.0, -4_000.0, -200.5, -1.0, -0.001, 0.0, 0.25, 17.0, 999.9, 4_000.0,
        ];
        let mut mapped = 0;
        for kind in [Kind::Drive, Kind::Position] {
            for monitor in Monitor::ALL {
                let scale = kind.monitor_scale(monitor);
                let mapping = kind.monitor_mapping(monitor);
                assert_eq!(
                    mapping.copied(),
                    scale.map(Scale::mapping),
                    "{kind:?} {monitor:?}"
                );
                for v in values {
                    let v = Fix::from_num(v);
                    assert_eq!(
                        map_by(mapping, v),
                        map(scale, v),
                        "{kind:?} {monitor:?} {v}"
                    );
                    mapped += usize::from(map_by(mapping, v) != 0);
                }
            }
            assert_eq!(kind.monitor_mapping(Monitor::Current), None);
        }
        assert_eq!(
            &INTERVAL_MAP,
            Kind::Drive.monitor_mapping(Monitor::Interval).unwrap()
        );
        assert_eq!(INTERVAL_MAP.map_int(2), INTERVAL.map_int(2));
        assert_eq!(CONTROL_MAP.map_int(255), 0xfffe);
        assert!(mapped > 80, "{mapped}");
    }

    #[test]
    fn the_interval_in_units_is_the_whole_ms_of_four_times_it() {
        for units in 0..=u16::MAX {
            assert_eq!(
                u32::from(interval_ms(units)),
                4 * u32::from(units) / 1000,
                "{units}"
            );
        }
    }

    #[test]
    fn the_interval_and_the_mapping_period_are_as_with_a_32_bit_timestamp() {
        // The form replaced: the 32-bit µs of the previous update and of the last mapping
        // (0 at power-up, 10 ms before the start), the interval ⌊gap/1000⌋ and the mapping
        // due when now − it ≥ 10 ms, wrapping. Gaps in whole units (the chip's time) below
        // 2^16 units, as on the board: short ones (the position motors' 2 ms), the drive's
        // 150 ms windows and 10 ms updates, late ones, the longest (2^18 − 4 µs), across
        // the clock's wrap.
        let mut m = Motor::new(Kind::Position);
        let (mut mapped_us, mut last_us) = (0u32, 0u32);
        let mut now = u32::MAX - 3_000_000 + 1;
        let mut seed = 0x2545_f491u32;
        let (mut due, mut not_due, mut long) = (0, 0, 0);
        assert!(m.take_fresh());
        for k in 0..60_000 {
            if k == 0 || k == 40_000 {
                m.start(now);
                mapped_us = now.wrapping_sub(MONITOR_PERIOD_US);
                last_us = now;
            }
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            let gap = 4 * match seed % 10 {
                0 => (seed >> 8) % 65_536,
                1 => 65_535 - seed % 30,
                2 => 37_500 + seed % 300,
                3 => 2_500 + seed % 8_192,
                4..=6 => seed % 3_000,
                _ => seed % 750,
            };
            long += usize::from(gap > 150_000);
            now = now.wrapping_add(gap);
            let cx = UpdateContext {
                now_us: now,
                now_ms: now / 1000,
                in_exception: false,
                fault_time_ms: 500,
            };
            m.update(Fix::from_bits((seed as i32) >> 9), &cx);
            let interval = now.wrapping_sub(last_us) / 1000;
            last_us = now;
            assert_eq!(u32::from(m.monitors().interval_ms), interval, "update {k}");
            let want = now.wrapping_sub(mapped_us) >= MONITOR_PERIOD_US;
            if want {
                mapped_us = now;
                due += 1;
            } else {
                not_due += 1;
            }
            assert_eq!(m.take_fresh(), want, "update {k}, gap {gap}");
        }
        assert!(
            due > 20_000 && not_due > 10_000 && long > 5_000,
            "{due} {not_due} {long}"
        );
    }

    #[test]
    fn terms_remap_whenever_any_bit_of_them_or_of_the_last_is_set() {
        // Values with bits in one half only, both halves, and none, in every order: the
        // raw ERROR and ERRORDERIV after each due record are those values' mapping.
        let bits = [
            0,
            1,
            0,
            0x1_0000,
            0,
            -1,
            i32::MIN,
            0,
            0,
            0x8000,
            0x7fff_0000,
            0,
        ];
        let mut m = Motor::new(Kind::Drive);
        m.start(0);
        let scale = |monitor| Kind::Drive.monitor_scale(monitor);
        let (mut mapped_nonzero, mut now_us) = (0, 0);
        for (k, &e) in bits.iter().enumerate() {
            for (error, deriv) in [(e, 0), (0, e), (e, e)] {
                // 10 ms on: every record maps.
                now_us += 10_000;
                let cx = UpdateContext {
                    now_us,
                    now_ms: now_us / 1000,
                    in_exception: false,
                    fault_time_ms: 500,
                };
                let (error, deriv) = (Fix::from_bits(error), Fix::from_bits(deriv));
                m.track.record(Kind::Drive, error, deriv, 0, &cx);
                assert!(m.take_fresh(), "{k}");
                let raw = m.monitors().raw;
                assert_eq!(raw[1], map(scale(Monitor::Error), error), "{k} {error}");
                assert_eq!(raw[3], map(scale(Monitor::Deriv), deriv), "{k} {deriv}");
                mapped_nonzero += usize::from(raw[1] != MID || raw[3] != MID);
            }
        }
        assert!(mapped_nonzero > 12, "{mapped_nonzero}");
    }

    #[test]
    fn differ_is_the_bits_not_equal() {
        let values = [
            0,
            1,
            -1,
            0xffff,
            0x1_0000,
            0x1_0001,
            i32::MIN,
            i32::MAX,
            0x7fff_0000,
        ];
        let mut equal = 0;
        for a in values {
            for b in values {
                let (fa, fb) = (Fix::from_bits(a), Fix::from_bits(b));
                assert_eq!(differ(fa, fb), a != b, "{a:#x} {b:#x}");
                equal += usize::from(a == b);
            }
        }
        assert_eq!(equal, values.len());
    }

    #[test]
    fn control_keeps_the_last_applied_duty_in_exception() {
        for kind in [Kind::Drive, Kind::Position] {
            let mut m = Motor::new(kind);
            m.start(0);
            m.set_param(kind, Param::P, 0x4000);
            m.params.required = Fix::from_num(30);
            let cx = |k: u32, in_exception| UpdateContext {
                now_us: 20_000 * k,
                now_ms: 20 * k,
                in_exception,
                fault_time_ms: 500,
            };
            m.update(Fix::ZERO, &cx(1, false));
            let duty = m.demand().magnitude;
            assert!(duty > 0, "{kind:?}");
            let applied = CONTROL.map_int(u16::from(duty));
            assert_eq!(m.monitors().raw[4], applied, "{kind:?}");
            // Mapped again in exception (the interval changed): CONTROL stays.
            for k in 2..5 {
                m.update(Fix::from_num(k), &cx(k * k, true));
                assert!(m.take_fresh());
                assert_eq!(m.monitors().raw[4], applied, "{kind:?} {k}");
            }
            // Out of it: the duty of the update (0 or not) again.
            m.update(Fix::ZERO, &cx(30, false));
            let now = CONTROL.map_int(u16::from(m.demand().magnitude));
            assert_eq!(m.monitors().raw[4], now, "{kind:?}");
        }
    }

    #[test]
    fn control_shows_the_last_duty_applied_before_an_exception_between_mappings() {
        // A position motor updates every 2 ms; its monitoring values are mapped every
        // 10 ms. Its duty rises after a mapping and an exception comes before the next:
        // CONTROL must show the last duty applied, not the one last mapped.
        let mut m = Motor::new(Kind::Position);
        m.start(0);
        m.set_param(Kind::Position, Param::P, 0x0800);
        m.params.required = Fix::from_num(40);
        let cx = |ms: u32, in_exception| UpdateContext {
            now_us: 1_000 * ms,
            now_ms: ms,
            in_exception,
            fault_time_ms: 500,
        };
        m.update(Fix::ZERO, &cx(20, false));
        let mapped = m.monitors().raw[4];
        assert_eq!(mapped, CONTROL.map_int(u16::from(m.demand().magnitude)));
        // The actual angle falls away: the duty rises, unmapped for now.
        m.update(Fix::from_num(-10), &cx(22, false));
        m.update(Fix::from_num(-20), &cx(24, false));
        let last = m.demand().magnitude;
        assert_eq!(m.monitors().raw[4], mapped, "not mapped within 10 ms");
        assert_ne!(CONTROL.map_int(u16::from(last)), mapped);
        // The exception, then the updates in it until the next mapping.
        for ms in [26, 28, 30, 32] {
            m.update(Fix::from_num(-20), &cx(ms, true));
        }
        assert!(m.take_fresh(), "mapped at 30 ms");
        assert_eq!(m.monitors().raw[4], CONTROL.map_int(u16::from(last)));
    }

    #[test]
    fn shared_monitoring_statics_serve_equal_scales_only() {
        // The pairs that share a static map alike (checked at compile time above); no
        // others do.
        assert!(DRIVE_ERROR.maps_as(INTEGRAL));
        for (a, b) in [
            (DRIVE_ACTUAL, DRIVE_ERROR),
            (DRIVE_ERROR, POSITION_ERROR),
            (CONTROL, INTERVAL),
            (INTERVAL, DRIVE_ERROR),
            (CAP, INTEGRAL),
        ] {
            assert!(!a.maps_as(b), "{a:?} {b:?}");
        }
        assert_eq!(
            INTEGRAL.map(Fix::from_num(-999.5)),
            DRIVE_ERROR.map(Fix::from_num(-999.5))
        );
        // Five statics for the eight mapped monitors of the two kinds.
        let mut distinct: Vec<*const Mapping> = Vec::new();
        for kind in [Kind::Drive, Kind::Position] {
            for monitor in Monitor::ALL {
                if let Some(m) = kind.monitor_mapping(monitor) {
                    if !distinct.contains(&(m as *const Mapping)) {
                        distinct.push(m);
                    }
                }
            }
        }
        assert_eq!(distinct.len(), 5);
    }

    #[test]
    fn a_conversion_in_line_leaves_what_angle_gives() {
        let mut changed = 0;
        for (min, max) in [(0x00, 0xfe), (0x43, 0xc4), (0xc4, 0x43), (0x7f, 0x7f)] {
            let mut m = Motor::new(Kind::Position);
            m.set_param(Kind::Position, Param::CalibMin, min);
            m.set_param(Kind::Position, Param::CalibMax, max);
            let mut plain = m;
            for reading in [0, 1, 1, 512, 1023, 1024, u16::MAX, 700, 700, 3] {
                let before = m.angle;
                m.angle_in_line(reading);
                changed += usize::from(m.angle != before);
                // What `angle` returns next (the kept conversion) is a fresh one's.
                assert_eq!(
                    m.angle(reading),
                    plain.angle(reading),
                    "{min} {max} {reading}"
                );
                assert_eq!(m, plain, "{min} {max} {reading}");
            }
        }
        assert!(changed > 15, "{changed}");
    }

    #[test]
    fn a_calibration_write_keeps_the_other_end() {
        // Params::set's one rebuild for both ends is set_min's and set_max's.
        let raws = [0x00, 0x01, 0x0b, 0x43, 0x7f, 0xc4, 0xf2, 0xfe, 0xff];
        let unmap = |raw| CALIB.unmap(raw);
        let mut rebuilt = 0;
        for first in raws {
            for second in raws {
                for (a, b) in [
                    (Param::CalibMin, Param::CalibMax),
                    (Param::CalibMax, Param::CalibMin),
                ] {
                    let mut params = Params::POWER_ON;
                    let mut want = params.calibration;
                    for (param, raw) in [(a, first), (b, second)] {
                        params.set(Kind::Position, param, raw);
                        match param {
                            Param::CalibMin => want.set_min(unmap(raw)),
                            _ => want.set_max(unmap(raw)),
                        }
                        assert_eq!(params.calibration, want, "{param:?} {first} {second}");
                    }
                    rebuilt += usize::from(want != Params::POWER_ON.calibration);
                }
            }
        }
        assert!(rebuilt > 150, "{rebuilt}");
    }

    #[test]
    fn the_unmapping_table_holds_each_kind_and_params_scale() {
        use Param::*;
        let params = [
            Required, P, I, D, Cap, Decay, Threshold, StallCheck, DeadZone, CalibMin, CalibMax,
        ];
        for kind in [Kind::Drive, Kind::Position] {
            for param in params {
                let table = kind.param_unmapping(param);
                assert_eq!(
                    table,
                    kind.param_scale(param).unmapping(),
                    "{kind:?} {param:?}"
                );
                // Every one-byte value, then every 7th two-byte one and the top.
                let raws = (0..=255)
                    .chain((256..=u16::MAX).step_by(7))
                    .chain([u16::MAX]);
                for raw in raws {
                    assert_eq!(
                        table.unmap(raw),
                        kind.param_scale(param).unmap(raw),
                        "{kind:?} {param:?} {raw}"
                    );
                }
            }
        }
        // The drive's REQSPEED and PGAIN differ from a position motor's.
        assert_ne!(
            Kind::Drive.param_unmapping(Required),
            Kind::Position.param_unmapping(Required)
        );
        assert_ne!(
            Kind::Drive.param_unmapping(P),
            Kind::Position.param_unmapping(P)
        );
    }

    #[test]
    fn monitors_are_fresh_at_power_up_and_after_each_remap_only() {
        let mut m = Motor::new(Kind::Position);
        assert!(m.take_fresh(), "power-up values need writing once");
        assert!(!m.take_fresh());
        m.start(0);
        let cx = |now_us| UpdateContext {
            now_us,
            now_ms: now_us / 1000,
            in_exception: false,
            fault_time_ms: 500,
        };
        // Started at 0: the first update maps, the next one 2 ms later does not.
        m.update(Fix::from_num(12), &cx(2_000));
        assert!(m.take_fresh());
        assert_eq!(m.monitors().raw[5], INTERVAL.map_int(2));
        m.update(Fix::from_num(13), &cx(4_000));
        assert!(!m.take_fresh());
        m.update(Fix::from_num(14), &cx(12_000));
        assert!(m.take_fresh());
        assert_eq!(m.monitors().interval_ms, 8);
    }

    #[test]
    fn power_up_monitors_are_the_mapping_of_what_they_start_from() {
        let from = MappedFrom::POWER_ON;
        for kind in [Kind::Drive, Kind::Position] {
            let scale = |monitor| kind.monitor_scale(monitor);
            let zero_terms = [Monitor::Error, Monitor::Integral, Monitor::Deriv]
                .map(|monitor| map(scale(monitor), Fix::ZERO));
            assert_eq!(from.terms, 0);
            assert_eq!(
                [
                    map(scale(Monitor::Actual), from.actual),
                    zero_terms[0],
                    zero_terms[1],
                    zero_terms[2],
                    CONTROL.map_int(u16::from(from.duty)),
                    INTERVAL.map_int(from.interval_ms),
                ],
                Monitors::POWER_ON.raw,
                "{kind:?}"
            );
        }
    }

    #[test]
    fn the_first_mapping_equals_mapping_everything() {
        // Each value 0 or not at the first mapping, in and out of exception: the raw
        // values are each value's mapping (CONTROL's only outside an exception).
        for kind in [Kind::Drive, Kind::Position] {
            for in_exception in [false, true] {
                for actual in [0.0, -3.5, 17.25] {
                    for required in [0.0, 40.0] {
                        let mut m = Motor::new(kind);
                        m.start(0);
                        m.set_param(kind, Param::P, 0x2000);
                        m.params.required = Fix::from_num(required);
                        let cx = UpdateContext {
                            now_us: 2_000,
                            now_ms: 2,
                            in_exception,
                            fault_time_ms: 500,
                        };
                        let actual = Fix::from_num(actual);
                        let mut pid = m.track.pid;
                        m.update(actual, &cx);
                        let step = match kind {
                            Kind::Drive => pid.speed(&m.params.gains, m.params.required, actual),
                            Kind::Position => {
                                pid.position(&m.params.gains, m.params.required, actual)
                            }
                        };
                        let scale = |monitor| kind.monitor_scale(monitor);
                        let control = if in_exception {
                            Monitors::POWER_ON.raw[4]
                        } else {
                            CONTROL.map_int(u16::from(step.duty.magnitude))
                        };
                        let want = [
                            map(scale(Monitor::Actual), actual),
                            map(scale(Monitor::Error), step.error),
                            map(scale(Monitor::Integral), step.integral),
                            map(scale(Monitor::Deriv), step.deriv),
                            control,
                            INTERVAL.map_int(2),
                        ];
                        let case = format!("{kind:?} {in_exception} {actual} {required}");
                        assert_eq!(m.monitors().raw, want, "{case}");
                        if !in_exception && required != 0.0 {
                            assert_ne!(want[1], Monitors::POWER_ON.raw[1], "{case}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_held_update_maps_the_held_measurement_and_zero_terms() {
        // The record of an update that holds reads the measurement and the integral
        // from the controller: they must be the held angle and 0.
        let mut m = Motor::new(Kind::Position);
        m.start(0);
        m.set_param(Kind::Position, Param::I, 0x3332);
        m.set_param(Kind::Position, Param::Required, 0x9998);
        let required = m.params.required;
        let cx = |k: u32| UpdateContext {
            now_us: 2_000 * k,
            now_ms: 2 * k,
            in_exception: false,
            fault_time_ms: 500,
        };
        // Off the demand (terms not 0, mapped at 2 ms), then on it: at rest.
        m.update(required - Fix::from_num(3), &cx(1));
        assert_ne!(m.monitors().raw[1], Monitors::POWER_ON.raw[1]);
        let mut held = 0;
        for k in 2..40 {
            held += usize::from(m.holds(required, &cx(k)));
            m.update(required, &cx(k));
        }
        assert!(held > 30, "{held}");
        let scale = |monitor| Kind::Position.monitor_scale(monitor);
        assert_eq!(
            m.monitors().raw,
            [
                map(scale(Monitor::Actual), required),
                map(scale(Monitor::Error), Fix::ZERO),
                map(scale(Monitor::Integral), Fix::ZERO),
                map(scale(Monitor::Deriv), Fix::ZERO),
                CONTROL.map_int(0),
                INTERVAL.map_int(2),
            ]
        );
        assert_ne!(m.monitors().raw[0], Monitors::POWER_ON.raw[0]);
    }

    #[test]
    fn the_drive_never_holds() {
        // `update_unheld` skips the hold test for the drive: its steps at rest (zero
        // gains, no demand, the same speed) must never mark it at rest.
        let mut m = Motor::new(Kind::Drive);
        m.start(0);
        let mut rests = 0;
        for k in 0..20u32 {
            let cx = UpdateContext {
                now_us: 150_000 * (k + 1),
                now_ms: 150 * (k + 1),
                in_exception: k % 3 == 0,
                fault_time_ms: 500,
            };
            m.update(Fix::ZERO, &cx);
            let step = m.track.pid;
            rests += usize::from(step.integral() == Fix::ZERO && step.control() == Fix::ZERO);
            assert!(!m.at_rest && !m.holds(Fix::ZERO, &cx), "update {k}");
        }
        assert_eq!(rests, 20);
        // A position motor in the same state does hold.
        let mut m = Motor::new(Kind::Position);
        m.start(0);
        let cx = UpdateContext {
            now_us: 2_000,
            now_ms: 2,
            in_exception: false,
            fault_time_ms: 500,
        };
        m.update(Fix::ZERO, &cx);
        assert!(m.holds(Fix::ZERO, &cx));
    }

    #[test]
    fn updates_at_rest_equal_the_controller_s_own() {
        let mut m = Motor::new(Kind::Position);
        m.start(0);
        // I 2, cap 300, decay 0.95, dead zone 0.5 (raw values as calibrate() sends).
        for (param, raw) in [
            (Param::I, 0x3332),
            (Param::Cap, 0x4ccc),
            (Param::Decay, 0xf331),
            (Param::DeadZone, 0x02),
            (Param::Required, 0x8ccc),
        ] {
            m.set_param(Kind::Position, param, raw);
        }
        let mut pid = Pid::new();
        let gains = m.params.gains;
        let required = m.params.required;
        let mut rests = 0;
        for k in 0..1_000u32 {
            // Approach the demand, hold it (within the dead zone: the integral decays to
            // 0 in a few hundred updates), move on.
            let actual = match k {
                0..=99 => required - Fix::from_num(100 - k),
                100..=899 => required + Fix::from_num(0.25),
                _ => required + Fix::from_num(k - 899),
            };
            let cx = UpdateContext {
                now_us: 2_000 * (k + 1),
                now_ms: 2 * (k + 1),
                in_exception: false,
                fault_time_ms: 500,
            };
            rests += usize::from(m.at_rest);
            m.update(actual, &cx);
            let step = pid.position(&gains, required, actual);
            assert_eq!(m.pid(), &pid, "update {k}");
            assert_eq!(m.demand(), step.duty, "update {k}");
        }
        assert!(rests > 100, "at rest {rests} times");
    }
}
