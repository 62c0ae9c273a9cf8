//! Progress bars on stderr for long work, only when stderr is a terminal
//! (and not with `--quiet`).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

fn style(label: &str, what: &str) -> ProgressStyle {
    let template = format!("{label} {{bar:40}} {{pos}}/{{len}} {what}, {{eta}} left");
    ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar())
}

/// A bar counting `len` steps of `what` (e.g. "rows"), labelled `label`;
/// `None` when stderr is not a terminal or the work is short (`len < min`).
pub fn bar(label: &str, what: &str, len: u64, min: u64) -> Option<ProgressBar> {
    if len < min || crate::say::quiet() || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(len);
    bar.set_style(style(label, what));
    Some(bar)
}

/// A bar for work whose length is known only as it starts, drawn once the
/// work has run `after` (short work shows nothing); `None` when stderr is
/// not a terminal.
pub struct LateBar {
    bar: ProgressBar,
    after: Duration,
    shown: AtomicBool,
}

impl LateBar {
    pub fn new(label: &str, what: &str, after: Duration) -> Option<LateBar> {
        if crate::say::quiet() || !std::io::stderr().is_terminal() {
            return None;
        }
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        bar.set_style(style(label, what));
        Some(LateBar { bar, after, shown: AtomicBool::new(false) })
    }

    /// `done` of `total` steps done (from any thread).
    pub fn update(&self, done: u64, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(done);
        if self.bar.elapsed() >= self.after && !self.shown.swap(true, Ordering::Relaxed) {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Runs `f`, which writes to the terminal, with the bar out of its way.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
