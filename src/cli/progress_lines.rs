//! Progress as plain lines, for when standard error is not a terminal (a
//! script, a log file, CI): bars redraw in place and mean nothing there. The
//! first report gives a line at once; after that at most one line every
//! [`EVERY`], each with the stage, done/total and an estimate of the time
//! left in the stage.

use radiosity::pipeline::{Progress, Stage};
use std::time::{Duration, Instant};

/// The least time between two lines.
pub const EVERY: Duration = Duration::from_secs(5);

/// What the lines need to remember.
pub struct Lines {
    last_line: Option<Instant>,
    /// The stage being reported, and when its first report came.
    stage: Option<(Stage, Instant)>,
}

impl Lines {
    /// No line yet.
    pub fn new() -> Self {
        Lines {
            last_line: None,
            stage: None,
        }
    }

    /// The line to print for report `p` received at `now`, if one is due.
    pub fn line(&mut self, p: Progress, now: Instant) -> Option<String> {
        let same = self.stage.is_some_and(|(s, _)| same_stage(s, p.stage));
        if !same {
            self.stage = Some((p.stage, now));
        }
        let due = self
            .last_line
            .is_none_or(|t| now.duration_since(t) >= EVERY);
        if !due {
            return None;
        }
        self.last_line = Some(now);
        let started = self.stage.map_or(now, |(_, t)| t);
        Some(describe(p, now.duration_since(started)))
    }
}

/// Shooting stays one stage as its shot count and unshot fraction move.
fn same_stage(a: Stage, b: Stage) -> bool {
    match (a, b) {
        (Stage::Shoot { .. }, Stage::Shoot { .. }) => true,
        _ => a == b,
    }
}

/// The stage's name as the bars show it.
pub fn stage_name(stage: Stage) -> String {
    match stage {
        Stage::FormFactors { pass: 0 } => "form factors".to_string(),
        Stage::FormFactors { pass } => format!("refine {pass}: form factors"),
        Stage::SharedRows { pass: 0 } => "shared rows: own direct light".to_string(),
        Stage::SharedRows { pass } => format!("refine {pass}: shared rows: own direct light"),
        Stage::Solve => "solve".to_string(),
        Stage::PartViews => "shaped gather: part views".to_string(),
        Stage::LightGroups => "light groups".to_string(),
        Stage::Shoot { .. } => "shooting".to_string(),
    }
}

/// `progress: STAGE DONE/TOTAL (P%), S s in this stage, about T s left`,
/// the estimate from the rate so far (none before the first unit is done).
fn describe(p: Progress, elapsed: Duration) -> String {
    let mut text = format!("progress: {} {}/{}", stage_name(p.stage), p.done, p.total);
    if p.total > 0 {
        text.push_str(&format!(
            " ({:.0}%)",
            100.0 * p.done as f64 / p.total as f64
        ));
    }
    let seconds = elapsed.as_secs_f64();
    text.push_str(&format!(", {seconds:.0} s in this stage"));
    if p.done > 0 && p.total >= p.done {
        let left = seconds * (p.total - p.done) as f64 / p.done as f64;
        text.push_str(&format!(", about {left:.0} s left"));
    }
    if let Stage::Shoot {
        shots,
        unshot_fraction,
    } = p.stage
    {
        text.push_str(&format!(
            ", unshot {unshot_fraction:.2e} after {shots} shots"
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ff(done: usize) -> Progress {
        Progress {
            stage: Stage::FormFactors { pass: 0 },
            done,
            total: 1000,
        }
    }

    #[test]
    fn a_line_at_once_then_one_every_few_seconds_with_the_time_left() {
        let t0 = Instant::now();
        let at = |s: u64| t0 + Duration::from_secs(s);
        let mut lines = Lines::new();
        let first = lines.line(ff(0), at(0)).unwrap();
        assert_eq!(
            first,
            "progress: form factors 0/1000 (0%), 0 s in this stage"
        );
        assert_eq!(lines.line(ff(100), at(2)), None);
        // 250 done in 10 s: 750 more take 30 s.
        let line = lines.line(ff(250), at(10)).unwrap();
        assert_eq!(
            line,
            "progress: form factors 250/1000 (25%), 10 s in this stage, about 30 s left"
        );
        assert_eq!(lines.line(ff(300), at(14)), None);
        // A new stage starts its own clock, but waits its turn.
        let solve = Progress {
            stage: Stage::Solve,
            done: 1,
            total: 4,
        };
        assert_eq!(lines.line(solve, at(14)), None);
        let line = lines.line(Progress { done: 2, ..solve }, at(16)).unwrap();
        assert_eq!(
            line,
            "progress: solve 2/4 (50%), 2 s in this stage, about 2 s left"
        );
    }
}
