//! `radiosity view`: serves a bake and the page that walks through it and
//! relights it, on the loopback address.

use super::setting_flags::with_flags;
use super::viewer::server::{serve, Site};
use super::viewer::{page, scene_name, FILES};
use anyhow::{bail, Context, Result};
use clap::Args;
use radiosity::gltf_io::{load_baked, ImportLimits};
use std::io::Write;
use std::net::TcpListener;
use std::path::PathBuf;
use std::sync::Arc;

/// The most light groups the page mixes (`MAX_GROUPS` of its `render.js`).
pub const MAX_VIEWED_GROUPS: usize = 64;

/// `radiosity view`.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// A baked solution (.glb or .gltf written by `radiosity bake`).
    pub baked: PathBuf,
    /// Port on 127.0.0.1 (0: any free port; the address is printed).
    #[arg(long, default_value_t = 0)]
    pub port: u16,
}

/// Runs `radiosity view`: checks the bake, then serves until stopped.
pub fn run(a: &ViewArgs) -> Result<()> {
    let baked = load_baked(&a.baked, &ImportLimits::default())?;
    if baked.groups.is_empty() {
        bail!(
            "{} is a bake without light groups (made before they were); bake the scene again \
             with `radiosity bake`",
            a.baked.display()
        );
    }
    if baked.groups.len() > MAX_VIEWED_GROUPS {
        bail!(
            "{} has {} light groups; the viewer mixes at most {MAX_VIEWED_GROUPS} (bake it \
             again with fewer: --light-group NAME=PATTERN,... merges sources)",
            a.baked.display(),
            baked.groups.len()
        );
    }
    for w in &baked.warnings {
        eprintln!("warning: {}", with_flags(w));
    }
    let bytes =
        std::fs::read(&a.baked).with_context(|| format!("reading {}", a.baked.display()))?;
    let scene = scene_name(&a.baked);
    let kind = if scene.ends_with(".glb") {
        "model/gltf-binary"
    } else {
        "model/gltf+json"
    };
    let mut files: Vec<(String, String, Vec<u8>)> = vec![(
        "index.html".into(),
        FILES[0].1.into(),
        page(scene, &baked.name).into_bytes(),
    )];
    for (name, kind, text) in &FILES[1..] {
        files.push((name.to_string(), kind.to_string(), text.as_bytes().to_vec()));
    }
    files.push((scene.to_string(), kind.to_string(), bytes));
    let listener = TcpListener::bind(("127.0.0.1", a.port)).with_context(|| {
        format!(
            "listening on 127.0.0.1:{} (--port 0 takes any free port)",
            a.port
        )
    })?;
    let address = listener.local_addr()?;
    let mut out = std::io::stdout();
    writeln!(
        out,
        "serving {} ({} triangles, {} light groups) at http://{address}/ (Ctrl-C stops)",
        a.baked.display(),
        baked.mesh.triangles.len(),
        baked.groups.len()
    )?;
    out.flush()?;
    serve(listener, Arc::new(Site::new(files)))
}
