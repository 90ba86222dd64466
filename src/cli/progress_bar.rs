//! Progress on standard error, fed by the library's progress callback: a
//! bar on a terminal, plain lines every few seconds otherwise
//! ([`super::progress_lines`]), nothing with `--quiet`.

use super::cost_watch::CostWatch;
use super::progress_lines::{stage_name, Lines};
use super::setting_flags::with_flags;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use radiosity::pipeline::{Progress, Stage};
use std::io::IsTerminal;
use std::mem::discriminant;
use std::sync::Mutex;
use std::time::Instant;

/// One bar, relabelled per stage, or plain lines.
pub struct Bars {
    bar: ProgressBar,
    stage: Mutex<Option<Stage>>,
    /// Plain lines instead of the bar (standard error is not a terminal).
    lines: Option<Mutex<Lines>>,
    /// The hemi-cubes' cost, checked when the form factors begin.
    cost: Option<CostWatch>,
}

impl Bars {
    /// A bar on standard error if it is a terminal, else plain lines; none
    /// at all when `quiet`.
    pub fn new(quiet: bool) -> Self {
        let bar = ProgressBar::new(0);
        let terminal = std::io::stderr().is_terminal();
        if quiet || !terminal {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix:>22} [{bar:40}] {pos}/{len} {elapsed_precise} {msg}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Bars {
            bar,
            stage: Mutex::new(None),
            lines: (!quiet && !terminal).then(|| Mutex::new(Lines::new())),
            cost: None,
        }
    }

    /// Also warns (whatever `quiet` says) when the first pass of form
    /// factors begins, if hemi-cubes of `resolution` on `threads` threads
    /// cost out of proportion (see [`CostWatch`]).
    pub fn watching_cost(mut self, resolution: usize, threads: usize) -> Self {
        self.cost = Some(CostWatch::new(resolution, threads));
        self
    }

    /// The cost warning given, if any.
    pub fn cost_warning(&self) -> Option<String> {
        self.cost.as_ref().and_then(CostWatch::warning)
    }

    /// Shows one progress report.
    pub fn update(&self, p: Progress) {
        if let Some(w) = self.cost.as_ref().and_then(|c| c.observe(p)) {
            self.bar.suspend(|| eprintln!("warning: {}", with_flags(w)));
        }
        if let Some(lines) = &self.lines {
            let line = lines.lock().expect("progress lock").line(p, Instant::now());
            if let Some(line) = line {
                eprintln!("{line}");
            }
            return;
        }
        let mut stage = self.stage.lock().expect("progress lock");
        // A new stage relabels the bar; shooting stays one stage as its shot
        // count and unshot fraction move.
        let same = match (*stage, p.stage) {
            (Some(a @ Stage::Shoot { .. }), b) => discriminant(&a) == discriminant(&b),
            (a, b) => a == Some(b),
        };
        if !same {
            *stage = Some(p.stage);
            self.bar.set_prefix(stage_name(p.stage));
            self.bar.set_length(p.total as u64);
            self.bar.reset_elapsed();
            self.bar.set_message("");
        }
        if let Stage::Shoot {
            shots,
            unshot_fraction,
        } = p.stage
        {
            self.bar
                .set_message(format!("unshot {unshot_fraction:.2e} after {shots} shots"));
        }
        self.bar.set_position(p.done as u64);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
