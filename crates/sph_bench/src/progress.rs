//! Progress bars on stderr (indicatif). A run's bar appears once the run has taken about two
//! seconds, so short runs print nothing; every bar is hidden with `--quiet` and when stderr is not
//! a terminal (`ProgressDrawTarget::stderr` hides itself then, and for `TERM=dumb`).

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::borrow::Cow;
use std::time::Duration;

/// How long a run goes before its bar appears.
const SHOW_AFTER: Duration = Duration::from_secs(2);

/// A run's bar: label, bar, percentage, detail, time left (fits 80 columns).
const RUN_TEMPLATE: &str = "  {prefix} [{bar:20}] {percent:>3}% {msg}, {eta} left";

/// The bar over a study's runs: runs done, time spent and left, the current run.
const STUDY_TEMPLATE: &str = "{prefix} [{bar:20}] {pos}/{len} runs, {elapsed}, {eta} left: {msg}";

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("#>.")
}

/// Where a command's bars go: one `MultiProgress` on stderr (hidden with `--quiet`), so a
/// study's overall bar and its current run's bar share the screen.
#[derive(Clone)]
pub struct Bars {
    multi: MultiProgress,
    /// Keep a finished run's bar on screen (a command's runs) or clear it (a study's).
    keep_finished: bool,
}

impl Bars {
    /// Bars on stderr, or none when `quiet`.
    pub fn new(quiet: bool) -> Self {
        let target = if quiet {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        Self {
            multi: MultiProgress::with_draw_target(target),
            keep_finished: true,
        }
    }

    /// The same bars, with every finished run's bar cleared (for a study of many runs).
    pub fn clearing_finished_runs(&self) -> Self {
        Self {
            multi: self.multi.clone(),
            keep_finished: false,
        }
    }

    /// Prints a line on stderr above the bars (also when they are hidden).
    pub fn note(&self, line: impl std::fmt::Display) {
        self.multi.suspend(|| eprintln!("{line}"));
    }

    /// The bar of one run of `len` units (steps, or simulated milliseconds), labelled `label`;
    /// it appears after about two seconds.
    pub fn run(&self, label: impl Into<Cow<'static, str>>, len: u64) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden())
            .with_style(style(RUN_TEMPLATE))
            .with_prefix(label);
        Progress {
            bar,
            multi: self.multi.clone(),
            shown: false,
            keep: self.keep_finished,
        }
    }

    /// The bar over `len` runs, shown at once.
    pub fn study(&self, label: impl Into<Cow<'static, str>>, len: u64) -> Progress {
        let bar = ProgressBar::new(len)
            .with_style(style(STUDY_TEMPLATE))
            .with_prefix(label);
        Progress {
            bar: self.multi.add(bar),
            multi: self.multi.clone(),
            shown: true,
            keep: true,
        }
    }
}

/// One bar.
pub struct Progress {
    bar: ProgressBar,
    multi: MultiProgress,
    shown: bool,
    keep: bool,
}

impl Progress {
    /// Shows `position` of the bar's length done, with `detail`.
    pub fn set(&mut self, position: u64, detail: impl Into<Cow<'static, str>>) {
        self.bar.set_message(detail);
        self.bar.set_position(position);
        if !self.shown && self.bar.elapsed() >= SHOW_AFTER {
            self.shown = true;
            self.bar = self.multi.add(self.bar.clone());
        }
    }

    /// Ends the bar: a run's last state stays on screen (cleared in a study), a study's stays.
    pub fn finish(self) {
        if !self.shown {
            return;
        }
        if self.keep {
            self.bar.finish();
        } else {
            self.bar.finish_and_clear();
            self.multi.remove(&self.bar);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_parse() {
        for template in [RUN_TEMPLATE, STUDY_TEMPLATE] {
            assert!(ProgressStyle::with_template(template).is_ok(), "{template}");
        }
    }

    #[test]
    fn quiet_bars_are_hidden_and_count_all_the_same() {
        let bars = Bars::new(true);
        assert!(bars.multi.is_hidden());
        let mut study = bars.study("trade", 3);
        study.set(2, "last");
        assert_eq!(study.bar.position(), 2);
        let mut run = bars.clearing_finished_runs().run("dam-break", 100);
        run.set(40, "t = 0.4 s");
        assert_eq!(run.bar.position(), 40);
        assert!(!run.shown, "a run's bar waits about two seconds");
        run.finish();
        study.finish();
    }
}
