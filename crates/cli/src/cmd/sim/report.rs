//! `sim`'s report, as text and as one JSON object: the grid, the rapids,
//! each tool (moves, time, volume removed, its worst gouge) and the
//! comparison with the target.

use std::fmt::Write as _;

use kezuri_cam::sim::compare::Comparison;
use kezuri_cam::sim::{SimReport, ToolCut};
use serde_json::json;

use super::SimArgs;
use crate::simulation::stock::StockSpec;
use crate::simulation::tools::ToolSet;
use crate::simulation::{Allowance, Figures};

/// A simulation done, all its report needs.
pub struct Done<'a> {
    pub args: &'a SimArgs,
    pub file: &'a str,
    pub tools: &'a ToolSet,
    pub stock: &'a StockSpec,
    /// The stock's highest point before cutting.
    pub top: f64,
    /// Where it came from: given, target or cutting-moves.
    pub top_from: &'a str,
    /// The gouge allowance of the comparison.
    pub allowance: Allowance,
    /// The figures of every cell: the grid, its range, the gouges.
    pub figures: &'a Figures,
    pub report: &'a SimReport,
    /// Seconds of each tool of `tools.table`.
    pub times: Vec<f64>,
    pub comparison: Option<&'a Comparison>,
    pub seconds: f64,
}

impl Done<'_> {
    /// The name and the time of a tool of the report.
    fn tool(&self, cut: &ToolCut) -> (&str, f64) {
        let k = self.tools.table.iter().position(|(n, _)| *n == cut.number).unwrap_or(0);
        (&self.tools.names[k], self.times.get(k).copied().unwrap_or(0.0))
    }

    fn removed(&self) -> f64 {
        self.report.tools.iter().map(|t| t.volume).sum()
    }

    pub fn json(&self) -> serde_json::Value {
        let (zmap, report) = (&self.figures.grid, self.report);
        let (lo, hi) = self.figures.range;
        let tools: Vec<_> = report
            .tools
            .iter()
            .enumerate()
            .map(|(k, cut)| {
                let (name, time) = self.tool(cut);
                let mut t = json!({
                    "number": cut.number,
                    "shape": name,
                    "moves": cut.moves,
                    "segments": cut.segments,
                    "time_s": time,
                    "volume_mm3": cut.volume,
                });
                if self.comparison.is_some() {
                    let g = self.figures.gouges.get(k).copied().flatten();
                    t["max_gouge_mm"] = json!(g.map_or(0.0, |g| g.depth));
                    t["max_gouge_at"] = json!(g.map(|g| g.at));
                }
                t
            })
            .collect();
        let mut v = json!({
            "file": self.file,
            "tool": self.tools.summary(),
            "tools_from": self.tools.from,
            "tools": tools,
            "volume_mm3": self.removed(),
            "res_mm": zmap.res,
            "nx": zmap.nx,
            "ny": zmap.ny,
            "cells": zmap.cells(),
            "tiles": self.figures.tiles.as_ref().map_or(1, |t| t.count),
            "stock": self.stock.json(zmap, self.top),
            "stock_top_mm": self.top,
            "stock_top_from": self.top_from,
            "moves": report.moves,
            "segments": report.segments,
            "rotary_moves": report.rotary_moves,
            "unplaced_moves": report.unplaced_moves,
            "chord_tol_mm": self.args.setup.chord_tol,
            "min_z_mm": lo,
            "max_z_mm": hi,
            "rapids_into_stock": report.rapid_hits.len(),
            "first_rapid_into_stock_line": report.rapid_hits.first().map(|h| h.line),
            "drill_side_moves": report.drill_side_moves.len(),
            "first_drill_side_move_line": report.drill_side_moves.first().map(|h| h.line),
            "rapid_hits": report.rapid_hits.iter().take(100)
                .map(|h| json!({"line": h.line, "move": h.index, "depth_mm": h.depth})).collect::<Vec<_>>(),
            "seconds": self.seconds,
        });
        if let Some(m) = self.tools.measured() {
            v["tool_profile"] = json!({
                "samples": m.samples(),
                "diameter_mm": 2.0 * m.radius(),
                "tip_mm": m.tip(),
                "lower_surface_corners": m.corners().len(),
            });
        }
        if let Some(c) = self.comparison {
            let extra = json!({
                "max_gouge_mm": c.max_gouge,
                "gouge_tol_mm": self.allowance.mm,
                "gouge_tol_from": self.allowance.from,
                "gouge_cells": self.figures.gouged,
                "max_left_mm": c.max_left,
                "mean_abs_dev_mm": c.mean_abs_dev,
                "max_gouge_at": c.gouge_at,
                "max_gouge_tool": self.figures.gouge_tool,
                "max_left_at": c.left_at,
                "compared_cells": c.compared,
                "cells_without_target": c.missing,
                "deviation_range_mm": [c.range.0, c.range.1],
                "histogram": {"edges_mm": c.histogram.edges, "counts": c.histogram.counts},
            });
            if let (Some(o), Some(e)) = (v.as_object_mut(), extra.as_object()) {
                o.extend(e.clone());
            }
        }
        v
    }

    pub fn text(&self) -> String {
        let (zmap, report) = (&self.figures.grid, self.report);
        let mut t = String::new();
        let name = match self.tools.measured() {
            Some(m) => format!(
                "{} (measured: Ø{:.4}, tip at {:.4}, {} samples)",
                self.tools.summary(),
                2.0 * m.radius(),
                m.tip(),
                m.samples()
            ),
            None => self.tools.summary(),
        };
        let top_note = match self.top_from {
            "target" => " (the target's top)",
            "cutting-moves" => " (from the feed moves)",
            _ => "",
        };
        let _ = writeln!(
            t,
            "{}: {name} over {}{top_note} at {} mm: {} × {} = {} cells",
            self.file,
            self.stock.describe(zmap),
            zmap.res,
            zmap.nx,
            zmap.ny,
            zmap.cells()
        );
        let _ =
            writeln!(t, "  moves      {} ({} straight segments), {:.2} s", report.moves, report.segments, self.seconds);
        if let Some(tiles) = &self.figures.tiles {
            let every = match (tiles.sample, tiles.sample % 100) {
                (1, _) => "every cell".to_string(),
                (f, 11..=13) => format!("every {f}th cell each way"),
                (f, _) => format!("every {f}{} cell each way", ["th", "st", "nd", "rd"].get(f % 10).unwrap_or(&"th")),
            };
            let _ = writeln!(
                t,
                "  tiles      {} of {} rows (over --max-memory); the pictures and the histogram of {every}",
                tiles.count, tiles.rows
            );
        }
        let (lo, hi) = self.figures.range;
        let _ = writeln!(t, "  surface    {lo:.4} … {hi:.4} mm");
        let _ = writeln!(t, "  removed    {:.3} mm³ (tools from {})", self.removed(), self.tools.from);
        for (k, cut) in report.tools.iter().enumerate() {
            let (name, time) = self.tool(cut);
            let label = if cut.number == 0 { name.to_string() } else { format!("T{} {name}", cut.number) };
            let gouge = match self.figures.gouges.get(k).copied().flatten() {
                Some(g) if g.depth <= self.allowance.mm => {
                    format!(", gouge {:.4} mm at ({:.3}, {:.3}), within the allowance", g.depth, g.at[0], g.at[1])
                }
                Some(g) => format!(", gouge {:.4} mm at ({:.3}, {:.3})", g.depth, g.at[0], g.at[1]),
                None if self.comparison.is_some() => ", no gouge".to_string(),
                None => String::new(),
            };
            let _ =
                writeln!(t, "    {label:<16} {:>7} moves {:>9.1} s {:>12.3} mm³{gouge}", cut.moves, time, cut.volume);
        }
        if report.unplaced_moves > 0 {
            let _ = writeln!(
                t,
                "  unplaced   {} moves before the program names X, Y and Z (or after G28) are not simulated",
                report.unplaced_moves
            );
        }
        if report.rotary_moves > 0 {
            let _ = writeln!(t, "  rotary     {} moves turn A/B/C (simulated in X Y Z only)", report.rotary_moves);
        }
        match report.rapid_hits.first() {
            None => t.push_str("  rapids     none into the stock\n"),
            Some(h) => {
                let _ = writeln!(
                    t,
                    "  RAPIDS     {} into the stock; first at line {} ({:.4} mm deep)",
                    report.rapid_hits.len(),
                    h.line,
                    h.depth
                );
            }
        }
        if let Some(h) = report.drill_side_moves.first() {
            let _ = writeln!(
                t,
                "  DRILL      {} sideways in the material; first at line {} ({:.4} mm deep)",
                crate::say::count(report.drill_side_moves.len() as u64, "feed"),
                h.line,
                h.depth
            );
        }
        if let Some(c) = self.comparison {
            let target = self.args.setup.compare.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
            let _ = writeln!(t, "compare with {target}: {} cells ({} outside the target)", c.compared, c.missing);
            let at = |p: Option<[f64; 2]>| p.map(|[x, y]| format!(" at ({x:.3}, {y:.3})")).unwrap_or_default();
            let by =
                self.figures.gouge_tool.filter(|&n| n != 0).map(|n| format!(", cut last by T{n}")).unwrap_or_default();
            let _ = writeln!(t, "  max gouge  {:.4} mm{}{by}", c.max_gouge, at(c.gouge_at));
            let (a, deeper) = (self.allowance, self.figures.gouged);
            let verdict =
                if deeper == 0 { "no cell deeper".to_string() } else { format!("{deeper} cells deeper: GOUGES") };
            let _ = writeln!(t, "  allowance  {:.4} mm ({}): {verdict}", a.mm, a.source());
            let _ = writeln!(t, "  max left   {:.4} mm{}", c.max_left, at(c.left_at));
            let _ = writeln!(t, "  mean |dev| {:.4} mm", c.mean_abs_dev);
            t.push_str("  deviation (simulated − target), mm:\n");
            let most = c.histogram.counts.iter().copied().max().unwrap_or(1).max(1);
            for (k, &n) in c.histogram.counts.iter().enumerate() {
                let bar = "#".repeat(((n as f64 / most as f64) * 40.0).round() as usize);
                let (a, b) = (c.histogram.edges[k], c.histogram.edges[k + 1]);
                let _ = writeln!(t, "    {a:>9.4} … {b:>9.4} {n:>10} {bar}");
            }
        }
        t
    }
}
