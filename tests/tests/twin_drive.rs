//! End to end through the twin's serial line, written as the original PC library behaves
//! (reference §4.1, §4.3, §4.7, §8.3, §8.5): wait for `Ready`, configure read sets 0, 1, 2,
//! calibrate, reset exceptions, then drive all wheels at 1000, turn 40 and lift, watching
//! update() — all in emulated time, with the real master and the nine real slave images
//! and the physics around them.
//!
//!
//! The second test runs the README's demo drive, `examples/demo.rover`, with hostctl's own
//! `run` code over the twin in emulated time (calibrate, reset, drive at 1000, turn 40, lift
//! wheel 1, stop) and checks the live view it prints against what the rover should be
//! doing, so the demo shows real output of the emulated firmware. The third runs a script
//! with `--pairs 0` on a twin whose pairs 1 and 2 are off the bus from power-up, as on a
//! bench with the rear pair (wheels 1 and 2) alone. The fourth runs `examples/step.rover`
//! with `--json`: a steer step recorded by `watch 2 0`, a view at every update, as a
//! researcher tuning a controller would.
//! (The tests live in one file so they run in parallel.)
//!
//! Needs the firmware images: `scripts/firmware.sh`.

mod twin_support;

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::Duration;

use hostctl::cmd::pc::{Motor, Op, WHEELS};
use hostctl::cmd::run::{self, Clock, Output};
use hostctl::link::Link;
use twin_support::{
    drive_speed, lift_pos, master_exception, rover, slave_exception, slave_running, steer_pos,
    EmuClock, EmuPort, Session,
};

#[test]
fn drive_turn_and_lift_like_the_pc_library() {
    let mut s = Session::start();

    // After the boot every board is in its boot exception, and the master too.
    let snap = s.update();
    assert_eq!(master_exception(&snap), 0x0002, "master boot exception");
    for n in 1..=9 {
        assert_eq!(slave_exception(&snap, n), Some(2), "controller {n} in boot");
    }

    // calibrate(): the §8.3 frames, byte for byte, with their 50-ms pauses.
    let ops = s.pc.clone().calibrate().unwrap();
    let first: Vec<Vec<u8>> = ops
        .iter()
        .filter_map(|op| match op {
            Op::Write(w) => Some(w.frame.to_vec()),
            Op::Pause(_) => None,
        })
        .take(2)
        .collect();
    assert_eq!(
        first[0],
        [
            0x19, 0x12, 0x08, 0x0a, 0x41, 0x00, 0x0b, 0x00, 0x00, 0x0c, 0xff, 0x7f, 0x0d, 0x00,
            0x00, 0x0e, 0x00, 0x00, 0x0f, 0xff, 0x7f, 0x18, 0xfe, 0x19, 0x05
        ]
    );
    assert_eq!(
        first[1],
        [
            0x1d, 0x12, 0x0a, 0x1b, 0x00, 0x00, 0x1c, 0x00, 0x00, 0x1d, 0xff, 0x7f, 0x1e, 0x00,
            0x00, 0x1f, 0x00, 0x00, 0x20, 0x8f, 0x02, 0x2a, 0x43, 0x2b, 0xc4, 0x28, 0xfe, 0x29,
            0x05
        ]
    );
    // Calibrated while every board is still in its boot exception, as the original
    // operator program does at start-up: a position motor in exception holds where it is
    // (required := actual), so the new calibration moves nothing.
    s.calibrate();

    // resetExceptions(), then every board is out of exception.
    s.reset_exceptions();
    let (ok, snap, took) = s.until(1.0, |s| {
        master_exception(s) == 0 && (1..=9).all(|n| slave_running(s, n))
    });
    assert!(ok, "exceptions not cleared after {took:?}: {snap:?}");

    // Drive all six at 1000 ticks/s: every actual speed within 5 % in a few seconds.
    let all: Vec<(u8, f32)> = WHEELS.map(|w| (w, 1000.0)).collect();
    s.set(Motor::Drive, &all);
    let (ok, snap, took) = s.until(5.0, |s| {
        (1..=6).all(|w| (drive_speed(s, w) - 1000.0).abs() <= 50.0)
    });
    let speeds: Vec<f32> = WHEELS.map(|w| drive_speed(&snap, w)).collect();
    assert!(ok, "speeds {speeds:?} after {took:?}");
    println!("all six drives within 5 % of 1000 after {took:?}: {speeds:?}");
    // The wheels really turn at that speed (the physics, not only the firmware's number).
    for w in WHEELS {
        let physical = s.twin.borrow().wheel(w).unwrap().drive_ticks_per_s;
        assert!(
            (physical - 1000.0).abs() < 60.0,
            "wheel {w} turns at {physical}"
        );
    }

    // Turn 40 (the operator's `t`): wheels 1, 2 at +40, 5, 6 at -40, 3, 4 at 0.
    let turn = [
        (1, 40.0),
        (2, 40.0),
        (5, -40.0),
        (6, -40.0),
        (3, 0.0),
        (4, 0.0),
    ];
    s.set(Motor::Steer, &turn);
    let settled = |s: &hostctl::cmd::live::Snapshot| {
        turn.iter()
            .all(|&(w, want)| (steer_pos(s, w) - want).abs() <= 2.0)
    };
    let (ok, snap, took) = s.until(6.0, settled);
    let steer: Vec<f32> = WHEELS.map(|w| steer_pos(&snap, w)).collect();
    assert!(ok, "steer {steer:?} after {took:?}");
    // Settled means it stays there.
    s.pass(1.0);
    let snap = s.update();
    let later: Vec<f32> = WHEELS.map(|w| steer_pos(&snap, w)).collect();
    assert!(settled(&snap), "steer drifted to {later:?}");
    println!("steer settled after {took:?}: {later:?}");

    // Lift wheel 1 to +20 and wheel 4 to -20, within their limits (the library refuses
    // demands beyond the calibration less 10°, before sending anything).
    assert!(s.pc.clone().set_required(1, Motor::Lift, 100.0).is_err());
    s.set(Motor::Lift, &[(1, 20.0), (4, -20.0)]);
    let (ok, snap, took) = s.until(6.0, |s| {
        (lift_pos(s, 1) - 20.0).abs() <= 2.0 && (lift_pos(s, 4) + 20.0).abs() <= 2.0
    });
    let lifts: Vec<f32> = WHEELS.map(|w| lift_pos(&snap, w)).collect();
    assert!(ok, "lift {lifts:?} after {took:?}");
    for w in [2u8, 3, 5, 6] {
        let lift = lifts[usize::from(w - 1)];
        assert!(
            lift.abs() < 2.0,
            "wheel {w}'s lift moved to {lift}: {lifts:?}"
        );
    }
    println!("lifts settled after {took:?}: {lifts:?}");

    // Nothing went wrong on the way: no exception anywhere, and the speeds held.
    assert_eq!(master_exception(&snap), 0, "{snap:?}");
    let speeds: Vec<f32> = WHEELS.map(|w| drive_speed(&snap, w)).collect();
    assert!(
        speeds.iter().all(|v| (v - 1000.0).abs() <= 50.0),
        "{speeds:?}"
    );

    // The library's full update() rate, in emulated time.
    let start = s.clock_now();
    for _ in 0..20 {
        s.update();
    }
    let per_s = 20.0 / (s.clock_now() - start).as_secs_f64();
    println!("full update() rate: {per_s:.1}/s of emulated time");
    assert!(per_s >= 25.0, "update() {per_s:.1}/s");
}

/// The numbers of the view's row for `wheel` in the first view printed after `marker`.
fn row_after(text: &str, marker: &str, wheel: u8) -> Vec<f64> {
    words_after(text, marker, wheel)
        .iter()
        .map(|w| w.parse().unwrap_or(f64::NAN))
        .collect()
}

/// [`row_after`]'s six columns as printed.
fn words_after<'a>(text: &'a str, marker: &str, wheel: u8) -> Vec<&'a str> {
    let start = text
        .find(marker)
        .unwrap_or_else(|| panic!("no {marker:?} in {text}"));
    let line = text[start..]
        .lines()
        .find(|l| l.split_whitespace().next() == Some(&wheel.to_string()))
        .unwrap_or_else(|| panic!("no row for wheel {wheel} after {marker:?}"));
    line.split_whitespace().skip(1).take(6).collect()
}

/// Runs `plan` with hostctl's `run` code on `twin`, as the binary does after opening its
/// port; returns what it printed (also echoed) and the clock, at the script's end.
fn run_on(twin: &Rc<RefCell<twin::Rover>>, plan: &run::Plan, json: bool) -> (String, EmuClock) {
    let port = EmuPort::new(Rc::clone(twin));
    let mut link = Link::connect(port, "the twin", Duration::ZERO).unwrap();
    let mut clock = EmuClock::new(Rc::clone(twin));
    clock.sleep(hostctl::link::SETTLE);
    let mut out = Vec::new();
    let result = run::run(
        plan,
        &mut link,
        &mut clock,
        &mut Output {
            out: &mut out,
            in_place: false,
            json,
            width: || None,
        },
    );
    let text = String::from_utf8(out).unwrap();
    println!("{text}");
    result.unwrap();
    (text, clock)
}

/// Runs `examples/NAME` on a new twin, all six wheels fitted; returns what it printed, the
/// clock and the twin.
fn run_example(name: &str, json: bool) -> (String, EmuClock, Rc<RefCell<twin::Rover>>) {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name);
    let plan = run::plan(&run::Args {
        file,
        pairs: "0,1,2".into(),
    })
    .unwrap();
    let twin = Rc::new(RefCell::new(rover()));
    let (text, clock) = run_on(&twin, &plan, json);
    (text, clock, twin)
}

#[test]
fn the_demo_script_drives_the_twin_and_its_view_shows_it() {
    let (text, clock, twin) = run_example("demo.rover", false);
    println!(
        "demo: {:.1} s of emulated time, twin speed {:.2}x real time",
        clock.now().as_secs_f64(),
        twin.borrow().speed().ratio()
    );

    // [drive req, actual, steer req, actual, lift req, actual]
    for w in 1..=6 {
        let r = row_after(&text, "> drive all 1000", w);
        assert_eq!(r[0], 1000.0);
        assert!(
            (r[1] - 1000.0).abs() <= 50.0,
            "wheel {w} after driving: {r:?}"
        );
    }
    let turn = [40.0, 40.0, 0.0, 0.0, -40.0, -40.0];
    for w in 1..=6u8 {
        let r = row_after(&text, "> turn 40", w);
        let want = turn[usize::from(w - 1)];
        assert_eq!(r[2], want);
        assert!((r[3] - want).abs() <= 2.0, "wheel {w} after turning: {r:?}");
    }
    let r = row_after(&text, "> lift 1 20", 1);
    assert!((r[5] - 20.0).abs() <= 2.0, "wheel 1 lift: {r:?}");
    // After the stop every demand is 0, in brackets: the stop's own exception dropped
    // them (a drive aims for 0, a position holds where it stood, and every gain is 0),
    // and no board is left in an exception.
    // Each checked in the watch's last view.
    let tail = &text[text.rfind("> watch 3").unwrap()..];
    let last = &tail[tail.rfind("wheel ").unwrap()..];
    for w in 1..=6 {
        let r = words_after(last, "wheel", w);
        assert_eq!(
            [r[0], r[2], r[4]],
            ["(0)", "(0.0)", "(0.0)"],
            "wheel {w}: {r:?}"
        );
        let row = last.lines().find(|l| l.starts_with(&format!("{w} ")));
        assert!(row.is_some_and(|l| l.ends_with(" -")), "wheel {w}: {row:?}");
    }
    assert!(last.contains("master: no exception"), "{last}");
    // The stop left every drive unpowered, so the wheels coast to rest within the watch
    // (the library's stop alone keeps them under a decaying duty for some 20 s).
    for w in 1..=6 {
        let r = row_after(last, "wheel", w);
        assert!(r[1].abs() < 50.0, "wheel {w} still turning: {r:?}");
    }
}

#[test]
fn a_bench_with_the_front_pair_alone_drives_with_pairs_0() {
    let dir = std::env::temp_dir().join(format!("blodwen-pairs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bench.rover");
    std::fs::write(&file, "calibrate\nreset\ndrive all 1000\nwatch 6\n").unwrap();
    let plan = run::plan(&run::Args {
        file,
        pairs: "0".into(),
    })
    .unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let twin = Rc::new(RefCell::new(rover()));
    for n in 4..=9 {
        twin.borrow_mut().cut(n).unwrap();
    }
    let (text, _) = run_on(&twin, &plan, false);
    // The last view: wheels 1 and 2 at 1000, no row for the others, no exception (the
    // master counts controllers that never answered as absent, not silent).
    let tail = &text[text.rfind("> watch 6").unwrap()..];
    let last = &tail[tail.rfind("wheel ").unwrap()..];
    for w in 1..=2 {
        let r = row_after(last, "wheel", w);
        assert_eq!(r[0], 1000.0);
        assert!((r[1] - 1000.0).abs() <= 50.0, "wheel {w}: {r:?}");
    }
    assert!(!last.contains("\n3 "), "{last}");
    assert!(
        last.contains("wheels 3, 4, 5, 6 not fitted (--pairs): not polled"),
        "{last}"
    );
    assert!(last.contains("master: no exception"), "{last}");
}

#[test]
fn a_point_turn_then_a_rotation_turns_every_wheel_round_the_centre() {
    let (text, _, _) = run_example("spin.rover", false);
    // [drive req, actual, steer req, actual, lift req, actual]
    let point_turn = [-46.0, 46.0, 0.0, 0.0, 46.0, -46.0];
    // The operator's `rot 500`: right-side corners back, left forward, the middle wheels
    // at 1/1.8 of that.
    let speed = [-500.0, 500.0, -500.0 / 1.8, 500.0 / 1.8, -500.0, 500.0];
    for w in 1..=6u8 {
        let i = usize::from(w - 1);
        let r = row_after(&text, "> pointturn", w);
        assert_eq!(r[2], point_turn[i], "wheel {w}: {r:?}");
        assert!(
            (r[3] - point_turn[i]).abs() <= 2.0,
            "wheel {w} steer: {r:?}"
        );
        let r = row_after(&text, "> rotate 500", w);
        assert!((r[0] - speed[i]).abs() < 0.5, "wheel {w}: {r:?}");
        assert!(
            (r[1] - speed[i]).abs() <= 0.05 * speed[i].abs(),
            "wheel {w} drive: {r:?}"
        );
        // The steers held their angles while the wheels turned.
        assert!(
            (r[3] - point_turn[i]).abs() <= 2.0,
            "wheel {w} steer: {r:?}"
        );
        // `rotate 0` sends 0 to each (shown as 0, not -0), and the wheels slow to within 5 %
        // of the rotation's speed.
        assert_eq!(words_after(&text, "> rotate 0", w)[0], "0");
        let r = row_after(&text, "> rotate 0", w);
        assert!(r[1].abs() <= 25.0, "wheel {w} stopped: {r:?}");
    }
}

#[test]
fn a_steer_step_is_recorded_at_the_links_full_rate() {
    let (text, _, _) = run_example("step.rover", true);
    // (elapsed s, wheel 1's steer actual) of each view the `watch` line printed.
    let number = |line: &str, key: &str| -> f64 {
        let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key} in {line}")) + key.len()..];
        let end = rest.find([',', '}']).unwrap();
        rest[..end].parse().unwrap()
    };
    let views: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with(r#"{"command":"run","line":13,"elapsed_s""#))
        .collect();
    let series: Vec<(f64, f64)> = views
        .iter()
        .map(|l| {
            let wheel = &l[l.find(r#"{"wheel":1,"#).unwrap()..];
            let steer = &wheel[wheel.find(r#""steer":"#).unwrap()..];
            assert_eq!(number(steer, r#""required":"#), 40.0, "{l}");
            (number(l, r#""elapsed_s":"#), number(steer, r#""actual":"#))
        })
        .collect();
    // The `show` line's registers in each view: the controller's duty and error.
    let shown = |l: &str, register: &str| {
        let at = l.find(&format!(r#""register":"{register}""#)).unwrap();
        number(&l[at..], r#""value":"#)
    };
    for (l, &(_, actual)) in views.iter().zip(&series) {
        // Read after the round that read the actual, some 45 ms later: the steer, turning
        // at up to ~65°/s towards 40, has then closed up to 3° more of the gap.
        let error = shown(l, "REGDS_STEER_ERROR");
        let gap = 40.0 - actual;
        assert!(error <= gap + 0.5 && error >= gap - 3.5, "{l}");
    }
    assert_eq!(
        shown(views[1], "REGDS_STEER_CONTROL"),
        255.0,
        "full duty at first"
    );
    let (first, last) = (series[0], series[series.len() - 1]);
    println!(
        "{} views in {:.2} s; steer {:.1} -> {:.1}",
        series.len(),
        last.0,
        first.1,
        last.1
    );
    // One view per update: the link's rate, some 20 a second, where `watch 2` alone
    // prints three.
    assert!(series.len() >= 30, "{series:?}");
    assert!(series.windows(2).all(|w| w[1].0 > w[0].0), "{series:?}");
    assert!((last.0 - 2.0).abs() < 0.1, "{series:?}");
    // The step itself, from near 0 to 40 within 2°, with the swing in between sampled
    // (more than five views between 10 % and 90 % of the way).
    assert!(first.1.abs() < 8.0, "{series:?}");
    assert!((last.1 - 40.0).abs() <= 2.0, "{series:?}");
    let rising = series
        .iter()
        .filter(|&&(_, a)| {
            a > first.1 + 0.1 * (40.0 - first.1) && a < first.1 + 0.9 * (40.0 - first.1)
        })
        .count();
    println!("{rising} views between 10 % and 90 % of the step");
    assert!(rising > 5, "{rising} views on the way: {series:?}");
}
