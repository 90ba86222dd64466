//! Which sources make up each light group: the emitting surfaces and the
//! punctual lights whose light a group carries.

use crate::error::{Error, Result};
use crate::scene::Scene;
use std::collections::HashMap;

/// One light group: a name and the sources whose light it carries.
#[derive(Clone, Debug, PartialEq)]
pub struct LightGroup {
    /// Its name, unique among the groups (shown by viewers, used by
    /// [`LightGroups::scaled_scene`]).
    pub name: String,
    /// Indices into [`Scene::surfaces`] of the emitting surfaces it holds.
    pub surfaces: Vec<u32>,
    /// Indices into [`Scene::lights`] of the punctual lights it holds.
    pub lights: Vec<u32>,
    /// Whether it holds the scene's sky ([`Scene::sky`]).
    pub sky: bool,
}

impl LightGroup {
    /// True when it holds no source.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.surfaces.is_empty() && self.lights.is_empty() && !self.sky
    }
}

/// A partition of a scene's sources into light groups: every emitting
/// surface and every punctual light belongs to exactly one group, so that
/// the groups' solutions add up to the solution with every light on.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightGroups {
    /// The groups, in the order viewers list them.
    pub groups: Vec<LightGroup>,
}

/// How [`LightGroups::by_rule`] forms the groups of the sources no pattern
/// names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GroupRule {
    /// One group per emissive material (named after it), one per punctual
    /// light (named after it) and one for the sky (named `sky`).
    #[default]
    Each,
    /// One group, `all`, holding every source.
    One,
}

/// A named group made of every source whose names contain one of the
/// patterns (see [`LightGroups::by_rule`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GroupPattern {
    /// The group's name.
    pub name: String,
    /// Substrings of the names of its sources.
    pub patterns: Vec<String>,
}

impl GroupPattern {
    /// Parses `NAME=PATTERN[,PATTERN...]`.
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] (named `light_groups`) for a missing `=`, an empty
    /// name or an empty pattern.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |message: String| Error::Setting {
            name: "light_groups",
            message,
        };
        let (name, patterns) = text
            .split_once('=')
            .ok_or_else(|| bad(format!("'{text}': expected NAME=PATTERN[,PATTERN...]")))?;
        let name = name.trim();
        if name.is_empty() {
            return Err(bad(format!("'{text}': the group needs a name before '='")));
        }
        let patterns: Vec<String> = patterns.split(',').map(|p| p.trim().to_string()).collect();
        if patterns.iter().any(String::is_empty) {
            return Err(bad(format!(
                "'{text}': every pattern after '=' must be a non-empty part of a name"
            )));
        }
        Ok(GroupPattern {
            name: name.to_string(),
            patterns,
        })
    }
}

/// A source of light in a scene, with the names patterns are matched to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Source {
    /// An emitting surface, by index in the scene.
    Surface(u32),
    /// A punctual light, by index in the scene.
    Light(u32),
    /// The scene's sky.
    Sky,
}

impl LightGroups {
    /// One group per emissive material and one per punctual light: the
    /// default.
    #[must_use]
    pub fn each(scene: &Scene) -> Self {
        Self::build(scene, GroupRule::Each, &[])
    }

    /// One group holding every source.
    #[must_use]
    pub fn one(scene: &Scene) -> Self {
        Self::build(scene, GroupRule::One, &[])
    }

    /// Groups by `patterns` first: a source joins the first pattern group one
    /// of whose patterns is part of its names (for an emitting surface, its
    /// object's (node's) name or its material's; for a punctual light, its
    /// name, which names the light and its node; for the sky, `sky`). The
    /// sources no pattern
    /// names are grouped by `rule`. Groups that would hold no source are
    /// left out.
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] (named `light_groups`) when two patterns give the
    /// same group name, or a pattern group matches no source (a misspelt
    /// name would otherwise go unnoticed).
    pub fn by_rule(scene: &Scene, rule: GroupRule, patterns: &[GroupPattern]) -> Result<Self> {
        for (i, p) in patterns.iter().enumerate() {
            if patterns[..i].iter().any(|q| q.name == p.name) {
                return Err(Error::Setting {
                    name: "light_groups",
                    message: format!("the group '{}' is given twice", p.name),
                });
            }
        }
        let groups = Self::build(scene, rule, patterns);
        if let Some(p) = patterns
            .iter()
            .find(|p| !groups.groups.iter().any(|g| g.name == p.name))
        {
            return Err(Error::Setting {
                name: "light_groups",
                message: format!(
                    "no emitting surface or punctual light of scene '{}' has a name containing \
                     {} (the group '{}'); sources: {}",
                    scene.name,
                    p.patterns
                        .iter()
                        .map(|x| format!("'{x}'"))
                        .collect::<Vec<_>>()
                        .join(" or "),
                    p.name,
                    source_names(scene).join(", ")
                ),
            });
        }
        Ok(groups)
    }

    fn build(scene: &Scene, rule: GroupRule, patterns: &[GroupPattern]) -> Self {
        let mut groups: Vec<LightGroup> = patterns
            .iter()
            .map(|p| LightGroup {
                name: p.name.clone(),
                surfaces: Vec::new(),
                lights: Vec::new(),
                sky: false,
            })
            .collect();
        // Default groups by key, in order of first source.
        let mut by_key: HashMap<String, usize> = HashMap::new();
        for source in sources(scene) {
            let names = names_of(scene, source);
            let named = patterns.iter().position(|p| {
                p.patterns
                    .iter()
                    .any(|x| names.iter().any(|n| n.contains(x)))
            });
            let g = match named {
                Some(g) => g,
                None => {
                    let key = match (rule, source) {
                        (GroupRule::One, _) => "all".to_string(),
                        (GroupRule::Each, Source::Surface(s)) => {
                            format!("m{}", scene.surfaces[s as usize].material)
                        }
                        (GroupRule::Each, Source::Light(l)) => format!("l{l}"),
                        (GroupRule::Each, Source::Sky) => "sky".to_string(),
                    };
                    *by_key.entry(key).or_insert_with(|| {
                        let name = match (rule, source) {
                            (GroupRule::One, _) => "all".to_string(),
                            (GroupRule::Each, Source::Surface(s)) => {
                                scene.material_of(&scene.surfaces[s as usize]).name.clone()
                            }
                            (GroupRule::Each, Source::Light(l)) => {
                                scene.lights[l as usize].name.clone()
                            }
                            (GroupRule::Each, Source::Sky) => "sky".to_string(),
                        };
                        groups.push(LightGroup {
                            name,
                            surfaces: Vec::new(),
                            lights: Vec::new(),
                            sky: false,
                        });
                        groups.len() - 1
                    })
                }
            };
            match source {
                Source::Surface(s) => groups[g].surfaces.push(s),
                Source::Light(l) => groups[g].lights.push(l),
                Source::Sky => groups[g].sky = true,
            }
        }
        groups.retain(|g| !g.is_empty());
        let mut out = LightGroups { groups };
        out.make_names_unique();
        out
    }

    /// Appends ` (2)`, ` (3)`, ... to names already taken by an earlier
    /// group (two materials or lights may share a name), and names unnamed
    /// groups after their place.
    fn make_names_unique(&mut self) {
        let mut taken: Vec<String> = Vec::new();
        for (i, g) in self.groups.iter_mut().enumerate() {
            if g.name.trim().is_empty() {
                g.name = format!("group {}", i + 1);
            }
            let base = g.name.clone();
            let mut n = 2;
            while taken.contains(&g.name) {
                g.name = format!("{base} ({n})");
                n += 1;
            }
            taken.push(g.name.clone());
        }
    }

    /// The number of groups.
    #[must_use]
    pub fn len(&self) -> usize {
        self.groups.len()
    }

    /// True when there is no group (a scene without light).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.groups.is_empty()
    }

    /// The index of the group named `name`.
    #[must_use]
    pub fn position(&self, name: &str) -> Option<usize> {
        self.groups.iter().position(|g| g.name == name)
    }

    /// Per scene surface, the group whose light it emits (`None` for a
    /// surface that emits nothing).
    #[must_use]
    pub(crate) fn surface_groups(&self, scene: &Scene) -> Vec<Option<u32>> {
        let mut out = vec![None; scene.surfaces.len()];
        for (g, group) in self.groups.iter().enumerate() {
            for &s in &group.surfaces {
                if let Some(slot) = out.get_mut(s as usize) {
                    *slot = Some(g as u32);
                }
            }
        }
        out
    }
}

/// Every source of `scene`: its emitting surfaces, then its punctual lights,
/// then its sky if it gives light.
pub(super) fn sources(scene: &Scene) -> impl Iterator<Item = Source> + '_ {
    let surfaces = scene
        .surfaces
        .iter()
        .enumerate()
        .filter(|(_, s)| scene.material_of(s).is_emitter())
        .map(|(i, _)| Source::Surface(i as u32));
    let sky = scene
        .sky
        .filter(|s| s.zenith.max_band() > 0.0)
        .map(|_| Source::Sky);
    surfaces
        .chain((0..scene.lights.len() as u32).map(Source::Light))
        .chain(sky)
}

/// The names a pattern is matched to.
fn names_of(scene: &Scene, source: Source) -> Vec<&str> {
    match source {
        Source::Surface(s) => {
            let surface = &scene.surfaces[s as usize];
            vec![
                scene.objects[surface.object as usize].name.as_str(),
                scene.material_of(surface).name.as_str(),
            ]
        }
        Source::Light(l) => vec![scene.lights[l as usize].name.as_str()],
        Source::Sky => vec!["sky"],
    }
}

/// A source in words.
pub(super) fn describe(scene: &Scene, source: Source) -> String {
    match source {
        Source::Surface(s) => {
            let surface = &scene.surfaces[s as usize];
            format!(
                "emitting surface {s} of object '{}' (material '{}')",
                scene.objects[surface.object as usize].name,
                scene.material_of(surface).name
            )
        }
        Source::Light(l) => format!("punctual light {}", scene.lights[l as usize].name),
        Source::Sky => "sky".to_string(),
    }
}

/// The distinct names of the scene's sources, for messages (at most 12).
fn source_names(scene: &Scene) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for source in sources(scene) {
        for n in names_of(scene, source) {
            let quoted = format!("'{n}'");
            if !names.contains(&quoted) {
                names.push(quoted);
            }
        }
    }
    if names.len() > 12 {
        let more = names.len() - 12;
        names.truncate(12);
        names.push(format!("and {more} more"));
    }
    names
}
