//! Animated USD stages against the truth: read at a time code, each fixture stage gives the
//! cage Pixar's USD library reads at that time (`fixtures/usd/make_animated.py`: time-sampled
//! points of a bending pawn, time-sampled transforms above two meshes, one time between
//! samples), and the stage's time range is what it authors.

use std::path::PathBuf;

use subdiv_mesh::{
    CageError, CageOptions, Mesh, UsdError, UsdReadOptions, UsdStageReader, read_cage, read_obj,
    read_usd,
};

fn fixture(name: &str) -> PathBuf {
    subdiv_test_support::fixture("usd").join(name)
}

fn at(name: &str, time: Option<f64>) -> Mesh {
    let opts = UsdReadOptions {
        time,
        ..Default::default()
    };
    read_usd(fixture(name), &opts).unwrap().mesh
}

/// Same topology, positions (bit for bit), sharpness and options.
fn assert_same_cage(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.num_vertices(), b.num_vertices(), "{what}");
    assert_eq!(a.face_lists(), b.face_lists(), "{what}");
    for (i, (p, q)) in a.positions().iter().zip(b.positions()).enumerate() {
        assert_eq!(
            p.to_array().map(f32::to_bits),
            q.to_array().map(f32::to_bits),
            "{what}: vertex {i}: {p} vs {q}"
        );
    }
    assert_eq!(a.edge_sharpnesses(), b.edge_sharpnesses(), "{what}");
    assert_eq!(a.vertex_sharpnesses(), b.vertex_sharpnesses(), "{what}");
    assert_eq!(a.options(), b.options(), "{what}");
}

#[test]
fn time_sampled_points_equal_pixars_cage_at_each_time() {
    for t in [1.0, 13.0, 30.0, 48.0] {
        let truth = read_obj(fixture(&format!("pawn_bend_t{t}.obj"))).unwrap();
        let read = at("pawn_bend.usdc", Some(t));
        assert_same_cage(&read, &truth, &format!("pawn_bend at {t}"));
    }
    // Without a time: the earliest sample (no default is authored); past the end: the last
    // sample, held.
    let first = read_obj(fixture("pawn_bend_t1.obj")).unwrap();
    assert_same_cage(&at("pawn_bend.usdc", None), &first, "no time");
    let last = read_obj(fixture("pawn_bend_t48.obj")).unwrap();
    assert_same_cage(&at("pawn_bend.usdc", Some(100.0)), &last, "held");
    // The frames differ: the pawn moves.
    let mid = at("pawn_bend.usdc", Some(13.0));
    assert_ne!(mid.positions(), first.positions());
}

#[test]
fn time_sampled_transforms_equal_pixars_cage_at_each_time() {
    for (t, name) in [(1.0, "1"), (12.0, "12"), (18.5, "18_5"), (24.0, "24")] {
        let truth = read_obj(fixture(&format!("xform_anim_t{name}.obj"))).unwrap();
        let read = at("xform_anim.usda", Some(t));
        assert_same_cage(&read, &truth, &format!("xform_anim at {t}"));
        assert_eq!(read.groups(), truth.groups());
    }
}

#[test]
fn the_stage_time_names_its_range_and_what_moves() {
    let stage = UsdStageReader::open(fixture("pawn_bend.usdc"), &Default::default()).unwrap();
    let time = stage.time().unwrap();
    assert_eq!(time.authored, Some((1.0, 48.0)));
    assert_eq!(time.range(), Some((1.0, 48.0)));
    assert_eq!(time.time_codes_per_second, 24.0);
    assert!(time.is_animated());
    assert_eq!(time.sampled.len(), 1);
    assert_eq!(time.sampled[0].0, "/World/Pawn.points");
    let expected: Vec<f64> = (1..=48).map(f64::from).collect();
    assert_eq!(time.sampled[0].1, expected);

    let stage = UsdStageReader::open(fixture("xform_anim.usda"), &Default::default()).unwrap();
    let time = stage.time().unwrap();
    let names: Vec<&str> = time.sampled.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["/World/Arm.xformOp:translate", "/World.xformOp:rotateZ"]
    );
    assert_eq!(time.sampled[0].1, [1.0, 12.0, 24.0]);
    assert_eq!(time.range(), Some((1.0, 24.0)));
    // Reading many times from one open stage gives what a fresh read gives.
    let again = stage.read_at(Some(18.5)).unwrap().mesh;
    assert_same_cage(&again, &at("xform_anim.usda", Some(18.5)), "reader");

    // A static stage: nothing sampled, no range.
    let stage = UsdStageReader::open(fixture("scene.usda"), &Default::default()).unwrap();
    let time = stage.time().unwrap();
    assert!(!time.is_animated());
    assert_eq!(time.range(), None);
}

#[test]
fn a_time_that_is_not_a_number_or_an_obj_with_a_time_is_refused() {
    let opts = UsdReadOptions {
        time: Some(f64::NAN),
        ..Default::default()
    };
    let e = read_usd(fixture("pawn_bend.usdc"), &opts).unwrap_err();
    assert!(matches!(e, UsdError::Time { .. }), "{e:?}");
    assert!(e.to_string().contains("pawn_bend.usdc: time NaN"), "{e}");
    let e = read_cage(
        fixture("pawn_bend_t1.obj"),
        &CageOptions {
            time: Some(3.0),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, CageError::TimeNotUsd { .. }), "{e:?}");
    assert!(e.to_string().contains("a time (3)"), "{e}");
}
