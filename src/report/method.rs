//! What a sweep varies, and one run of it.

use crate::pipeline::Settings;
use std::fmt;

/// How the runs of one curve differ from each other.
///
/// Every method is measured the same way, so a new one needs only a variant
/// here and its runs in [`SweepPlan::runs`](super::SweepPlan::runs); the runner,
/// the metrics, the tables and the plots take any method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Substructuring with every patch split uniformly to one depth and no
    /// adaptation. Parameter: the depth.
    Uniform,
    /// Substructuring with adaptive subdivision where neighbouring elements
    /// differ. Parameter: the refinement tolerance.
    Adaptive,
    /// The base settings at one hemi-cube resolution. Parameter: the
    /// resolution (pixels across the top face).
    Hemicube,
    /// Uniformly small patches with no elements below them: every receiver is
    /// also a source, the full system without substructuring. Parameter: the
    /// patch size in metres.
    Patches,
    /// The progressive (shooting) solver of Cohen, Chen, Wallace and Greenberg
    /// 1988 at the base's mesh settings, stopped once the unshot power is at
    /// most a fraction of the emitted power. Parameter: that fraction. Its
    /// answer is what has been shot so far, without the display-only ambient
    /// term.
    Progressive,
}

impl Method {
    /// Every method, in the order tables list them.
    pub const ALL: [Method; 5] = [
        Method::Uniform,
        Method::Adaptive,
        Method::Hemicube,
        Method::Patches,
        Method::Progressive,
    ];

    /// The method's name in tables and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Uniform => "uniform",
            Method::Adaptive => "adaptive",
            Method::Hemicube => "hemicube",
            Method::Patches => "patches",
            Method::Progressive => "progressive",
        }
    }

    /// What the method's parameter is.
    #[must_use]
    pub(crate) fn parameter_name(self) -> &'static str {
        match self {
            Method::Uniform => "depth",
            Method::Adaptive => "refine tolerance",
            Method::Hemicube => "hemi-cube resolution",
            Method::Patches => "patch size (m)",
            Method::Progressive => "unshot fraction",
        }
    }

    /// A longer label for plot legends.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Method::Uniform => "uniform depth (substructured)",
            Method::Adaptive => "adaptive subdivision (substructured)",
            Method::Hemicube => "hemi-cube resolution",
            Method::Patches => "small patches (no substructuring)",
            Method::Progressive => "progressive, stopped at unshot fractions",
        }
    }

    /// The method called `name` (as [`Method::name`] spells it).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One solve of a sweep: its method, the value of the method's parameter, and
/// the complete settings.
#[derive(Clone, Debug)]
pub struct SweepRun {
    /// The curve it belongs to.
    pub method: Method,
    /// The value of the method's parameter.
    pub parameter: f64,
    /// The settings of the solve.
    pub settings: Settings,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Some(m));
        }
        assert_eq!(Method::from_name("shooting"), None);
    }
}
