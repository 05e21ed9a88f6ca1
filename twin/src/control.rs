//! The control channel of a running twin: a Unix socket that takes one text command per
//! connection (see [`crate::command`]) and answers with one reply, then closes.
//!
//! A reply that starts with `error: ` means the command was refused; anything else is the
//! command's report. `twin inject` is the client ([`send`]).

use std::io::{self, BufRead, BufReader, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::TwinError;

/// How long a client may take to send its command line.
const READ_TIMEOUT: Duration = Duration::from_millis(500);
/// How long a client waits for the twin's reply (the twin answers between emulation slices).
const REPLY_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest command line accepted.
const MAX_LINE: u64 = 1024;

/// The listening end, owned by the twin; the socket file is removed on drop.
pub struct ControlSocket {
    listener: UnixListener,
    path: PathBuf,
}

fn io_err<'a>(what: &'static str, path: &'a Path) -> impl FnOnce(io::Error) -> TwinError + 'a {
    move |source| TwinError::Io {
        what,
        path: path.to_path_buf(),
        source,
    }
}

impl ControlSocket {
    /// Listens at `path`. A socket file left there by a twin that is gone is replaced; a
    /// live twin's socket is not (that twin is reported as already running).
    pub fn bind(path: &Path) -> Result<ControlSocket, TwinError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io_err("cannot create the directory of", path))?;
        }
        if std::fs::symlink_metadata(path).is_ok() {
            if UnixStream::connect(path).is_ok() {
                return Err(TwinError::AlreadyRunning {
                    control: path.to_path_buf(),
                    // Named after a link only when that link is there (`--control` may name
                    // any socket).
                    link: crate::paths::link_of(path).filter(|link| link.exists()),
                });
            }
            std::fs::remove_file(path).map_err(io_err("cannot remove the stale socket", path))?;
        }
        let listener = UnixListener::bind(path).map_err(io_err("cannot listen on", path))?;
        listener
            .set_nonblocking(true)
            .map_err(io_err("cannot set up", path))?;
        Ok(ControlSocket {
            listener,
            path: path.to_path_buf(),
        })
    }

    /// The socket's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Serves every client waiting now: reads its command line and writes `handle`'s reply.
    /// Never blocks for long: a client that sends nothing is dropped after a short wait.
    pub fn serve(&mut self, handle: &mut dyn FnMut(&str) -> String) {
        while let Ok((stream, _)) = self.listener.accept() {
            // A client that misbehaves only loses its own answer.
            let _ = serve_one(stream, handle);
        }
    }
}

fn serve_one(stream: UnixStream, handle: &mut dyn FnMut(&str) -> String) -> io::Result<()> {
    stream.set_nonblocking(false)?;
    stream.set_read_timeout(Some(READ_TIMEOUT))?;
    let mut line = String::new();
    BufReader::new(io::Read::take(&stream, MAX_LINE)).read_line(&mut line)?;
    if line.trim().is_empty() {
        // A liveness probe (`hostctl`, or a second twin checking the socket): no command.
        return Ok(());
    }
    let mut reply = handle(line.trim());
    if !reply.ends_with('\n') {
        reply.push('\n');
    }
    (&stream).write_all(reply.as_bytes())
}

impl Drop for ControlSocket {
    fn drop(&mut self) {
        // Best effort: the file may already be gone.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Sends one command line to the twin listening at `path`; returns its reply.
pub fn send(path: &Path, line: &str) -> Result<String, TwinError> {
    let err = |what| io_err(what, path);
    let mut stream = UnixStream::connect(path).map_err(err(
        "no twin answers (start one with `twin --link PATH`) at control socket",
    ))?;
    stream
        .set_read_timeout(Some(REPLY_TIMEOUT))
        .map_err(err("cannot set up"))?;
    stream
        .write_all(format!("{line}\n").as_bytes())
        .map_err(err("cannot send to"))?;
    let mut reply = String::new();
    io::Read::read_to_string(&mut stream, &mut reply).map_err(err("no reply from"))?;
    Ok(reply.trim_end().to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_command_gets_its_reply_and_the_socket_goes_away() {
        let dir = std::env::temp_dir().join(format!("twin-ctl-test-{}", std::process::id()));
        let path = dir.join("port.ctl");
        let mut socket = ControlSocket::bind(&path).unwrap();
        // A live socket is kept, and the error says what to do; its link is named only when
        // there is one.
        let refused = |path: &Path| ControlSocket::bind(path).err().map(|e| e.to_string());
        let ctl = path.display();
        let advice = "stop it first (Ctrl-C where it runs), or start this one with another \
                      --link (or --control)";
        assert_eq!(
            refused(&path),
            Some(format!(
                "another twin is already running with control socket {ctl}: use it \
                 (`twin inject --control {ctl} status`), {advice}"
            ))
        );
        let link = dir.join("port");
        std::fs::write(&link, b"").unwrap();
        assert_eq!(
            refused(&path),
            Some(format!(
                "another twin is already running with control socket {ctl}: use it \
                 (`hostctl --port {} …`, `twin inject --control {ctl} status`), {advice}",
                link.display()
            ))
        );
        std::fs::remove_file(&link).unwrap();
        let client = {
            let path = path.clone();
            std::thread::spawn(move || send(&path, "cut 4"))
        };
        let mut seen = Vec::new();
        for _ in 0..200 {
            socket.serve(&mut |line| {
                seen.push(line.to_owned());
                format!("did {line}")
            });
            if !seen.is_empty() {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(client.join().unwrap().unwrap(), "did cut 4");
        assert_eq!(seen, ["cut 4"]);
        drop(socket);
        assert!(!path.exists());
        assert!(send(&path, "status").is_err());
        let _ = std::fs::remove_dir(&dir);
    }
}
