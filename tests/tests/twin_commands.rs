//! The twin's fault commands say what they changed: one that finds the rover already so
//! (a restore of a controller that was never cut, a second cut) says it changed nothing.

use twin::command::Command;
use twin::Rover;

fn apply(rover: &mut Rover, line: &str) -> String {
    Command::parse(line).unwrap().apply(rover).unwrap()
}

#[test]
fn a_command_that_changes_nothing_says_so() {
    let mut r = Rover::new().expect("the twin builds (run scripts/firmware.sh)");
    assert_eq!(
        apply(&mut r, "restore 4"),
        "controller 4 was not cut off, so it is on the bus; nothing changed (`cut 4` takes it off)"
    );
    assert_eq!(apply(&mut r, "cut 4"), "controller 4 cut off the bus");
    assert_eq!(
        apply(&mut r, "cut 4"),
        "controller 4 was already cut off the bus; nothing changed"
    );
    assert_eq!(r.cut_off(), [4]);
    assert_eq!(apply(&mut r, "restore 4"), "controller 4 back on the bus");
    assert!(r.cut_off().is_empty());

    assert_eq!(
        apply(&mut r, "sensor 2 restore"),
        "sensor 2 was not removed; nothing changed"
    );
    assert_eq!(apply(&mut r, "sensor 2 remove"), "sensor 2 removed");
    assert_eq!(
        apply(&mut r, "sensor 2 remove"),
        "sensor 2 was already removed; nothing changed"
    );
    assert_eq!(apply(&mut r, "sensor 2 restore"), "sensor 2 restored");
    assert!(r.removed_sensors().is_empty());

    // drop-serial 0 is refused before it reaches the rover.
    assert_eq!(
        Command::parse("drop-serial 0").unwrap_err().to_string(),
        "drop-serial 0 would lose no byte, so nothing was changed; give N of 1 or more"
    );
}
