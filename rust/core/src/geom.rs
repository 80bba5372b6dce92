//! Plane vectors as `[f64; 2]`, shared by the linkage kernels.

/// A point or vector in the plane [m].
pub type V2 = [f64; 2];

/// a − b.
#[inline]
pub fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}

/// a · b.
#[inline]
pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// a × b (the z component).
#[inline]
pub fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// |a − b|.
#[inline]
pub fn dist(a: V2, b: V2) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}
