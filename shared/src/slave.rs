//! Every decision of a slave board (drive/steer or lift/lift), as plain logic that runs
//! and is tested on the host.
//!
//! The slave firmware is a thin shell around this module. Its interrupts collect raw
//! facts: the TWI interrupt drives the [`RegisterFile`], the encoder interrupt an
//! [`EdgeCounter`], the ADC interrupt an [`AdcCollector`]. The control tick (every
//! [`TICK_US`]) hands them to [`Core`], which returns [`Outputs`]: a duty and direction
//! (or STOP) per motor, the two LEDs, and whether to feed the watchdog or let it reset
//! the board. Values are fixed point ([`crate::pid::Fix`]); no float and no fixed-point
//! division runs on the firmware path.
//!
//! | Module | Job |
//! |---|---|
//! | [`board`] | variants, motor ids, addresses, which register belongs to which motor |
//! | [`registers`] | the register file, its I2C semantics, change marks, power-up values |
//! | [`scale`] | raw register values to fixed point and back |
//! | [`state`] | the exception state machine |
//! | [`silence`] | the bus-silence failsafe (new) |
//! | [`current`] | current filter and overcurrent rule |
//! | [`encoder`] | edge counting, speed measurement, odometer |
//! | [`pot`] | pot readings to angles |
//! | [`fault`] | stall and sensor-fault detection |
//! | [`leds`] | LED patterns |
//! | [`motor`] | one motor: parameters, controller, monitoring values |
//! | [`clock`] | uptime and tick interval |
//! | [`divide`] | the one small `u32` division all of them use |
//! | [`product`] | the 16×16→32-bit product the per-tick arithmetic uses |
//! | [`io`] | the tick's inputs and outputs |
//! | `core` | [`Core`], which ties them together |

pub mod board;
pub mod clock;
mod core;
pub mod current;
pub mod divide;
pub mod encoder;
pub mod fault;
pub mod image;
pub mod io;
pub mod leds;
pub mod motor;
pub mod pot;
pub mod product;
pub mod registers;
pub mod scale;
pub mod silence;
pub mod state;
pub mod words;

pub use self::core::{Core, POSITION_PERIOD_US, TICK_US};
pub use board::{bus_address, Board, DriveSteerBoard, LiftLiftBoard, MotorId, Variant};
pub use encoder::{DriveMode, EdgeCounter, EdgeSample};
pub use io::{
    next_mux, AdcChannel, AdcCollector, AdcSample, Inputs, MotorOutput, Outputs, Watchdog,
};
pub use leds::LedLevels;
pub use registers::{Changes, RegisterFile};
pub use silence::SilenceWatch;
pub use state::{Cause, LocalFault, State};
