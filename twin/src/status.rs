//! The twin's state in words, for `twin inject status`: emulated time and speed, the
//! faults in force, every wheel as the physics has it, and every board as one would see it
//! on the bench: its LEDs and what its bridges do with its motors.

use std::fmt::Write as _;

use physics::bridge::{Bridge, BridgeMode};
use physics::wheel::Motor;

use crate::leds::describe;
use crate::serial::Direction;
use crate::wiring::{self, CONTROLLERS, MASTER_CHIP, WHEELS};
use crate::Rover;

/// The twin's state in a few lines: time, speed, faults, each wheel as the physics has it,
/// and each board's LEDs and bridges.
pub fn status(rover: &mut Rover) -> String {
    let mut out = String::new();
    let speed = rover.speed();
    let _ = writeln!(
        out,
        "emulated {:.3} s, compute headroom {:.2}x real time ({:.2}x per second of CPU)",
        rover.micros() as f64 / 1e6,
        speed.ratio(),
        speed.cpu_ratio()
    );
    let list = |v: Vec<String>| {
        if v.is_empty() {
            "none".to_owned()
        } else {
            v.join(", ")
        }
    };
    let stalled = rover
        .stalled()
        .into_iter()
        .map(|(w, a)| format!("wheel {w} {}", a.name()))
        .collect();
    let cut = rover.cut_off().into_iter().map(|n| n.to_string()).collect();
    let removed = rover
        .removed_sensors()
        .into_iter()
        .map(|n| n.to_string())
        .collect();
    let _ = writeln!(out, "stalled: {}", list(stalled));
    let _ = writeln!(out, "cut off the bus: {}", list(cut));
    let spikes = rover
        .spikes()
        .into_iter()
        .map(|(w, a, amps, left_ms)| {
            format!("wheel {w} {} +{amps} A ({left_ms:.1} ms left)", a.name())
        })
        .collect();
    let _ = writeln!(out, "current spikes: {}", list(spikes));
    let _ = writeln!(out, "sensors removed: {}", list(removed));
    let temps: Vec<String> = rover
        .temperatures()
        .iter()
        .map(|&h| format!("{:.1}", f64::from(h) / 2.0))
        .collect();
    let _ = writeln!(
        out,
        "temperatures °C (ambient, then controllers 1..9): {}",
        temps.join(" ")
    );
    let line = rover.serial();
    let _ = writeln!(
        out,
        "serial bytes lost: {} to master, {} to host ({} and {} pending)",
        line.dropped(Direction::ToMaster),
        line.dropped(Direction::ToHost),
        line.pending(Direction::ToMaster),
        line.pending(Direction::ToHost)
    );
    let rc = rover.rc_widths();
    let _ = writeln!(
        out,
        "RC receiver: {} ({} / {} / {} µs)",
        if rover.rc_on() { "on" } else { "off" },
        rc[0],
        rc[1],
        rc[2]
    );
    let _ = writeln!(
        out,
        "watchdog resets (master, 1..9): {:?}",
        rover.watchdog_resets()
    );
    boards(rover, &mut out);
    let _ = write!(out, "wheel  drive ticks/s  steer °  lift °");
    for w in WHEELS {
        if let Ok(s) = rover.wheel(w) {
            let _ = write!(
                out,
                "\n{w:>5}  {:>13.0}  {:>7.1}  {:>6.1}",
                s.drive_ticks_per_s, s.steer_deg, s.lift_deg
            );
        }
    }
    out
}

/// The boards' lines: each LED with how long it has held its level (a latched exception
/// stays lit; a ping flashes LED1 on a drive board, LED2 on a lift board, for 50 ms each
/// second), and each motor's bridge.
fn boards(rover: &Rover, out: &mut String) {
    let now = rover.micros();
    if let Some([blue, status]) = rover.leds(MASTER_CHIP) {
        let _ = writeln!(
            out,
            "master LEDs: blue {}, status {}",
            describe(blue, now),
            describe(status, now)
        );
    }
    for n in CONTROLLERS {
        let _ = write!(out, "controller {n} ({}):", wiring::image_of(n));
        if let Some([led1, led2]) = rover.leds(usize::from(n)) {
            let _ = write!(
                out,
                " LED1 {}, LED2 {};",
                describe(led1, now),
                describe(led2, now)
            );
        }
        if let Some(bridges) = rover.bridges(n) {
            let motors: Vec<String> = [Motor::M1, Motor::M2]
                .into_iter()
                .zip(bridges)
                .filter_map(|(slot, bridge)| {
                    let (wheel, axis) = wiring::wheel_of(n, slot)?;
                    Some(format!(
                        "wheel {wheel} {} {}",
                        axis.name(),
                        bridge_words(bridge)
                    ))
                })
                .collect();
            let _ = write!(out, " {}", motors.join(", "));
        }
        out.push('\n');
    }
}

/// A bridge in words: `off` (the motor coasts), `forward 42 %`, `reverse 3 %`, `braking 100 %`.
fn bridge_words(bridge: Bridge) -> String {
    let percent = (bridge.duty() * 100.0).round();
    match bridge.mode() {
        BridgeMode::Off => "off".to_owned(),
        BridgeMode::Forward => format!("forward {percent} %"),
        BridgeMode::Reverse => format!("reverse {percent} %"),
        BridgeMode::Brake => format!("braking {percent} %"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bridge_reads_as_what_it_does_with_its_motor() {
        assert_eq!(bridge_words(Bridge::off()), "off");
        assert_eq!(bridge_words(Bridge::forward(0.424)), "forward 42 %");
        assert_eq!(bridge_words(Bridge::reverse(0.026)), "reverse 3 %");
        assert_eq!(
            bridge_words(Bridge::from_pins(1.0, false, false)),
            "braking 100 %"
        );
        assert_eq!(
            bridge_words(Bridge::forward(0.0)),
            "off",
            "duty 0 disables the bridge"
        );
    }
}
