//! The approach law of one pin-flank line contact: Hertz half-width and pressure, the paper's
//! and Johnson's approach, a linear spring (docs/model.md section 3).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Elastic constants of the disc and the pins, Pa (paper Table 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Materials {
    /// Young's modulus of the disc `E1`, Pa.
    pub disc_youngs_modulus: f64,
    /// Poisson's ratio of the disc `nu1`.
    pub disc_poisson_ratio: f64,
    /// Young's modulus of the pins `E2`, Pa.
    pub pin_youngs_modulus: f64,
    /// Poisson's ratio of the pins `nu2`.
    pub pin_poisson_ratio: f64,
}

impl Materials {
    /// Compliances `(1 - nu1^2)/E1`, `(1 - nu2^2)/E2`, 1/Pa.
    pub(crate) fn compliances(&self) -> (f64, f64) {
        (
            (1.0 - self.disc_poisson_ratio.powi(2)) / self.disc_youngs_modulus,
            (1.0 - self.pin_poisson_ratio.powi(2)) / self.pin_youngs_modulus,
        )
    }

    /// Contact modulus `E*` with `1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2` (paper eq 13), Pa.
    pub(crate) fn contact_modulus(&self) -> f64 {
        let (c1, c2) = self.compliances();
        1.0 / (c1 + c2)
    }
}

/// The approach (normal compliance) law of one pin-tooth line contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproachLaw {
    /// Paper eq 6 with the Hertz half-width of eq 11 (default):
    /// `delta = 2F/(pi B) [C1 (1/3 + ln(4 rho/b)) + C2 (1/3 + ln(4 rrp/b))]`.
    Paper,
    /// Johnson's form: `delta = F/(pi B) sum_k C_k (2 ln(4 R_k / b) - 1)`, about 11 % stiffer.
    Johnson,
    /// A linear spring `F = k delta` (stiffness in N/m), for checks against Li's closed form.
    Linear {
        /// Stiffness, N/m.
        stiffness: f64,
    },
}

/// The housing groove a pin is seated in (SI): a conformal line contact on the far side of the
/// pin, in series with the pin-flank contact (docs/model.md section 3.4). Its approach has the
/// form of the flank's, `delta_g = 2F/(pi L) [C_pin (c0 + ln(4 rrp/b_g)) + C_housing (c0 +
/// ln(4 h/b_g))]` with the Hertz half-width `b_g` of the reduced radius `rrp R_g / (R_g -
/// rrp)` (Johnson, *Contact Mechanics*, sections 4.3 and 5.6: conformal cylinders), so the
/// two contacts in series keep the law's closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Groove {
    /// Groove radius minus pin radius, m (> 0).
    pub clearance: f64,
    /// Loaded length of the pin in its groove, m.
    pub length: f64,
    /// Reference depth of the housing term, m.
    pub housing_depth: f64,
}

/// A pin held only at its two ends in the housing (no groove along it), bent by a disc's load
/// as a Timoshenko beam simply supported over `span` and loaded at `load_at` from one support
/// (docs/model.md section 3.5): the deflection under the load is `F c`,
///
/// `c = x^2 (L - x)^2 / (3 E I L) + x (L - x) / (kappa G A L)`,
///
/// bending (Roark's Formulas for Stress and Strain, 7th ed., table 8.1, case 1e) plus shear
/// (section 8.10, `kappa = 0.9` for a round section), `I = pi d^4/64`, `A = pi d^2/4`, `d` the
/// pin's diameter, `E`, `G = E/(2 (1 + nu))` the pin's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinBending {
    /// Distance between the pin's supports `L`, m.
    pub span: f64,
    /// Distance of the disc's mid-plane from the nearer support `x`, m (`0 < x <= L/2`).
    pub load_at: f64,
}

impl PinBending {
    /// The compliance `c` (m/N) under the load of a pin of radius `pin_radius` (m) of the pin
    /// material of `materials`.
    pub fn compliance(&self, pin_radius: f64, materials: &Materials) -> f64 {
        let (l, x) = (self.span, self.load_at);
        let d = 2.0 * pin_radius;
        let i = std::f64::consts::PI * d.powi(4) / 64.0;
        let a = std::f64::consts::PI * d * d / 4.0;
        let e = materials.pin_youngs_modulus;
        let g = e / (2.0 * (1.0 + materials.pin_poisson_ratio));
        let kappa = 0.9;
        x * x * (l - x) * (l - x) / (3.0 * e * i * l) + x * (l - x) / (kappa * g * a * l)
    }
}

/// Hertz line-contact model of a pin on the disc flank.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    /// The housing groove of the pins in series with the flank contact (`None`: pins held
    /// rigidly, the earlier model).
    pub groove: Option<Groove>,
    /// Bending compliance of a pin held at its ends only, at the disc's load, m/N (0: pins
    /// held rigidly or bedded in grooves; [`PinBending`]), in series with the flank contact.
    pub pin_compliance: f64,
    /// The approach law.
    pub law: ApproachLaw,
    /// The materials.
    pub materials: Materials,
    /// Contact length (disc width) `B`, m.
    pub width: f64,
    /// Pin radius `rrp`, m.
    pub pin_radius: f64,
    /// Cap on the disc's radius of curvature in the reduced radius (and, with
    /// `disc_depth = None`, in the disc term of the approach law), m. Near the inflection of the
    /// profile (mesh angle about 35 deg) the flank is nearly flat and the 2D approach
    /// `ln(4 rho / b)` has no finite limit; the cap (default: the pin circle radius, the size of
    /// the disc) stands for the finite body.
    pub max_radius: f64,
    /// Reference depth `d` of the disc term of the approach law, `C1 (c0 + ln(4 d / b))`, m.
    /// `Some(d)`: the same depth at every flank point (default `d = Rp`: the approach of the
    /// flank relative to the disc body at the scale of the disc, where the bearings hold it), so
    /// that concave, flat and convex flanks differ only through the Hertz half-width. `None`:
    /// the paper's eq 6 as printed, the local flank radius of curvature (capped at
    /// `max_radius`): concave root contacts (radius about 3-5 mm) come out about 65 % stiffer in
    /// the disc term than mid-flank ones (capped at 64 mm), which is an artefact of the 2D
    /// half-space reference, not a property of the disc.
    pub disc_depth: Option<f64>,
}

/// Hertz quantities of one loaded contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzState {
    /// Normal force, N.
    pub force: f64,
    /// Contact half-width `b`, m (paper eq 11).
    pub half_width: f64,
    /// Maximum Hertz pressure `p0 = 2F/(pi b B)`, Pa.
    pub max_pressure: f64,
    /// Mean pressure `F/(2 b B)`, Pa (paper eq 19).
    pub mean_pressure: f64,
}

impl ContactModel {
    /// Reduced radius `R*` with `1/R* = 1/rrp + k` (`k` the disc curvature, negative where the
    /// flank is concave), capped at `max_radius`; m.
    pub(crate) fn reduced_radius(&self, disc_curvature: f64) -> f64 {
        let inv = 1.0 / self.pin_radius + disc_curvature;
        if inv <= 1.0 / self.max_radius {
            self.max_radius
        } else {
            (1.0 / inv).min(self.max_radius)
        }
    }

    /// Hertz half-width, maximum and mean pressure of force `force` (N) on a flank of
    /// curvature `disc_curvature` (1/m). Zero force gives zeros.
    pub(crate) fn hertz(&self, force: f64, disc_curvature: f64) -> HertzState {
        if force <= 0.0 {
            return HertzState {
                force: 0.0,
                half_width: 0.0,
                max_pressure: 0.0,
                mean_pressure: 0.0,
            };
        }
        let r = self.reduced_radius(disc_curvature);
        let e = self.materials.contact_modulus();
        let b = (4.0 * force * r / (std::f64::consts::PI * self.width * e)).sqrt();
        HertzState {
            force,
            half_width: b,
            max_pressure: 2.0 * force / (std::f64::consts::PI * b * self.width),
            mean_pressure: force / (2.0 * b * self.width),
        }
    }

    /// The disc's own term of the approach law per unit force, m/N: `2/(pi B) C1 (c0 + ln(4
    /// rho / w))`, the mean approach of the half-plane under the flank from an elliptic load of
    /// half-width `w` (m) down to the law's reference depth `rho` (docs/model.md section 5.13):
    /// what a finite-element disc loaded over the half-width `w` models again, beyond the
    /// part the law keeps below `w`. 0 for the linear law.
    pub(crate) fn disc_depth_compliance(&self, disc_curvature: f64, w: f64) -> f64 {
        if let ApproachLaw::Linear { .. } = self.law {
            return 0.0;
        }
        let (c0, rho, _) = self.log_law_terms(disc_curvature);
        let (c1, _) = self.materials.compliances();
        2.0 / (std::f64::consts::PI * self.width) * c1 * (c0 + (4.0 * rho / w).ln())
    }

    /// Constant `c0` and the two radii of the logarithmic laws.
    fn log_law_terms(&self, disc_curvature: f64) -> (f64, f64, f64) {
        let c0 = match self.law {
            ApproachLaw::Johnson => -0.5,
            _ => 1.0 / 3.0,
        };
        let rho = match self.disc_depth {
            Some(d) => d,
            None if disc_curvature.abs() < 1.0 / self.max_radius => self.max_radius,
            None => 1.0 / disc_curvature.abs(),
        };
        (c0, rho, self.pin_radius)
    }

    /// The approach law with its parts that do not depend on the flank curvature evaluated
    /// ([`PreparedLaw`]): what a solver's inner loop keeps for the force, stiffness and
    /// energy of every contact.
    pub(crate) fn prepared(&self) -> PreparedLaw {
        match self.law {
            ApproachLaw::Linear { stiffness } => PreparedLaw::Linear { stiffness },
            _ => PreparedLaw::Log(self.log_law()),
        }
    }

    /// The logarithmic law ([`LogLaw`]; its coefficients `(g0, g1)` of
    /// `delta = F (g0 - g1 ln F)`, F in N, delta in m) of a law that is not linear.
    fn log_law(&self) -> LogLaw {
        let pi = std::f64::consts::PI;
        let (c0, _, rp) = self.log_law_terms(0.0);
        let (c1, c2) = self.materials.compliances();
        let e = self.materials.contact_modulus();
        let k = 2.0 / (pi * self.width);
        // b = sqrt(cb F) with cb = 4 R / (pi B E); ln(4 rho / b) = ln(4 rho) - ln(cb)/2 - ln(F)/2
        // and ln(cb) = ln(4 / (pi B E)) + ln R: the disc's term k c1 ln(4 rho) (a constant with
        // a fixed depth) and the reduced radius's -k (c1 + c2) ln(R) / 2 vary with the flank.
        let mut base = k
            * ((c1 + c2) * (c0 - 0.5 * (4.0 / (pi * self.width * e)).ln()) + c2 * (4.0 * rp).ln())
            + self.pin_compliance;
        let mut g1 = 0.5 * k * (c1 + c2);
        if let Some(d) = self.disc_depth {
            base += k * c1 * (4.0 * d).ln();
        }
        if let Some(gr) = self.groove {
            let (h0, h1) = self.groove_coefficients(&gr, c0);
            base += h0;
            g1 += h1;
        }
        LogLaw {
            base,
            disc: if self.disc_depth.is_some() {
                0.0
            } else {
                k * c1
            },
            radius: -0.5 * k * (c1 + c2),
            g1,
            inv_pin_radius: 1.0 / self.pin_radius,
            max_radius: self.max_radius,
            ln_max_radius: self.max_radius.ln(),
        }
    }

    /// `(h0, h1)` of the groove's approach `F (h0 - h1 ln F)` ([`Groove`]), for the law's
    /// constant `c0`.
    pub(crate) fn groove_coefficients(&self, gr: &Groove, c0: f64) -> (f64, f64) {
        let pi = std::f64::consts::PI;
        let (c_housing, c_pin) = self.materials.compliances();
        let rp = self.pin_radius;
        let reduced = rp * (rp + gr.clearance) / gr.clearance;
        let e = self.materials.contact_modulus();
        let cb = 4.0 * reduced / (pi * gr.length * e);
        let k = 2.0 / (pi * gr.length);
        let h0 = k
            * (c_pin * (c0 + (4.0 * rp).ln() - 0.5 * cb.ln())
                + c_housing * (c0 + (4.0 * gr.housing_depth).ln() - 0.5 * cb.ln()));
        (h0, 0.5 * k * (c_pin + c_housing))
    }

    /// Elastic energy `int_0^delta F d(delta)` (J) stored in the contact at approach `delta` (m):
    /// for the logarithmic laws, with `delta = F (g0 - g1 ln F)`, exactly
    /// `F^2/2 (g0 - g1/2 - g1 ln F)`; `k delta^2 / 2` for the linear law. Zero for
    /// `delta <= 0`.
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    #[cfg(test)]
    pub(crate) fn potential(&self, delta: f64, disc_curvature: f64) -> Result<f64> {
        if delta <= 0.0 {
            return Ok(0.0);
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return Ok(0.5 * stiffness * delta * delta);
        }
        let (f, _) = self.force(delta, disc_curvature)?;
        Ok(self.prepared().energy_at_force(f, disc_curvature))
    }

    /// Approach `delta` (m) of the force `force` (N) on a flank of curvature `disc_curvature`.
    pub(crate) fn approach(&self, force: f64, disc_curvature: f64) -> f64 {
        if force <= 0.0 {
            return 0.0;
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return force / stiffness;
        }
        let (c0, rho, rp) = self.log_law_terms(disc_curvature);
        let (c1, c2) = self.materials.compliances();
        let b = self.hertz(force, disc_curvature).half_width;
        let groove = self.groove.map_or(0.0, |gr| {
            let (h0, h1) = self.groove_coefficients(&gr, c0);
            force * (h0 - h1 * force.ln())
        });
        2.0 * force / (std::f64::consts::PI * self.width)
            * (c1 * (c0 + (4.0 * rho / b).ln()) + c2 * (c0 + (4.0 * rp / b).ln()))
            + groove
            + force * self.pin_compliance
    }

    /// Force (N) and contact stiffness `dF/ddelta` (N/m) at approach `delta` (m): the inverse of
    /// `ContactModel::approach`, by Newton's method in `ln F` (the law is `F` times a function
    /// linear in `ln F`).
    ///
    /// # Errors
    /// [`Error::Numerical`] if the approach is beyond the range where the logarithmic law
    /// increases with force (half-width comparable with the radii).
    pub fn force(&self, delta: f64, disc_curvature: f64) -> Result<(f64, f64)> {
        if delta <= 0.0 {
            return Ok((0.0, 0.0));
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return Ok((stiffness * delta, stiffness));
        }
        self.force_from(delta, disc_curvature, f64::NAN)
    }

    /// [`ContactModel::force`] with a starting guess `f_guess` (N) for the Newton iteration (a
    /// warm start from the previous force of the same contact; ignored if not positive).
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    pub(crate) fn force_from(
        &self,
        delta: f64,
        disc_curvature: f64,
        f_guess: f64,
    ) -> Result<(f64, f64)> {
        self.prepared().force_from(delta, disc_curvature, f_guess)
    }
}

/// A [`ContactModel`]'s approach law prepared for a solver's inner loop
/// ([`ContactModel::prepared`]): the linear law, or the logarithmic laws with their parts that
/// do not depend on the flank curvature evaluated ([`LogLaw`]); [`ContactModel::force_from`]
/// calls it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PreparedLaw {
    /// `F = k delta` (N/m).
    Linear { stiffness: f64 },
    /// Johnson's or the paper's eq 6.
    Log(LogLaw),
}

impl PreparedLaw {
    /// [`ContactModel::force_from`]: the force (N) and contact stiffness `dF/ddelta` (N/m) at
    /// approach `delta` (m) on a flank of curvature `disc_curvature` (1/m), from the force
    /// `f_guess` (N) a moment before; zero for `delta <= 0`.
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    #[inline]
    pub(crate) fn force_from(
        &self,
        delta: f64,
        disc_curvature: f64,
        f_guess: f64,
    ) -> Result<(f64, f64)> {
        match self {
            _ if delta <= 0.0 => Ok((0.0, 0.0)),
            PreparedLaw::Linear { stiffness } => Ok((stiffness * delta, *stiffness)),
            PreparedLaw::Log(law) => law.force_from(delta, disc_curvature, f_guess),
        }
    }

    /// Elastic energy (J) stored in a contact carrying `force` (N) on a flank of curvature
    /// `disc_curvature` (1/m): `int F d(delta)` from zero, for the logarithmic laws
    /// `F^2 (g0/2 - g1/4 - (g1/2) ln F)` (the integral of `delta'(F) F`), for the linear law
    /// `F^2 / (2 k)`. Zero for `force <= 0`.
    pub(crate) fn energy_at_force(&self, force: f64, disc_curvature: f64) -> f64 {
        match self {
            _ if force <= 0.0 => 0.0,
            PreparedLaw::Linear { stiffness } => 0.5 * force * force / stiffness,
            PreparedLaw::Log(law) => law.energy_at_force(force, disc_curvature),
        }
    }

    /// Change of the contact force with the flank curvature at a fixed approach, `dF/dkappa`
    /// (N m), for a contact carrying `force` (N) with stiffness `stiffness` (N/m) on a flank of
    /// curvature `disc_curvature` (1/m): from `delta = F (g0(kappa) - g1 ln F)`,
    /// `dF/dkappa = -F g0'(kappa) dF/ddelta` (`g0'` by a central difference of the closed
    /// form). Zero for the linear law or no force.
    pub(crate) fn force_curvature_derivative(
        &self,
        force: f64,
        stiffness: f64,
        disc_curvature: f64,
    ) -> f64 {
        match self {
            PreparedLaw::Log(law) if force > 0.0 => {
                law.force_curvature_derivative(force, stiffness, disc_curvature)
            }
            _ => 0.0,
        }
    }
}

/// The logarithmic approach laws of a [`ContactModel`] (Johnson's and the paper's eq 6), with
/// the parts of `delta = F (g0(kappa) - g1 ln F)` that do not depend on the flank curvature
/// `kappa` evaluated once ([`ContactModel::prepared`]): `g0 = base + disc ln(4 rho(kappa)) +
/// radius ln(R(kappa))`, `rho` the disc term's radius and `R` the reduced radius (m). A
/// solver's inner loop then takes one logarithm for the coefficients (two without a fixed
/// disc depth) where the closed form takes three.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogLaw {
    /// The constant part of `g0`, m/N.
    base: f64,
    /// Factor of `ln(4 rho)` in `g0` (0 with a fixed disc depth, which `base` holds), m/N.
    disc: f64,
    /// Factor of `ln R` in `g0`, m/N.
    radius: f64,
    /// `g1`, m/N.
    g1: f64,
    /// The inverse of [`ContactModel::pin_radius`], 1/m.
    inv_pin_radius: f64,
    /// [`ContactModel::max_radius`], m, and its logarithm.
    max_radius: f64,
    ln_max_radius: f64,
}

impl LogLaw {
    /// `(g0, g1)` (m/N) on a flank of curvature `disc_curvature` (1/m), as
    /// [`ContactModel::log_law_terms`] and [`ContactModel::reduced_radius`] give the radii.
    #[inline]
    fn coefficients(&self, disc_curvature: f64) -> (f64, f64) {
        // ln R = -ln(1/R), R = 1 / (1/rrp + kappa) capped at the largest radius.
        let inv = self.inv_pin_radius + disc_curvature;
        let ln_r = if inv * self.max_radius <= 1.0 {
            self.ln_max_radius
        } else {
            -inv.ln()
        };
        let mut g0 = self.base + self.radius * ln_r;
        if self.disc != 0.0 {
            let rho = if disc_curvature.abs() * self.max_radius < 1.0 {
                self.max_radius
            } else {
                1.0 / disc_curvature.abs()
            };
            g0 += self.disc * (4.0 * rho).ln();
        }
        (g0, self.g1)
    }

    /// [`PreparedLaw::energy_at_force`] for this law (`force > 0`), J.
    fn energy_at_force(&self, force: f64, disc_curvature: f64) -> f64 {
        let (g0, g1) = self.coefficients(disc_curvature);
        0.5 * force * force * (g0 - 0.5 * g1 - g1 * force.ln())
    }

    /// [`PreparedLaw::force_curvature_derivative`] for this law (`force > 0`), N m.
    fn force_curvature_derivative(&self, force: f64, stiffness: f64, disc_curvature: f64) -> f64 {
        let h = 1e-6 * disc_curvature.abs().max(1.0);
        let (gp, _) = self.coefficients(disc_curvature + h);
        let (gm, _) = self.coefficients(disc_curvature - h);
        -force * stiffness * (gp - gm) / (2.0 * h)
    }

    /// [`PreparedLaw::force_from`] for this law (`delta > 0`): the force (N) and contact stiffness
    /// `dF/ddelta` (N/m) at approach `delta` (m) on a flank of curvature `disc_curvature`
    /// (1/m), by Newton's method on the law from the force `f_guess` (N, ignored if not
    /// positive), to 1e-14 of the force; where that start does not serve (not positive, or
    /// the steps leave the law's range), by Newton's method in `ln F` from a cold start.
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    fn force_from(&self, delta: f64, disc_curvature: f64, f_guess: f64) -> Result<(f64, f64)> {
        let (g0, g1) = self.coefficients(disc_curvature);
        // From a warm start, Newton's method on `F (g0 - g1 ln F) = delta` itself, concave and
        // increasing in F over the law's range (`g0 - g1 ln F > g1`): one logarithm a step, and
        // one step where the start is the contact's force a moment before.
        if f_guess > 0.0 {
            let mut f = f_guess;
            for _ in 0..4 {
                let lf = f.ln();
                let g = g0 - g1 * lf;
                if g <= 2.0 * g1 {
                    break;
                }
                let fp = g - g1;
                let inv_fp = 1.0 / fp;
                let step = (f * g - delta) * inv_fp;
                let next = f - step;
                if next.is_nan() || next <= 0.0 {
                    break;
                }
                // Newton's error after the step is `|f''| / (2 f') step^2 = g1 step^2 /
                // (2 F fp)`, relative to the force; the stiffness `1 / (fp + g1 step / F)` at
                // the new force to first order in the step (its error is of that order too).
                let tol = 1e-14 * next;
                if step.abs() < tol || g1 * step * step < 0.2 * tol * next * fp {
                    let moved = g1 * inv_fp * (step / f);
                    return Ok((next, inv_fp * (1.0 - moved)));
                }
                f = next;
            }
        }
        // delta = e^u (g0 - g1 u) with u = ln F; solve ln delta = u + ln(g0 - g1 u).
        let target = delta.ln();
        let warm = if f_guess > 0.0 {
            f_guess.ln()
        } else {
            f64::NAN
        };
        let mut u = if g0 - g1 * warm > 2.0 * g1 {
            warm
        } else {
            (delta / (g0 - g1 * 10.0_f64.ln()).max(1e-30)).ln()
        };
        for _ in 0..60 {
            let g = g0 - g1 * u;
            if g <= g1 {
                return Err(Error::numerical(
                    "contact law",
                    format!(
                        "approach {:.3e} m is beyond the validity of the line-contact law",
                        delta
                    ),
                ));
            }
            let f = u + g.ln() - target;
            let fp = 1.0 - g1 / g;
            let step = f / fp;
            u -= step;
            // Relative to |u|: at approaches of 1e-30 m, u = ln F is about -60 and its ulp
            // alone is 7e-15. Newton's error after a step is `c step^2` with
            // `c = |f''| / (2 |f'|) = g1^2 / (2 g (g - g1))`; a step whose square makes that
            // smaller than the tolerance ends the iteration too (a warm start then takes one
            // logarithm in place of two).
            let tol = 1e-14 * u.abs().max(1.0);
            if step.abs() < tol || g1 * g1 / (2.0 * g * (g - g1)) * step * step < 0.1 * tol {
                let force = u.exp();
                let g = g0 - g1 * u;
                let stiffness = 1.0 / (g - g1);
                return Ok((force, stiffness));
            }
        }
        Err(Error::numerical(
            "contact law",
            format!("force for approach {delta:e} m did not converge"),
        ))
    }
}
