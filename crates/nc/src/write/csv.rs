//! The CSV motion dump (`kezuri run --emit csv`): one row per motion end
//! point, full precision, the same text the golden tests compare.

use std::fmt::Write;

use kezuri_geom::{MoveKind, Toolpath};

/// The header of the CSV dump.
pub const CSV_HEADER: &str = "line,kind,x,y,z,a,b,c,feed";

/// The columns a toolpath that moves U V W has after [`CSV_HEADER`]'s.
pub const CSV_UVW: &str = ",u,v,w";

/// Writes `line,kind,x,y,z,a,b,c,feed` rows: `kind` is `rapid`, `feed`,
/// `cw`, `ccw` or `probe`; dwells give no row; numbers are the shortest text
/// that reads back to the same double; `feed` is in mm/min and empty for
/// rapids. A toolpath that moves U V W (LinuxCNC's) has the columns
/// `u,v,w` after `feed`; any other keeps the header as it is.
pub fn csv(toolpath: &Toolpath) -> String {
    let mut out = String::with_capacity(64 * toolpath.moves.len() + 32);
    out.push_str(CSV_HEADER);
    let uvw = toolpath.moves.iter().any(|m| m.start.uvw() != [0.0; 3] || m.end.uvw() != [0.0; 3]);
    if uvw {
        out.push_str(CSV_UVW);
    }
    out.push('\n');
    for m in &toolpath.moves {
        let kind = match m.kind {
            // G28 and G53 moves are rapids too.
            MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => "rapid",
            MoveKind::Feed => "feed",
            MoveKind::Arc(arc) if arc.ccw => "ccw",
            MoveKind::Arc(_) => "cw",
            MoveKind::Probe => "probe",
            MoveKind::Dwell(_) => continue,
        };
        let e = m.end;
        let _ = write!(out, "{},{kind},{},{},{},{},{},{},", m.line, e.x, e.y, e.z, e.a, e.b, e.c);
        if !m.is_rapid() {
            let _ = write!(out, "{}", m.feed);
        }
        if uvw {
            let _ = write!(out, ",{},{},{}", e.u, e.v, e.w);
        }
        out.push('\n');
    }
    out
}
