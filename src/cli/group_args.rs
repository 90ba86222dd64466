//! The light-group options of `bake` and `view`: how sources form groups,
//! and re-solving with a group's emission scaled.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use radiosity::light_groups::{GroupPattern, GroupRule, LightGroups};
use radiosity::math::Rgb;
use radiosity::scene::Scene;

/// Light-group options.
#[derive(Args, Debug, Clone)]
pub struct GroupArgs {
    /// How sources form light groups, each solved on the one refined mesh and
    /// kept apart in the bake (a viewer's slider each): each (one group per
    /// emissive material and per punctual light), one (a single group), or
    /// none (no groups: the plain solve, the whole light as one group).
    #[arg(long = "light-groups", value_enum, default_value_t = GroupChoice::Each)]
    pub rule: GroupChoice,
    /// A named group of every source whose node, material or light name
    /// contains one of the patterns: NAME=PATTERN[,PATTERN...] (repeat for
    /// more groups; the first that matches takes a source; sources no pattern
    /// names keep --light-groups).
    #[arg(long = "light-group", value_name = "NAME=PATTERNS")]
    pub patterns: Vec<String>,
    /// Solve with light group NAME's emission scaled: NAME=FACTOR or
    /// NAME=R,G,B (repeatable), to compare a viewer's mix with a new solve.
    #[arg(long = "group-scale", value_name = "NAME=FACTOR")]
    pub scales: Vec<String>,
}

/// How sources form groups.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GroupChoice {
    /// One group per emissive material and per punctual light.
    Each,
    /// One group holding every source.
    One,
    /// No light groups.
    None,
}

impl GroupArgs {
    /// Checks the options' syntax before any work.
    pub fn check(&self) -> Result<()> {
        self.parsed_patterns()?;
        self.parsed_scales()?;
        if self.rule == GroupChoice::None && !self.patterns.is_empty() {
            bail!("--light-group names groups, and --light-groups none asks for none");
        }
        Ok(())
    }

    fn parsed_patterns(&self) -> Result<Vec<GroupPattern>> {
        self.patterns
            .iter()
            .map(|p| GroupPattern::parse(p).map_err(anyhow::Error::from))
            .collect()
    }

    fn parsed_scales(&self) -> Result<Vec<(String, Rgb)>> {
        self.scales.iter().map(|s| parse_scale(s)).collect()
    }

    /// The light groups of `scene` (`None` for --light-groups none).
    pub fn groups(&self, scene: &Scene) -> Result<Option<LightGroups>> {
        let rule = match self.rule {
            GroupChoice::None => return Ok(None),
            GroupChoice::Each => GroupRule::Each,
            GroupChoice::One => GroupRule::One,
        };
        Ok(Some(LightGroups::by_rule(
            scene,
            rule,
            &self.parsed_patterns()?,
        )?))
    }

    /// `scene` with the groups --group-scale names scaled, and its groups
    /// formed again (a group scaled to 0 no longer emits, and is gone).
    pub fn scaled(&self, scene: Scene) -> Result<Scene> {
        let scales = self.parsed_scales()?;
        if scales.is_empty() {
            return Ok(scene);
        }
        let groups = match self.groups(&scene)? {
            Some(g) => g,
            None => LightGroups::each(&scene),
        };
        let mut factors = vec![Rgb::ONE; groups.len()];
        for (name, factor) in &scales {
            let Some(g) = groups.position(name) else {
                let names: Vec<String> = groups
                    .groups
                    .iter()
                    .map(|g| format!("'{}'", g.name))
                    .collect();
                bail!(
                    "--group-scale: scene '{}' has no light group '{name}' (its groups: {})",
                    scene.name,
                    names.join(", ")
                );
            };
            factors[g] = *factor;
        }
        Ok(groups.scaled_scene(&scene, &factors)?)
    }
}

/// Parses `NAME=FACTOR` or `NAME=R,G,B`.
fn parse_scale(text: &str) -> Result<(String, Rgb)> {
    let (name, value) = text
        .split_once('=')
        .with_context(|| format!("--group-scale '{text}': expected NAME=FACTOR or NAME=R,G,B"))?;
    let numbers: Vec<f64> = value
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .with_context(|| format!("--group-scale '{text}': the factor is not a number"))?;
    let factor = match numbers[..] {
        [f] => Rgb::splat(f),
        [r, g, b] => Rgb::new(r, g, b),
        _ => bail!("--group-scale '{text}': give one factor or three (R,G,B)"),
    };
    if !(factor.is_finite() && factor.min_band() >= 0.0) {
        bail!("--group-scale '{text}': factors must be finite and at least 0");
    }
    if name.trim().is_empty() {
        bail!("--group-scale '{text}': the group needs a name before '='");
    }
    Ok((name.trim().to_string(), factor))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_parse_and_reject() {
        assert_eq!(
            parse_scale("lamp=0.5").unwrap(),
            ("lamp".into(), Rgb::splat(0.5))
        );
        assert_eq!(
            parse_scale("sky = 1,0.5,0").unwrap(),
            ("sky".into(), Rgb::new(1.0, 0.5, 0.0))
        );
        for bad in [
            "lamp", "lamp=", "lamp=x", "lamp=1,2", "lamp=-1", "=2", "lamp=inf",
        ] {
            assert!(parse_scale(bad).is_err(), "{bad}");
        }
    }
}
