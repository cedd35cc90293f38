//! Progress bars for the pipeline stages (indicatif).

use flexmbs_fe::eigen::EigenEvent;
use flexmbs_reduce::pipeline::Stage;
use indicatif::{ProgressBar, ProgressStyle};
use std::time::Duration;

/// Renders [`Stage`] events as a spinner or a bar.
pub struct Progress {
    bar: Option<ProgressBar>,
    key: String,
    quiet: bool,
}

impl Progress {
    /// A new renderer (silent when `quiet`).
    pub fn new(quiet: bool) -> Self {
        Self {
            bar: None,
            key: String::new(),
            quiet,
        }
    }

    fn spinner(&mut self, msg: String) {
        if self.quiet {
            return;
        }
        self.finish();
        self.key.clear();
        let b = ProgressBar::new_spinner();
        b.set_style(
            ProgressStyle::with_template("{spinner} {elapsed:>4} {msg}")
                .unwrap_or(ProgressStyle::default_spinner()),
        );
        b.enable_steady_tick(Duration::from_millis(120));
        b.set_message(msg);
        self.bar = Some(b);
    }

    fn bar(&mut self, len: u64, msg: &str) -> Option<&ProgressBar> {
        if self.quiet {
            return None;
        }
        let needs_new =
            self.bar.as_ref().is_none_or(|b| b.length() != Some(len)) || self.key != msg;
        if needs_new {
            self.finish();
            self.key = msg.to_string();
            let b = ProgressBar::new(len);
            b.set_style(
                ProgressStyle::with_template(
                    "{msg:>14} [{bar:40}] {pos}/{len} {elapsed}, ETA {eta}",
                )
                .unwrap_or(ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            b.set_message(msg.to_string());
            self.bar = Some(b);
        }
        self.bar.as_ref()
    }

    /// Shows one stage event.
    pub fn stage(&mut self, s: Stage) {
        match s {
            Stage::Started(m) => self.spinner(m),
            Stage::Assembly { done, total } => {
                if let Some(b) = self.bar(total as u64, "assembly") {
                    b.set_position(done as u64);
                }
            }
            Stage::Eigen(e) => match e {
                EigenEvent::Factorizing { n, nnz } => {
                    self.spinner(format!("factorizing {n} equations ({nnz} nonzeros)"))
                }
                EigenEvent::FactorEstimate { nnz_l, bytes } => {
                    let available = flexmbs_fe::memory::available_memory()
                        .map_or_else(String::new, |(b, _)| {
                            format!(", {} available", flexmbs_fe::memory::format_bytes(b))
                        });
                    self.spinner(format!(
                        "factorizing: L has {nnz_l} entries, about {}{available}",
                        flexmbs_fe::memory::format_bytes(bytes)
                    ))
                }
                EigenEvent::Factorized { nnz_l } => {
                    self.spinner(format!("factorized (nnz(L) = {nnz_l}), iterating"))
                }
                EigenEvent::Iteration {
                    basis,
                    converged,
                    wanted,
                } => {
                    if let Some(b) = self.bar(wanted as u64, "eigenpairs") {
                        b.set_position(converged.min(wanted) as u64);
                        b.set_message(format!("eigenpairs (basis {basis})"));
                    }
                }
                EigenEvent::SturmCheck { expected, found } => self.spinner(format!(
                    "Sturm check: {found} eigenvalues below the bound, {expected} expected"
                )),
            },
        }
    }

    /// Clears the current bar.
    pub fn finish(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}
