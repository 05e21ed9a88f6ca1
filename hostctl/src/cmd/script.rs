//! The `hostctl run` script language: one command per line, with comments.
//!
//! A comment runs from a `#` to the end of the line when the `#` starts the line, or follows
//! a space and is followed by a space or the line's end: `drive all 100 # forward` drives,
//! while `say Wheel #1 is the right rear` prints all of `Wheel #1 is the right rear`.
//!
//! | Line | What it does |
//! |---|---|
//! | `reset` | resetExceptions(): REG_RESET = 1 to controllers 1..9, then the master (§8.5) |
//! | `calibrate` | Rover::calibrate(): the §8.3 parameter and calibration frames, with their pauses, while every running board is stopped (REG_EXCEPTIONDATA first, REG_RESET 1 after): each steer and lift then holds where it stands on its new calibration, where the library's call alone turns it to the number it held, read on the new scale; each drive aims for 0. Demands sent before it are dropped. Boards it finds in exception (boot included) are left as they are; when the master may have stopped the rover meanwhile (it holds an exception other than its boot state, or a board does not answer) the boards stay stopped until a `reset`, with a note, as does a board whose state the serial line lost at the start |
//! | `write DEV REG VALUE` | One register write, as `hostctl write` (checked against the register's range only, not the library's position limits) |
//! | `drive W\|all SPEED` | Drive speed demand (ticks/s) on wheel W or all six |
//! | `steer W\|all DEG` | Steer demand (°) on wheel W or all six |
//! | `turn DEG` | Wheels 1, 2 steer +DEG, 5, 6 −DEG, 3, 4 0 (the operator's `t`) |
//! | `pointturn` | Steers of wheels 1..6 to −46°, 46°, 0°, 0°, 46°, −46°: each wheel across the line to the rover's centre, ready to `rotate` (the operator's `pt`) |
//! | `rotate SPEED` | Drives of wheels 1, 5 (right) at −SPEED, 2, 6 (left) at +SPEED, 3 at −SPEED/1.8, 4 at +SPEED/1.8 (ticks/s; the middle wheels are nearer the centre): the rover turns on the spot once the steers stand at `pointturn`'s angles (the operator's `rot`) |
//! | `lift W\|all DEG` | Lift demand (°) on wheel W or all six |
//! | `stop` | Every bridge off at once (REG_EXCEPTIONDATA to each controller), then the operator's emergency stop (§10.3: 36 frames, every demand 0, the gains 0), then each board this stop sent into REMOTESLAVE leaves it (REG_RESET 1): the drives coast unpowered, where the library's stop alone leaves them decaying under power for some 20 s. A board still running then (its DISABLEDEXCEPTIONS masks REMOTESLAVE) fails the line, named |
//! | `wait SECONDS` | Let time pass, showing the live view (required vs actual), redrawn in place; to a file or pipe, the last view only, when it ends |
//! | `watch SECONDS [EVERY]` | Like `wait`, printing the view every EVERY seconds (a log; 1 by default, 0 for every update: a step response at the link's full rate) |
//! | `show DEV REG…` | Add up to 24 registers of device DEV to every later live view (read sets 3..6: at most four different register lists, as lines naming the same registers share a set) |
//! | `say TEXT` | Print TEXT (up to a comment) |
//!
//! The whole script is checked, and its frames built, before anything is sent: a bad line
//! is reported with its number. Demands are checked as the original library checks them
//! (drive ±4000; steer and lift within the calibration less 10°, which `calibrate` and
//! `stop` change), replaying the script's own calibration state.

use std::time::Duration;

use shared::mapping;
use shared::protocol::READ_SET_SIZE;
use shared::regs::{id, BoardKind, Register};

use super::pc::{self, Motor, Op, Pairs, Pc, WHEELS};
use super::write;
use crate::error::HostError;
use crate::resolve::{self, Target};

/// What one script line does, in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// A frame or a pause of the library.
    Op(Op),
    /// Poll and show the live view for a while.
    Live {
        /// How long.
        time: Duration,
        /// `None` for `wait` (the view redrawn in place, or drawn once at the end); for
        /// `watch`, the time between two printed views (a log), zero for every update.
        every: Option<Duration>,
    },
    /// The end of a `stop`: each controller its REG_EXCEPTIONDATA write left in
    /// REMOTESLAVE leaves it again (REG_RESET bit 0), found by one update().
    Release,
    /// The start of a `calibrate`: one update(), then REG_EXCEPTIONDATA to each controller
    /// it shows running, which stops both its motors (REMOTESLAVE) and from then on holds
    /// each position demand at the angle measured, on whatever calibration the board holds.
    Freeze,
    /// The end of a `calibrate`: each controller [`Action::Freeze`] stopped leaves
    /// REMOTESLAVE again (REG_RESET bit 0), found by one update(), so that its steer or lifts
    /// hold where they stand on the new calibration and its drive aims for 0.
    Thaw,
    /// Print a line.
    Say(String),
    /// Add registers of a device to every later live view (each such line takes one of the
    /// read sets [`SHOW_SETS`], handed out in turn).
    Show {
        /// The device.
        target: Target,
        /// Its registers, in the order given.
        regs: Vec<&'static Register>,
        /// The read set that holds them, one of [`SHOW_SETS`].
        set: u8,
    },
}

/// The read sets `show` lines use, in order: 0..2 are the library's, 7 is hostctl's scratch.
pub const SHOW_SETS: [u8; 4] = [3, 4, 5, 6];

/// The read sets `show` lines take. A set holds register ids only, and a read resolves them
/// on the device it addresses (reference §4.2), so a line whose registers have the same ids
/// as an earlier line's, on any device, shares that line's set: `show 1 drive_control`,
/// `show 4 drive_control`, … take one set for any number of boards.
#[derive(Debug, Default)]
struct ShowSets {
    /// The id list of each set taken, in [`SHOW_SETS`] order.
    taken: Vec<Vec<u8>>,
}

impl ShowSets {
    /// The set for a line showing `regs`: the earlier line's with the same ids, else the next
    /// free one; `None` when all four hold other lists.
    fn take(&mut self, regs: &[&'static Register]) -> Option<u8> {
        let ids: Vec<u8> = regs.iter().map(|r| r.id).collect();
        let index = match self.taken.iter().position(|t| *t == ids) {
            Some(i) => i,
            None if self.taken.len() < SHOW_SETS.len() => {
                self.taken.push(ids);
                self.taken.len() - 1
            }
            None => return None,
        };
        SHOW_SETS.get(index).copied()
    }
}

/// One checked script line.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Line number in the file, from 1.
    pub number: usize,
    /// The line's text, trimmed, without its comment.
    pub text: String,
    /// What it does.
    pub actions: Vec<Action>,
    /// The library's state after the line (demands, for the live view).
    pub pc: Pc,
}

/// The longest `wait` or `watch`: one hour.
const MAX_SECONDS: f64 = 3600.0;

/// Parses and checks a whole script for the whole rover; the first bad line is the error.
pub fn parse(path: &str, source: &str) -> Result<Vec<Line>, HostError> {
    parse_for(path, source, Pairs::ALL)
}

/// The most command lines (not blank, not only a comment) one script may hold: each keeps
/// the demands as they stand after it (about 1.4 KB), so a generated script of millions of
/// lines would exhaust the memory before its first line ran.
pub const MAX_LINES: usize = 20_000;

/// [`parse`] for a rover with only `pairs` fitted: `all`, `calibrate`, `reset`, `stop` and
/// `turn` reach those, and a line naming another wheel or controller is refused.
pub fn parse_for(path: &str, source: &str, pairs: Pairs) -> Result<Vec<Line>, HostError> {
    let form = |why: String| HostError::ScriptForm {
        path: path.to_owned(),
        why,
    };
    // Lines end in LF or CRLF; a lone CR would make the rest of the script one line.
    if source.split("\r\n").any(|part| part.contains('\r')) {
        return Err(form(
            "its lines end in a lone CR (the old Mac format), which would run as one line; \
             save it with LF or CRLF line endings"
                .to_owned(),
        ));
    }
    let mut pc = Pc::with_pairs(pairs);
    let mut lines = Vec::new();
    let mut show_sets = ShowSets::default();
    // A byte-order mark (some editors write one) is no part of the first line.
    let source = source.strip_prefix('\u{feff}').unwrap_or(source);
    for (i, raw) in source.lines().enumerate() {
        let text = without_comment(raw).trim();
        if text.is_empty() {
            continue;
        }
        if lines.len() == MAX_LINES {
            return Err(form(format!(
                "more than {MAX_LINES} command lines, the most one script holds (each keeps \
                 the demands as they stand, for its view); split it into several runs"
            )));
        }
        let actions = line(&mut pc, text, &mut show_sets).map_err(|why| {
            // `#forward` or `1000#fwd` is text, not a comment: say how to write one.
            let hint = if text.contains('#') {
                "; a comment is `#` followed by a space"
            } else {
                ""
            };
            HostError::ScriptLine {
                path: path.to_owned(),
                line: i + 1,
                text: text.to_owned(),
                why: format!("{why}{hint}"),
            }
        })?;
        lines.push(Line {
            number: i + 1,
            text: text.to_owned(),
            actions,
            pc: pc.clone(),
        });
    }
    Ok(lines)
}

/// What a script that is valid line by line still leaves out, in words: demands to a board
/// no line resets (every board is in its boot exception after the port opens, so nothing
/// acts on a demand until a reset), a demand before its board's reset (a board in
/// exception replaces its demands, reference §6.4: that one is lost), or demands to a
/// motor no line gives gains (no `calibrate`, nor a `write` of a gain: they stay 0, so
/// nothing moves), a demand after a `stop` before the next `calibrate` (the stop sets the
/// gains to 0), or a last demand with no `wait` or `watch` after it (the script's end
/// reboots the rover at once), demands a `stop` or a `calibrate` leaves without effect
/// (see `stop_and_calibrate_notes`), and a `rotate` without the point turn's steers.
pub fn notes(lines: &[Line]) -> Vec<String> {
    fn first_word(l: &Line) -> String {
        command_word(&l.text)
    }
    fn is_demand(l: &&Line) -> bool {
        sends_demands(&first_word(l))
    }
    let mut notes = hard_reset_notes(lines);
    notes.extend(pc_timeout_notes(lines));
    notes.extend(speed_notes(lines));
    notes.extend(rotate_notes(lines));
    let Some(demand) = lines.iter().find(is_demand) else {
        return notes;
    };
    let has = |word: &str| lines.iter().any(|l| first_word(l) == word);
    notes.extend(reset_note(lines, demand));
    notes.extend(gains_note(lines, demand));
    if has("calibrate") {
        notes.extend(stop_and_calibrate_notes(lines));
    }
    // The script's end closes the port, which reboots the rover: a last demand with no
    // wait after it has no time to act.
    if let Some(last) = lines.iter().rev().find(is_demand) {
        let waits = lines.iter().any(|l| {
            l.number > last.number && l.actions.iter().any(|a| matches!(a, Action::Live { .. }))
        });
        if !waits {
            notes.push(format!(
                "line {} sends a demand and no `wait` follows it: the script ends at once, and \
                 closing the port reboots the rover, which stops it; put `wait SECONDS` after it",
                last.number
            ));
        }
    }
    notes
}

/// A line's one-register writes: (device, register id, raw value).
fn one_register_writes(line: &Line) -> impl Iterator<Item = (u8, u8, u16)> + '_ {
    line.actions.iter().filter_map(|a| match a {
        // Length, address, count 1, id, then the value's one or two bytes (LSB first).
        Action::Op(Op::Write(send)) => match send.frame.as_slice() {
            [_, _, 1, reg, lo] => Some((send.device, *reg, u16::from(*lo))),
            [_, _, 1, reg, lo, hi] => Some((send.device, *reg, u16::from_le_bytes([*lo, *hi]))),
            _ => None,
        },
        _ => None,
    })
}

/// The controllers a line takes out of an exception: REG_RESET with bit 0 set, as a
/// `reset` line or a `write DEV reset 1` sends it.
fn resets(line: &Line) -> Vec<u8> {
    one_register_writes(line)
        .filter(|&(d, reg, raw)| d != 0 && reg == id::REG_RESET && raw & 1 == 1)
        .map(|(d, ..)| d)
        .collect()
}

/// The register of `device`'s table with id `reg`.
fn register_of(device: u8, reg: u8) -> Option<&'static Register> {
    BoardKind::of_device(device)?.register(reg)
}

/// The motor a register belongs to, by its name's prefix (`REGDS_DRIVE`, `REGLL_ONE`, …).
fn motor_prefix(reg: &Register) -> &str {
    reg.name
        .rsplit_once('_')
        .map_or(reg.name, |(prefix, _)| prefix)
}

/// The demands of a demand line: (device, demand register).
fn demands_of(line: &Line) -> Vec<(u8, &'static Register)> {
    one_register_writes(line)
        .filter_map(|(d, reg, _)| Some((d, register_of(d, reg)?)))
        .collect()
}

/// The first demand that no reset lets act, per controller: its board is in its boot
/// exception after the port opens until a line resets it (a `reset` line, or a
/// `write DEV reset 1`), and one in exception replaces its demands (reference §6.4), so a
/// demand sent before its board's reset is lost. `first` is the script's first demand.
fn reset_note(lines: &[Line], first: &Line) -> Option<String> {
    // The first line that resets each controller (index by device), found in one pass.
    let mut first_reset: [Option<&Line>; 10] = [None; 10];
    for line in lines {
        for d in resets(line) {
            if let Some(slot) = first_reset.get_mut(usize::from(d)) {
                slot.get_or_insert(line);
            }
        }
    }
    if first_reset.iter().all(Option::is_none) {
        return Some(format!(
            "line {} sends a demand, but no line is `reset`: after the port opens every board \
             is in its boot exception, so nothing will move",
            first.number
        ));
    }
    for line in lines {
        if !sends_demands(&command_word(&line.text)) {
            continue;
        }
        for (d, _) in demands_of(line) {
            let reset = first_reset.get(usize::from(d)).copied().flatten();
            if reset.is_some_and(|r| r.number < line.number) {
                continue;
            }
            // Reference §6.4: what a board in exception does with a demand.
            const LOST: &str = "a board in exception replaces its demands (a drive's with 0, a \
                                steer's or lift's with its angle), so this one is lost; send \
                                it after the reset";
            let n = line.number;
            // Its first reset, if any, comes after this line.
            let note = match reset {
                Some(r) if command_word(&r.text) == "reset" => {
                    format!(
                        "line {n} sends a demand before the first `reset` (line {}): {LOST}",
                        r.number
                    )
                }
                Some(r) => format!(
                    "line {n} sends a demand to controller {d} before line {} resets it: \
                     {LOST}",
                    r.number
                ),
                None => format!(
                    "line {n} sends a demand to controller {d}, which no line resets \
                     (`reset`, or `write {d} reset 1`): after the port opens it is in its \
                     boot exception, so its motors will not move"
                ),
            };
            return Some(note);
        }
    }
    None
}

/// The first demand to a motor that no line gives gains: a board's gains are 0 from
/// power-up until a `calibrate`, or a `write` of the motor's P, I or D gain other than 0.
/// `first` is the script's first demand.
fn gains_note(lines: &[Line], first: &Line) -> Option<String> {
    let calibrates = lines.iter().any(|l| command_word(&l.text) == "calibrate");
    if calibrates {
        return None;
    }
    // (device, motor prefix) of each gain written other than 0.
    let gains: Vec<(u8, &str)> = lines
        .iter()
        .flat_map(one_register_writes)
        .filter(|&(_, _, raw)| raw != 0)
        .filter_map(|(d, reg, _)| {
            let reg = register_of(d, reg)?;
            reg.name.ends_with("GAIN").then(|| (d, motor_prefix(reg)))
        })
        .collect();
    if gains.is_empty() {
        return Some(format!(
            "line {} sends a demand, but no line is `calibrate`: the boards' gains stay 0, so \
             nothing will move",
            first.number
        ));
    }
    lines
        .iter()
        .filter(|l| sends_demands(&command_word(&l.text)))
        .find_map(|line| {
            let (d, reg) = demands_of(line)
                .into_iter()
                .find(|&(d, reg)| !gains.contains(&(d, motor_prefix(reg))))?;
            Some(format!(
                "line {} sends {} on controller {d}, but no line gives that motor a gain \
                 (`calibrate`, or a `write` of its P, I or D gain other than 0): its gains \
                 stay 0, so it will not move",
                line.number, reg.name
            ))
        })
}

/// The manual's "about the highest safe speed" (reference §13), ticks/s.
pub const SAFE_SPEED: f32 = 2500.0;

/// A line sending a drive speed beyond [`SAFE_SPEED`] either way (a `drive` line, or a
/// `write` of DRIVE_REQSPEED): the library allows ±4000, so it is sent, but the manual
/// warns against it.
fn speed_notes(lines: &[Line]) -> Vec<String> {
    let reqspeed = BoardKind::DriveSteer.register(id::REGDS_DRIVE_REQSPEED);
    lines
        .iter()
        .filter_map(|l| {
            let reg = reqspeed?;
            let fastest = l
                .actions
                .iter()
                .filter_map(|a| match a {
                    // A one-register write: length, address, count 1, id, value LSB, MSB.
                    Action::Op(Op::Write(send)) => match send.frame.as_slice() {
                        [_, _, 1, r, lo, hi] if *r == reg.id && send.device != 0 => {
                            Some(mapping::unmap(u16::from_le_bytes([*lo, *hi]), reg))
                        }
                        _ => None,
                    },
                    _ => None,
                })
                .filter(|v| v.abs() > SAFE_SPEED)
                .max_by(|a, b| a.abs().total_cmp(&b.abs()))?;
            Some(format!(
                "line {} drives at {fastest:.0} ticks/s, beyond the ±{SAFE_SPEED} the manual \
                 calls about the highest safe speed; it is sent (the library allows ±4000)",
                l.number
            ))
        })
        .collect()
}

/// How far (°) a steer demand may stand from its point-turn angle for a `rotate`.
const POINT_TURN_SLACK: f32 = 1.0;

/// A `rotate` that turns the wheels (SPEED not 0) while a fitted wheel's steer demand is
/// not its [`POINT_TURN`] angle, or with no `wait` or `watch` since a line last changed
/// a steer demand (a steer takes about a second to get there): the wheels would be
/// dragged sideways over the ground.
fn rotate_notes(lines: &[Line]) -> Vec<String> {
    let steers = |pc: &Pc| -> Vec<(u8, Option<f32>)> {
        pc.pairs()
            .wheels()
            .map(|w| (w, pc.demand(w, Motor::Steer)))
            .collect()
    };
    let mut notes = Vec::new();
    let mut before = lines.first().map(|l| steers(&Pc::with_pairs(l.pc.pairs())));
    let mut waited = true;
    for line in lines {
        let now = steers(&line.pc);
        if before.as_ref() != Some(&now) {
            waited = false;
        }
        if line
            .actions
            .iter()
            .any(|a| matches!(a, Action::Live { .. }))
        {
            waited = true;
        }
        let spins = command_word(&line.text) == "rotate"
            && line
                .text
                .split_whitespace()
                .nth(1)
                .and_then(|v| number(v).ok())
                .is_some_and(|v| v != 0.0);
        if spins {
            let off: Vec<String> = now
                .iter()
                .filter_map(|&(w, demand)| {
                    let want = POINT_TURN[usize::from(w - 1)];
                    match demand {
                        Some(d) if (d - want).abs() <= POINT_TURN_SLACK => None,
                        Some(d) => Some(format!("wheel {w} at {d}° for {want}°")),
                        None => Some(format!("wheel {w} with no steer demand")),
                    }
                })
                .collect();
            if !off.is_empty() {
                notes.push(format!(
                    "line {} rotates the rover on the spot, but its steers are not at the \
                     point turn's angles ({}): the wheels would be dragged sideways; put \
                     `pointturn` and `wait 1` before it",
                    line.number,
                    off.join(", ")
                ));
            } else if !waited {
                notes.push(format!(
                    "line {} rotates the rover with no `wait` since its steers were sent to the \
                     point turn's angles: they take about a second to get there, dragged \
                     meanwhile; put `wait 1` before it",
                    line.number
                ));
            }
        }
        before = Some(now);
    }
    notes
}

/// Demands a `stop` or a `calibrate` leaves without effect. After a `stop` with no
/// `calibrate` (or `write`, which may set gains) between them: the stop sends every motor
/// the library's default block, whose gains are 0 (reference §10.3), so the demand moves
/// nothing. Before a `calibrate`, once a `reset` has let the boards run (and no `stop`
/// has dropped them since): the calibrate stops every running board while it runs, which
/// drops its demands (a drive then aims for 0, a steer or lift holds where it stands), so
/// the last such demand is named, whether or not a wait let it act first.
fn stop_and_calibrate_notes(lines: &[Line]) -> Vec<String> {
    let word = |l: &Line| command_word(&l.text);
    let mut notes = Vec::new();
    let mut stop = None;
    let mut reset = false;
    let mut demand = None;
    for line in lines {
        match word(line).as_str() {
            "stop" => {
                // The stop drops every demand itself.
                stop = Some(line.number);
                demand = None;
            }
            "reset" => reset = true,
            "write" => stop = None,
            "calibrate" => {
                stop = None;
                if let Some(at) = demand.take() {
                    notes.push(format!(
                        "the `calibrate` on line {} drops the demands before it (the last on \
                         line {at}): it stops every running board while it runs, and then \
                         each drive aims for 0 and each steer and lift holds where it stands; \
                         send the demands you want after it",
                        line.number
                    ));
                }
            }
            w if sends_demands(w) => {
                if let Some(at) = stop.take() {
                    // That note's fix covers the calibrate's too.
                    notes.push(format!(
                        "line {} sends a demand after the `stop` on line {at}, which set every \
                         motor's gains to 0 until a `calibrate`, so it moves nothing before \
                         one; put `calibrate` after the stop, before the demands",
                        line.number
                    ));
                } else if reset {
                    demand = Some(line.number);
                }
            }
            _ => {}
        }
    }
    notes
}

/// The shortest REGMASTER_PCTIMEOUT a run keeps: a reply the serial line loses costs
/// hostctl a 1-s wait (the library's reply timeout) and a probe before its next frame, so
/// a shorter timeout would stop every motor on one lost byte.
pub const PC_TIMEOUT_MIN_MS: u16 = 1_500;

/// A PC-silence timeout (a write of REGMASTER_PCTIMEOUT) shorter than
/// [`PC_TIMEOUT_MIN_MS`] but not 0 (off).
fn pc_timeout_notes(lines: &[Line]) -> Vec<String> {
    let mut notes = Vec::new();
    for line in lines {
        for action in &line.actions {
            let Action::Op(Op::Write(send)) = action else {
                continue;
            };
            // Its one write: length, address, count 1, id, value LSB, MSB.
            let ms = match send.frame.as_slice() {
                [_, _, 1, reg, lo, hi] if send.device == 0 && *reg == id::REGMASTER_PCTIMEOUT => {
                    u16::from_le_bytes([*lo, *hi])
                }
                _ => continue,
            };
            if ms != 0 && ms < PC_TIMEOUT_MIN_MS {
                notes.push(format!(
                    "line {} sets the PC-silence failsafe to {ms} ms: hostctl waits up to 1 s \
                     for a reply the serial line lost before its next frame, so one lost byte \
                     would stop every motor; use {PC_TIMEOUT_MIN_MS} ms or more",
                    line.number
                ));
            }
        }
    }
    notes
}

/// A hard reset (REG_RESET with bit 1, value 2) not followed by a `wait` or `watch`: the
/// board reboots 16 ms after it, so writes sent at once may be acknowledged and then lost,
/// and on the real rover a slave takes up to 5 s to come back (the master waits as long
/// after its own boot).
fn hard_reset_notes(lines: &[Line]) -> Vec<String> {
    let mut notes = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let hard = line
            .actions
            .iter()
            .any(|a| matches!(a, Action::Op(Op::Write(w)) if w.hard_resets()));
        let waits = lines.get(i + 1).is_some_and(|next| {
            matches!(next.actions.as_slice(), [Action::Live { time, .. }] if time.as_secs() >= 5)
        });
        if hard && !waits && i + 1 < lines.len() {
            notes.push(format!(
                "line {} hard-resets a board: it reboots, and writes sent to it before it is \
                 back may be lost; put `wait 5` after it",
                line.number
            ));
        }
    }
    notes
}

/// A line's command word, in lower case: commands are read whatever their case
/// (`Drive ALL 100`), as register names are.
fn command_word(text: &str) -> String {
    text.split_whitespace()
        .next()
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// `raw` without its comment. A `#` inside a word (`#1`, `a#b`) is text, so `say` can
/// print it.
fn without_comment(raw: &str) -> &str {
    if raw.trim_start().starts_with('#') {
        return "";
    }
    let starts_comment = |i: usize| {
        raw[..i].ends_with(char::is_whitespace)
            && raw[i + 1..].chars().next().is_none_or(char::is_whitespace)
    };
    match raw
        .match_indices('#')
        .map(|(i, _)| i)
        .find(|&i| starts_comment(i))
    {
        Some(i) => &raw[..i],
        None => raw,
    }
}

/// Why a line is refused: a usage message or an error of the command it runs.
#[derive(Debug)]
enum Why {
    /// The words do not fit the command: its usage line, e.g. `write DEV REG VALUE`.
    Usage(&'static str),
    /// A limit of the rover's, in words.
    Limit(&'static str),
    /// Anything else, in words.
    Text(String),
    /// A word that should be a finite number and is not (the word as written).
    Number(String),
    /// A register, device or value that hostctl's own checks refuse.
    Host(HostError),
}

impl std::fmt::Display for Why {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Why::Usage(u) => write!(f, "usage: {u}"),
            Why::Limit(l) => write!(f, "{l}"),
            Why::Text(t) => write!(f, "{t}"),
            Why::Number(n) => write!(f, "`{n}` is not a number"),
            Why::Host(e) => write!(f, "{e}"),
        }
    }
}

impl From<HostError> for Why {
    fn from(e: HostError) -> Self {
        Why::Host(e)
    }
}

pub(crate) const COMMANDS: &str = "reset | calibrate | write DEV REG VALUE | drive W|all SPEED | \
steer W|all DEG | turn DEG | pointturn | rotate SPEED | lift W|all DEG | stop | wait SECONDS | \
watch SECONDS [EVERY] | show DEV REG… | say TEXT";

/// The operator's point turn `pt` (reference §10.2): the steer angles of wheels 1..6, each
/// wheel across the line to the rover's centre.
pub const POINT_TURN: [f32; 6] = [-46.0, 46.0, 0.0, 0.0, 46.0, -46.0];

/// The operator's `rot` (reference §10.2): the drive demands of wheels 1..6 for a rotation
/// at `speed`, in its order of arithmetic (the middle wheels, nearer the centre, at
/// 1/1.8 of the others).
fn rotation(speed: f32) -> [f32; 6] {
    [-speed, speed, -speed / 1.8, speed / 1.8, -speed, speed]
}

/// The words of the lines that send demands.
fn sends_demands(word: &str) -> bool {
    matches!(
        word,
        "drive" | "steer" | "turn" | "lift" | "pointturn" | "rotate"
    )
}

fn number(word: &str) -> Result<f32, Why> {
    resolve::ascii_minus(word)
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| Why::Number(word.to_owned()))
}

/// `all` (the fitted wheels) or one wheel.
fn wheels(word: &str, pairs: Pairs, usage: &'static str) -> Result<Vec<u8>, Why> {
    if word.eq_ignore_ascii_case("all") {
        return Ok(pairs.wheels().collect());
    }
    match word.parse::<u8>() {
        Ok(w) if WHEELS.contains(&w) => Ok(vec![w]),
        _ => Err(Why::Usage(usage)),
    }
}

/// How often `watch` prints a view when its line does not say.
pub const WATCH_EVERY: Duration = Duration::from_secs(1);

const WATCH_USAGE: &str = "watch SECONDS [EVERY]   (0..3600; a view every EVERY seconds, \
1 by default, 0 for every update)";

fn seconds(word: &str, usage: &'static str) -> Result<Duration, Why> {
    // Parsed as f64, so that `0.05` is 50 ms, not the f32 nearest to it.
    let s = word
        .parse::<f64>()
        .ok()
        .filter(|s| s.is_finite())
        .ok_or(Why::Usage(usage))?;
    if !(0.0..=MAX_SECONDS).contains(&s) {
        return Err(Why::Usage(usage));
    }
    Ok(Duration::from_secs_f64(s))
}

/// Wheels 1..6 paired with their values.
fn by_wheel(values: [f32; 6]) -> Vec<(u8, f32)> {
    (1..=6).zip(values).collect()
}

fn ops(list: Vec<Op>) -> Vec<Action> {
    list.into_iter().map(Action::Op).collect()
}

/// One line's actions, updating the library state `pc`; a `show` line takes a read set of
/// `show_sets`.
fn line(pc: &mut Pc, text: &str, show_sets: &mut ShowSets) -> Result<Vec<Action>, Why> {
    let command = command_word(text);
    let words: Vec<&str> = std::iter::once(command.as_str())
        .chain(text.split_whitespace().skip(1))
        .collect();
    let set = |pc: &mut Pc, motor, targets: &[u8], value| -> Result<Vec<Action>, Why> {
        targets
            .iter()
            .map(|&w| Ok(Action::Op(pc.set_required(w, motor, value)?)))
            .collect()
    };
    // One demand per (wheel, value), in that order, to the fitted wheels only.
    let each = |pc: &mut Pc, motor, demands: &[(u8, f32)]| -> Result<Vec<Action>, Why> {
        let pairs = pc.pairs();
        demands
            .iter()
            .filter(|(w, _)| pairs.has_wheel(*w))
            .map(|&(w, v)| Ok(Action::Op(pc.set_required(w, motor, v)?)))
            .collect()
    };
    match words.as_slice() {
        ["reset"] => Ok(ops(pc::reset_exceptions_of(pc.pairs())?)),
        ["calibrate"] => {
            let mut calibrate = vec![Action::Freeze];
            calibrate.extend(ops(pc.calibrate()?));
            calibrate.push(Action::Thaw);
            Ok(calibrate)
        }
        ["stop"] => {
            let mut stop = ops(pc::bridges_off(pc.pairs())?);
            stop.extend(ops(pc.emergency_stop()?));
            stop.push(Action::Release);
            Ok(stop)
        }
        ["write", dev, reg, value] => {
            let plan = write::plan(&write::Args {
                device: (*dev).to_owned(),
                register: (*reg).to_owned(),
                value: (*value).to_owned(),
            })
            .map_err(|e| match e {
                // In a script the way to see it is a `show` line, not another command.
                HostError::ReadOnly { register, device } => Why::Text(format!(
                    "{register} on device {device} is read-only; a `show {device} {register}` \
                     line adds it to every later view"
                )),
                e => Why::Host(e),
            })?;
            pc.pairs().check_device(plan.target.device)?;
            pc.note_write(plan.target.device, plan.reg.id, plan.raw, plan.value);
            Ok(vec![Action::Op(Op::Write(pc::Send {
                device: plan.target.device,
                frame: plan.frame.to_vec(),
                what: plan.reg.name,
            }))])
        }
        ["write", ..] => Err(Why::Usage("write DEV REG VALUE")),
        ["show", dev, regs @ ..] if !regs.is_empty() && regs.len() <= READ_SET_SIZE => {
            let target = resolve::device(dev)?;
            pc.pairs().check_device(target.device)?;
            let mut regs = regs
                .iter()
                .map(|r| resolve::register(target, r))
                .collect::<Result<Vec<_>, _>>()?;
            // A register named twice is shown once.
            let mut seen = Vec::new();
            regs.retain(|reg| {
                !seen.contains(&reg.id) && {
                    seen.push(reg.id);
                    true
                }
            });
            let set = show_sets.take(&regs).ok_or(Why::Limit(
                "the four read sets for `show` (3..6) hold four other register lists already; \
                 a line naming the same registers as an earlier one, on any device, shares \
                 its set (`show 4 drive_control` after `show 1 drive_control`), so give \
                 boards of a kind the same list",
            ))?;
            Ok(vec![Action::Show { target, regs, set }])
        }
        ["show", ..] => Err(Why::Usage("show DEV REG [REG …]   (1 to 24 registers)")),
        ["drive", w, v] => {
            const U: &str = "drive W|all SPEED   (W = wheel 1..6, SPEED in ticks/s)";
            set(pc, Motor::Drive, &wheels(w, pc.pairs(), U)?, number(v)?)
        }
        ["steer", w, v] => {
            const U: &str = "steer W|all DEG   (W = wheel 1..6)";
            set(pc, Motor::Steer, &wheels(w, pc.pairs(), U)?, number(v)?)
        }
        ["lift", w, v] => {
            const U: &str = "lift W|all DEG   (W = wheel 1..6)";
            set(pc, Motor::Lift, &wheels(w, pc.pairs(), U)?, number(v)?)
        }
        ["drive" | "steer" | "lift", ..] => Err(Why::Usage(
            "drive|steer|lift W|all VALUE   (W = wheel 1..6)",
        )),
        ["turn", v] => {
            let v = number(v)?;
            let angles = [(1, v), (2, v), (5, -v), (6, -v), (3, 0.0), (4, 0.0)];
            each(pc, Motor::Steer, &angles)
        }
        ["turn", ..] => Err(Why::Usage("turn DEG")),
        ["pointturn"] => each(pc, Motor::Steer, &by_wheel(POINT_TURN)),
        ["pointturn", ..] => Err(Why::Usage(
            "pointturn   (no argument: the steers to the point turn's angles)",
        )),
        ["rotate", v] => each(pc, Motor::Drive, &by_wheel(rotation(number(v)?))),
        ["rotate", ..] => Err(Why::Usage(
            "rotate SPEED   (ticks/s: the right-side corner wheels 1, 5 at −SPEED, the left 2, 6 at \
             +SPEED, the middle ones 3, 4 at 1/1.8 of that)",
        )),
        ["wait", s] => Ok(vec![Action::Live {
            time: seconds(s, "wait SECONDS   (0..3600)")?,
            every: None,
        }]),
        ["watch", s] => Ok(vec![Action::Live {
            time: seconds(s, WATCH_USAGE)?,
            every: Some(WATCH_EVERY),
        }]),
        ["watch", s, every] => Ok(vec![Action::Live {
            time: seconds(s, WATCH_USAGE)?,
            every: Some(seconds(every, WATCH_USAGE)?),
        }]),
        ["wait", ..] => Err(Why::Usage("wait SECONDS   (0..3600)")),
        ["watch", ..] => Err(Why::Usage(WATCH_USAGE)),
        ["reset" | "calibrate" | "stop", ..] => Err(Why::Text(format!(
            "`{}` takes no argument: it acts on every fitted board (to reset one board, \
             `write DEV reset 1`)",
            words[0]
        ))),
        ["say", ..] => Ok(vec![Action::Say(
            text.split_once(char::is_whitespace)
                .map_or("", |(_, said)| said.trim())
                .to_owned(),
        )]),
        _ => Err(Why::Usage(COMMANDS)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::hex;

    fn frames(lines: &[Line]) -> Vec<String> {
        lines
            .iter()
            .flat_map(|l| &l.actions)
            .filter_map(|a| match a {
                Action::Op(Op::Write(s)) => Some(hex(&s.frame)),
                _ => None,
            })
            .collect()
    }

    fn refusal(source: &str) -> String {
        parse("demo.rover", source).unwrap_err().to_string()
    }

    #[test]
    fn show_lines_take_sets_3_to_6() {
        let lines = parse("s", "show 1 drive_control\nshow 3 one_control two_control").unwrap();
        assert!(matches!(
            &lines[1].actions[..],
            [Action::Show { set: 4, regs, .. }] if regs.len() == 2
        ));
        // The same registers share a set on any device: five boards' drive duty in one.
        let same = "show 1 drive_control\nshow 2 drive_control\nshow 4 drive_control\n\
                    show 5 drive_control\nshow 7 drive_control\n";
        let sets: Vec<(u8, u8)> = parse("s", same)
            .unwrap()
            .iter()
            .flat_map(|l| &l.actions)
            .filter_map(|a| match a {
                Action::Show { target, set, .. } => Some((target.device, *set)),
                _ => None,
            })
            .collect();
        assert_eq!(sets, [(1, 3), (2, 3), (4, 3), (5, 3), (7, 3)]);
        // Four other lists take every set; a fifth is refused with the way round it.
        let five = "show 1 timer\nshow 1 drive_control\nshow 1 steer_control\n\
                    show 1 timer drive_control\nshow 2 steer_control\nshow 1 drive_reqspeed\n";
        let err = parse("s", five).unwrap_err().to_string();
        assert_eq!(
            err,
            "s line 6 (`show 1 drive_reqspeed`): the four read sets for `show` (3..6) hold four \
             other register lists already; a line naming the same registers as an earlier \
             one, on any device, shares its set (`show 4 drive_control` after `show 1 \
             drive_control`), so give boards of a kind the same list"
        );
        let err = parse("s", "show 1 one_control").unwrap_err().to_string();
        assert!(err.contains("LL table"), "{err}");
        assert!(parse("s", "show 1").is_err());
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_line() {
        let lines = parse("s", "\u{feff}reset\nsay ok\n").unwrap();
        assert_eq!(lines[0].text, "reset");
        assert_eq!(lines[0].number, 1);
        assert_eq!(lines.len(), 2);
    }

    #[test]
    fn line_endings_are_lf_or_crlf_and_a_lone_cr_is_refused() {
        let crlf = parse("s", "say one\r\nsay two\r\n").unwrap();
        assert_eq!(
            crlf.iter().map(|l| l.text.as_str()).collect::<Vec<_>>(),
            ["say one", "say two"]
        );
        for cr in ["say cr only\rsay two\r", "say one\r\nsay two\rsay three\n"] {
            assert_eq!(
                parse("s", cr).unwrap_err().to_string(),
                "s: its lines end in a lone CR (the old Mac format), which would run as one \
                 line; save it with LF or CRLF line endings; nothing was sent"
            );
        }
    }

    #[test]
    fn a_script_holds_at_most_max_lines_command_lines() {
        // Blank and comment lines do not count.
        let full = "say x\n\n# note\n".repeat(MAX_LINES);
        assert_eq!(parse("s", &full).unwrap().len(), MAX_LINES);
        let over = format!("{full}say one more\n");
        assert_eq!(
            parse("s", &over).unwrap_err().to_string(),
            format!(
                "s: more than {MAX_LINES} command lines, the most one script holds (each keeps \
                 the demands as they stand, for its view); split it into several runs; nothing \
                 was sent"
            )
        );
    }

    #[test]
    fn a_hash_glued_to_a_number_gets_the_comment_hint() {
        let err = parse("s", "drive all 1000#fwd").unwrap_err().to_string();
        assert!(
            err.ends_with("; a comment is `#` followed by a space"),
            "{err}"
        );
    }

    #[test]
    fn a_script_that_cannot_move_anything_is_noted() {
        let notes = |src: &str| notes(&parse("s", src).unwrap());
        assert_eq!(
            notes("write 1 reset 2\ncalibrate"),
            [
                "line 1 hard-resets a board: it reboots, and writes sent to it before it is \
              back may be lost; put `wait 5` after it"
            ]
        );
        assert!(notes("write 1 reset 2\nwait 5\ncalibrate").is_empty());
        assert!(
            notes("write 1 reset 1\ncalibrate").is_empty(),
            "a clear only"
        );
        assert!(
            notes("calibrate\nwrite 1 reset 2").is_empty(),
            "nothing after it"
        );
        assert_eq!(
            notes("say go\ndrive all 1000\nwait 2"),
            [
                "line 2 sends a demand, but no line is `reset`: after the port opens every board \
                 is in its boot exception, so nothing will move",
                "line 2 sends a demand, but no line is `calibrate`: the boards' gains stay 0, so \
                 nothing will move",
            ]
        );
        assert_eq!(notes("reset\nturn 10\nwait 1").len(), 1);
        // A board reset and given a gain by `write` lines moves: no note. Another board,
        // or another motor of the same board, still gets one.
        assert!(notes("write 1 reset 1\nwrite 1 drive_pgain 0.02\ndrive 1 500\nwait 3").is_empty());
        assert!(notes("reset\nwrite 1 drive_pgain 0.02\ndrive 1 500\nwait 3").is_empty());
        assert_eq!(
            notes("write 1 reset 1\nwrite 1 drive_pgain 0.02\ndrive 2 500\nsteer 1 5\nwait 3"),
            [
                "line 3 sends a demand to controller 2, which no line resets (`reset`, or \
                 `write 2 reset 1`): after the port opens it is in its boot exception, so its \
                 motors will not move",
                "line 3 sends REGDS_DRIVE_REQSPEED on controller 2, but no line gives that \
                 motor a gain (`calibrate`, or a `write` of its P, I or D gain other than 0): \
                 its gains stay 0, so it will not move",
            ]
        );
        assert_eq!(
            notes("reset\nwrite 1 drive_pgain 0.02\nsteer 1 5\nwait 3"),
            [
                "line 3 sends REGDS_STEER_REQPOS on controller 1, but no line gives that motor \
                 a gain (`calibrate`, or a `write` of its P, I or D gain other than 0): its \
                 gains stay 0, so it will not move"
            ]
        );
        // A gain written as 0 is none; a reset of the master (device 0) resets no board.
        assert_eq!(
            notes("write 0 reset 1\nwrite 1 drive_pgain 0\ndrive 1 5\nwait 3").len(),
            2
        );
        assert_eq!(
            notes("drive 1 5\nwrite 1 reset 1\ncalibrate\nwait 3"),
            [
                "line 1 sends a demand to controller 1 before line 2 resets it: a board in \
                 exception replaces its demands (a drive's with 0, a steer's or lift's with \
                 its angle), so this one is lost; send it after the reset"
            ]
        );
        // A last demand with no wait after it: the end of the script stops the rover.
        assert_eq!(
            notes("calibrate\nreset\ndrive all 100\nwait 1\nsteer all 20\nsay bye"),
            [
                "line 5 sends a demand and no `wait` follows it: the script ends at once, and \
                 closing the port reboots the rover, which stops it; put `wait SECONDS` after it"
            ]
        );
        assert!(notes("calibrate\nreset\nsteer all 20\nwatch 2\nsay bye").is_empty());
        // A demand before the reset is replaced by the board: lost.
        assert_eq!(
            notes("drive 1 100\ncalibrate\nreset\nwait 1"),
            [
                "line 1 sends a demand before the first `reset` (line 3): a board in exception \
              replaces its demands (a drive's with 0, a steer's or lift's with its angle), so \
              this one is lost; send it after the reset"
            ]
        );
        // After the reset and before a calibrate, which stops every running board while it
        // runs: dropped too. The last one before each calibrate is named.
        let dropped = |at: usize, by: usize| {
            format!(
                "the `calibrate` on line {by} drops the demands before it (the last on line \
                 {at}): it stops every running board while it runs, and then each drive aims \
                 for 0 and each steer and lift holds where it stands; send the demands you \
                 want after it"
            )
        };
        assert_eq!(
            notes("reset\ndrive 1 100\nsteer 1 5\ncalibrate\nwait 1"),
            [dropped(3, 4)]
        );
        assert_eq!(
            notes("reset\ncalibrate\nlift 1 5\nwait 1\ncalibrate\nturn 3\ncalibrate\nwait 1"),
            [dropped(3, 5), dropped(6, 7)]
        );
        assert!(notes("reset\ncalibrate\ndrive 1 100\nwait 1").is_empty());
        // A stop drops the demands itself: a calibrate after it, as its note advises, is
        // not noted.
        assert!(notes(
            "calibrate\nreset\nsteer all 20\nwait 3\nstop\ncalibrate\nsteer all 5\nwait 1"
        )
        .is_empty());
        // No demand, nothing to note.
        assert!(notes("calibrate\nwait 1").is_empty());
        // A demand after a stop, whose gains are 0, until a calibrate: noted once a stop.
        assert_eq!(
            notes("calibrate\nreset\ndrive all 100\nwait 1\nstop\ndrive all 200\nlift 1 5\nwait 1"),
            [
                "line 6 sends a demand after the `stop` on line 5, which set every motor's \
                 gains to 0 until a `calibrate`, so it moves nothing before one; put \
                 `calibrate` after the stop, before the demands"
            ]
        );
        assert_eq!(
            notes("calibrate\nreset\nstop\ndrive 1 1\ncalibrate\nwait 1").len(),
            1,
            "still nothing before the calibrate"
        );
        assert!(notes("calibrate\nreset\nstop\ncalibrate\ndrive all 100\nwait 1").is_empty());
        assert!(
            notes("calibrate\nreset\nstop\nwrite 1 drive_pgain 0.01\ndrive 1 100\nwait 1")
                .is_empty(),
            "gains written by hand"
        );
        // With no calibrate at all, the one note says so.
        assert_eq!(notes("reset\nstop\ndrive 1 100\nwait 1").len(), 1);
        // A PC-silence failsafe a lost byte would trip; 0 (off) and 1500 ms are fine.
        assert_eq!(
            notes("write 0 pctimeout 500\ncalibrate\nwait 1"),
            [
                "line 1 sets the PC-silence failsafe to 500 ms: hostctl waits up to 1 s for a \
                 reply the serial line lost before its next frame, so one lost byte would stop \
                 every motor; use 1500 ms or more"
            ]
        );
        assert!(notes("write 0 pctimeout 1500\nwrite 0 pctimeout 0\nwait 1").is_empty());
    }

    #[test]
    fn a_script_becomes_frames_in_order() {
        let lines = parse(
            "s",
            "# drive a little\nreset\n\ndrive all 1000   # forward\nturn 40\nlift 1 20\nwait 0.5\nsay done\n",
        )
        .unwrap();
        let numbers: Vec<usize> = lines.iter().map(|l| l.number).collect();
        assert_eq!(numbers, [2, 4, 5, 6, 7, 8]);
        assert_eq!(lines[1].text, "drive all 1000");
        let f = frames(&lines);
        assert_eq!(f.len(), 10 + 6 + 6 + 1);
        assert_eq!(f[10], "06 12 01 09 fe 9f");
        assert_eq!(f[15], "06 82 01 09 fe 9f");
        // turn: 1, 2 +40; 5, 6 -40; 3, 4 0, in that order.
        assert_eq!(
            &f[16..22],
            [
                "06 12 01 1a 98 99",
                "06 22 01 1a 98 99",
                "06 72 01 1a 65 66",
                "06 82 01 1a 65 66",
                "06 42 01 1a ff 7f",
                "06 52 01 1a ff 7f"
            ]
        );
        assert_eq!(f[22], "06 32 01 09 cb 8c");
        assert_eq!(
            lines[4].actions,
            [Action::Live {
                time: Duration::from_millis(500),
                every: None
            }]
        );
        assert_eq!(lines[5].actions, [Action::Say("done".into())]);
        assert_eq!(lines[5].pc.demand(1, Motor::Lift), Some(20.0));
        assert_eq!(lines[5].pc.demand(5, Motor::Steer), Some(-40.0));
    }

    #[test]
    fn watch_prints_a_view_every_second_or_as_often_as_its_line_says() {
        let live = |text: &str| parse("s", text).unwrap()[0].actions.clone();
        let watch = |time: u64, every: Option<u64>| {
            vec![Action::Live {
                time: Duration::from_millis(time),
                every: every.map(Duration::from_millis),
            }]
        };
        assert_eq!(live("watch 3"), watch(3_000, Some(1_000)));
        assert_eq!(live("watch 3 0.05"), watch(3_000, Some(50)));
        // 0: a view at every update, for a step response at the link's full rate.
        assert_eq!(live("watch 2 0"), watch(2_000, Some(0)));
        assert_eq!(live("wait 2"), watch(2_000, None));
        let usage = "usage: watch SECONDS [EVERY]   (0..3600; a view every EVERY seconds, 1 by \
                     default, 0 for every update)";
        for bad in [
            "watch",
            "watch 3 -1",
            "watch 3 fast",
            "watch 3 4000",
            "watch 3 1 2",
        ] {
            assert_eq!(
                refusal(bad),
                format!("demo.rover line 1 (`{bad}`): {usage}"),
                "{bad}"
            );
        }
        assert_eq!(
            refusal("wait 3 1"),
            "demo.rover line 1 (`wait 3 1`): usage: wait SECONDS   (0..3600)"
        );
    }

    #[test]
    fn a_hash_inside_a_word_is_text_not_a_comment() {
        let lines = parse(
            "s",
            "say Wheel #1 is the right rear\n#note\n  # indented note\ndrive all 100 # forward\n\
             say a#b # c\nsay trailing #\nsay #tag\tand #\tend\n",
        )
        .unwrap();
        let numbers: Vec<usize> = lines.iter().map(|l| l.number).collect();
        assert_eq!(numbers, [1, 4, 5, 6, 7]);
        assert_eq!(
            lines[0].actions,
            [Action::Say("Wheel #1 is the right rear".into())]
        );
        assert_eq!(lines[1].text, "drive all 100");
        assert_eq!(lines[2].actions, [Action::Say("a#b".into())]);
        assert_eq!(lines[3].actions, [Action::Say("trailing".into())]);
        assert_eq!(lines[4].actions, [Action::Say("#tag\tand".into())]);
        assert_eq!(
            refusal("drive all 100 #forward"),
            "demo.rover line 1 (`drive all 100 #forward`): usage: drive|steer|lift W|all VALUE   (W = wheel 1..6); a comment is `#` followed by a space"
        );
    }

    #[test]
    fn bad_lines_are_reported_with_their_number() {
        assert_eq!(
            refusal("reset\nfly 3\n"),
            format!("demo.rover line 2 (`fly 3`): usage: {COMMANDS}")
        );
        assert_eq!(
            refusal("drive 7 100"),
            "demo.rover line 1 (`drive 7 100`): usage: drive W|all SPEED   (W = wheel 1..6, SPEED in ticks/s)"
        );
        assert_eq!(
            refusal("drive all fast"),
            "demo.rover line 1 (`drive all fast`): `fast` is not a number"
        );
        assert!(refusal("drive 1 5000").contains("5000 is out of range for REGDS_DRIVE_REQSPEED"));
        assert_eq!(
            refusal("write 0 TEMP1 3"),
            "demo.rover line 1 (`write 0 TEMP1 3`): REGMASTER_TEMP1 on device 0 is read-only; a \
             `show 0 REGMASTER_TEMP1` line adds it to every later view"
        );
        // The PC-silence failsafe is armed from a script like any master register.
        assert!(parse("s", "write 0 pctimeout 500").is_ok());
        assert!(refusal("wait -1").contains("usage: wait SECONDS"));
        assert_eq!(
            refusal("wait abc"),
            "demo.rover line 1 (`wait abc`): usage: wait SECONDS   (0..3600)"
        );
        assert_eq!(
            refusal("reset 1"),
            "demo.rover line 1 (`reset 1`): `reset` takes no argument: it acts on every \
             fitted board (to reset one board, `write DEV reset 1`)"
        );
        assert!(refusal("calibrate now").contains("`calibrate` takes no argument"));
        assert!(refusal("stop 3").contains("`stop` takes no argument"));
    }

    #[test]
    fn a_point_turn_and_a_rotation_send_the_operators_demands() {
        let lines = parse("s", "pointturn\nrotate 500\nrotate -4000").unwrap();
        // pt: -46, 46, 0, 0, 46, -46 to the steers of wheels 1..6 (DS boards 1, 2, 4, 5, 7,
        // 8; STEER_REQPOS 0x1a on ±200: 46 maps to 0x9d6f, -46 to 0x628e).
        let f = frames(&lines);
        assert_eq!(
            &f[..6],
            [
                "06 12 01 1a 8e 62",
                "06 22 01 1a 6f 9d",
                "06 42 01 1a ff 7f",
                "06 52 01 1a ff 7f",
                "06 72 01 1a 6f 9d",
                "06 82 01 1a 8e 62"
            ]
        );
        // rot 500: wheels 1, 5 at -500; 2, 6 at 500; 3 at -500/1.8, 4 at 500/1.8
        // (DRIVE_REQSPEED 0x09 on ±4000: 500 is 0x8ffe, -500 0x6fff, ±277.78 0x88e2 / 0x771b).
        assert_eq!(
            &f[6..12],
            [
                "06 12 01 09 ff 6f",
                "06 22 01 09 fe 8f",
                "06 42 01 09 1b 77",
                "06 52 01 09 e2 88",
                "06 72 01 09 ff 6f",
                "06 82 01 09 fe 8f"
            ]
        );
        assert_eq!(lines[1].pc.demand(3, Motor::Drive), Some(-500.0 / 1.8));
        // rot -4000: wheel 1 at +4000, wheel 2 at -4000, the library's limits.
        assert_eq!(&f[12..14], ["06 12 01 09 fe ff", "06 22 01 09 00 00"]);
        // `rotate 0` and `turn 0` record 0 where they negate it, never -0, which a view
        // would print as "-0".
        let zero = parse("s", "rotate 0\nturn 0").unwrap();
        assert!(zero[0]
            .pc
            .demand(1, Motor::Drive)
            .is_some_and(f32::is_sign_positive));
        assert!(zero[1]
            .pc
            .demand(6, Motor::Steer)
            .is_some_and(f32::is_sign_positive));
        // With the rear pair alone, only wheels 1 and 2 are sent.
        let rear = parse_for("s", "pointturn\nrotate 100", Pairs::parse("0").unwrap()).unwrap();
        assert_eq!(frames(&rear).len(), 4);
        // Bad forms and a rotation beyond the library's ±4000 are refused.
        assert!(refusal("pointturn 3").contains("usage: pointturn"));
        assert!(refusal("rotate").contains("usage: rotate SPEED"));
        assert_eq!(
            frames(&parse("s", "rotate \u{2212}500").unwrap()),
            frames(&parse("s", "rotate -500").unwrap()),
            "a Unicode minus is a minus"
        );
        assert_eq!(
            refusal("rotate fast"),
            "demo.rover line 1 (`rotate fast`): `fast` is not a number"
        );
        assert!(refusal("rotate 4001").contains("out of range for REGDS_DRIVE_REQSPEED"));
        // The point turn's angles are within every wheel's calibrated limits.
        assert!(parse("s", "calibrate\npointturn").is_ok());
    }

    #[test]
    fn a_rotation_without_the_point_turns_steers_before_it_is_noted() {
        let notes_of = |src: &str| notes(&parse("s", src).unwrap());
        let start = "calibrate\nreset\n";
        assert!(notes_of(&format!("{start}pointturn\nwait 1\nrotate 500\nwait 3")).is_empty());
        // Stopping a rotation needs no point turn.
        assert!(notes_of(&format!("{start}rotate 0\nwait 1")).is_empty());
        assert_eq!(
            notes_of(&format!("{start}rotate \u{2212}500\nwait 1")).len(),
            1
        );
        assert_eq!(
            notes_of(&format!("{start}turn 20\nwait 1\nrotate 500\nwait 3")),
            [
                "line 5 rotates the rover on the spot, but its steers are not at the point \
                 turn's angles (wheel 1 at 20° for -46°, wheel 2 at 20° for 46°, wheel 5 at \
                 -20° for 46°, wheel 6 at -20° for -46°): the wheels would be dragged \
                 sideways; put `pointturn` and `wait 1` before it"
            ]
        );
        let unsteered = notes_of(&format!("{start}steer 1 -46\nwait 1\nrotate 500\nwait 3"));
        assert_eq!(unsteered.len(), 1);
        assert!(
            unsteered[0].contains("wheel 2 with no steer demand, wheel 3 with no steer demand"),
            "{unsteered:?}"
        );
        assert_eq!(
            notes_of(&format!("{start}pointturn\nrotate 500\nwait 3")),
            [
                "line 4 rotates the rover with no `wait` since its steers were sent to the \
                 point turn's angles: they take about a second to get there, dragged \
                 meanwhile; put `wait 1` before it"
            ]
        );
        // A wait between them, however many lines apart, is enough.
        assert!(notes_of(&format!(
            "{start}pointturn\nwatch 2\nlift all 10\nrotate 500\nwait 3"
        ))
        .is_empty());
    }

    #[test]
    fn limits_follow_the_scripts_own_calibration() {
        // Uncalibrated: -90..90; calibrated wheel 1 steer: -46..56; after stop: -90..90.
        assert!(parse("s", "steer 1 60").is_ok());
        assert_eq!(
            refusal("calibrate\nsteer 1 60"),
            "demo.rover line 2 (`steer 1 60`): wheel 1 steer 60 is outside its limits -46..56 (the calibration less 10°)"
        );
        assert!(parse("s", "calibrate\nstop\nsteer 1 60").is_ok());
        assert!(refusal("calibrate\nturn 50").contains("wheel 2 steer 50"));
    }

    #[test]
    fn commands_are_read_whatever_their_case_and_say_keeps_its_own() {
        let upper = parse(
            "s",
            "CALIBRATE\nReset\nDrive ALL 100\nWAIT 1\nSay Hello #1\n",
        )
        .unwrap();
        let lower = parse(
            "s",
            "calibrate\nreset\ndrive all 100\nwait 1\nsay Hello #1\n",
        )
        .unwrap();
        let actions = |lines: &[Line]| lines.iter().map(|l| l.actions.clone()).collect::<Vec<_>>();
        assert_eq!(actions(&upper), actions(&lower));
        assert_eq!(upper[4].actions, [Action::Say("Hello #1".to_owned())]);
        // The notes read the commands the same way: this script needs none.
        assert!(notes(&upper).is_empty(), "{:?}", notes(&upper));
        assert_eq!(
            notes(&parse("s", "Drive 1 100\nWait 1").unwrap()).len(),
            2,
            "no reset, no calibrate"
        );
    }

    #[test]
    fn a_drive_beyond_the_manual_s_safe_speed_is_noted_and_sent() {
        let lines = parse(
            "s",
            "calibrate\nreset\ndrive all -3000\ndrive 2 2500\nwait 1",
        )
        .unwrap();
        assert_eq!(
            notes(&lines),
            [
                "line 3 drives at -3000 ticks/s, beyond the ±2500 the manual calls about the \
                 highest safe speed; it is sent (the library allows ±4000)"
            ]
        );
        assert_eq!(frames(&lines[2..3]).len(), 6, "sent to all six wheels");
        // A register write of the same demand, on a DS board: noted too.
        let lines = parse(
            "s",
            "write 4 drive_reqspeed 3500\nwrite 4 drive_reqspeed 2000",
        )
        .unwrap();
        assert_eq!(notes(&lines).len(), 1);
        assert!(notes(&lines)[0].starts_with("line 1 drives at 3500 ticks/s"));
    }
}
