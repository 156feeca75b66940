//! Modal reduction of the FE disc for the multibody model: the disc as a flexible body.
//!
//! The disc frame is tied to the crank bores (their spiders' translations held, as in the
//! quasi-static model of [`super`]): the bores are the interface with the crank bearings and
//! carry the rigid-body motion of the multibody disc (centre and angle). The elastic field
//! relative to that frame is
//!
//! `u = sum_i phi_i eta_i + (K^-1 - sum_i phi_i phi_i^T / omega_i^2) f`
//!
//! - `phi_i`, `omega_i`: the fixed-interface normal modes of the disc (bores held) up to a
//!   cut-off frequency, mass-normalised (`phi^T M phi = 1`): the Craig-Bampton fixed-interface
//!   modes (Craig & Bampton, AIAA J. 6, 1968; Craig & Kurdila, *Fundamentals of Structural
//!   Dynamics*, 2006, ch. 18), with modal coordinates `eta_i`;
//! - the second term: the residual flexibility of the modes left out at the load stations
//!   (MacNeal, Comput. Struct. 1, 1971; Rubin, AIAA J. 13, 1975): the static response of the
//!   truncated modes to the pin forces `f`. The pin contacts are force interfaces, so the load
//!   stations enter as *attachment modes* (the station compliance `C` of [`super::DiscModel`]
//!   already condensed there) rather than as the displacement-type constraint modes of a
//!   Craig-Bampton interface: a pin force acts on the stations' patches, which then need no
//!   mass and add no stiff station modes to the integration.
//!
//! At a load station (or a contact point interpolated between stations) the normal approach is
//! `y_j = sum_i b_i(t_j) eta_i + sum_k R_jk F_k`, `b_i(t) = s(t) . phi_i` (the station load
//! vector `s` times the mode), `R = C - sum_i b_i b_i^T / omega_i^2`. Quasi-statically
//! (`eta_i = b_i . F / omega_i^2`) this is exactly `C F`: the static flexible analysis is the
//! limit of the dynamic one with any number of modes.
//!
//! Modal equations, in the disc frame: `eta_i'' + 2 zeta omega_i eta_i' + omega_i^2 eta_i =
//! sum_j b_i(t_j) F_j - L_i . A`, with `A` the rigid-body acceleration of the frame (centre,
//! angle; in the frame's axes) and `L_i = phi_i^T M r` the modes' participation factors; the
//! rigid body carries the reaction `L^T eta''`. Centrifugal and Coriolis terms of the elastic
//! field (the disc turns at about the output speed, a few rad/s, against modal frequencies of
//! 1e5 rad/s) are left out.
//!
//! Modes come from subspace iteration with the factorised stiffness (Bathe, *Finite Element
//! Procedures*, 2nd ed., 2014, section 11.6): `X <- K^-1 M X`, Rayleigh-Ritz on the subspace
//! (dense symmetric eigenproblem, nalgebra), until the wanted eigenvalues change by less than
//! `EIGEN_TOLERANCE`.

use faer::sparse::SparseColMat;
use faer::Mat;
use nalgebra::{DMatrix, SymmetricEigen};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::DiscModel;
use crate::error::{Error, Result};

/// Relative change of the wanted eigenvalues between two subspace iterations at convergence.
pub(crate) const EIGEN_TOLERANCE: f64 = 1e-10;

/// Settings of the modal reduction (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalSettings {
    /// Cut-off frequency, Hz: every fixed-interface mode below it is kept.
    pub cutoff_hz: f64,
    /// Modal damping ratio of every mode.
    pub damping_ratio: f64,
    /// Largest number of modes (a cut-off that needs more is refused).
    pub max_modes: usize,
    /// Disc density, kg/m^3.
    pub density: f64,
}

/// The disc as a flexible body: fixed-interface modes with their station amplitudes and
/// participation factors, and the station compliance of the FE model.
#[derive(Debug)]
pub struct ModalDisc<'a> {
    /// The FE disc condensed onto its load stations.
    pub disc: &'a DiscModel,
    /// Natural frequencies of the kept modes, rad/s, ascending.
    pub omega: Vec<f64>,
    /// Mode amplitudes at the stations, m kg^-1/2 (`stations x modes`, row-major): the
    /// station's load vector (a unit pin force) times the mass-normalised mode.
    pub station_modes: Vec<f64>,
    /// Participation factors `[x, y, rotation]` of every mode (kg^1/2 m per m, kg^1/2 m per
    /// rad): the modal inertia force per unit acceleration of the frame.
    pub participation: Vec<[f64; 3]>,
    /// Modal damping ratio.
    pub damping_ratio: f64,
    /// Frequency of the first mode left out, rad/s (the subspace's next Ritz value).
    pub first_omitted: f64,
    /// Mass (kg) and polar inertia about the disc centre (kg m^2) of the meshed disc.
    pub fe_inertia: (f64, f64),
}

impl<'a> ModalDisc<'a> {
    /// Reduces `disc`: every fixed-interface mode below `settings.cutoff_hz`.
    ///
    /// # Errors
    /// [`Error::Invalid`] (key `dynamics.flexible.cutoff_khz`) if more than
    /// `settings.max_modes` modes lie below the cut-off; [`Error::Numerical`] if the subspace
    /// iteration does not converge or the mass is not positive definite.
    pub fn build(disc: &'a DiscModel, settings: &ModalSettings) -> Result<ModalDisc<'a>> {
        let fe = &disc.fe;
        let mass = fe.mass_matrix(settings.density)?;
        let cutoff = std::f64::consts::TAU * settings.cutoff_hz;
        let mut wanted = 8usize.min(settings.max_modes);
        let mut start: Option<Mat<f64>> = None;
        let (omega2, modes, next) = loop {
            let (lambda, x) = lowest_modes(disc, &mass, wanted, cutoff * cutoff, start.as_ref())?;
            let below = lambda[..wanted]
                .iter()
                .take_while(|l| l.sqrt() < cutoff)
                .count();
            if below < wanted {
                break (lambda[..below].to_vec(), x, lambda[below].sqrt());
            }
            if wanted >= settings.max_modes {
                return Err(Error::invalid(
                    "dynamics.flexible.cutoff_khz",
                    settings.cutoff_hz * 1e-3,
                    format!(
                        "keeps more than {} modes of the disc (the {}th is at {:.1} kHz); \
                         lower the cut-off",
                        settings.max_modes,
                        wanted,
                        lambda[wanted - 1].sqrt() / std::f64::consts::TAU * 1e-3
                    ),
                ));
            }
            wanted = (2 * wanted).min(settings.max_modes);
            start = Some(x);
        };
        let m = omega2.len();
        let ns = disc.stations();
        let mut station_modes = vec![0.0; ns * m];
        for (g, load) in disc.station_loads.iter().enumerate() {
            for i in 0..m {
                station_modes[g * m + i] = load.iter().map(|&(q, v)| v * modes[(q, i)]).sum();
            }
        }
        let (rigid, fe_mass, fe_polar) = fe.rigid_inertia_loads(settings.density)?;
        let participation = (0..m)
            .map(|i| {
                std::array::from_fn(|k| {
                    rigid[k]
                        .iter()
                        .enumerate()
                        .map(|(q, v)| v * modes[(q, i)])
                        .sum()
                })
            })
            .collect();
        Ok(ModalDisc {
            disc,
            omega: omega2.iter().map(|l| l.sqrt()).collect(),
            station_modes,
            participation,
            damping_ratio: settings.damping_ratio,
            first_omitted: next,
            fe_inertia: (fe_mass, fe_polar),
        })
    }

    /// Number of modes kept.
    pub fn modes(&self) -> usize {
        self.omega.len()
    }

    /// Mode amplitudes `b_i(t)` (m kg^-1/2, one per mode, into `out`) at profile parameter `t`
    /// (rad), interpolated between stations with the compliance's weights
    /// ([`DiscModel::weights`]).
    pub(crate) fn amplitudes(&self, t: f64, out: &mut [f64]) {
        let m = self.modes();
        out[..m].iter_mut().for_each(|v| *v = 0.0);
        for (g, w) in self.disc.weights(t) {
            let row = &self.station_modes[g * m..(g + 1) * m];
            for (o, b) in out.iter_mut().zip(row) {
                *o += w * b;
            }
        }
    }

    /// Residual compliance (m/N, `n x n` row-major) between contacts at profile parameters
    /// `ts` whose mode amplitudes are the rows of `amps` (`n x modes`):
    /// `R = C(ts) - sum_i b_i b_i^T / omega_i^2`.
    pub(crate) fn residual_compliance(&self, ts: &[f64], amps: &[f64]) -> Vec<f64> {
        let n = ts.len();
        let m = self.modes();
        let mut r = self.disc.compliance_at(ts);
        for a in 0..n {
            for b in 0..=a {
                let s: f64 = (0..m)
                    .map(|i| amps[a * m + i] * amps[b * m + i] / (self.omega[i] * self.omega[i]))
                    .sum();
                r[a * n + b] -= s;
                if a != b {
                    r[b * n + a] -= s;
                }
            }
        }
        r
    }
}

/// `y = M x` for the columns of `x`.
fn mass_times(mass: &SparseColMat<usize, f64>, x: &Mat<f64>) -> Mat<f64> {
    let mut y = Mat::<f64>::zeros(x.nrows(), x.ncols());
    faer::sparse::linalg::matmul::sparse_dense_matmul(
        y.as_mut(),
        faer::Accum::Replace,
        mass.as_ref(),
        x.as_ref(),
        1.0,
        faer::get_global_parallelism(),
    );
    super::plane::clear_upper_simd();
    y
}

/// `a^T b` (columns of two `n x q` matrices), symmetrised, as a dense nalgebra matrix.
fn gram(a: &Mat<f64>, b: &Mat<f64>) -> DMatrix<f64> {
    let g = a.transpose() * b;
    super::plane::clear_upper_simd();
    let q = a.ncols();
    DMatrix::from_fn(q, q, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]))
}

/// The lowest eigenpairs `K phi = lambda M phi` of the disc (bores held), by subspace iteration
/// on `max(2 wanted, wanted + 8)` vectors (Bathe's choice); eigenvalues (rad^2/s^2) of the whole
/// subspace, ascending, and the mass-normalised vectors as columns. Converged when the first
/// `wanted` eigenvalues, or those below `cutoff2` (rad^2/s^2) and the first above it, change by
/// less than [`EIGEN_TOLERANCE`]. `start` (vectors of an earlier, smaller run) fills the first
/// columns of the start subspace; the rest are random.
fn lowest_modes(
    disc: &DiscModel,
    mass: &SparseColMat<usize, f64>,
    wanted: usize,
    cutoff2: f64,
    start: Option<&Mat<f64>>,
) -> Result<(Vec<f64>, Mat<f64>)> {
    let fe = &disc.fe;
    let n = fe.equations();
    let q = (2 * wanted).max(wanted + 8).min(n);
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_d15c);
    let mut x = Mat::<f64>::from_fn(n, q, |i, c| match start {
        Some(s) if c < s.ncols() => s[(i, c)],
        _ => rng.random_range(-1.0..1.0),
    });
    let mut prev = vec![f64::INFINITY; q];
    for _ in 0..200 {
        let y = mass_times(mass, &x);
        let mut xb = y.clone();
        fe.solve_reduced(&mut xb);
        // Projected stiffness xb^T K xb = xb^T y, projected mass xb^T M xb.
        let kr = gram(&xb, &y);
        let mxb = mass_times(mass, &xb);
        let mr = gram(&xb, &mxb);
        let chol = mr.clone().cholesky().ok_or_else(|| {
            Error::numerical("disc modes", "projected mass not positive definite")
        })?;
        let l = chol.l();
        let linv = l.clone().try_inverse().ok_or_else(|| {
            Error::numerical("disc modes", "projected mass not positive definite")
        })?;
        let a = &linv * &kr * linv.transpose();
        let a = (&a + a.transpose()) * 0.5;
        let eig = SymmetricEigen::new(a);
        let mut order: Vec<usize> = (0..q).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        let lambda: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
        // Ritz vectors: X = xb L^-T V (M-orthonormal).
        let coef = linv.transpose() * &eig.eigenvectors;
        let coef = Mat::<f64>::from_fn(q, q, |k, c| coef[(k, order[c])]);
        x = &xb * &coef;
        super::plane::clear_upper_simd();
        let check = (lambda.iter().take_while(|l| **l < cutoff2).count() + 1).min(wanted);
        let converged = lambda
            .iter()
            .zip(&prev)
            .take(check)
            .all(|(l, p)| (l - p).abs() <= EIGEN_TOLERANCE * l.abs());
        prev = lambda;
        if converged {
            if prev.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
                return Err(Error::numerical(
                    "disc modes",
                    "a non-positive eigenvalue: the disc is not held",
                ));
            }
            return Ok((prev, x));
        }
    }
    Err(Error::numerical(
        "disc modes",
        format!("the subspace iteration for {wanted} modes did not converge in 200 iterations"),
    ))
}
