//! The twin's state in words, for `twin inject status`: emulated time and speed, the
//! faults in force, and every wheel as the physics has it.

use std::fmt::Write as _;

use crate::serial::Direction;
use crate::wiring::WHEELS;
use crate::Rover;

/// The twin's state in a few lines: time, speed, faults, and each wheel as the physics has it.
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
