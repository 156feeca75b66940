//! Selective assembly of a sampled reducer (docs/model.md section 12.4): the pin grade that
//! brings the new unit's backlash into the factory's band, or the unit rejected at assembly.

use crate::config::{Model, SelectiveAssembly};
use crate::error::{Error, Result};
use crate::units::ARCMIN_PER_RAD;

/// Status of a sample that no pin grade brings into the band (its prefix: `rejected at
/// assembly: ...`).
pub const REJECTED: &str = "rejected at assembly";

/// The sampled reducer `m` (its part errors drawn) built with the pin grade of `sel` that
/// brings its new backlash (`backlash(unit)`, arcmin: the catalogue backlash of the unworn
/// unit, as the samples' stages are analysed) into the band: of the grades
/// whose backlash falls within it, the tightest (the least backlash: the unit leaves the
/// factory with the most of its accuracy life; the smaller offset where two are as tight).
/// Each grade adds its offset to every pin's radius.
///
/// # Errors
/// The status of a unit rejected at assembly ([`REJECTED`], with the backlash the grades give
/// and the band) where no grade brings it into the band, or `failed: ...` where no grade
/// could be analysed.
pub(crate) fn select_grade(
    m: Model,
    sel: &SelectiveAssembly,
    backlash: impl Fn(&Model) -> Result<f64>,
) -> std::result::Result<Model, String> {
    let [lo, hi] = sel.backlash.map(|b| b * ARCMIN_PER_RAD);
    let mut best: Option<(f64, f64, Model)> = None;
    let mut seen: Vec<f64> = Vec::new();
    let mut failure: Option<Error> = None;
    for &grade in &sel.pin_grades {
        let mut g = m.clone();
        for r in &mut g.reducer.errors.pin_radius {
            *r += grade;
        }
        let backlash = match backlash(&g) {
            Ok(b) => b,
            Err(e) => {
                failure.get_or_insert(e);
                continue;
            }
        };
        seen.push(backlash);
        if (lo..=hi).contains(&backlash) {
            let rank = (backlash, grade.abs());
            if best.as_ref().is_none_or(|(d, a, _)| rank < (*d, *a)) {
                best = Some((rank.0, rank.1, g));
            }
        }
    }
    if let Some((_, _, g)) = best {
        return Ok(g);
    }
    let status = match (seen.is_empty(), failure) {
        (true, Some(e)) => format!("failed: {e}"),
        _ => {
            let (a, b) = seen
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            format!(
                "{REJECTED}: backlash {a:.3} to {b:.3} arcmin over {} pin grades, none within \
                 [{}, {}] arcmin",
                seen.len(),
                round_arcmin(lo),
                round_arcmin(hi)
            )
        }
    };
    Err(status)
}

/// An angle of the band (arcmin) as written: to the nanoarcminute, which the degrees-radians
/// round trip blurs in its last bits.
fn round_arcmin(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}
