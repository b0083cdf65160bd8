//! Set-up shared by the image-based bound tests: the fixture cages and a renderer (skipped,
//! with a message, where no Vulkan driver is installed unless `SUBDIV_VK_REQUIRE_DRIVER=1`).

use std::path::{Path, PathBuf};

use subdiv::vk::{ContextOptions, Renderer, Validation, VkError};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every fixture cage (`fixtures/reference/shapes`, `fixtures/scenes`), sorted per folder.
pub fn cages() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in ["fixtures/reference/shapes", "fixtures/scenes"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "obj"))
            .collect();
        files.sort();
        out.extend(files);
    }
    out
}

/// A headless renderer, or `None` (after a message) where Vulkan is missing and not required.
pub fn renderer() -> Option<Renderer> {
    let options = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    match Renderer::with_options(&options) {
        Ok(r) => Some(r),
        Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. }))
            if std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1") =>
        {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("cannot create renderer: {e}"),
    }
}
