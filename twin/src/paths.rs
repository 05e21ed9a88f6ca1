//! Where a twin keeps its pty link and control socket when nobody says otherwise.
//!
//! `hostctl` joins (or starts) the twin at [`default_link`] when it is given no port; the
//! two programs must agree on this path (a test checks that they do).

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// Directory under the runtime directory that holds the default twin's files.
pub const DIR_NAME: &str = "blodwen-twin";
/// File name of the default twin's pty link inside [`default_dir`].
pub const LINK_NAME: &str = "port";
/// Suffix that turns a link path into its control socket path.
pub const CONTROL_SUFFIX: &str = ".ctl";

/// `$XDG_RUNTIME_DIR/blodwen-twin`, or `/tmp/blodwen-twin` without a runtime directory.
pub fn default_dir() -> PathBuf {
    dir_under(std::env::var_os("XDG_RUNTIME_DIR"))
}

fn dir_under(runtime: Option<OsString>) -> PathBuf {
    runtime
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp"))
        .join(DIR_NAME)
}

/// The default twin's pty link: `<default_dir>/port`.
pub fn default_link() -> PathBuf {
    default_dir().join(LINK_NAME)
}

/// The control socket of the twin whose pty link is `link`: `<link>.ctl`.
pub fn control_of(link: &Path) -> PathBuf {
    let mut s = link.as_os_str().to_owned();
    s.push(CONTROL_SUFFIX);
    PathBuf::from(s)
}

/// The pty link whose control socket is `control` (the inverse of [`control_of`]); None
/// for a socket not named `<link>.ctl`.
pub fn link_of(control: &Path) -> Option<PathBuf> {
    let name = control.to_str()?;
    name.strip_suffix(CONTROL_SUFFIX)
        .filter(|link| !link.is_empty() && !link.ends_with('/'))
        .map(PathBuf::from)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_follow_the_runtime_dir() {
        assert_eq!(
            dir_under(Some("/run/user/1000".into())),
            PathBuf::from("/run/user/1000/blodwen-twin")
        );
        assert_eq!(dir_under(None), PathBuf::from("/tmp/blodwen-twin"));
        assert_eq!(
            dir_under(Some("".into())),
            PathBuf::from("/tmp/blodwen-twin")
        );
        assert_eq!(
            control_of(Path::new("/tmp/x/port")),
            PathBuf::from("/tmp/x/port.ctl")
        );
        assert_eq!(
            link_of(Path::new("/tmp/x/port.ctl")),
            Some(PathBuf::from("/tmp/x/port"))
        );
        assert_eq!(link_of(Path::new("/tmp/x/sock")), None);
        assert_eq!(link_of(Path::new("/tmp/x/.ctl")), None);
    }
}
