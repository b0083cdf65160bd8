//! Paths of the workspace's fixtures, found from this crate's own directory, so that every
//! crate's tests name them the same way.

use std::path::PathBuf;

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The workspace's `fixtures/` directory.
pub fn fixtures() -> PathBuf {
    root().join("fixtures")
}

/// `fixtures/<rel>`.
pub fn fixture(rel: &str) -> PathBuf {
    fixtures().join(rel)
}

/// `fixtures/reference/shapes/<file>`: OpenSubdiv's shapes (`file` with its extension).
pub fn shape(file: &str) -> PathBuf {
    fixture("reference/shapes").join(file)
}

/// All files in `fixtures/<dir>` with extension `ext`, sorted.
pub fn fixture_files(dir: &str, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(fixture(dir))
        .unwrap_or_else(|e| panic!("fixtures/{dir}: {e}"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixture_paths_exist() {
        assert!(root().join("Cargo.toml").is_file());
        assert!(fixture("reference/shapes/catmark_cube.obj").is_file());
        assert!(shape("catmark_cube.obj").is_file());
        let shapes = fixture_files("reference/shapes", "obj");
        assert!(shapes.len() > 10);
        assert!(shapes.windows(2).all(|w| w[0] < w[1]));
    }
}
