//! The reducer's worn state at some working hours (docs/model.md section 7): the disc's wear
//! depth and the map its profile is made with, the pins' wear and the crank bearings' grown
//! clearances. Built in one place ([`WornState::new`]) from the wear integration's maps and
//! the bearings' clearance growth, and lent to every analysis that sees the worn reducer: the
//! wear integration's rate evaluations ([`WornState::reducer`]), a study's stages and the
//! accuracy life's trials, Monte Carlo's samples and the single commands at `--hours`
//! (through the model, `Model::worn`).

use std::borrow::Cow;

use super::{BearingWearRates, WearModelKind};
use crate::error::Result;
use crate::geometry::WearMap;
use crate::reducer::{PinWear, Reducer};

/// The reducer's worn parts at `hours`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WornState {
    /// Working hours, h.
    pub hours: f64,
    /// The disc's wear depth on the wear model's mesh-angle grid (`None`: unworn).
    pub disc: Option<WearMap>,
    /// The map the worn profile is made with ([`profile_maps`]; `None`: unworn).
    pub disc_profile: Option<WearMap>,
    /// The pins' wear, m around the pin ([`PinWear`]; empty or zero: unworn).
    pub pins: Vec<f64>,
    /// The crank-disc bearings' clearance growth, m.
    pub bearing_disc: f64,
    /// The crank-carrier bearings' clearance growth, m.
    pub bearing_carrier: f64,
}

/// The wear model's rule from the integration's depths `map` (m per grid point; empty or
/// zero: unworn) to the disc's wear map and the map its profile is made with: the same in
/// Flodin's model; the uniform map at the largest depth in the paper's (its section 3.1).
/// `(None, None)` when unworn.
///
/// # Errors
/// [`crate::Error::Invalid`] for a map [`WearMap::new`] refuses.
pub fn profile_maps(
    kind: WearModelKind,
    map: &[f64],
) -> Result<(Option<WearMap>, Option<WearMap>)> {
    let max = map.iter().copied().fold(0.0, f64::max);
    if max <= 0.0 {
        return Ok((None, None));
    }
    let wear = WearMap::new(map.to_vec())?;
    let profile = match kind {
        WearModelKind::Paper => WearMap::uniform(map.len(), max)?,
        WearModelKind::Flodin => wear.clone(),
    };
    Ok((Some(wear), Some(profile)))
}

impl WornState {
    /// The state at `hours` of a reducer whose bearings' clearances grow at `rates` (m/h,
    /// constant in time), whose disc has worn by `disc_map` and pins by `pin_map` (m; empty:
    /// unworn), under the wear model `kind` ([`profile_maps`]).
    ///
    /// # Errors
    /// Those of [`profile_maps`].
    pub fn new(
        kind: WearModelKind,
        rates: BearingWearRates,
        hours: f64,
        disc_map: &[f64],
        pin_map: &[f64],
    ) -> Result<WornState> {
        let (disc, disc_profile) = profile_maps(kind, disc_map)?;
        Ok(WornState {
            disc,
            disc_profile,
            ..WornState::parts(rates, hours, pin_map)
        })
    }

    /// The state of the parts other than the disc at `hours`: the bearings grown at `rates`
    /// (m/h), the pins worn by `pin_map` (m); the disc unworn.
    pub fn parts(rates: BearingWearRates, hours: f64, pin_map: &[f64]) -> WornState {
        let grows = rates != BearingWearRates::default() && hours > 0.0;
        WornState {
            hours,
            disc: None,
            disc_profile: None,
            pins: if pin_map.iter().any(|&d| d > 0.0) {
                pin_map.to_vec()
            } else {
                Vec::new()
            },
            bearing_disc: if grows { rates.disc * hours } else { 0.0 },
            bearing_carrier: if grows { rates.carrier * hours } else { 0.0 },
        }
    }

    /// This state with the pins and the disc new: the bearings' wear alone.
    pub fn bearings_only(&self) -> WornState {
        WornState {
            hours: self.hours,
            bearing_disc: self.bearing_disc,
            bearing_carrier: self.bearing_carrier,
            ..WornState::default()
        }
    }

    /// Whether the crank bearings' clearances have grown.
    pub fn bearings_worn(&self) -> bool {
        self.bearing_disc != 0.0 || self.bearing_carrier != 0.0
    }

    /// Whether the pins have worn.
    pub fn pins_worn(&self) -> bool {
        !self.pins.is_empty()
    }

    /// `red` with its crank bearings and pins worn to this state; itself when neither wears.
    /// The disc's wear is in its profile, made apart ([`WornState::disc_profile`]).
    pub fn reducer<'a>(&self, red: &'a Reducer) -> Cow<'a, Reducer> {
        if !self.bearings_worn() && !self.pins_worn() {
            return Cow::Borrowed(red);
        }
        let mut r = red.clone();
        self.wear_parts(&mut r);
        Cow::Owned(r)
    }

    /// Wears `red`'s crank bearings (their clearances opened by this state's growth) and pins
    /// to this state, in place.
    pub fn wear_parts(&self, red: &mut Reducer) {
        if self.bearings_worn() {
            red.bearings.disc.clearance += self.bearing_disc;
            red.bearings.carrier.clearance += self.bearing_carrier;
        }
        if self.pins_worn() {
            red.pin_wear = PinWear::new(self.pins.clone());
        }
    }
}
