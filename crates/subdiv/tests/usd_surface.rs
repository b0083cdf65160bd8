//! A USD cage gives exactly the surface of the equivalent OBJ cage (the one Pixar's USD library
//! makes from it, `fixtures/usd/make_fixtures.py`): same limit points, normals and faces, bit
//! for bit, with the scheme the stage names.

use std::path::PathBuf;

use subdiv::mesh::{CageOptions, UsdScheme, read_cage, read_obj};
use subdiv::rules::Scheme;
use subdiv::uniform_limit;

fn fixture(name: &str) -> PathBuf {
    subdiv_test_support::fixture("usd").join(name)
}

#[test]
fn usd_cages_tessellate_to_the_surface_of_their_obj() {
    for (usd, obj, want) in [
        ("scene.usda", "scene.obj", UsdScheme::CatmullClark),
        ("scene.usdc", "scene.obj", UsdScheme::CatmullClark),
        (
            "open_lefthanded.usdz",
            "open_lefthanded.obj",
            UsdScheme::CatmullClark,
        ),
        ("tetra_loop.usda", "tetra_loop.obj", UsdScheme::Loop),
    ] {
        let cage = read_cage(fixture(usd), &CageOptions::default()).unwrap();
        assert_eq!(cage.scheme, Some(want), "{usd}");
        let scheme = Scheme::from_usd(want).unwrap();
        let reference = read_obj(fixture(obj)).unwrap();
        for depth in 1..=3 {
            let a = uniform_limit(&cage.mesh, scheme, depth).unwrap();
            let b = uniform_limit(&reference, scheme, depth).unwrap();
            assert!(!a.positions().is_empty(), "{usd}");
            assert_eq!(a.positions(), b.positions(), "{usd} depth {depth}");
            assert_eq!(a.normals(), b.normals(), "{usd} depth {depth}");
            assert_eq!(a.face_indices(), b.face_indices(), "{usd} depth {depth}");
            assert_eq!(
                a.corner_normals(),
                b.corner_normals(),
                "{usd} depth {depth}"
            );
        }
    }
    // bilinear is the bilinear scheme; none names no scheme of subdiv.
    assert_eq!(
        Scheme::from_usd(UsdScheme::Bilinear),
        Some(Scheme::Bilinear)
    );
    assert_eq!(Scheme::from_usd(UsdScheme::None), None);
}
