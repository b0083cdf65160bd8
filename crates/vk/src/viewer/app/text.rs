//! The viewer's words: the window title and the names of numbered screenshots.

use std::path::PathBuf;
use std::time::Instant;

use super::App;

impl App<'_> {
    /// The window title: fps, triangles, modes and the source's status.
    pub(super) fn title(&self, triangles: usize, status: &str) -> String {
        let mut title = format!(
            "{} | {:.1} fps | {} triangles | {}",
            self.options.title,
            self.fps,
            triangles,
            self.render.shading.name()
        );
        if self.render.wire_overlay {
            title.push_str(" +wire");
        }
        if self.silhouettes {
            title.push_str(" +silhouettes");
        }
        if self.frozen.is_some() {
            title.push_str(" | culling camera frozen");
        }
        if self.control.is_on() {
            title.push_str(&format!(
                " | {} control, target {:.0} fps",
                self.control.name(),
                self.target_fps
            ));
        } else {
            title.push_str(" | fps control off");
        }
        if let Some(player) = &self.player {
            title.push_str(" | ");
            title.push_str(&player.status(Instant::now()));
        }
        if !status.is_empty() {
            title.push_str(" | ");
            title.push_str(status);
        }
        title
    }
}

/// `dir/name.png` → `dir/name-0003.png`.
pub(super) fn numbered(path: &std::path::Path, n: usize) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "screenshot".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "png".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}-{n:04}.{ext}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screenshots_are_numbered() {
        assert_eq!(
            numbered(std::path::Path::new("d/shot.png"), 3),
            PathBuf::from("d/shot-0003.png")
        );
    }
}
