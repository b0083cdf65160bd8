//! Versioned renders keep the vertices the renderer already holds and write only the dirty
//! ranges, vertices appended since the last version included: the picture equals a fresh
//! render of the same mesh, and a range left out of `dirty` really is not written (so the test
//! can tell).
//!
//! Without a Vulkan driver the test prints a note and passes, unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1` is set.

mod common;
mod grid;

use grid::{Grid, grid};
use subdiv_vk::glam::Vec3;
use subdiv_vk::{RenderMesh, RenderOptions, View};

#[test]
fn versioned_renders_write_only_the_dirty_vertices_and_match_fresh_ones() {
    let Some(mut r) = common::renderer() else {
        return;
    };
    let view = View::look_at(
        Vec3::new(0.3, -0.4, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        0.7,
        4.0 / 3.0,
        0.1,
        100.0,
    );
    let size = [96, 72];
    let options = RenderOptions {
        samples: Some(1),
        ..RenderOptions::default()
    };
    let k = 8;
    let flat = grid(k, |_, _| 0.0);
    // Version 2 lifts the vertices of rows 3 and 4 (indices 27..45).
    let lifted = grid(k, |_, j| if (3..=4).contains(&j) { 0.4 } else { 0.0 });
    let rows = 3 * (k + 1)..5 * (k + 1);
    fn mesh(m: &(Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>)) -> RenderMesh<'_> {
        RenderMesh {
            positions: &m.0,
            normals: &m.1,
            triangles: &m.2,
            ..Default::default()
        }
    }
    let fresh_flat = r.render(&mesh(&flat), &view, size, &options).unwrap();
    let fresh_lifted = r.render(&mesh(&lifted), &view, size, &options).unwrap();
    assert_ne!(fresh_flat, fresh_lifted, "the lift must show");
    // Version 1 in full, then version 2 with only its dirty rows written: as a fresh render.
    let all = 0..flat.0.len() as u32;
    let v1 = r
        .render_versioned(&mesh(&flat), &view, size, &options, 1, &[all])
        .unwrap();
    assert_eq!(v1, fresh_flat);
    let v2 = r
        .render_versioned(
            &mesh(&lifted),
            &view,
            size,
            &options,
            2,
            std::slice::from_ref(&rows),
        )
        .unwrap();
    assert_eq!(v2, fresh_lifted);
    // The same version again with nothing dirty keeps everything.
    let again = r
        .render_versioned(&mesh(&lifted), &view, size, &options, 2, &[])
        .unwrap();
    assert_eq!(again, fresh_lifted);
    // Back to flat as version 3, the lifted rows left out of `dirty`: the renderer keeps
    // version 2's lifted rows (so it really writes only `dirty`), and the picture is wrong.
    let kept = r
        .render_versioned(&mesh(&flat), &view, size, &options, 3, &[])
        .unwrap();
    assert_eq!(kept, fresh_lifted);
    // A version that does not follow the one held (a frame was skipped) is written in full.
    let skipped = r
        .render_versioned(&mesh(&flat), &view, size, &options, 9, &[])
        .unwrap();
    assert_eq!(skipped, fresh_flat);
    // An unversioned render in between forgets what was held.
    r.render(&mesh(&lifted), &view, size, &options).unwrap();
    let after = r
        .render_versioned(&mesh(&flat), &view, size, &options, 10, &[])
        .unwrap();
    assert_eq!(after, fresh_flat);

    // Vertices appended (an adaptive frame's new blocks) are written when `dirty` covers them,
    // and the rest is kept. `stack(parts, t)` lays grids one after the other and draws the
    // triangles of part `t`.
    let stack = |parts: &[&Grid], t: usize| {
        let n = flat.0.len() as u32;
        let pos: Vec<[f32; 3]> = parts.iter().flat_map(|m| m.0.clone()).collect();
        let nrm: Vec<[f32; 3]> = parts.iter().flat_map(|m| m.1.clone()).collect();
        let tris: Vec<u32> = flat.2.iter().map(|&i| i + t as u32 * n).collect();
        (pos, nrm, tris)
    };
    let n = flat.0.len() as u32;
    // A big mesh first, so that the buffer has room for the stacks below (a buffer too small
    // for a frame is written in full).
    let big = stack(&[&flat, &flat, &flat, &lifted], 3);
    r.render(&mesh(&big), &view, size, &options).unwrap();
    let v20 = r
        .render_versioned(
            &mesh(&flat),
            &view,
            size,
            &options,
            20,
            std::slice::from_ref(&(0..n)),
        )
        .unwrap();
    assert!(v20 == fresh_flat);
    let grown = stack(&[&flat, &lifted], 1);
    let v21 = r
        .render_versioned(
            &mesh(&grown),
            &view,
            size,
            &options,
            21,
            std::slice::from_ref(&(n..2 * n)),
        )
        .unwrap();
    assert!(v21 == fresh_lifted, "appended vertices written");
    // Grown again with only the new tail dirty: the first grid, rewritten but not marked,
    // keeps version 21's flat vertices, so the picture is the flat one.
    let tail = stack(&[&lifted, &lifted, &flat], 0);
    let v22 = r
        .render_versioned(
            &mesh(&tail),
            &view,
            size,
            &options,
            22,
            std::slice::from_ref(&(2 * n..3 * n)),
        )
        .unwrap();
    assert!(
        v22 == fresh_flat,
        "the vertices before the appended ones kept"
    );
    // Grown with the new vertices not among the dirty ones: everything is written.
    let v23 = r
        .render_versioned(
            &mesh(&big),
            &view,
            size,
            &options,
            23,
            std::slice::from_ref(&(0..n)),
        )
        .unwrap();
    assert!(v23 == fresh_lifted, "written in full");
}
