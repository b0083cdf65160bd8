//! Headless rendering's errors: bad input, a missing Vulkan loader or driver, each a typed
//! error naming what to install, never a panic.

mod common;

use std::process::Command;

use common::{WHITE, finish, front_view, renderer, square};
use subdiv_vk::{ContextOptions, RenderMesh, RenderOptions, Renderer, Validation, VkError};

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let Some(mut r) = renderer() else { return };
    let sq = square(0.0);
    let view = front_view(1.0);
    let bad = RenderMesh {
        triangles: &[0, 1, 9],
        ..sq.mesh()
    };
    assert!(matches!(
        r.render(&bad, &view, [16, 16], &RenderOptions::default()),
        Err(VkError::InvalidMesh(_))
    ));
    assert!(matches!(
        r.render(&sq.mesh(), &view, [0, 16], &RenderOptions::default()),
        Err(VkError::InvalidSize { .. })
    ));
    assert!(matches!(
        r.render(&sq.mesh(), &view, [1 << 20, 16], &RenderOptions::default()),
        Err(VkError::InvalidSize { .. })
    ));
    // An empty mesh is just background, and the renderer still works afterwards.
    let empty = r
        .render(
            &RenderMesh::default(),
            &view,
            [16, 16],
            &RenderOptions::default(),
        )
        .unwrap();
    assert!(empty.pixels().all(|p| p.0 == WHITE));
    assert!(
        r.render(&sq.mesh(), &view, [16, 16], &RenderOptions::default())
            .is_ok()
    );
    finish(r);
}

#[test]
fn missing_loader_library_names_the_package() {
    let options = ContextOptions {
        validation: Validation::Off,
        library_path: Some("/nonexistent/libvulkan.so.1".into()),
    };
    let err = Renderer::with_options(&options).err().expect("must fail");
    assert!(matches!(err, VkError::LoaderMissing { .. }), "{err:?}");
    assert!(err.to_string().contains("mesa-vulkan-drivers"), "{err}");
}

/// Runs in a child process with no driver visible to the loader.
#[test]
fn missing_driver_names_the_package() {
    const CHILD: &str = "SUBDIV_VK_TEST_NO_DRIVER_CHILD";
    if std::env::var_os(CHILD).is_some() {
        let err = Renderer::with_options(&ContextOptions {
            validation: Validation::Off,
            ..Default::default()
        })
        .err()
        .expect("no driver: must fail");
        assert!(
            matches!(
                err,
                VkError::NoDriver { .. } | VkError::LoaderMissing { .. }
            ),
            "{err:?}"
        );
        assert!(err.to_string().contains("mesa-vulkan-drivers"), "{err}");
        return;
    }
    let exe = std::env::current_exe().unwrap();
    let out = Command::new(exe)
        .args([
            "--exact",
            "missing_driver_names_the_package",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, "1")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env_remove("VK_ADD_DRIVER_FILES")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "child failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("1 passed"));
}
