//! `[contact]`: the line-contact law of a pin on the disc flank (docs/model.md section 3), how
//! the contact geometry sees a worn flank (section 4) and how the discs are held (section 5).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::contact::{ApproachLaw, ContactModel, Groove, Materials, PinBending};
use crate::error::{Error, Result};
use crate::geometry::CycloidGeometry;
use crate::reducer::Support;

/// `[contact]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactConfig {
    /// `"paper"` (default), `"johnson"` or `"linear"`.
    #[serde(default = "default_law")]
    pub law: String,
    /// Stiffness of the `"linear"` law, N/um. Range: [1, 1e7] N/um (physical pin contacts).
    #[serde(default)]
    pub linear_stiffness_n_per_um: Option<f64>,
    /// Cap on the flank radius of curvature in the contact law, mm (default: pin circle
    /// radius). Range: [0.1, 1e5] mm.
    #[serde(default)]
    pub max_curvature_radius_mm: Option<f64>,
    /// Reference depth of the disc term of the approach law: `"body"` (default: the pin circle
    /// radius at every flank point) or `"local_radius"` (the paper's eq 6 as printed: the local
    /// flank radius, capped at `max_curvature_radius_mm`).
    #[serde(default = "default_disc_depth")]
    pub disc_depth: String,
    /// How the discs are held: `"bearings"` (default: both discs on their crank bearings, the
    /// load share from the equilibrium) or `"rigid"` (the paper's and Li's model: one disc, its
    /// centre fixed on the eccentric, carrying `load_share` of the output torque).
    #[serde(default = "default_support")]
    pub support: String,
    /// Share of the output torque on the disc with `support = "rigid"` (paper eqs 8-9: 0.55).
    /// Range: (0, 1].
    #[serde(default)]
    pub load_share: Option<f64>,
    /// Force whose Hertz half-width sets the band over which the contact geometry averages the
    /// worn flank, N (default: Li's largest pin force at the rated torque). Range: (0, 1e7] N.
    #[serde(default)]
    pub band_force_n: Option<f64>,
    /// How the contact geometry sees the worn flank: `"envelope"` (default: the upper envelope
    /// of the flank averaged over a sixteenth of `band_force_n` and over `band_force_n`) or
    /// `"single"` (averaged over the band of `band_force_n`).
    #[serde(default = "default_band")]
    pub band: String,
    /// How the pins are held: `"groove"` (each pin seated in a housing groove, the pin-groove
    /// contact in series with the flank contact: the RV construction, default for
    /// `reducer.drive = "rv"`), `"rigid"` (the pins held rigidly, the paper's model and the
    /// default of a single-stage drive) or `"ends"` (each pin held at its two ends only and
    /// bent by the disc's load, a beam in series with the flank contact; docs/model.md
    /// sections 3.4 and 3.5). The groove needs the log laws (`law = "paper"` or `"johnson"`).
    #[serde(default)]
    pub pin_support: Option<String>,
    /// Distance between the supports of a pin held at its ends, mm (`pin_support = "ends"`
    /// only; default three disc widths: the two discs side by side and half a disc width at
    /// each end for the running clearances and the support, an **estimate**). Range: [2 B,
    /// 2000] mm, `B` the disc width (the two discs must fit between the supports).
    #[serde(default)]
    pub pin_span_mm: Option<f64>,
    /// Groove radius minus pin radius, um (default 10 um: an **estimate** of a running fit of
    /// a hardened pin in a ground groove). Range: [1, 1000] um.
    #[serde(default)]
    pub groove_clearance_um: Option<f64>,
}

fn default_band() -> String {
    "envelope".into()
}

fn default_law() -> String {
    "paper".into()
}

fn default_disc_depth() -> String {
    "body".into()
}

fn default_support() -> String {
    "bearings".into()
}

impl Default for ContactConfig {
    fn default() -> Self {
        ContactConfig {
            law: default_law(),
            linear_stiffness_n_per_um: None,
            max_curvature_radius_mm: None,
            disc_depth: default_disc_depth(),
            support: default_support(),
            load_share: None,
            band_force_n: None,
            band: default_band(),
            pin_support: None,
            pin_span_mm: None,
            groove_clearance_um: None,
        }
    }
}

/// `[contact]` checked, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// The line-contact law.
    pub law: ContactModel,
    /// How the discs are held in the static analysis.
    pub support: Support,
    /// `band = "envelope"`: the contact geometry is the upper envelope of the flank averaged
    /// over a narrow and the wide band.
    pub envelope: bool,
    /// The band force, N (`None`: Li's largest pin force at the rated torque,
    /// [`super::cross_section`]).
    pub band_force: Option<f64>,
}

/// `"<value>"` must be one of `allowed`, as the message says.
fn one_of<'v>(key: &str, value: &'v str, allowed: &[&str], words: &str) -> Result<&'v str> {
    if allowed.contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(key, format!("\"{value}\""), words))
    }
}

impl ContactConfig {
    /// The contact law for the stage `geometry` and the elastic constants `materials`, the
    /// support, the band, SI; `rv` for an RV reducer (its pins sit in housing grooves unless
    /// `pin_support` says otherwise).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and the allowed values or range.
    pub fn validate(
        &self,
        geometry: &CycloidGeometry,
        materials: Materials,
        rv: bool,
    ) -> Result<ContactParams> {
        let law = match self.law.as_str() {
            "paper" => ApproachLaw::Paper,
            "johnson" => ApproachLaw::Johnson,
            "linear" => {
                let k = self.linear_stiffness_n_per_um.ok_or_else(|| {
                    Error::invalid(
                        "contact.linear_stiffness_n_per_um",
                        "missing",
                        "required with law = \"linear\"",
                    )
                })?;
                ApproachLaw::Linear {
                    stiffness: check(
                        "contact.linear_stiffness_n_per_um",
                        k,
                        Range::closed(1.0, 1e7, "N/um"),
                    )? * 1e6,
                }
            }
            other => {
                return Err(Error::invalid(
                    "contact.law",
                    format!("\"{other}\""),
                    "must be \"paper\", \"johnson\" or \"linear\"",
                ))
            }
        };
        let max_radius = match self.max_curvature_radius_mm {
            Some(v) => {
                check(
                    "contact.max_curvature_radius_mm",
                    v,
                    Range::closed(0.1, 1e5, "mm"),
                )? * 1e-3
            }
            None => geometry.pin_circle_radius,
        };
        let disc_depth = match one_of(
            "contact.disc_depth",
            &self.disc_depth,
            &["body", "local_radius"],
            "must be \"body\" or \"local_radius\"",
        )? {
            "body" => Some(geometry.pin_circle_radius),
            _ => None,
        };
        let groove_clearance = match self.groove_clearance_um {
            Some(v) => {
                check(
                    "contact.groove_clearance_um",
                    v,
                    Range::closed(1.0, 1e3, "um"),
                )? * 1e-6
            }
            None => 10e-6,
        };
        let log_law = !matches!(law, ApproachLaw::Linear { .. });
        let default_support = if rv && log_law { "groove" } else { "rigid" };
        let pin_support = one_of(
            "contact.pin_support",
            self.pin_support.as_deref().unwrap_or(default_support),
            &["groove", "rigid", "ends"],
            "must be \"groove\", \"rigid\" or \"ends\"",
        )?;
        let groove = match pin_support {
            // Loaded over the disc width, into a housing wall of about 0.15 Rp (estimate).
            "groove" if log_law => Some(Groove {
                clearance: groove_clearance,
                length: geometry.width,
                housing_depth: 0.15 * geometry.pin_circle_radius,
            }),
            _ => None,
        };
        let b = geometry.width;
        let span = match self.pin_span_mm {
            Some(v) if pin_support == "ends" => {
                check(
                    "contact.pin_span_mm",
                    v,
                    Range::closed(2.0 * b * 1e3, 2000.0, "mm"),
                )? * 1e-3
            }
            Some(_) => {
                return Err(Error::invalid(
                    "contact.pin_span_mm",
                    "given",
                    "applies only to pin_support = \"ends\"",
                ))
            }
            None => 3.0 * b,
        };
        // Two discs side by side about the span's middle: each disc's mid-plane half a disc
        // width from it.
        let pin_compliance = if pin_support == "ends" && log_law {
            PinBending {
                span,
                load_at: 0.5 * span - 0.5 * b,
            }
            .compliance(geometry.pin_radius, &materials)
        } else {
            0.0
        };
        let law = ContactModel {
            groove,
            pin_compliance,
            law,
            materials,
            width: geometry.width,
            pin_radius: geometry.pin_radius,
            max_radius,
            disc_depth,
        };
        let support = match one_of(
            "contact.support",
            &self.support,
            &["bearings", "rigid"],
            "must be \"bearings\" or \"rigid\"",
        )? {
            "bearings" => {
                if self.load_share.is_some() {
                    return Err(Error::invalid(
                        "contact.load_share",
                        "given",
                        "applies only to support = \"rigid\" (with bearings the load share \
                         comes out of the equilibrium)",
                    ));
                }
                Support::Bearings
            }
            _ => Support::Rigid {
                load_share: check(
                    "contact.load_share",
                    self.load_share.unwrap_or(0.55),
                    Range::positive(1.0, ""),
                )?,
            },
        };
        let envelope = one_of(
            "contact.band",
            &self.band,
            &["single", "envelope"],
            "must be \"single\" or \"envelope\"",
        )? == "envelope";
        let band_force = self
            .band_force_n
            .map(|f| check("contact.band_force_n", f, Range::positive(1e7, "N")))
            .transpose()?;
        Ok(ContactParams {
            law,
            support,
            envelope,
            band_force,
        })
    }
}
