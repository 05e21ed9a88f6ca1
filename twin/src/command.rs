//! The twin's fault-injection and status commands, as text: what the control socket accepts,
//! what `twin inject` sends and what `twin --fault` applies at start.
//!
//! | Command | Effect |
//! |---|---|
//! | `stall W [drive\|steer\|lift] on\|off` | Hold wheel W's motor still (drive if not named), or let it go |
//! | `cut N` / `restore N` | Take controller N off the I²C bus / put it back |
//! | `reboot N` | Reset controller N, as a brown-out or its watchdog would: back in its boot state |
//! | `spike W drive\|steer\|lift AMPS MS` | Add AMPS (up to 10.24) to that motor's sensed current for MS ms (up to 60 s) |
//! | `sensor I remove\|restore` | Unplug temperature sensor I (0 ambient, 1..9) / plug it back |
//! | `temp I CELSIUS` | Set what sensor I measures (0.5 °C steps) |
//! | `drop-serial N [to-master\|to-host]` | Lose the next N bytes on the serial line (to the master if not named) |
//! | `drop-serial clear` | Cancel the losses still pending, both ways |
//! | `rc on\|off` | Start / stop the RC receiver's pulses |
//! | `rc CH US` | Set RC channel CH's pulse width (µs, 500..2500) |
//! | `status` | Emulated time, speed, faults, every wheel's physical state, every board's LEDs and bridges |
//! | `time` | Emulated time since power-up, µs (`hostctl` waits in it for the slaves to boot) |
//! | `dtr low\|high` | A host's DTR line, which a pty cannot carry (`hostctl` sends its open's DTR pulse and its close's DTR drop this way): a change resets the master, as on the Uno, whoever else holds the port open |

use crate::serial::Direction;
use crate::wiring::{Axis, WHEELS};
use crate::{Rover, TwinError};

/// One command to the twin.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Stall or free one motor.
    Stall {
        /// Wheel 1..=6.
        wheel: u8,
        /// Which of its motors.
        axis: Axis,
        /// Stall (true) or free (false).
        on: bool,
    },
    /// Take a controller off the bus.
    Cut(u8),
    /// Put a controller back on the bus.
    Restore(u8),
    /// Reset a controller.
    Reboot(u8),
    /// A current spike on one motor's sense.
    Spike {
        /// Wheel 1..=6.
        wheel: u8,
        /// Which of its motors.
        axis: Axis,
        /// Extra current, A.
        amps: f64,
        /// How long, ms of emulated time.
        ms: f64,
    },
    /// Unplug or plug back a temperature sensor.
    Sensor {
        /// 0 ambient, 1..=9 controller n's sensor.
        index: u8,
        /// Plugged in (true) or not.
        present: bool,
    },
    /// Set what a temperature sensor measures.
    Temp {
        /// 0 ambient, 1..=9 controller n's sensor.
        index: u8,
        /// Temperature, 0.5 °C units.
        half_degrees: i16,
    },
    /// Lose bytes on the serial line.
    DropSerial {
        /// How many bytes.
        n: u64,
        /// Which way.
        direction: Direction,
    },
    /// Cancel the serial losses still pending.
    ClearSerialDrops,
    /// Turn the RC receiver on or off.
    Rc(bool),
    /// Set one RC channel's width.
    RcWidth {
        /// Channel 0..=2.
        channel: u8,
        /// Pulse width, µs.
        us: u16,
    },
    /// Report the twin's state.
    Status,
    /// Report the emulated time.
    Time,
    /// A host's DTR line: high (true) or low. Only a served port has one
    /// ([`crate::serve::Server`] applies it).
    Dtr(bool),
}

/// Why a command line was not understood.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CommandError {
    /// Nothing was given.
    #[error("no command given; {help}", help = HELP)]
    Empty,
    /// The first word is no command.
    #[error("unknown command `{0}`; {help}", help = HELP)]
    Unknown(String),
    /// The words after the command do not fit it.
    #[error("usage: {0}")]
    Usage(&'static str),
    /// A number lies outside what the command can do.
    #[error("{what} `{given}` is out of range; give {allowed}")]
    OutOfRange {
        /// What the number stands for.
        what: &'static str,
        /// The text given.
        given: String,
        /// The range accepted, in words.
        allowed: &'static str,
    },
    /// A command that would change nothing, such as `drop-serial 0`.
    #[error("{0}")]
    Nothing(&'static str),
    /// A number was expected.
    #[error("`{given}` is not {what}")]
    BadNumber {
        /// What the number stands for.
        what: &'static str,
        /// The text given.
        given: String,
    },
}

/// The list of commands, for error messages.
pub const HELP: &str = "commands: stall W [drive|steer|lift] on|off, cut N, restore N, \
reboot N, spike W drive|steer|lift AMPS MS, sensor I remove|restore, temp I CELSIUS, \
drop-serial N [to-master|to-host], drop-serial clear, rc on|off, rc CH US, status, time, \
dtr low|high";

const STALL: &str = "stall W [drive|steer|lift] on|off   (W = wheel 1..6)";
const CUT: &str = "cut N   (N = controller 1..9)";
const RESTORE: &str = "restore N   (N = controller 1..9)";
const REBOOT: &str = "reboot N   (N = controller 1..9)";
const SPIKE: &str = "spike W drive|steer|lift AMPS MS   (0 < AMPS <= 10.24, 0 < MS <= 60000)";
const SENSOR: &str = "sensor I remove|restore   (I = 0 ambient, 1..9)";
const TEMP: &str = "temp I CELSIUS   (I = 0 ambient, 1..9; -55 <= CELSIUS <= 125)";
const DROP: &str = "drop-serial N [to-master|to-host], or drop-serial clear";
const RC: &str = "rc on|off, or rc CH US   (CH = 0 drive, 1 steer, 2 mode; US = 500..2500)";
const DTR: &str = "dtr low|high";

/// Every command's usage, as its errors give it: `twin inject --help` lists each form.
pub const USAGES: [&str; 12] = [
    STALL, CUT, RESTORE, REBOOT, SPIKE, SENSOR, TEMP, DROP, RC, "status", "time", DTR,
];

fn number<T: std::str::FromStr>(word: &str, what: &'static str) -> Result<T, CommandError> {
    // A Unicode minus (U+2212, as the docs print "−55") reads as the ASCII one.
    word.replace('\u{2212}', "-")
        .parse()
        .map_err(|_| CommandError::BadNumber {
            what,
            given: word.to_owned(),
        })
}

fn on_off(word: &str, usage: &'static str) -> Result<bool, CommandError> {
    match word {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(CommandError::Usage(usage)),
    }
}

fn wheel(word: &str) -> Result<u8, CommandError> {
    let w = number(word, "a wheel number (1..6)")?;
    if WHEELS.contains(&w) {
        Ok(w)
    } else {
        Err(CommandError::BadNumber {
            what: "a wheel number (1..6)",
            given: word.to_owned(),
        })
    }
}

fn finite(word: &str, what: &'static str) -> Result<f64, CommandError> {
    let v: f64 = number(word, what)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CommandError::BadNumber {
            what,
            given: word.to_owned(),
        })
    }
}

/// The largest spike the current sense can show: its reading saturates at the ADC's
/// reference (5 V at 488.3 mV/A), so a larger one would read the same.
pub const SPIKE_MAX_A: f64 = 10.24;
/// The longest spike, ms: a spike is a transient; a lasting fault is `stall`.
pub const SPIKE_MAX_MS: f64 = 60_000.0;

/// A number in `0 < x <= max`: a spike of no current or no time would change nothing.
fn positive_up_to(
    word: &str,
    what: &'static str,
    name: &'static str,
    max: f64,
    allowed: &'static str,
) -> Result<f64, CommandError> {
    let v = finite(word, what)?;
    if v > 0.0 && v <= max {
        Ok(v)
    } else {
        Err(CommandError::OutOfRange {
            what: name,
            given: word.to_owned(),
            allowed,
        })
    }
}

/// An RC pulse width the receiver model sends: one outside it is refused rather than
/// clamped, so the channel is never set to a width other than the one asked for.
fn rc_width(word: &str) -> Result<u16, CommandError> {
    let us: u16 = number(word, "a pulse width in µs")?;
    let (min, max) = harness::rc::WIDTH_RANGE_US;
    if (min..=max).contains(&us) {
        Ok(us)
    } else {
        Err(CommandError::OutOfRange {
            what: "the RC pulse width (µs)",
            given: word.to_owned(),
            allowed: "500 to 2500 µs (what a receiver sends; the sticks span about 940 to 1940)",
        })
    }
}

/// Bytes for `drop-serial` to lose: 0 would lose none, so it is refused rather than
/// reported as a fault that was set.
fn byte_count(word: &str) -> Result<u64, CommandError> {
    match number(word, "a byte count")? {
        0 => Err(CommandError::Nothing(
            "drop-serial 0 would lose no byte, so nothing was changed; give N of 1 or more",
        )),
        n => Ok(n),
    }
}

impl Command {
    /// Parses one command line (words separated by blanks).
    pub fn parse(line: &str) -> Result<Command, CommandError> {
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((&first, rest)) = words.split_first() else {
            return Err(CommandError::Empty);
        };
        match (first, rest) {
            ("stall", [w, state]) => Ok(Command::Stall {
                wheel: wheel(w)?,
                axis: Axis::Drive,
                on: on_off(state, STALL)?,
            }),
            ("stall", [w, axis, state]) => Ok(Command::Stall {
                wheel: wheel(w)?,
                axis: Axis::parse(axis).ok_or(CommandError::Usage(STALL))?,
                on: on_off(state, STALL)?,
            }),
            ("stall", _) => Err(CommandError::Usage(STALL)),
            ("cut", [n]) => Ok(Command::Cut(number(n, "a controller number (1..9)")?)),
            ("cut", _) => Err(CommandError::Usage(CUT)),
            ("restore", [n]) => Ok(Command::Restore(number(n, "a controller number (1..9)")?)),
            ("restore", _) => Err(CommandError::Usage(RESTORE)),
            ("reboot", [n]) => Ok(Command::Reboot(number(n, "a controller number (1..9)")?)),
            ("reboot", _) => Err(CommandError::Usage(REBOOT)),
            ("spike", [w, axis, amps, ms]) => Ok(Command::Spike {
                wheel: wheel(w)?,
                axis: Axis::parse(axis).ok_or(CommandError::Usage(SPIKE))?,
                amps: positive_up_to(
                    amps,
                    "a current in amperes",
                    "the spike current (A)",
                    SPIKE_MAX_A,
                    "more than 0 and at most 10.24 A (the current sense reads no more)",
                )?,
                ms: positive_up_to(
                    ms,
                    "a duration in milliseconds",
                    "the spike duration (ms)",
                    SPIKE_MAX_MS,
                    "more than 0 and at most 60000 ms (for a lasting fault, `stall`)",
                )?,
            }),
            ("spike", _) => Err(CommandError::Usage(SPIKE)),
            ("sensor", [i, what]) => Ok(Command::Sensor {
                index: number(i, "a sensor number (0..9)")?,
                present: match *what {
                    "remove" => false,
                    "restore" => true,
                    _ => return Err(CommandError::Usage(SENSOR)),
                },
            }),
            ("sensor", _) => Err(CommandError::Usage(SENSOR)),
            ("temp", [i, celsius]) => {
                let c = finite(celsius, "a temperature in °C")?;
                if !(-55.0..=125.0).contains(&c) {
                    return Err(CommandError::OutOfRange {
                        what: "the temperature (°C)",
                        given: (*celsius).to_owned(),
                        allowed: "-55 to 125 (what the DS18S20 measures)",
                    });
                }
                Ok(Command::Temp {
                    index: number(i, "a sensor number (0..9)")?,
                    half_degrees: (c * 2.0).round() as i16,
                })
            }
            ("temp", _) => Err(CommandError::Usage(TEMP)),
            ("drop-serial", ["clear"]) => Ok(Command::ClearSerialDrops),
            ("drop-serial", [n]) => Ok(Command::DropSerial {
                n: byte_count(n)?,
                direction: Direction::ToMaster,
            }),
            ("drop-serial", [n, dir]) => Ok(Command::DropSerial {
                n: byte_count(n)?,
                direction: Direction::parse(dir).ok_or(CommandError::Usage(DROP))?,
            }),
            ("drop-serial", _) => Err(CommandError::Usage(DROP)),
            ("rc", [state]) => Ok(Command::Rc(on_off(state, RC)?)),
            ("rc", [ch, us]) => Ok(Command::RcWidth {
                channel: number(ch, "an RC channel (0..2)")?,
                us: rc_width(us)?,
            }),
            ("rc", _) => Err(CommandError::Usage(RC)),
            ("status", []) => Ok(Command::Status),
            ("status", _) => Err(CommandError::Usage("status")),
            ("time", []) => Ok(Command::Time),
            ("time", _) => Err(CommandError::Usage("time")),
            ("dtr", ["low"]) => Ok(Command::Dtr(false)),
            ("dtr", ["high"]) => Ok(Command::Dtr(true)),
            ("dtr", _) => Err(CommandError::Usage(DTR)),
            (other, _) => Err(CommandError::Unknown(other.to_owned())),
        }
    }

    /// Applies the command to `rover`; returns what happened, in words.
    pub fn apply(&self, rover: &mut Rover) -> Result<String, TwinError> {
        Ok(match *self {
            Command::Stall { wheel, axis, on } => {
                rover.stall(wheel, axis, on)?;
                let state = if on { "stalled" } else { "free" };
                format!("wheel {wheel} {} {state}", axis.name())
            }
            // A cut or restore that finds the controller already so says it changed nothing.
            Command::Cut(n) => {
                let was_cut = rover.cut_off().contains(&n);
                rover.cut(n)?;
                if was_cut {
                    format!("controller {n} was already cut off the bus; nothing changed")
                } else {
                    format!("controller {n} cut off the bus")
                }
            }
            Command::Restore(n) => {
                let was_cut = rover.cut_off().contains(&n);
                rover.restore(n)?;
                if was_cut {
                    format!("controller {n} back on the bus")
                } else {
                    format!(
                        "controller {n} was not cut off, so it is on the bus; nothing changed \
                         (`cut {n}` takes it off)"
                    )
                }
            }
            Command::Reboot(n) => {
                rover.reboot(n)?;
                format!("controller {n} reset: it restarts in its boot state, on its defaults")
            }
            Command::Spike {
                wheel,
                axis,
                amps,
                ms,
            } => {
                rover.spike(wheel, axis, amps, ms)?;
                format!("wheel {wheel} {}: +{amps} A for {ms} ms", axis.name())
            }
            Command::Sensor { index, present } => {
                let was_present = !rover.removed_sensors().contains(&index);
                rover.set_sensor_present(index, present)?;
                match (was_present, present) {
                    (true, true) => {
                        format!("sensor {index} was not removed; nothing changed")
                    }
                    (false, false) => {
                        format!("sensor {index} was already removed; nothing changed")
                    }
                    (_, true) => format!("sensor {index} restored"),
                    (_, false) => format!("sensor {index} removed"),
                }
            }
            Command::Temp {
                index,
                half_degrees,
            } => {
                rover.set_temperature(index, half_degrees)?;
                format!(
                    "sensor {index} measures {:.1} °C",
                    f64::from(half_degrees) / 2.0
                )
            }
            Command::DropSerial { n, direction } => {
                rover.drop_serial(direction, n);
                format!(
                    "the next {n} serial bytes {} will be lost",
                    direction.name()
                )
            }
            Command::ClearSerialDrops => match rover.clear_serial_drops() {
                (0, 0) => "no serial byte loss was pending; nothing changed".to_owned(),
                (to_master, to_host) => format!(
                    "serial losses cancelled: {to_master} bytes to-master and {to_host} \
                     to-host will now arrive"
                ),
            },
            Command::Rc(on) => {
                rover.set_rc(on);
                format!("RC receiver {}", if on { "on" } else { "off" })
            }
            Command::RcWidth { channel, us } => {
                rover.set_rc_width(channel, us)?;
                let widths = rover.rc_widths();
                format!("RC channel {channel} = {} µs", widths[usize::from(channel)])
            }
            Command::Status => crate::status(rover),
            Command::Time => format!("{} µs emulated", rover.micros()),
            Command::Dtr(_) => return Err(TwinError::PortOnly("dtr")),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_command() {
        let p = |s| Command::parse(s);
        assert_eq!(
            p("stall 3 on"),
            Ok(Command::Stall {
                wheel: 3,
                axis: Axis::Drive,
                on: true
            })
        );
        assert_eq!(
            p("stall 6 lift off"),
            Ok(Command::Stall {
                wheel: 6,
                axis: Axis::Lift,
                on: false
            })
        );
        assert_eq!(p("cut 4"), Ok(Command::Cut(4)));
        assert_eq!(p("  restore   4 "), Ok(Command::Restore(4)));
        assert_eq!(p("reboot 9"), Ok(Command::Reboot(9)));
        assert_eq!(
            p("spike 2 steer 3.5 20"),
            Ok(Command::Spike {
                wheel: 2,
                axis: Axis::Steer,
                amps: 3.5,
                ms: 20.0
            })
        );
        assert_eq!(
            p("sensor 0 remove"),
            Ok(Command::Sensor {
                index: 0,
                present: false
            })
        );
        assert_eq!(
            p("temp 9 25.5"),
            Ok(Command::Temp {
                index: 9,
                half_degrees: 51
            })
        );
        assert_eq!(
            p("drop-serial 3"),
            Ok(Command::DropSerial {
                n: 3,
                direction: Direction::ToMaster
            })
        );
        assert_eq!(
            p("drop-serial 1 to-host"),
            Ok(Command::DropSerial {
                n: 1,
                direction: Direction::ToHost
            })
        );
        assert_eq!(p("drop-serial clear"), Ok(Command::ClearSerialDrops));
        assert_eq!(p("rc on"), Ok(Command::Rc(true)));
        assert_eq!(
            p("rc 1 1200"),
            Ok(Command::RcWidth {
                channel: 1,
                us: 1200
            })
        );
        assert_eq!(p("status"), Ok(Command::Status));
        assert_eq!(p("time"), Ok(Command::Time));
        assert_eq!(p("dtr low"), Ok(Command::Dtr(false)));
        assert_eq!(p("dtr high"), Ok(Command::Dtr(true)));
        assert_eq!(
            Command::parse("dtr up").map_err(|e| e.to_string()),
            Err("usage: dtr low|high".to_owned())
        );
    }

    #[test]
    fn refuses_bad_lines_with_the_usage() {
        let e = |s| Command::parse(s).err().map(|e| e.to_string());
        assert_eq!(Command::parse(""), Err(CommandError::Empty));
        assert_eq!(
            Command::parse("fly 3"),
            Err(CommandError::Unknown("fly".into()))
        );
        assert_eq!(
            e("stall 7 on").as_deref(),
            Some("`7` is not a wheel number (1..6)")
        );
        assert_eq!(
            e("stall 1 maybe").as_deref(),
            Some(format!("usage: {STALL}").as_str())
        );
        assert_eq!(
            Command::parse("spike 1 wheel 2 3"),
            Err(CommandError::Usage(SPIKE))
        );
        assert_eq!(
            e("spike 1 drive inf 3").as_deref(),
            Some("`inf` is not a current in amperes")
        );
        // A spike must change something and stay within what the sense can show.
        let amps = "more than 0 and at most 10.24 A (the current sense reads no more)";
        let ms = "more than 0 and at most 60000 ms (for a lasting fault, `stall`)";
        for (line, what, given, allowed) in [
            ("spike 1 drive -5 10", "spike current (A)", "-5", amps),
            ("spike 1 drive 0 10", "spike current (A)", "0", amps),
            ("spike 1 drive -0 10", "spike current (A)", "-0", amps),
            ("spike 1 drive 10.25 10", "spike current (A)", "10.25", amps),
            ("spike 1 drive 5 -10", "spike duration (ms)", "-10", ms),
            ("spike 1 drive 5 0", "spike duration (ms)", "0", ms),
            (
                "spike 1 drive 5 60000.5",
                "spike duration (ms)",
                "60000.5",
                ms,
            ),
            ("spike 1 drive 5 1e300", "spike duration (ms)", "1e300", ms),
        ] {
            assert_eq!(
                e(line),
                Some(format!(
                    "the {what} `{given}` is out of range; give {allowed}"
                )),
                "{line}"
            );
        }
        // A temperature the sensor cannot measure is refused, not clamped.
        for c in ["-55.5", "125.5", "1000"] {
            assert_eq!(
                Command::parse(&format!("temp 1 {c}"))
                    .err()
                    .map(|e| e.to_string()),
                Some(format!(
                    "the temperature (°C) `{c}` is out of range; give -55 to 125 (what the \
                     DS18S20 measures)"
                ))
            );
        }
        // The ASCII minus, or the Unicode one the docs print.
        for minus in ["-", "\u{2212}"] {
            assert_eq!(
                Command::parse(&format!("temp 0 {minus}55")),
                Ok(Command::Temp {
                    index: 0,
                    half_degrees: -110
                })
            );
        }
        assert_eq!(
            Command::parse("spike 6 lift 10.24 60000"),
            Ok(Command::Spike {
                wheel: 6,
                axis: Axis::Lift,
                amps: 10.24,
                ms: 60_000.0
            })
        );
        assert_eq!(
            Command::parse("sensor 2 eat"),
            Err(CommandError::Usage(SENSOR))
        );
        assert_eq!(
            Command::parse("drop-serial 2 sideways"),
            Err(CommandError::Usage(DROP))
        );
        // Losing no byte is no fault: refused, not reported as set.
        for line in ["drop-serial 0", "drop-serial 0 to-host"] {
            assert_eq!(
                e(line).as_deref(),
                Some(
                    "drop-serial 0 would lose no byte, so nothing was changed; give N of 1 or more"
                )
            );
        }
        assert_eq!(Command::parse("rc"), Err(CommandError::Usage(RC)));
        // A width the receiver cannot send is refused, not clamped to its end.
        for us in ["499", "2501", "5000"] {
            assert_eq!(
                Command::parse(&format!("rc 1 {us}"))
                    .err()
                    .map(|e| e.to_string()),
                Some(format!(
                    "the RC pulse width (µs) `{us}` is out of range; give 500 to 2500 µs (what \
                     a receiver sends; the sticks span about 940 to 1940)"
                ))
            );
        }
        assert_eq!(
            e("rc 1 70000").as_deref(),
            Some("`70000` is not a pulse width in µs")
        );
        for (line, us) in [("rc 0 500", 500), ("rc 2 2500", 2500)] {
            assert!(
                matches!(Command::parse(line), Ok(Command::RcWidth { us: u, .. }) if u == us),
                "{line}"
            );
        }
        assert_eq!(Command::parse("reboot"), Err(CommandError::Usage(REBOOT)));
        assert_eq!(
            Command::parse("status now"),
            Err(CommandError::Usage("status"))
        );
    }
}
