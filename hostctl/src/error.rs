//! Everything that can go wrong in `hostctl`, each with the next step.

use std::io;

use shared::master::LinkError;
use shared::protocol::{DecodeError, EncodeError};

use crate::twin::Inject;

/// One `hostctl` failure. Every message names what was wrong and how to fix
/// it; bad input is caught before anything is sent.
#[derive(Debug, thiserror::Error)]
pub enum HostError {
    /// The device number is not 0 (master) or 1..9 (controllers).
    #[error("device `{given}` does not exist: use 0 for the master or 1..9 for a controller (DS: 1, 2, 4, 5, 7, 8; LL: 3, 6, 9)")]
    BadDevice {
        /// The text given on the command line.
        given: String,
    },

    /// No register of that name is on the device's table.
    #[error("device {device} ({board} table) has no register named `{name}`{hint}")]
    UnknownRegister {
        /// The name given.
        name: String,
        /// The device addressed.
        device: u8,
        /// The device's table name.
        board: &'static str,
        /// Either close names (", did you mean …?") or a pointer to the table list.
        hint: String,
    },

    /// The register exists, but on another kind of board.
    #[error("register `{name}` is on the {other}, not on device {device} ({board}); address one of devices {devices} instead (readset and watch: --device)")]
    WrongBoard {
        /// The name given.
        name: String,
        /// The device addressed.
        device: u8,
        /// The device's table name.
        board: &'static str,
        /// The tables that have the register, e.g. `DS table` or `DS and LL tables`.
        other: String,
        /// The devices that use those tables.
        devices: String,
    },

    /// A register number beyond the device's table.
    #[error("device {device} ({board} table) has registers 0..{last}; there is no register {id}")]
    NoSuchId {
        /// The id given.
        id: u32,
        /// The device addressed.
        device: u8,
        /// The device's table name.
        board: &'static str,
        /// The highest id on that table.
        last: u8,
    },

    /// The value is not a number.
    #[error("`{given}` is not a number: give the value in engineering units, e.g. 1000 or -40.5 (a register without units, such as a bit field, also takes hexadecimal: 0x1000)")]
    BadValue {
        /// The text given.
        given: String,
    },

    /// The value is outside what the register can carry.
    #[error("{given} is out of range for {}: allowed {}", .allowed.place(), .allowed.span())]
    OutOfRange {
        /// The value as given.
        given: String,
        /// What the register allows.
        allowed: Allowed,
    },

    /// A value above 0 that the register's mapping truncates to 0: it would be sent as 0.
    #[error("{given} is finer than {} can carry: it would arrive as 0 (its values run {} in {steps} steps); write 0, or {step} or more", .allowed.place(), .allowed.span())]
    BelowStep {
        /// The value as given.
        given: String,
        /// What the register allows.
        allowed: Allowed,
        /// The smallest value above 0 the register carries, rounded up to two digits.
        step: String,
        /// How many steps its range holds.
        steps: u32,
    },

    /// A fraction for a register that holds whole numbers (an unmapped one).
    #[error("{value} is not a whole number, but {} holds whole numbers {}; give one, e.g. {example}", .allowed.place(), .allowed.span())]
    NotWhole {
        /// The value given.
        value: f32,
        /// What the register allows.
        allowed: Allowed,
        /// The value without its fraction.
        example: f32,
    },

    /// `watch --count 0`, which would poll nothing.
    #[error("`watch --count 0` would poll nothing; give --count 1 or more, or leave --count out to poll until interrupted")]
    ZeroCount,

    /// The register cannot be written.
    #[error("{register} on device {device} is read-only; use `hostctl read {device} {register}` to see it")]
    ReadOnly {
        /// The register's name.
        register: &'static str,
        /// The device addressed.
        device: u8,
    },

    /// The read-set index is not 0..7.
    #[error(
        "read set `{given}` does not exist: sets are 0..7 (hostctl's one-off reads use set 7)"
    )]
    BadSet {
        /// The text given.
        given: String,
    },

    /// More registers than a read set holds.
    #[error("{count} registers given, but a read set holds at most 24; split them over two sets")]
    TooManyRegisters {
        /// How many were given.
        count: usize,
    },

    /// `watch` of a set that has no standard contents, without registers.
    #[error("read set {set} has no standard contents (only sets 0, 1 and 2 do), and a set configured by an earlier `hostctl readset` is gone (opening the port resets the master, which empties every read set); name the registers to watch after the options, e.g. `hostctl watch --readset {set} TEMPAMBIENT`")]
    NoStandardSet {
        /// The set asked for.
        set: u8,
    },

    /// `watch` of a standard set on a device of the wrong kind.
    #[error("read set {set}'s standard contents are for {wanted} boards, but device {device} is {board}; pick one of devices {devices} or name the registers")]
    StandardSetMismatch {
        /// The set asked for.
        set: u8,
        /// The board kind the set is made for.
        wanted: &'static str,
        /// The device asked for.
        device: u8,
        /// That device's board kind.
        board: &'static str,
        /// The devices that fit.
        devices: String,
    },

    /// `watch --device` names boards on which the set's ids are different registers.
    #[error("the set reads {first_regs} on device {first} ({first_board}) but {other_regs} on device {other} ({other_board}); a read set holds ids, which each device reads on its own table, so watch boards of one kind together (the master apart)")]
    MixedSet {
        /// The first device.
        first: u8,
        /// Its board kind.
        first_board: &'static str,
        /// The registers there, e.g. `REGMASTER_EXCEPTIONDATA (11)`.
        first_regs: String,
        /// A device where they differ.
        other: u8,
        /// Its board kind.
        other_board: &'static str,
        /// The registers there.
        other_regs: String,
    },

    /// A demand outside the position limits the original library enforces.
    #[error("wheel {wheel} {motor} {value} is outside its limits {min}..{max} (the calibration less 10°)")]
    PositionLimit {
        /// Wheel 1..6.
        wheel: u8,
        /// `steer` or `lift`.
        motor: &'static str,
        /// The demand given.
        value: f32,
        /// Lowest allowed demand.
        min: f32,
        /// Highest allowed demand.
        max: f32,
    },

    /// `--pairs` is not a list of wheel pairs.
    #[error("`--pairs {given}` is not a list of wheel pairs: give one or more of 0, 1, 2 separated by commas (pair p is wheels 2p+1 and 2p+2 on controllers 3p+1..3p+3, as the library's init() mask numbers them), e.g. `--pairs 0` for the rear pair (wheels 1 and 2) alone")]
    BadPairs {
        /// What was given.
        given: String,
    },

    /// A script line names a wheel or controller of a pair `--pairs` leaves out.
    #[error("{what} is on wheel pair {pair} (wheels {}, {}; controllers {}..{}), which --pairs leaves out; add {pair} to --pairs if it is fitted", 2 * pair + 1, 2 * pair + 2, 3 * pair + 1, 3 * pair + 3)]
    PairLeftOut {
        /// The wheel or controller, in words.
        what: String,
        /// Its pair, 0..2.
        pair: u8,
    },

    /// The script file could not be read.
    #[error("cannot read the script {path}: {source}")]
    ScriptFile {
        /// The path given.
        path: String,
        /// What the operating system said.
        source: io::Error,
    },

    /// The script as a whole cannot be run (its line endings, its length); nothing was sent.
    #[error("{path}: {why}; nothing was sent")]
    ScriptForm {
        /// The script's path.
        path: String,
        /// What is wrong and how to fix it.
        why: String,
    },

    /// A script line is wrong; nothing was sent.
    #[error("{path} line {line} (`{text}`): {why}")]
    ScriptLine {
        /// The script's path.
        path: String,
        /// Line number, from 1.
        line: usize,
        /// The line.
        text: String,
        /// What is wrong with it.
        why: String,
    },

    /// A script line failed while running; the lines before it were done.
    #[error("{path} line {line} (`{text}`) failed: {source}")]
    ScriptStep {
        /// The script's path.
        path: String,
        /// Line number, from 1.
        line: usize,
        /// The line.
        text: String,
        /// The failure.
        source: Box<HostError>,
    },

    /// A script ran to its end with a board stopped by an exception or not answering
    /// (exit status 3).
    #[error("{path} ran to its end with boards stopped or out of reach: {}. A board in exception stops its motors until a `reset` line in the script clears it, which holds once the cause is gone (docs/safety.md lists each exception's causes); a controller that does not answer is off the bus or unpowered; a rebooted one needs `calibrate` again", faults.join("; "))]
    EndedInException {
        /// The script's path.
        path: String,
        /// What held the rover stopped at the end, one entry per board.
        faults: Vec<String>,
    },

    /// A watch with `--count` ended with a round that could not read some devices (exit
    /// status 3).
    #[error("the watch ended without the values of device(s) {}: the last round had no answer from them or lost their reply on the serial line (its rows say which); a controller that does not answer is off the bus or unpowered", list(devices))]
    WatchEndedUnread {
        /// The devices whose row had no values in the last round.
        devices: Vec<u8>,
    },

    /// Ctrl-C or SIGTERM stopped a script ([`crate::interrupt`]).
    #[error("stopped by {} {at}", crate::interrupt::name(*signal))]
    Interrupted {
        /// The signal's number.
        signal: i32,
        /// Where the script was and what follows, e.g. "during line 3 (`wait 30`); hostctl
        /// closes the port, …" ([`crate::interrupt::CLOSES`]).
        at: String,
        /// The script line it was at, if any.
        line: Option<usize>,
    },

    /// The twin could not be started or joined.
    #[error("cannot start the twin: {why}; pass --port PATH for a real rover, or start the twin yourself with `twin --link PATH` and pass hostctl the same --port PATH")]
    Twin {
        /// What went wrong.
        why: String,
    },

    /// `--port` was given an empty path.
    #[error("--port is empty: give the serial device's path (e.g. /dev/ttyACM0 or the twin's pty), or leave --port out to use BLODWEN_PORT or the twin")]
    EmptyPort,

    /// Neither `--port` nor `BLODWEN_PORT` says where the rover is.
    #[error("no serial port given: pass --port PATH (e.g. /dev/ttyACM0 or the twin's pty), set BLODWEN_PORT, or start the twin")]
    NoPort,

    /// The port is the link of a twin that no longer runs: a link left by a twin that was
    /// killed may now lead to another program's terminal.
    #[error("{path} is the link of a twin that is gone (its control socket {control} does not answer), and it may now lead to another program's terminal, so hostctl did not open it; start a twin there (`twin --link {path}`), or remove the stale link and its socket")]
    TwinGone {
        /// The link given.
        path: String,
        /// Its control socket.
        control: String,
    },

    /// The port is a file of another kind than a serial device.
    #[error("{path} is {what}, not a serial device; give the rover's port (e.g. /dev/ttyACM0) or a twin's link (`twin --link PATH`)")]
    NotSerial {
        /// The path given.
        path: String,
        /// What it is, in words.
        what: &'static str,
    },

    /// The serial device could not be opened.
    #[error("cannot open {path}: {source}; {}", open_hint(path, source))]
    Open {
        /// The path given.
        path: String,
        /// What the operating system said.
        source: serialport::Error,
    },

    /// The master never said `Ready`.
    #[error("no `Ready` from {path}: {why}; is the rover/twin running? is {path} right? does another program read it (a serial monitor, ModemManager: `fuser {path}` names it)? (a port last closed without HUPCL, e.g. after `stty -hupcl`, does not reset the master when opened: run `stty -F {path} hupcl` and retry; a twin told to lose serial bytes loses the banner too: `twin inject --link {path} status` shows any still pending, `drop-serial clear` cancels them)")]
    NoBanner {
        /// The port.
        path: String,
        /// What was seen instead.
        why: String,
    },

    /// Writing hostctl's own output failed: nothing is wrong with the rover or the link.
    #[error("cannot write hostctl's output: {0} (standard output was closed, e.g. by `| head`); the rover and the serial link are not at fault")]
    Output(io::Error),

    /// Reading or writing the port failed.
    #[error("serial I/O failed: {0}; check the cable or restart the twin. The rover may still be moving: a master with power of its own goes on with the last demands, unless the session wrote REGMASTER_PCTIMEOUT (`write 0 pctimeout MS`), which stops every motor that long after the PC went quiet")]
    Io(#[from] io::Error),

    /// The reply did not arrive in time.
    #[error("{}", timeout_words(*device, *expected, *got, *master, inject))]
    Timeout {
        /// The device addressed.
        device: u8,
        /// Bytes expected.
        expected: usize,
        /// Bytes received.
        got: usize,
        /// What the master said when asked for its last link error afterwards.
        master: MasterSays,
        /// How the advice reaches a twin behind the port.
        inject: Inject,
    },

    /// The master's start-up banner arrived in the middle of a session.
    #[error("the master rebooted during this session (its start-up banner arrived unasked: a reset, its watchdog or a power dip), so the read sets, REGMASTER_PCTIMEOUT and every board's state are gone and every controller is in its boot exception; run the command again, and check the power and the cable if it keeps happening")]
    MasterRebooted,

    /// More bytes came than the reply has.
    #[error("device {device}'s reply was followed by {extra} more bytes than asked for: the link is out of step, so the values are not shown; run the command again, and check the cable if it keeps happening")]
    OutOfStep {
        /// The device addressed.
        device: u8,
        /// How many bytes came after the reply.
        extra: usize,
    },

    /// The master reported a failed write.
    #[error("{}: code {code:#04x} ({words}); {}", refused_what(*device, register, *writes), refusal_advice(*device, *code, inject))]
    WriteRefused {
        /// The device addressed.
        device: u8,
        /// The register written, or what the frame's writes are (a parameter block).
        register: &'static str,
        /// How many register writes the frame held: the master sends each of a frame's
        /// writes even after one fails, so with more than one the board may hold some.
        writes: u8,
        /// The reply byte.
        code: u8,
        /// What the code means.
        words: String,
        /// How the advice reaches a twin behind the port.
        inject: Inject,
    },

    /// Writes of one script line were refused; the line's other writes were still sent.
    #[error("{refused} of the line's {writes} writes refused, the other {} sent; the first: {first}", writes - refused)]
    WritesRefused {
        /// How many were refused.
        refused: usize,
        /// How many writes the line has.
        writes: usize,
        /// The first refusal.
        first: Box<HostError>,
    },

    /// A `stop` left controllers running: each answered out of exception after its
    /// REG_EXCEPTIONDATA write, so its DISABLEDEXCEPTIONS masks REMOTESLAVE (bit 3).
    #[error("controller(s) {} ignored the stop: out of exception after its REG_EXCEPTIONDATA write, each masks REMOTESLAVE in its DISABLEDEXCEPTIONS (bit 3, value 8), so its bridges stayed on, a drive decaying from its last duty under power. The run ends here, and closing the port reboots the rover, which stops it (each boot clears DISABLEDEXCEPTIONS). Leave bit 3 clear in the script's `write … disabledexceptions` lines to keep `stop` working", list(devices))]
    StopIgnored {
        /// The controllers still running.
        devices: Vec<u8>,
    },

    /// A `calibrate` could not stop a running controller before its frames, so none was
    /// sent.
    #[error("no calibration sent: controller {device} could not be stopped first ({source}). The run ends here, and closing the port reboots the rover, which stops every board")]
    CalibrateNotHeld {
        /// The controller whose REG_EXCEPTIONDATA write failed.
        device: u8,
        /// Why.
        source: Box<HostError>,
    },

    /// REG_RESET writes that would let stopped controllers run again were refused.
    #[error("controller(s) {} stay stopped: the REG_RESET that releases each was refused (the first: {first}). The run ends here, and closing the port reboots the rover", list(devices))]
    ReleaseRefused {
        /// The controllers whose REG_RESET was refused.
        devices: Vec<u8>,
        /// The first refusal.
        first: Box<HostError>,
    },

    /// The set-read-set reply was not the register count.
    #[error("device {device} answered {got} to set-read-set {set}, expected the count {expected}{words}")]
    ReadSetRejected {
        /// The device addressed.
        device: u8,
        /// The set configured.
        set: u8,
        /// The count sent.
        expected: usize,
        /// The reply byte.
        got: u8,
        /// What the reply means, if it is an error code (with a leading "; ").
        words: String,
    },

    /// The frame could not be built (input is checked before this, so it
    /// points at a bug in hostctl).
    #[error("cannot build the frame: {0}; please report this as a hostctl bug")]
    Encode(#[from] EncodeError),

    /// The reply could not be decoded against the device's table.
    #[error("cannot decode the reply of device {device}: {source}; the link may be out of step, so reconnect")]
    Decode {
        /// The device addressed.
        device: u8,
        /// What was wrong.
        source: DecodeError,
    },
}

/// The master's answer, after a timeout, to a read of its link-error registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MasterSays {
    /// It did not answer either.
    Silent,
    /// REGMASTER_LASTERROR (0: none since boot) and REGMASTER_ERRORCOUNT.
    Answered {
        /// The last link error's code.
        code: u8,
        /// Link errors since boot.
        count: u16,
    },
}

/// A timeout in words: the cause the master names, if it names one, else who did not
/// answer; then what to do.
fn timeout_words(
    device: u8,
    expected: usize,
    got: usize,
    master: MasterSays,
    inject: &Inject,
) -> String {
    let late = format!("within 1 s ({got} of {expected} reply bytes)");
    let (code, count) = match master {
        MasterSays::Silent if device == 0 => {
            return format!(
                "the master did not answer {late}, nor a read of its error registers: the \
                 master or the serial line is not answering (while the remote control has the \
                 link, the master ignores the PC); check the cable, turn the remote control \
                 off, reset the rover, or restart the twin"
            )
        }
        MasterSays::Silent => {
            return format!(
                "device {device} did not answer {late}, and neither did the master when asked \
                 for its error registers: the master or the serial line is not answering, \
                 which is no fault of device {device} (while the remote control has the link, \
                 the master ignores the PC); check the cable, turn the remote control off, \
                 reset the rover, or restart the twin"
            )
        }
        MasterSays::Answered { code, count } => (code, count),
    };
    let who = if device == 0 {
        "the master".to_owned()
    } else {
        format!("device {device}")
    };
    let Some(error) = LinkError::from_code(code) else {
        return if device == 0 {
            // It answers now and saw nothing wrong: the reply was lost on the way back.
            format!(
                "the master did not answer {late} but answers now and reports no link error, \
                 so its reply was lost on the serial line; retry, and check the cable if it \
                 keeps happening"
            )
        } else {
            // A controller that did not answer the master is recorded (NoAnswer): with
            // nothing recorded since the master's boot, the reply was lost on the serial
            // line, or the master rebooted meanwhile.
            format!(
                "device {device} did not answer {late}, but the master answers now and reports \
                 no link error since its boot: the reply was lost on the serial line or the \
                 master rebooted meanwhile; retry, and check the cable if it keeps happening"
            )
        };
    };
    let advice = match error {
        LinkError::Truncated => {
            "a byte was lost on the serial line; retry, and check the cable if it keeps happening"
                .to_owned()
        }
        LinkError::Framing | LinkError::Overrun => {
            "the serial line damaged a byte; retry, and check the cable and the baud rate \
             (115200 8N1) if it keeps happening"
                .to_owned()
        }
        LinkError::NoAnswer if device != 0 => format!(
            "controller {device} is not answering the master on the I2C bus; check that it is \
             fitted and powered (on the twin: `{inject} restore {device}`), then reset the \
             rover{STILL_BOOTING}"
        ),
        LinkError::NoAnswer => {
            "a controller is not answering the master on the I2C bus; reset the rover".to_owned()
        }
        LinkError::EmptyReadSet => {
            "the read set was empty, so the master had nothing to send: it has rebooted since \
             the set was configured (a reset, or its watchdog); run the command again"
                .to_owned()
        }
        _ => "the frame reached the master damaged; retry, and reset the rover or restart the \
              twin if it keeps happening"
            .to_owned(),
    };
    format!(
        "{who} did not answer {late}; the master's last link error since its boot (it may be \
         older than this command): {} (code {code}, {count} in all): {advice}",
        error.describe()
    )
}

/// The other cause of a controller's silence right after the port opened: the master's
/// boot resets every controller, and a short `--settle-ms` may not wait for them.
const STILL_BOOTING: &str = "; or, if this was the first command after the port opened, \
     it was still rebooting from the master's boot: leave `--settle-ms` at its default, 2000";

/// The start of a refused write's message: the register, or for a frame of several writes
/// (which the master sends each of, so some may have been taken) the frame and its count.
fn refused_what(device: u8, register: &str, writes: u8) -> String {
    if writes > 1 {
        format!(
            "device {device} refused a write of {register} ({writes} register writes; the \
             master sent each, so the board may hold some of them)"
        )
    } else {
        format!("device {device} refused the write to {register}")
    }
}

/// The next step after the master refused a write with error reply `code` (0x80 | the
/// link error's code).
fn refusal_advice(device: u8, code: u8, inject: &Inject) -> String {
    match LinkError::from_code(code & !shared::master::ERROR_REPLY_FLAG) {
        Some(LinkError::NoAnswer) => format!(
            "controller {device} is not answering the master on the I2C bus; check that it is \
             fitted and powered (on the twin: `{inject} restore {device}`), then reset the \
             rover{STILL_BOOTING}"
        ),
        _ => "the frame reached the master damaged or not as sent; retry, and reset the rover \
              or restart the twin if it keeps happening"
            .to_owned(),
    }
}

/// The next step after a failed open. A port another program holds (its lock, or
/// TIOCEXCL's EBUSY, both reported as `NoDevice` on POSIX) is not a missing rover.
fn open_hint(path: &str, source: &serialport::Error) -> String {
    if source.kind() == serialport::ErrorKind::NoDevice {
        format!(
            "{path} is in use by another program (another hostctl, a terminal such as \
             screen or minicom); close it first, then retry"
        )
    } else {
        format!("is the rover/twin running? is {path} right?")
    }
}

/// The values a register on a device allows, for the range errors.
#[derive(Debug, Clone, PartialEq)]
pub struct Allowed {
    /// The register's name.
    pub register: &'static str,
    /// The device addressed.
    pub device: u8,
    /// Lowest allowed value.
    pub min: f32,
    /// Highest allowed value.
    pub max: f32,
    /// The unit, with a leading space, or empty.
    pub unit: String,
}

impl Allowed {
    /// "REGISTER on device N".
    fn place(&self) -> String {
        format!("{} on device {}", self.register, self.device)
    }

    /// "MIN..MAX UNIT".
    fn span(&self) -> String {
        format!("{}..{}{}", self.min, self.max, self.unit)
    }
}

/// Controllers in words: "2, 7".
pub(crate) fn list(devices: &[u8]) -> String {
    devices
        .iter()
        .map(u8::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}
