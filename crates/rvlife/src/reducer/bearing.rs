//! One radial bearing of the reducer: a linear spring or a set of rollers with a Hertz line
//! contact per roller, with radial internal clearance, a compliance in series and damping
//! (docs/model.md section 5.9).
//!
//! **Rollers** (Harris and Kotzalas, *Rolling Bearing Analysis*, 5th ed., vol. 2, ch. 1; the
//! approach of ISO/TS 16281): `Z` rollers per row, equally spaced, one of them under the load
//! (the stiffest position; Stribeck's). A displacement `d` of the inner ring's centre from the
//! outer's compresses roller `i`, at angle `psi_i = 2 pi i / Z` from the displacement, by
//! `delta_i = (d cos(psi_i) - c/2) cos(alpha)` (`c`: radial internal clearance, ISO 5753-1: the
//! total radial play ring to ring, so the centres move freely by `c/2` radially; `alpha`: the
//! contact angle of a tapered roller bearing, 0 for needles) and carries `Q_i = K_n delta_i^(10/9)` where `delta_i > 0`. `K_n` is
//! Palmgren's line contact, inner and outer raceway in series: `delta = 2 x 3.84e-5
//! Q^0.9 / l^0.8` (mm, N, roller length `l` in mm; steel). The radial force is
//! `F_r = rows sum Q_i cos(psi_i) cos(alpha)`.
//!
//! **Linear**: `F = k max(|r| - c/2, 0)` along `r`, the earlier model.
//!
//! **Dead band.** Within its clearance a bearing carries no load and its centre is free: a
//! spring of [`DEAD_BAND_STIFFNESS`] in parallel (standing in for lubricant film and seals)
//! keeps the equilibrium unique without a measurable force (0.01 N across 10 um of play).
//!
//! **In series**: a linear stiffness `k_s` (the crank's bending at the bearing, beam theory)
//! adds `F / k_s` to the displacement the bearing itself takes.

use nalgebra::Matrix2;

use crate::geometry::Vec2;

/// Stiffness (N/m) of the spring in parallel with every element that has a dead band (bearings
/// with clearance, rollers at zero load, meshes with backlash): the force across 10 um of play
/// is 0.01 N, against the tens of newtons of the smallest loads the analyses apply.
pub const DEAD_BAND_STIFFNESS: f64 = 1e3;

/// Width (m) over which a linear spring with play takes up its stiffness (a linear bearing
/// with clearance, a mesh with backlash): the force rises as `k x^2 / (2 w)` over the first
/// `w` beyond the play, then as `k (x - w/2)`, so that Newton's method does not cycle across
/// the kink. It shifts the play by `w/2`, 5 nm.
pub const TAKE_UP_WIDTH: f64 = 1e-8;

/// Force (N), stiffness (N/m) and energy (J) of a linear spring of stiffness `k` (N/m)
/// compressed `x` (m) beyond its play ([`TAKE_UP_WIDTH`]; zero for `x <= 0`).
#[inline]
pub(crate) fn take_up(x: f64, k: f64) -> (f64, f64, f64) {
    let w = TAKE_UP_WIDTH;
    if x <= 0.0 {
        (0.0, 0.0, 0.0)
    } else if x < w {
        (k * x * x / (2.0 * w), k * x / w, k * x * x * x / (6.0 * w))
    } else {
        let y = x - 0.5 * w;
        (k * y, k, 0.5 * k * y * y + k * w * w / 24.0)
    }
}

/// Palmgren's constant of a roller-raceway line contact (steel): `delta = 3.84e-5 Q^0.9 /
/// l^0.8` in mm, N and mm (Harris and Kotzalas, vol. 2, eq. 1.? of ch. 1; Palmgren, *Ball and
/// Roller Bearing Engineering*, 1959).
const PALMGREN_MM: f64 = 3.84e-5;

/// How one bearing carries a radial load (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BearingLaw {
    /// Isotropic linear spring, N/m.
    Linear {
        /// Radial stiffness, N/m.
        stiffness: f64,
    },
    /// Rolling elements with a Palmgren line contact each.
    Rollers {
        /// Rollers per row.
        count: usize,
        /// Rows (a tapered roller bearing pair: 2).
        rows: usize,
        /// `K_n` of one roller, inner and outer contact in series, N/m^(10/9).
        contact_constant: f64,
        /// Contact angle, rad (0: needle or cylindrical rollers).
        contact_angle: f64,
        /// Roller length, m.
        length: f64,
        /// Roller (mean) diameter, m: sets the rollers' spin and the cage speed, not the
        /// contact stiffness (Palmgren's line contact does not depend on it).
        diameter: f64,
        /// Pitch diameter of the roller set, m.
        pitch_diameter: f64,
    },
}

impl BearingLaw {
    /// Rollers of length `length` (m) and diameter `diameter` (m) on the pitch diameter
    /// `pitch_diameter` (m), `count` per row, `rows` rows at contact angle `angle` (rad), with
    /// Palmgren's line contact (`K_n = (l_mm^0.8 / (2 x 3.84e-5))^(10/9)` in N/mm^(10/9),
    /// converted to SI).
    pub fn rollers(
        count: usize,
        rows: usize,
        length: f64,
        diameter: f64,
        pitch_diameter: f64,
        angle: f64,
    ) -> Self {
        let l_mm = length * 1e3;
        let k_mm = (l_mm.powf(0.8) / (2.0 * PALMGREN_MM)).powf(10.0 / 9.0);
        BearingLaw::Rollers {
            count,
            rows,
            contact_constant: k_mm * 1e3_f64.powf(10.0 / 9.0),
            contact_angle: angle,
            length,
            diameter,
            pitch_diameter,
        }
    }
}

/// One radial bearing (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialBearing {
    /// Load-displacement law.
    pub law: BearingLaw,
    /// Radial internal clearance, m (ISO 5753-1: the total play, ring to ring; the centre
    /// moves freely within half of it).
    pub clearance: f64,
    /// Stiffness of the parts in series with the bearing, N/m (`f64::INFINITY`: none).
    pub series_stiffness: f64,
    /// Damping along the load, N s/m (dynamics only).
    pub damping: f64,
}

/// `x^(10/9)` and `x^(1/9)` for `x >= 0`: `exp(ln(x)/9)`, within a few ulps of `powf` (a
/// third faster; monotone like it, and 0 at 0).
#[inline]
fn pow_10_9(x: f64) -> (f64, f64) {
    let ninth = (x.ln() * (1.0 / 9.0)).exp();
    (x * ninth, ninth)
}

impl RadialBearing {
    /// Whether the bearing has a dead band (clearance, or rollers, whose stiffness vanishes at
    /// zero load), so that [`DEAD_BAND_STIFFNESS`] acts beside it.
    pub fn has_dead_band(&self) -> bool {
        self.clearance > 0.0 || matches!(self.law, BearingLaw::Rollers { .. })
    }

    /// Radial force (N) of the bearing itself at a centre displacement `d >= 0` (m), and its
    /// derivative `dF/dd` (N/m); without the series parts and the dead-band spring.
    pub fn own_force(&self, d: f64) -> (f64, f64) {
        let (f, k, _) = self.own_law(d, false);
        (f, k)
    }

    /// [`RadialBearing::own_force`] with the curvature `d2F/dd2` (N/m^2) when `curvature` is
    /// set (zero otherwise, and for a linear bearing beyond its take-up width).
    fn own_law(&self, d: f64, curvature: bool) -> (f64, f64, f64) {
        let half = 0.5 * self.clearance;
        match self.law {
            BearingLaw::Linear { stiffness } if half > 0.0 => {
                let x = d - half;
                let (f, k, _) = take_up(x, stiffness);
                let c = if x > 0.0 && x < TAKE_UP_WIDTH {
                    stiffness / TAKE_UP_WIDTH
                } else {
                    0.0
                };
                (f, k, c)
            }
            BearingLaw::Linear { stiffness } => (stiffness * d, stiffness, 0.0),
            BearingLaw::Rollers {
                count,
                rows,
                contact_constant,
                contact_angle,
                ..
            } => {
                // Roller 0 under the load and the pairs +-i beside it, while they face it
                // (their cosines by rotation steps).
                let ca = contact_angle.cos();
                let (s1, c1) = (std::f64::consts::TAU / count as f64).sin_cos();
                let (mut f, mut k, mut kc) = (0.0, 0.0, 0.0);
                let (mut c, mut sn) = (1.0_f64, 0.0_f64);
                let mut weight = 1.0;
                for _ in 0..count {
                    let cc = c * ca;
                    let delta = (d * c - half) * ca;
                    if delta <= 0.0 {
                        break;
                    }
                    let (p, ninth) = pow_10_9(delta);
                    f += weight * p * cc;
                    k += weight * ninth * cc * cc;
                    if curvature {
                        kc += weight * ninth / delta * cc * cc * cc;
                    }
                    (c, sn) = (c * c1 - sn * s1, sn * c1 + c * s1);
                    weight = 2.0;
                }
                let r = rows as f64 * contact_constant;
                (r * f, r * k * 10.0 / 9.0, r * kc * 10.0 / 81.0)
            }
        }
    }

    /// Load of each roller of one row (N) at a centre displacement `d` (m), roller 0 under the
    /// load (empty for a linear bearing).
    pub fn roller_loads(&self, d: f64) -> Vec<f64> {
        match self.law {
            BearingLaw::Linear { .. } => Vec::new(),
            BearingLaw::Rollers {
                count,
                contact_constant,
                contact_angle,
                ..
            } => (0..count)
                .map(|i| {
                    let c = (std::f64::consts::TAU * i as f64 / count as f64).cos();
                    let delta = (d * c - 0.5 * self.clearance) * contact_angle.cos();
                    if delta > 0.0 {
                        contact_constant * pow_10_9(delta).0
                    } else {
                        0.0
                    }
                })
                .collect(),
        }
    }

    /// Load (N) of the most loaded roller of one row when the bearing carries the radial load
    /// `f` (N) ([`RadialBearing::roller_loads_for`], roller 0). `None` for a linear bearing,
    /// which has no rollers.
    pub fn most_loaded_roller(&self, f: f64) -> Option<f64> {
        self.roller_loads_for(f).map(|q| q[0])
    }

    /// Load of each roller of one row (N, roller 0 under the load) when the bearing carries
    /// the radial load `f` (N): the displacement that carries `f` found by bisection on
    /// [`RadialBearing::own_force`] (monotone), then [`RadialBearing::roller_loads`]. `None`
    /// for a linear bearing, which has no rollers.
    pub fn roller_loads_for(&self, f: f64) -> Option<Vec<f64>> {
        let BearingLaw::Rollers { count, .. } = self.law else {
            return None;
        };
        if f <= 0.0 {
            return Some(vec![0.0; count]);
        }
        let half = 0.5 * self.clearance;
        let (mut lo, mut hi) = (half, half + 1e-6);
        while self.own_force(hi).0 < f && hi < 1.0 {
            hi = half + 2.0 * (hi - half);
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.own_force(mid).0 < f {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-15 * hi {
                break;
            }
        }
        Some(self.roller_loads(0.5 * (lo + hi)))
    }

    /// The exact radial law of [`RadialBearing::radial_force`]: the bearing's share `d`
    /// solves `g(d) = d + F(d)/k_s - x = 0`; plus the dead-band spring. `g` is increasing and
    /// convex above the clearance (`F` convex). The root is started from the local power law
    /// `F(x) ((d - c/2)/(x - c/2))^q` through the value and slope of `F` at `x` (exact for
    /// rollers without clearance, whose loaded set does not change with `d`), then refined by
    /// Halley's method (third order: two or three roller sums from that start reach
    /// round-off) to about `1e-15` of the share.
    pub fn radial_force_exact(&self, x: f64) -> (f64, f64) {
        let reg = if self.has_dead_band() {
            DEAD_BAND_STIFFNESS
        } else {
            0.0
        };
        let ks = self.series_stiffness;
        let (f, k) = if ks.is_finite() {
            let half = 0.5 * self.clearance;
            if x <= half {
                (0.0, 0.0)
            } else {
                let (f, kb) = self.series_share(x, half, ks);
                (f, if kb > 0.0 { kb * ks / (kb + ks) } else { 0.0 })
            }
        } else {
            self.own_force(x)
        };
        (f + reg * x, k + reg)
    }

    /// The bearing's force and stiffness `(F(d), F'(d))` at its share `d` of a total
    /// displacement `x > half` with series stiffness `ks` ([`RadialBearing::radial_force_exact`]).
    fn series_share(&self, x: f64, half: f64, ks: f64) -> (f64, f64) {
        let u = x - half;
        let y = {
            let (fx, kx, _) = self.own_law(x, false);
            if fx <= 0.0 || kx <= 0.0 {
                return (fx, kx);
            }
            // The power-law model: y + (fx/ks) (y/u)^q = u for y = d - half, by Newton from
            // y = u (the model's g is increasing and convex in y, so the iterates descend to
            // the root).
            let q = (kx * u / fx).max(1.0);
            let a = fx / ks;
            let mut y = u;
            for _ in 0..50 {
                let r = (y / u).powf(q);
                let g = y + a * r - u;
                let gp = 1.0 + a * q * r / y;
                let step = g / gp;
                y = (y - step).max(0.0);
                if step.abs() <= 1e-13 * u || y <= 0.0 {
                    break;
                }
            }
            y
        };
        // `max`/`min`, not `clamp`: a non-finite `x` from a diverging solve must not panic here
        // (the solver reports it).
        let mut d = (half + y).max(half).min(x);
        // The share's own scale beyond the clearance (small where the series part is soft).
        let scale = y.max(1e-6 * u);
        let mut out = self.own_law(d, true);
        for _ in 0..60 {
            let (fd, kd, cd) = out;
            let g = d + fd / ks - x;
            let gp = 1.0 + kd / ks;
            let gpp = cd / ks;
            let denom = 2.0 * gp * gp - g * gpp;
            // Halley's step; Newton's where the curvature term would more than double it.
            let halley = denom > gp * gp;
            let step = if halley { 2.0 * g * gp / denom } else { g / gp };
            if step.abs() <= 1e-13 * scale {
                // Converged at this share (the start, where the power law is exact).
                break;
            }
            d = (d - step).max(half).min(x);
            // A step below 1e-5 of the share (Halley's, third order) or 1e-8 (Newton's, second)
            // leaves an error of order 1e-15 of it.
            let last = step.abs() <= if halley { 1e-5 } else { 1e-8 } * scale;
            out = self.own_law(d, !last);
            if last {
                break;
            }
        }
        (out.0, out.1)
    }

    /// Force (N) on the first end for the relative position `r` (m) and relative velocity
    /// `rd` (m/s) of the first end from the second: along `r`, [`RadialBearing::radial_force`]
    /// of `|r|` plus damping along `r` while the bearing carries load.
    #[inline]
    pub fn force(&self, r: Vec2, rd: Vec2) -> Vec2 {
        if let Some(stiffness) = self.plain_linear() {
            return r * stiffness + rd * self.damping;
        }
        let len = r.norm();
        if len == 0.0 {
            return rd * self.damping.min(DEAD_BAND_STIFFNESS);
        }
        let n = r / len;
        let f = self.radial_force(len).0;
        let elastic = f - DEAD_BAND_STIFFNESS * len * f64::from(self.has_dead_band());
        let damp = if elastic > 0.0 {
            self.damping * rd.dot(&n)
        } else {
            0.0
        };
        n * (f + damp).max(0.0)
    }

    /// The stiffness (N/m) of a linear bearing without clearance or series parts, whose force
    /// is `k r` along any direction; `None` for any other bearing.
    fn plain_linear(&self) -> Option<f64> {
        match self.law {
            BearingLaw::Linear { stiffness }
                if self.clearance <= 0.0 && self.series_stiffness.is_infinite() =>
            {
                Some(stiffness)
            }
            _ => None,
        }
    }

    /// Static stiffness matrix `dF/dr` (N/m) at the relative position `r` (m):
    /// `F'(|r|) n n^T + F(|r|)/|r| (I - n n^T)` with `n = r/|r|` ([`RadialBearing::radial_force`]).
    pub fn stiffness_matrix(&self, r: Vec2) -> Matrix2<f64> {
        self.force_and_stiffness(r, false).1
    }

    /// [`RadialBearing::stiffness_matrix`] with each principal stiffness raised to at least
    /// half the bearing's [`RadialBearing::reference_stiffness`]: a stiffer stand-in for the
    /// first Newton steps of a solve that starts with the bearings unloaded, where the rollers'
    /// tangent stiffness vanishes (`F ~ d^(10/9)`). A bearing with clearance keeps its exact
    /// stiffness: within its dead band a floored stiffness would pull the step toward a contact
    /// that is not there.
    pub fn stiffness_matrix_floored(&self, r: Vec2) -> Matrix2<f64> {
        self.force_and_stiffness(r, true).1
    }

    /// The static force (N, [`RadialBearing::force`] at rest) and the stiffness matrix (N/m,
    /// [`RadialBearing::stiffness_matrix`], or with `floored`
    /// [`RadialBearing::stiffness_matrix_floored`]) at the relative position `r` (m), from one
    /// evaluation of the law.
    pub(crate) fn force_and_stiffness(&self, r: Vec2, floored: bool) -> (Vec2, Matrix2<f64>) {
        let len = r.norm();
        let (f, k) = self.radial_force(len);
        let floor = if floored && self.clearance <= 0.0 {
            0.5 * self.reference_stiffness()
        } else {
            0.0
        };
        if len == 0.0 {
            return (Vec2::zeros(), Matrix2::identity() * k.max(floor));
        }
        let n = r / len;
        let nn = n * n.transpose();
        let force = match self.plain_linear() {
            Some(stiffness) => r * stiffness,
            None => n * f.max(0.0),
        };
        (
            force,
            nn * k.max(floor) + (Matrix2::identity() - nn) * (f / len).max(floor),
        )
    }

    /// The energy (J) of the exact law at a displacement `x` (m): the rollers' `rows K_n sum
    /// (9/19) delta_i^(19/9)` (or the linear spring's) at the bearing's own share `d`, plus
    /// `F^2 / (2 k_s)` in the series parts and the dead-band spring's.
    pub(crate) fn energy_exact(&self, x: f64) -> f64 {
        let reg = if self.has_dead_band() {
            0.5 * DEAD_BAND_STIFFNESS * x * x
        } else {
            0.0
        };
        let half = 0.5 * self.clearance;
        if x <= half {
            return reg;
        }
        let (f, _) = self.radial_force_exact(x);
        let f = f - if self.has_dead_band() {
            DEAD_BAND_STIFFNESS * x
        } else {
            0.0
        };
        let (d, series) = if self.series_stiffness.is_finite() {
            let ks = self.series_stiffness;
            (x - f / ks, f * f / (2.0 * ks))
        } else {
            (x, 0.0)
        };
        let own = match self.law {
            BearingLaw::Linear { stiffness } if half > 0.0 => take_up(d - half, stiffness).2,
            BearingLaw::Linear { stiffness } => 0.5 * stiffness * d * d,
            BearingLaw::Rollers {
                count,
                rows,
                contact_constant,
                contact_angle,
                ..
            } => {
                let mut e = 0.0;
                for i in 0..count {
                    let c = (std::f64::consts::TAU * i as f64 / count as f64).cos();
                    let delta = (d * c - half) * contact_angle.cos();
                    if delta > 0.0 {
                        e += 9.0 / 19.0 * delta.powf(19.0 / 9.0);
                    }
                }
                rows as f64 * contact_constant * e
            }
        };
        reg + own + series
    }

    /// Tangent stiffness (N/m) of the bearing at 5 um beyond its clearance: the scale of its
    /// damping in the dynamics and of the defaults that take a bearing's stiffness.
    pub fn reference_stiffness(&self) -> f64 {
        self.radial_force(0.5 * self.clearance + 5e-6).1
    }
}
