//! The terminal's size, for views that redraw in place.

/// Standard output's width in columns, when it is a terminal that says.
#[cfg(unix)]
pub fn stdout_width() -> Option<usize> {
    use nix::libc;
    let mut size = libc::winsize {
        ws_row: 0,
        ws_col: 0,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    // SAFETY: TIOCGWINSZ writes one `winsize` through the pointer, which points at a
    // live, writable `winsize`; on a descriptor that is no terminal it fails and writes
    // nothing.
    let done = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut size) };
    (done == 0 && size.ws_col > 0).then_some(usize::from(size.ws_col))
}

/// Standard output's width in columns: unknown here, so each line counts as one row.
#[cfg(not(unix))]
pub fn stdout_width() -> Option<usize> {
    None
}
