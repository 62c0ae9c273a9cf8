//! Progress bars on stderr for long work, only when stderr is a terminal
//! (and not with `--quiet`).

use std::io::{IsTerminal, Read};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
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

/// Whether a [`LateBar`] is on the terminal's last line already: one bar at
/// a time (the files of `check --jobs` have one bar, not one each).
static BAR_HELD: AtomicBool = AtomicBool::new(false);

/// A bar for work whose length is known only as it starts, drawn once the
/// work has run `after` (short work shows nothing); `None` when stderr is
/// not a terminal, with `--quiet`, or while another bar is held.
pub struct LateBar {
    bar: ProgressBar,
    after: Duration,
    shown: AtomicBool,
}

impl LateBar {
    pub fn new(label: &str, what: &str, after: Duration) -> Option<LateBar> {
        LateBar::styled(style(label, what), after)
    }

    /// A bar counting bytes, labelled by [`LateBar::label`]: "reading
    /// ▇▇▇ 312.00 MB of 920.00 MB, 12s left".
    pub fn bytes(label: &str, after: Duration) -> Option<LateBar> {
        let template = "{msg} {bar:40} {decimal_bytes} of {decimal_total_bytes}, {eta} left";
        let bar = LateBar::styled(
            ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
            after,
        )?;
        bar.bar.set_message(label.to_string());
        Some(bar)
    }

    fn styled(style: ProgressStyle, after: Duration) -> Option<LateBar> {
        if crate::say::quiet() || !std::io::stderr().is_terminal() || BAR_HELD.swap(true, Ordering::Relaxed) {
            return None;
        }
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        bar.set_style(style);
        Some(LateBar { bar, after, shown: AtomicBool::new(false) })
    }

    /// A new stage of the work under a new label (a bar made by
    /// [`LateBar::bytes`]): its time left is estimated afresh.
    pub fn label(&self, label: &str) {
        self.bar.set_message(label.to_string());
        self.bar.reset_eta();
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

impl Drop for LateBar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
        BAR_HELD.store(false, Ordering::Relaxed);
    }
}

/// Progress through a program's text by bytes: the parser and the
/// interpreter store the offset they have reached in [`ByteProgress::counter`]
/// (a loop moves it back), and a thread shows it on a [`LateBar`] every
/// 150 ms. Without a bar (not a terminal, `--quiet`) there is no counter
/// and no thread.
pub struct ByteProgress {
    bar: Option<Arc<LateBar>>,
    counter: Option<Arc<AtomicU64>>,
    stop: Option<Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl ByteProgress {
    /// Progress through `total` bytes under `label`, drawn once the work
    /// has run 2 s.
    pub fn start(label: &str, total: u64) -> ByteProgress {
        let Some(bar) = LateBar::bytes(label, Duration::from_secs(2)) else {
            return ByteProgress { bar: None, counter: None, stop: None, thread: None };
        };
        let bar = Arc::new(bar);
        let counter = Arc::new(AtomicU64::new(0));
        let (stop, stopped) = channel::<()>();
        let (b, c) = (Arc::clone(&bar), Arc::clone(&counter));
        let thread = std::thread::spawn(move || {
            while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(Duration::from_millis(150)) {
                b.update(c.load(Ordering::Relaxed).min(total), total);
            }
        });
        ByteProgress { bar: Some(bar), counter: Some(counter), stop: Some(stop), thread: Some(thread) }
    }

    /// The counter of bytes done for the parser and the interpreter; `None`
    /// where nothing is shown.
    pub fn counter(&self) -> Option<Arc<AtomicU64>> {
        self.counter.clone()
    }

    /// The next stage of the work (the run after the reading), from byte 0.
    pub fn stage(&self, label: &str) {
        if let (Some(bar), Some(counter)) = (&self.bar, &self.counter) {
            counter.store(0, Ordering::Relaxed);
            bar.label(label);
        }
    }

    /// Stops the thread and clears the bar, before anything else is
    /// printed.
    pub fn finish(mut self) {
        self.end();
    }

    fn end(&mut self) {
        self.stop.take();
        if let Some(thread) = self.thread.take() {
            thread.join().ok();
        }
        if let Some(bar) = self.bar.take() {
            bar.finish();
        }
    }
}

impl Drop for ByteProgress {
    fn drop(&mut self) {
        self.end();
    }
}

/// A reader that stores in a [`ByteProgress`]'s counter how many bytes of
/// the file have been read, starting at `at` (past a header read already).
pub struct CountingReader<R> {
    inner: R,
    at: u64,
    done: Option<Arc<AtomicU64>>,
}

impl<R: Read> CountingReader<R> {
    pub fn new(inner: R, at: u64, progress: &ByteProgress) -> CountingReader<R> {
        CountingReader { inner, at, done: progress.counter() }
    }
}

impl<R: Read> Read for CountingReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.at += n as u64;
        if let Some(done) = &self.done {
            done.store(self.at, Ordering::Relaxed);
        }
        Ok(n)
    }
}
