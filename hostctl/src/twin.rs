//! The twin as `hostctl`'s default port: with no `--port` and no `BLODWEN_PORT`, hostctl
//! joins the twin that serves the well-known link `$XDG_RUNTIME_DIR/blodwen-twin/port`
//! (`/tmp/blodwen-twin/port` without a runtime directory), or starts one there: the `twin`
//! program next to hostctl's own executable (or `$BLODWEN_TWIN`), detached, exiting by
//! itself after [`IDLE_EXIT_S`] seconds in which no program had the port open.
//!
//! These paths must agree with the twin's own defaults (`twin::paths`); a test checks it.
//!
//! **Settling in emulated time.** After `Ready`, hostctl waits (`--settle-ms`) for the slaves
//! the master has just hard-reset to reboot. A twin runs in emulated time, which may be
//! slower than the wall clock on a busy machine; when the port has a twin's control socket
//! next to it, hostctl measures that wait, and `run`'s pauses and live views, in the twin's
//! own time ([`TwinClock`]).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::cmd::run::{Clock, WallClock};
use crate::error::HostError;

/// Directory under the runtime directory that holds the default twin's files.
pub const DIR_NAME: &str = "blodwen-twin";
/// File name of the default twin's pty link.
pub const LINK_NAME: &str = "port";
/// Suffix that turns a link path into its control socket path.
pub const CONTROL_SUFFIX: &str = ".ctl";
/// A twin started by hostctl exits after this many seconds unused.
pub const IDLE_EXIT_S: u32 = 600;
/// How long a starting twin may take to put up its link.
pub const START_TIMEOUT: Duration = Duration::from_secs(20);

/// `$XDG_RUNTIME_DIR/blodwen-twin/port`, or `/tmp/blodwen-twin/port`.
pub fn default_link() -> PathBuf {
    std::env::var_os("XDG_RUNTIME_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp"))
        .join(DIR_NAME)
        .join(LINK_NAME)
}

/// The control socket of the twin whose link is `link`.
pub fn control_of(link: &Path) -> PathBuf {
    let mut s = link.as_os_str().to_owned();
    s.push(CONTROL_SUFFIX);
    PathBuf::from(s)
}

/// The `twin inject` command line that reaches the twin behind a port, for advice in
/// messages: the default link's twin needs no option, a twin at another path `--link PATH`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Inject {
    /// The port, when it is not the default link.
    link: Option<String>,
}

impl Inject {
    /// The command for the twin whose pty is `port`.
    pub fn for_port(port: &str) -> Self {
        let link = (Path::new(port) != default_link()).then(|| port.to_owned());
        Self { link }
    }
}

impl std::fmt::Display for Inject {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.link {
            None => write!(f, "twin inject"),
            // A path a shell would split or expand is quoted, so the line can be pasted.
            Some(p)
                if p.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "/._-+:,@".contains(c)) =>
            {
                write!(f, "twin inject --link {p}")
            }
            Some(p) => write!(f, "twin inject --link '{}'", p.replace('\'', r"'\''")),
        }
    }
}

/// Whether a live twin serves `link`: the link leads to a device and the twin's control
/// socket answers (a twin killed without cleaning up leaves neither alive).
pub fn is_running(link: &Path) -> bool {
    std::fs::metadata(link).is_ok()
        && std::os::unix::net::UnixStream::connect(control_of(link)).is_ok()
}

/// Sends one command line to the twin at control socket `control` and returns its reply,
/// if it answers within `timeout`.
fn ask(control: &Path, line: &str, timeout: Duration) -> Option<String> {
    use std::io::{Read, Write};
    let mut stream = std::os::unix::net::UnixStream::connect(control).ok()?;
    stream.set_read_timeout(Some(timeout)).ok()?;
    stream.write_all(format!("{line}\n").as_bytes()).ok()?;
    let mut reply = String::new();
    stream.read_to_string(&mut reply).ok()?;
    Some(reply)
}

/// The emulated time of the twin whose pty is `port` (µs), if a twin answers at its control
/// socket.
pub fn emulated_us(port: &Path) -> Option<u64> {
    let reply = ask(&control_of(port), "time", Duration::from_secs(2))?;
    reply.split_whitespace().next()?.parse().ok()
}

/// Tells the twin behind control socket `control` that the host set DTR `high` or low
/// (its pty has no modem lines); whether it took it. Bounded: a twin that does not answer
/// within a second is taken as gone.
pub fn set_dtr(control: &Path, high: bool) -> bool {
    let line = if high { "dtr high" } else { "dtr low" };
    ask(control, line, Duration::from_secs(1)).is_some_and(|reply| reply.starts_with("DTR "))
}

/// Time as a twin counts it: its emulated time, read over its control socket. `hostctl`
/// waits in it (the settle after the banner, `run`'s pauses and live views) when its port
/// is a twin's, so a twin slower than real time still sees the waits the script asks for.
pub struct TwinClock {
    port: PathBuf,
    start_us: u64,
    /// Wall-clock fallback if the twin stops answering.
    wall: Instant,
}

impl TwinClock {
    /// The clock of the twin behind `port`, if a twin answers there.
    pub fn of(port: &Path) -> Option<TwinClock> {
        Some(TwinClock {
            port: port.to_path_buf(),
            start_us: emulated_us(port)?,
            wall: Instant::now(),
        })
    }
}

impl Clock for TwinClock {
    fn now(&self) -> Duration {
        match emulated_us(&self.port) {
            Some(us) => Duration::from_micros(us.saturating_sub(self.start_us)),
            None => self.wall.elapsed(),
        }
    }

    fn sleep(&mut self, d: Duration) {
        let until = self.now() + d;
        let wall = Instant::now();
        // Bounded, should the twin stop answering or stall.
        while wall.elapsed() < d + START_TIMEOUT {
            let now = self.now();
            if now >= until {
                return;
            }
            std::thread::sleep((until - now).min(Duration::from_millis(20)));
        }
    }
}

/// The clock `hostctl` waits by on `port`: the twin's if a twin serves it, else the wall's.
pub fn clock_for(port: &str) -> Box<dyn Clock> {
    match TwinClock::of(Path::new(port)) {
        Some(clock) => Box::new(clock),
        None => Box::new(WallClock::new()),
    }
}

/// The `twin` program: `$BLODWEN_TWIN`, else `twin` next to this executable.
fn twin_program() -> Result<PathBuf, HostError> {
    if let Some(p) = std::env::var_os("BLODWEN_TWIN").filter(|p| !p.is_empty()) {
        return Ok(PathBuf::from(p));
    }
    let exe = std::env::current_exe().map_err(|e| HostError::Twin {
        why: format!("cannot find hostctl's own executable ({e})"),
    })?;
    let twin = exe.with_file_name("twin");
    if twin.exists() {
        Ok(twin)
    } else {
        Err(HostError::Twin {
            why: format!(
                "there is no `twin` program at {} (build it with `cargo build --release -p twin`, or set BLODWEN_TWIN)",
                twin.display()
            ),
        })
    }
}

/// The last lines of the twin's log, for an error message.
fn log_tail(log: &Path) -> String {
    let text = std::fs::read_to_string(log).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(3)..].join(" / ")
}

/// Joins the twin at the default link, or starts one; returns the link path. `note` hears
/// what was done when a twin is started.
pub fn join_or_start(note: &mut dyn FnMut(&str)) -> Result<String, HostError> {
    join_or_start_at(&default_link(), &twin_program()?, note)
}

/// File next to the link that hostctls starting a twin lock in turn.
const START_LOCK: &str = "start.lock";

/// Takes the start lock of the twin directory `dir`, waiting (bounded, Ctrl-C ends it)
/// while another hostctl holds it; released when the file is dropped.
fn lock_start(dir: &Path, text: &str) -> Result<std::fs::File, HostError> {
    let path = dir.join(START_LOCK);
    let file = std::fs::File::create(&path).map_err(|e| HostError::Twin {
        why: format!("cannot write {} ({e})", path.display()),
    })?;
    let start = Instant::now();
    loop {
        match file.try_lock() {
            Ok(()) => return Ok(file),
            Err(std::fs::TryLockError::WouldBlock) => {}
            Err(std::fs::TryLockError::Error(e)) => {
                return Err(HostError::Twin {
                    why: format!("cannot lock {} ({e})", path.display()),
                })
            }
        }
        if let Some(signal) = crate::interrupt::caught() {
            return Err(HostError::Interrupted {
                signal,
                at: format!(
                    "while another hostctl started the twin behind {text}, before the script \
                     started"
                ),
                line: None,
            });
        }
        if start.elapsed() > START_TIMEOUT {
            return Err(HostError::Twin {
                why: format!(
                    "another hostctl has been starting it for {} s (lock {}); stop that \
                     hostctl, or give --port",
                    START_TIMEOUT.as_secs(),
                    path.display()
                ),
            });
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// [`join_or_start`] with the link and the twin program given. Two hostctls started
/// together take turns (a lock file next to the link), so the second joins the twin the
/// first started instead of starting another over the same link.
fn join_or_start_at(
    link: &Path,
    program: &Path,
    note: &mut dyn FnMut(&str),
) -> Result<String, HostError> {
    let text = link.display().to_string();
    if is_running(link) {
        return Ok(text);
    }
    let dir = link.parent().unwrap_or(Path::new("/tmp"));
    std::fs::create_dir_all(dir).map_err(|e| HostError::Twin {
        why: format!("cannot create {} ({e})", dir.display()),
    })?;
    let _turn = lock_start(dir, &text)?;
    if is_running(link) {
        return Ok(text);
    }
    let log_path = dir.join("twin.log");
    let log = std::fs::File::create(&log_path).map_err(|e| HostError::Twin {
        why: format!("cannot write {} ({e})", log_path.display()),
    })?;
    let mut child = {
        use std::os::unix::process::CommandExt;
        Command::new(program)
            .arg("--link")
            .arg(link)
            .arg("--idle-exit")
            .arg(IDLE_EXIT_S.to_string())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log)
            // Its own process group: a Ctrl-C meant for hostctl does not stop the twin.
            .process_group(0)
            .spawn()
            .map_err(|e| HostError::Twin {
                why: format!("cannot run {} ({e})", program.display()),
            })?
    };
    let start = Instant::now();
    while !is_running(link) {
        if let Ok(Some(status)) = child.try_wait() {
            return Err(HostError::Twin {
                why: format!("it exited ({status}): {}", log_tail(&log_path)),
            });
        }
        if let Some(signal) = crate::interrupt::caught() {
            return Err(HostError::Interrupted {
                signal,
                at: format!(
                    "while the twin started, before the script started; the twin goes on \
                     starting behind {text} and exits after {} min unused",
                    IDLE_EXIT_S / 60
                ),
                line: None,
            });
        }
        if start.elapsed() > START_TIMEOUT {
            return Err(HostError::Twin {
                why: format!(
                    "no link at {text} after {} s (log: {})",
                    START_TIMEOUT.as_secs(),
                    log_path.display()
                ),
            });
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    note(&format!(
        "hostctl: started the rover twin behind {text} (pid {}; it exits after {} min unused; log {})",
        child.id(),
        IDLE_EXIT_S / 60,
        log_path.display()
    ));
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inject_advice_names_a_port_that_is_not_the_default_link() {
        let default = default_link();
        assert_eq!(
            Inject::for_port(&default.to_string_lossy()).to_string(),
            "twin inject"
        );
        assert_eq!(
            Inject::for_port("/tmp/lab/rover").to_string(),
            "twin inject --link /tmp/lab/rover"
        );
        assert_eq!(
            Inject::for_port("/tmp/my rover's pty").to_string(),
            r"twin inject --link '/tmp/my rover'\''s pty'"
        );
        assert_eq!(Inject::default().to_string(), "twin inject");
    }

    /// A stand-in for the twin: it notes its start, takes 0.3 s to put up its control
    /// socket and link (as the real one builds ten chips first), then answers for 2 s. A
    /// second one over the same link fails to bind, as the real one does.
    const FAKE_TWIN: &str = r#"import os, socket, sys, time
link = sys.argv[sys.argv.index("--link") + 1]
with open(os.path.join(os.path.dirname(link), "starts"), "a") as f:
    f.write("%d\n" % os.getpid())
time.sleep(0.3)
s = socket.socket(socket.AF_UNIX)
s.bind(link + ".ctl")
s.listen(8)
os.symlink("/dev/null", link)
s.settimeout(2)
try:
    while True:
        s.accept()[0].close()
except socket.timeout:
    pass
"#;

    #[test]
    fn two_hostctls_started_together_start_one_twin() {
        let dir = std::env::temp_dir().join(format!("hostctl-start-race-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let twin_dir = dir.join(DIR_NAME);
        std::fs::create_dir_all(&twin_dir).unwrap();
        let program = dir.join("fake-twin");
        std::fs::write(&program, format!("#!/usr/bin/env python3\n{FAKE_TWIN}")).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
        let link = twin_dir.join(LINK_NAME);

        let joins: Vec<_> = (0..2)
            .map(|_| {
                let (link, program) = (link.clone(), program.clone());
                std::thread::spawn(move || join_or_start_at(&link, &program, &mut |_| {}))
            })
            .collect();
        for join in joins {
            let joined = join.join().unwrap().map_err(|e| e.to_string());
            assert_eq!(joined, Ok(link.display().to_string()));
        }
        let starts = std::fs::read_to_string(twin_dir.join("starts")).unwrap();
        assert_eq!(starts.lines().count(), 1, "one twin started: {starts:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_control_socket_sits_next_to_the_link() {
        assert_eq!(
            control_of(Path::new("/run/user/7/blodwen-twin/port")),
            PathBuf::from("/run/user/7/blodwen-twin/port.ctl")
        );
        assert!(default_link().ends_with("blodwen-twin/port"));
        assert!(!is_running(Path::new("/nonexistent/blodwen-twin/port")));
    }
}
