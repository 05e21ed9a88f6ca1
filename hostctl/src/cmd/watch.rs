//! `hostctl watch --readset N [--device D] [--count K] [--interval-ms MS] [REG...]`:
//! poll a read set and show it live.
//!
//! With registers named, set N is (re)configured with them first. Without,
//! sets 0, 1 and 2 get the contents the original PC library gives them
//! (reference §4.3) and any other set is refused. The default devices are
//! all DS boards for set 0, all LL boards for set 1 and the master otherwise.
//!
//! When the master's row holds temperatures, REGMASTER_TEMPSREAD is read beside it through
//! another set (the watched set keeps the library's contents), so a sensor the master has
//! not read yet shows as "-", not as 0.0 °C.
//!
//! A controller the master reports off the bus (NoAnswer) shows as "no answer" and is read
//! again each round; the watch goes on with the others. So does a reply the serial line
//! loses ("reply lost"), a few in a row at most ([`crate::link::Link::forgive`]).

use std::time::Duration;

use shared::regs::{id, BoardKind, Register};

use super::read::SCRATCH_SET;
use super::run::{sleep_unless_interrupted, Clock};
use super::{fresh, Frame, Reading, SetRead};
use crate::error::HostError;
use crate::interrupt::CLOSES;
use crate::json;
use crate::link::Link;
use crate::meaning::Meaning;
use crate::port::Port;
use crate::resolve::{self, Target};
use crate::table::Table;

/// Arguments of `watch`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Read set to poll, 0..7.
    #[arg(long, value_name = "N")]
    pub readset: String,
    /// The devices to poll: a number, a list (`1,4,7`) or every board of a kind (`ds`,
    /// `ll`) [default: DS boards for set 0, LL boards for set 1, else the master].
    #[arg(long, value_name = "D[,D…]")]
    pub device: Option<String>,
    /// Stop after this many rounds [default: run until interrupted]. Exit status 3 when
    /// the last round lacks a device's values (no answer, or a reply lost).
    #[arg(long, value_name = "K")]
    pub count: Option<u64>,
    /// Pause between rounds, in milliseconds (at most an hour).
    #[arg(
        long,
        value_name = "MS",
        default_value_t = 500,
        value_parser = clap::value_parser!(u64).range(..=crate::cli::MAX_INTERVAL_MS)
    )]
    pub interval_ms: u64,
    /// Registers to put in the set first (names or numbers, at most 24).
    #[arg(value_name = "REG")]
    pub registers: Vec<String>,
}

/// A standard read set of the original PC library: its board kind and ids.
struct Standard {
    kind: BoardKind,
    ids: &'static [u8],
}

/// The original PC library's read sets 0, 1 and 2 (reference §4.3).
fn standard(set: u8) -> Option<Standard> {
    use shared::regs::id::*;
    match set {
        0 => Some(Standard {
            kind: BoardKind::DriveSteer,
            ids: &[
                REG_TIMER,
                REG_INTERVALI2C,
                REG_STATUS,
                REG_EXCEPTIONDATA,
                REGDS_CHASSIS,
                REGDS_DRIVE_ACTUALSPEED,
                REGDS_DRIVE_ERROR,
                REGDS_DRIVE_ERRORINTEGRAL,
                REGDS_DRIVE_ERRORDERIV,
                REGDS_DRIVE_CONTROL,
                REGDS_DRIVE_INTERVALCTRL,
                REGDS_DRIVE_CURRENT,
                REGDS_DRIVE_ODO,
                REGDS_STEER_ACTUALPOS,
                REGDS_STEER_ERROR,
                REGDS_STEER_ERRORINTEGRAL,
                REGDS_STEER_ERRORDERIV,
                REGDS_STEER_CONTROL,
                REGDS_STEER_INTERVALCTRL,
                REGDS_STEER_CURRENT,
            ],
        }),
        1 => Some(Standard {
            kind: BoardKind::LiftLift,
            ids: &[
                REG_TIMER,
                REG_INTERVALI2C,
                REG_STATUS,
                REG_EXCEPTIONDATA,
                REGLL_ONE_ACTUALPOS,
                REGLL_ONE_ERROR,
                REGLL_ONE_ERRORINTEGRAL,
                REGLL_ONE_ERRORDERIV,
                REGLL_ONE_CONTROL,
                REGLL_ONE_INTERVALCTRL,
                REGLL_ONE_CURRENT,
                REGLL_TWO_ACTUALPOS,
                REGLL_TWO_ERROR,
                REGLL_TWO_ERRORINTEGRAL,
                REGLL_TWO_ERRORDERIV,
                REGLL_TWO_CONTROL,
                REGLL_TWO_INTERVALCTRL,
                REGLL_TWO_CURRENT,
            ],
        }),
        2 => Some(Standard {
            kind: BoardKind::Master,
            ids: &[
                REGMASTER_TEMPAMBIENT,
                REGMASTER_TEMP1,
                REGMASTER_TEMP2,
                REGMASTER_TEMP3,
                REGMASTER_TEMP4,
                REGMASTER_TEMP5,
                REGMASTER_TEMP6,
                REGMASTER_TEMP7,
                REGMASTER_TEMP8,
                REGMASTER_TEMP9,
                REGMASTER_EXCEPTIONDATA,
            ],
        }),
        _ => None,
    }
}

/// The ids of standard set `set` (0, 1 or 2), in the original library's order.
pub(crate) fn standard_ids(set: u8) -> Option<&'static [u8]> {
    standard(set).map(|s| s.ids)
}

/// The devices polled when `--device` is not given.
fn default_devices(set: u8) -> Vec<u8> {
    let kind = match set {
        0 => BoardKind::DriveSteer,
        1 => BoardKind::LiftLift,
        _ => BoardKind::Master,
    };
    (0..=shared::protocol::MAX_DEVICE)
        .filter(|&d| BoardKind::of_device(d) == Some(kind))
        .collect()
}

/// The devices `--device` names: a number, several separated by commas (`1,4,7`), or
/// every board of a kind (`ds`, `ll`, any case), in the order given, each once.
fn devices(text: &str) -> Result<Vec<Target>, HostError> {
    let mut targets: Vec<Target> = Vec::new();
    for part in text.split(',').map(str::trim) {
        let kind = [BoardKind::DriveSteer, BoardKind::LiftLift]
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(part));
        let named = match kind {
            Some(kind) => (1..=shared::protocol::MAX_DEVICE)
                .filter(|&d| BoardKind::of_device(d) == Some(kind))
                .filter_map(Target::of)
                .collect(),
            None => vec![resolve::device(part)?],
        };
        for target in named {
            if !targets.contains(&target) {
                targets.push(target);
            }
        }
    }
    Ok(targets)
}

/// Refuses reads whose registers are not `first`'s: the set is configured once, with
/// `first`'s ids, and each device reads those ids on its own table, where the same name
/// may be another id (EXCEPTIONDATA) and the same id another register (id 9 on a DS and an
/// LL board).
fn same_registers(first: &SetRead, reads: &[SetRead]) -> Result<(), HostError> {
    let names = |read: &SetRead| {
        read.regs
            .iter()
            .map(|r| format!("{} ({})", r.name, r.id))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match reads.iter().find(|read| read.regs != first.regs) {
        None => Ok(()),
        Some(other) => Err(HostError::MixedSet {
            first: first.target.device,
            first_board: first.target.board(),
            first_regs: names(first),
            other: other.target.device,
            other_board: other.target.board(),
            other_regs: names(other),
        }),
    }
}

/// REGMASTER_TEMPSREAD, read through a set of its own beside the watched one.
#[derive(Debug)]
pub struct TempsRead {
    /// The set it is put in.
    pub set: u8,
    /// The configuring frame.
    pub set_frame: Frame,
    /// Its read.
    pub read: SetRead,
}

/// A checked watch, ready to run.
#[derive(Debug)]
pub struct Plan {
    /// The set polled.
    pub set: u8,
    /// The configuring frame, sent once before polling (via the first device).
    pub set_frame: Frame,
    /// One read per device, in row order.
    pub reads: Vec<SetRead>,
    /// The read of REGMASTER_TEMPSREAD, when the master's row holds temperatures.
    pub temps_read: Option<Box<TempsRead>>,
    /// Rounds to run, or `None` for no limit.
    pub count: Option<u64>,
    /// Pause between rounds.
    pub interval: Duration,
}

/// Checks the arguments and builds the frames; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let set = resolve::set(&args.readset)?;
    // Opening the port resets the rover, so refuse a watch that would show nothing.
    if args.count == Some(0) {
        return Err(HostError::ZeroCount);
    }
    let targets: Vec<Target> = match &args.device {
        Some(text) => devices(text)?,
        None => default_devices(set)
            .into_iter()
            .filter_map(Target::of)
            .collect(),
    };
    let mut reads = Vec::new();
    for &target in &targets {
        let regs = if args.registers.is_empty() {
            standard_regs(set, target)?
        } else {
            resolve::read_set(target, &args.registers)?
        };
        reads.push(SetRead::new(target, set, regs)?);
    }
    let first = reads.first().ok_or(HostError::NoStandardSet { set })?;
    same_registers(first, &reads)?;
    let set_frame = super::set_frame(first.target, set, &first.regs)?;
    let temps_read = temps_read_of(set, &reads)?;
    Ok(Plan {
        set,
        set_frame,
        reads,
        temps_read,
        count: args.count,
        interval: Duration::from_millis(args.interval_ms),
    })
}

/// The read of REGMASTER_TEMPSREAD for the master's row, if it holds a temperature: through
/// the scratch set, or set 6 when set 7 is the one watched (every set is empty after the
/// port's open, so neither holds anything of the user's).
fn temps_read_of(set: u8, reads: &[SetRead]) -> Result<Option<Box<TempsRead>>, HostError> {
    let Some(master) = reads.iter().find(|r| {
        r.regs
            .iter()
            .any(|reg| fresh::sensor_bit(r.target, reg).is_some())
    }) else {
        return Ok(None);
    };
    let other = if set == SCRATCH_SET { 6 } else { SCRATCH_SET };
    let reg = resolve::register(master.target, &id::REGMASTER_TEMPSREAD.to_string())?;
    Ok(Some(Box::new(TempsRead {
        set: other,
        set_frame: super::set_frame(master.target, other, &[reg])?,
        read: SetRead::new(master.target, other, vec![reg])?,
    })))
}

/// The standard contents of `set`, looked up on `target`'s table.
fn standard_regs(set: u8, target: Target) -> Result<Vec<&'static Register>, HostError> {
    let std = standard(set).ok_or(HostError::NoStandardSet { set })?;
    if std.kind != target.kind {
        return Err(HostError::StandardSetMismatch {
            set,
            wanted: std.kind.name(),
            device: target.device,
            board: target.board(),
            devices: resolve::devices_of(std.kind),
        });
    }
    std.ids
        .iter()
        .map(|&id| resolve::register(target, &id.to_string()))
        .collect()
}

/// One device's values in one round.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The device read.
    pub target: Target,
    /// Its registers, in set order.
    pub regs: Vec<&'static Register>,
    /// Their raw values, or why there are none this round.
    pub reading: Reading,
    /// The master's REGMASTER_TEMPSREAD, read beside a row of temperatures.
    pub temps_read: Option<u16>,
}

impl Row {
    /// Whether the register holds a reading: `Some(false)` for a temperature the master has
    /// not read since boot, `None` where that is not known or does not apply.
    fn is_reading(&self, reg: &Register) -> Option<bool> {
        let bit = fresh::sensor_bit(self.target, reg)?;
        Some(self.temps_read? & bit != 0)
    }
}

/// One poll of every device.
#[derive(Debug, Clone, PartialEq)]
pub struct Round {
    /// 1 for the first round.
    pub number: u64,
    /// The set polled.
    pub set: u8,
    /// One row per device.
    pub rows: Vec<Row>,
}

/// Configures the set, then polls it, handing each round to `on_round`; waits between
/// rounds on `clock`. Ctrl-C (or SIGTERM) ends the watch after the round it is in.
pub fn run<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    clock: &mut dyn Clock,
    on_round: &mut dyn FnMut(&Round) -> Result<(), HostError>,
) -> Result<(), HostError> {
    configure_sets(plan, link, |_| true)?;
    let mut number = 0;
    let mut unread = Vec::new();
    while plan.count.is_none_or(|k| number < k) {
        if number > 0 {
            sleep_unless_interrupted(clock, plan.interval);
        }
        if let Some(signal) = clock.interrupted_by() {
            let at = if number == 0 {
                format!("before the first round{CLOSES}")
            } else {
                format!("after round {number}; the last round above is the rover as it was then{CLOSES}")
            };
            return Err(HostError::Interrupted {
                signal,
                at,
                line: None,
            });
        }
        number += 1;
        let mut rows = Vec::with_capacity(plan.reads.len());
        for read in &plan.reads {
            let reading = read.read_for_view(link)?;
            restore_scratch(plan, link)?;
            rows.push(Row {
                target: read.target,
                regs: read.regs.clone(),
                reading,
                temps_read: None,
            });
        }
        if let Some(t) = &plan.temps_read {
            let bits = t.read.read_for_view(link)?;
            restore_scratch(plan, link)?;
            for row in rows.iter_mut().filter(|r| r.target == t.read.target) {
                match bits.values() {
                    Some(bits) => row.temps_read = bits.first().copied(),
                    // Without TEMPSREAD a 0.0 °C could pass for a reading: the row is lost.
                    None => row.reading = Reading::Lost,
                }
            }
        }
        unread = rows
            .iter()
            .filter(|r| r.reading.values().is_none())
            .map(|r| r.target.device)
            .collect();
        on_round(&Round {
            number,
            set: plan.set,
            rows,
        })?;
    }
    // A watch that ends (--count) without some device's values says so in its status, as
    // a script that ends with a controller not answering does.
    if unread.is_empty() {
        Ok(())
    } else {
        Err(HostError::WatchEndedUnread { devices: unread })
    }
}

/// Configures again whichever of the plan's sets is the scratch set, when a read that
/// failed was followed by a probe of the master's error registers through it
/// ([`Link::take_scratch_clobbered`]).
fn restore_scratch<P: Port>(plan: &Plan, link: &mut Link<P>) -> Result<(), HostError> {
    if link.take_scratch_clobbered() {
        configure_sets(plan, link, |set| set == SCRATCH_SET)?;
    }
    Ok(())
}

/// Configures the plan's sets that `which` picks: the watched one (through its first
/// device) and the one holding TEMPSREAD.
fn configure_sets<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    which: impl Fn(u8) -> bool,
) -> Result<(), HostError> {
    if let Some(first) = plan.reads.first().filter(|_| which(plan.set)) {
        super::configure(
            link,
            first.target,
            plan.set,
            &plan.set_frame,
            first.regs.len(),
        )?;
    }
    if let Some(t) = plan.temps_read.as_deref().filter(|t| which(t.set)) {
        super::configure(link, t.read.target, t.set, &t.set_frame, 1)?;
    }
    Ok(())
}

/// The round as lines for people: a title, then a table with one row per
/// device and a column per register (name over unit). A controller's position is on its
/// boot calibration (the port's open rebooted it): its unit is marked, with a legend.
pub fn table_lines(round: &Round) -> Vec<String> {
    let mut table = Table::default();
    let mut boot_scale = false;
    if let Some(first) = round.rows.first() {
        let mut names = vec!["dev".to_owned()];
        let mut units = vec![String::new()];
        for reg in &first.regs {
            names.push(reg.short_name().to_owned());
            if first.target.device != 0 && super::fresh::on_calibrated_scale(reg) {
                boot_scale = true;
                units.push(format!("{}*", reg.unit));
            } else {
                units.push(reg.unit.to_owned());
            }
        }
        table.headers = vec![names, units];
    }
    let mut unread = false;
    let mut boot_end = false;
    let mut silent = Vec::new();
    let mut lost = Vec::new();
    let mut coded = Legend::default();
    for row in &round.rows {
        let mut cells = vec![row.target.device.to_string()];
        let raws = match &row.reading {
            Reading::Values(raws) => raws,
            Reading::NoAnswer => {
                silent.push(row.target.device);
                cells.push("no answer".to_owned());
                table.rows.push(cells);
                continue;
            }
            Reading::Lost => {
                lost.push(row.target.device);
                cells.push("reply lost".to_owned());
                table.rows.push(cells);
                continue;
            }
        };
        let in_exception = row.target.device != 0
            && row.regs.iter().zip(raws).any(|(reg, raw)| {
                reg.id == id::REG_STATUS && raw & crate::meaning::STATUS_EXCEPTION != 0
            });
        cells.extend(row.regs.iter().zip(raws).map(|(&reg, &raw)| {
            if row.is_reading(reg) == Some(false) {
                unread = true;
                "-".to_owned()
            } else if row.target.device != 0 && fresh::is_boot_calibration_end(reg, raw) {
                // A calibration end as a board fresh from boot shows it: it uses ±512.
                boot_end = true;
                format!("{}*", resolve::show(reg, raw))
            } else {
                if let Some(m) = Meaning::of(row.target.device, reg, raw) {
                    // EXCEPTIONDATA beside a STATUS with its bit 0 set is the exception
                    // the board is in now.
                    let m = if in_exception { m.held() } else { m };
                    coded.add(reg, raw, m.words(), row.target.device);
                }
                resolve::show(reg, raw)
            }
        }));
        table.rows.push(cells);
    }
    let mut lines = vec![format!("read set {}, round {}", round.set, round.number)];
    lines.extend(table.lines());
    let columns: Vec<&Register> = round
        .rows
        .first()
        .map(|row| row.regs.clone())
        .unwrap_or_default();
    lines.extend(coded.lines(round.rows.len(), &columns));
    if boot_scale {
        lines.push(
            "* not degrees: opening the port rebooted the rover, so the boards are on their \
             boot calibration (pot 0..1023 as -512..512)"
                .to_owned(),
        );
    }
    if boot_end {
        lines.push(
            "* a calibration end at its register's end: not what the board uses, which is \
             -512..512 from boot until CALIBMIN and CALIBMAX are written"
                .to_owned(),
        );
    }
    if unread {
        lines.push(format!("- no reading: {}", fresh::NOT_READ));
    }
    if !silent.is_empty() {
        lines.push(super::no_answer_legend(&silent));
    }
    if !lost.is_empty() {
        lines.push(super::reply_lost_legend(&lost));
    }
    lines
}

/// The coded values of a round in words ([`Meaning`]), one line per register and value
/// (the value also in hex, as the layouts are given), naming the devices that hold it when
/// the table has more than one row; grouped by register, in the table's column order.
#[derive(Default)]
struct Legend {
    /// (register, raw, words, devices), in the order first met.
    entries: Vec<(&'static Register, u16, String, Vec<u8>)>,
}

impl Legend {
    fn add(&mut self, reg: &'static Register, raw: u16, words: String, device: u8) {
        match self
            .entries
            .iter_mut()
            .find(|(g, r, w, _)| *g == reg && *r == raw && *w == words)
        {
            Some((_, _, _, devices)) => devices.push(device),
            None => self.entries.push((reg, raw, words, vec![device])),
        }
    }

    fn lines(&self, rows: usize, columns: &[&Register]) -> Vec<String> {
        let column = |reg: &Register| columns.iter().position(|c| *c == reg);
        let mut entries: Vec<_> = self.entries.iter().collect();
        entries.sort_by_key(|(reg, ..)| column(reg));
        entries
            .into_iter()
            .map(|(reg, raw, words, devices)| {
                let value = format!(
                    "{} {raw} = 0x{raw:0width$x}",
                    reg.short_name(),
                    width = usize::from(reg.size) * 2
                );
                if rows > 1 {
                    let list: Vec<String> = devices.iter().map(u8::to_string).collect();
                    format!("{value} (dev {}): {words}", list.join(", "))
                } else {
                    format!("{value}: {words}")
                }
            })
            .collect()
    }
}

/// The round as JSON lines: one object per device, each with `"command":"watch"` as
/// every other command's lines have their command's name.
pub fn json_lines(round: &Round) -> Vec<String> {
    round
        .rows
        .iter()
        .map(|row| {
            // `values` null: the controller did not answer (`no_answer`), or its reply was
            // lost (`reply_lost`).
            let values = match &row.reading {
                Reading::Values(raws) => {
                    json::array(row.regs.iter().zip(raws).map(|(&reg, &raw)| {
                        let object = fresh::register_json(
                            json::Object::new(),
                            row.target.device,
                            reg,
                            raw,
                            row.is_reading(reg),
                        );
                        // As `read` says it: the port's opening rebooted the boards.
                        let boot = row.target.device != 0
                            && (fresh::on_calibrated_scale(reg)
                                || fresh::is_boot_calibration_end(reg, raw));
                        if boot {
                            object.bool("boot_calibration", true).finish()
                        } else {
                            object.finish()
                        }
                    }))
                }
                Reading::NoAnswer | Reading::Lost => "null".to_owned(),
            };
            let object = json::Object::new()
                .str("command", "watch")
                .int("round", i64::try_from(round.number).unwrap_or(i64::MAX))
                .int("set", round.set)
                .int("device", row.target.device)
                .str("board", row.target.board())
                .raw("values", &values);
            match row.reading {
                Reading::Values(_) => object,
                Reading::NoAnswer => object.bool("no_answer", true),
                Reading::Lost => object.bool("reply_lost", true),
            }
            .finish()
        })
        .collect()
}
