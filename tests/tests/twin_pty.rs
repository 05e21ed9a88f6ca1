//! The twin behind a real pseudo-terminal, opened the way hostctl opens a serial port (the
//! `serialport` crate at 115200 8N1, DTR pulse, wait for `Ready`): the master's banner
//! arrives after every open, because opening resets the master (the Uno's DTR auto-reset),
//! and device 0 answers frames. A Python program written from the reference alone
//! (`examples/python/rover_client.py`) drives it too, as any program written for the real
//! rover would. Runs against whatever slave images are built.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use harness::Pty;
use twin::control::ControlSocket;
use twin::serve::{Limits, Server};
use twin::Rover;

/// Starts a paced twin on a thread, its pty linked at `link` (and its control socket next
/// to it) if given; returns the pty path and the flag that stops it.
fn start_twin(
    link: Option<std::path::PathBuf>,
) -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel();
    let flag = Arc::clone(&stop);
    let thread = std::thread::spawn(move || {
        let rover = Rover::new().expect("the twin builds (run scripts/firmware.sh)");
        let mut pty = Pty::open().expect("a pty");
        let control = link.as_ref().map(|link| {
            pty.link(link).unwrap();
            ControlSocket::bind(&twin::paths::control_of(link)).unwrap()
        });
        let mut server = Server::new(rover, pty, control, true);
        tx.send(server.path().display().to_string()).unwrap();
        server
            .serve(
                Limits::default(),
                &|| flag.load(Ordering::SeqCst),
                &mut |_, _, _| {},
            )
            .expect("the twin serves");
    });
    let path = rx.recv_timeout(Duration::from_secs(30)).expect("pty path");
    (path, stop, thread)
}

#[test]
fn a_serial_program_sees_the_banner_after_each_open() {
    let (path, stop, thread) = start_twin(None);
    for _ in 0..2 {
        // hostctl's own open: serialport at 115200, DTR pulse (refused by a pty), banner.
        let mut link = hostctl::link::open_serial(&path, Duration::ZERO)
            .expect("the banner with Ready arrives after the open");
        // Device 0 answers: configure the library's read set 2 (11 ids), reply = count.
        let frame = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
        assert_eq!(link.transact(0, &frame, 1).unwrap(), [0x0b]);
        // 22 bytes of master registers; at boot the master is in its boot exception.
        let reply = link.transact(0, &[0x03, 0x03, 0x02], 22).unwrap();
        assert_eq!(&reply[20..], [0x02, 0x00], "EXCEPTIONDATA = boot");
    }
    stop.store(true, Ordering::SeqCst);
    thread.join().unwrap();
}

#[test]
fn hostctl_sets_hupcl_so_its_close_resets_the_master_whatever_came_before() {
    use nix::sys::termios::{tcgetattr, tcsetattr, ControlFlags, SetArg};
    let pty = Pty::open().expect("a pty");
    // A program before hostctl cleared HUPCL (`stty -F PORT -hupcl`, a common Arduino trick).
    let other = std::fs::File::open(pty.path()).unwrap();
    let mut termios = tcgetattr(&other).unwrap();
    termios.control_flags.remove(ControlFlags::HUPCL);
    tcsetattr(&other, SetArg::TCSANOW, &termios).unwrap();
    drop(other);
    assert!(!pty.hangs_up_on_close());
    let port = hostctl::port::SerialPort::open(&pty.path().display().to_string(), Duration::ZERO)
        .expect("the pty opens as a serial port");
    assert!(
        pty.hangs_up_on_close(),
        "hostctl sets HUPCL as the original library does, so its close drops DTR"
    );
    // And again at its close, if another program cleared it while hostctl ran.
    let other = std::fs::File::open(pty.path()).unwrap();
    tcsetattr(&other, SetArg::TCSANOW, &termios).unwrap();
    assert!(!pty.hangs_up_on_close());
    drop(port);
    assert!(pty.hangs_up_on_close());
    drop(other);
}

#[test]
fn hostctl_finds_the_twin_behind_a_link_and_waits_in_its_time() {
    let dir = std::env::temp_dir().join(format!("twin-pty-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("port");
    let (_path, stop, thread) = start_twin(Some(link.clone()));
    assert!(hostctl::twin::is_running(&link));
    let before = hostctl::twin::emulated_us(&link).expect("the twin tells its time");
    // hostctl's clock for this port is the twin's: 200 ms of it pass in a sleep.
    let mut clock = hostctl::twin::clock_for(&link.display().to_string());
    let t0 = clock.now();
    clock.sleep(Duration::from_millis(200));
    assert!(clock.now() - t0 >= Duration::from_millis(200));
    let after = hostctl::twin::emulated_us(&link).unwrap();
    assert!(after >= before + 200_000, "{before} -> {after}");
    // The link opens as a serial port, banner included.
    let mut port = hostctl::link::open_serial(&link.display().to_string(), Duration::ZERO)
        .expect("banner through the link");
    assert_eq!(port.transact(0, &[0x04, 0x04, 0x06, 0x0b], 1).unwrap(), [1]);
    stop.store(true, Ordering::SeqCst);
    thread.join().unwrap();
    assert!(
        !hostctl::twin::is_running(&link),
        "the link and socket go with the twin"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hostctl_and_the_twin_agree_on_the_default_link() {
    assert_eq!(hostctl::twin::default_link(), twin::paths::default_link());
    assert_eq!(
        hostctl::twin::control_of(&hostctl::twin::default_link()),
        twin::paths::control_of(&twin::paths::default_link())
    );
}

/// A paced twin whose pty is linked in a fresh directory, with what a test uses of it.
struct Linked {
    dir: std::path::PathBuf,
    link: std::path::PathBuf,
    /// Its control socket.
    control: std::path::PathBuf,
    /// The link as hostctl takes a port.
    port: String,
    stop: Arc<AtomicBool>,
    thread: std::thread::JoinHandle<()>,
}

impl Linked {
    /// Starts one in a directory named after `test`.
    fn start(test: &str) -> Linked {
        let dir = std::env::temp_dir().join(format!("{test}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let link = dir.join("port");
        let (_path, stop, thread) = start_twin(Some(link.clone()));
        Linked {
            control: twin::paths::control_of(&link),
            port: link.display().to_string(),
            dir,
            link,
            stop,
            thread,
        }
    }

    /// Stops the twin and removes its directory.
    fn finish(self) {
        self.stop.store(true, Ordering::SeqCst);
        self.thread.join().unwrap();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Each controller's watchdog resets, from the twin's status (its line lists the master
/// first, then controllers 1..9).
fn slave_resets(control: &std::path::Path) -> Vec<u64> {
    let status = twin::control::send(control, "status").expect("the twin answers");
    let line = status
        .lines()
        .find_map(|l| l.strip_prefix("watchdog resets (master, 1..9): "))
        .expect("a watchdog line in the status");
    let counts: Vec<u64> = line
        .trim_matches(['[', ']'])
        .split(", ")
        .map(|n| n.parse().expect("a count"))
        .collect();
    assert_eq!(counts.len(), 10, "{line}");
    counts[1..].to_vec()
}

/// Every wheel's physical state from the twin's status table: drive ticks/s, steer and
/// lift degrees.
fn wheel_states(control: &std::path::Path) -> Vec<[f64; 3]> {
    let status = twin::control::send(control, "status").expect("the twin answers");
    let rows = status
        .lines()
        .skip_while(|l| !l.starts_with("wheel  drive"));
    rows.skip(1)
        .take(6)
        .map(|row| {
            let mut numbers = row.split_whitespace().skip(1);
            [(); 3].map(|()| numbers.next().expect("3 values").parse().expect("a number"))
        })
        .collect()
}

/// Every wheel's drive speed (ticks/s), from the twin's status table.
fn drive_speeds(control: &std::path::Path) -> Vec<f64> {
    wheel_states(control).iter().map(|s| s[0]).collect()
}

/// Opens `twin`'s port as hostctl does and runs a script that ends with every wheel
/// driving at 1000; returns the open link and the wheels' speeds at the script's end.
fn leave_driving(
    twin: &Linked,
    clock: &mut dyn hostctl::cmd::run::Clock,
) -> (hostctl::link::Link<hostctl::port::SerialPort>, Vec<f64>) {
    let script = twin.dir.join("drive.rover");
    std::fs::write(&script, "calibrate\nreset\ndrive all 1000\nwait 5\n").unwrap();
    let args = ["hostctl", "run", &script.display().to_string()];
    let cli = <hostctl::cli::Cli as clap::Parser>::try_parse_from(args).unwrap();
    let plan = hostctl::plan(&cli.command).unwrap();
    let style = hostctl::Style {
        json: false,
        in_place: false,
        width: || None,
    };
    let mut serial = hostctl::link::open_serial(&twin.port, Duration::ZERO).expect("the banner");
    hostctl::execute_with_clock(&plan, &mut serial, style, &mut Vec::new(), clock)
        .expect("the script runs");
    let driving = drive_speeds(&twin.control);
    assert_eq!(driving.len(), 6);
    assert!(
        driving.iter().all(|&s| s > 900.0),
        "driving at the end: {driving:?}"
    );
    (serial, driving)
}

/// Closes hostctl's port and checks that this rebooted the master, which hard-reset every
/// controller once, so that every wheel coasts down from `driving`.
fn close_and_see_every_wheel_coast(
    twin: &Linked,
    serial: hostctl::link::Link<hostctl::port::SerialPort>,
    driving: &[f64],
    clock: &mut dyn hostctl::cmd::run::Clock,
) {
    let before = slave_resets(&twin.control);
    drop(serial);
    clock.sleep(Duration::from_millis(1_500));
    let after = slave_resets(&twin.control);
    for (b, a) in before.iter().zip(&after) {
        assert_eq!(*a, b + 1, "one hard reset each: {before:?} -> {after:?}");
    }
    let coasting = drive_speeds(&twin.control);
    assert_eq!(coasting.len(), 6, "{coasting:?}");
    for (d, c) in driving.iter().zip(&coasting) {
        assert!(*c < d * 0.7, "coasting down: {driving:?} -> {coasting:?}");
    }
}

#[test]
fn closing_the_port_stops_a_rover_left_driving() {
    let twin = Linked::start("twin-hangup-test");
    let mut clock = hostctl::twin::clock_for(&twin.port);

    // A script that ends with the rover driving, run over a port this test holds open.
    let (serial, driving) = leave_driving(&twin, &mut *clock);
    // Closed as hostctl closes it: HUPCL is the serial port's default, as on the
    // original library's port. The master resets on the close and hard-resets every
    // controller: all coast down.
    close_and_see_every_wheel_coast(&twin, serial, &driving, &mut *clock);

    // A program that clears HUPCL closes without a reset: nothing reboots.
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&twin.link)
        .unwrap();
    let mut termios = nix::sys::termios::tcgetattr(&file).unwrap();
    termios
        .control_flags
        .remove(nix::sys::termios::ControlFlags::HUPCL);
    nix::sys::termios::tcsetattr(&file, nix::sys::termios::SetArg::TCSANOW, &termios).unwrap();
    clock.sleep(Duration::from_millis(700));
    let opened = slave_resets(&twin.control);
    drop(file);
    clock.sleep(Duration::from_millis(700));
    assert_eq!(
        slave_resets(&twin.control),
        opened,
        "no reset on a close without HUPCL"
    );
    // DTR stayed up, so the next open does not reset either (as on a USB serial port).
    let again = std::fs::File::open(&twin.link).unwrap();
    clock.sleep(Duration::from_millis(700));
    assert_eq!(
        slave_resets(&twin.control),
        opened,
        "no reset on an open with DTR still up"
    );
    drop(again);

    twin.finish();
}

#[test]
fn hostctl_resets_the_master_at_its_open_and_close_while_another_program_holds_the_port() {
    let twin = Linked::start("twin-held-port");
    let mut clock = hostctl::twin::clock_for(&twin.port);
    // A serial monitor (or ModemManager, or `cat`) opened the port first and reads what
    // comes: the banner of the reset its open made is gone when hostctl opens.
    let mut other = std::fs::File::open(&twin.link).unwrap();
    clock.sleep(Duration::from_millis(700));
    let flags = nix::fcntl::fcntl(&other, nix::fcntl::FcntlArg::F_GETFL).unwrap();
    let nonblocking = nix::fcntl::OFlag::from_bits_truncate(flags) | nix::fcntl::OFlag::O_NONBLOCK;
    nix::fcntl::fcntl(&other, nix::fcntl::FcntlArg::F_SETFL(nonblocking)).unwrap();
    let mut taken = Vec::new();
    let _ = std::io::Read::read_to_end(&mut other, &mut taken);
    assert!(
        String::from_utf8_lossy(&taken).contains("Ready"),
        "the other program took the banner: {taken:?}"
    );

    // hostctl's open pulses DTR, which on a USB serial port resets the Uno whoever holds
    // the port (a pty has no DTR: the twin hears it over its control socket), so a fresh
    // banner comes; and its close drops DTR, which reboots the master with the other
    // program still holding the port, where that close alone would not.
    let (serial, driving) = leave_driving(&twin, &mut *clock);
    close_and_see_every_wheel_coast(&twin, serial, &driving, &mut *clock);

    // DTR is already down: the other program's close resets nothing more.
    let after = slave_resets(&twin.control);
    drop(other);
    clock.sleep(Duration::from_millis(700));
    assert_eq!(slave_resets(&twin.control), after, "no second reset");
    twin.finish();
}

#[test]
fn a_second_open_of_a_port_in_use_resets_nothing() {
    let twin = Linked::start("twin-second-open");
    let mut clock = hostctl::twin::clock_for(&twin.port);
    let mut serial = hostctl::link::open_serial(&twin.port, Duration::ZERO).expect("the banner");
    clock.sleep(Duration::from_millis(300));
    let before = slave_resets(&twin.control);

    // `stty -F` or a second program opens the port and closes it again: on the Uno DTR
    // stays as the first program holds it, so nothing reboots.
    let other = std::fs::File::open(&twin.link).unwrap();
    clock.sleep(Duration::from_millis(500));
    drop(other);
    clock.sleep(Duration::from_millis(500));
    assert_eq!(
        slave_resets(&twin.control),
        before,
        "no reset by a second open"
    );
    // The first program's session goes on: device 0 answers its frames.
    assert_eq!(
        serial.transact(0, &[0x04, 0x04, 0x06, 0x0b], 1).unwrap(),
        [1]
    );

    drop(serial);
    twin.finish();
}

#[test]
fn a_watch_goes_on_past_bytes_the_serial_line_loses() {
    use hostctl::cmd::watch::{self, Args};
    use hostctl::cmd::Reading;
    let twin = Linked::start("twin-pty-lost");
    let control = twin.control.clone();
    let mut port =
        hostctl::link::open_serial(&twin.port, Duration::ZERO).expect("banner through the link");
    // The master's standard set 2 (temperatures, EXCEPTIONDATA), with REGMASTER_TEMPSREAD
    // read beside it through the scratch set, which each lost reply's probe overwrites.
    let plan = watch::plan(&Args {
        readset: "2".into(),
        device: None,
        count: Some(7),
        interval_ms: 0,
        registers: Vec::new(),
    })
    .unwrap();
    let mut seen = Vec::new();
    let mut clock = hostctl::twin::clock_for(&twin.port);
    watch::run(&plan, &mut port, &mut *clock, &mut |round| {
        let row = &round.rows[0];
        seen.push(match &row.reading {
            Reading::Values(raws) => format!(
                "EXCEPTIONDATA {:#06x}, TEMPSREAD read: {}",
                raws[10],
                row.temps_read.is_some()
            ),
            other => format!("{other:?}"),
        });
        // After round 1 the line loses a byte of the next reply; after round 3, a byte of
        // the next read frame; after round 5, two (its set byte is left, read as a length).
        let fault = match round.number {
            1 => Some("drop-serial 1 to-host"),
            3 => Some("drop-serial 1 to-master"),
            5 => Some("drop-serial 2 to-master"),
            _ => None,
        };
        if let Some(fault) = fault {
            twin::control::send(&control, fault).expect("the twin takes the fault");
        }
        Ok(())
    })
    .expect("the watch goes on past single lost bytes");
    assert_eq!(
        seen,
        [
            "EXCEPTIONDATA 0x0002, TEMPSREAD read: true",
            "Lost",
            "EXCEPTIONDATA 0x0002, TEMPSREAD read: true",
            "Lost",
            "EXCEPTIONDATA 0x0002, TEMPSREAD read: true",
            "Lost",
            "EXCEPTIONDATA 0x0002, TEMPSREAD read: true"
        ],
        "the master stays in its boot exception (type 2) throughout, and the scratch set \
         holding TEMPSREAD is configured again after each probe"
    );
    let status = twin::control::send(&control, "status").unwrap();
    assert!(
        status.contains("serial bytes lost: 3 to master, 1 to host (0 and 0 pending)"),
        "{status}"
    );
    drop(port);
    twin.finish();
}

/// Runs hostctl with `args` against `twin`'s port, as the binary would (text unless the
/// args say `--json`, no terminal); returns its result and what it printed.
fn hostctl_on(twin: &Linked, args: &[&str]) -> (Result<(), hostctl::HostError>, String) {
    use clap::Parser;
    let line = ["hostctl", "--port", twin.port.as_str()]
        .into_iter()
        .chain(args.iter().copied());
    let cli = hostctl::Cli::try_parse_from(line).expect("a valid command line");
    let style = hostctl::Style {
        json: cli.json,
        in_place: false,
        width: || None,
    };
    let mut out = Vec::new();
    let open = |p: &str| hostctl::link::open_serial(p, Duration::ZERO);
    let result = hostctl::run(&cli, None, open, style, &mut out);
    (result, String::from_utf8_lossy(&out).into_owned())
}

#[test]
fn hostctl_s_advice_for_a_silent_controller_names_the_twin_it_is_talking_to() {
    let twin = Linked::start("twin-pty-advice");
    twin::control::send(&twin.control, "cut 4").expect("the twin cuts controller 4 off");
    let (result, _) = hostctl_on(&twin, &["write", "4", "drive_reqspeed", "0"]);
    let err = result.expect_err("controller 4 is off the bus").to_string();
    // The twin is not at the default link, so the advice says which twin to restore it on.
    let advice = format!(
        "(on the twin: `twin inject --link {} restore 4`)",
        twin.port
    );
    assert!(
        err.starts_with("device 4 refused the write to REGDS_DRIVE_REQSPEED: code 0x8c")
            && err.contains(&advice),
        "{err}"
    );
    // `twin inject --link PORT` reaches the socket next to PORT: this twin's.
    let socket = twin::paths::control_of(std::path::Path::new(&twin.port));
    let reply = twin::control::send(&socket, "restore 4").unwrap();
    assert!(!reply.starts_with("error"), "{reply}");
    twin.finish();
}

/// Runs the Python client of `examples/python`: a PC program written from the reference
/// alone, with its own tables, float32 mapping and frames, sharing no code with this
/// project. Returns its stdout; fails the test with its stderr if it fails.
fn python_client(args: &[&str]) -> String {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/python/rover_client.py"
    );
    let out = std::process::Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 runs (every machine this project sets up has it)");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "the client failed: {stderr}");
    String::from_utf8(out.stdout).expect("the client prints text")
}

#[test]
fn the_python_client_builds_the_reference_s_frames() {
    // Reference §4.3 (read sets via pair 0 and the master), §8.3 (calibrate() for wheel
    // 1; its lift's first send is §8.2's default block with the §8.3 calibration, as the
    // steer's first send is), §8.5 (resetExceptions() for pair 1) and §4.5 (demands).
    let expected = "\
init 1: 17 14 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27
init 2: 17 24 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27
init 3: 15 34 01 01 02 03 05 10 11 12 13 14 15 16 22 23 24 25 26 27 28
init 0: 0e 04 02 01 02 03 04 05 06 07 08 09 0a 0b
drive: 19 12 08 0a 41 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f ff 7f 18 fe 19 05
steer 1st: 1d 12 0a 1b 00 00 1c 00 00 1d ff 7f 1e 00 00 1f 00 00 20 8f 02 2a 43 2b c4 28 fe 29 05
steer 2nd: 1d 12 0a 1b 00 00 1c 32 33 1d ff 7f 1e cc 4c 1f 31 f3 20 ff 7f 2a 43 2b c4 28 fe 29 02
lift 1st: 1d 32 0a 0a 00 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f 8f 02 17 0b 18 f2 19 fe 1a 05
lift 2nd: 1d 32 0a 0a 00 00 0b ff 7f 0c ff 7f 0d cc 0c 0e 64 e6 0f ff 7f 17 0b 18 f2 19 fe 1a 05
reset 4: 05 42 01 00 01
reset 5: 05 52 01 00 01
reset 6: 05 62 01 00 01
reset 0: 05 02 01 00 01
drive 1 1000: 06 12 01 09 fe 9f
drive 1 0: 06 12 01 09 ff 7f
steer 1 40: 06 12 01 1a 98 99
lift 1 20: 06 32 01 09 cb 8c
lift 2 20: 06 32 01 1b cb 8c
read master: 03 03 02
";
    assert_eq!(python_client(&["--print-frames"]), expected);
}

#[test]
fn the_python_client_maps_values_as_the_reference_s_float32_examples() {
    // Reference §3's worked examples (raw value, and the value the board unmaps), then
    // raw values above F; 5000 is clamped to the range. The integer parameters
    // (OVERCURRENTTHRESH) are truncated on the board after this unmapping.
    let expected = "\
DRIVE_REQSPEED 1000 -> 0x9ffe -> 999.908203
DRIVE_REQSPEED 0 -> 0x7fff -> 0.000000
DRIVE_REQSPEED -1000 -> 0x5fff -> -1000.030518
DRIVE_REQSPEED -4000 -> 0x0000 -> -4000.000000
DRIVE_REQSPEED 4000 -> 0xfffe -> 4000.000000
DRIVE_REQSPEED 1300 -> 0xa998 -> 1299.966309
DRIVE_REQSPEED 5000 -> 0xfffe -> 4000.000000
STEER_REQPOS 40 -> 0x9998 -> 39.997559
STEER_REQPOS -40 -> 0x6665 -> -40.003662
STEER_CALIBMIN -56 -> 0x0043 -> -56.692913
STEER_CALIBMIN 66 -> 0x00c4 -> 65.196854
DRIVE_PGAIN 0.01 -> 0x0041 -> 0.009919
STEER_IGAIN 2 -> 0x3332 -> 1.999878
INTEGRALDECAY 0.95 -> 0xf331 -> 0.949995
INTEGRALDECAY 0.9 -> 0xe664 -> 0.899991
INTEGRALCAP 300 -> 0x4ccc -> 299.996948
INTEGRALCAP 50 -> 0x0ccc -> 49.989319
OVERCURRENTTHRESH 500 -> 0x7fff -> 500.000000
OVERCURRENTTHRESH 200 -> 0x3332 -> 199.987793
OVERCURRENTTHRESH 10 -> 0x028f -> 9.994812
STALLCHECK 255 -> 0x00fe -> 255.000000
DEADZONE 1 -> 0x0005 -> 0.984252
DEADZONE 0.5 -> 0x0002 -> 0.393701
TEMP1 0.0 -> 0x2aaa -> -0.000610
TEMP1 21.5 -> 0x5887 -> 21.498459
DRIVE_REQSPEED raw 0xffff -> 4000.122070
STALLCHECK raw 0x00ff -> 256.003937
STEER_CALIBMIN raw 0x00ff -> 120.944885
";
    assert_eq!(python_client(&["--print-mapping"]), expected);
}

/// The numbers after `speed`, `steer` and `lift` on a client's `wheel W…:` line.
fn client_wheel(line: &str) -> [f64; 3] {
    let words: Vec<&str> = line.split([' ', ',']).filter(|w| !w.is_empty()).collect();
    ["speed", "steer", "lift"].map(|name| {
        let at = words.iter().position(|w| *w == name).expect(name);
        words[at + 1].parse().expect("a number")
    })
}

#[test]
fn a_python_program_written_from_the_reference_drives_the_twin() {
    let twin = Linked::start("twin-pty-python");
    // Open, banner, read sets, calibrate(), resetExceptions(), all drives to 1000, wheel
    // 1 steered to 40 and lifted to 20, update() until every demand holds for 10 updates,
    // then every drive to 0 until the wheels stop; its timeout is wall time, generous for
    // a loaded machine.
    let report = python_client(&["--port", &twin.port, "--timeout", "120"]);
    let line = |prefix: &str| {
        report
            .lines()
            .find_map(|l| l.strip_prefix(prefix))
            .unwrap_or_else(|| panic!("no {prefix:?} line in:\n{report}"))
    };
    assert!(line("banner: ").ends_with("| Ready"), "{report}");
    // The client's own checks: every demand met (drives within 5 %, positions within
    // 2°) for 10 updates in a row, and every drive then below 20 ticks/s.
    assert_eq!(line("settled: "), "yes", "{report}");
    assert_eq!(line("stopped: "), "yes", "{report}");
    assert_eq!(line("exceptions: "), "none", "{report}");
    // Checked here, not by the client: the twin's wheels did what the demands asked,
    // and what the boards told the program is where the wheels are. The positions stay
    // after the close resets the boards (nothing moves an unpowered gearmotor).
    let physical = wheel_states(&twin.control);
    assert_eq!(physical.len(), 6);
    for (wheel, [speed, steer, lift]) in (1..=6u8).zip(physical) {
        let (want_steer, want_lift) = if wheel == 1 { (40.0, 20.0) } else { (0.0, 0.0) };
        let state = format!("wheel {wheel}: {speed} ticks/s, {steer}°, {lift}°");
        assert!((steer - want_steer).abs() <= 2.0, "{state}\n{report}");
        assert!((lift - want_lift).abs() <= 2.0, "{state}\n{report}");
        assert!(speed.abs() < 50.0, "stopped: {state}\n{report}");
        let [_, told_steer, told_lift] = client_wheel(line(&format!("wheel {wheel} after stop: ")));
        assert!((steer - told_steer).abs() <= 1.0, "{state}\n{report}");
        assert!((lift - told_lift).abs() <= 1.0, "{state}\n{report}");
    }
    twin.finish();
}

#[test]
fn a_run_that_ends_with_a_board_faulted_says_which_wheel_and_fails() {
    let twin = Linked::start("twin-pty-faulted-run");
    // 8 A on wheel 3's drive sense (controller 4, motor 0) for the whole run: once the
    // script's `reset` takes the board out of its boot state, it raises SHORTOC (a current
    // above the threshold at a duty of 250 or less); the master's ping spreads it.
    twin::control::send(&twin.control, "spike 3 drive 8 20000").expect("the twin takes it");
    let dir = std::env::temp_dir().join(format!("faulted-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("faulted.rover");
    std::fs::write(&script, "calibrate\nreset\nwait 5\n").unwrap();
    let (result, text) = hostctl_on(&twin, &["--json", "run", &script.display().to_string()]);
    let err = result.expect_err("the rover ends stopped");
    let short = "short (overcurrent at a duty of 250 or less: a short, or a blocked motor)";
    match &err {
        hostctl::HostError::EndedInException { faults, .. } => assert_eq!(
            faults,
            &[
                format!("controller 4: {short}, motor 0 (wheel 3's drive)"),
                "controllers 1, 2, 3, 5, 6, 7, 8, 9: remote (EXCEPTIONDATA written: another \
                 board's fault spread by the master, or a PC), the whole board"
                    .to_owned(),
                format!("master: {short} on controller 4, motor 0 (wheel 3's drive)"),
            ]
        ),
        other => panic!("not the end state: {other}"),
    }
    assert_eq!(hostctl::exit_status(&err), std::process::ExitCode::from(3));
    // The last view, for a program: each motor with its board's exception taken apart (the
    // short names wheel 3's drive, and stops its steer too), the spread one on every other
    // wheel, the master's state beside them.
    let view = text
        .lines()
        .rfind(|l| l.contains("\"wheels\""))
        .expect("a view");
    let wheel = |n: u8| {
        let from = view
            .find(&format!(r#"{{"wheel":{n},"#))
            .expect("the wheel's object");
        let to = view[from + 1..]
            .find(r#"{"wheel":"#)
            .map_or(view.len(), |i| from + 1 + i);
        &view[from..to]
    };
    let shortoc = format!(
        r#""exception":{{"type":8,"name":"SHORTOC","motor":0,"wheel":3,"wheel_motor":"drive","text":"{short}, motor 0 (wheel 3's drive)"}}"#
    );
    assert_eq!(
        wheel(3).matches(&shortoc).count(),
        2,
        "drive and steer: {}",
        wheel(3)
    );
    for n in [1, 2, 4, 5, 6] {
        assert_eq!(
            wheel(n)
                .matches(r#""exception":{"type":3,"name":"REMOTESLAVE","#)
                .count(),
            3,
            "wheel {n}'s three motors: {}",
            wheel(n)
        );
    }
    assert!(
        view.contains(
            r#""master_state":{"exception":{"type":8,"name":"SHORTOC","controller":4,"motor":0,"wheel":3,"wheel_motor":"drive""#
        ),
        "{view}"
    );
    // And the failure as the last line, with what held the rover stopped.
    let last = text.lines().last().unwrap_or_default();
    assert!(
        last.starts_with(r#"{"command":"run","error":""#)
            && last.contains(&format!(r#""faults":["controller 4: {short}, motor 0"#)),
        "{last}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    twin.finish();
}

/// Steps `server` through `ms` of emulated time, then takes what the host side can read.
fn step_and_read(server: &mut Server, port: &mut std::fs::File, ms: u64) -> Vec<u8> {
    use std::io::Read;
    let mut got = Vec::new();
    for _ in 0..ms {
        server.step().expect("the twin steps");
        let mut buf = [0u8; 256];
        loop {
            match port.read(&mut buf) {
                Ok(n) if n > 0 => got.extend_from_slice(&buf[..n]),
                _ => break,
            }
        }
    }
    got
}

#[test]
fn bytes_a_program_wrote_before_closing_never_reach_the_next_session() {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let rover = Rover::new().expect("the twin builds (run scripts/firmware.sh)");
    let pty = Pty::open().expect("a pty");
    let path = pty.path().to_path_buf();
    let mut server = Server::new(rover, pty, None, false);
    let open = || {
        std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(nix::libc::O_NONBLOCK)
            .open(&path)
            .expect("the pty opens")
    };
    // A program opens the port, writes REGMASTER_PCTIMEOUT = 300 (the PC-silence failsafe)
    // and closes it, HUPCL set, before the twin looks: its bytes wait in the pty.
    let mut first = open();
    first
        .write_all(&[0x06, 0x02, 0x01, 0x0f, 0x2c, 0x01])
        .unwrap();
    drop(first);
    // The next program opens the port: the banner, and nothing after it.
    let mut next = open();
    let banner = step_and_read(&mut server, &mut next, 2_000);
    let text = String::from_utf8_lossy(&banner);
    assert!(text.ends_with("Ready\r\n"), "{text:?}");
    // PCTIMEOUT (master register 15) reads as its boot value 0, through read set 7.
    next.write_all(&[0x04, 0x04, 0x07, 0x0f]).unwrap();
    assert_eq!(step_and_read(&mut server, &mut next, 20), [0x01]);
    next.write_all(&[0x03, 0x03, 0x07]).unwrap();
    assert_eq!(
        step_and_read(&mut server, &mut next, 20),
        [0x00, 0x00],
        "the failsafe is off: the old program's write died with its session"
    );
}
