//! The accuracy life's search over a study (docs/model.md section 11): the crossing between the
//! stages, each trial the study's wear replayed to its hours, and the search beyond the last
//! stage, the wear integration continued.

use super::stage::accuracy_point;
use crate::config::Model;
use crate::error::Result;
use crate::quantities::{AccuracyPoint, StageSummary};
use crate::te::CrankStart;
use crate::wear::{integrate, BearingWearRates, WearHistory, WearInputs};

/// [`crate::life::accuracy_life`] of a study of `model`: the stages' summaries, each trial
/// the study's own wear integration `wear` replayed to the trial hours
/// ([`WearHistory::replay`]: no wear rate is evaluated again) and the worn profile's accuracy
/// quantities ([`accuracy_point`]); beyond the last stage a wear
/// integration by the model's rule, each step announced by `notice` (one line of text: the
/// search can take as long as the study). `ahead`: the trials beyond the stages already made
/// from the last stage while the stages were analysed ([`LifeTrials::ahead`]), used when they
/// start from the same point.
///
/// # Errors
/// Wear integration and analysis failures.
pub(crate) fn study_life(
    model: &Model,
    stages: &[StageSummary],
    wear: &WearHistory,
    ahead: Option<LifeTrials>,
    notice: &dyn Fn(&str),
) -> Result<Option<crate::life::AccuracyLife>> {
    let points: Vec<AccuracyPoint> = stages.iter().map(AccuracyPoint::of).collect();
    let last = points.last().map_or(0.0, |p| p.hours);
    let beyond = |h: f64, max_h: f64| {
        notice(&format!(
            "within spec at the last stage ({last:.0} h): wear integrated on to {h:.0} h to find \
             the accuracy life (search horizon {max_h:.0} h, life.max_hours)"
        ))
    };
    let Some(&start) = points.last() else {
        return Ok(None);
    };
    let mut trials = match ahead {
        Some(t) if wear.limit.is_none() && (t.start == start || t.within_stages) => t,
        _ => LifeTrials::new(wear, start),
    };
    crate::life::accuracy_life(&model.life, &points, |h| trials.at(model, h), &beyond)
}

/// The accuracy life's trials of a study ([`study_life`]): its wear integration, continued
/// as the trials go beyond its last stage, and the points evaluated so far.
pub(crate) struct LifeTrials {
    /// The last stage's point, where the trials beyond the stages start.
    start: AccuracyPoint,
    /// Trials between two stages only (the crossing of [`LifeTrials::crossing_ahead`]): good
    /// for any last stage.
    within_stages: bool,
    rates: BearingWearRates,
    history: WearHistory,
    seen: Vec<AccuracyPoint>,
    /// Where the next trial's crank angles start: the last trial's ([`accuracy_point`]).
    starts: Vec<CrankStart>,
}

impl LifeTrials {
    /// No trials yet, on the study's wear integration `wear` (its bearings' growth included)
    /// whose last stage's point is `start`.
    fn new(wear: &WearHistory, start: AccuracyPoint) -> Self {
        LifeTrials {
            start,
            within_stages: false,
            rates: wear.bearing_rates,
            history: wear.clone(),
            seen: Vec::new(),
            starts: Vec::new(),
        }
    }

    /// The trials beyond the stages ([`crate::life::beyond_stages`]) from the last stage's
    /// point `start`, made while the other stages are analysed when that point lies within
    /// the spec (the search beyond the stages then likely follows; the study waits for them).
    /// Their failures are left to the search itself, which meets them again.
    pub(crate) fn ahead(model: &Model, wear: &WearHistory, start: AccuracyPoint) -> Option<Self> {
        let mut trials = LifeTrials::new(wear, start);
        crate::life::beyond_stages(&model.life, start, &mut |h| trials.at(model, h), &|_, _| {});
        Some(trials)
    }

    /// The trials of the crossing between two stages, made while the later stages are
    /// analysed: `stages` gives each stage's accuracy point in order (`None`: not known yet;
    /// `Some(None)`: the stage failed). `None` while the crossing is not known yet (a stage up
    /// to the first outside the spec, or any stage when none is outside so far, still to
    /// come); `Some(None)` when no trials are to be made there (the first stage outside, none
    /// outside, or a failure before, or `claim` returning `false`: another worker makes them);
    /// otherwise the trials. `claim` is called once the crossing is known, before any trial:
    /// the one worker it returns `true` to makes them. The accuracy life's search there
    /// ([`crate::life::accuracy_life`]) meets the same trials again and finds them done. Their
    /// failures are left to the search itself.
    pub(crate) fn crossing_ahead(
        model: &Model,
        wear: &WearHistory,
        stages: impl IntoIterator<Item = Option<Option<AccuracyPoint>>>,
        claim: impl FnOnce() -> bool,
    ) -> Option<Option<Self>> {
        if !model.life.any() {
            return Some(None);
        }
        let mut points = Vec::new();
        for stage in stages {
            let p = stage?;
            let Some(p) = p else {
                return Some(None);
            };
            points.push(p);
            if crate::life::outside(&model.life, &p) {
                break;
            }
        }
        let Some(&last) = points.last() else {
            return Some(None);
        };
        if points.len() < 2 || !crate::life::outside(&model.life, &last) || !claim() {
            return Some(None);
        }
        let mut trials = LifeTrials::new(wear, last);
        trials.within_stages = true;
        let _ =
            crate::life::accuracy_life(&model.life, &points, |h| trials.at(model, h), &|_, _| {});
        Some(Some(trials))
    }

    /// The accuracy point after `h` working hours: one evaluated before, or the wear replayed
    /// to `h` from the integration, continued beyond its last stage when `h` lies beyond it.
    ///
    /// # Errors
    /// Wear integration (the validity limit met on the way included) and analysis failures.
    fn at(&mut self, model: &Model, h: f64) -> Result<AccuracyPoint> {
        if let Some(p) = self.seen.iter().find(|p| p.hours == h) {
            return Ok(*p);
        }
        let rates = self.rates;
        let base = WearInputs {
            bearing_rates: rates,
            ..model.wear_inputs()
        };
        let (map, pins) = match self.history.replay(&base, h)? {
            Some(state) => state,
            None => {
                // Beyond the hours integrated so far: the integration continued there,
                // and the trials between replayed from it.
                let next = if self.history.limit.is_none() && h > 0.0 {
                    self.history.continued(&base, h)?
                } else {
                    let mut w = model.wear.clone();
                    w.stage_hours = vec![h];
                    integrate(&WearInputs { wear: &w, ..base }, &|_, _| {})?
                };
                if let Some(l) = &next.limit {
                    return Err(crate::error::Error::numerical(
                        "accuracy life",
                        l.reason.clone(),
                    ));
                }
                let state = (
                    next.maps.last().cloned().unwrap_or_default(),
                    next.pin_maps.last().cloned().unwrap_or_default(),
                );
                self.history = next;
                state
            }
        };
        let worn = crate::wear::WornState::new(model.wear.model, rates, h, &map, &pins)?;
        let profile = model.cycloid.profile(worn.disc_profile.clone())?;
        let p = accuracy_point(&model.worn(&worn), &profile, h, &mut self.starts)?;
        self.seen.push(p);
        Ok(p)
    }
}
