//! Progress of a long stage: a bar on a terminal; periodic log lines when stderr is not one (a
//! job writing into a log file says where it is every `VCUTS_PROGRESS_SECONDS`, 10 by default,
//! and when each stage starts and ends); nothing with `-q`.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// One stage's progress.
pub struct Bar {
    what: String,
    unit: &'static str,
    total: Option<u64>,
    out: Out,
}

enum Out {
    Terminal(ProgressBar),
    Log { start: Instant, every: Duration, last: Mutex<Instant>, pos: AtomicU64, message: Mutex<String> },
    Hidden,
}

impl Bar {
    /// A stage of `total` `unit`s called `what`.
    pub fn new(what: &str, total: u64, unit: &'static str) -> Bar {
        Bar::with_total(what, Some(total), unit)
    }

    /// A stage of unknown length (a spinner on a terminal).
    pub fn spinner(what: &str) -> Bar {
        Bar::with_total(what, None, "")
    }

    fn with_total(what: &str, total: Option<u64>, unit: &'static str) -> Bar {
        let out = if !log::log_enabled!(log::Level::Info) {
            Out::Hidden
        } else if std::io::stderr().is_terminal() {
            let bar = match total {
                Some(n) => {
                    let bar = ProgressBar::new(n);
                    bar.set_style(
                        ProgressStyle::with_template(&format!(
                            "{{prefix:>10}} [{{bar:40}}] {{pos}}/{{len}} {unit} {{per_sec}} elapsed {{elapsed}} ETA {{eta}} {{msg}}"
                        ))
                        .unwrap_or_else(|_| ProgressStyle::default_bar())
                        .progress_chars("=> "),
                    );
                    bar
                }
                None => {
                    let bar = ProgressBar::new_spinner();
                    bar.set_style(
                        ProgressStyle::with_template("{spinner} {prefix} {msg} [{elapsed}]")
                            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                    );
                    bar
                }
            };
            bar.set_prefix(what.to_string());
            Out::Terminal(bar)
        } else {
            let seconds = std::env::var("VCUTS_PROGRESS_SECONDS").ok().and_then(|s| s.parse::<f64>().ok());
            let every = Duration::from_secs_f64(seconds.filter(|s| s.is_finite() && *s >= 0.0).unwrap_or(10.0));
            match total {
                Some(n) => log::info!("{what}: started, {n} {unit}"),
                None => log::info!("{what}: started"),
            }
            let now = Instant::now();
            Out::Log {
                start: now,
                every,
                last: Mutex::new(now),
                pos: AtomicU64::new(0),
                message: Mutex::new(String::new()),
            }
        };
        Bar { what: what.into(), unit, total, out }
    }

    /// Sets how far the stage is.
    pub fn set_position(&self, n: u64) {
        match &self.out {
            Out::Terminal(bar) => bar.set_position(n),
            Out::Log { pos, .. } => {
                pos.store(n, Ordering::Relaxed);
                self.maybe_log();
            }
            Out::Hidden => {}
        }
    }

    /// Advances the stage by `n`.
    pub fn inc(&self, n: u64) {
        match &self.out {
            Out::Terminal(bar) => bar.inc(n),
            Out::Log { pos, .. } => {
                pos.fetch_add(n, Ordering::Relaxed);
                self.maybe_log();
            }
            Out::Hidden => {}
        }
    }

    /// Sets the note shown after the counts (the section, the iteration).
    pub fn set_message(&self, text: String) {
        match &self.out {
            Out::Terminal(bar) => {
                bar.set_message(text);
                if self.total.is_none() {
                    bar.tick();
                }
            }
            Out::Log { message, .. } => {
                *message.lock().unwrap_or_else(|e| e.into_inner()) = text;
                self.maybe_log();
            }
            Out::Hidden => {}
        }
    }

    fn maybe_log(&self) {
        let Out::Log { start, every, last, pos, message } = &self.out else { return };
        let now = Instant::now();
        {
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if now.duration_since(*last) < *every {
                return;
            }
            *last = now;
        }
        let done = pos.load(Ordering::Relaxed);
        let elapsed = now.duration_since(*start).as_secs_f64();
        let message = message.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let note = if message.is_empty() { String::new() } else { format!(", {message}") };
        match self.total {
            Some(n) if n > 0 => {
                let share = done as f64 / n as f64;
                let eta = if done > 0 { elapsed * (1.0 - share) / share } else { f64::NAN };
                log::info!(
                    "{}: {done}/{n} {} ({:.0} %), {elapsed:.0} s elapsed, ETA {eta:.0} s{note}",
                    self.what,
                    self.unit,
                    100.0 * share
                );
            }
            _ => log::info!("{}: {elapsed:.0} s elapsed{note}", self.what),
        }
    }

    /// Ends the stage, leaving "done" on a terminal and a closing line in a log.
    pub fn finish(&self) {
        self.end(false);
    }

    /// Ends the stage and removes its bar from a terminal (a log gets its closing line).
    pub fn finish_and_clear(&self) {
        self.end(true);
    }

    fn end(&self, clear: bool) {
        match &self.out {
            Out::Terminal(bar) if clear => bar.finish_and_clear(),
            Out::Terminal(bar) => bar.finish_with_message("done"),
            Out::Log { start, pos, .. } => {
                let s = start.elapsed().as_secs_f64();
                match self.total {
                    Some(_) => {
                        log::info!("{}: done, {} {} in {s:.1} s", self.what, pos.load(Ordering::Relaxed), self.unit)
                    }
                    None => log::info!("{}: done in {s:.1} s", self.what),
                }
            }
            Out::Hidden => {}
        }
    }
}
