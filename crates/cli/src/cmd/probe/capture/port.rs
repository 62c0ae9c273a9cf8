//! The serial port, read with a bounded wait so that silences can be
//! reported and a hang-up never blocks. Its input is flushed on open: what
//! the instrument sent while nobody read the port is not a reading of the
//! points to come.

use std::time::Duration;

use anyhow::{Context, Result};
use serialport::{ClearBuffer, SerialPort};

/// What one wait on the port gave.
pub(super) enum Got {
    Data(usize),
    Quiet,
    Gone(String),
}

/// What arrived before the line settled (`Port::settle`).
pub(super) struct Settled {
    /// The line went quiet (otherwise the wait gave up).
    pub(super) quiet: bool,
    /// Bytes discarded.
    pub(super) discarded: usize,
    /// The first of them.
    pub(super) sample: Vec<u8>,
}

/// The serial port, read with a bounded wait.
pub(super) struct Port {
    #[cfg(unix)]
    port: serialport::TTYPort,
    #[cfg(not(unix))]
    port: Box<dyn serialport::SerialPort>,
}

impl Port {
    /// Opens the port and discards its pending input (tcflush on Unix).
    pub(super) fn open(path: &str, baud: u32) -> Result<Port> {
        let builder = serialport::new(path, baud)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(Duration::from_millis(200));
        #[cfg(unix)]
        {
            let port = builder.open_native().with_context(|| format!("cannot open serial port {path}"))?;
            // Non-blocking reads: a hang-up must never leave us blocked in read().
            use std::os::unix::io::AsRawFd;
            let fd = port.as_raw_fd();
            // SAFETY: fcntl on a descriptor we own.
            unsafe {
                let flags = libc::fcntl(fd, libc::F_GETFL);
                if flags >= 0 {
                    libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK);
                }
            }
            port.clear(ClearBuffer::Input).with_context(|| format!("cannot flush serial port {path}"))?;
            Ok(Port { port })
        }
        #[cfg(not(unix))]
        {
            let port = builder.open().with_context(|| format!("cannot open serial port {path}"))?;
            port.clear(ClearBuffer::Input).with_context(|| format!("cannot flush serial port {path}"))?;
            Ok(Port { port })
        }
    }

    /// Discards what arrives until the line has been quiet for `quiet`, or
    /// for at most `limit`; `Err` when the port goes away.
    pub(super) fn settle(&mut self, quiet: Duration, limit: Duration) -> Result<Settled, String> {
        let start = std::time::Instant::now();
        let mut last = start;
        let mut got = Settled { quiet: false, discarded: 0, sample: Vec::new() };
        let mut buf = [0u8; 512];
        while start.elapsed() < limit {
            match self.read(&mut buf, Duration::from_millis(20)) {
                Got::Data(n) => {
                    last = std::time::Instant::now();
                    got.discarded += n;
                    let room = 64usize.saturating_sub(got.sample.len()).min(n);
                    got.sample.extend_from_slice(&buf[..room]);
                }
                Got::Quiet if last.elapsed() >= quiet => {
                    got.quiet = true;
                    break;
                }
                Got::Quiet => {}
                Got::Gone(why) => return Err(why),
            }
        }
        Ok(got)
    }

    #[cfg(unix)]
    pub(super) fn read(&mut self, buf: &mut [u8], wait: Duration) -> Got {
        use std::os::unix::io::AsRawFd;
        let fd = self.port.as_raw_fd();
        let mut pfd = libc::pollfd { fd, events: libc::POLLIN, revents: 0 };
        let ms = wait.as_millis().clamp(1, 60_000) as libc::c_int;
        // SAFETY: one valid pollfd.
        let r = unsafe { libc::poll(&mut pfd, 1, ms) };
        if r < 0 {
            let e = std::io::Error::last_os_error();
            return if e.kind() == std::io::ErrorKind::Interrupted { Got::Quiet } else { Got::Gone(e.to_string()) };
        }
        if r == 0 {
            return Got::Quiet;
        }
        // Readable, hung up or in error: read() tells which (data still
        // buffered is read before a hang-up is reported).
        // SAFETY: reading into a buffer we own, at most its length.
        let n = unsafe { libc::read(fd, buf.as_mut_ptr().cast(), buf.len()) };
        match n {
            n if n > 0 => Got::Data(n as usize),
            0 => Got::Gone("end of file".into()),
            _ => {
                let e = std::io::Error::last_os_error();
                let hung = pfd.revents & (libc::POLLHUP | libc::POLLERR | libc::POLLNVAL) != 0;
                match e.kind() {
                    std::io::ErrorKind::Interrupted => Got::Quiet,
                    std::io::ErrorKind::WouldBlock if !hung => Got::Quiet,
                    std::io::ErrorKind::WouldBlock => Got::Gone("hang-up".into()),
                    _ => Got::Gone(e.to_string()),
                }
            }
        }
    }

    #[cfg(not(unix))]
    pub(super) fn read(&mut self, buf: &mut [u8], wait: Duration) -> Got {
        let _ = self.port.set_timeout(wait);
        match std::io::Read::read(&mut self.port, buf) {
            Ok(0) => Got::Gone("end of file".into()),
            Ok(n) => Got::Data(n),
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => Got::Quiet,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => Got::Quiet,
            Err(e) => Got::Gone(e.to_string()),
        }
    }
}
