//! The parts in series with the crank bearings and the sun-planet meshes (docs/model.md section
//! 5.9): the crankshaft as a Timoshenko beam loaded at its two eccentrics, the carrier's
//! pillars at the crank seats, the cranks' and the input shaft's torsion, and the structure
//! compliance that stands for what the model leaves out. Closed forms of beam theory (Roark's
//! *Formulas for Stress and Strain*, 7th ed., tables 8.1 and 10.1, section 8.10), SI.

use std::f64::consts::PI;

/// Young's modulus of the shafts and the carrier, Pa (bearing and case-hardening steel).
pub const STEEL_YOUNGS_MODULUS: f64 = 210e9;

/// Poisson's ratio of the shafts and the carrier.
const STEEL_POISSON: f64 = 0.3;

/// Timoshenko's shear coefficient of a solid round section (0.9; Roark, section 8.10, where
/// Cowper's `6 (1 + nu)/(7 + 6 nu)` gives 0.886 at `nu = 0.3`).
pub const ROUND_SHEAR_COEFFICIENT: f64 = 0.9;

/// The steel's shear modulus, Pa.
fn shear_modulus() -> f64 {
    STEEL_YOUNGS_MODULUS / (2.0 * (1.0 + STEEL_POISSON))
}

/// A crankshaft between its crank-carrier bearings: a solid round steel beam of `diameter`,
/// simply supported at its two bearings `span` apart, loaded at its two eccentrics, which sit
/// symmetrically about mid-span `eccentric_spacing` apart (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrankBeam {
    /// Diameter of the shaft, m.
    pub diameter: f64,
    /// Distance between the supports (the crank-carrier bearings' rows), m.
    pub span: f64,
    /// Distance between the two eccentrics' mid-planes, m (less than `span`).
    pub eccentric_spacing: f64,
}

impl CrankBeam {
    /// The beam's flexibility at its two eccentrics, m/N: `(direct, cross)`, the deflection at
    /// one eccentric per unit load at the same one and at the other (the 2x2 flexibility is
    /// symmetric with equal diagonal terms, the eccentrics sitting symmetrically). Bending and
    /// shear of Timoshenko's beam, simply supported: a load at `xi` moves `x <= xi` by
    /// `x (L - xi) (2 L xi - xi^2 - x^2)/(6 E I L)` in bending and `x (L - xi)/(L kappa G A)`
    /// in shear (Roark, table 8.1, case 1e, and section 8.10), `I = pi d^4/64`,
    /// `A = pi d^2/4`, `kappa` [`ROUND_SHEAR_COEFFICIENT`].
    pub fn flexibility(&self) -> (f64, f64) {
        let l = self.span;
        let x = 0.5 * (l - self.eccentric_spacing);
        let xi = 0.5 * (l + self.eccentric_spacing);
        let e = STEEL_YOUNGS_MODULUS;
        let inertia = PI * self.diameter.powi(4) / 64.0;
        let shear = ROUND_SHEAR_COEFFICIENT * shear_modulus() * PI * self.diameter.powi(2) / 4.0;
        let at = |x: f64, xi: f64| {
            x * (l - xi) * (2.0 * l * xi - xi * xi - x * x) / (6.0 * e * inertia * l)
                + x * (l - xi) / (l * shear)
        };
        (at(x, x), at(x, xi))
    }
}

/// Torsional stiffness (N m/rad) of a solid round steel shaft of `diameter` twisted over
/// `length` (m): `k_t = G pi d^4/(32 L)` (Roark, table 10.1, case 1), `G = E/(2 (1 + 0.3))`.
pub fn shaft_torsion_stiffness(diameter: f64, length: f64) -> f64 {
    shear_modulus() * PI * diameter.powi(4) / (32.0 * length)
}

/// Stiffness (N/m) of the carrier at a crank's seat, in series with the crank-carrier bearing
/// pair: the carrier as two plates joined by `pillar` round bars of `pillar_diameter` and
/// `pillar_length` (m). The output is taken at one plate; each crank rests on both, half its
/// force on each, so the other plate's half reaches the output through the pillars, which it
/// shears and bends as beams guided by one plate against the other, each root elastic in its
/// plate: `1/k_p = L^3/(12 E I) + L/(kappa G A) + L^2/(2 K_r) + 2/K_h` (Timoshenko's beam,
/// Roark, table 8.1, and section 8.10; the antisymmetric end moments `V L/2` turn both roots
/// by `V L/(2 K_r)`), with each root a rigid circular punch of the pillar's radius `a` on an
/// elastic half-space, rocking `K_r = 8 G a^3/(3 (1 - nu))` and sliding `K_h = 8 G a/(2 - nu)`
/// (Gazetas, *J. Geotech. Eng.* 117(9), 1991, table 1; Richart, Hall & Woods, *Vibrations of
/// Soils and Foundations*, 1970). With as many pillars as cranks on the crank circle, that
/// plate turns by `(T/2)/(n k_p r^2)`, moving each crank's far seat by `r` times that and the
/// crank (between its two seats) by half of it: a seat stiffness `4 k_p` per crank, whatever
/// the number of cranks.
pub fn carrier_seat_stiffness(pillar_diameter: f64, pillar_length: f64) -> f64 {
    4.0 / pillar_compliance(pillar_diameter, pillar_length)
}

/// The compliance `1/k_p` (m/N) of one pillar with its roots ([`carrier_seat_stiffness`]).
fn pillar_compliance(d: f64, l: f64) -> f64 {
    let (e, g, nu) = (STEEL_YOUNGS_MODULUS, shear_modulus(), STEEL_POISSON);
    let area = PI * d * d / 4.0;
    let inertia = PI * d.powi(4) / 64.0;
    let a = 0.5 * d;
    let rocking = 8.0 * g * a.powi(3) / (3.0 * (1.0 - nu));
    let sliding = 8.0 * g * a / (2.0 - nu);
    l.powi(3) / (12.0 * e * inertia)
        + l / (ROUND_SHEAR_COEFFICIENT * g * area)
        + l * l / (2.0 * rocking)
        + 2.0 / sliding
}

/// The housing ring that holds the pins: a steel ring from the pins' grooves (`inner_radius`,
/// the pin circle radius plus the pin radius) to the case's outside (`outer_radius`), `width`
/// long (m), bent in its plane by the pins' loads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HousingRing {
    /// Inner radius, m.
    pub inner_radius: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// Axial width carrying the pins, m.
    pub width: f64,
}

impl HousingRing {
    /// The work (J) of point loads `(angle rad, radial N outward, tangential N in +angle)` on
    /// the ring through the displacements they cause: the ring as a thin inextensional ring
    /// of neutral radius `R` (mid-wall) and `I = w t^3/12`, its radial displacement
    /// `w = sum_n (a_n cos n theta + b_n sin n theta)`, tangential `v` with `v' = -w`; the
    /// strain energy `E I/(2 R^3) int (w'' + w)^2 d theta` gives, for harmonics `n >= 2`,
    /// `a_n = R^3 A_n/(pi E I (n^2 - 1)^2)` with the generalised force
    /// `A_n = sum_k (P_k cos n theta_k - Q_k sin n theta_k / n)` (and `B_n` with
    /// `P_k sin n theta_k + Q_k cos n theta_k / n`), and the work
    /// `sum_n R^3 (A_n^2 + B_n^2)/(pi E I (n^2 - 1)^2)` (Timoshenko, *Strength of Materials*,
    /// part I, ch. 12: the ring's `u_n = q_n R^4/(E I (n^2 - 1)^2)` for a radial load harmonic
    /// `q_n`). The harmonics 0 (the ring's stretch and its turn on its mount) and 1 (its
    /// translation, held by the mount) are left out; `harmonics` is the last `n` summed.
    pub fn work(&self, loads: &[(f64, f64, f64)], harmonics: usize) -> f64 {
        let r = 0.5 * (self.inner_radius + self.outer_radius);
        let t = self.outer_radius - self.inner_radius;
        let ei = STEEL_YOUNGS_MODULUS * self.width * t.powi(3) / 12.0;
        (2..=harmonics)
            .map(|n| {
                let nf = n as f64;
                let (mut a, mut b) = (0.0, 0.0);
                for &(theta, p, q) in loads {
                    let (s, c) = (nf * theta).sin_cos();
                    a += p * c - q * s / nf;
                    b += p * s + q * c / nf;
                }
                r.powi(3) * (a * a + b * b) / (PI * ei * (nf * nf - 1.0).powi(2))
            })
            .sum()
    }

    /// The ring's share of the output twist per output torque, rad/(N m), of an RV reducer
    /// with the stage `geometry`, discs at eccentric phases `phases` (rad) each carrying
    /// `disc_torque` N m per N m of output torque: the pins' loads of Li's closed form
    /// (docs/model.md section 5.6; each along the line from the pitch point, at `a Zp` along
    /// its disc's eccentric, through the pin's centre), both discs' on each pin summed, their
    /// work on the ring per squared torque ([`HousingRing::work`], `4 Zp` harmonics), mean
    /// over `samples` crank angles of a mesh cycle. Under a pure torque `T` the ring's energy
    /// `W/2` is the output's `T psi/2`, so its twist is `W/T`.
    pub fn twist_compliance(
        &self,
        geometry: &crate::geometry::CycloidGeometry,
        phases: &[f64],
        disc_torque: f64,
        samples: usize,
    ) -> f64 {
        let zp = geometry.pins;
        let pitch = geometry.eccentricity * zp as f64;
        let mut sum = 0.0;
        for i in 0..samples {
            let phi = std::f64::consts::TAU / zp as f64 * i as f64 / samples as f64;
            let mut load = vec![crate::geometry::Vec2::zeros(); zp];
            for &phase in phases {
                let ecc = phi + phase;
                let forces = crate::contact::li::li_load_distribution(geometry, ecc, disc_torque);
                let p = crate::geometry::Vec2::new(ecc.cos(), ecc.sin()) * pitch;
                for (j, f) in forces.iter().enumerate() {
                    if *f > 0.0 {
                        let c = geometry.pin_centre(j);
                        load[j] += (c - p).normalize() * *f;
                    }
                }
            }
            let loads: Vec<(f64, f64, f64)> = load
                .iter()
                .enumerate()
                .map(|(j, g)| {
                    let th = std::f64::consts::TAU * j as f64 / zp as f64;
                    let (s, c) = th.sin_cos();
                    (th, g.x * c + g.y * s, -g.x * s + g.y * c)
                })
                .collect();
            sum += self.work(&loads, 4 * zp);
        }
        sum / samples as f64
    }
}

/// The compliances (m/N) of the parts in series with each crank-disc bearing, each crank's
/// crank-carrier pair and each sun-planet mesh, part by part: what the reducer's series
/// stiffnesses ([`super::RadialBearing::series_stiffness`], [`super::Mesh::stiffness`]) are the
/// sums of, kept so that a part can be taken out again (the share of the twist each part
/// takes, `statics::shares`). 0: the part is rigid or left out.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SeriesCompliances {
    /// The crank's bending at an eccentric beyond what both eccentrics share (`direct -
    /// cross` of [`CrankBeam::flexibility`]), with each crank-disc bearing.
    pub crank_bending_own: f64,
    /// The crank's bending that both eccentrics share (`cross`), with the crank-carrier pair,
    /// which carries both discs' loads: the 2x2 flexibility of the crank exactly, for the
    /// loads of the discs.
    pub crank_bending_shared: f64,
    /// The disc's body between its pins' contacts and its crank bores, beyond the contact
    /// law's own depth term (`crate::fem::body`), with each crank-disc bearing.
    pub disc_body: f64,
    /// The ovalisation of the disc's crank bores under the needles' pressure
    /// (`crate::fem::body`), with each crank-disc bearing.
    pub disc_bores: f64,
    /// The carrier's pillars at the seat ([`carrier_seat_stiffness`]), with the crank-carrier
    /// pair.
    pub carrier: f64,
    /// The housing ring under the pins' loads ([`HousingRing::twist_compliance`] `c_h`), at
    /// the seats as `c_h n r^2` with the crank-carrier pair.
    pub housing: f64,
    /// The structure compliance `c` (output twist per output torque, rad/(N m)) at the seats:
    /// `c n r^2` with the crank-carrier pair, which turns the output by `c T` under a pure
    /// torque `T` on `n` cranks at radius `r`.
    pub structure: f64,
    /// The crank's torsion between its planet and its eccentrics, `r_bp^2/k_t`, with the mesh.
    pub crank_torsion: f64,
    /// The input shaft's torsion between the locked input and the sun, `n r_bs^2/k_s` with
    /// each of the `n` meshes (the sun's torque shared equally).
    pub input_shaft: f64,
}

impl SeriesCompliances {
    /// The parts with a crank-disc bearing, m/N.
    pub fn disc_side(&self) -> f64 {
        self.crank_bending_own + self.disc_body + self.disc_bores
    }
    /// The parts with a crank-carrier pair, m/N.
    pub fn carrier_side(&self) -> f64 {
        self.crank_bending_shared + self.carrier + self.housing + self.structure
    }
    /// The parts with a mesh, m/N.
    pub fn mesh_side(&self) -> f64 {
        self.crank_torsion + self.input_shaft
    }

    /// These compliances with the housing `ring` under the pins' loads (`housing`: its twist
    /// compliance at the seats, docs/model.md section 5.9) of an RV reducer with the stage
    /// `geometry`, discs at eccentric phases `phases` (rad), sun-to-planet ratio
    /// `sun_planet_ratio` and `planets` cranks at `crank_circle` (m): the ring's
    /// [`HousingRing::twist_compliance`] (each disc carrying half of `(Zp - 1)/(Zp + i_1)` of
    /// the output torque, 12 crank angles) times `n r^2`.
    pub fn with_housing(
        mut self,
        ring: &HousingRing,
        geometry: &crate::geometry::CycloidGeometry,
        phases: &[f64],
        sun_planet_ratio: f64,
        planets: usize,
        crank_circle: f64,
    ) -> Self {
        let zp = geometry.pins as f64;
        let twist_factor = (zp - 1.0) / (zp + sun_planet_ratio);
        let c = ring.twist_compliance(geometry, phases, 0.5 * twist_factor, 12);
        self.housing = c * planets as f64 * crank_circle * crank_circle;
        self
    }

    /// Sums these compliances into the series stiffnesses they are the parts of
    /// (docs/model.md section 5.9): the crank-disc bearings' (`disc`, [`Self::disc_side`]),
    /// the crank-carrier pairs' (`carrier`, [`Self::carrier_side`]), and the sun-planet mesh's
    /// own stiffness in series with [`Self::mesh_side`] (`mesh`).
    pub fn put_in_series(
        &self,
        disc: &mut super::RadialBearing,
        carrier: &mut super::RadialBearing,
        mesh: &mut super::Mesh,
    ) {
        disc.series_stiffness = stiffness_of(self.disc_side());
        carrier.series_stiffness = stiffness_of(self.carrier_side());
        mesh.stiffness = 1.0 / (1.0 / mesh.stiffness + self.mesh_side());
    }
}

/// The stiffness (N/m) of a compliance `c` (m/N): infinite for 0.
pub fn stiffness_of(c: f64) -> f64 {
    if c > 0.0 {
        1.0 / c
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 2x2 flexibility against a beam solution found independently: the unit-load method
    /// (virtual work, `int M m/(E I) + V v/(kappa G A) dx`) integrated numerically over the
    /// span for a load at either eccentric, on several beams; and its shear part alone against
    /// Timoshenko's closed form for a load at mid-span, `F L/(4 kappa G A)`.
    #[test]
    fn crank_flexibility_is_the_beam_with_two_loads() {
        let e = STEEL_YOUNGS_MODULUS;
        for (d, l, s) in [
            (16.2e-3, 35e-3, 10.5e-3),
            (10e-3, 60e-3, 20e-3),
            (30e-3, 40e-3, 0.0),
            (12e-3, 25e-3, 24e-3),
        ] {
            let beam = CrankBeam {
                diameter: d,
                span: l,
                eccentric_spacing: s,
            };
            let (direct, cross) = beam.flexibility();
            let inertia = PI * d.powi(4) / 64.0;
            let ga = ROUND_SHEAR_COEFFICIENT * shear_modulus() * PI * d * d / 4.0;
            let (x1, x2) = (0.5 * (l - s), 0.5 * (l + s));
            // Moment and shear of a unit load at `p` on the simply supported beam.
            let moment = |p: f64, x: f64| {
                if x <= p {
                    (l - p) / l * x
                } else {
                    p / l * (l - x)
                }
            };
            let shear = |p: f64, x: f64| if x < p { (l - p) / l } else { -p / l };
            let n = 200_000;
            let h = l / n as f64;
            let (mut f11, mut f12) = (0.0, 0.0);
            for i in 0..n {
                let x = (i as f64 + 0.5) * h;
                f11 += h
                    * (moment(x1, x) * moment(x1, x) / (e * inertia)
                        + shear(x1, x) * shear(x1, x) / ga);
                f12 += h
                    * (moment(x1, x) * moment(x2, x) / (e * inertia)
                        + shear(x1, x) * shear(x2, x) / ga);
            }
            assert!((direct / f11 - 1.0).abs() < 1e-6, "{direct} vs {f11}");
            assert!((cross / f12 - 1.0).abs() < 1e-6, "{cross} vs {f12}");
            assert!(cross <= direct && cross > 0.0);
        }
        // Shear alone: an infinitely stiff bending beam is a shear beam; at mid-span with the
        // eccentrics together, `F L/(4 kappa G A)` beside the bending `F L^3/(48 E I)`.
        let (d, l) = (16.2e-3, 35e-3);
        let beam = CrankBeam {
            diameter: d,
            span: l,
            eccentric_spacing: 0.0,
        };
        let inertia = PI * d.powi(4) / 64.0;
        let ga = ROUND_SHEAR_COEFFICIENT * shear_modulus() * PI * d * d / 4.0;
        let closed = l.powi(3) / (48.0 * e * inertia) + l / (4.0 * ga);
        let (direct, cross) = beam.flexibility();
        assert!((direct / closed - 1.0).abs() < 1e-12);
        assert!((cross / closed - 1.0).abs() < 1e-12);
    }

    /// A pillar with elastic roots against the direct stiffness method: a Timoshenko beam
    /// element (exact in statics: Przemieniecki, *Theory of Matrix Structural Analysis*, 1968,
    /// section 5.6) joined to each plate by a rocking and a sliding spring of the punch
    /// formulas, one plate held, the other pushed sideways without turning; its deflection per
    /// force against [`pillar_compliance`], on several pillars.
    #[test]
    fn pillar_with_roots_is_the_beam_on_root_springs() {
        let (e, g, nu) = (STEEL_YOUNGS_MODULUS, shear_modulus(), STEEL_POISSON);
        for (d, l) in [(18.9e-3_f64, 21.9e-3_f64), (10e-3, 40e-3), (30e-3, 15e-3)] {
            let a = 0.5 * d;
            let (kr, kh) = (
                8.0 * g * a.powi(3) / (3.0 * (1.0 - nu)),
                8.0 * g * a / (2.0 - nu),
            );
            let ei = e * PI * d.powi(4) / 64.0;
            let phi = 12.0 * ei / (ROUND_SHEAR_COEFFICIENT * g * PI * d * d / 4.0 * l * l);
            let c = ei / (l.powi(3) * (1.0 + phi));
            let kb = [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [6.0 * l, (4.0 + phi) * l * l, -6.0 * l, (2.0 - phi) * l * l],
                [-12.0, -6.0 * l, 12.0, -6.0 * l],
                [6.0 * l, (2.0 - phi) * l * l, -6.0 * l, (4.0 + phi) * l * l],
            ];
            // Unknowns: w_A, theta_A, w_B, theta_B (beam ends), delta (the pushed plate).
            let mut k = nalgebra::DMatrix::<f64>::zeros(5, 5);
            for i in 0..4 {
                for j in 0..4 {
                    k[(i, j)] = c * kb[i][j];
                }
            }
            k[(0, 0)] += kh;
            k[(1, 1)] += kr;
            k[(3, 3)] += kr;
            for (i, j, v) in [(2, 2, kh), (4, 4, kh), (2, 4, -kh), (4, 2, -kh)] {
                k[(i, j)] += v;
            }
            let f = nalgebra::DVector::from_vec(vec![0.0, 0.0, 0.0, 0.0, 1.0]);
            let u = k.lu().solve(&f).expect("regular");
            let closed = pillar_compliance(d, l);
            assert!((u[4] / closed - 1.0).abs() < 1e-9, "{} vs {closed}", u[4]);
        }
    }

    /// The housing ring against the ring formulas: a thin ring pinched by two opposite radial
    /// loads `P` shortens that diameter by `(pi/4 - 2/pi) P R^3/(E I) = 0.1488 P R^3/(E I)`
    /// (Roark, table 9.2, case 1), so the loads' work is `P` times that, within 1e-6 (the
    /// series to `n` = 4000); and `N = 360` point loads `P cos(n theta)` (a radial harmonic
    /// `q_n = P N/(2 pi R)`) or `Q sin(n theta)` (a tangential one) do the work `N/2` times the
    /// load times `u_n = R^4 (q_n - p_n/n)/(E I (n^2 - 1)^2)`, within 1e-9, for `n` = 2, 3, 5
    /// (summed to `n` = 179, below the first harmonic the 360 points alias onto it).
    #[test]
    fn the_housing_ring_follows_the_ring_formulas() {
        let ring = HousingRing {
            inner_radius: 67e-3,
            outer_radius: 95e-3,
            width: 26.25e-3,
        };
        let r = 0.5 * (ring.inner_radius + ring.outer_radius);
        let t = ring.outer_radius - ring.inner_radius;
        let ei = STEEL_YOUNGS_MODULUS * ring.width * t.powi(3) / 12.0;
        let p = 1000.0;
        let pinch = ring.work(&[(0.0, -p, 0.0), (PI, -p, 0.0)], 4000);
        let closed = p * (PI / 4.0 - 2.0 / PI) * p * r.powi(3) / ei;
        assert!((pinch / closed - 1.0).abs() < 1e-6, "{pinch} vs {closed}");
        let n_loads = 360;
        for n in [2usize, 3, 5] {
            let nf = n as f64;
            let theta = |k: usize| std::f64::consts::TAU * k as f64 / n_loads as f64;
            let u = |q: f64, pt: f64| r.powi(4) * (q - pt / nf) / (ei * (nf * nf - 1.0).powi(2));
            let radial: Vec<(f64, f64, f64)> = (0..n_loads)
                .map(|k| (theta(k), p * (nf * theta(k)).cos(), 0.0))
                .collect();
            let q = p * n_loads as f64 / (std::f64::consts::TAU * r);
            let w = ring.work(&radial, n_loads / 2 - 1);
            let closed = 0.5 * n_loads as f64 * p * u(q, 0.0);
            assert!((w / closed - 1.0).abs() < 1e-9, "n {n}: {w} vs {closed}");
            let tangential: Vec<(f64, f64, f64)> = (0..n_loads)
                .map(|k| (theta(k), 0.0, p * (nf * theta(k)).sin()))
                .collect();
            // The tangential harmonic `p_n sin(n theta)` moves the ring radially by
            // `u_n cos(n theta)` and tangentially by `-u_n sin(n theta)/n`: its work.
            let w = ring.work(&tangential, n_loads / 2 - 1);
            let un = u(0.0, q);
            let closed = 0.5 * n_loads as f64 * p * (-un / nf);
            assert!((w / closed - 1.0).abs() < 1e-9, "n {n}: {w} vs {closed}");
        }
    }

    /// The example's crank (16.2 mm, 35 mm between bearings, eccentrics 10.5 mm apart): shear
    /// adds about half to the bending compliance, and the cross term is about 0.77 of the
    /// direct one (0.89 in bending alone).
    #[test]
    fn the_example_crank_shears_and_couples() {
        let beam = CrankBeam {
            diameter: 16.2e-3,
            span: 35e-3,
            eccentric_spacing: 10.5e-3,
        };
        let (direct, cross) = beam.flexibility();
        let bending = 0.01225f64.powi(2) * 0.02275f64.powi(2)
            / (3.0 * STEEL_YOUNGS_MODULUS * PI * 16.2e-3f64.powi(4) / 64.0 * 35e-3);
        assert!(
            (1.0 / bending / 960e6 - 1.0).abs() < 1e-3,
            "{}",
            1.0 / bending
        );
        let shear_part = direct / bending - 1.0;
        assert!((shear_part - 0.51).abs() < 0.01, "{shear_part}");
        assert!((cross / direct - 0.773).abs() < 0.002, "{}", cross / direct);
    }
}
