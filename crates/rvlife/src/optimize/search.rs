//! The single-goal search (docs/model.md section 19.2): a Latin hypercube over the unit box
//! (with the base design); CMA-ES (Hansen's covariance matrix adaptation, the cmaes crate)
//! from the best point with half of the evaluations left, which learns the
//! directions of narrow valleys (the equidistant and offset modifications together); then a
//! compass search (a generalised pattern search: Kolda, Lewis and Torczon, SIAM Review 45(3),
//! 2003) with at most half of the rest, each key moved either way, an improving move followed
//! with the step doubled, the step halved where no move improves, down to 1e-4 of the ranges, which walks onto a wall of refused candidates or
//! a face of the box along a key, where a simplex stalls; then a Nelder-Mead polish (argmin's
//! `NelderMead`) from the best with the rest, restarted there with a simplex half as large each
//! time it settles.
//!
//! Both move in `R^d`: a point outside the box is evaluated at its projection on the box with
//! [`BOX_PENALTY`] times its distance from it added, which brings the search back. A candidate
//! the config refuses (a wall inside the box) ranks last; CMA-ES ranks its points, so a wall
//! does not distort its steps.
//! Points are ranked by [`Point::merit`]; a failed candidate counts as [`FAILED_MERIT`].

use std::cell::RefCell;
use std::collections::HashMap;

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::point::{Point, Settings};

/// Merit of a point outside the box, per unit distance from it (merits are of order 1).
pub const BOX_PENALTY: f64 = 10.0;

/// Merit of a candidate whose evaluation failed (worse than any design's).
pub const FAILED_MERIT: f64 = 1e6;

/// CMA-ES's initial step size, as a fraction of each range.
const CMA_STEP: f64 = 0.2;

/// CMA-ES's tolerance on the spread of its points, as a fraction of each range.
const CMA_TOL_X: f64 = 3e-3;

/// The polish's first simplex edge, as a fraction of each range.
const FIRST_STEP: f64 = 0.05;

/// The simplex's edge below which the polish has converged.
const LAST_STEP: f64 = 1e-3;

/// The compass search's first step, as a fraction of each range.
const COMPASS_STEP: f64 = 0.02;

/// The compass search's step below which the search has converged.
const COMPASS_LAST_STEP: f64 = 1e-4;

/// Spread of the simplex's merits at which one Nelder-Mead run ends.
const SD_TOLERANCE: f64 = 1e-6;

/// Evaluates points of the unit box in a named phase: one at a time, or several the search
/// asks for together (the Latin hypercube, a generation of NSGA-II), which a cluster can
/// evaluate at once. `None`: no more evaluations (the budget is spent or the user stopped the
/// search). A closure `FnMut(&[f64], &str) -> Option<Point>` is one, evaluating a batch in
/// order.
pub trait Evaluator {
    /// The point at `x`.
    fn one(&mut self, x: &[f64], phase: &str) -> Option<Point>;
    /// The points at `xs` (distinct), in order; `None` from the first one not evaluated on.
    fn many(&mut self, xs: &[Vec<f64>], phase: &str) -> Vec<Option<Point>> {
        let mut out = Vec::with_capacity(xs.len());
        for x in xs {
            let p = self.one(x, phase);
            let end = p.is_none();
            out.push(p);
            if end {
                break;
            }
        }
        out.resize(xs.len(), None);
        out
    }
}

impl<F: FnMut(&[f64], &str) -> Option<Point>> Evaluator for F {
    fn one(&mut self, x: &[f64], phase: &str) -> Option<Point> {
        self(x, phase)
    }
}

/// The evaluator a search is given.
pub type Evaluate<'a> = dyn Evaluator + 'a;

/// The bits of `x`, by which the searches remember the points they evaluated.
pub(super) fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Those of `items` (`(key, point)`) whose key `seen` does not hold, each key once, in order:
/// what a batch has to evaluate.
pub(super) fn unseen<V>(
    items: impl IntoIterator<Item = (Vec<u64>, Vec<f64>)>,
    seen: &HashMap<Vec<u64>, V>,
) -> Vec<(Vec<u64>, Vec<f64>)> {
    let mut fresh: Vec<(Vec<u64>, Vec<f64>)> = Vec::new();
    for (key, x) in items {
        if !seen.contains_key(&key) && !fresh.iter().any(|f| f.0 == key) {
            fresh.push((key, x));
        }
    }
    fresh
}

/// Points of the Latin hypercube of a `dim`-key search with `evaluations` in all: `4 + 2 dim`,
/// at most a third of the evaluations (at least 2).
pub fn hypercube_points(dim: usize, evaluations: usize) -> usize {
    (4 + 2 * dim).min(evaluations / 3).max(2)
}

/// A Latin hypercube of `n` points in `[0, 1]^dim` from `rng`: each coordinate's `n` values
/// one in each of `n` equal slices, in random order.
fn hypercube(dim: usize, n: usize, rng: &mut ChaCha8Rng) -> Vec<Vec<f64>> {
    let mut pts = vec![vec![0.0; dim]; n];
    for k in 0..dim {
        let mut slots: Vec<usize> = (0..n).collect();
        slots.shuffle(rng);
        for (p, s) in pts.iter_mut().zip(slots) {
            p[k] = (s as f64 + rng.random::<f64>()) / n as f64;
        }
    }
    pts
}

/// The search's memory: every merit evaluated (by the point's bits, projected), the best.
struct Memory<'a, 'f> {
    evaluate: &'a mut Evaluate<'f>,
    seen: HashMap<Vec<u64>, f64>,
    best: Option<(f64, Vec<f64>)>,
    stopped: bool,
    phase: String,
    /// Most points of the phase running (new points beyond it are refused).
    limit: usize,
}

impl Memory<'_, '_> {
    /// The merit of `x` (projected on the box, [`BOX_PENALTY`] for the distance); `None` once
    /// the evaluations are spent.
    fn merit(&mut self, x: &[f64]) -> Option<f64> {
        let p: Vec<f64> = x.iter().map(|v| v.clamp(0.0, 1.0)).collect();
        let out = x
            .iter()
            .zip(&p)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        let key = bits(&p);
        let m = match self.seen.get(&key) {
            Some(m) => *m,
            None => {
                if self.stopped || self.seen.len() >= self.limit {
                    return None;
                }
                let Some(point) = self.evaluate.one(&p, &self.phase) else {
                    self.stopped = true;
                    return None;
                };
                self.record(key, &p, &point)
            }
        };
        Some(m + BOX_PENALTY * out)
    }

    /// Records the point at `p` (in the box, `key` its bits); its merit.
    fn record(&mut self, key: Vec<u64>, p: &[f64], point: &Point) -> f64 {
        let m = point.merit();
        let m = if m.is_finite() { m } else { FAILED_MERIT };
        self.seen.insert(key, m);
        if self.best.as_ref().is_none_or(|b| m < b.0) {
            self.best = Some((m, p.to_vec()));
        }
        m
    }

    /// Evaluates together those of `xs` (in the box) not seen yet, as many as the phase
    /// allows, in order: [`Self::merit`] then finds them recorded.
    fn prefetch(&mut self, xs: &[Vec<f64>]) {
        let mut fresh = unseen(xs.iter().map(|x| (bits(x), x.clone())), &self.seen);
        fresh.truncate(self.limit.saturating_sub(self.seen.len()));
        if self.stopped || fresh.is_empty() {
            return;
        }
        let points: Vec<Vec<f64>> = fresh.iter().map(|f| f.1.clone()).collect();
        let got = self.evaluate.many(&points, &self.phase);
        for ((key, p), point) in fresh.into_iter().zip(got) {
            match point {
                Some(point) => {
                    self.record(key, &p, &point);
                }
                None => {
                    self.stopped = true;
                    return;
                }
            }
        }
    }
}

/// argmin's view of the memory.
struct Cost<'m, 'a, 'f>(&'m RefCell<Memory<'a, 'f>>);

impl CostFunction for Cost<'_, '_, '_> {
    type Param = Vec<f64>;
    type Output = f64;
    /// Once the evaluations are spent, the worst merit without an evaluation: argmin's
    /// Nelder-Mead unwraps the costs of its first simplex, so an error there would panic; the
    /// run then ends within its iteration limit, evaluating nothing more.
    fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.0.borrow_mut().merit(x).unwrap_or(FAILED_MERIT))
    }
}

/// `x` with key `k` moved by `by` onto the box (`None` where that does not move it: `x` on the
/// face already).
fn moved(x: &[f64], k: usize, by: f64) -> Option<Vec<f64>> {
    let mut y = x.to_vec();
    y[k] = (y[k] + by).clamp(0.0, 1.0);
    (y[k] != x[k]).then_some(y)
}

/// Minimises [`Point::merit`] over `[0, 1]^dim` with at most `settings.evaluations` calls of
/// `evaluate` (module docs): `start` (if given) and the Latin hypercube of
/// [`hypercube_points`] points (seeded by `settings.seed`), then Nelder-Mead from the best.
/// Returns the best point and its merit (`None` if nothing was evaluated).
pub fn minimise(
    dim: usize,
    settings: &Settings,
    start: Option<&[f64]>,
    evaluate: &mut Evaluate<'_>,
) -> Option<(Vec<f64>, f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
    let memory = RefCell::new(Memory {
        evaluate,
        seen: HashMap::new(),
        best: None,
        stopped: false,
        phase: "start".into(),
        limit: usize::MAX,
    });
    if let Some(s) = start {
        let _ = memory.borrow_mut().merit(s);
    }
    memory.borrow_mut().phase = "hypercube".into();
    let points = hypercube(dim, hypercube_points(dim, settings.evaluations), &mut rng);
    memory.borrow_mut().prefetch(&points);
    for p in points {
        if memory.borrow_mut().merit(&p).is_none() {
            break;
        }
    }
    let spent = |m: &RefCell<Memory>| m.borrow().seen.len();
    // CMA-ES from the best point so far, with half of the evaluations left.
    {
        let left = settings.evaluations.saturating_sub(spent(&memory));
        let cma_budget = left - left / 2;
        let best = memory.borrow().best.clone();
        if let Some((_, best)) = best.filter(|_| cma_budget >= 2 * (4 + dim)) {
            memory.borrow_mut().phase = "cma-es".into();
            let objective = |x: &cmaes::DVector<f64>| -> f64 {
                memory
                    .borrow_mut()
                    .merit(x.as_slice())
                    .unwrap_or(FAILED_MERIT)
            };
            let built = cmaes::CMAESOptions::new(best, CMA_STEP)
                .max_function_evals(cma_budget)
                .tol_x(CMA_TOL_X)
                .seed(settings.seed)
                .build(objective);
            if let Ok(mut cma) = built {
                while !memory.borrow().stopped && cma.next().is_none() {}
            }
        }
    }
    // A compass search from the best: each key moved by the step either way (onto the box's
    // face where the step would leave it), the first move that improves kept and followed
    // with the step doubled while it improves, the step halved where no move improves; it
    // walks onto a wall of refused candidates or a face of the box along a key, where the
    // simplex stalls; with half of the evaluations left at most.
    let compass_end = spent(&memory) + settings.evaluations.saturating_sub(spent(&memory)) / 2;
    memory.borrow_mut().phase = "compass".into();
    memory.borrow_mut().limit = compass_end;
    let mut step = COMPASS_STEP;
    while !memory.borrow().stopped && step >= COMPASS_LAST_STEP && spent(&memory) < compass_end {
        let Some((m0, x0)) = memory.borrow().best.clone() else {
            break;
        };
        let mut improved = false;
        'keys: for k in 0..dim {
            for sign in [1.0, -1.0] {
                let Some(y) = moved(&x0, k, sign * step) else {
                    continue;
                };
                let m = memory.borrow_mut().merit(&y);
                match m {
                    Some(m) if m < m0 => {
                        // On along the improving direction, the step doubled while it improves.
                        let (mut at, mut best, mut s) = (y, m, step);
                        loop {
                            s *= 2.0;
                            let Some(z) = moved(&at, k, sign * s) else {
                                break;
                            };
                            let mz = memory.borrow_mut().merit(&z);
                            match mz {
                                Some(mz) if mz < best => (at, best) = (z, mz),
                                _ => break,
                            }
                        }
                        improved = true;
                        break 'keys;
                    }
                    Some(_) => {}
                    None => break 'keys,
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    // Nelder-Mead from the best with the rest, restarted with a simplex half as large each
    // time it settles.
    {
        memory.borrow_mut().limit = usize::MAX;
        let mut step = FIRST_STEP;
        let mut round = 0;
        while !memory.borrow().stopped && step >= LAST_STEP && spent(&memory) < settings.evaluations
        {
            let Some((_, best)) = memory.borrow().best.clone() else {
                break;
            };
            round += 1;
            memory.borrow_mut().phase = format!("simplex {round}");
            let mut simplex = vec![best.clone()];
            for k in 0..dim {
                let mut v = best.clone();
                v[k] += if best[k] + step <= 1.0 { step } else { -step };
                simplex.push(v);
            }
            let solver = NelderMead::new(simplex)
                .with_sd_tolerance(SD_TOLERANCE)
                .expect("a non-negative tolerance");
            // Ends when the simplex settles or after 50 d steps (once the evaluations are spent
            // its costs are the worst merit and nothing more is evaluated).
            let _ = Executor::new(Cost(&memory), solver)
                .configure(|s| s.max_iters(50 * dim as u64))
                .run();
            step *= 0.5;
        }
    }
    memory.into_inner().best.map(|(m, p)| (p, m))
}
