//! The tool database, the SQLite file of `kezuri tool db` (which fills and
//! shows it) and `kezuri wear apply --tool-id` (which reads a tool's newest
//! profile): one row per measured profile, one row per sample of it.
//!
//! The file says what it is: `PRAGMA application_id` is [`APPLICATION_ID`]
//! and `PRAGMA user_version` the schema's version ([`VERSION`]); any other
//! SQLite file is refused untouched. It runs in WAL mode (readers never wait
//! for a writer) and every connection waits up to [`BUSY_TIMEOUT`] for
//! another's write to end, so concurrent `add`s queue instead of failing.
//! One `add` is one transaction: a writer killed midway leaves nothing of
//! its profile behind.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context, Result};
use kezuri_geom::ToolProfile;
use rusqlite::{params, Connection, ErrorCode, OpenFlags, TransactionBehavior};

/// `PRAGMA application_id` of a kezuri tool database: "KzTD".
pub const APPLICATION_ID: i32 = 0x4B7A_5444;
/// The schema's version (`PRAGMA user_version`).
pub const VERSION: i32 = 1;
/// How long a connection waits for another's write.
pub const BUSY_TIMEOUT: Duration = Duration::from_secs(10);

const SCHEMA: &str = "
CREATE TABLE profile (
    id            INTEGER PRIMARY KEY,
    tool_id       TEXT    NOT NULL,
    measured_at   TEXT    NOT NULL,  -- UTC, 'YYYY-MM-DDTHH:MM:SSZ'
    added_at      TEXT    NOT NULL,  -- UTC, when `add` stored it
    source        TEXT    NOT NULL,  -- the profile CSV as named to `add`
    note          TEXT,
    samples       INTEGER NOT NULL,  -- its rows in sample
    tip_z_mm      REAL    NOT NULL,
    top_z_mm      REAL    NOT NULL,
    max_radius_mm REAL    NOT NULL
);
CREATE INDEX profile_by_tool ON profile (tool_id, measured_at, id);
CREATE TABLE sample (
    profile_id INTEGER NOT NULL REFERENCES profile (id),
    k          INTEGER NOT NULL,     -- 0, 1, ... up the tool (z increasing)
    z_mm       REAL    NOT NULL,
    radius_mm  REAL    NOT NULL,
    PRIMARY KEY (profile_id, k)
) WITHOUT ROWID;
";

/// One stored profile's record (its samples apart).
#[derive(Clone, Debug)]
pub struct Entry {
    /// Its number in the database.
    pub id: i64,
    /// The tool.
    pub tool_id: String,
    /// When it was measured (UTC, RFC 3339).
    pub measured_at: String,
    /// The CSV file it was read from.
    pub source: String,
    /// The note given to `add`.
    pub note: Option<String>,
    /// How many samples it has.
    pub samples: usize,
    /// Its lowest point, mm.
    pub tip_z_mm: f64,
    /// Its largest radius, mm.
    pub max_radius_mm: f64,
}

/// An open tool database.
pub struct Db {
    conn: Connection,
    path: PathBuf,
    /// A write failed for want of space: on closing, the `-wal` and `-shm`
    /// files are removed where nothing needs them.
    full: std::cell::Cell<bool>,
    /// The database file did not exist before this connection made it.
    made: bool,
}

impl Drop for Db {
    fn drop(&mut self) {
        if !self.full.get() {
            return;
        }
        // Close the connection first (its locks go with it).
        if let Ok(memory) = Connection::open_in_memory() {
            drop(std::mem::replace(&mut self.conn, memory));
            leave_nothing(&self.path, self.made);
        }
    }
}

/// After a write that found the disk full, with no connection of this
/// process open: removes the `-wal` and `-shm` files where no other
/// connection uses them (SQLite's own test: an exclusive lock on the
/// `-shm`'s byte 128) and the log holds no committed transaction; and the
/// database file itself where this run made it and it is still empty.
fn leave_nothing(path: &Path, made: bool) {
    use std::os::unix::io::AsRawFd;
    let with = |tail: &str| {
        let mut p = path.as_os_str().to_owned();
        p.push(tail);
        PathBuf::from(p)
    };
    let (wal, shm) = (with("-wal"), with("-shm"));
    let empty_made = || made && std::fs::metadata(path).is_ok_and(|m| m.len() == 0);
    let Ok(f) = std::fs::OpenOptions::new().read(true).write(true).open(&shm) else {
        if !wal.exists() && empty_made() {
            std::fs::remove_file(path).ok();
        }
        return;
    };
    // SAFETY: a plain struct of integers, zeroed then filled.
    let mut lock: libc::flock = unsafe { std::mem::zeroed() };
    lock.l_type = libc::F_WRLCK as _;
    lock.l_whence = libc::SEEK_SET as _;
    lock.l_start = 128;
    lock.l_len = 1;
    // SAFETY: `f` is open for the call; `lock` lives through it.
    if unsafe { libc::fcntl(f.as_raw_fd(), libc::F_SETLK, &lock) } != 0 {
        return; // Another connection uses the database.
    }
    let log = std::fs::read(&wal).unwrap_or_default();
    if commits(&log) {
        return; // Transactions not yet in the database file: they stay.
    }
    std::fs::remove_file(&wal).ok();
    std::fs::remove_file(&shm).ok();
    drop(f);
    if empty_made() {
        std::fs::remove_file(path).ok();
    }
}

/// Whether the write-ahead log `log` holds a committed transaction: a frame
/// whose "database size after commit" is set, its salts the header's.
fn commits(log: &[u8]) -> bool {
    if log.len() < 32 {
        return false;
    }
    let word = |at: usize| u32::from_be_bytes([log[at], log[at + 1], log[at + 2], log[at + 3]]);
    let page = match word(8) {
        1 => 65536,
        p => p as usize,
    };
    let (salt1, salt2) = (word(16), word(20));
    let mut at = 32;
    while page > 0 && at + 24 + page <= log.len() {
        if word(at + 8) != salt1 || word(at + 12) != salt2 {
            break;
        }
        if word(at + 4) != 0 {
            return true;
        }
        at += 24 + page;
    }
    false
}

fn is_code(e: &rusqlite::Error, code: ErrorCode) -> bool {
    matches!(e, rusqlite::Error::SqliteFailure(f, _) if f.code == code)
}

/// Whether `e` is SQLite's "database is locked" (busy).
fn is_busy(e: &anyhow::Error) -> bool {
    e.chain()
        .filter_map(|c| c.downcast_ref::<rusqlite::Error>())
        .any(|e| is_code(e, ErrorCode::DatabaseBusy) || is_code(e, ErrorCode::DatabaseLocked))
}

impl Db {
    /// Opens the database at `path`, making it first when `create` is set
    /// (otherwise a missing file is an error).
    pub fn open(path: &Path, create: bool) -> Result<Db> {
        let shown = path.display();
        if !create && !path.exists() {
            bail!("no tool database at {shown} (`kezuri tool db add` makes one; --db names another)");
        }
        let mut flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        if create {
            flags |= OpenFlags::SQLITE_OPEN_CREATE;
        }
        let made = !path.exists();
        let conn = Connection::open_with_flags(path, flags).with_context(|| format!("cannot open {shown}"))?;
        conn.busy_timeout(BUSY_TIMEOUT)?;
        let db = Db { conn, path: path.to_path_buf(), full: std::cell::Cell::new(false), made };
        // Making a new file races other `add`s making it; switching it to
        // WAL can meet another's lock without waiting (SQLite's deadlock
        // rule): try again until the busy timeout.
        let deadline = Instant::now() + BUSY_TIMEOUT;
        let mut attempt = 0u64;
        loop {
            match db.prepare(create) {
                Err(e) if is_busy(&e) && Instant::now() < deadline => {
                    attempt += 1;
                    std::thread::sleep(Duration::from_millis(5 + (attempt * 7 + u64::from(std::process::id())) % 40));
                }
                Err(e) => return Err(db.said(e)),
                Ok(()) => return Ok(db),
            }
        }
    }

    /// Checks the file is a kezuri tool database (making one of an empty
    /// file when `create`), in WAL mode.
    fn prepare(&self, create: bool) -> Result<()> {
        let (app, version, tables) = self.header()?;
        if app == 0 && version == 0 && tables == 0 {
            if !create {
                bail!("{} is not a kezuri tool database: it is empty", self.path.display());
            }
            self.create_schema()?;
        } else {
            self.check_header(app, version)?;
        }
        let mode: String = self.conn.query_row("PRAGMA journal_mode", [], |r| r.get(0))?;
        if !mode.eq_ignore_ascii_case("wal") {
            // Persistent in the file.
            let mode: String = self.conn.query_row("PRAGMA journal_mode = WAL", [], |r| r.get(0))?;
            if !mode.eq_ignore_ascii_case("wal") {
                bail!("{}: cannot use WAL journal mode (got {mode})", self.path.display());
            }
        }
        Ok(())
    }

    /// `(application_id, user_version, number of schema objects)`, read at
    /// once (another `add` may be making the file); a file that is not
    /// SQLite at all says so.
    fn header(&self) -> Result<(i32, i32, i64)> {
        let read = self.conn.query_row(
            "SELECT (SELECT application_id FROM pragma_application_id()), \
                    (SELECT user_version FROM pragma_user_version()), \
                    (SELECT count(*) FROM sqlite_schema)",
            [],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        );
        read.map_err(|e| {
            if is_code(&e, ErrorCode::NotADatabase) {
                anyhow!("{} is not a kezuri tool database (not an SQLite file)", self.path.display())
            } else {
                anyhow!(e).context(format!("cannot read {}", self.path.display()))
            }
        })
    }

    fn check_header(&self, app: i32, version: i32) -> Result<()> {
        let shown = self.path.display();
        if app != APPLICATION_ID {
            bail!("{shown} is an SQLite database but not a kezuri tool database (application_id {app:#x}, not {APPLICATION_ID:#x})");
        }
        if version > VERSION {
            bail!("{shown} has schema version {version}: written by a newer kezuri (this one reads version {VERSION})");
        }
        if version < 1 {
            bail!("{shown}: a kezuri tool database with no schema (user_version {version})");
        }
        Ok(())
    }

    /// Makes the tables in one transaction, unless a concurrent `add` has
    /// just made them.
    fn create_schema(&self) -> Result<()> {
        let tx = rusqlite::Transaction::new_unchecked(&self.conn, TransactionBehavior::Immediate)?;
        let (app, version, tables) = self.header()?;
        if app == 0 && version == 0 && tables == 0 {
            tx.execute_batch(SCHEMA)?;
            tx.execute_batch(&format!("PRAGMA application_id = {APPLICATION_ID}; PRAGMA user_version = {VERSION};"))?;
            tx.commit()?;
            Ok(())
        } else {
            drop(tx);
            self.check_header(app, version)
        }
    }

    /// An error of this database as said to the user: a write that found
    /// the disk full (or a quota, or the file size limit) says so, naming
    /// the file, and marks the `-wal` and `-shm` files for removal.
    fn said(&self, e: anyhow::Error) -> anyhow::Error {
        let io = e
            .chain()
            .filter_map(|c| c.downcast_ref::<rusqlite::Error>())
            .any(|e| is_code(e, ErrorCode::DiskFull) || is_code(e, ErrorCode::SystemIoFailure));
        if !io {
            return e;
        }
        // SAFETY: the handle of this open connection, read at once.
        let errno = unsafe { rusqlite::ffi::sqlite3_system_errno(self.conn.handle()) };
        let sqlite = |e: &rusqlite::Error| match e {
            rusqlite::Error::SqliteFailure(f, _) => Some(f.extended_code),
            _ => None,
        };
        let codes: Vec<i32> =
            e.chain().filter_map(|c| c.downcast_ref::<rusqlite::Error>()).filter_map(sqlite).collect();
        if [libc::ENOSPC, libc::EDQUOT, libc::EFBIG].contains(&errno) {
            self.full.set(true);
            return crate::files::cannot_write(&self.path, std::io::Error::from_raw_os_error(errno));
        }
        if codes.contains(&rusqlite::ffi::SQLITE_FULL) {
            self.full.set(true);
            return crate::files::cannot_write(&self.path, std::io::Error::from_raw_os_error(libc::ENOSPC));
        }
        // The `-shm` file could not grow (SQLite keeps no errno of it).
        if codes.contains(&rusqlite::ffi::SQLITE_IOERR_SHMSIZE) {
            self.full.set(true);
            return anyhow!(
                "cannot write {}: its shared-memory file ({0}-shm) cannot grow: the disk is full or the file size \
                 limit is reached",
                self.path.display()
            );
        }
        e
    }

    /// Stores `profile` of `tool_id` measured at `measured_at` (UTC text)
    /// in one transaction; returns its id.
    pub fn add(
        &mut self,
        tool_id: &str,
        profile: &ToolProfile,
        measured_at: &str,
        added_at: &str,
        source: &str,
        note: Option<&str>,
    ) -> Result<i64> {
        let r = self.add_one(tool_id, profile, measured_at, added_at, source, note);
        r.map_err(|e| self.said(e))
    }

    fn add_one(
        &mut self,
        tool_id: &str,
        profile: &ToolProfile,
        measured_at: &str,
        added_at: &str,
        source: &str,
        note: Option<&str>,
    ) -> Result<i64> {
        let tx = self.conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
        tx.execute(
            "INSERT INTO profile (tool_id, measured_at, added_at, source, note, samples, tip_z_mm, top_z_mm, max_radius_mm)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
            params![
                tool_id,
                measured_at,
                added_at,
                source,
                note,
                profile.z().len() as i64,
                profile.tip(),
                profile.top(),
                profile.max_radius()
            ],
        )?;
        let id = tx.last_insert_rowid();
        {
            let mut insert =
                tx.prepare("INSERT INTO sample (profile_id, k, z_mm, radius_mm) VALUES (?1, ?2, ?3, ?4)")?;
            for (k, (z, r)) in profile.z().iter().zip(profile.radius()).enumerate() {
                insert.execute(params![id, k as i64, z, r])?;
            }
        }
        tx.commit().with_context(|| format!("cannot write {}", self.path.display()))?;
        Ok(id)
    }

    /// Every tool's profiles (or `tool_id`'s) in time order (ties in the
    /// order added), tools by id.
    pub fn entries(&self, tool_id: Option<&str>) -> Result<Vec<Entry>> {
        entries(&self.conn, tool_id).map_err(|e| self.said(e))
    }

    /// The profiles of `tool_id` in time order with their samples (the
    /// latest alone when `latest_only`), read in one transaction; one at
    /// least: a tool with none is an error naming known ones.
    pub fn profiles(&mut self, tool_id: &str, latest_only: bool) -> Result<Vec<(Entry, ToolProfile)>> {
        let r = self.read_profiles(tool_id, latest_only);
        r.map_err(|e| self.said(e))
    }

    fn read_profiles(&mut self, tool_id: &str, latest_only: bool) -> Result<Vec<(Entry, ToolProfile)>> {
        let tx = self.conn.transaction()?;
        let mut entries = entries(&tx, Some(tool_id))?;
        if entries.is_empty() {
            return Err(unknown(&tx, &self.path, tool_id));
        }
        if latest_only {
            entries.drain(..entries.len() - 1);
        }
        let mut out = Vec::with_capacity(entries.len());
        let mut q = tx.prepare("SELECT z_mm, radius_mm FROM sample WHERE profile_id = ?1 ORDER BY k")?;
        for e in entries {
            let (mut z, mut radius) = (Vec::with_capacity(e.samples), Vec::with_capacity(e.samples));
            let mut rows = q.query([e.id])?;
            while let Some(row) = rows.next()? {
                z.push(row.get(0)?);
                radius.push(row.get(1)?);
            }
            if z.len() != e.samples {
                bail!(
                    "{}: profile {} of {tool_id} has {} of its {} samples",
                    self.path.display(),
                    e.id,
                    z.len(),
                    e.samples
                );
            }
            let p = ToolProfile::new(z, radius)
                .map_err(|err| anyhow!("{}: profile {} of {tool_id}: {err}", self.path.display(), e.id))?;
            out.push((e, p));
        }
        Ok(out)
    }
}

/// The newest profile of `tool_id` in the database at `db` (by the time it
/// was measured; of two at the same time, the one added last).
pub fn latest_profile(db: &Path, tool_id: &str) -> Result<ToolProfile> {
    let mut db = Db::open(db, false)?;
    let mut profiles = db.profiles(tool_id, true)?;
    Ok(profiles.pop().expect("profiles() returns one at least").1)
}

/// The records of the profiles (of `tool_id`, or all) in time order, tools
/// by id.
fn entries(conn: &Connection, tool_id: Option<&str>) -> Result<Vec<Entry>> {
    let mut q = conn.prepare(
        "SELECT id, tool_id, measured_at, source, note, samples, tip_z_mm, max_radius_mm FROM profile
         WHERE ?1 IS NULL OR tool_id = ?1 ORDER BY tool_id, measured_at, id",
    )?;
    let rows = q.query_map([tool_id], |r| {
        Ok(Entry {
            id: r.get(0)?,
            tool_id: r.get(1)?,
            measured_at: r.get(2)?,
            source: r.get(3)?,
            note: r.get(4)?,
            samples: r.get::<_, i64>(5)? as usize,
            tip_z_mm: r.get(6)?,
            max_radius_mm: r.get(7)?,
        })
    })?;
    Ok(rows.collect::<rusqlite::Result<_>>()?)
}

/// The error for a tool with no profiles, naming the first few known ones.
fn unknown(conn: &Connection, path: &Path, tool_id: &str) -> anyhow::Error {
    let known: Vec<String> = conn
        .prepare("SELECT DISTINCT tool_id FROM profile ORDER BY tool_id LIMIT 11")
        .and_then(|mut q| q.query_map([], |r| r.get(0))?.collect())
        .unwrap_or_default();
    let shown = path.display();
    match known.len() {
        0 => anyhow!("no tool {tool_id:?} in {shown}: it holds no tools yet"),
        1..=10 => anyhow!("no tool {tool_id:?} in {shown}; it knows {}", known.join(", ")),
        _ => anyhow!("no tool {tool_id:?} in {shown}; it knows {}, … (`kezuri tool db list`)", known[..10].join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_latest_profile_is_the_last_measured() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.sqlite");
        let p = |tip: f64, r: f64| ToolProfile::new(vec![tip, 1.0, 2.0], vec![0.0, r, r]).unwrap();
        let mut db = Db::open(&path, true).unwrap();
        db.add("T1", &p(0.0, 1.0), "2026-05-02T00:00:00Z", "2026-05-09T00:00:00Z", "a.csv", None).unwrap();
        // Added later, measured earlier.
        db.add("T1", &p(0.1, 0.9), "2026-05-01T00:00:00Z", "2026-05-09T00:00:00Z", "b.csv", None).unwrap();
        db.add("T2", &p(0.2, 0.5), "2026-05-03T00:00:00Z", "2026-05-09T00:00:00Z", "c.csv", Some("x")).unwrap();
        drop(db);
        assert_eq!(latest_profile(&path, "T1").unwrap(), p(0.0, 1.0));
        assert_eq!(latest_profile(&path, "T2").unwrap(), p(0.2, 0.5));
        let e = latest_profile(&path, "T3").unwrap_err().to_string();
        assert!(e.contains("no tool \"T3\"") && e.contains("T1, T2"), "{e}");
    }
}
