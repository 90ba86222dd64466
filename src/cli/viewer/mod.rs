//! The page that walks through a bake and relights it: its files (embedded
//! in the binary), written beside a bake (`bake --html`) or served on the
//! loopback address (`radiosity view`). The JavaScript is the project's own
//! (a small WebGL2 viewer of its bakes): nothing is fetched from elsewhere.

pub mod server;

use anyhow::{bail, Context, Result};
use radiosity::output::{prepare_folder, Outputs};
use std::path::Path;

/// The page's files: (name, content type, text). `index.html` is a template
/// (see [`page`]).
pub const FILES: [(&str, &str, &str); 4] = [
    (
        "index.html",
        "text/html; charset=utf-8",
        include_str!("index.html"),
    ),
    (
        "viewer.js",
        "text/javascript; charset=utf-8",
        include_str!("viewer.js"),
    ),
    (
        "gltf.js",
        "text/javascript; charset=utf-8",
        include_str!("gltf.js"),
    ),
    (
        "render.js",
        "text/javascript; charset=utf-8",
        include_str!("render.js"),
    ),
];

/// The name the page fetches the bake by: `scene.glb` or `scene.gltf`, as
/// `bake` is one or the other.
pub fn scene_name(bake: &Path) -> &'static str {
    match bake.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("gltf") => "scene.gltf",
        _ => "scene.glb",
    }
}

/// `index.html` for the bake `scene` (the name the page fetches) titled
/// `title`.
pub fn page(scene: &str, title: &str) -> String {
    let escaped: String = title
        .chars()
        .map(|c| match c {
            '<' => "&lt;".to_string(),
            '>' => "&gt;".to_string(),
            '&' => "&amp;".to_string(),
            '"' => "&quot;".to_string(),
            c => c.to_string(),
        })
        .collect();
    FILES[0]
        .2
        .replace("{{SCENE}}", scene)
        .replace("{{TITLE}}", &escaped)
}

/// Writes the page and a copy of the bake `bake` into `dir` (created if
/// needed), all files replacing their targets together.
pub fn write_site(dir: &Path, bake: &Path) -> Result<()> {
    prepare_folder(dir)?;
    let bytes = std::fs::read(bake).with_context(|| format!("reading {}", bake.display()))?;
    if bytes.is_empty() {
        bail!("{} is empty", bake.display());
    }
    let scene = scene_name(bake);
    let title = bake
        .file_stem()
        .map_or_else(|| "bake".to_string(), |s| s.to_string_lossy().into_owned());
    let mut outputs = Outputs::new();
    outputs.stage_bytes(&dir.join("index.html"), page(scene, &title).as_bytes())?;
    for (name, _, text) in &FILES[1..] {
        outputs.stage_bytes(&dir.join(name), text.as_bytes())?;
    }
    outputs.stage_bytes(&dir.join(scene), &bytes)?;
    outputs.commit()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_names_its_bake_and_escapes_its_title() {
        let html = page("scene.glb", "a<b & \"c\"");
        assert!(html.contains(r#"content="scene.glb""#));
        assert!(html.contains("a&lt;b &amp; &quot;c&quot;"));
        assert!(!html.contains("{{"));
        assert_eq!(scene_name(Path::new("x/Room.GLTF")), "scene.gltf");
        assert_eq!(scene_name(Path::new("room.glb")), "scene.glb");
    }

    #[test]
    fn the_page_mixes_as_many_groups_as_view_lets_through() {
        let limit = format!(
            "export const MAX_GROUPS = {};",
            crate::cli::view_cmd::MAX_VIEWED_GROUPS
        );
        assert!(FILES[3].2.contains(&limit));
    }
}
