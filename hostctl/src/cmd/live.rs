//! The live view of `hostctl run`: the original library's read sets 0, 1 and 2, configured
//! as its init() does and polled as its update() does (reference §4.3), shown as required
//! against actual per wheel.

use std::time::Duration;

use shared::exception::ExceptionType;
use shared::mapping;
use shared::regs::{id, BoardKind};

use super::pc::{device_of, Motor, Pairs, Pc, Send, WHEELS};
use super::{configure, set_frame, Reading, SetRead};
use crate::error::HostError;
use crate::exception::Exception;
use crate::json;
use crate::link::Link;
use crate::meaning::STATUS_EXCEPTION;
use crate::port::Port;
use crate::resolve::{self, Target};
use crate::table::Table;

/// The read set the library gives each board kind.
fn set_of(kind: BoardKind) -> u8 {
    match kind {
        BoardKind::DriveSteer => 0,
        BoardKind::LiftLift => 1,
        BoardKind::Master => 2,
    }
}

/// The legend of a position marked `*`.
pub const NOT_DEGREES: &str = "* not degrees: the board's pot calibration is not the wheel's (no \
`calibrate` since the port opened; or since then a `stop`, which sends -100/100, a write to its \
CALIBMIN or CALIBMAX, a hard reset, a reboot seen (back in its boot state after being out of \
it), or a time it did not answer and may have rebooted)";

/// update()'s reads, in its order: controllers 1..9, then the master.
pub struct Poller {
    reads: Vec<SetRead>,
}

/// One update(): each device's registers and raw values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshot {
    rows: Vec<(u8, Vec<(u8, u16)>)>,
    /// The controllers that did not answer, in update() order.
    silent: Vec<u8>,
    /// The devices whose reply the serial line lost, in update() order.
    lost: Vec<u8>,
}

impl Snapshot {
    /// A snapshot from (device, [(register id, raw)]) rows.
    pub fn new(rows: Vec<(u8, Vec<(u8, u16)>)>) -> Snapshot {
        Snapshot {
            rows,
            silent: Vec::new(),
            lost: Vec::new(),
        }
    }

    /// The controllers that did not answer the master this update (their values are not
    /// read: every value of theirs shows as "-").
    pub fn silent(&self) -> &[u8] {
        &self.silent
    }

    /// The devices whose reply the serial line lost this update (their values are not
    /// read: every value of theirs shows as "-").
    pub fn lost(&self) -> &[u8] {
        &self.lost
    }

    /// The raw value of register `reg` of `device`, if it was read.
    pub fn raw(&self, device: u8, reg: u8) -> Option<u16> {
        let (_, values) = self.rows.iter().find(|(d, _)| *d == device)?;
        values.iter().find(|(r, _)| *r == reg).map(|&(_, raw)| raw)
    }

    /// The value of register `reg` of `device` in its units, if it was read.
    pub fn value(&self, device: u8, reg: u8) -> Option<f32> {
        let kind = BoardKind::of_device(device)?;
        let register = kind.register(reg)?;
        Some(mapping::unmap(self.raw(device, reg)?, register))
    }

    /// Whether register `reg` of `device` holds no reading: a master temperature whose
    /// REGMASTER_TEMPSREAD bit (read with the master's row) is clear holds 0.0 °C, which
    /// is no value; one whose bit is unknown (the master's reply was lost) is not shown as
    /// one either.
    pub fn no_reading(&self, device: u8, reg: u8) -> bool {
        let bit = Target::of(device).and_then(|target| {
            let register = target.kind.register(reg)?;
            super::fresh::sensor_bit(target, register)
        });
        match (bit, self.raw(0, id::REGMASTER_TEMPSREAD)) {
            (Some(bit), Some(read)) => read & bit == 0,
            // The master's reply (and its TEMPSREAD) was lost: 0.0 °C may be no reading.
            (Some(_), None) => self.lost.contains(&0),
            (None, _) => false,
        }
    }
}

impl Poller {
    /// The ten reads of update(), with the library's standard sets; the master's set also
    /// holds REGMASTER_TEMPSREAD, so a sensor not read yet is not shown as 0.0 °C.
    pub fn new() -> Result<Poller, HostError> {
        Poller::for_pairs(Pairs::ALL)
    }

    /// [`Poller::new`] for the controllers of `pairs` and the master.
    pub fn for_pairs(pairs: Pairs) -> Result<Poller, HostError> {
        let mut reads = Vec::new();
        for device in pairs.devices().chain([0]) {
            let target = Target::of(device).ok_or(HostError::BadDevice {
                given: device.to_string(),
            })?;
            let set = set_of(target.kind);
            let extra: &[u8] = if device == 0 {
                &[id::REGMASTER_TEMPSREAD]
            } else {
                &[]
            };
            let regs = super::watch::standard_ids(set)
                .ok_or(HostError::NoStandardSet { set })?
                .iter()
                .chain(extra)
                .map(|&reg| resolve::register(target, &reg.to_string()))
                .collect::<Result<Vec<_>, _>>()?;
            reads.push(SetRead::new(target, set, regs)?);
        }
        Ok(Poller { reads })
    }

    /// init(): set 0 via controllers 3p+1 and 3p+2, set 1 via 3p+3 for each pair, then set 2
    /// via the master; each must be answered with its count.
    pub fn configure<P: Port>(&self, link: &mut Link<P>) -> Result<(), HostError> {
        for read in &self.reads {
            let set = set_of(read.target.kind);
            let frame = set_frame(read.target, set, &read.regs)?;
            configure(link, read.target, set, &frame, read.regs.len())?;
        }
        Ok(())
    }

    /// update(): reads every set in order.
    pub fn update<P: Port>(&self, link: &mut Link<P>) -> Result<Snapshot, HostError> {
        let mut rows = Vec::with_capacity(self.reads.len());
        let mut silent = Vec::new();
        let mut lost = Vec::new();
        for read in &self.reads {
            match read.read_for_view(link)? {
                Reading::Values(raws) => rows.push((
                    read.target.device,
                    read.regs.iter().map(|r| r.id).zip(raws).collect(),
                )),
                Reading::NoAnswer => silent.push(read.target.device),
                Reading::Lost => lost.push(read.target.device),
            }
        }
        Ok(Snapshot { rows, silent, lost })
    }
}

/// The demands a board has dropped: an exception sets its drive's required speed to 0 and a
/// position motor's to where it stands (reference §6.4), until a new demand is sent. So
/// does the board's leaving it (REG_RESET bit 0), for a demand sent while it was in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Dropped {
    /// Per wheel and motor, how many demands it had been sent when its board was last
    /// seen in exception.
    at: [[Option<u32>; 3]; 6],
    /// Per wheel and position motor, how many times each end of its calibration had been
    /// written when its board last did not answer: it may have rebooted, back on its boot
    /// calibration, until both ends are written again.
    calibration_at: [[Option<[u32; 2]>; 3]; 6],
    /// Per controller 1..9 (index 0 unused), whether it was last seen in its boot state
    /// (`None`: not read yet). A board seen out of it and then in it again has rebooted
    /// (a watchdog or power reset: the boot state is never raised otherwise) and is back
    /// on its boot calibration.
    in_boot: [Option<bool>; 10],
    /// Per controller 1..9, whether it has been seen out of its boot state this session:
    /// one seen back in it has rebooted, its demands and calibration gone.
    left_boot: [bool; 10],
    /// Per controller 1..9, whether it is in exception as far as this session knows: at
    /// first every one (opening the port rebooted the rover into its boot exception),
    /// then as each update reads it, or as a write to its REG_RESET changes it.
    held: [bool; 10],
}

impl Default for Dropped {
    /// A session's start: every controller in its boot exception.
    fn default() -> Self {
        Dropped {
            at: Default::default(),
            calibration_at: Default::default(),
            in_boot: Default::default(),
            left_boot: [false; 10],
            held: [true; 10],
        }
    }
}

impl Dropped {
    /// Notes a write the master acknowledged: every demand sent to a controller in
    /// exception is one it drops (the board replaces it at its updates, and as it leaves
    /// the exception); then a reset of `send`'s controller takes it out of its exception
    /// (bit 0) or reboots it into its boot exception (bit 1).
    pub fn note_sent(&mut self, send: &Send, pc: &Pc) {
        self.mark_held(pc);
        let held = &mut self.held[usize::from(send.device).min(9)];
        if send.hard_resets() {
            *held = true;
        } else if send.leaves_exception() {
            *held = false;
        }
    }

    /// Marks the demands sent so far to every controller in exception as dropped.
    fn mark_held(&mut self, pc: &Pc) {
        for wheel in WHEELS {
            for motor in [Motor::Drive, Motor::Steer, Motor::Lift] {
                if self.held[usize::from(device_of(wheel, motor))] {
                    let (w, m) = (usize::from(wheel - 1), motor.index());
                    self.at[w][m] = Some(pc.demand_sends(wheel, motor));
                }
            }
        }
    }

    /// Notes every motor whose board `s` shows in exception, and every position motor
    /// whose board did not answer or is seen to have rebooted.
    pub fn note(&mut self, s: &Snapshot, pc: &Pc) {
        let mut rebooted = [false; 10];
        for device in 1..=9u8 {
            // `None`: no STATUS read from it this update.
            let Some(now) = in_boot(s, device) else {
                continue;
            };
            let d = usize::from(device);
            rebooted[d] = self.in_boot[d] == Some(false) && now;
            self.in_boot[d] = Some(now);
            self.left_boot[d] |= !now;
            self.held[d] = slave_exception(s, device).is_some();
        }
        self.mark_held(pc);
        for wheel in WHEELS {
            for motor in [Motor::Drive, Motor::Steer, Motor::Lift] {
                let (w, m) = (usize::from(wheel - 1), motor.index());
                let device = device_of(wheel, motor);
                let lost = s.silent.contains(&device) || rebooted[usize::from(device)];
                if motor != Motor::Drive && lost {
                    self.calibration_at[w][m] = Some(pc.calibration_writes(wheel, motor));
                }
            }
        }
    }

    /// Whether controller `device` has been seen out of its boot state this session.
    pub fn left_boot(&self, device: u8) -> bool {
        self.left_boot
            .get(usize::from(device))
            .copied()
            .unwrap_or(false)
    }

    /// Whether `motor` of `wheel` reads in degrees: `pc` has it calibrated
    /// ([`Pc::calibrated`]), and both ends have been written again since its board last
    /// failed to answer (a board that drops off may have rebooted) or was seen to reboot.
    pub fn calibrated(&self, pc: &Pc, wheel: u8, motor: Motor) -> bool {
        let lost = self.calibration_at[usize::from(wheel - 1)][motor.index()];
        let writes = pc.calibration_writes(wheel, motor);
        pc.calibrated(wheel, motor)
            && lost.is_none_or(|at| at.iter().zip(writes).all(|(&a, b)| a != b))
    }

    /// Whether `pc`'s demand of `motor` of `wheel` is one its board has dropped.
    pub fn has(&self, pc: &Pc, wheel: u8, motor: Motor) -> bool {
        self.at[usize::from(wheel - 1)][motor.index()] == Some(pc.demand_sends(wheel, motor))
    }
}

/// The actual speed or position of `motor` of `wheel`, read from the snapshot: its board's
/// ACTUALSPEED or ACTUALPOS (lift ONE on odd wheels, TWO on even ones).
pub(crate) fn actual(s: &Snapshot, wheel: u8, motor: Motor) -> Option<f32> {
    s.value(device_of(wheel, motor), actual_register(wheel, motor))
}

/// The register [`actual`] reads.
fn actual_register(wheel: u8, motor: Motor) -> u8 {
    match motor {
        Motor::Drive => id::REGDS_DRIVE_ACTUALSPEED,
        Motor::Steer => id::REGDS_STEER_ACTUALPOS,
        Motor::Lift if wheel % 2 == 1 => id::REGLL_ONE_ACTUALPOS,
        Motor::Lift => id::REGLL_TWO_ACTUALPOS,
    }
}

/// [`actual`] for the view, as [`reading`] writes it.
fn actual_text(s: &Snapshot, wheel: u8, motor: Motor, decimals: usize) -> String {
    reading(
        s,
        device_of(wheel, motor),
        actual_register(wheel, motor),
        decimals,
    )
}

/// Which end of its range [`actual`] sits at, if it does ([`limit`]).
pub(crate) fn actual_limit(s: &Snapshot, wheel: u8, motor: Motor) -> Option<resolve::Limit> {
    limit(s, device_of(wheel, motor), actual_register(wheel, motor))
}

/// Which end of its range `reg` of `device` reads at, if it does: that end holds any
/// reading beyond it ([`resolve::limit_of`]).
fn limit(s: &Snapshot, device: u8, reg: u8) -> Option<resolve::Limit> {
    BoardKind::of_device(device)
        .and_then(|kind| kind.register(reg))
        .zip(s.raw(device, reg))
        .and_then(|(register, raw)| resolve::limit_of(register, raw))
}

/// The value of `reg` of `device` with `decimals` ("?" when not read), marked "≥" or "≤"
/// at its range's end, which holds any reading beyond it ([`limit`]).
fn reading(s: &Snapshot, device: u8, reg: u8, decimals: usize) -> String {
    let text = cell(s.value(device, reg), decimals);
    match limit(s, device, reg) {
        Some(limit) => format!("{}{text}", limit.sign()),
        None => text,
    }
}

/// A slave's exception as update() decodes it: its EXCEPTIONDATA while STATUS bit 0 is set.
pub(crate) fn slave_exception(s: &Snapshot, device: u8) -> Option<Exception> {
    let status = s.raw(device, id::REG_STATUS)?;
    if status & STATUS_EXCEPTION == 0 {
        return None;
    }
    Some(Exception::slave(device, s.raw(device, id::REG_EXCEPTIONDATA)?).held())
}

/// Whether `s` shows `device` in its boot state (in exception, type BOOT); `None` when
/// `s` has no STATUS of it.
fn in_boot(s: &Snapshot, device: u8) -> Option<bool> {
    s.raw(device, id::REG_STATUS)?;
    Some(slave_exception(s, device).is_some_and(|e| e.code == ExceptionType::Boot as u8))
}

/// The exception the view's column puts on `motor` of `wheel`, routed as the library
/// routes a board's (DS: motor 0 drive, 1 steer, other both; LL: 0 ONE, 1 TWO, other
/// both). The board stops both its motors whichever it names (reference §6.4).
fn motor_exception(s: &Snapshot, wheel: u8, motor: Motor) -> Option<Exception> {
    let e = slave_exception(s, device_of(wheel, motor))?;
    e.wheel_motor()
        .is_none_or(|named| named == (wheel, motor))
        .then_some(e)
}

/// One wheel's exceptions column: its controllers that did not answer, then its motors'
/// exceptions ("-": neither).
pub(crate) fn wheel_exceptions(s: &Snapshot, wheel: u8) -> String {
    // A controller off the bus comes first: its exceptions are not known.
    let mut words: Vec<String> = [Motor::Drive, Motor::Lift]
        .map(|m| device_of(wheel, m))
        .into_iter()
        .filter_map(|d| {
            if s.silent.contains(&d) {
                Some(format!("controller {d}: no answer"))
            } else if s.lost.contains(&d) {
                Some(format!("controller {d}: reply lost"))
            } else {
                None
            }
        })
        .collect();
    let exceptions = motor_exceptions(s, wheel);
    if exceptions != "-" || words.is_empty() {
        words.push(exceptions);
    }
    words.join("; ")
}

/// What `s` shows holding the rover stopped, in words: each controller in an exception
/// other than its boot state (one raised, or spread to it), back in its boot state after
/// `dropped` saw it out of it (rebooted), not answering or with its reply lost (its state
/// unknown); controllers in the same state share an entry, the ones a fault was spread to
/// after the others; then the master's exception other than boot. Empty when nothing does.
pub(crate) fn raised(s: &Snapshot, dropped: &Dropped) -> Vec<String> {
    let boot = ExceptionType::Boot as u8;
    // (words, controllers, spread to them).
    let mut states: Vec<(String, Vec<u8>, bool)> = Vec::new();
    for d in 1..=9u8 {
        let (words, spread) = if s.silent.contains(&d) {
            ("no answer".to_owned(), false)
        } else if s.lost.contains(&d) {
            ("reply lost, state unknown".to_owned(), false)
        } else {
            match slave_exception(s, d) {
                Some(e) if e.code != boot => {
                    (e.words(), e.code == ExceptionType::RemoteSlave as u8)
                }
                Some(_) if dropped.left_boot(d) => (
                    "rebooted: back in its boot state, its demands and calibration gone".to_owned(),
                    false,
                ),
                _ => continue,
            }
        };
        match states.iter_mut().find(|(w, _, _)| *w == words) {
            Some((_, devices, _)) => devices.push(d),
            None => states.push((words, vec![d], spread)),
        }
    }
    states.sort_by_key(|&(_, _, spread)| spread);
    let mut faults: Vec<String> = states
        .into_iter()
        .map(|(words, devices, _)| match devices.as_slice() {
            [d] => format!("controller {d}: {words}"),
            _ => {
                let list: Vec<String> = devices.iter().map(u8::to_string).collect();
                format!("controllers {}: {words}", list.join(", "))
            }
        })
        .collect();
    if s.lost.contains(&0) {
        faults.push("master: reply lost, state unknown".to_owned());
    } else if let Some(raw) = s.raw(0, id::REGMASTER_EXCEPTIONDATA) {
        let e = Exception::master(raw);
        if !e.is_none() && e.code != boot {
            faults.push(format!("master: {}", e.words()));
        }
    }
    faults
}

/// The exceptions of `wheel`'s three motors in words ("-": none; one name when all
/// three share it). A motor whose board is in an exception routed to its other motor is
/// stopped all the same (reference §6.4): `drive stall, steer stopped` on the row of the
/// motor named, `lift stopped (by wheel 2's lift stall)` on another wheel's row.
fn motor_exceptions(s: &Snapshot, wheel: u8) -> String {
    let words = |m: Motor| -> Option<String> {
        if let Some(e) = motor_exception(s, wheel, m) {
            return Some(e.type_name());
        }
        let e = slave_exception(s, device_of(wheel, m))?;
        Some(match e.wheel_motor()? {
            (w, _) if w == wheel => "stopped".to_owned(),
            (w, other) => format!(
                "stopped (by wheel {w}'s {} {})",
                other.name(),
                e.type_name()
            ),
        })
    };
    let parts: Vec<(Motor, String)> = [Motor::Drive, Motor::Steer, Motor::Lift]
        .into_iter()
        .filter_map(|m| Some((m, words(m)?)))
        .collect();
    match parts.as_slice() {
        [] => "-".to_owned(),
        [(_, a), (_, b), (_, c)] if a == b && b == c => a.clone(),
        _ => parts
            .iter()
            .map(|(m, t)| format!("{} {t}", m.name()))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// A demand as the required column shows it: "-" when none was sent this session (the
/// board then holds whatever it was last given, which this view cannot know), in
/// parentheses when an exception has dropped it.
fn demand(v: Option<f32>, decimals: usize, dropped: bool) -> String {
    match v {
        Some(v) if dropped => format!("({v:.decimals$})"),
        Some(v) => format!("{v:.decimals$}"),
        None => "-".to_owned(),
    }
}

fn cell(v: Option<f32>, decimals: usize) -> String {
    match v {
        Some(v) => {
            let text = format!("{v:.decimals$}");
            // A value that rounds to zero shows as 0, not -0.
            match text.strip_prefix('-') {
                Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
                _ => text,
            }
        }
        None => "?".to_owned(),
    }
}

/// The master's line of the view: its exception in words and its temperatures, or that its
/// reply was lost.
pub(crate) fn master_line(s: &Snapshot) -> String {
    if s.lost.contains(&0) {
        return "master: reply lost on the serial line (read again next update)".to_owned();
    }
    let data = s.raw(0, id::REGMASTER_EXCEPTIONDATA);
    let exception = match data.map(Exception::master) {
        None => "exception not read".to_owned(),
        Some(e) if e.is_none() => "no exception".to_owned(),
        Some(e) => format!("exception: {}", e.words()),
    };
    // A sensor the master has not read since boot (or cannot find) holds 0.0 °C, which
    // is no reading: shown as "-".
    let temp = |reg: u8| {
        if s.no_reading(0, reg) {
            "-".to_owned()
        } else {
            reading(s, 0, reg, 1)
        }
    };
    let ambient = temp(id::REGMASTER_TEMPAMBIENT);
    let temps: Vec<String> = (id::REGMASTER_TEMP1..=id::REGMASTER_TEMP9)
        .map(temp)
        .collect();
    let unread = if ambient == "-" || temps.iter().any(|t| t == "-") {
        " (- no reading: not read yet, one sensor every 2 s from 5 s after boot; missing; or its last read failed)"
    } else {
        ""
    };
    format!(
        "master: {exception}; °C ambient {ambient}, boards {}{unread}",
        temps.join(" ")
    )
}

/// The master's state for `--json`: `exception` (its EXCEPTIONDATA taken apart, null when
/// not read) and `temperatures` (`ambient` and nine `boards` in °C, null for no reading);
/// null as a whole when the serial line lost its reply.
pub(crate) fn master_json(s: &Snapshot) -> String {
    if s.lost.contains(&0) {
        return "null".to_owned();
    }
    let temp = |reg: u8| match s.value(0, reg) {
        Some(v) if !s.no_reading(0, reg) => v,
        _ => f32::NAN,
    };
    let boards =
        json::array((id::REGMASTER_TEMP1..=id::REGMASTER_TEMP9).map(|reg| json::number(temp(reg))));
    let exception = match s.raw(0, id::REGMASTER_EXCEPTIONDATA) {
        Some(raw) => Exception::master(raw).json(),
        None => "null".to_owned(),
    };
    let temperatures = json::Object::new()
        .num("ambient", temp(id::REGMASTER_TEMPAMBIENT))
        .raw("boards", &boards)
        .finish();
    json::Object::new()
        .raw("exception", &exception)
        .raw("temperatures", &temperatures)
        .finish()
}

/// The view: one row per wheel, required (the library's last demand) against actual (from
/// the slaves), then the master's state and the poll rate.
pub fn view_lines(
    s: &Snapshot,
    pc: &Pc,
    dropped: &Dropped,
    elapsed: Duration,
    updates: u64,
    rate: f64,
) -> Vec<String> {
    let mut table = Table {
        rows: Vec::new(),
        headers: vec![
            [
                "wheel",
                "drive req",
                "actual",
                "steer req",
                "actual",
                "lift req",
                "actual",
            ]
            .map(String::from)
            .to_vec(),
            ["", "ticks/s", "ticks/s", "°", "°", "°", "°"]
                .map(String::from)
                .to_vec(),
        ],
    };
    let mut exceptions = vec!["exceptions".to_owned(), String::new()];
    // A position on a pot scale that is not the wheel's is marked, not passed off as degrees.
    let mut uncalibrated = false;
    let mut position = |wheel: u8, motor: Motor| {
        let text = actual_text(s, wheel, motor, 1);
        if actual(s, wheel, motor).is_none() || dropped.calibrated(pc, wheel, motor) {
            text
        } else {
            uncalibrated = true;
            format!("{text}*")
        }
    };
    for wheel in pc.pairs().wheels() {
        table.rows.push(vec![
            wheel.to_string(),
            demand(
                pc.demand(wheel, Motor::Drive),
                0,
                dropped.has(pc, wheel, Motor::Drive),
            ),
            actual_text(s, wheel, Motor::Drive, 0),
            demand(
                pc.demand(wheel, Motor::Steer),
                1,
                dropped.has(pc, wheel, Motor::Steer),
            ),
            position(wheel, Motor::Steer),
            demand(
                pc.demand(wheel, Motor::Lift),
                1,
                dropped.has(pc, wheel, Motor::Lift),
            ),
            position(wheel, Motor::Lift),
        ]);
        exceptions.push(wheel_exceptions(s, wheel));
    }
    // The exceptions column is text: left-aligned after the table.
    let mut lines: Vec<String> = table
        .lines()
        .into_iter()
        .zip(exceptions)
        .map(|(row, exc)| format!("{row}  {exc}").trim_end().to_owned())
        .collect();
    let any_dropped = WHEELS.into_iter().any(|w| {
        [Motor::Drive, Motor::Steer, Motor::Lift]
            .into_iter()
            .any(|m| pc.demand(w, m).is_some() && dropped.has(pc, w, m))
    });
    if any_dropped {
        lines.push(
            "(…) dropped by an exception: the board aims for speed 0, a position holds where \
             it stood, until a new demand is sent"
                .to_owned(),
        );
    }
    if uncalibrated {
        lines.push(NOT_DEGREES.to_owned());
    }
    if !s.silent.is_empty() {
        lines.push(super::no_answer_legend(&s.silent));
    }
    if !s.lost.is_empty() {
        lines.push(super::reply_lost_legend(&s.lost));
    }
    let left_out: Vec<String> = WHEELS
        .filter(|&w| !pc.pairs().has_wheel(w))
        .map(|w| w.to_string())
        .collect();
    if !left_out.is_empty() {
        lines.push(format!(
            "wheels {} not fitted (--pairs): not polled",
            left_out.join(", ")
        ));
    }
    lines.push(master_line(s));
    lines.push(format!(
        "{:.1} s: {updates} updates, {rate:.1} update()/s (required = last demand sent, - none this session; actual = read from the boards)",
        elapsed.as_secs_f64()
    ));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snapshot() -> Snapshot {
        let ds = |status: u16, data: u16, speed: u16| {
            vec![
                (id::REG_STATUS, status),
                (id::REG_EXCEPTIONDATA, data),
                (id::REGDS_DRIVE_ACTUALSPEED, speed),
                (id::REGDS_STEER_ACTUALPOS, 0x9998),
            ]
        };
        let mut rows: Vec<(u8, Vec<(u8, u16)>)> = vec![
            (1, ds(0x0008, 0x0502, 0x9ffe)),
            (2, ds(0x0009, 0x0005, 0x7fff)),
            (4, ds(0x0009, 0x0502, 0x7fff)),
            (5, ds(0x0008, 0x0000, 0x7fff)),
            (7, ds(0x0008, 0x0000, 0x7fff)),
            (8, ds(0x0008, 0x0000, 0x7fff)),
        ];
        for ll in [3, 6, 9] {
            let status = if ll == 6 { 0x0005 } else { 0x0004 };
            rows.push((
                ll,
                vec![
                    (id::REG_STATUS, status),
                    (id::REG_EXCEPTIONDATA, 0x0502),
                    (id::REGLL_ONE_ACTUALPOS, 0x8ccb),
                    (id::REGLL_TWO_ACTUALPOS, 0x7fff),
                ],
            ));
        }
        rows.push((
            0,
            vec![
                (id::REGMASTER_EXCEPTIONDATA, 0x0205),
                (id::REGMASTER_TEMPAMBIENT, 0x5887),
            ],
        ));
        Snapshot::new(rows)
    }

    /// The view of [`snapshot`] for `pc`, two seconds and 50 updates in.
    fn view(pc: &Pc, dropped: &Dropped) -> Vec<String> {
        view_lines(&snapshot(), pc, dropped, Duration::from_secs(2), 50, 25.0)
    }

    #[test]
    fn view_shows_required_against_actual() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        pc.set_required(1, Motor::Drive, 1000.0).unwrap();
        pc.set_required(1, Motor::Lift, 20.0).unwrap();
        pc.set_required(2, Motor::Steer, 0.0).unwrap();
        let lines = view(&pc, &Dropped::default());
        assert_eq!(
            lines[0],
            "wheel  drive req   actual  steer req  actual  lift req  actual  exceptions"
        );
        assert_eq!(
            lines[2],
            "1           1000     1000          -    40.0      20.0    20.0  -"
        );
        // A demand not sent this session is "-", one sent as 0 is 0.
        // Controller 2 in exception with motor 0 (drive); controller 4 with no motor
        // (drive and steer) and LL 6 with no motor (wheel 3's lift); wheel 4's lift too.
        assert_eq!(
            lines[3],
            "2              -        0        0.0    40.0         -     0.0  drive stall, steer stopped"
        );
        assert_eq!(
            lines[4],
            "3              -        0          -    40.0         -    20.0  boot"
        );
        assert_eq!(
            lines[5],
            "4              -        0          -    40.0         -     0.0  lift boot"
        );
        assert_eq!(lines[6].trim_end().chars().last(), Some('-'));
        assert_eq!(
            lines[8],
            "master: exception: stall on controller 2, motor 0 (wheel 2's drive); °C ambient 21.5, boards ? ? ? ? ? ? ? ? ?"
        );
        assert!(lines[9].starts_with("2.0 s: 50 updates, 25.0 update()/s"));
    }

    #[test]
    fn a_motor_its_boards_exception_stops_says_by_what() {
        // LL board 9 in a stall of motor 1 (wheel 6's lift): wheel 5's lift, on the same
        // board, is stopped too (reference §6.4).
        let ll9 = vec![(id::REG_STATUS, 0x0005), (id::REG_EXCEPTIONDATA, 0x0105)];
        let running = vec![(id::REG_STATUS, 0x0008), (id::REG_EXCEPTIONDATA, 0)];
        let s = Snapshot::new(vec![(7, running.clone()), (8, running), (9, ll9)]);
        assert_eq!(
            motor_exceptions(&s, 5),
            "lift stopped (by wheel 6's lift stall)"
        );
        assert_eq!(motor_exceptions(&s, 6), "lift stall");
        assert_eq!(motor_exceptions(&s, 4), "-");
    }

    #[test]
    fn for_programs_each_motor_has_its_exception_and_the_master_its_state() {
        let s = snapshot();
        // Controller 2's stall on motor 0 holds wheel 2's drive, not its steer.
        assert_eq!(
            motor_exception(&s, 2, Motor::Drive).map(|e| e.json()),
            Some(
                r#"{"type":5,"name":"STALL","motor":0,"wheel":2,"wheel_motor":"drive","text":"stall, motor 0 (wheel 2's drive)"}"#
                    .to_owned()
            )
        );
        // The view's column routes it to the drive only, as the library does; for programs
        // the board's exception holds both its motors (the JSON's per-motor `exception`).
        assert_eq!(motor_exception(&s, 2, Motor::Steer), None);
        assert_eq!(
            slave_exception(&s, 2).map(|e| e.wheel_motor()),
            Some(Some((2, Motor::Drive)))
        );
        // Controller 4's boot (no motor) holds both of wheel 3's; LL 6's wheel 4's lift.
        for (wheel, motor) in [(3, Motor::Drive), (3, Motor::Steer), (4, Motor::Lift)] {
            let e = motor_exception(&s, wheel, motor).expect("in exception");
            assert_eq!((e.code, e.motor), (2, 5), "wheel {wheel} {motor:?}");
        }
        // Controller 1 is not in exception (STATUS bit 0 clear): its last type holds nothing.
        assert_eq!(motor_exception(&s, 1, Motor::Drive), None);
        assert_eq!(
            master_json(&s),
            r#"{"exception":{"type":5,"name":"STALL","controller":2,"motor":0,"wheel":2,"wheel_motor":"drive","text":"stall on controller 2, motor 0 (wheel 2's drive)"},"temperatures":{"ambient":21.498459,"boards":[null,null,null,null,null,null,null,null,null]}}"#
        );
        // A sensor with its TEMPSREAD bit clear holds no reading: null, not 0.0 °C.
        let mut master = vec![
            (id::REGMASTER_EXCEPTIONDATA, 0),
            (id::REGMASTER_TEMPAMBIENT, 0x5887),
            (id::REGMASTER_TEMPSREAD, 0b101),
        ];
        master.extend((id::REGMASTER_TEMP1..=id::REGMASTER_TEMP9).map(|r| (r, 0x2aaa)));
        let m = master_json(&Snapshot::new(vec![(0, master)]));
        assert!(m.ends_with(
            r#""temperatures":{"ambient":21.498459,"boards":[null,-0.00061035156,null,null,null,null,null,null,null]}}"#
        ), "{m}");
        // The master's reply lost: nothing known.
        let mut lost = Snapshot::new(Vec::new());
        lost.lost.push(0);
        assert_eq!(master_json(&lost), "null");
    }

    #[test]
    fn what_holds_the_rover_stopped_leaves_out_the_boot_state() {
        // Controller 2 in a stall, 4 and 6 in their boot state, the master holding the
        // stall it spread.
        let s = snapshot();
        assert_eq!(
            raised(&s, &Dropped::default()),
            [
                "controller 2: stall, motor 0 (wheel 2's drive)",
                "master: stall on controller 2, motor 0 (wheel 2's drive)"
            ]
        );
        // A controller silent or its reply lost: its state is in doubt.
        let mut doubt = Snapshot::new(vec![(0, vec![(id::REGMASTER_EXCEPTIONDATA, 2)])]);
        doubt.silent.push(5);
        doubt.lost.push(7);
        assert_eq!(
            raised(&doubt, &Dropped::default()),
            [
                "controller 5: no answer",
                "controller 7: reply lost, state unknown"
            ]
        );
        // Every board in its boot state, or out of exception: nothing.
        let boot = Snapshot::new(vec![
            (
                1,
                vec![(id::REG_STATUS, 9), (id::REG_EXCEPTIONDATA, 0x0502)],
            ),
            (
                3,
                vec![(id::REG_STATUS, 4), (id::REG_EXCEPTIONDATA, 0x0101)],
            ),
            (0, vec![(id::REGMASTER_EXCEPTIONDATA, 0)]),
        ]);
        assert!(raised(&boot, &Dropped::default()).is_empty());
        // The same boot state after the session saw controller 1 out of it: a reboot.
        let pc = Pc::new();
        let mut dropped = Dropped::default();
        dropped.note(
            &Snapshot::new(vec![(
                1,
                vec![(id::REG_STATUS, 8), (id::REG_EXCEPTIONDATA, 0x0502)],
            )]),
            &pc,
        );
        dropped.note(&boot, &pc);
        assert_eq!(
            raised(&boot, &dropped),
            ["controller 1: rebooted: back in its boot state, its demands and calibration gone"]
        );
        // A fault spread to the others: they share one entry, after the board that raised it.
        let mut rows = vec![(
            4,
            vec![(id::REG_STATUS, 9), (id::REG_EXCEPTIONDATA, 0x0008)],
        )];
        rows.extend([1, 2, 3].map(|d| {
            (
                d,
                vec![(id::REG_STATUS, 9), (id::REG_EXCEPTIONDATA, 0x0503)],
            )
        }));
        assert_eq!(
            raised(&Snapshot::new(rows), &Dropped::default()),
            [
                "controller 4: short (overcurrent at a duty of 250 or less: a short, or a blocked motor), motor 0 (wheel 3's drive)",
                "controllers 1, 2, 3: remote (EXCEPTIONDATA written: another board's fault \
                 spread by the master, or a PC), the whole board"
            ]
        );
    }

    #[test]
    fn a_sensor_not_read_yet_is_not_shown_as_zero_degrees() {
        // Ambient and controller 2 read; the others still hold 0.0 °C (raw 0x2aaa).
        let mut master = vec![
            (id::REGMASTER_EXCEPTIONDATA, 0),
            (id::REGMASTER_TEMPAMBIENT, 0x5887),
            (id::REGMASTER_TEMPSREAD, 0b101),
        ];
        master.extend((id::REGMASTER_TEMP1..=id::REGMASTER_TEMP9).map(|r| (r, 0x2aaa)));
        let s = Snapshot::new(vec![(0, master.clone())]);
        assert_eq!(
            master_line(&s),
            "master: no exception; °C ambient 21.5, boards - 0.0 - - - - - - - \
             (- no reading: not read yet, one sensor every 2 s from 5 s after boot; missing; or its last read failed)"
        );
        // At the register's ends a reading may be beyond them.
        let mut ends = master.clone();
        ends.retain(|&(r, _)| r != id::REGMASTER_TEMPAMBIENT && r != id::REGMASTER_TEMP1);
        ends.extend([
            (id::REGMASTER_TEMPAMBIENT, 0),
            (id::REGMASTER_TEMP1, 0xfffe),
        ]);
        ends.retain(|&(r, _)| r != id::REGMASTER_TEMPSREAD);
        ends.push((id::REGMASTER_TEMPSREAD, 0x3ff));
        assert!(master_line(&Snapshot::new(vec![(0, ends)]))
            .starts_with("master: no exception; °C ambient ≤-20.0, boards ≥100.0 0.0 "),);
        // Every sensor read: no legend.
        master.retain(|&(r, _)| r != id::REGMASTER_TEMPSREAD);
        master.push((id::REGMASTER_TEMPSREAD, 0x3ff));
        assert_eq!(
            master_line(&Snapshot::new(vec![(0, master)])),
            "master: no exception; °C ambient 21.5, boards 0.0 0.0 0.0 0.0 0.0 0.0 0.0 0.0 0.0"
        );
    }

    #[test]
    fn an_actual_at_its_ranges_end_is_marked_with_that_end() {
        // Wheel 1: drive and steer on controller 1, lift on controller 3 (its motor ONE).
        let s = Snapshot::new(vec![
            (
                1,
                vec![
                    (id::REGDS_DRIVE_ACTUALSPEED, 0xfffe),
                    (id::REGDS_STEER_ACTUALPOS, 0x8000),
                ],
            ),
            (3, vec![(id::REGLL_ONE_ACTUALPOS, 0)]),
        ]);
        assert_eq!(
            actual_limit(&s, 1, Motor::Drive),
            Some(resolve::Limit::Upper)
        );
        assert_eq!(actual_limit(&s, 1, Motor::Steer), None);
        assert_eq!(
            actual_limit(&s, 1, Motor::Lift),
            Some(resolve::Limit::Lower)
        );
        // Not read: no end to be at.
        assert_eq!(actual_limit(&s, 2, Motor::Drive), None);
        // The text view marks the same two.
        assert_eq!(actual_text(&s, 1, Motor::Drive, 0), "≥4000");
        assert_eq!(actual_text(&s, 1, Motor::Steer, 1), "0.0");
        assert_eq!(actual_text(&s, 1, Motor::Lift, 1), "≤-200.0");
    }

    #[test]
    fn a_demand_dropped_by_an_exception_is_shown_so() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        pc.set_required(2, Motor::Drive, 500.0).unwrap();
        pc.set_required(1, Motor::Drive, 1000.0).unwrap();
        // Controller 2 (wheel 2's drive and steer) is in exception; controller 1 is not.
        let mut dropped = Dropped::default();
        dropped.note(&snapshot(), &pc);
        let lines = view(&pc, &dropped);
        assert!(lines[2].starts_with("1           1000 "), "{}", lines[2]);
        assert!(lines[3].starts_with("2          (500) "), "{}", lines[3]);
        assert!(lines
            .iter()
            .any(|l| l.starts_with("(…) dropped by an exception")));
        // A new demand is in force again.
        pc.set_required(2, Motor::Drive, 600.0).unwrap();
        let lines = view(&pc, &dropped);
        assert!(lines[3].starts_with("2            600 "), "{}", lines[3]);
        assert!(!lines.iter().any(|l| l.starts_with("(…)")));
    }

    /// Notes `op`'s frame as sent, as a run does once the master acknowledged it.
    fn sent(dropped: &mut Dropped, op: &super::super::pc::Op, pc: &Pc) {
        if let super::super::pc::Op::Write(send) = op {
            dropped.note_sent(send, pc);
        }
    }

    #[test]
    fn a_demand_sent_before_the_reset_is_shown_dropped_and_one_after_it_in_force() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        let mut dropped = Dropped::default();
        // At the session's start every board is in its boot exception, seen or not.
        let op = pc.set_required(1, Motor::Drive, 500.0).unwrap();
        sent(&mut dropped, &op, &pc);
        for op in super::super::pc::reset_exceptions_of(Pairs::ALL).unwrap() {
            sent(&mut dropped, &op, &pc);
        }
        let lines = view(&pc, &dropped);
        assert!(lines[2].starts_with("1          (500) "), "{}", lines[2]);
        // After the reset a demand is in force.
        let op = pc.set_required(1, Motor::Drive, 600.0).unwrap();
        sent(&mut dropped, &op, &pc);
        let lines = view(&pc, &dropped);
        assert!(lines[2].starts_with("1            600 "), "{}", lines[2]);
        // A hard reset reboots the board into its boot exception: a demand sent then is
        // dropped.
        let hard = Send {
            device: 1,
            frame: vec![5, 0x12, 1, id::REG_RESET, 2],
            what: "REG_RESET",
        };
        dropped.note_sent(&hard, &pc);
        let op = pc.set_required(1, Motor::Drive, 700.0).unwrap();
        sent(&mut dropped, &op, &pc);
        let lines = view(&pc, &dropped);
        assert!(lines[2].starts_with("1          (700) "), "{}", lines[2]);
    }

    #[test]
    fn a_reply_the_line_lost_shows_as_lost_not_as_values_or_silence() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        // Controller 1's and the master's replies were lost this update.
        let mut s = snapshot();
        s.rows.retain(|(d, _)| *d != 1 && *d != 0);
        s.lost = vec![1, 0];
        let lines = view_lines(
            &s,
            &pc,
            &Dropped::default(),
            Duration::from_secs(2),
            50,
            25.0,
        );
        assert_eq!(
            lines[2],
            "1              -        ?          -       ?         -    20.0  controller 1: reply lost"
        );
        assert!(
            lines.contains(
                &"reply lost: the serial line lost or garbled the read of devices 1, 0 this round, \
                  the request on its way to the master or the reply on its way back (the master \
                  still answers); read again next round; the view stops if one read loses 4 \
                  in a row"
                    .to_owned()
            ),
            "{lines:#?}"
        );
        assert!(
            !lines.iter().any(|l| l.contains("no answer")),
            "a lost reply is no silent controller: {lines:#?}"
        );
        // The master's state is not passed off as "no exception", nor an unread 0.0 °C in a
        // `show` set as a temperature.
        assert!(
            lines.contains(
                &"master: reply lost on the serial line (read again next update)".to_owned()
            ),
            "{lines:#?}"
        );
        assert!(s.no_reading(0, id::REGMASTER_TEMP1));
        assert!(
            !snapshot().no_reading(0, id::REGMASTER_TEMP1),
            "TEMPSREAD not in the set"
        );
        // A lost reply says nothing of a reboot: the calibration stands.
        let mut dropped = Dropped::default();
        dropped.note(&s, &pc);
        assert!(dropped.calibrated(&pc, 1, Motor::Steer));
    }

    #[test]
    fn a_board_that_did_not_answer_is_not_taken_as_calibrated_until_both_ends_are_sent_again() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        let mut dropped = Dropped::default();
        dropped.note(&snapshot(), &pc);
        assert!(dropped.calibrated(&pc, 1, Motor::Steer));
        // Controller 1 (wheel 1's drive and steer) misses an update: it may have rebooted.
        let silent = Snapshot {
            silent: vec![1],
            ..snapshot()
        };
        dropped.note(&silent, &pc);
        assert!(!dropped.calibrated(&pc, 1, Motor::Steer));
        assert!(
            dropped.calibrated(&pc, 1, Motor::Drive),
            "a speed has no pot"
        );
        assert!(
            dropped.calibrated(&pc, 1, Motor::Lift),
            "controller 3 answered"
        );
        assert!(dropped.calibrated(&pc, 2, Motor::Steer));
        // One end written again is not enough; both are.
        let min = BoardKind::DriveSteer
            .register(id::REGDS_STEER_CALIBMIN)
            .unwrap();
        pc.note_write(1, min.id, mapping::map(-56.0, min), -56.0);
        assert!(!dropped.calibrated(&pc, 1, Motor::Steer));
        pc.calibrate().unwrap();
        assert!(dropped.calibrated(&pc, 1, Motor::Steer));
    }

    #[test]
    fn a_board_seen_back_in_its_boot_state_is_not_taken_as_calibrated() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        // `snapshot()` shows controller 4 (wheel 3's drive and steer) in its boot state and
        // controller 1 (wheel 1's) out of exception.
        let booting = |device: u8| {
            let mut s = snapshot();
            for (d, regs) in &mut s.rows {
                if *d == device {
                    for (reg, raw) in regs.iter_mut() {
                        match *reg {
                            id::REG_STATUS => *raw = 0x0009,
                            id::REG_EXCEPTIONDATA => *raw = 0x0502,
                            _ => {}
                        }
                    }
                }
            }
            s
        };
        let mut dropped = Dropped::default();
        dropped.note(&snapshot(), &pc);
        // Seen in it from the first look: as after power-up, not a reboot.
        assert!(dropped.calibrated(&pc, 3, Motor::Steer));
        // Controller 1, out of exception, is next seen in its boot state: it rebooted.
        dropped.note(&booting(1), &pc);
        assert!(!dropped.calibrated(&pc, 1, Motor::Steer));
        assert!(
            dropped.calibrated(&pc, 3, Motor::Steer),
            "still in boot: no change"
        );
        assert!(
            dropped.calibrated(&pc, 1, Motor::Lift),
            "controller 3 did not reboot"
        );
        // Staying in its boot state is no second reboot: calibrating again is enough.
        dropped.note(&booting(1), &pc);
        pc.calibrate().unwrap();
        dropped.note(&booting(1), &pc);
        assert!(dropped.calibrated(&pc, 1, Motor::Steer));
        // A board in another exception (controller 2, wheel 2's drive and steer: type 5)
        // that is then seen in its boot state rebooted too.
        assert!(dropped.calibrated(&pc, 2, Motor::Steer));
        dropped.note(&booting(2), &pc);
        assert!(!dropped.calibrated(&pc, 2, Motor::Steer));
        // A round in which a board is not read tells nothing.
        let unread = Snapshot {
            rows: snapshot()
                .rows
                .into_iter()
                .filter(|(d, _)| *d != 5)
                .collect(),
            ..snapshot()
        };
        dropped.note(&unread, &pc);
        dropped.note(&booting(5), &pc);
        assert!(
            !dropped.calibrated(&pc, 4, Motor::Steer),
            "5 was last seen out of it"
        );
    }

    #[test]
    fn positions_off_the_wheels_calibration_are_marked() {
        let mut pc = Pc::new();
        let lines = view(&pc, &Dropped::default());
        assert_eq!(
            lines[2],
            "1              -     1000          -   40.0*         -   20.0*  -"
        );
        let legend = "* not degrees: the board's pot calibration is not the wheel's (no \
                      `calibrate` since the port opened; or since then a `stop`, which sends \
                      -100/100, a write to its CALIBMIN or CALIBMAX, a hard reset, a \
                      reboot seen (back in its boot state after being out of it), or a time \
                      it did not answer and may have rebooted)";
        assert_eq!(lines[8], legend);
        pc.calibrate().unwrap();
        let lines = view(&pc, &Dropped::default());
        assert!(!lines.iter().any(|l| l.contains('*')), "{lines:#?}");
        // A write of 70° to wheel 1's steer CALIBMAX leaves only that position off its
        // calibration.
        let max = BoardKind::DriveSteer
            .register(id::REGDS_STEER_CALIBMAX)
            .unwrap();
        pc.note_write(1, max.id, mapping::map(70.0, max), 70.0);
        let lines = view(&pc, &Dropped::default());
        assert_eq!(
            lines[2],
            "1              -     1000          -   40.0*         -    20.0  -"
        );
        assert_eq!(
            lines.iter().filter(|l| l.contains('*')).count(),
            2,
            "{lines:#?}"
        );
        assert_eq!(lines[8], legend);
        pc.calibrate().unwrap();
        // After the operator's stop the calibration is -100/100 again.
        pc.emergency_stop().unwrap();
        let lines = view(&pc, &Dropped::default());
        assert_eq!(lines[8], legend);
    }
}
