//! Conversion from nalgebra (the public API) to glam (parry's math types).

use nalgebra::Point3;
use parry3d_f64::math::Vector as GlamVector;

/// A nalgebra point as parry's glam vector.
#[inline]
pub(crate) fn to_glam(p: &Point3<f64>) -> GlamVector {
    GlamVector::new(p.x, p.y, p.z)
}

/// A parry glam vector as a nalgebra point.
#[cfg(test)]
fn from_glam(v: GlamVector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_every_component() {
        let p = Point3::new(1.5, -2.25, 3.125e-7);
        let g = to_glam(&p);
        assert_eq!((g.x, g.y, g.z), (1.5, -2.25, 3.125e-7));
        assert_eq!(from_glam(g), p);
    }
}
