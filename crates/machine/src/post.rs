//! `--post NAME` and the machine file's `[post]`: how G-code is written for
//! a control. A preset (`fanuc`, `haas`, `linuxcnc`, `grbl`, `mach3`) gives
//! everything; the machine file's `[post]` changes what it names:
//!
//! ```toml
//! [post]
//! preset = "haas"            # used when --post is not given
//! program_number = 1001      # O1001 (Fanuc, Haas)
//! start = "G90 G17 G94 G40 G49 G80"   # safe start codes, after G21/G20
//! work_offset = "G54"
//! retract = "G28"            # before tool changes and at the end: G28, G53 or none
//! prestage = true            # T<next> after M06
//! optional_stop = true       # M01 before each tool change after the first
//! length_offset = true       # G43 H<the tool's H> on the first Z move after a change
//! spindle_dwell_s = 0        # dwell after the spindle starts
//! dwell_unit = "ms"          # G04 P in ms or s (Mach3 is set either way)
//! coolant = "flood"          # flood, mist or none
//! home = "G28"               # X Y at the end: G28, none, or a park position [X, Y]
//! end = "M30"
//! line_numbers = 10          # N10, N20, … (0: none)
//! digits = 3
//! arcs = "ijk"               # ijk, r or lines
//! comments = true
//! percent = true             # % first and last line [default: Fanuc, Haas]
//! block_limit = 128          # characters a block may have
//! byte_limit = 512000        # bytes a program may have
//! ```

use std::collections::BTreeMap;
use std::path::Path;

use kezuri_nc::write::{Arcs, CoolantChoice, Home, Retract, WriteOptions, PRESETS};
use serde::Deserialize;

use crate::error::{fail, Error, ErrorKind, Result};
use crate::machine::{Machine, ToolEntry};

/// The machine file's `[post]`, as written: every key optional.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PostFile {
    preset: Option<String>,
    /// The program number (`O1001`, Fanuc and Haas).
    pub program_number: Option<u32>,
    start: Option<String>,
    work_offset: Option<String>,
    retract: Option<String>,
    prestage: Option<bool>,
    optional_stop: Option<bool>,
    length_offset: Option<bool>,
    spindle_dwell_s: Option<f64>,
    dwell_unit: Option<String>,
    coolant: Option<String>,
    home: Option<toml::Value>,
    end: Option<String>,
    line_numbers: Option<u32>,
    digits: Option<u8>,
    arcs: Option<String>,
    comments: Option<bool>,
    percent: Option<bool>,
    block_limit: Option<u32>,
    byte_limit: Option<u64>,
}

/// The write options of preset `name` (else `[post] preset`, else
/// `fanuc`) with the machine file's `[post]` on top, and the length
/// register of every tool of the table whose H is not its number.
pub fn options(file: &PostFile, name: Option<&str>, tools: &BTreeMap<u32, ToolEntry>) -> Result<WriteOptions> {
    let name = name.or(file.preset.as_deref()).unwrap_or("fanuc");
    let mut o = WriteOptions::preset(name).map_err(|e| Error::new(ErrorKind::UnknownPost, e.to_string()))?;
    let Some(setup) = o.setup.as_mut() else { unreachable!("a preset has a setup") };
    let word = |key: &str, v: &Option<String>| -> Result<Option<String>> {
        match v {
            Some(t) if t.contains(['(', ')', ';', '%', '\n']) => {
                fail!(Invalid, "post.{key}: '{t}' must be codes only (no comment, no %)")
            }
            v => Ok(v.as_ref().map(|t| t.trim().to_ascii_uppercase())),
        }
    };
    if let Some(n) = file.program_number {
        o.program_number = n;
    }
    if let Some(t) = word("start", &file.start)? {
        // The writer gives the units and keeps positions absolute with
        // incremental arc centres: a start that changed them would move
        // every position of the program.
        if let Some(w) = t.split_whitespace().find(|w| ["G20", "G21", "G91", "G90.1"].contains(w)) {
            fail!(Invalid, "post.start: '{w}' would change what every position of the program means (units, G91, G90.1): leave it out");
        }
        setup.start = t;
    }
    if let Some(t) = word("work_offset", &file.work_offset)? {
        setup.work_offset = t;
    }
    if let Some(t) = word("end", &file.end)? {
        if !t.split_whitespace().any(|w| ["M30", "M02", "M2"].contains(&w)) {
            fail!(Invalid, "post.end: '{t}' does not end the program: it must hold M30 or M02");
        }
        setup.end = t;
    }
    if let Some(r) = &file.retract {
        setup.retract = match r.trim().to_ascii_uppercase().as_str() {
            "G28" => Retract::Reference,
            "G53" => Retract::MachineZero,
            "NONE" => Retract::None,
            _ => fail!(Invalid, "post.retract: '{r}' is not G28, G53 or none"),
        };
    }
    setup.prestage = file.prestage.unwrap_or(setup.prestage);
    setup.optional_stop = file.optional_stop.unwrap_or(setup.optional_stop);
    setup.length_offset = file.length_offset.unwrap_or(setup.length_offset);
    if let Some(d) = file.spindle_dwell_s {
        if !(0.0..=3600.0).contains(&d) {
            fail!(Invalid, "post.spindle_dwell_s: {d} is not 0 to 3600 seconds");
        }
        setup.spindle_dwell = d;
    }
    if let Some(u) = &file.dwell_unit {
        o.dwell_ms = Some(match u.trim() {
            "ms" => true,
            "s" => false,
            _ => fail!(Invalid, "post.dwell_unit: '{u}' is not ms or s"),
        });
    }
    if let Some(c) = &file.coolant {
        setup.coolant = match c.trim().to_ascii_lowercase().as_str() {
            "flood" => CoolantChoice::Flood,
            "mist" => CoolantChoice::Mist,
            "none" => CoolantChoice::Off,
            _ => fail!(Invalid, "post.coolant: '{c}' is not flood, mist or none"),
        };
    }
    if let Some(h) = &file.home {
        setup.home = match h {
            toml::Value::String(t) if t.eq_ignore_ascii_case("G28") => Home::Reference,
            toml::Value::String(t) if t.eq_ignore_ascii_case("none") => Home::None,
            toml::Value::Array(a) => {
                let v: Vec<f64> = a.iter().filter_map(|v| v.as_float().or(v.as_integer().map(|i| i as f64))).collect();
                match v[..] {
                    [x, y] if a.len() == 2 && x.is_finite() && y.is_finite() => Home::Park([x, y]),
                    _ => fail!(Invalid, "post.home: a park position is two numbers [X, Y], machine coordinates in mm"),
                }
            }
            _ => fail!(Invalid, "post.home: '{h}' is not G28, none or a park position [X, Y]"),
        };
    }
    if let Some(step) = file.line_numbers {
        o.line_numbers = (step > 0).then_some(step);
    }
    if let Some(d) = file.digits {
        if d > 6 {
            fail!(Invalid, "post.digits: {d} is not 0 to 6");
        }
        o.digits = d;
    }
    if let Some(a) = &file.arcs {
        o.arcs = match a.trim().to_ascii_lowercase().as_str() {
            "ijk" => Arcs::Ijk,
            "r" => Arcs::Radius,
            "lines" | "none" => Arcs::Lines,
            _ => fail!(Invalid, "post.arcs: '{a}' is not ijk, r or lines"),
        };
    }
    o.comments = file.comments.unwrap_or(o.comments);
    o.percent = file.percent.or(o.percent);
    o.block_limit = file.block_limit.or(o.block_limit);
    o.byte_limit = file.byte_limit.or(o.byte_limit);
    setup.registers = tools.iter().filter(|(t, e)| e.h != **t).map(|(t, e)| (*t, e.h)).collect();
    Ok(o)
}

impl PostFile {
    /// The `preset` this `[post]` names, if any.
    pub fn preset(&self) -> Option<&str> {
        self.preset.as_deref()
    }

    /// Whether this `[post]` says the machine uses tool length offsets:
    /// its `length_offset`, else its preset's; `None` where it says
    /// neither.
    pub fn length_offset(&self) -> Option<bool> {
        match (self.length_offset, &self.preset) {
            (Some(on), _) => Some(on),
            (None, Some(p)) => WriteOptions::preset(p).ok().and_then(|o| o.setup).map(|s| s.length_offset),
            (None, None) => None,
        }
    }
}

/// The write options of `--post NAME` for `machine` (its `[post]` and
/// tool table), else of the machine file's preset, else of the control the
/// name of the `output` file says (`.ngc` linuxcnc, `.gcode` grbl: as every
/// command reads the file back), else fanuc.
pub fn for_machine(machine: &Machine, name: Option<&str>, output: Option<&Path>) -> Result<WriteOptions> {
    if let Some(n) = name.filter(|n| !PRESETS.iter().any(|p| p.eq_ignore_ascii_case(n.trim()))) {
        fail!(UnknownPost, "--post {n}: not a post; the posts are {}", PRESETS.join(", "));
    }
    let named = || match output.and_then(|p| kezuri_nc::detect::by_extension(&p.to_string_lossy())) {
        Some(kezuri_nc::Dialect::LinuxCnc) => Some("linuxcnc"),
        Some(kezuri_nc::Dialect::Grbl) => Some("grbl"),
        _ => None,
    };
    let name = name.or_else(|| machine.post.preset.is_none().then(named).flatten());
    options(&machine.post, name, &machine.tools)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<WriteOptions> {
        let file: PostFile = toml::from_str(text).map_err(|e| Error::new(ErrorKind::Syntax, e.to_string()))?;
        options(&file, None, &BTreeMap::new())
    }

    #[test]
    fn the_documented_example_reads() {
        let doc = include_str!("post.rs");
        let example: String = doc
            .lines()
            .skip_while(|l| !l.contains("```toml"))
            .skip(2)
            .take_while(|l| !l.contains("```"))
            .map(|l| l.trim_start_matches("//!").trim_start().to_string() + "\n")
            .collect();
        let o = parse(&example).unwrap();
        let s = o.setup.unwrap();
        assert_eq!((o.program_number, o.line_numbers, o.block_limit), (1001, Some(10), Some(128)));
        assert_eq!((s.retract, s.home, s.coolant), (Retract::Reference, Home::Reference, CoolantChoice::Flood));
        assert!(s.prestage && s.length_offset);
    }

    #[test]
    fn overrides_and_refusals() {
        let o = parse("preset = \"linuxcnc\"\nhome = [10, -5.5]\narcs = \"r\"\nretract = \"none\"\npercent = true")
            .unwrap();
        assert_eq!(o.percent, Some(true));
        let s = o.setup.unwrap();
        assert_eq!((s.home, s.retract, o.arcs), (Home::Park([10.0, -5.5]), Retract::None, Arcs::Radius));
        for (text, words) in [
            ("preset = \"okuma\"", "unknown post 'okuma'"),
            ("retract = \"G30\"", "post.retract: 'G30'"),
            ("home = [1]", "two numbers"),
            ("start = \"G90 (SAFE)\"", "codes only"),
            ("start = \"G20 G90 G17\"", "'G20' would change"),
            ("start = \"G91 G17\"", "'G91' would change"),
            ("end = \"\"", "does not end the program"),
            ("end = \"M05\"", "does not end the program"),
            ("spindle_dwell_s = -1", "0 to 3600"),
            ("coolant = \"air\"", "post.coolant"),
            ("program = 5", "unknown field `program`"),
        ] {
            let e = parse(text).expect_err(text).to_string();
            assert!(e.contains(words), "{text}: {e}");
        }
    }
}
