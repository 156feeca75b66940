//! How the reducer's structural forces evaluate its crank bearings
//! ([`crate::reducer::Reducer::structural_forces_with`]): by their law (a roller bearing's from
//! its table, docs/model.md section 5.9), recording each bearing's state, or linearised at a
//! recorded state.

use nalgebra::Matrix2;

use super::bearing::RadialBearing;
use crate::geometry::Vec2;

/// A bearing's state recorded by [`BearingEval::Record`]: relative position (m), static force
/// (N) and stiffness matrix (N/m).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frozen {
    r: Vec2,
    f: Vec2,
    k: Matrix2<f64>,
}

impl Frozen {
    /// The recorded static force, N.
    pub(crate) fn force(&self) -> Vec2 {
        self.f
    }
}

/// How [`crate::reducer::Reducer::structural_forces_with`] evaluates the bearings: by their law
/// ([`RadialBearing::force`]), by it while recording each bearing's state (in call order), or
/// each bearing's law linearised at a recorded state (for the structural stiffness by
/// differences of the forces: exact kinematics, no look-ups).
pub(crate) enum BearingEval<'a> {
    /// By the law ([`RadialBearing::force`]).
    Exact,
    /// Records each bearing's state; with `true` its stiffness floored
    /// ([`RadialBearing::stiffness_matrix_floored`]).
    Record(&'a mut Vec<Frozen>, bool),
    Frozen(&'a [Frozen], usize),
}

impl BearingEval<'_> {
    /// Passes over one bearing in call order without evaluating it (its slot in `Frozen` is
    /// skipped; `Exact` and `Record` keep no order and are left as they are).
    #[inline]
    pub(crate) fn skip(&mut self) {
        match self {
            BearingEval::Frozen(_, next) => *next += 1,
            BearingEval::Exact | BearingEval::Record(..) => {}
        }
    }

    /// The force of `bearing` at `r` with relative velocity `rd`
    /// ([`RadialBearing::force`]), as this evaluation takes it.
    #[inline]
    pub(crate) fn force(&mut self, bearing: &RadialBearing, r: Vec2, rd: Vec2) -> Vec2 {
        match self {
            BearingEval::Exact => bearing.force(r, rd),
            BearingEval::Record(list, floored) => {
                let (f, k) = bearing.force_and_stiffness(r, *floored);
                list.push(Frozen { r, f, k });
                f
            }
            BearingEval::Frozen(list, next) => {
                let s = list[*next];
                *next += 1;
                s.f + s.k * (r - s.r)
            }
        }
    }
}
