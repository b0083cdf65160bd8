use super::*;
use crate::{refine_uniform_levels, tessellate_uniform};
use subdiv_mesh::parse_obj;

/// An open cage with a pentagon, a triangle and a quad (boundary edges, n-gons).
const MIXED: &str = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nv 3 -1 0\nv 1 -1.5 0\n\
                     v 0 -1 0\nf 1 2 3 4 5\nf 2 6 3\nf 1 8 7 2\n";
const TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

fn mesh(text: &str) -> Mesh {
    Mesh::from_soup(&parse_obj(text).unwrap()).unwrap()
}

/// The estimate's counts equal the real refinement's and tessellation's on cages with n-gons
/// and boundaries, both schemes.
#[test]
fn uniform_estimate_is_the_real_size() {
    let cube = subdiv_test_support::cube().obj();
    for (text, scheme) in [
        (cube.as_str(), Scheme::CatmullClark),
        (MIXED, Scheme::CatmullClark),
        (TET, Scheme::Loop),
        (TET, Scheme::CatmullClark),
    ] {
        let m = mesh(text);
        for depth in 0..=4 {
            let s = estimate(&m, Request::Uniform { scheme, depth });
            let refined = refine_uniform_levels(&m, scheme, depth).unwrap();
            assert_eq!(
                s.vertices,
                refined.num_vertices() as u64,
                "{scheme:?} {depth}"
            );
            assert_eq!(s.faces, refined.num_faces() as u64, "{scheme:?} {depth}");
            let t = tessellate_uniform(&m, scheme, depth).unwrap();
            assert_eq!(s.vertices, t.positions().len() as u64);
            assert_eq!(s.faces, t.num_faces() as u64);
            assert_eq!(s.triangles, t.triangles().len() as u64 / 3);
        }
    }
}

/// Saturating arithmetic: the deepest depths and step counts on a cage give huge sizes, never
/// an overflow panic, and are refused by any finite memory.
#[test]
fn huge_requests_saturate_and_are_refused() {
    let m = mesh(&subdiv_test_support::cube().obj());
    for request in [
        Request::Uniform {
            scheme: Scheme::CatmullClark,
            depth: Depth::MAX,
        },
        Request::Adaptive {
            scheme: Scheme::CatmullClark,
            max_depth: Depth::MAX,
        },
        Request::Refine { steps: u32::MAX },
    ] {
        let s = estimate(&m, request);
        assert_eq!(s.triangles, u64::MAX, "{request:?}");
        assert_eq!(s.bytes, u64::MAX, "{request:?}");
        let budget = Budget {
            max_bytes: Some(1 << 40),
            max_triangles: None,
        };
        let e = budget.check(&m, request).unwrap_err();
        assert_eq!(e.limit, Limit::Memory { bytes: 1 << 40 });
    }
}

/// The triangle limit refuses one triangle above the exact count and accepts the count itself,
/// naming the limit.
#[test]
fn triangle_limit_is_exact() {
    let m = mesh(&subdiv_test_support::cube().obj());
    let request = Request::Uniform {
        scheme: Scheme::CatmullClark,
        depth: 3,
    };
    let at = 6 * 64 * 2;
    let ok = Budget::unlimited().with_max_triangles(Some(at));
    assert_eq!(ok.check(&m, request).unwrap().triangles, at);
    let e = Budget::unlimited()
        .with_max_triangles(Some(at - 1))
        .check(&m, request)
        .unwrap_err();
    assert_eq!(e.limit, Limit::Triangles { max: at - 1 });
    assert_eq!(
        e.to_string(),
        "depth 3 on 6 faces asks for 384 quads (768 triangles, 386 vertices, about 16.6 KiB \
         of output); the limit is 767 triangles"
    );
}

/// The message of a request beyond the memory states the request, the size and the memory.
#[test]
fn memory_message_states_the_size() {
    let m = mesh(TET);
    let e = Budget {
        max_bytes: Some(23 << 30),
        max_triangles: None,
    }
    .check(
        &m,
        Request::Uniform {
            scheme: Scheme::Loop,
            depth: 12,
        },
    );
    assert!(e.is_ok(), "{e:?}");
    let e = Budget {
        max_bytes: Some(1 << 20),
        max_triangles: None,
    }
    .check(
        &m,
        Request::Uniform {
            scheme: Scheme::Loop,
            depth: 12,
        },
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "depth 12 on 4 faces asks for 67,108,864 triangles (33,554,434 vertices, about 1.75 GiB \
         of output); this machine has 1.00 MiB of memory available"
    );
}

#[test]
fn formats() {
    assert_eq!(format_count(0), "0");
    assert_eq!(format_count(999), "999");
    assert_eq!(format_count(1000), "1,000");
    assert_eq!(format_count(872_415_232_000), "872,415,232,000");
    assert_eq!(format_bytes(512), "512 bytes");
    assert_eq!(format_bytes(1536), "1.50 KiB");
    assert_eq!(format_bytes(95 << 30), "95.0 GiB");
    assert_eq!(format_bytes(u64::MAX), "16.0 EiB");
}

#[test]
fn meminfo_and_cgroup() {
    let text = "MemTotal:       24000000 kB\nMemFree:         1000 kB\nMemAvailable:   \
                23000000 kB\n";
    assert_eq!(parse_meminfo(text), Some(23_000_000 * 1024));
    assert_eq!(parse_meminfo("MemTotal: 2048 kB\n"), Some(2048 * 1024));
    assert_eq!(parse_meminfo("nothing\n"), None);
    assert_eq!(parse_cgroup_max("max\n"), None);
    assert_eq!(parse_cgroup_max("4294967296\n"), Some(1 << 32));
    assert_eq!(
        cgroup_dirs(Some("0::/user.slice/a.scope\n")),
        ["/sys/fs/cgroup", "/sys/fs/cgroup/user.slice/a.scope"]
    );
    assert_eq!(cgroup_dirs(Some("0::/\n")), ["/sys/fs/cgroup"]);
    if cfg!(target_os = "linux") {
        assert!(machine_memory().is_some_and(|b| b > 0));
    }
}
