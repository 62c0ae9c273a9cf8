//! `kezuri tool db`: a database of each tool's measured profiles as it
//! wears: `add` stores a profile CSV with the time it was
//! measured, `list` names the tools, `show` tabulates (and charts) one
//! tool's wear against its first profile. The file is SQLite
//! (`tool_store.rs` has its schema).

mod time;

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use kezuri_geom::ToolProfile;
use kezuri_picture::chart::{line_chart, Line};
use kezuri_picture::png_from_svg;
use serde_json::json;

use crate::files::write_atomic;
use crate::tool_store::{Db, Entry};

/// Heights at which `show` tabulates the radius change.
const HEIGHTS: usize = 10;

/// `kezuri tool db …`.
#[derive(Subcommand, Debug)]
#[command(after_help = "The database is one SQLite file (--db, default kezuri-tools.sqlite in this folder) that
commands running at once on this computer may share; keep it on a local disk (the way SQLite
lets them share it, its write-ahead log, does not work over a network file system).

Examples:
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-new.csv
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-worn.csv
  kezuri tool db add T7 t7-new.csv --at 2026-05-01T08:00:00Z \\
      --note \"new, 0.5 mm ball\"
  kezuri tool db add T7 t7-worn.csv
  kezuri tool db list
  kezuri tool db show T7 --png t7-wear.png")]
pub enum DbCommand {
    /// Store a measured profile of a tool, with the time it was measured.
    Add(AddArgs),
    /// One line per tool: its profiles, first and latest time, latest size.
    List(ListArgs),
    /// A tool's wear: each profile against the first, as a table (and a chart).
    Show(ShowArgs),
}

/// The database file, shared by every `tool db` command.
#[derive(Args, Debug)]
pub struct DbFile {
    /// The database (SQLite; `add` makes it when missing).
    #[arg(long, value_name = "FILE", default_value = "kezuri-tools.sqlite")]
    pub db: PathBuf,
}

/// `kezuri tool db add`.
#[derive(Args, Debug)]
#[command(after_help = "PROFILE.csv is a profile as `kezuri tool profile` writes it: header z_mm,radius_mm, z up
from the nominal tip. Each add is one transaction: concurrent adds wait
for each other (up to 10 s) and an add that is interrupted stores nothing.

Examples:
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-new.csv
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-worn.csv
  kezuri tool db add T7 t7-new.csv --at 2026-05-01T08:00:00Z \\
      --note \"new, 0.5 mm ball\"
  kezuri tool db add T7 t7-worn.csv
  kezuri tool db add T7 t7-worn.csv --db shop-tools.sqlite \\
      --at 2026-05-03T17:30:00+09:00")]
pub struct AddArgs {
    /// The tool's name (as on its holder: T12, ball6-a, …).
    #[arg(value_name = "TOOL_NAME")]
    pub tool_id: String,
    /// The profile CSV (`-` for standard input).
    #[arg(value_name = "PROFILE.csv")]
    pub profile: PathBuf,
    #[command(flatten)]
    pub file: DbFile,
    /// A note kept with the profile.
    #[arg(long, value_name = "TEXT")]
    pub note: Option<String>,
    /// When the profile was measured (RFC 3339; whole seconds) [default: now].
    #[arg(long, value_name = "RFC3339-TIME")]
    pub at: Option<String>,
    /// Print what was stored as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `kezuri tool db list`.
#[derive(Args, Debug)]
#[command(after_help = "Columns: the tool, how many profiles it has, when the first and the latest were measured
(UTC), and the latest's largest radius and tip z (mm up from the nominal tip).

Examples:
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-new.csv
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-worn.csv
  kezuri tool db add T7 t7-new.csv --at 2026-05-01T08:00:00Z \\
      --note \"new, 0.5 mm ball\"
  kezuri tool db add T7 t7-worn.csv
  kezuri tool db list
  kezuri tool db list --db kezuri-tools.sqlite --json")]
pub struct ListArgs {
    #[command(flatten)]
    pub file: DbFile,
    /// Print one JSON object: {"tools": [...]}, each with id, profiles, first, latest,
    /// max_radius_mm and tip_z_mm.
    #[arg(long)]
    pub json: bool,
}

/// `kezuri tool db show`.
#[derive(Args, Debug)]
#[command(after_help = "One row per profile in time order: when it was measured, its tip z and largest radius,
its radius less the first profile's at ten heights evenly over the span every profile
covers (negative: thinner), and its largest radius loss against the first anywhere both
cover, with where (the first is the reference: '-'). Tip wear shows as the tip z rising.
--png draws each profile's radius loss along z.

Examples:
  kezuri tool profile samples/tool-T7/new/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-new.csv
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7-worn.csv
  kezuri tool db add T7 t7-new.csv --at 2026-05-01T08:00:00Z \\
      --note \"new, 0.5 mm ball\"
  kezuri tool db add T7 t7-worn.csv
  kezuri tool db show T7
  kezuri tool db show T7 --png t7-wear.png
  kezuri tool db show T7 --db kezuri-tools.sqlite --json")]
pub struct ShowArgs {
    /// The tool's name in the database (as `add` stored it).
    #[arg(value_name = "TOOL_NAME")]
    pub tool_id: String,
    #[command(flatten)]
    pub file: DbFile,
    /// Also draw the radius loss along the tool, one line per profile, as a PNG.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// Print the table as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs a `tool db` command.
pub fn run(command: &DbCommand) -> Result<()> {
    match command {
        DbCommand::Add(args) => add(args),
        DbCommand::List(args) => list(args),
        DbCommand::Show(args) => show(args),
    }
}

fn check_tool_id(id: &str) -> Result<()> {
    if id.is_empty() || id.trim() != id || id.chars().any(char::is_control) || id.chars().count() > 100 {
        bail!("tool name {id:?}: give 1 to 100 characters, no control characters nor spaces at either end");
    }
    Ok(())
}

/// What is wrong when a tool whose largest radius was `before` measures
/// `now`: wear only takes material away, and not a tenth of the radius.
/// Larger by more than 0.01 mm or smaller by more than 10 %: another
/// nominal size.
fn size_change(before: f64, now: f64) -> Option<&'static str> {
    if now > before + 0.01 {
        Some("larger than")
    } else if now < 0.9 * before {
        Some("a tenth or more smaller than")
    } else {
        None
    }
}

fn add(args: &AddArgs) -> Result<()> {
    check_tool_id(&args.tool_id)?;
    let measured = match &args.at {
        Some(at) => time::parse_rfc3339(at)?,
        None => time::now(),
    };
    // The CSV first: a bad one leaves no new database behind.
    let profile = crate::tool_profile::read_profile(&args.profile)?;
    let source = if args.profile == Path::new("-") { "(stdin)".into() } else { args.profile.display().to_string() };
    let (measured_at, added_at) = (time::format_utc(measured), time::format_utc(time::now()));
    let mut db = Db::open(&args.file.db, true)?;
    let history =
        if db.entries(Some(&args.tool_id))?.is_empty() { Vec::new() } else { db.profiles(&args.tool_id, false)? };
    if let Some((entry, widest)) = history.iter().max_by(|a, b| a.1.max_radius().total_cmp(&b.1.max_radius())) {
        let (before, now) = (widest.max_radius(), profile.max_radius());
        if let Some(how) = size_change(before, now) {
            eprintln!(
                "warning: tool {}: this profile's largest radius is {now:.4} mm, {how} the {before:.4} mm of its \
                 profile of {}: another tool's? Its wear (`tool db show`) is measured against its first profile",
                args.tool_id, entry.measured_at
            );
        }
    }
    let id = db.add(&args.tool_id, &profile, &measured_at, &added_at, &source, args.note.as_deref())?;
    let count = db.entries(Some(&args.tool_id))?.len();
    if args.json {
        let v = json!({
            "id": id, "tool_id": args.tool_id, "measured_at": measured_at, "source": source, "note": args.note,
            "samples": profile.z().len(), "tip_z_mm": profile.tip(), "top_z_mm": profile.top(),
            "max_radius_mm": profile.max_radius(), "profiles": count,
        });
        println!("{v}");
    } else {
        println!(
            "stored profile {id} of tool {} in {}: {} samples, z {:.4} … {:.4} mm, max radius {:.4} mm, \
             measured {measured_at}, from {source} ({count} profile{} of this tool)",
            args.tool_id,
            args.file.db.display(),
            profile.z().len(),
            profile.tip(),
            profile.top(),
            profile.max_radius(),
            if count == 1 { "" } else { "s" },
        );
    }
    Ok(())
}

fn list(args: &ListArgs) -> Result<()> {
    let db = Db::open(&args.file.db, false)?;
    let entries = db.entries(None)?;
    // Entries come grouped by tool, in time order within a tool.
    let mut tools: Vec<(&Entry, &Entry, usize)> = Vec::new();
    for e in &entries {
        match tools.last_mut() {
            Some((first, latest, n)) if first.tool_id == e.tool_id => {
                *latest = e;
                *n += 1;
            }
            _ => tools.push((e, e, 1)),
        }
    }
    if args.json {
        let tools: Vec<_> = tools
            .iter()
            .map(|(first, latest, n)| {
                json!({"id": first.tool_id, "profiles": n, "first": first.measured_at, "latest": latest.measured_at,
                       "max_radius_mm": latest.max_radius_mm, "tip_z_mm": latest.tip_z_mm})
            })
            .collect();
        println!("{}", json!({ "tools": tools }));
        return Ok(());
    }
    let width = tools.iter().map(|t| t.0.tool_id.chars().count()).max().unwrap_or(0).max(4);
    println!("{:<width$}  profiles  first                 latest                max_radius_mm  tip_z_mm", "tool");
    // A stored size that is no number (a database changed outside kezuri)
    // is shown as `-` and said, never as `inf` or `NaN`.
    let mm = |v: f64| if v.is_finite() { format!("{v:.4}") } else { "-".to_string() };
    for (first, latest, n) in &tools {
        println!(
            "{:<width$}  {n:>8}  {}  {}  {:>13}  {:>8}",
            first.tool_id,
            first.measured_at,
            latest.measured_at,
            mm(latest.max_radius_mm),
            mm(latest.tip_z_mm)
        );
    }
    for (first, latest, _) in &tools {
        if !(latest.max_radius_mm.is_finite() && latest.tip_z_mm.is_finite()) {
            eprintln!(
                "warning: {}: profile {} of tool {} stores a max_radius_mm or tip_z_mm that is not a finite number \
                 (shown as -): the database was changed outside kezuri; `kezuri tool db show {}` reads its samples",
                args.file.db.display(),
                latest.id,
                first.tool_id,
                first.tool_id
            );
        }
    }
    if tools.is_empty() {
        println!("(no tools in {})", args.file.db.display());
    }
    Ok(())
}

/// The radius of `first` less that of `p` (mm, > 0 where `p` is thinner) at
/// every sample height of either inside both spans, in z order: the
/// difference of two polylines is straight between these heights.
fn loss_curve(first: &ToolProfile, p: &ToolProfile) -> Vec<(f64, f64)> {
    let (lo, hi) = (first.tip().max(p.tip()), first.top().min(p.top()));
    if lo > hi {
        return Vec::new();
    }
    let mut z: Vec<f64> =
        first.z().iter().chain(p.z()).copied().filter(|z| (lo..=hi).contains(z)).chain([lo, hi]).collect();
    z.sort_by(f64::total_cmp);
    z.dedup();
    z.into_iter().filter_map(|z| Some((z, first.radius_at(z)? - p.radius_at(z)?))).collect()
}

/// One row of `show`.
struct Row<'a> {
    entry: &'a Entry,
    profile: &'a ToolProfile,
    /// Radius less the first's at each height; `None` outside its span.
    change: Vec<Option<f64>>,
    /// The largest loss and where, `None` where the spans do not meet.
    largest: Option<(f64, f64)>,
    curve: Vec<(f64, f64)>,
}

fn show(args: &ShowArgs) -> Result<()> {
    if args.png.as_deref() == Some(Path::new("-")) {
        bail!("--png needs a file name (the table goes to standard output)");
    }
    let mut db = Db::open(&args.file.db, false)?;
    let profiles = db.profiles(&args.tool_id, false)?;
    let first = &profiles[0].1;
    // Heights evenly over the span all profiles cover; the first's span when
    // they have none in common.
    let lo = profiles.iter().map(|p| p.1.tip()).fold(f64::MIN, f64::max);
    let hi = profiles.iter().map(|p| p.1.top()).fold(f64::MAX, f64::min);
    let (lo, hi) = if lo < hi { (lo, hi) } else { (first.tip(), first.top()) };
    let heights: Vec<f64> = (0..HEIGHTS).map(|k| lo + (hi - lo) * k as f64 / (HEIGHTS - 1) as f64).collect();
    let rows: Vec<Row> = profiles
        .iter()
        .enumerate()
        .map(|(k, (entry, profile))| {
            let change = heights.iter().map(|&z| Some(profile.radius_at(z)? - first.radius_at(z)?)).collect::<Vec<_>>();
            let curve = loss_curve(first, profile);
            // The first is the reference: no loss of its own.
            let largest = if k == 0 {
                None
            } else {
                curve.iter().copied().max_by(|a, b| a.1.total_cmp(&b.1)).map(|(z, v)| (v, z))
            };
            Row { entry, profile, change, largest, curve }
        })
        .collect();
    if let Some(png) = &args.png {
        let lines: Vec<Line> = rows
            .iter()
            .enumerate()
            .map(|(k, r)| Line { label: format!("{} {}", k + 1, r.entry.measured_at), points: r.curve.clone() })
            .collect();
        let db = args
            .file
            .db
            .file_name()
            .map_or_else(|| args.file.db.display().to_string(), |n| n.to_string_lossy().into_owned());
        let title = format!("tool {} in {db}: radius loss against its first profile", args.tool_id);
        write_atomic(
            png,
            &png_from_svg(&line_chart(
                &title,
                "z up the tool from the nominal tip (mm)",
                "radius loss against the first profile (mm)",
                &lines,
            ))?,
        )?;
    }
    if args.json {
        let profiles: Vec<_> = rows
            .iter()
            .map(|r| {
                json!({
                    "id": r.entry.id, "measured_at": r.entry.measured_at, "source": r.entry.source,
                    "note": r.entry.note, "samples": r.entry.samples, "tip_z_mm": r.profile.tip(),
                    "top_z_mm": r.profile.top(), "max_radius_mm": r.profile.max_radius(),
                    "radius_change_mm": r.change, "largest_loss_mm": r.largest.map(|l| l.0),
                    "largest_loss_z_mm": r.largest.map(|l| l.1),
                })
            })
            .collect();
        println!("{}", json!({ "tool_id": args.tool_id, "heights_mm": heights, "profiles": profiles }));
        return Ok(());
    }
    print!("{}", table(&args.tool_id, &heights, &rows));
    if let Some(png) = &args.png {
        crate::say::note!("wrote {}", png.display());
    }
    Ok(())
}

/// The text table of `show`.
fn table(tool_id: &str, heights: &[f64], rows: &[Row]) -> String {
    use std::fmt::Write;
    let mut s = format!(
        "tool {tool_id}: {} profile{}; radius change against profile 1 (mm; negative: thinner) at z (mm)\n",
        rows.len(),
        if rows.len() == 1 { "" } else { "s" }
    );
    let _ = write!(s, "{:>3}  {:<20}  {:>8}  {:>8}", "#", "measured (UTC)", "tip_z", "max_r");
    for z in heights {
        let _ = write!(s, "  {z:>8.3}");
    }
    let _ = writeln!(s, "  {:>9}  {:>8}", "max_loss", "at_z");
    for (k, r) in rows.iter().enumerate() {
        let _ = write!(
            s,
            "{:>3}  {:<20}  {:>8.4}  {:>8.4}",
            k + 1,
            r.entry.measured_at,
            r.profile.tip(),
            r.profile.max_radius()
        );
        for c in &r.change {
            match c {
                // A change that rounds to nothing prints as 0, not -0.
                Some(c) => write!(s, "  {:>8}", format!("{c:.4}").replace("-0.0000", "0.0000")),
                None => write!(s, "  {:>8}", "-"),
            }
            .ok();
        }
        match r.largest {
            Some((v, z)) => writeln!(s, "  {v:>9.4}  {z:>8.3}"),
            None => writeln!(s, "  {:>9}  {:>8}", "-", "-"),
        }
        .ok();
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loss_curve_meets_both_spans() {
        let p = |tip: f64, r: f64| ToolProfile::new(vec![tip, 1.0, 2.0], vec![0.0, r, r]).unwrap();
        let curve = loss_curve(&p(0.0, 1.0), &p(0.5, 0.9));
        // From the worn tip (where it has no radius yet) up: straight between.
        assert_eq!(curve, [(0.5, 0.5), (1.0, 1.0 - 0.9), (2.0, 1.0 - 0.9)]);
    }
}
