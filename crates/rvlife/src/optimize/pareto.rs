//! The multi-goal search (docs/model.md section 19.3): NSGA-II (Deb, Pratap, Agarwal and
//! Meyarivan, IEEE Trans. Evol. Comput. 6(2), 2002; the moors crate's `Nsga2`) over the unit
//! box, simulated binary crossover and Gaussian mutation, the constraints by feasibility
//! first (a feasible candidate beats an infeasible one, two infeasible ones by their total
//! violation). The front reported is that of every candidate evaluated
//! ([`super::point::pareto_front`]), not only the last population's.

use std::cell::RefCell;
use std::collections::HashMap;

use moors::{
    CloseDuplicatesCleaner, ConstraintsFn, GaussianMutation, Nsga2Builder, RandomSamplingFloat,
    SimulatedBinaryCrossover,
};
use ndarray::Array2;

use super::point::{Point, Settings};
use super::search::{bits, unseen, Evaluate};
use crate::error::{Error, Result};

/// What a population's goals and constraints were, by the genes' bits.
struct Memory<'a, 'f> {
    evaluate: &'a mut Evaluate<'f>,
    seen: HashMap<Vec<u64>, Point>,
    generation: usize,
    stopped: bool,
    goals: usize,
    constraints: usize,
}

impl Memory<'_, '_> {
    /// Evaluates the rows of `genes` not seen yet together (a generation, which a cluster
    /// evaluates at once), recording each; [`Self::point`] then finds them.
    fn prefetch(&mut self, genes: &Array2<f64>) {
        if self.stopped {
            return;
        }
        // Keyed by the genes, evaluated on the box (as `point` does).
        let fresh = unseen(
            genes.rows().into_iter().map(|row| {
                let genes = row.to_vec();
                (
                    bits(&genes),
                    genes.iter().map(|v| v.clamp(0.0, 1.0)).collect(),
                )
            }),
            &self.seen,
        );
        let phase = format!("generation {}", self.generation);
        let points: Vec<Vec<f64>> = fresh.iter().map(|f| f.1.clone()).collect();
        let got = self.evaluate.many(&points, &phase);
        for ((key, _), p) in fresh.into_iter().zip(got) {
            match p {
                Some(p) => {
                    self.seen.insert(key, self.finite(p));
                }
                None => {
                    self.stopped = true;
                    return;
                }
            }
        }
    }

    /// `p` with non-finite objectives (a failed candidate's) set to the worst merit.
    fn finite(&self, mut p: Point) -> Point {
        for o in &mut p.objectives {
            if !o.is_finite() {
                *o = super::search::FAILED_MERIT;
            }
        }
        p
    }

    /// The point of `genes` (evaluated once); a worst, infeasible point once the evaluations
    /// are spent.
    fn point(&mut self, genes: &[f64]) -> Point {
        let key = bits(genes);
        if let Some(p) = self.seen.get(&key) {
            return p.clone();
        }
        let worst = Point {
            objectives: vec![super::search::FAILED_MERIT; self.goals],
            violations: vec![1.0; self.constraints],
        };
        if self.stopped {
            return worst;
        }
        let phase = format!("generation {}", self.generation);
        let clamped: Vec<f64> = genes.iter().map(|v| v.clamp(0.0, 1.0)).collect();
        let p = match self.evaluate.one(&clamped, &phase) {
            Some(p) => self.finite(p),
            None => {
                self.stopped = true;
                worst
            }
        };
        self.seen.insert(key, p.clone());
        p
    }
}

/// The constraints of the population (what [`Memory`] holds for its genes), and the box.
struct Constraints<'m, 'a, 'f>(&'m RefCell<Memory<'a, 'f>>);

impl ConstraintsFn for Constraints<'_, '_, '_> {
    type Dim = ndarray::Ix2;
    fn call(&self, genes: &Array2<f64>) -> Array2<f64> {
        let mut m = self.0.borrow_mut();
        let k = m.constraints;
        let mut out = Array2::zeros((genes.nrows(), k));
        for (i, row) in genes.rows().into_iter().enumerate() {
            let p = m.point(&row.to_vec());
            for (j, v) in p.violations.iter().enumerate() {
                out[[i, j]] = *v;
            }
        }
        out
    }
    fn lower_bound(&self) -> Option<f64> {
        Some(0.0)
    }
    fn upper_bound(&self) -> Option<f64> {
        Some(1.0)
    }
}

/// The population size of a search of `evaluations`: a sixth of them, even, in `[8, 40]`.
pub fn population(evaluations: usize) -> usize {
    ((evaluations / 6).clamp(8, 40) / 2) * 2
}

/// Runs NSGA-II over `[0, 1]^dim` for `goals` objectives and `constraints` constraints with
/// at most about `settings.evaluations` calls of `evaluate` ([`population`] per generation,
/// seeded by `settings.seed`). The candidates are what `evaluate` records.
///
/// # Errors
/// [`Error::Numerical`] if the algorithm refuses its set-up or fails.
pub fn nsga2(
    dim: usize,
    goals: usize,
    constraints: usize,
    settings: &Settings,
    evaluate: &mut Evaluate<'_>,
) -> Result<()> {
    let pop = population(settings.evaluations);
    let generations = (settings.evaluations.saturating_sub(pop) / pop).max(1);
    let memory = RefCell::new(Memory {
        evaluate,
        seen: HashMap::new(),
        generation: 0,
        stopped: false,
        goals,
        constraints,
    });
    let fitness = |genes: &Array2<f64>| -> Array2<f64> {
        let mut m = memory.borrow_mut();
        m.prefetch(genes);
        let mut out = Array2::zeros((genes.nrows(), goals));
        for (i, row) in genes.rows().into_iter().enumerate() {
            let p = m.point(&row.to_vec());
            for (j, v) in p.objectives.iter().enumerate() {
                out[[i, j]] = *v;
            }
        }
        m.generation += 1;
        out
    };
    let fail = |e: String| Error::numerical("optimize (NSGA-II)", e);
    let mut algorithm = Nsga2Builder::default()
        .sampler(RandomSamplingFloat::new(0.0, 1.0))
        .crossover(SimulatedBinaryCrossover::new(15.0))
        .mutation(GaussianMutation::new(1.0 / dim as f64, 0.1))
        .duplicates_cleaner(CloseDuplicatesCleaner::new(1e-9))
        .fitness_fn(fitness)
        .constraints_fn(Constraints(&memory))
        .num_vars(dim)
        .population_size(pop)
        .num_offsprings(pop)
        .num_iterations(generations)
        .mutation_rate(1.0)
        .crossover_rate(0.9)
        .keep_infeasible(true)
        .seed(settings.seed)
        .build()
        .map_err(|e| fail(e.to_string()))?;
    algorithm.run().map_err(|e| fail(e.to_string()))?;
    Ok(())
}
