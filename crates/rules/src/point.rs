//! The point types rules are applied to.

use glam::{DVec3, Vec3, Vec3A};

/// A 3D point the subdivision rules can combine: `f32` (`Vec3`, `Vec3A`) or `f64` (`DVec3`).
///
/// Rules are written once against this trait, so the whole-mesh reference refinement, the
/// exact-limit ring evaluation (in `f64`) and the slate tessellator (in `f32`) share one
/// implementation of every rule.
pub trait Point: Copy + Send + Sync + 'static {
    /// The origin.
    const ZERO: Self;
    /// `self + o`.
    fn add(self, o: Self) -> Self;
    /// `self - o`.
    fn sub(self, o: Self) -> Self;
    /// `self * s`.
    fn scale(self, s: f64) -> Self;
    /// `self + o * s`.
    #[inline]
    fn madd(self, o: Self, s: f64) -> Self {
        self.add(o.scale(s))
    }
    /// Conversion to `f64`.
    fn to_dvec3(self) -> DVec3;
    /// Conversion from `f64`.
    fn from_dvec3(p: DVec3) -> Self;
}

macro_rules! impl_point_f32 {
    ($t:ty) => {
        impl Point for $t {
            const ZERO: Self = <$t>::ZERO;
            #[inline]
            fn add(self, o: Self) -> Self {
                self + o
            }
            #[inline]
            fn sub(self, o: Self) -> Self {
                self - o
            }
            #[inline]
            fn scale(self, s: f64) -> Self {
                self * s as f32
            }
            #[inline]
            fn to_dvec3(self) -> DVec3 {
                DVec3::new(self.x as f64, self.y as f64, self.z as f64)
            }
            #[inline]
            fn from_dvec3(p: DVec3) -> Self {
                <$t>::new(p.x as f32, p.y as f32, p.z as f32)
            }
        }
    };
}
impl_point_f32!(Vec3);
impl_point_f32!(Vec3A);

impl Point for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    #[inline]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline]
    fn scale(self, s: f64) -> Self {
        self * s
    }
    #[inline]
    fn to_dvec3(self) -> DVec3 {
        self
    }
    #[inline]
    fn from_dvec3(p: DVec3) -> Self {
        p
    }
}

/// The average of a set of points (zero for an empty set).
#[inline]
pub fn centroid<P: Point>(pts: impl IntoIterator<Item = P>) -> P {
    let mut s = P::ZERO;
    let mut n = 0usize;
    for p in pts {
        s = s.add(p);
        n += 1;
    }
    if n == 0 { s } else { s.scale(1.0 / n as f64) }
}
