//! Progress bars on standard error, fed by the library's progress callback.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use radiosity::pipeline::{Progress, Stage};
use std::mem::discriminant;
use std::sync::Mutex;

/// One bar, relabelled per stage.
pub struct Bars {
    bar: ProgressBar,
    stage: Mutex<Option<Stage>>,
}

impl Bars {
    /// Bars on standard error, or none at all when `quiet`.
    pub fn new(quiet: bool) -> Self {
        let bar = ProgressBar::new(0);
        if quiet {
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
        }
    }

    /// Shows one progress report.
    pub fn update(&self, p: Progress) {
        let mut stage = self.stage.lock().expect("progress lock");
        // A new stage relabels the bar; shooting stays one stage as its shot
        // count and unshot fraction move.
        let same = match (*stage, p.stage) {
            (Some(a @ Stage::Shoot { .. }), b) => discriminant(&a) == discriminant(&b),
            (a, b) => a == Some(b),
        };
        if !same {
            *stage = Some(p.stage);
            let label = match p.stage {
                Stage::FormFactors { pass: 0 } => "form factors".to_string(),
                Stage::FormFactors { pass } => format!("refine {pass}: form factors"),
                Stage::Solve => "solve".to_string(),
                Stage::Shoot { .. } => "shooting".to_string(),
            };
            self.bar.set_prefix(label);
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
