//! Elementary functions with the same bits on every platform, for the geometry the FE disc is
//! meshed on.
//!
//! `f64::sin` and its kin call the platform's C library: glibc natively, another libm in the
//! WebAssembly module. Each is within an ulp of the true value, but not always the same ulp, and
//! the mesher's refinement is a sequence of discrete decisions (split this edge, insert that
//! circumcentre) that a last-bit difference in an outline point can turn: the built-in disc was
//! meshed with 20 100 nodes natively and 20 108 in the module, which moved its flexible TE by
//! about 1e-5. The functions here are the `libm` crate's (a port of musl's, in Rust, compiled
//! from source for each target, with no platform-dependent instruction), so every input of
//! the mesh, the disc profile's closed form, the bores' and holes' centres and the circles'
//! vertices, is the same on every platform, and so is the mesh (docs/model.md section 9.1).
//!
//! Accuracy: within 1 ulp of the true value (musl's bound), as `f64::sin_cos` natively.

/// `(sin x, cos x)` of `x` (rad).
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// The point at angle `a` (rad) on the unit circle: `(cos a, sin a)`.
#[inline]
pub fn unit(a: f64) -> super::Vec2 {
    let (s, c) = sin_cos(a);
    super::Vec2::new(c, s)
}
