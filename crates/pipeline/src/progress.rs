//! Progress bars (indicatif, on standard error): one per stage, advanced per piece. Silenced
//! with `quiet`, and hidden by indicatif itself when standard error is not a terminal.

use std::time::Duration;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The bars of one run.
pub struct Progress {
    multi: Option<MultiProgress>,
    prefix: String,
}

impl Progress {
    /// Bars for the pipeline `prefix`, or none when `quiet`.
    pub fn new(quiet: bool, prefix: &str) -> Self {
        let multi = (!quiet).then(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()));
        Self {
            multi,
            prefix: prefix.to_string(),
        }
    }

    /// No bars at all.
    pub fn hidden() -> Self {
        Self::new(true, "")
    }

    /// A bar for `stage` over `len` items (pieces), or a spinner when `len` is 0.
    pub fn stage(&self, stage: &str, len: u64) -> ProgressBar {
        let Some(multi) = &self.multi else {
            return ProgressBar::hidden();
        };
        let bar = if len == 0 {
            let b = ProgressBar::new_spinner();
            if let Ok(style) =
                ProgressStyle::with_template("{prefix:.bold} {msg:<9} {spinner} {elapsed}")
            {
                b.set_style(style);
            }
            b.enable_steady_tick(Duration::from_millis(120));
            b
        } else {
            let b = ProgressBar::new(len);
            if let Ok(style) = ProgressStyle::with_template(
                "{prefix:.bold} {msg:<9} [{bar:30}] {pos}/{len} pieces {elapsed}",
            ) {
                b.set_style(style.progress_chars("=> "));
            }
            b
        };
        let bar = multi.add(bar);
        bar.set_prefix(self.prefix.clone());
        bar.set_message(stage.to_string());
        bar
    }
}
