//! The local time in the capture's messages.

use std::time::SystemTime;

use kezuri_cam::probe::capture::utc_iso;

/// Local wall-clock time for messages (`2026-11-24 05:58:10 +0900`); UTC
/// where the local zone is unknown.
pub(super) fn local_time(t: SystemTime) -> String {
    #[cfg(unix)]
    {
        let secs = t.duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs()) as libc::time_t;
        // SAFETY: localtime_r writes only the `tm` we hand it.
        let mut tm: libc::tm = unsafe { std::mem::zeroed() };
        if !unsafe { libc::localtime_r(&secs, &mut tm) }.is_null() {
            let off = tm.tm_gmtoff / 60;
            let sign = if off < 0 { '-' } else { '+' };
            return format!(
                "{:04}-{:02}-{:02} {:02}:{:02}:{:02} {sign}{:02}{:02}",
                tm.tm_year + 1900,
                tm.tm_mon + 1,
                tm.tm_mday,
                tm.tm_hour,
                tm.tm_min,
                tm.tm_sec,
                off.abs() / 60,
                off.abs() % 60
            );
        }
    }
    utc_iso(t)
}
