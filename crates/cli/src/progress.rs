//! Progress bars on stderr for long work, only when stderr is a terminal.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar counting `len` steps of `what` (e.g. "rows"), labelled `label`;
/// `None` when stderr is not a terminal or the work is short (`len < min`).
pub fn bar(label: &str, what: &str, len: u64, min: u64) -> Option<ProgressBar> {
    if len < min || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(len);
    let template = format!("{label} {{bar:40}} {{pos}}/{{len}} {what}, {{eta}} left");
    bar.set_style(ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar()));
    Some(bar)
}
