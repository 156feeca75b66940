//! The validated configuration, [`Model`]: one parameter struct per section, composed in
//! [`Config::validate`] after every section has been checked on its own (in its own file) and
//! the cross-section rules applied ([`super::cross_section`]).

use super::cross_section;
use super::range::{check, whole, Range};
use super::{
    Config, DynamicsConfig, FemConfig, LifeThresholds, LoadParams, MaterialParams, Rating,
    Tolerances,
};
use crate::budget::Budget;
use crate::dynamics::DynamicsParams;
use crate::error::{Error, Result};
use crate::fem::FemParams;
use crate::geometry::{CycloidParams, Profile};
use crate::reducer::Reducer;
use crate::te::TeParams;
use crate::wear::{WearInputs, WearParams};

/// An analysis section with an `enabled` switch (`[dynamics]`, `[fem]`): `rvlife run` adds it
/// to every stage when it is enabled. Its parameters are checked as far as the enabled
/// analyses read them; a disabled section that does not validate carries its defaults, which
/// nothing reads.
#[derive(Debug, Clone)]
pub struct Section<T> {
    /// Whether `rvlife run` runs this analysis at every stage.
    pub enabled: bool,
    /// Its parameters, SI.
    pub params: T,
}

/// The configuration checked and converted to SI: the parameter struct of every section.
/// Each analysis takes the ones it reads (the wear integration: [`Model::wear_inputs`]).
#[derive(Debug, Clone)]
pub struct Model {
    /// `[cycloid]`: the stage, its modifications and measured deviation; builds every profile.
    pub cycloid: CycloidParams,
    /// The reducer's mechanical model: `[reducer]` with its gears, bearings and output pins,
    /// the `[contact]` law and support, `[errors]`.
    pub reducer: Reducer,
    /// `[reducer]`: rated torque and input speed.
    pub rating: Rating,
    /// `[reducer.structure]`: the dimensions of the parts in series in `reducer`.
    pub structure: super::StructureParams,
    /// `[materials]`: elastic constants (also in the contact law) and the contact's static
    /// capacity.
    pub materials: MaterialParams,
    /// `[load]`: the load spectrum the discs wear under.
    pub load: LoadParams,
    /// `[wear]`: the wear model, its coefficient, the stages and the update schedule.
    pub wear: WearParams,
    /// `[te]`: the TE samples, the loaded-TE torque, the lost-motion measuring torque.
    pub te: TeParams,
    /// `[dynamics]`: the multibody model.
    pub dynamics: Section<DynamicsParams>,
    /// `[fem]`: the flexible disc (its parameters also serve the flexible multibody model).
    pub fem: Section<FemParams>,
    /// `[tolerances]`: the part errors' distributions (empty: none).
    pub tolerances: Tolerances,
    /// `[life]`: the accuracy spec (none set: no accuracy life).
    pub life: LifeThresholds,
    /// `[lubrication]`: the oil, the surfaces and the friction models (losses, efficiency,
    /// the wear's dependence on the film).
    pub lubrication: crate::tribology::Lubrication,
    /// Work budget in static contact solves (the command line's `--work-budget-min`,
    /// [`crate::budget`]); checked by [`crate::api::validated`], not here.
    pub work_budget: f64,
}

impl Model {
    /// What the wear integration of this model reads ([`crate::wear::integrate`]).
    pub fn wear_inputs(&self) -> WearInputs<'_> {
        WearInputs {
            reducer: &self.reducer,
            disc: &self.cycloid,
            wear: &self.wear,
            load: &self.load.levels,
            band_torque: self.te.loaded_torque,
            budget: self.budget(),
            bearing_rates: Default::default(),
            lubrication: self.lubrication,
        }
    }

    /// This model for the static accuracy-life study alone: the multibody dynamics and the
    /// flexible disc off (they do not enter the accuracy life; docs/model.md section 12).
    /// What the page's study and Monte Carlo, Python's `accuracy_life` and the calibration's
    /// reference passes run.
    pub fn static_only(mut self) -> Model {
        self.dynamics.enabled = false;
        self.fem.enabled = false;
        self
    }

    /// The work budget and the cost of the stages' analyses besides the wear.
    pub fn budget(&self) -> Budget {
        Budget {
            solves: self.work_budget,
            per_stage: crate::budget::stage_solves(self.te.samples, !self.reducer.errors.is_zero()),
        }
    }

    /// This model with the parts of `state` worn: the crank bearings' clearances grown and
    /// the pins worn (the static analysis sees them, [`crate::reducer::PinWear`]; the
    /// multibody model runs on the same reducer); itself when neither wears. The disc's wear is in
    /// the profile made from `state.disc_profile`.
    pub fn worn(&self, state: &crate::wear::WornState) -> std::borrow::Cow<'_, Model> {
        if !state.bearings_worn() && !state.pins_worn() {
            return std::borrow::Cow::Borrowed(self);
        }
        let mut m = self.clone();
        state.wear_parts(&mut m.reducer);
        std::borrow::Cow::Owned(m)
    }

    /// The unworn profile (with the modifications and measured deviation).
    ///
    /// # Errors
    /// Those of [`CycloidParams::profile`].
    pub fn profile(&self) -> Result<Profile> {
        self.cycloid.profile(None)
    }
}

impl Config {
    /// Checks every section and converts it to SI ([`Model`]): each section in its own file,
    /// then the rules that span sections ([`cross_section`]): the reducer's mechanical model,
    /// the measured profile on the wear grid, a disabled `[dynamics]` or `[fem]` checked only
    /// as far as it is read; then the parts the analyses add ([`Config::assemble`]). The work
    /// budget and the physical checks of the unworn stage (the modifications keep the disc in
    /// mesh, every torque of the config is carried) are the gate every command passes
    /// ([`crate::api::validated`], docs/model.md section 15.2), not this call.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and the allowed range. A key the file does
    /// not set (a default) is named as such, with what its default depends on. Those of the FE
    /// disc's series compliance.
    pub fn validate(&self) -> Result<Model> {
        let model = self.validate_unassembled()?;
        self.assemble(model)
    }

    /// The sections checked and converted ([`Config::validate`] without [`Config::assemble`]):
    /// the model the physical checks of the unworn stage are made on (`study::validated`).
    ///
    /// # Errors
    /// Those of [`Config::validate`].
    pub(crate) fn validate_unassembled(&self) -> Result<Model> {
        self.validate_sections()
            .map_err(|e| self.explain_default(e))
    }

    /// The parts of `model` that the analyses add to the checked sections: the housing's
    /// surface for the heat balance (an estimate where its outline is not given), the
    /// quasi-static friction with `[lubrication]` enabled (docs/model.md section 18), and the
    /// FE disc's body and bore compliances in series with the crank bearings (an RV reducer on
    /// roller bearings with `structure.elastic_disc`; docs/model.md section 5.13).
    ///
    /// # Errors
    /// Those of the FE disc's series compliance (`crate::fem::body`), keys named as in
    /// [`Config::validate`].
    pub(crate) fn assemble(&self, model: Model) -> Result<Model> {
        self.assembled(model).map_err(|e| self.explain_default(e))
    }

    fn assembled(&self, mut model: Model) -> Result<Model> {
        let single = matches!(model.reducer.drive, crate::reducer::Drive::SingleStage(_));
        let structure = model.structure;
        if let Some(h) = &mut model.lubrication.heat {
            // The housing's surface: a cylinder of its outer diameter and half as long, with
            // one free end face (an estimate where the outline is not given).
            let d = match &structure.housing {
                Some(ring) => 2.0 * ring.outer_radius,
                None => 2.6 * model.cycloid.geometry.pin_circle_radius,
            };
            h.area.get_or_insert(0.75 * std::f64::consts::PI * d * d);
        }
        if model.lubrication.enabled {
            model.reducer.friction = Some(
                model
                    .lubrication
                    .quasi_static(model.wear.pin_turning, model.wear.pin_rolling_fraction),
            );
        }
        if structure.elastic_disc
            && !single
            && model.reducer.support == crate::reducer::Support::Bearings
            && self.reducer.bearings.model == "rollers"
        {
            let c = &model.cycloid;
            let nominal_profile = Profile::new(c.geometry.clone(), c.modification, None)?;
            elastic_disc(&mut model, &nominal_profile)?;
        }
        Ok(model)
    }

    fn validate_sections(&self) -> Result<Model> {
        // The sections, each on its own.
        let (geometry, modification) = self.cycloid.validate()?;
        // The stage's own checks (K1, undercut).
        let nominal_profile = Profile::new(geometry.clone(), modification, None)?;
        let materials = self.materials.validate()?;
        let parts = self.reducer.validate(&geometry)?;
        let contact = self
            .contact
            .validate(&geometry, materials.elastic, !parts.single)?;
        let rating = parts.rating;
        let gap_points = whole(
            "dynamics.gap_points_per_tooth",
            self.dynamics.gap_points_per_tooth,
            64,
            65536,
        )?;
        let errors = self.errors.validate(geometry.pins, parts.cranks)?;
        let load = self
            .load
            .validate(rating.rated_torque, rating.input_speed_rpm, |p| {
                self.path(p)
            })?;
        let wear = self.wear.validate()?;
        let te = self.te.validate(rating.rated_torque)?;
        // Across sections.
        let reducer = cross_section::reducer(&parts, &geometry, &contact, gap_points, errors);
        let measured = self
            .cycloid
            .measured_profile
            .as_ref()
            .map(|p| {
                cross_section::measured(
                    &nominal_profile,
                    &self.path(p),
                    geometry.pins * wear.crank_steps,
                )
            })
            .transpose()?;
        let (dynamics, fem) =
            self.dynamics_and_fem(&parts, &reducer, &nominal_profile, &materials)?;
        let work_budget = crate::budget::solves_in_minutes(check(
            "--work-budget-min",
            self.work_budget_minutes,
            Range::closed(
                crate::budget::MIN_MINUTES,
                1e6,
                "min (6 s to about two years)",
            ),
        )?);
        let tolerances = self.tolerances.validate(&geometry)?;
        let life = self.life.validate()?;
        let lubrication = self.lubrication.validate()?;
        let model = Model {
            cycloid: CycloidParams {
                geometry,
                modification,
                measured,
            },
            reducer,
            rating,
            structure: parts.structure,
            materials,
            load,
            wear,
            te,
            dynamics,
            fem,
            tolerances,
            life,
            lubrication,
            work_budget,
        };
        Ok(model)
    }

    /// `[dynamics]` and `[fem]`, each checked as far as the enabled analyses read it (a
    /// disabled section that does not validate carries its defaults, so that `te` and
    /// `contact` never fail on a section they do not use; the `dynamics` command enables its
    /// section), on the RV twin of a single-stage drive (whose multibody and FE models are
    /// refused).
    fn dynamics_and_fem(
        &self,
        parts: &super::reducer::ReducerParts,
        reducer: &Reducer,
        nominal_profile: &Profile,
        materials: &MaterialParams,
    ) -> Result<(Section<DynamicsParams>, Section<FemParams>)> {
        if parts.single {
            for (key, on) in [
                ("dynamics.enabled", self.dynamics.enabled),
                ("fem.enabled", self.fem.enabled),
            ] {
                if on {
                    return Err(Error::invalid(
                        key,
                        "true",
                        "the multibody and finite-element models are built for RV reducers; \
                         set enabled = false for drive = \"single_stage\"",
                    ));
                }
            }
        }
        let twin = cross_section::rv_twin(parts, reducer);
        let rv = if parts.single { &twin } else { reducer };
        let planets = rv.cranks;
        let rated = parts.rating.rated_torque;
        let dynamics_of = |d: &DynamicsConfig| {
            d.validate(rv, parts.damping, nominal_profile, rated, |p| self.path(p))
        };
        let dynamics = match dynamics_of(&self.dynamics) {
            Err(e) if self.dynamics.enabled => return Err(e),
            Err(e) => dynamics_of(&DynamicsConfig::default()).map_err(|_| e)?,
            Ok(d) => d,
        };
        let geometry = &reducer.geometry;
        let default_bore = geometry.scaled_from_root(13.0);
        let (e1, nu1) = (
            materials.elastic.disc_youngs_modulus,
            materials.elastic.disc_poisson_ratio,
        );
        let fem_of = |f: &FemConfig, bore_mm: f64| {
            f.validate(
                nominal_profile,
                planets,
                bore_mm * 1e-3,
                rv.crank_circle_radius,
                e1,
                nu1,
            )
        };
        let bore = self
            .dynamics
            .inertia
            .crank_bore_radius_mm
            .unwrap_or(default_bore);
        // The flexible disc of the dynamics reads `[fem]` (its mesh and holes).
        let flexible = self.dynamics.enabled && self.dynamics.disc == "flexible";
        let fem_read = self.fem.enabled || flexible;
        let fem = match fem_of(&self.fem, bore) {
            Err(e) if fem_read => return Err(e),
            Err(e) => fem_of(&FemConfig::default(), default_bore).map_err(|_| e)?,
            Ok(f) => f,
        };
        // The multibody model carries one modal FE disc: every disc must be its part turned by
        // a symmetry of the holes (checked here, before any work).
        if flexible {
            let zc = geometry.disc_teeth();
            if let Some(d) = (0..reducer.discs())
                .find(|&d| crate::fem::mount_teeth(zc, reducer.profile_turn(d), &fem).is_none())
            {
                return Err(Error::invalid(
                    "dynamics.disc",
                    "\"flexible\"",
                    format!(
                        "needs every disc to be disc 1's part turned onto itself: disc {} is \
                         turned by its eccentric phase ({:.1} deg) and half a tooth, which maps \
                         the crank bores and holes of [fem] onto themselves only for an even \
                         number of cranks and an odd tooth count (here {planets} cranks, {zc} \
                         teeth); use \"rigid\" discs, or the quasi-static flexible disc of \
                         [fem] (fem.enabled), which models each disc",
                        d + 1,
                        reducer.phase(d).to_degrees()
                    ),
                ));
            }
        }
        Ok((
            Section {
                enabled: self.dynamics.enabled,
                params: dynamics,
            },
            Section {
                enabled: self.fem.enabled,
                params: fem,
            },
        ))
    }
}

/// `model` with its discs' body and bores in series with its crank-disc bearings
/// ([`crate::fem::body::series_compliances`] on the disc of `[fem]` at the rated torque,
/// docs/model.md section 5.13), in the static analysis's reducer and the dynamic analysis's.
///
/// # Errors
/// The FE models' and the static analysis's failures.
fn elastic_disc(model: &mut Model, profile: &Profile) -> Result<()> {
    let c = crate::fem::body::series_compliances_memoised(
        &model.reducer,
        profile,
        &model.fem.params,
        model.rating.rated_torque,
    )?;
    let series = crate::reducer::structure::SeriesCompliances {
        disc_body: c.body,
        disc_bores: c.bores,
        ..model.reducer.series
    };
    model.reducer.set_series(series);
    Ok(())
}

/// The crank bearings' clearance growth of `model`, m/h (zero unless
/// `wear.bearing_archard_coefficient_mm3_per_n_m` is set; docs/model.md section 7.9).
///
/// # Errors
/// Those of [`crate::wear::bearing_wear_rates`].
pub(crate) fn bearing_rates(model: &Model) -> Result<crate::wear::BearingWearRates> {
    if model.wear.bearings.archard <= 0.0 {
        return Ok(crate::wear::BearingWearRates::default());
    }
    crate::wear::bearing_wear_rates(&model.wear_inputs(), &model.profile()?, model.te.samples)
}
