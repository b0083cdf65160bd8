//! The faces of a slate tessellation are written once per layout and output
//! (`tessellate_layout_into`, `tessellate_tri_layout_into`) and kept by the calls that follow
//! with the same layout; every other case writes them. Each output is compared with a fresh
//! tessellation of the same layout, so stale faces fail.

use subdiv_mesh::{Mesh, read_obj};
use subdiv_rules::LimitMesh;
use subdiv_slate::{
    PatchLayout, TriLayout, tessellate_layout, tessellate_layout_into, tessellate_tri_layout_into,
};

fn shape(name: &str) -> Mesh {
    read_obj(subdiv_test_support::shape(name)).expect("fixture")
}

/// Tessellates `layout` into `out`, checks the result against a fresh output and returns
/// whether the call wrote the faces.
fn quads_into(mesh: &Mesh, layout: &PatchLayout, out: &mut LimitMesh) -> bool {
    tessellate_layout_into(mesh, layout, out).expect("tessellate");
    let fresh = tessellate_layout(mesh, layout).expect("tessellate");
    assert!(fresh.topology_written());
    assert_eq!(*out, fresh, "the output differs from a fresh one");
    out.topology_written()
}

fn tris_into(mesh: &Mesh, layout: &TriLayout, out: &mut LimitMesh) -> bool {
    tessellate_tri_layout_into(mesh, layout, out).expect("tessellate");
    let mut fresh = LimitMesh::default();
    tessellate_tri_layout_into(mesh, layout, &mut fresh).expect("tessellate");
    assert!(fresh.topology_written());
    assert_eq!(*out, fresh, "the output differs from a fresh one");
    out.topology_written()
}

#[test]
fn quads_are_kept_only_for_the_same_layout() {
    let mut pawn = shape("catmark_pawn.obj");
    let cube = shape("catmark_cube.obj");
    let mut out = LimitMesh::default();
    let a = PatchLayout::new(&pawn, 2).unwrap();
    assert!(quads_into(&pawn, &a, &mut out), "first call");
    assert!(!quads_into(&pawn, &a, &mut out), "same layout: kept");
    // The positions move, the topology does not: kept, and the points follow.
    let before = out.positions().to_vec();
    for p in pawn.positions_mut() {
        p.y += 0.5;
    }
    assert!(!quads_into(&pawn, &a, &mut out), "moved cage: kept");
    assert_ne!(out.positions(), before);
    // Another layout of the same cage and depth (the same faces, another key).
    let b = PatchLayout::new(&pawn, 2).unwrap();
    assert!(quads_into(&pawn, &b, &mut out), "another layout");
    // Another depth.
    let c = PatchLayout::new(&pawn, 3).unwrap();
    assert!(quads_into(&pawn, &c, &mut out), "another depth");
    assert!(!quads_into(&pawn, &c, &mut out));
    // A hole changed: a new layout of the changed cage.
    let mut holed = pawn.clone();
    let mut holes = holed.holes().to_vec();
    holes[7] = true;
    holed.set_holes(holes);
    let d = PatchLayout::new(&holed, 3).unwrap();
    assert!(quads_into(&holed, &d, &mut out), "a hole");
    assert!(quads_into(&pawn, &c, &mut out), "the hole gone again");
    // Another cage into the same output.
    let e = PatchLayout::new(&cube, 3).unwrap();
    assert!(quads_into(&cube, &e, &mut out), "another cage");
    assert!(!quads_into(&cube, &e, &mut out));
}

#[test]
fn quads_changed_or_written_by_another_tessellator_are_written() {
    let pawn = shape("catmark_pawn.obj");
    let layout = PatchLayout::new(&pawn, 2).unwrap();
    let mut out = LimitMesh::default();
    assert!(quads_into(&pawn, &layout, &mut out));
    // The faces removed.
    out.clear_faces();
    assert!(quads_into(&pawn, &layout, &mut out), "faces removed");
    // Rewritten as a triangle list (as the adaptive frame writes its surface).
    out.write_triangles(subdiv_rules::VertexScalar::Depth, |b| {
        b.triangles.truncate(99);
        b.corner_normals.clear();
        b.uv_indices.clear();
    })
    .unwrap();
    assert!(quads_into(&pawn, &layout, &mut out), "another face list");
    // A clone keeps no key.
    let mut copy = out.clone();
    assert!(quads_into(&pawn, &layout, &mut copy), "a clone");
    // Written by the Loop slates in between (the offsets could have the same length).
    let tet = shape("loop_tetrahedron.obj");
    let tri = TriLayout::new(&tet, 2).unwrap();
    assert!(tris_into(&tet, &tri, &mut out));
    assert!(
        quads_into(&pawn, &layout, &mut out),
        "after the Loop slates"
    );
    assert!(tris_into(&tet, &tri, &mut out), "after the quads");
    // As many quads as triangles: the same list lengths, other offsets (`4i`, not `3i`).
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    let quad = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
    let one = PatchLayout::new(&quad, 3).unwrap();
    assert_eq!(one.num_quads(), out.num_faces());
    assert!(
        quads_into(&quad, &one, &mut out),
        "as many quads as triangles"
    );
    assert!(
        tris_into(&tet, &tri, &mut out),
        "as many triangles as quads"
    );
}

#[test]
fn triangles_are_kept_only_for_the_same_layout() {
    let mut ico = shape("loop_icosahedron.obj");
    let tet = shape("loop_tetrahedron.obj");
    let mut out = LimitMesh::default();
    let a = TriLayout::new(&ico, 3).unwrap();
    assert!(tris_into(&ico, &a, &mut out), "first call");
    assert!(!tris_into(&ico, &a, &mut out), "same layout: kept");
    for p in ico.positions_mut() {
        p.x *= 1.5;
    }
    assert!(!tris_into(&ico, &a, &mut out), "moved cage: kept");
    // A clone of a layout is another layout.
    let b = a.clone();
    assert!(tris_into(&ico, &b, &mut out), "a clone of the layout");
    let c = TriLayout::new(&ico, 2).unwrap();
    assert!(tris_into(&ico, &c, &mut out), "another depth");
    let mut holed = ico.clone();
    let mut holes = holed.holes().to_vec();
    holes[3] = true;
    holed.set_holes(holes);
    let d = TriLayout::new(&holed, 2).unwrap();
    assert!(tris_into(&holed, &d, &mut out), "a hole");
    let e = TriLayout::new(&tet, 2).unwrap();
    assert!(tris_into(&tet, &e, &mut out), "another cage");
    out.clear_faces();
    assert!(tris_into(&tet, &e, &mut out), "faces removed");
    assert!(!tris_into(&tet, &e, &mut out));
}
