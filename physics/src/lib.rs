//! Physics of the rover's wheels, and the loop closer that feeds it to emulated slave chips.
//!
//! The rover's slave boards drive motors and read sensors; in the emulator nothing is
//! attached to their pins. This crate is what would be: for each wheel a drive motor with
//! inertia, friction and a quadrature encoder ([`drive`], [`encoder`]), steer and lift
//! gearmotors with end stops ([`gearmotor`]) read by pots ([`pot`]), current sensing
//! ([`sense`]), all behind the H-bridge input the firmware sets ([`bridge`]). A
//! [`wheel::SlaveBoardModel`] groups what one slave board sees, pin by pin.
//!
//! It sits between the emulator harness and the rover's tests and twin:
//! [`emulator::Plant`] closes the loop around a `harness::Avr` or the chips of a
//! `harness::bus::Bus`, reading PWM duty and direction pins and writing encoder edges
//! (each at its own cycle) and ADC millivolts.
//!
//! The models are pure, deterministic Rust with no I/O; every constant lives in
//! [`constants`], with its reasoning. Faults can be injected: a stalled wheel or axis
//! ([`drive::DriveMotor::set_stalled`], [`gearmotor::Gearmotor::set_stalled`]) and
//! current spikes ([`sense::CurrentSense::inject_spike`]).
//!
//! ```
//! use physics::bridge::Bridge;
//! use physics::drive::DriveMotor;
//!
//! let mut wheel = DriveMotor::new();
//! wheel.set_bridge(Bridge::forward(0.5));
//! let edges = wheel.advance(0.5); // half a second at half duty
//! assert!((wheel.ticks_per_s() - 1715.0).abs() < 5.0);
//! assert!(edges.len() > 2000);
//! ```

pub mod bridge;
pub mod constants;
pub mod drive;
pub mod emulator;
pub mod encoder;
mod error;
pub mod gearmotor;
pub mod pot;
pub mod sense;
pub mod wheel;

pub use error::PhysicsError;
