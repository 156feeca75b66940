//! The zero-torque state of one crank angle (docs/model.md sections 5.10 and 5.12): the
//! no-load limit each way from the contact problem, or, where the parts interfere, the one
//! preloaded equilibrium that carries zero torque; and the same started from a neighbouring
//! state's ends (a sampled reducer's last stage).

use crate::error::Result;
use crate::statics::{NoLoad, StaticAnalysis, StaticSolution};

/// Negative play (rad) below which the two ways' twists cross (interference, or preload):
/// the first contacts' round-off (an unmodified, unworn disc touches both ways at zero twist).
pub(crate) const PLAY_ROUND_OFF: f64 = 1e-9;

/// A play or a loop's width (rad) at its round-off floor: a negative value within
/// [`PLAY_ROUND_OFF`] of zero is the round-off of two twists that meet (an unmodified disc
/// without play touches both ways at the same twist) and is zero; any other value is kept (a
/// crossing beyond the round-off is interference or preload, which the callers report).
pub(crate) fn at_round_off_floor(width: f64) -> f64 {
    if (-PLAY_ROUND_OFF..0.0).contains(&width) {
        0.0
    } else {
        width
    }
}

/// Torque fraction of the rated torque at which a preloaded stage is solved each way to find
/// its zero-torque twist (docs/model.md section 5.12): the curve through zero torque is smooth
/// there, so the mean of the two twists is the zero-torque one to the curve's second order.
const PRELOAD_PROBE_FRACTION: f64 = 1e-4;

/// Torque fraction of the rated torque from which the solves of a preloaded stage come down
/// to [`PRELOAD_PROBE_FRACTION`] (docs/model.md section 5.12): the measuring torque's order,
/// where the preloaded contacts are settled and the solves converge.
const PRELOAD_DESCENT_FRACTION: f64 = 0.0256;

/// Largest twist (rad) behind zero from which a preloaded stage's solves start each way
/// (docs/model.md section 5.12), about 17 arcmin: a start farther back can reach the next
/// pins' flanks.
const PRELOAD_START_RANGE: f64 = 5e-3;

/// The zero-torque state of one crank angle (docs/model.md section 5.12), index 0 forward
/// (counter-clockwise), 1 reverse.
pub(crate) struct ZeroTorque {
    /// `[psi(0+), psi(0-)]`, rad.
    pub twist: [f64; 2],
    /// The twist each way from which loaded solves start (the rigid first contact, or the
    /// preloaded twist), rad.
    pub start: [f64; 2],
    /// The solutions each way from which the loaded levels start: the no-load limit's
    /// configuration, or with preload the heaviest solves of the descent (`None` without play).
    pub light: [Option<StaticSolution>; 2],
    /// Whether one equilibrium carries zero torque (no play at this crank angle).
    #[cfg_attr(not(test), allow(dead_code))]
    pub preloaded: bool,
    /// With preload, the lightest solves of the descent each way (positive torque first), the
    /// two the zero-torque twist is the secant of (`None` without preload).
    pub lightest: Option<Box<[StaticSolution; 2]>>,
}

/// The no-load limits of one crank angle each way ([`StaticAnalysis::no_load`]) and where the
/// loaded solves of each way start.
struct Limits {
    /// The twist each way from which loaded solves start (rad): the rigid first contact, no
    /// farther behind zero than `PRELOAD_START_RANGE` where the rigid contacts cross.
    start: [f64; 2],
    /// Whether the rigid first contacts cross (part errors or modifications that interfere).
    crossed: bool,
    /// Forward (counter-clockwise) and reverse; the reverse is not looked for where the
    /// forward is preloaded (`NoLoad::Preloaded { least: None }` then).
    limits: [NoLoad; 2],
}

impl Limits {
    /// The limits of crank angle `phi`, each from the rigid first contact of its direction.
    ///
    /// # Errors
    /// Those of the solver.
    fn at(sa: &StaticAnalysis, phi: f64) -> Result<Limits> {
        Self::at_from(sa, phi, &ZeroTorqueStart::default())
    }

    /// [`Limits::at`] with each way's contact problem started from the configuration `warm`
    /// holds for it, where it holds one.
    ///
    /// # Errors
    /// Those of the solver.
    fn at_from(sa: &StaticAnalysis, phi: f64, warm: &ZeroTorqueStart) -> Result<Limits> {
        let forward = sa.first_contact(phi, 1.0)?;
        let reverse = sa.first_contact(phi, -1.0)?;
        let crossed = forward < reverse - PLAY_ROUND_OFF;
        // Each way from behind the rest position: the rigid first contact, which for an
        // interfering disc can lie far beyond it (a pin near the line of centres), so no
        // farther than `PRELOAD_START_RANGE`.
        let start = if crossed {
            [
                forward.max(-PRELOAD_START_RANGE),
                reverse.min(PRELOAD_START_RANGE),
            ]
        } else {
            [forward, reverse]
        };
        // Where the rigid contacts cross, the contact problem starts from between them.
        let from = if crossed {
            let mid = (0.5 * (forward + reverse)).clamp(-PRELOAD_START_RANGE, PRELOAD_START_RANGE);
            [mid, mid]
        } else {
            start
        };
        // Parts that interfere one way are preloaded whatever the other way finds: its limit is
        // looked for only after a limit the first way.
        let up = sa.no_load_from(phi, 1.0, from[0], warm.configs[0].as_deref())?;
        let down = match up {
            NoLoad::Preloaded { .. } => NoLoad::Preloaded { least: None },
            NoLoad::Limit { .. } => {
                sa.no_load_from(phi, -1.0, from[1], warm.configs[1].as_deref())?
            }
        };
        Ok(Limits {
            start,
            crossed,
            limits: [up, down],
        })
    }

    /// Each way's configuration at the end of its contact problem (the limit's, or the one
    /// that violates the constraints least), where it has one.
    fn configs(&self) -> [Option<Vec<f64>>; 2] {
        [0, 1].map(|k| match &self.limits[k] {
            NoLoad::Limit { rest: Some(r), .. } => Some(r.deviations.clone()),
            NoLoad::Preloaded { least: Some(z) } => Some(z.clone()),
            _ => None,
        })
    }

    /// The two limits' twists `[psi(0+), psi(0-)]` (rad) where the reducer has play here: both
    /// ways found a limit, in order, and (where the rigid contacts cross) through the
    /// bearings' play. `None` where it is preloaded.
    fn play(&self) -> Option<[f64; 2]> {
        match &self.limits {
            [NoLoad::Limit {
                twist: up,
                rest: rest_up,
            }, NoLoad::Limit { twist: down, .. }]
                if *up >= down - PLAY_ROUND_OFF && !(self.crossed && rest_up.is_none()) =>
            {
                Some([*up, *down])
            }
            _ => None,
        }
    }
}

/// The zero-torque twist of a preloaded stage (rad): the secant at zero torque between the
/// lightest solves each way, `u` (positive torque) and `d` (negative), their mean where the
/// torques are equal (docs/model.md section 5.12).
fn preload_zero(u: &StaticSolution, d: &StaticSolution) -> f64 {
    let (tu, td) = (u.output_torque.abs(), d.output_torque.abs());
    d.twist + (u.twist - d.twist) * td / (tu + td)
}

/// How many times the twist its tangent stiffness gives the lightest solves each way may lie
/// apart before the interference between them is taken as holding no torque
/// ([`zero_twists_of_interference`]).
const PRELOAD_HOLD_FACTOR: f64 = 3.0;

/// The zero-torque twists `[psi(0+), psi(0-)]` (rad) of a crank angle whose parts interfere
/// in the rigid kinematics, from the lightest solves each way, `u` (positive torque) and `d`
/// (negative), docs/model.md section 5.12. Where the interference holds the discs (a
/// preload), one equilibrium carries zero torque and both twists are the secant between them
/// ([`preload_zero`]): they then lie apart by about the twist their torques give at their
/// tangent stiffness. Where they lie apart by more than [`PRELOAD_HOLD_FACTOR`] times that,
/// the interference is internal (parts over-constrained in the rigid kinematics, a pin on
/// the line of centres whose gap the twist hardly moves, closed by the parts' elastic
/// deformation at forces that carry no output torque) and the stage turns through its play
/// between them: the twists are the lightest solves' own (above the no-load limits by the
/// contacts' approach at [`PRELOAD_PROBE_FRACTION`] of the rated torque: 7e-4 arcmin on the
/// paper's reducer with 5 um in its crank-carrier bearings).
fn zero_twists_of_interference(u: &StaticSolution, d: &StaticSolution) -> [f64; 2] {
    let soft = u.stiffness.min(d.stiffness);
    let elastic = (u.output_torque - d.output_torque) / soft;
    if soft > 0.0 && u.twist - d.twist > PRELOAD_HOLD_FACTOR * elastic {
        [u.twist, d.twist]
    } else {
        let zero = preload_zero(u, d);
        [zero, zero]
    }
}

/// The zero-torque state of crank angle `phi`.
///
/// The two limits are the no-load limits of the contact problem
/// ([`StaticAnalysis::no_load`], docs/model.md section 5.10), each from the rigid first contact
/// of its direction. Where no configuration leaves every part unloaded (the contact problem is
/// infeasible, or, without play, the rigid first contacts cross: part errors or modifications
/// that interfere) the stage is preloaded: one equilibrium carries zero torque, and both limits
/// are its twist, the secant at zero between the lightest solves each way, which come down from
/// `PRELOAD_DESCENT_FRACTION` to `PRELOAD_PROBE_FRACTION` of `rated` (N m).
///
/// # Errors
/// Those of the solver.
pub(crate) fn zero_torque(sa: &StaticAnalysis, phi: f64, rated: f64) -> Result<ZeroTorque> {
    zero_torque_from(sa, phi, rated, Limits::at(sa, phi)?)
}

/// [`zero_torque`] from the limits `lim` of crank angle `phi`.
fn zero_torque_from(sa: &StaticAnalysis, phi: f64, rated: f64, lim: Limits) -> Result<ZeroTorque> {
    let start = lim.start;
    if let Some(twist) = lim.play() {
        let [NoLoad::Limit { rest: rest_up, .. }, NoLoad::Limit {
            rest: rest_down, ..
        }] = lim.limits
        else {
            unreachable!("play() holds two limits")
        };
        return Ok(ZeroTorque {
            twist,
            start,
            // Solves start from the rigid first contact (beside the rest configuration where
            // it lies beyond it in the solve's direction).
            light: [rest_up, rest_down].map(|r| {
                r.map(|mut r| {
                    r.first_contact_twist = start[usize::from(r.output_torque < 0.0)];
                    *r
                })
            }),
            preloaded: false,
            lightest: None,
        });
    }
    // Preloaded: solves each way bracket the one zero-torque equilibrium. Each way a solve at
    // `PRELOAD_DESCENT_FRACTION` of the rated torque, where the preloaded contacts are
    // settled, and from it the lightest level, `PRELOAD_PROBE_FRACTION` (the solver follows
    // the load down in steps where the solve from the level above does not converge).
    let ways: [Result<Vec<StaticSolution>>; 2] = [1.0, -1.0].map(|s| {
        let k = usize::from(s < 0.0);
        let first = sa.solve_near(phi, s * PRELOAD_DESCENT_FRACTION * rated, start[k], None)?;
        let light = sa.solve_near(
            phi,
            s * preload_probe_level() * rated,
            start[k],
            Some(&first),
        )?;
        Ok(vec![first, light])
    });
    let [up, down] = ways;
    let (mut up, mut down) = (up?, down?);
    // The curve through zero is smooth: the secant between the lightest solves each way
    // at zero torque.
    let (Some(u), Some(d)) = (up.last(), down.last()) else {
        unreachable!("every way holds its first level")
    };
    let twist = zero_twists_of_interference(u, d);
    let lightest = Some(Box::new([u.clone(), d.clone()]));
    // The loaded levels start from the heaviest solves, next to the measuring torque.
    let light = [Some(up.swap_remove(0)), Some(down.swap_remove(0))];
    Ok(ZeroTorque {
        twist,
        start,
        light,
        preloaded: twist[0] == twist[1],
        lightest,
    })
}

/// Where the zero-torque search of one crank angle starts ([`zero_torque_twist_from`]): what
/// the search at the same crank angle found in a neighbouring state (the same reducer at fewer
/// hours of wear). The default is empty: the search starts from the rigid first contacts.
#[derive(Debug, Clone, Default)]
pub(crate) struct ZeroTorqueStart {
    /// Each way's configuration at the end of its contact problem (deviations: the limit's,
    /// or where preloaded the one that violates the constraints least, forward only).
    configs: [Option<Vec<f64>>; 2],
    /// Where the stage was preloaded, the lightest solve of each way (positive torque first).
    probes: Option<Box<[StaticSolution; 2]>>,
}

impl ZeroTorqueStart {
    /// Whether it holds nothing to start from.
    pub(super) fn is_empty(&self) -> bool {
        self.configs.iter().all(Option::is_none) && self.probes.is_none()
    }
}

/// The zero-torque twists `[psi(0+), psi(0-)]` (rad) of crank angle `phi`: those of
/// [`zero_torque`], without the loaded states it also gives, started from what `warm` holds
/// (the contact problems from its configurations), which it then holds for the next state.
/// Where the stage is preloaded, the lightest solve of each way ([`PRELOAD_DESCENT_FRACTION`]
/// halved down to [`PRELOAD_PROBE_FRACTION`], the torque that [`zero_torque`]'s descent
/// reaches) starts from `warm`'s lightest solves instead of coming down from the heavier
/// level; where `warm` holds none, [`zero_torque`]'s descent, whose lightest solves `warm`
/// then holds. The twists are the same to the solvers'
/// tolerances (the no-load limits to the contact problem's twist tolerance, the solves to
/// their residual tolerance).
///
/// # Errors
/// Those of the solver.
pub(crate) fn zero_torque_twist_from(
    sa: &StaticAnalysis,
    phi: f64,
    rated: f64,
    warm: &mut ZeroTorqueStart,
) -> Result<[f64; 2]> {
    Ok(zero_twist_and_start(sa, phi, rated, warm)?.0)
}

/// [`zero_torque_twist_from`] and the twist each way from which loaded solves start
/// ([`ZeroTorque::start`]), rad.
///
/// # Errors
/// Those of the solver.
pub(super) fn zero_twist_and_start(
    sa: &StaticAnalysis,
    phi: f64,
    rated: f64,
    warm: &mut ZeroTorqueStart,
) -> Result<([f64; 2], [f64; 2])> {
    let lim = Limits::at_from(sa, phi, warm)?;
    let start = lim.start;
    warm.configs = lim.configs();
    if let Some(twist) = lim.play() {
        warm.probes = None;
        return Ok((twist, start));
    }
    let probe = preload_probe_level() * rated;
    // Each way from the last lightest solve of that way (loaded in its sense).
    if let Some(from) = warm.probes.take() {
        let [u, d] = [1.0, -1.0].map(|s| {
            let k = usize::from(s < 0.0);
            sa.solve_near(phi, s * probe, lim.start[k], Some(&from[k]))
        });
        let (u, d) = (u?, d?);
        let twist = zero_twists_of_interference(&u, &d);
        warm.probes = Some(Box::new([u, d]));
        return Ok((twist, start));
    }
    let cold = zero_torque_from(sa, phi, rated, lim)?;
    warm.probes = cold.lightest;
    Ok((cold.twist, start))
}

/// The levels of a preloaded stage's descent from `first` (a fraction of the rated torque,
/// itself the first level): each half the one before, down to the first below about twice
/// [`PRELOAD_PROBE_FRACTION`].
fn halvings(first: f64) -> impl Iterator<Item = f64> {
    std::iter::successors(Some(first), |&f| {
        (f >= 2.0 * 0.99 * PRELOAD_PROBE_FRACTION).then_some(0.5 * f)
    })
}

/// The lightest level of a preloaded stage's descent from [`PRELOAD_DESCENT_FRACTION`], as a
/// fraction of the rated torque ([`halvings`]).
fn preload_probe_level() -> f64 {
    halvings(PRELOAD_DESCENT_FRACTION)
        .last()
        .expect("the first level is always there")
}
