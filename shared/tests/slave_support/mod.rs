//! Test bench for the slave logic: a [`Core`] and its [`RegisterFile`] on a fake clock,
//! an I2C master that speaks to the register file byte by byte, and tiny plants (a
//! drive wheel with its encoder, a steer or lift gearmotor with its pot) to close the
//! loop.
#![allow(dead_code)]

use shared::mapping;
use shared::regs::BoardKind;
use shared::slave::{
    clock::units, AdcSample, Core, EdgeCounter, Inputs, MotorOutput, Outputs, RegisterFile,
    Variant, TICK_US,
};

/// A slave on the bench.
pub struct Bench {
    pub core: Core,
    pub regs: RegisterFile,
    /// The fake µs clock.
    pub now_us: u32,
    pub last: Option<Outputs>,
    /// The highest duty of each motor since the bench was made: a test of "nothing
    /// raised" shows with it that a fault check was watching (it looks only above the
    /// motor's STALLCHECK).
    pub peak_duty: [u8; 2],
}

impl Bench {
    /// A board at address 1 (DS) or 3 (LL), before its first tick.
    pub fn new(variant: Variant) -> Bench {
        let address = match variant {
            Variant::DriveSteer => 1,
            Variant::LiftLift => 3,
        };
        Bench::at(variant, address)
    }

    /// A board at `address` (from EEPROM byte 0), before its first tick.
    pub fn at(variant: Variant, address: u8) -> Bench {
        Bench {
            core: Core::new(variant, address),
            regs: RegisterFile::new(variant),
            now_us: 0,
            last: None,
            peak_duty: [0; 2],
        }
    }

    /// A board after `Leave` (RESET = 1) has taken it out of the boot exception.
    pub fn running(variant: Variant) -> Bench {
        let mut bench = Bench::new(variant);
        bench.tick(&Inputs::default());
        bench.write(0, 1);
        bench.tick(&Inputs::default());
        bench
    }

    pub fn board(&self) -> BoardKind {
        self.core.variant().board()
    }

    /// One tick of the control loop, `TICK_US` after the previous one.
    pub fn tick(&mut self, inputs: &Inputs) -> Outputs {
        self.now_us = self.now_us.wrapping_add(TICK_US);
        let out = self.core.tick(self.now_us, inputs, &mut self.regs);
        self.last = Some(out);
        for (peak, motor) in self.peak_duty.iter_mut().zip(out.motors) {
            *peak = (*peak).max(motor.duty());
        }
        out
    }

    /// `n` ticks with the same inputs; returns the last outputs.
    pub fn ticks(&mut self, n: u32, inputs: &Inputs) -> Outputs {
        let mut out = self.tick(inputs);
        for _ in 1..n {
            out = self.tick(inputs);
        }
        out
    }

    /// An I2C write transaction: pointer, then `bytes`.
    pub fn write_bytes(&mut self, pointer: u8, bytes: &[u8]) {
        self.regs.start_write();
        self.regs.write(pointer);
        for &b in bytes {
            self.regs.write(b);
        }
        self.regs.stop();
    }

    /// Writes one register's raw value as the master does (size from the table).
    pub fn write(&mut self, id: u8, raw: u16) {
        let size = self.board().size_of(id).expect("register exists");
        let bytes = raw.to_le_bytes();
        self.write_bytes(id, &bytes[..usize::from(size)]);
    }

    /// Writes an engineering value, mapped as the PC does.
    pub fn write_value(&mut self, id: u8, value: f32) {
        let reg = self.board().register(id).expect("register exists");
        self.write(id, mapping::map(value, reg));
    }

    /// An I2C read of `n` bytes from `pointer` (pointer write, STOP, read, STOP).
    pub fn read_bytes(&mut self, pointer: u8, n: usize) -> Vec<u8> {
        self.regs.start_write();
        self.regs.write(pointer);
        self.regs.stop();
        self.regs.start_read();
        let out = (0..n).map(|_| self.regs.read()).collect();
        self.regs.stop();
        out
    }

    /// Reads one register's raw value as the master does.
    pub fn read(&mut self, id: u8) -> u16 {
        let size = usize::from(self.board().size_of(id).expect("register exists"));
        let bytes = self.read_bytes(id, size);
        let hi = if size > 1 { bytes[1] } else { 0 };
        u16::from_le_bytes([bytes[0], hi])
    }

    /// Reads one register and unmaps it as the PC does.
    pub fn read_value(&mut self, id: u8) -> f32 {
        let raw = self.read(id);
        let reg = self.board().register(id).expect("register exists");
        mapping::unmap(raw, reg)
    }

    /// Sends the PC library's "calibrate()" parameter blocks (reference §8.3, wheel 1)
    /// and leaves the exception.
    pub fn calibrate(&mut self) {
        use shared::regs::id::*;
        match self.core.variant() {
            Variant::DriveSteer => {
                self.write_value(REGDS_DRIVE_PGAIN, 0.01);
                self.write_value(REGDS_DRIVE_IGAIN, 0.0);
                self.write_value(REGDS_DRIVE_DGAIN, 0.0);
                self.write_value(REGDS_DRIVE_INTEGRALCAP, 0.0);
                self.write_value(REGDS_DRIVE_INTEGRALDECAY, 0.0);
                self.write_value(REGDS_DRIVE_OVERCURRENTTHRESH, 500.0);
                self.write_value(REGDS_DRIVE_STALLCHECK, 255.0);
                self.write_value(REGDS_DRIVE_DEADZONE, 1.0);
                self.write_value(REGDS_STEER_PGAIN, 0.0);
                self.write_value(REGDS_STEER_IGAIN, 2.0);
                self.write_value(REGDS_STEER_DGAIN, 0.0);
                self.write_value(REGDS_STEER_INTEGRALCAP, 300.0);
                self.write_value(REGDS_STEER_INTEGRALDECAY, 0.95);
                self.write_value(REGDS_STEER_OVERCURRENTTHRESH, 500.0);
                self.write_value(REGDS_STEER_CALIBMIN, -56.0);
                self.write_value(REGDS_STEER_CALIBMAX, 66.0);
                self.write_value(REGDS_STEER_STALLCHECK, 255.0);
                self.write_value(REGDS_STEER_DEADZONE, 0.5);
            }
            Variant::LiftLift => {
                for base in [REGLL_ONE_REQPOS, REGLL_TWO_REQPOS] {
                    let o = base - REGLL_ONE_REQPOS;
                    self.write_value(REGLL_ONE_PGAIN + o, 0.0);
                    self.write_value(REGLL_ONE_IGAIN + o, 5.0);
                    self.write_value(REGLL_ONE_DGAIN + o, 0.0);
                    self.write_value(REGLL_ONE_INTEGRALCAP + o, 50.0);
                    self.write_value(REGLL_ONE_INTEGRALDECAY + o, 0.9);
                    self.write_value(REGLL_ONE_OVERCURRENTTHRESH + o, 500.0);
                    self.write_value(REGLL_ONE_CALIBMIN + o, -109.0);
                    self.write_value(REGLL_ONE_CALIBMAX + o, 109.0);
                    self.write_value(REGLL_ONE_STALLCHECK + o, 255.0);
                    self.write_value(REGLL_ONE_DEADZONE + o, 1.0);
                }
            }
        }
        self.write(REG_RESET, 1);
    }
}

/// Volts on a motor for an output (12 V supply).
pub fn volts(out: MotorOutput) -> f64 {
    match out {
        MotorOutput::Drive(duty) => {
            let v = 12.0 * f64::from(duty.magnitude) / 255.0;
            match duty.direction {
                shared::pid::Direction::Forward => v,
                shared::pid::Direction::Reverse => -v,
            }
        }
        MotorOutput::Stop => 0.0,
    }
}

/// A drive wheel: a DC motor referred to the wheel, in encoder ticks. Free speed at 12 V
/// about 3800 ticks/s, mechanical time constant 32 ms, breakaway at 0.43 V, winding 2.2 Ω,
/// current sense 100 counts per A.
pub struct DriveWheel {
    /// Speed, ticks/s.
    pub speed: f64,
    /// Position, ticks (fractional).
    pub position: f64,
    /// The wheel is blocked.
    pub held: bool,
    /// The encoder is disconnected: no edges.
    pub encoder_broken: bool,
    /// The motor is disconnected: no current, no torque.
    pub open_circuit: bool,
    pub counter: EdgeCounter,
    pub current_counts: f64,
}

impl Default for DriveWheel {
    fn default() -> Self {
        DriveWheel {
            speed: 0.0,
            position: 0.0,
            held: false,
            encoder_broken: false,
            open_circuit: false,
            counter: EdgeCounter::new(),
            current_counts: 0.0,
        }
    }
}

/// Ticks/s per volt of back-EMF.
const DRIVE_TICKS_PER_V: f64 = 318.0;
const DRIVE_R: f64 = 2.2;
const DRIVE_TAU_S: f64 = 0.032;
const DRIVE_BREAKAWAY_V: f64 = 0.43;

impl DriveWheel {
    /// Advances the wheel by `dt_us` under `out`, starting at `t0_us`, recording every
    /// rising edge of A (B low at A's rise going forward, high going backward).
    pub fn advance(&mut self, out: MotorOutput, t0_us: u32, dt_us: u32) {
        let v = if self.open_circuit { 0.0 } else { volts(out) };
        let steps = dt_us / 10;
        for i in 0..steps {
            let h = 10e-6;
            let target = if self.held || v.abs() <= DRIVE_BREAKAWAY_V {
                0.0
            } else {
                (v - DRIVE_BREAKAWAY_V * v.signum()) * DRIVE_TICKS_PER_V
            };
            if self.held {
                self.speed = 0.0;
            } else {
                self.speed += (target - self.speed) * h / DRIVE_TAU_S;
            }
            let before = self.position;
            self.position += self.speed * h;
            if !self.encoder_broken && self.position.floor() != before.floor() {
                let forward = self.position > before;
                let at = t0_us.wrapping_add((i + 1) * 10);
                self.counter.rising_edge(units(at), !forward);
            }
        }
        let amps = if self.open_circuit {
            0.0
        } else {
            (v - self.speed / DRIVE_TICKS_PER_V) / DRIVE_R
        };
        self.current_counts = (amps.abs() * 100.0).min(1023.0);
    }
}

/// A steer or lift gearmotor with a pot: speed follows the voltage at once above the
/// friction voltage.
pub struct Gearmotor {
    /// Angle, degrees.
    pub angle: f64,
    /// Degrees per second at 12 V.
    pub deg_per_s_at_12v: f64,
    /// Below this the gear does not move, V.
    pub friction_v: f64,
    /// Winding, Ω.
    pub resistance: f64,
    /// Mechanical end stops, degrees.
    pub stops: (f64, f64),
    /// The pot's calibration as the slave holds it: angle at reading 0 and at 1024.
    pub pot: (f64, f64),
    pub held: bool,
    pub current_counts: f64,
}

impl Gearmotor {
    /// Wheel 1's steer: 60°/s, friction 0.8 V, 4 Ω, calibration −56.69..65.20.
    pub fn steer() -> Gearmotor {
        Gearmotor {
            angle: 0.0,
            deg_per_s_at_12v: 60.0,
            friction_v: 0.8,
            resistance: 4.0,
            stops: (-51.0, 60.0),
            pot: (-56.692_91, 65.196_85),
            held: false,
            current_counts: 0.0,
        }
    }

    /// Wheel 1's lift: 20°/s, friction 1.05 V, 3 Ω, calibration −109.61..108.66.
    pub fn lift() -> Gearmotor {
        Gearmotor {
            angle: 0.0,
            deg_per_s_at_12v: 20.0,
            friction_v: 1.05,
            resistance: 3.0,
            stops: (-104.0, 103.0),
            pot: (-109.606_3, 108.661_42),
            held: false,
            current_counts: 0.0,
        }
    }

    pub fn advance(&mut self, out: MotorOutput, dt_us: u32) {
        let v = volts(out);
        let moving_v = if v.abs() > self.friction_v {
            v - self.friction_v * v.signum()
        } else {
            0.0
        };
        let rate = if self.held {
            0.0
        } else {
            moving_v / 12.0 * self.deg_per_s_at_12v
        };
        let next = self.angle + rate * f64::from(dt_us) * 1e-6;
        let blocked = self.held || next < self.stops.0 || next > self.stops.1;
        self.angle = next.clamp(self.stops.0, self.stops.1);
        let amps = if blocked {
            v / self.resistance
        } else {
            (v - moving_v) / self.resistance
        };
        self.current_counts = (amps.abs() * 100.0).min(1023.0);
    }

    /// The pot's ADC reading.
    pub fn reading(&self) -> u16 {
        let (min, max) = self.pot;
        ((self.angle - min) * 1024.0 / (max - min)).clamp(0.0, 1023.0) as u16
    }
}

/// A drive/steer board with its drive wheel and steer motor.
pub struct DsRig {
    pub bench: Bench,
    pub wheel: DriveWheel,
    pub steer: Gearmotor,
}

impl DsRig {
    pub fn new() -> DsRig {
        DsRig {
            bench: Bench::new(Variant::DriveSteer),
            wheel: DriveWheel::default(),
            steer: Gearmotor::steer(),
        }
    }

    /// A new rig after the library's calibrate().
    pub fn calibrated() -> DsRig {
        let mut rig = DsRig::new();
        rig.bench.calibrate();
        rig
    }

    /// One tick: sensors in, logic, plants advanced under the outputs.
    pub fn tick(&mut self) -> Outputs {
        let current = [
            self.wheel.current_counts as u16,
            self.steer.current_counts as u16,
        ];
        let inputs = Inputs {
            edges: self.wheel.counter.take(),
            adc: AdcSample {
                current,
                current_peak: current,
                ch6: self.steer.reading(),
                ch7: 512,
            },
        };
        let t0 = self.bench.now_us.wrapping_add(TICK_US);
        let out = self.bench.tick(&inputs);
        self.wheel.advance(out.motors[0], t0, TICK_US);
        self.steer.advance(out.motors[1], TICK_US);
        out
    }

    /// `ms` ticks; returns the last outputs.
    pub fn run_ms(&mut self, ms: u32) -> Outputs {
        let mut out = self.tick();
        for _ in 1..ms {
            out = self.tick();
        }
        out
    }
}

/// A lift/lift board with its two lift motors.
pub struct LlRig {
    pub bench: Bench,
    pub lifts: [Gearmotor; 2],
}

impl LlRig {
    pub fn new() -> LlRig {
        LlRig {
            bench: Bench::new(Variant::LiftLift),
            lifts: [Gearmotor::lift(), Gearmotor::lift()],
        }
    }

    /// A new rig after the library's calibrate().
    pub fn calibrated() -> LlRig {
        let mut rig = LlRig::new();
        rig.bench.calibrate();
        rig
    }

    pub fn tick(&mut self) -> Outputs {
        let current = [
            self.lifts[0].current_counts as u16,
            self.lifts[1].current_counts as u16,
        ];
        let inputs = Inputs {
            edges: Default::default(),
            adc: AdcSample {
                current,
                current_peak: current,
                ch6: self.lifts[0].reading(),
                ch7: self.lifts[1].reading(),
            },
        };
        let out = self.bench.tick(&inputs);
        for (lift, motor) in self.lifts.iter_mut().zip(out.motors) {
            lift.advance(motor, TICK_US);
        }
        out
    }

    pub fn run_ms(&mut self, ms: u32) -> Outputs {
        let mut out = self.tick();
        for _ in 1..ms {
            out = self.tick();
        }
        out
    }
}
