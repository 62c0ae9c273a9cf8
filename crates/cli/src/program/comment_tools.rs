//! The tool table a program's comments give where no machine file gives
//! one: the tool lines CAM posts write (`(T9 D=2.5 CR=0. TAPER=118deg -
//! ZMIN=-4.751 - drill)`, read by `kezuri_cam::cutter::named`).

use kezuri_cam::cutter::named::tools_in_comments;
use kezuri_cam::Cutter;
use kezuri_machine::{Machine, ToolEntry};
use kezuri_nc::comments_forgetting;
use kezuri_nc::source::Text;

/// [`Machine::tools_from`] for a table the comments gave.
pub const FROM_COMMENTS: &str = "the program's comments";

/// Fills `machine`'s tool table, where it has none, from the tool lines of
/// the comments of `text` (its numbers in inches where `inch`), and says
/// which on standard error; `file` names the program. The text read
/// through is let go of as it goes (a mapped file's pages).
pub fn from_comments(machine: &mut Machine, text: &Text, inch: bool, file: &str) {
    if !machine.tools.is_empty() {
        return;
    }
    let forget = |r| text.forget(r);
    let tools = tools_in_comments(comments_forgetting(text, &forget), inch);
    if tools.is_empty() {
        return;
    }
    let mut said = Vec::with_capacity(tools.len());
    for t in tools {
        let shape = t.spec.clone().and_then(|s| s.parse::<Cutter>().map_err(|e| e.to_string()));
        let kind = if t.kind.is_empty() { String::new() } else { format!("{}, ", t.kind) };
        said.push(match &shape {
            Ok(c) => format!("T{} {c} (line {})", t.number, t.line),
            Err(why) => format!("T{} ({kind}line {}): no shape: {why}", t.number, t.line),
        });
        let entry = ToolEntry {
            shape: shape.ok(),
            h: t.h.unwrap_or(t.number),
            d: t.d,
            name: (!t.kind.is_empty()).then_some(t.kind),
            nose: None,
        };
        machine.tools.insert(t.number, entry);
    }
    machine.tools_from = FROM_COMMENTS;
    eprintln!(
        "note: {file}: no machine file gives a tool table: tools from the program's comments: {}",
        said.join(", ")
    );
}
