use crate::error::MeshError;
use crate::{Mesh, SHARPNESS_INFINITE, VertexId, parse_obj};

/// Three quads on the edge 1-2 and three on the edge 2-3 beside it (1-based): vertex 2 has
/// exactly two non-manifold edges (a crease for OpenSubdiv), 1 and 3 one each (corners). Each
/// fan at vertex 2 holds both non-manifold edges.
const FINS: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n\
    v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 -1 0\nv 1 -1 0\nv 2 -1 0\n\
    f 1 2 5 4\nf 2 3 6 5\nf 2 1 7 8\nf 3 2 8 9\nf 1 2 11 10\nf 2 3 12 11\n";

fn split(text: &str) -> Result<Mesh, MeshError> {
    let mut soup = parse_obj(text)?;
    soup.split_nonmanifold()?;
    Mesh::from_soup(&soup)
}

#[test]
fn a_semi_sharp_vertex_at_a_crease_vertex_goes_to_every_copy() {
    let mesh = split(&format!("{FINS}t corner 1/1/0 1 1.5\n")).unwrap();
    // Vertex 1 (0-based) and its two copies, all with the tag's sharpness.
    let at = mesh.position(VertexId(1));
    let copies: Vec<f32> = mesh
        .vertices()
        .filter(|&v| mesh.position(v) == at)
        .map(|v| mesh.vertex_sharpness(v))
        .collect();
    assert_eq!(copies, vec![1.5; 3]);
}

/// The vertex sharpness of vertex 1 (0-based) and its copies, sorted.
fn copies_sharpness(mesh: &Mesh) -> Vec<f32> {
    let at = mesh.position(VertexId(1));
    let mut s: Vec<f32> = mesh
        .vertices()
        .filter(|&v| mesh.position(v) == at)
        .map(|v| mesh.vertex_sharpness(v))
        .collect();
    s.sort_by(f32::total_cmp);
    s
}

/// The whole vertex's semi-sharp values of vertex 1 (0-based) and its copies.
fn copies_whole(mesh: &Mesh) -> Vec<Option<Vec<f32>>> {
    let at = mesh.position(VertexId(1));
    mesh.vertices()
        .filter(|&v| mesh.position(v) == at)
        .map(|v| mesh.whole_vertex_edges(v).map(<[f32]>::to_vec))
        .collect()
}

/// Semi-sharp creases at a non-manifold vertex: every copy carries all of them (sorted), its
/// own and the other copies', whatever the crease method; the vertex sharpness stays the tag's.
#[test]
fn every_copy_carries_the_whole_vertex_semi_sharp_edges() {
    for (tags, want) in [
        // In one copy, in two, in three (1.9, 1.1, 1.1: refused before, as no vertex sharpness
        // gave the first copy the whole vertex's weight of 0.367 after one level).
        ("t crease 2/1/0 1 4 1.5\n", vec![1.5]),
        (
            "t crease 2/1/0 1 4 1.5\nt crease 2/1/0 1 10 0.5\n",
            vec![0.5, 1.5],
        ),
        (
            "t crease 2/1/0 1 4 1.9\nt crease 2/1/0 1 7 1.1\nt crease 2/1/0 1 10 1.1\n",
            vec![1.1, 1.1, 1.9],
        ),
        // Chaikin creases in copies that decay differently alone (refused before).
        (
            "t crease 2/1/0 1 4 2\nt crease 2/1/0 1 7 1.5\nt creasemethod 0/0/1 chaikin\n",
            vec![1.5, 2.0],
        ),
        // At a corner (infinite tag): the Chaikin decay still averages all of them.
        (
            "t corner 1/1/0 1 10\nt crease 2/1/0 1 4 2\nt crease 2/1/0 1 7 1.5\n\
             t creasemethod 0/0/1 chaikin\n",
            vec![1.5, 2.0],
        ),
    ] {
        let mesh = split(&format!("{FINS}{tags}")).unwrap();
        assert_eq!(copies_whole(&mesh), vec![Some(want); 3], "{tags}");
        let corner = tags.contains("corner");
        let vs = if corner { SHARPNESS_INFINITE } else { 0.0 };
        assert_eq!(copies_sharpness(&mesh), vec![vs; 3], "{tags}");
    }
    // Without semi-sharp creases there is nothing to carry.
    assert_eq!(copies_whole(&split(FINS).unwrap()), vec![None; 3]);
}

/// `edge-and-corner` sharpens the vertices with a single face in the whole cage, not a copy of
/// a crease vertex with a single face in its piece: a fin of one quad across both
/// non-manifold edges of vertex 1 (0-based).
#[test]
fn edge_and_corner_sharpens_the_whole_cages_one_face_vertices() {
    let one_face_fin = FINS.replace(
        "f 1 2 11 10\nf 2 3 12 11\n",
        "f 1 2 3 11\nt interpolateboundary 1/0/0 1\n",
    );
    let mut soup = parse_obj(&one_face_fin).unwrap();
    soup.split_nonmanifold().unwrap();
    assert_eq!(
        soup.options.boundary,
        crate::BoundaryInterpolation::EdgeOnly
    );
    let mesh = Mesh::from_soup(&soup).unwrap();
    // The crease vertex and its copies (one of them with a single face) stay creases.
    assert_eq!(copies_sharpness(&mesh), vec![0.0; 3]);
    // Vertex 3 (0-based), with one face in the cage, is a corner.
    assert_eq!(mesh.vertex_sharpness(VertexId(3)), SHARPNESS_INFINITE);
}

/// A copy of a crease vertex whose ring lacks one or both of its non-manifold edges takes the
/// crease rule over those of the first copy that holds both.
#[test]
fn a_copy_without_the_crease_edges_follows_one_with_them() {
    // A closed tetrahedron touching vertex 1 (0-based): its copy holds neither edge.
    let mesh = split(&format!(
        "{FINS}v 1 0.5 -1\nv 1.5 0.3 -1.2\nv 0.7 0.2 -1.1\n\
         f 2 14 13\nf 2 15 14\nf 2 13 15\nf 13 14 15\n"
    ))
    .unwrap();
    let copies: Vec<VertexId> = mesh.crease_ends_all().map(|(v, _)| v).collect();
    assert_eq!(copies.len(), 1);
    let copy = copies[0];
    let master = mesh.crease_copy_of(copy).unwrap();
    // Its crease ends: the two non-manifold edges of vertex 1, leaving the master.
    let ends = mesh.crease_ends(copy).unwrap();
    let far: Vec<VertexId> = ends.iter().map(|&h| mesh.to(h)).collect();
    assert_eq!(
        far.iter().map(|&w| mesh.position(w)).collect::<Vec<_>>(),
        vec![mesh.position(VertexId(0)), mesh.position(VertexId(2))]
    );
    assert_eq!(mesh.position(copy), mesh.position(VertexId(1)));
    assert_eq!(mesh.position(master), mesh.position(VertexId(1)));
    // The master holds both infinitely sharp edges; the copy none.
    let sharp = |v| {
        mesh.outgoing(v)
            .filter(|h| mesh.edge_sharpness(h.edge()) >= SHARPNESS_INFINITE)
            .count()
    };
    assert_eq!((sharp(master), sharp(copy)), (2, 0));
    // A cone of triangles leaving and returning through the edge 1-2 (1-based).
    let mesh = split(&format!(
        "{FINS}v 0.5 0.5 -1\nv 1 0.2 -1.2\nf 2 1 13\nf 2 13 14\nf 2 14 1\n"
    ))
    .unwrap();
    assert_eq!(mesh.crease_ends_all().count(), 1);
}

/// Where no copy holds both non-manifold edges (cones of triangles leaving and returning
/// through each edge, two on each), every copy takes the crease rule over edges of two
/// different copies.
#[test]
fn without_a_copy_holding_both_edges_the_copies_share_two() {
    let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0.5 1 0\nv 0.5 0.5 1\nv 0.5 -1 0\nv 0.5 0 -1\n\
                v 1.5 1 0\nv 1.5 0.5 1\nv 1.5 -1 0\nv 1.5 0 -1\n\
                f 2 1 4\nf 2 4 5\nf 2 5 1\nf 2 1 6\nf 2 6 7\nf 2 7 1\n\
                f 2 3 8\nf 2 8 9\nf 2 9 3\nf 2 3 10\nf 2 10 11\nf 2 11 3\n";
    let mesh = split(text).unwrap();
    let copies: Vec<(VertexId, [crate::HalfedgeId; 2])> = mesh.crease_ends_all().collect();
    assert_eq!(copies.len(), 4);
    for (v, ends) in copies {
        assert_eq!(mesh.crease_copy_of(v), None);
        let far: Vec<_> = ends.iter().map(|&h| mesh.position(mesh.to(h))).collect();
        assert_eq!(
            far,
            vec![mesh.position(VertexId(0)), mesh.position(VertexId(2))]
        );
        assert!(
            ends.iter()
                .all(|&h| mesh.position(mesh.from(h)) == mesh.position(VertexId(1)))
        );
    }
}

/// `interpolateboundary none`: the faces at a vertex with a boundary edge of the cage become
/// holes, and the pieces take edge-only boundaries (their copies of a non-manifold vertex are
/// boundary vertices of the piece, which OpenSubdiv does not hide).
#[test]
fn boundary_none_hides_the_faces_opensubdiv_hides() {
    // A cube with a fin on its edge 1-2 (1-based): every face at vertex 1 or 2 is hidden.
    let cube = "v 0 0 0\nv 0 0 1\nv 1 0 0\nv 1 0 1\nv 1 1 0\nv 1 1 1\nv 0 1 0\nv 0 1 1\n\
                v -1 -1 0\nv -1 -1 1\nf 1 7 5 3\nf 2 4 6 8\nf 1 3 4 2\nf 3 5 6 4\nf 5 7 8 6\n\
                f 7 1 2 8\nf 2 1 9 10\nt interpolateboundary 1/0/0 0\nt hole 1/0/0 2\n";
    let mut soup = parse_obj(cube).unwrap();
    soup.split_nonmanifold().unwrap();
    let mut holes: Vec<i64> = soup.holes.iter().map(|h| h.f).collect();
    holes.sort_unstable();
    // Face 2 was a hole already; it is not tagged twice.
    assert_eq!(holes, vec![0, 1, 2, 5, 6]);
    assert_eq!(
        soup.options.boundary,
        crate::BoundaryInterpolation::EdgeOnly
    );
    let mesh = Mesh::from_soup(&soup).unwrap();
    assert_eq!(mesh.faces().filter(|&f| !mesh.is_hole(f)).count(), 2);
    // Infinitely sharp tags on the fin's three boundary edges: no vertex has a boundary edge
    // that is not infinitely sharp, so nothing is hidden.
    let tagged = cube.replace(
        "t hole 1/0/0 2\n",
        "t crease 2/1/0 0 8 10\nt crease 2/1/0 8 9 10\nt crease 2/1/0 9 1 10\n",
    );
    let mut soup = parse_obj(&tagged).unwrap();
    soup.split_nonmanifold().unwrap();
    assert!(soup.holes.is_empty());
    // A manifold cage keeps its option (subdiv's own rule applies).
    let mut quad =
        parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt interpolateboundary 1/0/0 0\n")
            .unwrap();
    quad.split_nonmanifold().unwrap();
    assert_eq!(quad.options.boundary, crate::BoundaryInterpolation::None);
    assert!(quad.holes.is_empty());
}

/// OpenSubdiv leaves a vertex with two non-manifold edges unsharpened only with more faces than
/// edges and no boundary edge: a fin strip along two edges of a pentagon, each non-manifold
/// edge used twice the same way round, has three faces and three edges at its middle vertex: a
/// corner (fuzz-osd seed 21 cage 79).
#[test]
fn a_crease_needs_more_faces_than_edges() {
    let text = "v 1.17 -0.89 -2.03\nv 2.06 -0.91 -2.43\nv 2.79 -1.22 -3.06\nv 4.1 0.45 -3.38\n\
                v 2.37 0.24 -2.96\nv 2.0 -1.45 -2.09\nv 1.0 -1.59 -1.51\nv 3.32 -0.11 -2.66\n\
                f 1 2 3 4 5\nf 2 3 6 7\nf 3 4 8 6\n";
    let mut soup = parse_obj(text).unwrap();
    let found = soup.split_nonmanifold().unwrap();
    assert_eq!(found.edges, vec![(1, 2, 2), (2, 3, 2)]);
    assert!(soup.corners.iter().any(|c| c.v == 2 && c.sharpness >= 10.0));
    // FINS (six faces, five edges at vertex 2, no boundary edge) keeps the crease.
    let mut soup = parse_obj(FINS).unwrap();
    soup.split_nonmanifold().unwrap();
    assert!(!soup.corners.iter().any(|c| c.v == 1));
}

/// `FINS` with texture coordinates: every face's corners name the values of chart `chart(f)`
/// (one value per vertex and chart).
fn fins_with_charts(chart: impl Fn(usize) -> usize) -> String {
    let (head, faces) = FINS.split_at(FINS.find("f ").unwrap());
    let mut text = head.to_string();
    for c in 0..2 {
        for v in 0..12 {
            text += &format!("vt {} {}\n", v + 20 * c, v);
        }
    }
    for (f, line) in faces.lines().enumerate() {
        let corners: Vec<String> = line[2..]
            .split(' ')
            .map(|v| format!("{v}/{}", v.parse::<usize>().unwrap() + 12 * chart(f)))
            .collect();
        text += &format!("f {}\n", corners.join(" "));
    }
    text
}

#[test]
fn copies_of_a_nonmanifold_vertex_whose_values_differ_keep_them() {
    // Every fin in one chart: the values agree, nothing is kept.
    let same = split(&fins_with_charts(|_| 0)).unwrap();
    assert!(same.fvar_corners().is_empty());
    // The third fin on each edge in another chart: the values differ at the non-manifold
    // vertices 0, 1 and 2 (0-based, at y = z = 0), so every copy of them is kept, and no
    // other vertex (the fins' far vertices are manifold).
    let mesh = split(&fins_with_charts(|f| usize::from(f >= 4))).unwrap();
    let on_edges = |v: VertexId| {
        let p = mesh.position(v);
        p.y == 0.0 && p.z == 0.0
    };
    let copies: Vec<u32> = mesh
        .vertices()
        .filter(|&v| on_edges(v))
        .map(|v| v.0)
        .collect();
    assert!(copies.len() > 3, "{copies:?}");
    assert_eq!(mesh.fvar_corners(), copies.as_slice());
    assert!(
        mesh.vertices()
            .all(|v| mesh.is_fvar_corner(v) == on_edges(v))
    );
}
