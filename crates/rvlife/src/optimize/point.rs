//! What a search ranks: a point's objectives and constraint violations, the merit of the
//! single-goal search, the Pareto filter; and the search's settings (docs/model.md section 19).

/// Settings of a search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Most candidate studies, `[2, MAX_EVALUATIONS]` (default 150).
    pub evaluations: usize,
    /// Seed of the search's random draws (the Latin hypercube, NSGA-II's operators).
    pub seed: u64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            evaluations: 150,
            seed: 1,
        }
    }
}

/// One point of a search in the unit box: what it minimises and by how much it violates each
/// constraint (relative to the limit's size; `<= 0` satisfied). Serialised (a cluster's
/// workers send it back) with an infinite objective, a failed candidate's, as `null`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Point {
    /// The values to minimise, one per goal.
    #[serde(with = "unbounded")]
    pub objectives: Vec<f64>,
    /// The constraints' violations, one per constraint (`<= 0`: satisfied).
    pub violations: Vec<f64>,
}

impl Point {
    /// Whether every constraint holds.
    pub fn feasible(&self) -> bool {
        self.violations.iter().all(|v| *v <= 0.0)
    }

    /// The single-goal merit: the first objective plus [`PENALTY`] times the sum of the
    /// violations (the search ranks an infeasible point behind feasible ones unless it
    /// violates by less than about 1/[`PENALTY`] of the objective's spread).
    pub fn merit(&self) -> f64 {
        self.objectives[0] + PENALTY * self.violations.iter().map(|v| v.max(0.0)).sum::<f64>()
    }
}

/// Weight of a constraint's relative violation in the single-goal merit ([`Point::merit`]):
/// the objectives are of order 1 (the life's score, docs/model.md section 19), so a 1 %
/// violation costs as much as the whole spread of lives.
pub const PENALTY: f64 = 100.0;

/// The indices of the feasible points of `points` that no other feasible point dominates (no
/// worse in every objective, better in one): the Pareto front, in the order given.
pub fn pareto_front(points: &[&Point]) -> Vec<usize> {
    let dominates = |a: &Point, b: &Point| {
        a.objectives.iter().zip(&b.objectives).all(|(x, y)| x <= y)
            && a.objectives.iter().zip(&b.objectives).any(|(x, y)| x < y)
    };
    (0..points.len())
        .filter(|&i| {
            points[i].feasible()
                && points[i].objectives.iter().all(|x| x.is_finite())
                && !(0..points.len())
                    .any(|j| j != i && points[j].feasible() && dominates(points[j], points[i]))
        })
        .collect()
}

/// Objectives on the wire: `+inf` (a failed candidate's) as `null`, which JSON has no number
/// for.
mod unbounded {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        v.iter()
            .map(|x| x.is_finite().then_some(*x))
            .collect::<Vec<Option<f64>>>()
            .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Ok(Vec::<Option<f64>>::deserialize(d)?
            .into_iter()
            .map(|x| x.unwrap_or(f64::INFINITY))
            .collect())
    }
}
