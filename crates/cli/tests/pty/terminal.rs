//! A pseudo-terminal for a test: kezuri is given one end, the test reads
//! or writes the other.
#![allow(dead_code)]

use std::fs::File;
use std::io::Write;
use std::os::unix::io::FromRawFd;
use std::thread;
use std::time::Duration;

/// A pseudo-terminal: the test is the instrument on `master`; kezuri opens `path`.
pub struct Pty {
    pub master: Option<File>,
    pub _slave: File,
    pub path: String,
}

pub fn pty() -> Pty {
    let (mut m, mut s) = (0, 0);
    // SAFETY: openpty writes two descriptors; no name buffer, default settings.
    let r = unsafe { libc::openpty(&mut m, &mut s, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) };
    assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
    // Not inherited by the kezuri processes other tests spawn: a copy of the
    // master there would keep the line up after the test closes it.
    // SAFETY: fcntl on the descriptors we just opened.
    unsafe {
        assert_eq!(libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC), 0);
        assert_eq!(libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC), 0);
    }
    // Raw from the start, so bytes written before kezuri opens the port are
    // not cooked (CR to LF, echo) by the line discipline.
    // SAFETY: termios calls on the slave we just opened.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        assert_eq!(libc::tcgetattr(s, &mut t), 0);
        libc::cfmakeraw(&mut t);
        assert_eq!(libc::tcsetattr(s, libc::TCSANOW, &t), 0);
    }
    let path = std::fs::read_link(format!("/proc/self/fd/{s}")).expect("slave path").display().to_string();
    // SAFETY: we own both descriptors.
    let (master, slave) = unsafe { (File::from_raw_fd(m), File::from_raw_fd(s)) };
    Pty { master: Some(master), _slave: slave, path }
}

impl Pty {
    pub fn send(&mut self, text: &str) {
        let m = self.master.as_mut().expect("master open");
        m.write_all(text.as_bytes()).unwrap();
        m.flush().unwrap();
        thread::sleep(Duration::from_millis(15));
    }
    /// The instrument's end goes away (cable pulled).
    pub fn cut(&mut self) {
        self.master.take();
    }
}
