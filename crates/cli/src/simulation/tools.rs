//! Which cutter `sim` cuts each tool's moves with: the machine file's
//! tool table, `--tool`/`--profile`, or one tool for all.

use std::collections::BTreeMap;

use anyhow::{bail, Result};
use kezuri_cam::sim::{MeasuredTool, Tool};
use kezuri_cam::Cutter;
use kezuri_machine::ToolEntry;

use super::SimSetup;

/// The cutter of each tool number the program cuts with, in the order they
/// first move.
pub struct ToolSet {
    /// Tool number and cutter.
    pub table: Vec<(u32, Tool)>,
    /// How the reports name each: `flat:6`, `profile:FILE`.
    pub names: Vec<String>,
    /// Where the cutters came from, for the report.
    pub from: &'static str,
}

impl ToolSet {
    /// The widest radius of the tools.
    pub fn reach(&self) -> f64 {
        self.table.iter().map(|(_, t)| t.radius()).fold(0.0, f64::max)
    }

    /// The one measured tool, when `--profile` gave it.
    pub fn measured(&self) -> Option<&MeasuredTool> {
        match &self.table.first()?.1 {
            Tool::Measured(m) => Some(m),
            Tool::Cutter(_) => None,
        }
    }

    /// The name of every tool, `T1 flat:6, T2 ball:3`, or the one name
    /// where one cutter cuts every move.
    pub fn summary(&self) -> String {
        match self.names.as_slice() {
            [first, rest @ ..] if rest.iter().all(|n| n == first) => first.clone(),
            _ => {
                let each = self.table.iter().zip(&self.names).map(|((n, _), name)| format!("T{n} {name}"));
                each.collect::<Vec<_>>().join(", ")
            }
        }
    }
}

/// `T1`, `T1 and T2`, `T1, T2 and T3`.
fn listed(numbers: &[u32]) -> String {
    let names: Vec<String> = numbers.iter().map(|n| format!("T{n}")).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// The one tool `--tool` or `--profile` gives, and its name.
pub fn given(args: &SimSetup) -> Result<Option<(Tool, String)>> {
    Ok(match (&args.tool, &args.profile) {
        (Some(spec), None) => {
            let c: Cutter = spec.parse()?;
            Some((Tool::Cutter(c), c.to_string()))
        }
        (None, Some(file)) => Some((
            Tool::Measured(MeasuredTool::new(&crate::tool_profile::read_profile(file)?)),
            format!("profile:{}", file.display()),
        )),
        (None, None) => None,
        _ => bail!("give one of --tool SPEC and --profile PROFILE.csv, not both"),
    })
}

/// The cutters to simulate a program with, `numbers` the tools that cut
/// its moves in the order they first do (a single 0 for a program that
/// loads none). Never a cutter the user did not
/// name for that tool: a program that changes tools takes its shapes from
/// the machine file's tool table, and `--tool` alone is refused for it
/// (unless `--same-tool-for-all`); `--tool` for a tool the table gives
/// another shape is refused too.
pub fn tool_set(
    args: &SimSetup,
    table: &BTreeMap<u32, ToolEntry>,
    table_from: &'static str,
    numbers: &[u32],
) -> Result<ToolSet> {
    let given = given(args)?;
    let loaded: Vec<u32> = numbers.iter().copied().filter(|&n| n != 0).collect();
    let shape = |n: u32| table.get(&n).and_then(|e| e.shape);
    let every = |tool: Tool, name: String, from| ToolSet {
        table: numbers.iter().map(|&n| (n, tool.clone())).collect(),
        names: vec![name; numbers.len()],
        from,
    };
    let needs = |extra: &str| {
        let each: Vec<String> =
            loaded.iter().map(|&n| format!("T{n} = {}", shape(n).map_or("?".to_string(), |c| c.to_string()))).collect();
        format!(
            "the program uses {}: give {} in the machine file's tool table (--machine M.toml, \
             [tools.T{}] shape = \"flat:6\"){extra} — {}",
            listed(&loaded),
            if loaded.len() == 1 { "its shape" } else { "their shapes" },
            loaded[0],
            each.join(", ")
        )
    };
    match given {
        Some((tool, name)) if args.same_tool_for_all => Ok(every(tool, name, "--same-tool-for-all")),
        Some((tool, name)) if loaded.len() <= 1 => {
            if let (Some(&n), Tool::Cutter(c)) = (loaded.first(), &tool) {
                if let Some(s) = shape(n).filter(|s| s != c) {
                    bail!(
                        "--tool {c}, but the machine file's tool table says T{n} is {s}: \
                         leave out --tool to cut with the table's, or mend the table"
                    );
                }
            }
            Ok(every(tool, name, if args.tool.is_some() { "--tool" } else { "--profile" }))
        }
        Some(_) => {
            let option = if args.tool.is_some() { "--tool" } else { "--profile" };
            if loaded.iter().all(|&n| shape(n).is_some()) {
                bail!(
                    "{option} is the cutter of a program with one tool; this one uses {} and the machine file \
                     gives them all: leave out {option}, or give --same-tool-for-all to cut every move with it",
                    listed(&loaded)
                );
            }
            bail!("{}", needs(&format!(", or --same-tool-for-all to cut every move with {option}")));
        }
        None if args.same_tool_for_all => {
            bail!("--same-tool-for-all needs the one tool: --tool SPEC or --profile PROFILE.csv")
        }
        None if loaded.is_empty() => {
            bail!("the program loads no tool (no T… M06): give its cutter with --tool SPEC or --profile PROFILE.csv")
        }
        None => {
            let mut table_out = Vec::with_capacity(loaded.len());
            for &n in &loaded {
                match shape(n) {
                    Some(c) => table_out.push((n, Tool::Cutter(c))),
                    None => bail!("{}", needs(if loaded.len() == 1 { ", or --tool SPEC" } else { "" })),
                }
            }
            let names = table_out.iter().map(|(_, t)| t.to_string()).collect();
            Ok(ToolSet { table: table_out, names, from: table_from })
        }
    }
}
