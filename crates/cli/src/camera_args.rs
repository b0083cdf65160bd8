//! Camera flags shared by `tessellate`, `refine`, `render` and `view`.

use glam::Vec3;
use subdiv::framing_box;
use subdiv::mesh::{Camera, Mesh};

/// `--eye X,Y,Z --target X,Y,Z --up X,Y,Z | --eye-relative X,Y,Z`, `--fov DEG`, `--size WxH`.
#[derive(clap::Args, Debug, Clone)]
pub struct CameraArgs {
    /// Eye position.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<Vec3>,
    /// Point looked at (default: the centre of the cage's bounding box).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<Vec3>,
    /// Up vector.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: Vec3,
    /// Eye at the cage's bounding-box centre + (X,Y,Z) * half its diagonal, looking at the
    /// centre (the same box in every mode: uniform, adaptive, DoI, Loop).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, conflicts_with_all = ["eye", "target"])]
    pub eye_relative: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 45.0)]
    pub fov: f32,
    /// Viewport size in pixels.
    #[arg(long, value_parser = parse_size, default_value = "800x600")]
    pub size: (u32, u32),
}

impl CameraArgs {
    /// `true` when the user gave a camera position.
    pub fn has_camera(&self) -> bool {
        self.eye.is_some() || self.eye_relative.is_some()
    }

    /// The camera the flags describe for `cage`, framed on its [`framing_box`] (the cage's
    /// bounding box, whatever is tessellated from it); without `--eye` or `--eye-relative`, the
    /// default view from `(0.8, 0.5, 2.2)` radii.
    pub fn camera(&self, cage: &Mesh) -> Camera {
        let (lo, hi) = framing_box(cage);
        let (w, h) = self.size;
        if let Some(eye) = self.eye {
            let target = self.target.unwrap_or((lo + hi) * 0.5);
            return Camera::new(eye, target, self.up, self.fov, w, h);
        }
        let rel = self.eye_relative.unwrap_or(Vec3::new(0.8, 0.5, 2.2));
        let mut camera = Camera::eye_relative(lo, hi, rel, self.fov, w, h);
        // A given --up (e.g. 0,0,1 for Z-up models) wins unless it is parallel to the view.
        if self.up != Vec3::Y && camera.forward().cross(self.up).length_squared() > 1e-6 {
            camera.up = self.up;
        }
        camera
    }
}

/// Parses `X,Y,Z`.
pub fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f32>()
                .map_err(|_| format!("'{s}' is not X,Y,Z"))
        })
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("'{s}' is not X,Y,Z (three finite numbers)")),
    }
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("'{s}' is not WxH"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("'{s}' is not WxH"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("size {w}x{h} must be between 1x1 and 16384x16384"));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers() {
        assert_eq!(parse_vec3("1,-2,3.5").unwrap(), Vec3::new(1.0, -2.0, 3.5));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,nan").is_err());
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert!(parse_size("0x480").is_err());
        assert!(parse_size("640").is_err());
    }
}
