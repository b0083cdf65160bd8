//! Set-up shared by the image-based bound tests: the fixture cages and a renderer (skipped,
//! with a message, where no Vulkan driver is installed unless `SUBDIV_VK_REQUIRE_DRIVER=1`).

use std::path::PathBuf;

use subdiv_test_support::fixture_files;

use subdiv::vk::{ContextOptions, Renderer, Validation, VkError};

/// Every fixture cage (`fixtures/reference/shapes`, `fixtures/scenes`), sorted per folder.
pub fn cages() -> Vec<PathBuf> {
    let mut out = fixture_files("reference/shapes", "obj");
    out.extend(fixture_files("scenes", "obj"));
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
