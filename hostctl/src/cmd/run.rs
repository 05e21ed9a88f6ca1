//! `hostctl run FILE`: a script of rover commands over one connection.
//!
//! Opening the port resets the master (the Uno's auto-reset, which the twin copies), so a
//! sequence that must act on one boot of the rover — reset the exceptions, calibrate,
//! drive — belongs in one session. `run` connects once, configures read sets 0, 1 and 2 as
//! the original library's init() does, then runs the script line by line (see
//! [`super::script`] for the language), printing each line as it starts. `wait` and
//! `watch` poll update() and show the live view: required against actual speed and
//! position per wheel, redrawn in place on a terminal. The script's first write waits until
//! [`WATCH_FROM`] after the master's banner, when the master watches every controller.
//!
//! With `--json` every printed thing is one JSON object per line, each with
//! `"command":"run"`: the start (`script`, `lines`), each line as it starts (`line`,
//! `text`), what a `say` line says (`line`, `say`), and each view (`line`, `elapsed_s`
//! since the line began, taken as the view's update() round ends, `updates`, `rate`,
//! `wheels` with required (null: none sent this session), actual,
//! calibrated, `at_limit` ("lower" or "upper", only when actual reads at its range's end,
//! which holds any value beyond it) and `exception` per motor (its board's, taken apart: type, name, the motor
//! it names and that motor's wheel, text; null: none; a board in exception stops both its
//! motors) and the wheel's exceptions in words (null: none),
//! `master_exception` (the raw value; null when its reply was lost), `no_answer` (the
//! controllers that did not answer), `reply_lost` (the devices whose reply the serial line
//! lost; each is read again next update), `master` (the text view's master line),
//! `master_state` (its `exception` taken apart and `temperatures`: `ambient` and nine
//! `boards` in °C, null for no reading; null when its reply was lost) and, after `show` lines,
//! `shown` (per set, `device` and its `values`: null when the controller did not answer, or
//! with `reply_lost` when the line lost the reply; an EXCEPTIONDATA value also comes taken
//! apart as `exception`). A failure ends the output with `error` (see [`crate::run_with`]).
//!
//! `--pairs` takes the fitted wheel pairs as a list of pair numbers (e.g. `0,2`), kept as
//! the library's init() mask (see [`super::pc::Pairs`]).

use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use shared::regs::{id, Register};

use super::fresh;
use super::hold::{in_remote_exception, release, running, Frozen, Thaw};
use super::live::{
    actual, actual_limit, master_json, master_line, raised, slave_exception, view_lines,
    wheel_exceptions, Dropped, Poller, Snapshot, NOT_DEGREES,
};
use super::pc::{self, Motor, Op, Pairs, Pc};
use super::script::{self, Action, Line};
use super::{configure, set_frame, Reading, SetRead};
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::meaning::Meaning;
use crate::port::Port;
use crate::resolve;
use crate::table::Screen;

/// Arguments of `run`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The script, e.g. examples/demo.rover (`-` reads it from standard input).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// The wheel pairs fitted, as a list of pair numbers (not the library's init() mask,
    /// which sets bit p for pair p): pair p is wheels 2p+1 and 2p+2 on controllers
    /// 3p+1..3p+3 (e.g. `--pairs 0` for a bench with the rear pair, wheels 1 and 2).
    /// Only these are polled, and `all`, calibrate, reset, stop and turn reach only them.
    #[arg(long, value_name = "P,…", default_value = "0,1,2")]
    pub pairs: String,
}

/// A checked script.
#[derive(Debug)]
pub struct Plan {
    /// The script's path, for messages.
    pub path: String,
    /// Its lines, checked, with their frames.
    pub lines: Vec<Line>,
    /// The pairs fitted.
    pub pairs: Pairs,
    /// How long after the master's banner the run starts (the `--settle-ms` waited), so
    /// that its first write waits for the master's watch ([`WATCH_FROM`]).
    pub settled: Duration,
}

/// How long after the master's banner a run's first write waits: the master pings every
/// controller, arming each one's own bus-silence stop, and starts finding the ones that
/// drop off, from 5 s after its boot (reference §5; the banner comes about 0.3 s after the
/// boot, so the first ping round is over by then). A board driven before then and lost
/// before its first ping would keep its demand, out of anyone's reach.
pub const WATCH_FROM: Duration = Duration::from_millis(shared::master::ping::BOOT_SETTLE_MS as u64);

/// A script's bytes as text, or why they are not UTF-8 and how to fix it.
fn script_text(bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        if bytes.starts_with(&[0xff, 0xfe]) || bytes.starts_with(&[0xfe, 0xff]) {
            return "the script is UTF-16 (what some editors call \"Unicode\"); save it as \
                    UTF-8"
                .to_owned();
        }
        let at = e.utf8_error().valid_up_to();
        let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
        format!(
            "line {line} is not UTF-8 (byte {:#04x}; an editor's Latin-1 or Windows-1252 \
             `°` or `é`?); save the script as UTF-8",
            bytes[at]
        )
    })
}

/// Reads and checks the script; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let pairs = Pairs::parse(&args.pairs)?;
    let stdin = args.file.as_os_str() == "-";
    let path = if stdin {
        "standard input".to_owned()
    } else {
        args.file.display().to_string()
    };
    let bytes = if stdin {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut bytes).map(|_| bytes)
    } else {
        std::fs::read(&args.file)
    };
    let bytes = bytes.map_err(|source| HostError::ScriptFile {
        path: path.clone(),
        source,
    })?;
    let source = script_text(bytes).map_err(|why| HostError::ScriptForm {
        path: path.clone(),
        why,
    })?;
    let lines = script::parse_for(&path, &source, pairs)?;
    Ok(Plan {
        path,
        lines,
        pairs,
        settled: Duration::ZERO,
    })
}

/// Time as the script sees it: the wall clock, or a fake one in tests.
pub trait Clock {
    /// Time since the clock started.
    fn now(&self) -> Duration;
    /// Lets `d` pass.
    fn sleep(&mut self, d: Duration);
    /// The signal that asked the script to stop (Ctrl-C or SIGTERM, [`crate::interrupt`]).
    fn interrupted_by(&self) -> Option<i32> {
        crate::interrupt::caught()
    }
    /// Whether the script has been asked to stop.
    fn interrupted(&self) -> bool {
        self.interrupted_by().is_some()
    }
}

/// The error for a script that `signal` stopped `at` (e.g. "during line 3 (`wait 30`)"),
/// with the port open.
fn stopped(signal: i32, at: String, line: Option<&Line>) -> HostError {
    HostError::Interrupted {
        signal,
        at: at + crate::interrupt::CLOSES,
        line: line.map(|l| l.number),
    }
}

/// How a message names `line`.
fn line_words(line: &Line) -> String {
    format!("line {} (`{}`)", line.number, line.text)
}

/// The wall clock.
pub struct WallClock(Instant);

impl WallClock {
    /// A clock starting now.
    pub fn new() -> WallClock {
        WallClock(Instant::now())
    }
}

impl Default for WallClock {
    fn default() -> Self {
        WallClock::new()
    }
}

impl Clock for WallClock {
    fn now(&self) -> Duration {
        self.0.elapsed()
    }

    fn sleep(&mut self, d: Duration) {
        std::thread::sleep(d);
    }
}

/// Pause between two update() calls while the view is live: the library's operator tick.
pub const TICK: Duration = Duration::from_millis(10);
/// How often the in-place view is redrawn.
pub const REDRAW: Duration = Duration::from_millis(200);
/// The pause before each write that takes a board out of its exception: two of the
/// board's 1-ms ticks, so that no demand sent before it reaches the board in the reset's
/// tick (see the note where it is used).
pub const RESET_GAP: Duration = Duration::from_millis(2);

/// Where the output goes and how.
pub struct Output<'a> {
    /// The stream.
    pub out: &'a mut dyn Write,
    /// Redraw the live view in place (a terminal).
    pub in_place: bool,
    /// JSON lines instead of text.
    pub json: bool,
    /// The terminal's width, asked at each redraw.
    pub width: fn() -> Option<usize>,
}

/// Runs the script over a connected link.
pub fn run<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    clock: &mut dyn Clock,
    output: &mut Output<'_>,
) -> Result<(), HostError> {
    let start = clock.now();
    let poller = Poller::for_pairs(plan.pairs)?;
    poller.configure(link)?;
    let mut session = Session::default();
    if output.json {
        let start = event()
            .str("script", &plan.path)
            .int("lines", i64::try_from(plan.lines.len()).unwrap_or(i64::MAX));
        writeln!(output.out, "{}", start.finish()).map_err(HostError::Output)?;
    } else {
        writeln!(
            output.out,
            "{}: {} lines; read sets 0, 1, 2 configured",
            plan.path,
            plan.lines.len()
        )?;
    }
    for note in script::notes(&plan.lines) {
        if output.json {
            writeln!(output.out, "{}", event().str("note", &note).finish())
                .map_err(HostError::Output)?;
        } else {
            writeln!(output.out, "note: {note}").map_err(HostError::Output)?;
        }
    }
    let mut watched = false;
    for line in &plan.lines {
        if !watched
            && line
                .actions
                .iter()
                .any(|a| matches!(a, Action::Op(Op::Write(_))))
        {
            watched = true;
            let since_banner = plan.settled + clock.now().saturating_sub(start);
            wait_for_the_watch(since_banner, clock, output)?;
        }
        if let Some(signal) = clock.interrupted_by() {
            let at = format!("before {} ran", line_words(line));
            return Err(stopped(signal, at, Some(line)));
        }
        // A `say` line speaks for itself; every other line is echoed as it starts.
        if !matches!(line.actions.as_slice(), [Action::Say(_)]) {
            if output.json {
                let echo = event().int("line", number(line)).str("text", &line.text);
                writeln!(output.out, "{}", echo.finish()).map_err(HostError::Output)?;
            } else {
                writeln!(output.out, "> {}", line.text).map_err(HostError::Output)?;
            }
            output.out.flush().map_err(HostError::Output)?;
        }
        // The view shows the demands as they stand after this line.
        run_line(line, link, clock, &poller, &mut session, output).map_err(|source| {
            if let HostError::Interrupted { .. } = source {
                return source;
            }
            HostError::ScriptStep {
                path: plan.path.clone(),
                line: line.number,
                text: line.text.clone(),
                source: Box::new(source),
            }
        })?;
    }
    // A signal during the last line's actions (only a view ends early).
    if let Some(signal) = clock.interrupted_by() {
        let at = "after the script's last line ran".to_string();
        return Err(stopped(signal, at, None));
    }
    ended_in_exception(plan, link, &poller, session)
}

/// Holds the first write until [`WATCH_FROM`] after the master's banner, saying why.
fn wait_for_the_watch(
    since_banner: Duration,
    clock: &mut dyn Clock,
    output: &mut Output<'_>,
) -> Result<(), HostError> {
    let left = WATCH_FROM.saturating_sub(since_banner);
    if left.is_zero() || clock.interrupted() {
        return Ok(());
    }
    let note = format!(
        "waiting {:.1} s before the first write: the master starts watching the controllers \
         5 s after its boot (from then a controller that drops off stops every motor)",
        left.as_secs_f64()
    );
    if output.json {
        writeln!(output.out, "{}", event().str("note", &note).finish())
    } else {
        writeln!(output.out, "note: {note}")
    }
    .map_err(HostError::Output)?;
    output.out.flush().map_err(HostError::Output)?;
    sleep_unless_interrupted(clock, left);
    Ok(())
}

/// Lets `d` pass on `clock`, in slices, ending early once Ctrl-C is pressed.
pub fn sleep_unless_interrupted(clock: &mut dyn Clock, d: Duration) {
    let until = clock.now() + d;
    while !clock.interrupted() {
        let now = clock.now();
        if now >= until {
            break;
        }
        clock.sleep((until - now).min(REDRAW));
    }
}

/// The run's outcome once every line is done: an error when the rover ends in an exception
/// (other than its boot state; see [`raised`]), so a program running the script learns of
/// it from the exit status. Judged on the last view's update(), or on a fresh one when
/// frames went out after it; a script with no view is not judged.
fn ended_in_exception<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    poller: &Poller,
    session: Session,
) -> Result<(), HostError> {
    let Some(last) = session.last else {
        return Ok(());
    };
    let mut dropped = session.dropped;
    let end = match plan.lines.last() {
        Some(line) if session.sent_since_last => {
            let end = poller.update(link)?;
            dropped.note(&end, &line.pc);
            end
        }
        _ => last,
    };
    let faults = raised(&end, &dropped);
    if faults.is_empty() {
        Ok(())
    } else {
        Err(HostError::EndedInException {
            path: plan.path.clone(),
            faults,
        })
    }
}

/// Runs one line's actions. A write the master refuses (it answered, so the link works)
/// does not stop the line's other writes: a `stop` must reach every board it can, as the
/// master itself sends a frame's other writes after a refused one. The line fails after
/// them, naming what was refused; anything else (a timeout, a dead port) stops at once.
fn run_line<P: Port>(
    line: &Line,
    link: &mut Link<P>,
    clock: &mut dyn Clock,
    poller: &Poller,
    session: &mut Session,
    output: &mut Output<'_>,
) -> Result<(), HostError> {
    let writes = line
        .actions
        .iter()
        .filter(|a| matches!(a, Action::Op(Op::Write(_))))
        .count();
    let mut refused = 0;
    let mut first = None;
    for action in &line.actions {
        if first.is_some() && !matches!(action, Action::Op(_)) {
            break;
        }
        match act(action, link, clock, poller, line, session, output) {
            Err(e @ HostError::WriteRefused { .. }) => {
                refused += 1;
                first.get_or_insert(e);
            }
            other => other?,
        }
    }
    match first {
        None => Ok(()),
        Some(first) if writes == 1 => Err(first),
        Some(first) => Err(HostError::WritesRefused {
            refused,
            writes,
            first: Box::new(first),
        }),
    }
}

/// What a run keeps from line to line.
#[derive(Default)]
struct Session {
    /// Demands the boards dropped in an exception, as the views saw it happen.
    dropped: Dropped,
    /// The read sets `show` lines configured, read at every update of a view.
    shown: Vec<SetRead>,
    /// The last update() a view took.
    last: Option<Snapshot>,
    /// Whether a write went out after it.
    sent_since_last: bool,
    /// The controllers a `calibrate` stopped while it runs ([`Action::Freeze`]).
    frozen: Frozen,
}

/// The values of the `show` sets at one update: each set's device and its registers with
/// their raw values, or why there are none ([`Reading::NoAnswer`], [`Reading::Lost`]).
type Shown = Vec<(u8, Result<Vec<(&'static Register, u16)>, Reading>)>;

/// Reads every `show` set.
fn read_shown<P: Port>(session: &Session, link: &mut Link<P>) -> Result<Shown, HostError> {
    session
        .shown
        .iter()
        .map(|read| {
            let values = match read.read_for_view(link)? {
                Reading::Values(raws) => Ok(read.regs.iter().copied().zip(raws).collect()),
                missing => Err(missing),
            };
            Ok((read.target.device, values))
        })
        .collect()
}

/// Whether `reg` of `device` is an angle on a pot calibration that is not its wheel's (see
/// [`Pc::calibrated`]); `None` when it is no such angle.
fn off_calibration(pc: &Pc, dropped: &Dropped, device: u8, reg: &Register) -> Option<bool> {
    if !fresh::on_calibrated_scale(reg) {
        return None;
    }
    let (wheel, motor) = pc::position_motor(device, reg)?;
    Some(!dropped.calibrated(pc, wheel, motor))
}

/// The `show` values as text: a line per set, angles off the wheel's calibration marked
/// `*` as in the view, with the legend after them when the view has not given it.
fn shown_lines(
    shown: &Shown,
    s: &Snapshot,
    pc: &Pc,
    dropped: &Dropped,
    view: &[String],
) -> Vec<String> {
    let mut marked = false;
    let mut lines: Vec<String> = shown
        .iter()
        .map(|(device, values)| {
            let values = match values {
                Ok(values) => values,
                Err(Reading::Lost) => {
                    return format!(
                        "device {device}: reply lost on the serial line (read again next update)"
                    )
                }
                Err(_) => return format!("device {device}: no answer"),
            };
            let cells: Vec<String> = values
                .iter()
                .map(|&(reg, raw)| {
                    if s.no_reading(*device, reg.id) {
                        return format!("{} - (no reading)", reg.short_name());
                    }
                    let mark = if off_calibration(pc, dropped, *device, reg) == Some(true) {
                        marked = true;
                        "*"
                    } else {
                        ""
                    };
                    let words = Meaning::of(*device, reg, raw)
                        .map(|m| format!(" ({})", m.words()))
                        .unwrap_or_default();
                    format!(
                        "{} {}{}{mark}{words}",
                        reg.short_name(),
                        resolve::show(reg, raw),
                        resolve::unit_suffix(reg)
                    )
                })
                .collect();
            format!("device {device}: {}", cells.join(", "))
        })
        .collect();
    if marked && !view.iter().any(|l| l == NOT_DEGREES) {
        lines.push(NOT_DEGREES.to_owned());
    }
    lines
}

/// The `show` values as a JSON array (`value` null for no reading; `calibrated` for an
/// angle through a pot calibration, false when it is not the wheel's).
fn shown_json(shown: &Shown, s: &Snapshot, pc: &Pc, dropped: &Dropped) -> String {
    json::array(shown.iter().map(|(device, values)| {
        let values = match values {
            Ok(values) => values,
            Err(missing) => {
                let object = json::Object::new()
                    .int("device", *device)
                    .raw("values", "null");
                return match missing {
                    Reading::Lost => object.bool("reply_lost", true),
                    _ => object.bool("no_answer", true),
                }
                .finish();
            }
        };
        let values = json::array(values.iter().map(|&(reg, raw)| {
            let calibrated =
                off_calibration(pc, dropped, *device, reg).map(|off| ("calibrated", !off));
            fresh::value_json(
                json::Object::new(),
                *device,
                reg,
                raw,
                s.no_reading(*device, reg.id),
                calibrated,
            )
            .finish()
        }));
        json::Object::new()
            .int("device", *device)
            .raw("values", &values)
            .finish()
    }))
}

/// A JSON line of `run`, its members still to come.
fn event() -> json::Object {
    json::Object::new().str("command", "run")
}

/// A line's number as a JSON integer.
fn number(line: &Line) -> i64 {
    i64::try_from(line.number).unwrap_or(i64::MAX)
}

/// The live view as one JSON object: required against actual per wheel and motor (actual
/// `null` when not read), and the master's EXCEPTIONDATA.
fn view_json(
    s: &Snapshot,
    line: &Line,
    dropped: &Dropped,
    shown: &Shown,
    elapsed: Duration,
    updates: u64,
    rate: f64,
) -> String {
    let wheels = json::array(line.pc.pairs().wheels().map(|wheel| {
        // `calibrated` false: a position on a pot scale that is not the wheel's, not degrees
        // (see `Pc::calibrated`).
        let motor = |m: Motor| {
            let required = json::Object::new()
                .num("required", line.pc.demand(wheel, m).unwrap_or(f32::NAN))
                .num("actual", actual(s, wheel, m).unwrap_or(f32::NAN))
                .bool("calibrated", dropped.calibrated(&line.pc, wheel, m));
            // A reading at its range's end holds any value beyond it, as `read --json` says.
            let required = match actual_limit(s, wheel, m) {
                Some(limit) => required.str("at_limit", limit.name()),
                None => required,
            };
            // An exception dropped the demand: the board no longer aims for it.
            let required = if line.pc.demand(wheel, m).is_some() && dropped.has(&line.pc, wheel, m)
            {
                required.bool("dropped", true)
            } else {
                required
            };
            // The exception its board is in, taken apart (null: none): a board in
            // exception stops both its motors, whichever one the exception names.
            match slave_exception(s, pc::device_of(wheel, m)) {
                Some(e) => required.raw("exception", &e.json()),
                None => required.raw("exception", "null"),
            }
            .finish()
        };
        let object = json::Object::new()
            .int("wheel", wheel)
            .raw("drive", &motor(Motor::Drive))
            .raw("steer", &motor(Motor::Steer))
            .raw("lift", &motor(Motor::Lift));
        // The exceptions in words, as the text view's column has them; null for none.
        match wheel_exceptions(s, wheel).as_str() {
            "-" => object.raw("exceptions", "null"),
            words => object.str("exceptions", words),
        }
        .finish()
    }));
    let exception = match s.raw(0, id::REGMASTER_EXCEPTIONDATA) {
        Some(raw) => raw.to_string(),
        None => "null".to_owned(),
    };
    let view = event()
        .int("line", number(line))
        .num("elapsed_s", to_the_ms(elapsed))
        .int("updates", i64::try_from(updates).unwrap_or(i64::MAX))
        .num("rate", rate as f32)
        .raw("wheels", &wheels)
        .raw("master_exception", &exception)
        .raw(
            "no_answer",
            &json::array(s.silent().iter().map(u8::to_string)),
        )
        .raw(
            "reply_lost",
            &json::array(s.lost().iter().map(u8::to_string)),
        )
        .str("master", &master_line(s))
        .raw("master_state", &master_json(s));
    // What `show` lines added, when there are any.
    if shown.is_empty() {
        view.finish()
    } else {
        view.raw("shown", &shown_json(shown, s, &line.pc, dropped))
            .finish()
    }
}

fn act<P: Port>(
    action: &Action,
    link: &mut Link<P>,
    clock: &mut dyn Clock,
    poller: &Poller,
    line: &Line,
    session: &mut Session,
    output: &mut Output<'_>,
) -> Result<(), HostError> {
    match action {
        Action::Show { target, regs, set } => {
            // A set an earlier line took holds these ids already (the script gives a set to
            // one id list only), and the master's table serves every device.
            if !session.shown.iter().any(|read| read.set == *set) {
                let frame = set_frame(*target, *set, regs)?;
                configure(link, *target, *set, &frame, regs.len())?;
            }
            // A line that repeats an earlier one's device and registers adds nothing.
            let shown = |read: &SetRead| read.set == *set && read.target.device == target.device;
            if !session.shown.iter().any(shown) {
                session
                    .shown
                    .push(SetRead::new(*target, *set, regs.clone())?);
            }
        }
        Action::Op(Op::Write(send)) => {
            if send.leaves_exception() {
                // A board takes the registers written in one 1-ms tick in id order,
                // REG_RESET first: a demand sent just before would count as sent after
                // the reset and be kept, where the view takes it as dropped.
                clock.sleep(RESET_GAP);
            }
            session.sent_since_last = true;
            let reply = link.transact(send.device, &send.frame, 1)?;
            let code = reply.first().copied().unwrap_or_default();
            if code != 0 {
                return Err(HostError::WriteRefused {
                    device: send.device,
                    register: send.what,
                    writes: send.writes(),
                    code,
                    words: super::reply_error(code)
                        .map(|e| e.describe().to_string())
                        .unwrap_or_else(|| "not a known error code".to_owned()),
                    inject: link.inject().clone(),
                });
            }
            session.dropped.note_sent(send, &line.pc);
        }
        Action::Op(Op::Pause(d)) => clock.sleep(*d),
        Action::Release => {
            let now = poller.update(link)?;
            session.dropped.note(&now, &line.pc);
            let remote = in_remote_exception(&now, line.pc.pairs());
            release(&remote, |reset| {
                act(reset, link, clock, poller, line, session, output)
            })?;
            let ignored = running(&now, line.pc.pairs());
            if !ignored.is_empty() {
                return Err(HostError::StopIgnored { devices: ignored });
            }
        }
        Action::Freeze => {
            let now = poller.update(link)?;
            session.dropped.note(&now, &line.pc);
            let mut frozen = Frozen::default();
            // A board whose state the line lost may be running: stopped too (a board in an
            // exception ignores the write), but never released, as it may have been in
            // REMOTESLAVE already.
            let unread = line.pc.pairs().devices().filter(|d| now.lost().contains(d));
            let stops = running(&now, line.pc.pairs())
                .into_iter()
                .map(|d| (d, false))
                .chain(unread.map(|d| (d, true)));
            for (device, unread) in stops {
                let stop = Action::Op(pc::bridge_off(device)?);
                act(&stop, link, clock, poller, line, session, output).map_err(|source| {
                    HostError::CalibrateNotHeld {
                        device,
                        source: Box::new(source),
                    }
                })?;
                if unread {
                    frozen.unread.push(device);
                } else {
                    frozen.stopped.push(device);
                }
                // Kept as it goes: the thaw must know of each board stopped so far.
                session.frozen = frozen.clone();
            }
        }
        Action::Thaw => {
            let frozen = std::mem::take(&mut session.frozen);
            if frozen.stopped.is_empty() && frozen.unread.is_empty() {
                return Ok(());
            }
            // Stopped by a signal: the boards stay stopped until the port closes.
            if let Some(signal) = clock.interrupted_by() {
                let at = format!(
                    "during {}, the boards it stopped for the calibration left stopped",
                    line_words(line)
                );
                return Err(stopped(signal, at, Some(line)));
            }
            let now = poller.update(link)?;
            session.dropped.note(&now, &line.pc);
            let thaw = Thaw::of(&frozen, &now, line.pc.pairs());
            let released = release(&thaw.release, |reset| {
                act(reset, link, clock, poller, line, session, output)
            });
            for note in &thaw.notes {
                say_note(note, line, output)?;
            }
            released?;
        }
        Action::Say(text) if output.json => {
            let say = event().int("line", number(line)).str("say", text);
            writeln!(output.out, "{}", say.finish()).map_err(HostError::Output)?;
        }
        Action::Say(text) => writeln!(output.out, "{text}").map_err(HostError::Output)?,
        Action::Live { time, every } => {
            live(*time, *every, link, clock, poller, line, session, output)?
        }
    }
    Ok(())
}

/// Prints a note of `line` as the run prints its other notes.
fn say_note(note: &str, line: &Line, output: &mut Output<'_>) -> Result<(), HostError> {
    if output.json {
        let event = event().int("line", number(line)).str("note", note);
        writeln!(output.out, "{}", event.finish())
    } else {
        writeln!(output.out, "note: {note}")
    }
    .map_err(HostError::Output)
}

/// Polls update() for `time`, showing the view: for `wait` (`every` None) redrawn in place
/// on a terminal, otherwise once at the end; for `watch` printed every `every` (a log; zero:
/// every update), and at the end.
#[allow(clippy::too_many_arguments)]
fn live<P: Port>(
    time: Duration,
    every: Option<Duration>,
    link: &mut Link<P>,
    clock: &mut dyn Clock,
    poller: &Poller,
    line: &Line,
    session: &mut Session,
    output: &mut Output<'_>,
) -> Result<(), HostError> {
    let start = clock.now();
    let log = every.is_some();
    let mut screen = Screen::new(output.in_place && !log, output.width);
    let mut updates = 0u64;
    let mut next_draw = start;
    let period = every.unwrap_or(REDRAW);
    // The newest view not drawn yet: a link that fails draws it before its error, so that
    // output sent to a file keeps the rover's last known state.
    let mut undrawn: Option<Frame> = None;
    loop {
        let polled = poller
            .update(link)
            .and_then(|snapshot| Ok((snapshot, read_shown(session, link)?)));
        let (snapshot, shown) = match polled {
            Ok(polled) => polled,
            Err(e) => {
                if let Some(frame) = undrawn.take() {
                    draw(&frame, log, line, session, output, &mut screen)?;
                }
                return Err(e);
            }
        };
        session.dropped.note(&snapshot, &line.pc);
        session.last = Some(snapshot.clone());
        session.sent_since_last = false;
        updates += 1;
        // Ctrl-C ends the view as its time would, drawn once more so that a file keeps it.
        let interrupted = clock.interrupted_by();
        let now = clock.now();
        let elapsed = now.saturating_sub(start);
        let done = elapsed >= time || interrupted.is_some();
        let frame = Frame {
            rate: updates as f64 / elapsed.as_secs_f64().max(1e-3),
            snapshot,
            shown,
            elapsed,
            updates,
        };
        let due = if log || output.in_place {
            now >= next_draw || done
        } else {
            done
        };
        if due {
            draw(&frame, log, line, session, output, &mut screen)?;
            next_draw = now + period;
            undrawn = None;
        } else {
            undrawn = Some(frame);
        }
        if let Some(signal) = interrupted {
            let at = format!(
                "during {}; the view above is the rover as it was then",
                line_words(line)
            );
            return Err(stopped(signal, at, Some(line)));
        }
        if done {
            return Ok(());
        }
        clock.sleep(TICK.min(time - elapsed));
    }
}

/// One update of a live view, ready to draw.
struct Frame {
    snapshot: Snapshot,
    shown: Shown,
    /// Since the view began.
    elapsed: Duration,
    /// Updates taken so far.
    updates: u64,
    /// Updates a second so far.
    rate: f64,
}

/// Draws `frame` as the output asks: a JSON line, a log block, or the screen redrawn.
fn draw(
    frame: &Frame,
    log: bool,
    line: &Line,
    session: &Session,
    output: &mut Output<'_>,
    screen: &mut Screen,
) -> Result<(), HostError> {
    let Frame {
        snapshot,
        shown,
        elapsed,
        updates,
        rate,
    } = frame;
    let dropped = &session.dropped;
    let text = if output.json {
        let mut t = view_json(snapshot, line, dropped, shown, *elapsed, *updates, *rate);
        t.push('\n');
        t
    } else {
        let mut lines = view_lines(snapshot, &line.pc, dropped, *elapsed, *updates, *rate);
        let shown_text = shown_lines(shown, snapshot, &line.pc, dropped, &lines);
        lines.extend(shown_text);
        if log {
            let mut t = lines.join("\n");
            t.push('\n');
            t
        } else {
            screen.frame(&lines)
        }
    };
    output
        .out
        .write_all(text.as_bytes())
        .map_err(HostError::Output)?;
    output.out.flush().map_err(HostError::Output)
}

/// Seconds to the nearest millisecond, for a view's `elapsed_s`: the views are some 45 ms
/// apart, and the ns below would print 1.817 s as 1.8169999.
fn to_the_ms(d: Duration) -> f32 {
    ((d.as_secs_f64() * 1000.0).round() / 1000.0) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::{CtrlCAt, FakeClock, FakePort};

    fn configure_replies() -> Vec<Vec<u8>> {
        (1..=9u8)
            .map(|d| vec![if d % 3 == 0 { 18 } else { 20 }])
            // The master's set: the library's eleven registers and REGMASTER_TEMPSREAD.
            .chain([vec![12]])
            .collect()
    }

    /// The replies of `init()`, then a first write refused with 0x8c (the slave did not
    /// acknowledge) and `accepted` writes answered 00.
    fn first_write_refused(accepted: usize) -> Vec<Vec<u8>> {
        let mut replies = configure_replies();
        replies.push(vec![0x8c]);
        replies.extend(std::iter::repeat_n(vec![0], accepted));
        replies
    }

    fn update_replies() -> Vec<Vec<u8>> {
        (1..=9u8)
            .map(|d| vec![0u8; if d % 3 == 0 { 36 } else { 40 }])
            .chain([vec![0u8; 24]])
            .collect()
    }

    /// update()'s replies with some controllers' STATUS and EXCEPTIONDATA set: (controller,
    /// STATUS, EXCEPTIONDATA); every other board reads running.
    fn update_with(states: &[(u8, u16, u16)]) -> Vec<Vec<u8>> {
        let mut now = update_replies();
        for &(device, status, data) in states {
            let row = &mut now[usize::from(device - 1)];
            row[4..6].copy_from_slice(&u16::to_le_bytes(status));
            row[6..8].copy_from_slice(&u16::to_le_bytes(data));
        }
        now
    }

    /// update()'s replies with every controller in its boot state (after the port opened).
    fn booted() -> Vec<Vec<u8>> {
        let boot: Vec<(u8, u16, u16)> = (1..=9).map(|d| (d, 0x01, 0x0502)).collect();
        update_with(&boot)
    }

    /// update()'s replies with every controller in REMOTESLAVE but those of `except`.
    fn remote_but(except: &[u8]) -> Vec<Vec<u8>> {
        let remote: Vec<(u8, u16, u16)> = (1..=9)
            .filter(|d| !except.contains(d))
            .map(|d| (d, 0x01, 0x0503))
            .collect();
        update_with(&remote)
    }

    /// The plan of a script `t.rover` holding `source`.
    fn plan(source: &str) -> Plan {
        plan_for(source, Pairs::ALL)
    }

    /// The same, for a rover with `pairs` fitted.
    fn plan_for(source: &str, pairs: Pairs) -> Plan {
        let lines = script::parse_for("t.rover", source, pairs).unwrap();
        Plan {
            path: "t.rover".into(),
            lines,
            pairs,
            settled: WATCH_FROM,
        }
    }

    /// What running a script over a fake port did.
    struct Ran {
        result: Result<(), HostError>,
        /// The frames sent, in hex.
        hex: Vec<String>,
        /// The pauses taken on the fake clock.
        pauses: Vec<Duration>,
        /// What was printed.
        text: String,
    }

    #[test]
    fn the_first_write_waits_for_the_masters_watch_of_the_controllers() {
        // Started 2 s after the banner: a `say` goes at once, the first write 3 s later.
        let mut early = plan("say hi\nwrite 1 drive_reqspeed 10\nwrite 1 drive_reqspeed 0\n");
        early.settled = Duration::from_secs(2);
        let mut replies = configure_replies();
        replies.extend([vec![0], vec![0]]);
        let ran = run_plan(&early, &replies, false);
        ran.result.unwrap();
        // One wait of 3 s, in slices that Ctrl-C can end.
        assert_eq!(ran.pauses, [REDRAW; 15]);
        let text: Vec<&str> = ran.text.lines().skip(1).collect();
        assert_eq!(
            text,
            [
                "hi",
                "note: waiting 3.0 s before the first write: the master starts watching the \
                 controllers 5 s after its boot (from then a controller that drops off stops \
                 every motor)",
                "> write 1 drive_reqspeed 10",
                "> write 1 drive_reqspeed 0",
            ]
        );
        assert_eq!(ran.hex.len(), 10 + 2, "the sets, then both writes");
        // Started late enough: no wait; and the same note as JSON.
        let ran = run_plan(&plan("write 1 drive_reqspeed 10\n"), &replies, false);
        assert!(ran.pauses.is_empty(), "{:?}", ran.pauses);
        early.settled = Duration::from_millis(4500);
        let ran = run_plan(&early, &replies, true);
        assert_eq!(ran.pauses, [REDRAW, REDRAW, Duration::from_millis(100)]);
        assert!(
            ran.text
                .contains("{\"command\":\"run\",\"note\":\"waiting 0.5 s before"),
            "{}",
            ran.text
        );
    }

    /// Runs `source` as `t.rover` against a fake port answering `replies`.
    fn run_script(source: &str, replies: &[Vec<u8>], json: bool) -> Ran {
        run_plan(&plan(source), replies, json)
    }

    /// Runs `plan` against a fake port answering `replies`.
    fn run_plan(plan: &Plan, replies: &[Vec<u8>], json: bool) -> Ran {
        // Ctrl-C never comes.
        run_interrupted(plan, replies, Duration::MAX, json)
    }

    /// [`run_plan`] with Ctrl-C at `at` on the fake clock.
    fn run_interrupted(plan: &Plan, replies: &[Vec<u8>], at: Duration, json: bool) -> Ran {
        run_on(plan, FakePort::with_replies(replies), at, json)
    }

    /// [`run_interrupted`] on `port`.
    fn run_on(plan: &Plan, mut port: FakePort, at: Duration, json: bool) -> Ran {
        let mut link = Link::ready(&mut port);
        let mut clock = CtrlCAt(FakeClock(Duration::ZERO, Vec::new()), at);
        let mut out = Vec::new();
        let mut output = Output {
            out: &mut out,
            in_place: false,
            json,
            width: || None,
        };
        let result = run(plan, &mut link, &mut clock, &mut output);
        Ran {
            result,
            hex: port.frames_hex(),
            pauses: clock.0 .1,
            text: String::from_utf8(out).unwrap(),
        }
    }

    #[test]
    fn a_stop_reaches_every_board_after_one_refuses_and_the_line_then_fails() {
        // Controller 1 refuses its first frame (0x8c: it did not acknowledge); the other 44
        // frames of the stop still go out, and the line fails naming the refusal.
        let ran = run_script("stop\nsay after\n", &first_write_refused(44), false);
        let stop_frames = &ran.hex[10..];
        assert_eq!(stop_frames.len(), 45, "{stop_frames:?}");
        // The last is wheel 6's lift demand: REQPOS 0 to controller 9 (TWO, id 27). No
        // update() and no release follow a refusal: the boards stay in exception.
        assert_eq!(stop_frames[44], "06 92 01 1b ff 7f");
        let message = ran.result.unwrap_err().to_string();
        assert!(
            message.starts_with(
                "t.rover line 1 (`stop`) failed: 1 of the line's 45 writes refused, the other 44 \
                 sent; the first: device 1 refused the write to REG_EXCEPTIONDATA"
            ),
            "{message}"
        );
        assert!(message.contains("code 0x8c"), "{message}");
        // The script stops there: the next line never runs.
        assert!(!ran.text.contains("after"), "{}", ran.text);
    }

    #[test]
    fn a_stop_turns_every_bridge_off_first_and_releases_the_boards_it_stopped() {
        let mut replies = configure_replies();
        replies.extend(std::iter::repeat_n(vec![0], 45));
        // The update() after the library's frames: every controller in REMOTESLAVE (the
        // stop's) but 4, in its own overcurrent, and 5, in its boot state.
        let mut now = remote_but(&[4, 5]);
        now[3][4..8].copy_from_slice(&[0x09, 0x00, 0x01, 0x00]);
        now[4][4..8].copy_from_slice(&[0x09, 0x00, 0x02, 0x05]);
        replies.extend(now);
        replies.extend(std::iter::repeat_n(vec![0], 7));
        let ran = run_script("stop\n", &replies, false);
        ran.result.unwrap();
        let sent = &ran.hex[10..];
        // First every controller's REG_EXCEPTIONDATA, then the library's 36 frames.
        let bridges: Vec<String> = (1..=9).map(|d| format!("06 {d}2 01 05 00 00")).collect();
        assert_eq!(sent[..9], bridges[..]);
        assert_eq!(
            sent[9],
            "19 12 08 0a 00 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f 32 33 18 fe 19 05"
        );
        assert_eq!(sent[44], "06 92 01 1b ff 7f");
        // One update() (ten reads), then REG_RESET 1 to each board in REMOTESLAVE only.
        assert_eq!(sent.len(), 45 + 10 + 7, "{sent:?}");
        let resets: Vec<String> = [1, 2, 3, 6, 7, 8, 9]
            .iter()
            .map(|d| format!("05 {d}2 01 00 01"))
            .collect();
        assert_eq!(sent[55..], resets[..]);
        // The library's 180-ms pause comes after the bridges' frames (it is the first
        // step of its stop), and a reset gap before each REG_RESET.
        assert_eq!(ran.pauses[0], Duration::from_millis(180));
        assert_eq!(ran.pauses[1..], [RESET_GAP; 7]);
    }

    #[test]
    fn a_stop_that_a_board_ignores_fails_naming_it_and_the_fix() {
        // Controllers 2 and 7 mask REMOTESLAVE (DISABLEDEXCEPTIONS bit 3): the update()
        // after the stop reads them running. The others are released, then the line fails.
        let mut replies = configure_replies();
        replies.extend(std::iter::repeat_n(vec![0], 45));
        replies.extend(remote_but(&[2, 7]));
        replies.extend(std::iter::repeat_n(vec![0], 7));
        let ran = run_script("stop\nsay after\n", &replies, false);
        assert_eq!(ran.hex.len(), 10 + 45 + 10 + 7, "{:?}", ran.hex);
        assert_eq!(ran.hex[ran.hex.len() - 1], "05 92 01 00 01");
        let message = ran.result.unwrap_err().to_string();
        assert!(
            message.starts_with(
                "t.rover line 1 (`stop`) failed: controller(s) 2, 7 ignored the stop: out of \
                 exception after its REG_EXCEPTIONDATA write, each masks REMOTESLAVE in its \
                 DISABLEDEXCEPTIONS (bit 3, value 8), so its bridges stayed on"
            ),
            "{message}"
        );
        assert!(!ran.text.contains("after"), "{}", ran.text);
    }

    /// A `calibrate` run over `update` at its start, its 30 frames answered 00, then
    /// `thaw` at its end and `resets` REG_RESETs answered 00.
    fn calibrate_over(stops: usize, start: Vec<Vec<u8>>, thaw: Vec<Vec<u8>>, resets: usize) -> Ran {
        let mut replies = configure_replies();
        replies.extend(start);
        replies.extend(std::iter::repeat_n(vec![0], stops + 30));
        replies.extend(thaw);
        replies.extend(std::iter::repeat_n(vec![0], resets));
        run_script("calibrate\nsay after\n", &replies, false)
    }

    #[test]
    fn a_calibrate_stops_the_running_boards_while_it_runs_and_releases_them() {
        // At its start controller 4 is in its own overcurrent and 5 in its boot state; the
        // other seven run. They are stopped first, then calibrated, then released: each
        // steer and lift holds where it stands on its new calibration.
        let own = [(4, 0x09, 0x0001), (5, 0x09, 0x0502)];
        let mut thaw = remote_but(&[4, 5]);
        thaw[3][4..8].copy_from_slice(&[0x09, 0x00, 0x01, 0x00]);
        thaw[4][4..8].copy_from_slice(&[0x09, 0x00, 0x02, 0x05]);
        let ran = calibrate_over(7, update_with(&own), thaw, 7);
        ran.result.unwrap();
        let sent = &ran.hex[10..];
        let running = [1, 2, 3, 6, 7, 8, 9];
        let stops: Vec<String> = running
            .iter()
            .map(|d| format!("06 {d}2 01 05 00 00"))
            .collect();
        assert_eq!(sent[0], "03 13 00", "an update() first");
        assert_eq!(sent[10..17], stops[..]);
        // calibrate()'s frames unchanged: wheel 1's drive block first.
        assert_eq!(
            sent[17],
            "19 12 08 0a 41 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f ff 7f 18 fe 19 05"
        );
        assert_eq!(sent[47], "03 13 00", "an update() after the frames");
        let resets: Vec<String> = running
            .iter()
            .map(|d| format!("05 {d}2 01 00 01"))
            .collect();
        assert_eq!(sent[57..], resets[..]);
        assert_eq!(ran.pauses[..12], [Duration::from_millis(50); 12]);
        assert_eq!(ran.pauses[12..], [RESET_GAP; 7]);
        assert_eq!(ran.text.lines().last(), Some("after"), "{}", ran.text);
        assert!(!ran.text.contains("note:"), "{}", ran.text);
    }

    #[test]
    fn a_calibrate_leaves_the_boards_stopped_when_the_master_may_have_stopped_them() {
        let stopped = |why: &str| {
            format!(
                "\nnote: the calibrate leaves the controllers it stopped ({}) in REMOTESLAVE: \
                 {why}, so the master may have stopped the rover itself; a `reset` line \
                 releases them once the cause is gone\n",
                "1, 2, 3, 4, 5, 6, 7, 8, 9"
            )
        };
        // The master holds SLAVESILENT naming controller 4 (0x040b), or a missing
        // temperature sensor (0x000a), at the end: it has sent every board into
        // REMOTESLAVE, and the calibrate must not undo that.
        for (raw, why) in [
            (
                0x040bu16,
                "the master holds an exception (slave not answering on controller 4, the \
                 whole board)",
            ),
            (
                0x000a,
                "the master holds an exception (temperature sensor missing)",
            ),
        ] {
            let mut thaw = remote_but(&[]);
            thaw[9][20..22].copy_from_slice(&raw.to_le_bytes());
            let ran = calibrate_over(9, update_replies(), thaw, 0);
            ran.result.unwrap();
            assert_eq!(ran.hex.len(), 10 + 10 + 9 + 30 + 10, "no REG_RESET");
            assert!(ran.text.contains(&stopped(why)), "{}", ran.text);
        }
        // A controller that no longer answers (the master spreads its silence even from
        // its boot state): the same, naming it; the list holds those read in REMOTESLAVE.
        let mut thaw = remote_but(&[]);
        thaw[9][20..22].copy_from_slice(&0x0002u16.to_le_bytes());
        thaw.remove(1);
        thaw.insert(1, vec![]);
        thaw.insert(2, vec![2]);
        thaw.insert(3, vec![0x0c, 0x01, 0x00]);
        let ran = calibrate_over(9, update_replies(), thaw, 0);
        ran.result.unwrap();
        assert!(
            ran.text.contains(
                "\nnote: the calibrate leaves the controllers it stopped (1, 3, 4, 5, 6, 7, 8, \
                 9) in REMOTESLAVE: controller(s) 2 not answering, so the master"
            ),
            "{}",
            ran.text
        );
        // Its state unknown: the same.
        let mut thaw = remote_but(&[]);
        thaw.pop();
        thaw.extend([vec![], vec![0x02], vec![0x00, 0x00, 0x00]]);
        let ran = calibrate_over(9, update_replies(), thaw, 0);
        assert!(
            ran.text
                .contains("in REMOTESLAVE: the master's state was not read, so"),
            "{:?}\n{}",
            ran.result,
            ran.text
        );
    }

    #[test]
    fn a_thaw_with_no_board_left_in_remoteslave_releases_and_says_nothing() {
        // Controller 1, stopped at the start, raised its own overcurrent meanwhile, which
        // the master latched (0x0101): nothing to release, and the view tells the rest.
        let now = Snapshot::new(vec![
            (
                1,
                vec![(id::REG_STATUS, 0x09), (id::REG_EXCEPTIONDATA, 0x0001)],
            ),
            (0, vec![(id::REGMASTER_EXCEPTIONDATA, 0x0101)]),
        ]);
        let frozen = Frozen {
            stopped: vec![1],
            unread: Vec::new(),
        };
        let thaw = Thaw::of(&frozen, &now, Pairs::ALL);
        assert_eq!(
            thaw,
            Thaw {
                release: Vec::new(),
                notes: Vec::new()
            }
        );
        // In REMOTESLAVE instead, with the master in its boot state: released.
        let now = Snapshot::new(vec![
            (
                1,
                vec![(id::REG_STATUS, 0x09), (id::REG_EXCEPTIONDATA, 0x0503)],
            ),
            (0, vec![(id::REGMASTER_EXCEPTIONDATA, 0x0002)]),
        ]);
        assert_eq!(Thaw::of(&frozen, &now, Pairs::ALL).release, [1]);
    }

    #[test]
    fn a_calibrate_names_a_board_that_ignored_its_stop() {
        // Controller 8 masks REMOTESLAVE: it runs on through the calibrate. The others are
        // released; a note names it.
        let ran = calibrate_over(9, update_replies(), remote_but(&[8]), 8);
        ran.result.unwrap();
        assert_eq!(ran.hex.len(), 10 + 10 + 9 + 30 + 10 + 8);
        assert!(
            ran.text.contains(
                "\nnote: controller(s) 8 ignored the calibrate's stop (DISABLEDEXCEPTIONS \
                 masks REMOTESLAVE, bit 3): their motors ran on through it, a drive toward its \
                 demand on the new gains"
            ),
            "{}",
            ran.text
        );
    }

    #[test]
    fn a_calibrate_stops_a_board_whose_state_the_line_lost_and_keeps_it_stopped() {
        // Controller 5's reply is lost at the start: it may run, so it is stopped too, and
        // as it may have been in REMOTESLAVE before, it is not released.
        let mut start = update_replies();
        start.remove(4);
        start.insert(4, vec![]);
        start.insert(5, vec![0x02]);
        start.insert(6, vec![0x00, 0x00, 0x00]);
        let ran = calibrate_over(9, start, remote_but(&[]), 8);
        ran.result.unwrap();
        let sent = &ran.hex[10..];
        // The eight running boards, then the one unread.
        let stops: Vec<&String> = sent.iter().filter(|f| f.ends_with("01 05 00 00")).collect();
        assert_eq!(stops.len(), 9, "{sent:?}");
        assert_eq!(stops[8], "06 52 01 05 00 00", "the unread board last");
        let resets: Vec<&String> = sent.iter().filter(|f| f.ends_with("01 00 01")).collect();
        assert_eq!(resets.len(), 8, "{sent:?}");
        assert!(
            !resets.contains(&&"05 52 01 00 01".to_owned()),
            "{resets:?}"
        );
        assert!(
            ran.text.contains(
                "\nnote: the calibrate leaves controller(s) 5 in REMOTESLAVE: the serial line \
                 lost their state before it"
            ),
            "{}",
            ran.text
        );
    }

    #[test]
    fn a_refused_release_tries_the_others_and_says_which_stay_stopped() {
        // Controller 2 refuses its REG_RESET; 3..9 are still released.
        let mut replies = configure_replies();
        replies.extend(update_replies());
        replies.extend(std::iter::repeat_n(vec![0], 9 + 30));
        replies.extend(remote_but(&[]));
        replies.extend([vec![0], vec![0x8c]]);
        replies.extend(std::iter::repeat_n(vec![0], 7));
        let ran = run_script("calibrate\n", &replies, false);
        assert_eq!(ran.hex.len(), 10 + 10 + 9 + 30 + 10 + 9, "{:?}", ran.hex);
        let message = ran.result.unwrap_err().to_string();
        assert!(
            message.starts_with(
                "t.rover line 1 (`calibrate`) failed: controller(s) 2 stay stopped: the \
                 REG_RESET that releases each was refused (the first: device 2 refused"
            ),
            "{message}"
        );
    }

    #[test]
    fn a_calibrate_that_cannot_stop_a_board_sends_no_calibration() {
        // Controller 3 does not acknowledge its REG_EXCEPTIONDATA (0x8c): no calibration
        // frame goes out, and 1 and 2, stopped already, stay stopped.
        let mut replies = configure_replies();
        replies.extend(update_replies());
        replies.extend([vec![0], vec![0], vec![0x8c]]);
        let ran = run_script("calibrate\n", &replies, false);
        assert_eq!(ran.hex.len(), 10 + 10 + 3, "{:?}", ran.hex);
        let message = ran.result.unwrap_err().to_string();
        assert!(
            message.starts_with(
                "t.rover line 1 (`calibrate`) failed: no calibration sent: controller 3 could \
                 not be stopped first (device 3 refused the write to REG_EXCEPTIONDATA"
            ),
            "{message}"
        );
        assert!(
            message.ends_with(
                "The run ends here, and closing the port reboots the rover, which stops every \
                 board"
            ),
            "{message}"
        );
    }

    #[test]
    fn a_refused_parameter_block_says_the_board_may_hold_some_of_it() {
        // Wheel 1's drive block (8 register writes in one frame) gets 0x8c: the master sent
        // each write and at least one was not taken.
        // Every board in its boot state: the calibrate stops none first.
        let mut replies = configure_replies();
        replies.extend(booted());
        replies.push(vec![0x8c]);
        replies.extend(std::iter::repeat_n(vec![0], 29));
        let ran = run_script("calibrate\n", &replies, false);
        assert_eq!(ran.hex.len(), 10 + 10 + 30, "{:?}", ran.hex);
        let message = ran.result.unwrap_err().to_string();
        assert!(
            message.contains(
                "the first: device 1 refused a write of a parameter block (8 register writes; \
                 the master sent each, so the board may hold some of them): code 0x8c"
            ),
            "{message}"
        );
    }

    #[test]
    fn a_stop_whose_master_does_not_answer_stops_at_once() {
        // No reply at all (the fake port runs dry): a timeout, so nothing more is sent.
        let replies = configure_replies();
        let ran = run_script("stop\n", &replies, false);
        // The first stop frame, then the probe of the master's error registers (its
        // set-read-set, unanswered too); no second stop frame.
        assert_eq!(ran.hex.len(), 10 + 1 + 1, "{:?}", ran.hex);
        assert_eq!(ran.hex[11], "05 04 07 0c 0d");
        assert!(matches!(
            ran.result,
            Err(HostError::ScriptStep { ref source, .. })
                if matches!(**source, HostError::Timeout { .. })
        ));
    }

    #[test]
    fn a_shown_temperature_without_a_reading_is_not_shown_as_one() {
        // `show 0 temp1`: TEMP1's REGMASTER_TEMPSREAD bit (the last two bytes of the
        // master's row) is clear in the first run, where it holds 0x2aaa (0.0 °C, no
        // reading); set in the second, where it holds 0x5887 (21.5 °C).
        for (read_bits, raw, want, value) in [
            (
                0x0000u16,
                0x2aaau16,
                "device 0: TEMP1 - (no reading)",
                "null",
            ),
            (0x0002, 0x5887, "device 0: TEMP1 21.498 degC", "21.498"),
        ] {
            let mut replies = configure_replies();
            replies.push(vec![1]);
            for _ in 0..2 {
                let mut update = update_replies();
                let master = update.last_mut().expect("the master's row");
                master[22..24].copy_from_slice(&read_bits.to_le_bytes());
                replies.extend(update);
                replies.push(raw.to_le_bytes().to_vec());
            }
            let ran = run_script("show 0 temp1\nwait 0.01\n", &replies, false);
            ran.result.unwrap();
            assert!(ran.text.contains(&format!("\n{want}\n")), "{}", ran.text);
            let ran = run_script("show 0 temp1\nwait 0.01\n", &replies, true);
            ran.result.unwrap();
            assert!(
                ran.text.contains(&format!(
                    "\"register\":\"REGMASTER_TEMP1\",\"raw\":{raw},\"value\":{value}"
                )),
                "{}",
                ran.text
            );
        }
    }

    #[test]
    fn a_shown_set_goes_on_past_a_lost_reply_and_takes_exceptiondata_apart() {
        // `show 0 exceptiondata` over two updates: one show reply holds 0x1401, the other is
        // lost on the line (the probe finds no link error since boot). The view printed is
        // the last update's.
        let lost = [vec![], vec![0x02], vec![0x00, 0x00, 0x00]];
        let replies = |lost_last: bool| {
            let mut replies = configure_replies();
            replies.push(vec![1]);
            for update in [false, true] {
                replies.extend(update_replies());
                if update == lost_last {
                    replies.extend(lost.clone());
                } else {
                    replies.push(vec![0x01, 0x14]);
                }
            }
            replies
        };
        let script = "show 0 exceptiondata\nwait 0.01\n";
        for (lost_last, json, want) in [
            (
                true,
                false,
                "\ndevice 0: reply lost on the serial line (read again next update)\n",
            ),
            (
                true,
                true,
                r#""shown":[{"device":0,"values":null,"reply_lost":true}]"#,
            ),
            (
                false,
                false,
                "\ndevice 0: EXCEPTIONDATA 5121 (overcurrent on controller 4, motor 1 (wheel 3's steer))\n",
            ),
            (
                false,
                true,
                r#""exception":{"type":1,"name":"OVERCURRENT","controller":4,"motor":1,"wheel":3,"wheel_motor":"steer","text":"overcurrent on controller 4, motor 1 (wheel 3's steer)"}"#,
            ),
        ] {
            let ran = run_script(script, &replies(lost_last), json);
            ran.result.unwrap();
            assert!(ran.text.contains(want), "{want}\n{}", ran.text);
        }
    }

    #[test]
    fn a_shown_angle_off_the_wheels_calibration_is_marked() {
        // `show 1 steer_actualpos drive_error`, once on the boot calibration, once after
        // `calibrate` (30 frames answered 00). The show set's 4 bytes: ACTUALPOS 0x8000,
        // ERROR 0x8000.
        for (script, calibrate) in [("", false), ("calibrate\n", true)] {
            let mut replies = configure_replies();
            replies.push(vec![2]);
            if calibrate {
                replies.extend(booted());
                replies.extend(std::iter::repeat_n(vec![0], 30));
            }
            for _ in 0..2 {
                replies.extend(update_replies());
                replies.push(vec![0x00, 0x80, 0x00, 0x80]);
            }
            let source = format!("show 1 steer_actualpos drive_error\n{script}wait 0.01\n");
            let ran = run_script(&source, &replies, false);
            ran.result.unwrap();
            let mark = if calibrate { "" } else { "*" };
            let want =
                format!("\ndevice 1: STEER_ACTUALPOS 0.006 deg{mark}, DRIVE_ERROR 0.031 ticks/s\n");
            assert!(ran.text.contains(&want), "{}", ran.text);
            let legends = ran.text.matches(NOT_DEGREES).count();
            assert_eq!(legends, usize::from(!calibrate), "{}", ran.text);
            let ran = run_script(&source, &replies, true);
            ran.result.unwrap();
            let calibrated = if calibrate { "true" } else { "false" };
            assert!(
                ran.text.contains(&format!(
                    "\"register\":\"REGDS_STEER_ACTUALPOS\",\"raw\":32768,\"value\":0.0061035156,\"unit\":\"deg\",\"calibrated\":{calibrated}}}"
                )),
                "{}",
                ran.text
            );
            assert!(
                ran.text.contains("\"unit\":\"ticks/s\"}"),
                "a speed has no calibration: {}",
                ran.text
            );
        }
    }

    #[test]
    fn a_run_that_ends_in_exception_fails_naming_it_judged_on_the_rover_as_it_ends() {
        // The master's update() reply with EXCEPTIONDATA 0x1401: an overcurrent spread from
        // controller 4's motor 1.
        let mut spread = update_replies();
        let master = spread.last_mut().expect("the master's reply");
        master[20..22].copy_from_slice(&[0x01, 0x14]);
        // The last view saw it, and nothing was sent after it: judged on that view.
        let mut replies = configure_replies();
        replies.extend(update_replies());
        replies.extend(spread.clone());
        let ran = run_script("wait 0.01\n", &replies, false);
        let faults = vec!["master: overcurrent on controller 4, motor 1 (wheel 3's steer)"];
        assert!(
            matches!(&ran.result, Err(HostError::EndedInException { faults: f, .. }) if *f == faults),
            "{:?}",
            ran.result
        );
        assert_eq!(ran.hex.len(), 10 + 2 * 10, "no update() past the view's");
        // A write after the last view: one more update() decides, here a clean one.
        let mut replies = configure_replies();
        replies.extend(update_replies());
        replies.extend(spread.clone());
        replies.push(vec![0]);
        replies.extend(update_replies());
        let ran = run_script("wait 0.01\nwrite 0 reset 1\n", &replies, false);
        ran.result.unwrap();
        assert_eq!(ran.hex.len(), 10 + 2 * 10 + 1 + 10);
        // The same script with the exception still there at its end.
        let mut replies = configure_replies();
        replies.extend(update_replies());
        replies.extend(update_replies());
        replies.push(vec![0]);
        replies.extend(spread);
        let ran = run_script("wait 0.01\nwrite 0 reset 1\n", &replies, true);
        assert!(
            matches!(&ran.result, Err(HostError::EndedInException { faults: f, .. }) if *f == faults),
            "{:?}",
            ran.result
        );
        // Controller 4 seen running, then back in its boot state: it rebooted.
        let mut running = update_replies();
        running[3][4..6].copy_from_slice(&[0x08, 0x00]);
        let mut rebooted = update_replies();
        rebooted[3][4..8].copy_from_slice(&[0x09, 0x00, 0x02, 0x05]);
        let mut replies = configure_replies();
        replies.extend(running);
        replies.extend(rebooted);
        let ran = run_script("wait 0.01\n", &replies, false);
        assert!(
            matches!(&ran.result, Err(HostError::EndedInException { faults: f, .. })
                if f == &["controller 4: rebooted: back in its boot state, its demands and calibration gone"]),
            "{:?}",
            ran.result
        );
        // A script that never looked at the rover is not judged.
        let mut replies = configure_replies();
        replies.push(vec![0]);
        run_script("write 0 reset 1\n", &replies, false)
            .result
            .unwrap();
        assert_eq!(
            crate::exit_status(&HostError::EndedInException {
                path: String::new(),
                faults: Vec::new()
            }),
            std::process::ExitCode::from(3)
        );
    }

    #[test]
    fn a_shown_angle_brings_its_legend_when_the_view_has_none() {
        // Every wheel calibrated but wheel 1's steer (its CALIBMAX written to 70°), and
        // controller 1 misses update()'s read: the view has no position to mark, so no
        // legend. It answers the `show` read: that angle is marked and explained.
        let mut replies = configure_replies();
        replies.push(vec![1]);
        replies.extend(booted());
        replies.extend(std::iter::repeat_n(vec![0], 31));
        let mut update = update_replies();
        update.remove(0);
        replies.extend([vec![], vec![2], vec![0x0c, 0x01, 0x00]]);
        replies.extend(update);
        replies.push(vec![0x00, 0x80]);
        let source = "show 1 steer_actualpos\ncalibrate\nwrite 1 steer_calibmax 70\nwait 0\n";
        let ran = run_script(source, &replies, false);
        // A controller that does not answer at the end is a doubt the exit status reports.
        assert!(
            matches!(&ran.result, Err(HostError::EndedInException { faults, .. })
                if faults == &["controller 1: no answer"]),
            "{:?}",
            ran.result
        );
        let text = ran.text;
        assert!(
            text.contains("\ndevice 1: STEER_ACTUALPOS 0.006 deg*\n"),
            "{text}"
        );
        assert_eq!(text.matches(NOT_DEGREES).count(), 1, "{text}");
    }

    #[test]
    fn the_view_goes_on_past_a_controller_that_does_not_answer() {
        // Controller 4 (wheel 3's drive and steer) is off the bus in both updates: no reply,
        // and the master's last link error is code 12 (NoAnswer).
        let mut replies = configure_replies();
        for count in 1..=2 {
            for (i, reply) in update_replies().into_iter().enumerate() {
                if i == 3 {
                    // The master's error count grows by one each time.
                    replies.extend([vec![], vec![2], vec![0x0c, count, 0x00]]);
                } else {
                    replies.push(reply);
                }
            }
        }
        let ran = run_script("wait 0.01\n", &replies, false);
        let ended = ran
            .result
            .expect_err("the run ends with controller 4 silent");
        assert_eq!(
            ended.to_string(),
            "t.rover ran to its end with boards stopped or out of reach: controller 4: no answer. A board \
             in exception stops its motors until a `reset` line in the script clears it, \
             which holds once the cause is gone (docs/safety.md lists each exception's \
             causes); a controller that does not answer is off the bus or unpowered; a \
             rebooted one needs `calibrate` again"
        );
        let text = ran.text;
        assert!(
            text.contains(
                "\n3              -        ?          -         ?         -  ≤-200.0*  controller 4: \
                 no answer\n"
            ),
            "{text}"
        );
        assert!(
            text.contains("\nno answer: controller 4 does not answer the master on the I2C bus"),
            "{text}"
        );
        assert_eq!(
            ran.hex.len(),
            10 + 2 * 12,
            "ten reads and two probes an update"
        );
        let ran = run_script("wait 0.01\n", &replies, true);
        assert!(ran.result.is_err());
        assert!(ran.text.contains("\"no_answer\":[4]"), "{}", ran.text);
        assert!(
            ran.text
                .contains("\"exceptions\":\"controller 4: no answer\""),
            "{}",
            ran.text
        );
    }

    #[test]
    fn a_rover_with_the_front_pair_alone_is_driven_and_polled_on_it_alone() {
        let pairs = Pairs::parse("0").unwrap();
        let plan = plan_for(
            "reset\ncalibrate\ndrive all 100\nturn 10\nwait 0.01\n",
            pairs,
        );
        // init(): set 0 via 1 and 2, set 1 via 3, set 2 via the master; then 4 resets; the
        // calibrate's update() of 4 reads (all three boards running), its REG_EXCEPTIONDATA
        // to each, 10 calibration frames (2 wheels), its update() (each in REMOTESLAVE) and
        // 3 REG_RESETs; 2 drives, 2 steers; then update()s of 4 reads.
        let running = || [vec![0; 40], vec![0; 40], vec![0; 36], vec![0; 24]];
        let mut replies: Vec<Vec<u8>> = vec![vec![20], vec![20], vec![18], vec![12]];
        replies.extend(std::iter::repeat_n(vec![0], 4));
        replies.extend(running());
        replies.extend(std::iter::repeat_n(vec![0], 3 + 10));
        let mut remote = running();
        for row in &mut remote[..3] {
            row[4..8].copy_from_slice(&[0x01, 0x00, 0x03, 0x05]);
        }
        replies.extend(remote);
        replies.extend(std::iter::repeat_n(vec![0], 3 + 2 + 2));
        for _ in 0..2 {
            replies.extend(running());
        }
        let ran = run_plan(&plan, &replies, false);
        ran.result.unwrap();
        let devices: Vec<&str> = ran.hex.iter().map(|f| &f[3..4]).collect();
        assert_eq!(
            devices.concat(),
            // init, reset, then the calibrate: update, stops, frames, update, resets.
            "1230".to_owned()
                + "1230"
                + "1230"
                + "123"
                + "1113322233"
                + "1230"
                + "123"
                + "12"
                + "12"
                + "1230"
                + "1230",
            "{:#?}",
            ran.hex
        );
        // Wheels 1 and 2 turn 10° (0x8665 on ±200); 3..6 get no frame.
        assert_eq!(ran.hex[20 + 14], "06 12 01 1a 65 86");
        let text = ran.text;
        assert!(text.contains("\n2            100"), "{text}");
        assert!(!text.contains("\n3 "), "{text}");
        assert!(
            text.contains("\nwheels 3, 4, 5, 6 not fitted (--pairs): not polled\n"),
            "{text}"
        );
        let ran = run_plan(&plan, &replies, true);
        assert!(
            ran.text.contains("\"wheels\":[{\"wheel\":1,"),
            "{}",
            ran.text
        );
        assert!(!ran.text.contains("\"wheel\":3"), "{}", ran.text);
    }

    #[test]
    fn a_line_naming_a_pair_left_out_is_refused_before_anything_is_sent() {
        let pairs = Pairs::parse("0,2").unwrap();
        for (line, what) in [
            ("drive 3 100", "wheel 3"),
            ("write 4 reset 1", "controller 4"),
            ("show 6 one_control", "controller 6"),
        ] {
            let err = script::parse_for("t.rover", line, pairs).unwrap_err();
            assert_eq!(
                err.to_string(),
                format!(
                    "t.rover line 1 (`{line}`): {what} is on wheel pair 1 (wheels 3, 4; \
                     controllers 4..6), which --pairs leaves out; add 1 to --pairs if it is fitted"
                )
            );
        }
        assert!(script::parse_for("t.rover", "drive 5 100\nwrite 9 reset 1", pairs).is_ok());
        for bad in ["", "3", "0,,1", "one", "-1"] {
            assert!(
                matches!(Pairs::parse(bad), Err(HostError::BadPairs { .. })),
                "{bad:?}"
            );
        }
        assert_eq!(Pairs::parse("2, 0").unwrap().mask(), 0b101);
    }

    #[test]
    fn show_adds_registers_to_every_view() {
        let mut replies = configure_replies();
        // The show set's count, then per update the ten reads and the show set's 4 bytes.
        replies.push(vec![2]);
        for _ in 0..2 {
            replies.extend(update_replies());
            // CONTROL at the middle of -255..255 (0), ERROR at the top of ±1000.
            replies.push(vec![0xff, 0x7f, 0xfe, 0xff]);
        }
        let ran = run_script(
            "show 1 drive_control drive_error\nwait 0.01\n",
            &replies,
            false,
        );
        ran.result.unwrap();
        let (hex, text) = (ran.hex, ran.text);
        // Set 3 on controller 1: DRIVE_CONTROL (20), DRIVE_ERROR (17); read after update().
        assert_eq!(hex[10], "05 14 03 14 11");
        assert_eq!(hex[21], "03 13 03");
        assert!(
            text.contains("\ndevice 1: DRIVE_CONTROL 0.000 duty, DRIVE_ERROR ≥1000.000 ticks/s\n"),
            "{text}"
        );
    }

    #[test]
    fn show_lines_with_the_same_registers_share_one_set_on_several_boards() {
        let mut replies = configure_replies();
        // One set-read-set for both lines, then per update the ten reads and both boards'
        // 2-byte show reads.
        replies.push(vec![1]);
        replies.extend(update_replies());
        replies.push(vec![0xff, 0x7f]);
        replies.push(vec![0x00, 0x00]);
        // A register named twice, and a line that repeats an earlier one, add nothing.
        let ran = run_script(
            "show 1 drive_control drive_control\nshow 4 drive_control\nshow 1 drive_control\n\
             wait 0\n",
            &replies,
            false,
        );
        ran.result.unwrap();
        let hex = ran.hex;
        assert_eq!(hex[10], "04 14 03 14", "set 3 := DRIVE_CONTROL, sent once");
        assert_eq!(hex[21..], ["03 13 03", "03 43 03"]);
        // A duty has no value beyond its range's ends: -255 is shown as it is.
        assert!(
            ran.text.contains(
                "\ndevice 1: DRIVE_CONTROL 0.000 duty\ndevice 4: DRIVE_CONTROL -255.000 duty\n"
            ),
            "{}",
            ran.text
        );
        assert_eq!(ran.text.matches("device 1:").count(), 1, "{}", ran.text);
    }

    #[test]
    fn each_reset_out_of_an_exception_comes_two_board_ticks_after_what_went_before() {
        // `reset`: REG_RESET 1 to the nine controllers, then the master's reset; a hard
        // reset (bit 1) is no way out of an exception and waits for nothing.
        let mut replies = configure_replies();
        replies.extend(std::iter::repeat_n(vec![0], 11));
        let ran = run_script(
            "reset
write 4 reset 2
",
            &replies,
            false,
        );
        ran.result.unwrap();
        assert_eq!(ran.hex[10], "05 12 01 00 01");
        assert_eq!(ran.hex[20], "05 42 01 00 02");
        assert_eq!(ran.pauses, [RESET_GAP; 9]);
    }

    /// The replies of `init()` and then of `rounds` update() rounds.
    fn updates(rounds: usize) -> Vec<Vec<u8>> {
        let mut replies = configure_replies();
        for _ in 0..rounds {
            replies.extend(booted());
        }
        replies
    }

    /// The end of every message of a script stopped with the port open.
    const CLOSES: &str = "; hostctl closes the port, which reboots the master and so stops \
                          every motor";

    #[test]
    fn ctrl_c_during_a_wait_draws_its_view_once_and_stops_the_script() {
        // To a file a `wait` prints its view when it ends: Ctrl-C at 2 s of a 30-s wait
        // ends it there, with the view, and the script goes no further.
        let script = plan("wait 30\nsay after\n");
        let ran = run_interrupted(&script, &updates(300), Duration::from_secs(2), false);
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 130);
        assert_eq!(
            e.to_string(),
            format!(
                "stopped by Ctrl-C during line 1 (`wait 30`); the view above is the rover as \
                 it was then{CLOSES}"
            )
        );
        let text = ran.text;
        assert_eq!(text.matches(" updates, ").count(), 1, "one view: {text}");
        assert!(text.contains("\n2.0 s: 201 updates, "), "{text}");
        assert!(!text.lines().any(|l| l == "after"), "{text}");
        // 201 update() rounds of ten frames after the nine set configurations.
        assert_eq!(ran.hex.len(), 9 + 1 + 201 * 10);
        // As JSON: the view, then the error naming the signal and the line.
        let ran = run_interrupted(&script, &updates(300), Duration::from_secs(2), true);
        let cli = <crate::Cli as clap::Parser>::try_parse_from(["hostctl", "run", "t.rover"]);
        let error = crate::error_json(&cli.unwrap().command, &ran.result.unwrap_err());
        assert!(
            error.ends_with(r#""interrupted":"Ctrl-C","line":1}"#),
            "{error}"
        );
        let last = ran.text.lines().last().unwrap_or_default();
        assert!(last.contains(r#""updates":201"#), "{last}");
    }

    #[test]
    fn a_fault_while_ctrl_c_is_pending_is_reported_as_itself() {
        // Ctrl-C at 45 ms; the sixth round's replies never come: the timeout is what the
        // user must know, not a view from before it.
        let ran = run_interrupted(
            &plan("wait 30\n"),
            &updates(5),
            Duration::from_millis(45),
            false,
        );
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 1);
        assert!(
            matches!(&e, HostError::ScriptStep { source, .. } if matches!(**source, HostError::Timeout { .. })),
            "{e}"
        );
        // The view's last update is drawn first, as the rover was last seen.
        assert_eq!(ran.text.matches(" updates, ").count(), 1, "{}", ran.text);
        assert!(ran.text.contains(": 5 updates, "), "{}", ran.text);
    }

    #[test]
    fn a_script_that_is_not_utf8_names_its_line_and_the_fix() {
        assert_eq!(script_text(b"say hi\n".to_vec()), Ok("say hi\n".to_owned()));
        // `say Temperatur 20°C` saved as Windows-1252, on line 2.
        let err = script_text(b"reset\nsay Temperatur 20\xb0C\n".to_vec()).unwrap_err();
        assert!(err.starts_with("line 2 is not UTF-8 (byte 0xb0;"), "{err}");
        assert!(err.ends_with("save the script as UTF-8"), "{err}");
        // Notepad's "Unicode": UTF-16 with its byte-order mark.
        let err = script_text(b"\xff\xfer\x00e\x00".to_vec()).unwrap_err();
        assert!(err.starts_with("the script is UTF-16"), "{err}");
    }

    #[test]
    fn watch_prints_a_view_as_often_as_its_line_says() {
        // The elapsed time of each view printed (JSON lines), on the fake clock: one
        // update() every 10 ms.
        let views = |script: &str| -> Vec<f32> {
            let ran = run_script(script, &updates(200), true);
            ran.result.unwrap();
            ran.text
                .lines()
                .filter_map(|l| l.split_once(r#""elapsed_s":"#))
                .map(|(_, rest)| rest.split(',').next().unwrap().parse().unwrap())
                .collect()
        };
        // Once a second by default, and at the end.
        assert_eq!(views("watch 1\n"), [0.0, 1.0]);
        assert_eq!(views("watch 1 0.25\n"), [0.0, 0.25, 0.5, 0.75, 1.0]);
        // 0: every update.
        assert_eq!(views("watch 0.05 0\n"), [0.0, 0.01, 0.02, 0.03, 0.04, 0.05]);
        // A `wait` to a file: its last view only.
        assert_eq!(views("wait 1\n"), [1.0]);
        // Printed to the millisecond, not as the f32 nearest a count of ns.
        let printed = |ns| json::number(to_the_ms(Duration::from_nanos(ns)));
        assert_eq!(printed(1_816_999_900), "1.817");
        assert_eq!(printed(1_817_000_400), "1.817");
        assert_eq!(printed(0), "0");
    }

    #[test]
    fn a_link_lost_during_a_view_draws_the_last_update_and_says_what_the_rover_may_do() {
        // The port goes away (a cable pulled, the twin killed) after 30 update() rounds.
        let mut port = FakePort::with_replies(&updates(300));
        port.gone_after = Some(10 + 30 * 10);
        let ran = run_on(&plan("wait 3\nsay after\n"), port, Duration::MAX, false);
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 1);
        let message = e.to_string();
        assert!(message.contains("broken pipe"), "{message}");
        assert!(message.contains("may still be moving"), "{message}");
        assert!(message.contains("pctimeout"), "{message}");
        // To a file a `wait` draws its view only at its end: the last one is drawn now.
        assert_eq!(ran.text.matches(" updates, ").count(), 1, "{}", ran.text);
        assert!(ran.text.contains(": 30 updates, "), "{}", ran.text);
        assert!(!ran.text.lines().any(|l| l == "after"), "{}", ran.text);
    }

    #[test]
    fn ctrl_c_stops_a_script_between_lines_and_after_its_last() {
        // Before the first line: nothing but the set configurations goes out.
        let ran = run_interrupted(&plan("reset\n"), &updates(0), Duration::ZERO, false);
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 130);
        assert_eq!(
            e.to_string(),
            format!("stopped by Ctrl-C before line 1 (`reset`) ran{CLOSES}")
        );
        assert_eq!(ran.hex.len(), 10);
        // During the last line's actions (its resets wait two board ticks each): the line
        // ends, and no closing update() follows.
        let mut replies = updates(0);
        replies.extend(std::iter::repeat_n(vec![0], 10));
        let ran = run_interrupted(&plan("reset\n"), &replies, Duration::from_millis(1), false);
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 130);
        assert_eq!(
            e.to_string(),
            format!("stopped by Ctrl-C after the script's last line ran{CLOSES}")
        );
        assert!(
            ran.hex[10..].iter().all(|f| f.starts_with("05 ")),
            "{:?}",
            ran.hex
        );
        // During the wait for the master's watch: no note, and the first write never goes
        // out.
        let mut early = plan("write 1 drive_reqspeed 10\n");
        early.settled = Duration::from_secs(2);
        let ran = run_interrupted(&early, &updates(0), Duration::ZERO, false);
        let e = ran.result.unwrap_err().to_string();
        assert!(
            e.starts_with("stopped by Ctrl-C before line 1 (`write 1 drive_reqspeed 10`) ran;"),
            "{e}"
        );
        assert_eq!(ran.hex.len(), 10, "no write");
        assert!(!ran.text.contains("note:"), "{}", ran.text);
        let ran = run_interrupted(&early, &updates(0), Duration::from_secs(1), false);
        assert_eq!(ran.hex.len(), 10, "no write");
        assert_eq!(
            ran.pauses.iter().sum::<Duration>(),
            Duration::from_secs(1),
            "the wait ended at Ctrl-C"
        );
    }

    #[test]
    fn ctrl_c_during_a_calibrate_leaves_the_boards_it_stopped_stopped() {
        // Every board runs; Ctrl-C at 100 ms, while calibrate()'s frames go out (50 ms
        // apart): they all go, and then no board is released.
        let mut replies = updates(0);
        replies.extend(update_replies());
        replies.extend(std::iter::repeat_n(vec![0], 9 + 30));
        let ran = run_interrupted(
            &plan("calibrate\nsay after\n"),
            &replies,
            Duration::from_millis(100),
            false,
        );
        let e = ran.result.unwrap_err();
        assert_eq!(crate::exit_code(&e), 130);
        assert_eq!(
            e.to_string(),
            format!(
                "stopped by Ctrl-C during line 1 (`calibrate`), the boards it stopped for the \
                 calibration left stopped{CLOSES}"
            )
        );
        let sent = &ran.hex[10..];
        assert_eq!(sent[0], "03 13 00", "an update() first");
        assert_eq!(
            sent.len(),
            10 + 9 + 30,
            "stops and frames, no release: {sent:?}"
        );
        assert!(!sent.iter().any(|f| f.ends_with(" 01 00 01")), "{sent:?}");
    }

    #[test]
    fn a_script_runs_in_one_session_with_its_pauses_and_view() {
        let mut replies = configure_replies();
        replies.push(vec![0]);
        // No `reset`: the calibrate finds every board in its boot state, and stops none.
        replies.extend(booted());
        replies.extend(std::iter::repeat_n(vec![0], 30));
        replies.extend(update_replies());
        replies.extend(update_replies());
        let ran = run_script("drive 1 1000\ncalibrate\nwait 0.01\n", &replies, false);
        ran.result.unwrap();
        let hex = ran.hex;
        assert_eq!(
            hex[0],
            "17 14 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27"
        );
        assert_eq!(
            hex[2],
            "15 34 01 01 02 03 05 10 11 12 13 14 15 16 22 23 24 25 26 27 28"
        );
        // The master's set 2: the library's eleven registers, then REGMASTER_TEMPSREAD.
        assert_eq!(hex[9], "0f 04 02 01 02 03 04 05 06 07 08 09 0a 0b 0e");
        assert_eq!(hex[10], "06 12 01 09 fe 9f");
        // The calibrate's update() (no board running: nothing stopped, none released).
        assert_eq!(hex[11], "03 13 00");
        assert_eq!(
            hex[21], "19 12 08 0a 41 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f ff 7f 18 fe 19 05",
            "wheel 1's drive block, calibrate()'s first frame"
        );
        assert_eq!(
            hex[51], "03 13 00",
            "the view's update() starts after the 30 calibration frames"
        );
        assert_eq!(hex[60], "03 03 02");
        assert_eq!(hex.len(), 71, "two update() rounds in 10 ms of fake time");
        let pauses = ran.pauses;
        assert_eq!(pauses[..12], [Duration::from_millis(50); 12]);
        assert_eq!(pauses[12..], [TICK]);
        let text = ran.text;
        assert!(text.starts_with(
            "t.rover: 3 lines; read sets 0, 1, 2 configured\n\
             note: line 1 sends a demand, but no line is `reset`: after the port opens every \
             board is in its boot exception, so nothing will move\n\
             > drive 1 1000\n> calibrate\n> wait 0.01\n"
        ));
        // All-zero replies unmap to the bottom of each range. The demand went to a board
        // in its boot exception (no `reset`): dropped.
        assert!(
            text.contains(
                "\n1         (1000)   ≤-4000          -  ≤-200.0         -  ≤-200.0  -\n"
            ),
            "{text}"
        );
        assert!(
            text.contains("\n0.0 s: 2 updates, 200.0 update()/s"),
            "{text}"
        );
    }

    #[test]
    fn with_json_every_line_printed_is_a_json_object() {
        let mut replies = configure_replies();
        replies.push(vec![0]);
        replies.extend(update_replies());
        replies.extend(update_replies());
        let ran = run_script("say Go\ndrive 1 1000\nwait 0.01\n", &replies, true);
        ran.result.unwrap();
        let text = ran.text;
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[..6],
            [
                r#"{"command":"run","script":"t.rover","lines":3}"#,
                r#"{"command":"run","note":"line 2 sends a demand, but no line is `reset`: after the port opens every board is in its boot exception, so nothing will move"}"#,
                r#"{"command":"run","note":"line 2 sends a demand, but no line is `calibrate`: the boards' gains stay 0, so nothing will move"}"#,
                r#"{"command":"run","line":1,"say":"Go"}"#,
                r#"{"command":"run","line":2,"text":"drive 1 1000"}"#,
                r#"{"command":"run","line":3,"text":"wait 0.01"}"#,
            ]
        );
        // All-zero replies unmap to the bottom of each range; wheel 1 was asked for 1000
        // while its board was in its boot exception (no `reset`), so it is dropped; nothing
        // else was sent (null). No `calibrate`: the positions are not degrees. Raw 0 is each
        // range's low end, so every actual is marked at_limit.
        let wheel = |n: u8, drive: &str, dropped: &str| {
            format!(
                r#"{{"wheel":{n},"drive":{{"required":{drive},"actual":-4000,"calibrated":true,"at_limit":"lower"{dropped},"exception":null}},"steer":{{"required":null,"actual":-200,"calibrated":false,"at_limit":"lower","exception":null}},"lift":{{"required":null,"actual":-200,"calibrated":false,"at_limit":"lower","exception":null}},"exceptions":null}}"#
            )
        };
        let wheels: Vec<String> = (1..=6)
            .map(|n| match n {
                1 => wheel(n, "1000", r#","dropped":true"#),
                _ => wheel(n, "null", ""),
            })
            .collect();
        assert_eq!(
            lines[6],
            format!(
                r#"{{"command":"run","line":3,"elapsed_s":0.01,"updates":2,"rate":200,"wheels":[{}],"master_exception":0,"no_answer":[],"reply_lost":[],"master":"master: no exception; °C ambient -, boards - - - - - - - - - (- no reading: not read yet, one sensor every 2 s from 5 s after boot; missing; or its last read failed)","master_state":{{"exception":{{"type":0,"name":null,"controller":0,"motor":0,"text":"no exception"}},"temperatures":{{"ambient":null,"boards":[null,null,null,null,null,null,null,null,null]}}}}}}"#,
                wheels.join(",")
            )
        );
        assert_eq!(lines.len(), 7, "{text}");
    }

    #[test]
    fn without_a_port_the_twin_is_asked_for_one_after_the_input_is_checked() {
        use clap::Parser;
        let style = crate::Style {
            json: false,
            in_place: false,
            width: || None,
        };
        let cli = crate::Cli::try_parse_from(["hostctl", "run", "/nonexistent.rover"]).unwrap();
        let mut asked = false;
        let err = crate::run_with(
            &cli,
            None,
            || {
                asked = true;
                Ok("/dev/twin".to_owned())
            },
            |_: &str| Ok(Link::ready(FakePort::default())),
            style,
            &mut Vec::new(),
        )
        .unwrap_err();
        assert!(matches!(err, HostError::ScriptFile { .. }), "{err}");
        assert!(!asked, "bad input never starts a twin");

        let cli = crate::Cli::try_parse_from(["hostctl", "write", "0", "RESET", "1"]).unwrap();
        let mut opened = String::new();
        crate::run_with(
            &cli,
            Some(String::new()),
            || Ok("/dev/twin".to_owned()),
            |path: &str| {
                opened = path.to_owned();
                Ok(Link::ready(FakePort::with_replies(&[[0u8]])))
            },
            style,
            &mut Vec::new(),
        )
        .unwrap();
        assert_eq!(opened, "/dev/twin");
    }

    #[test]
    fn a_refused_write_names_the_script_line() {
        // The other nine boards of resetExceptions() accept theirs.
        let ran = run_script("reset\n", &first_write_refused(9), false);
        assert_eq!(ran.hex.len(), 10 + 10, "every reset sent: {:?}", ran.hex);
        let err = ran.result.unwrap_err();
        assert!(
            err.to_string().starts_with("t.rover line 1 (`reset`) failed: 1 of the line's 10 writes refused, the other 9 sent; the first: device 1 refused the write to REG_RESET: code 0x8c (a slave did not answer on the I2C bus); controller 1 is not answering the master on the I2C bus"),
            "{err}"
        );
        // A line of one write fails with the refusal alone.
        let err = run_script("drive 1 10\n", &first_write_refused(0), false)
            .result
            .unwrap_err();
        assert!(
            err.to_string().starts_with("t.rover line 1 (`drive 1 10`) failed: device 1 refused the write to a demand: code 0x8c"),
            "{err}"
        );
    }
}
