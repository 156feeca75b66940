//! The hysteresis plot of a study: every stage's curve over the whole torque range, and a zoom
//! on the catalogue's lost-motion region (+-3 % of the rated torque) where the play shows.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::*;
use crate::study::Study;

/// Half-width of the zoom panel, as a multiple of the measuring torque (+-6 % of the rated
/// torque at the catalogue's 3 %).
const ZOOM: f64 = 2.0;

/// The part of the polyline `pts` with `|x| <= half`, the segments crossing the edge cut there
/// (linear interpolation): plotters draws past its axes otherwise.
fn clip_x(pts: &[(f64, f64)], half: f64) -> Polyline {
    let inside = |p: &(f64, f64)| p.0.abs() <= half;
    let mut out = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let cut = |edge: f64| {
            let t = (edge - a.0) / (b.0 - a.0);
            (edge, a.1 + t * (b.1 - a.1))
        };
        match (inside(&a), inside(&b)) {
            (true, true) => {
                out.push(a);
                out.push(b);
            }
            (true, false) => {
                out.push(a);
                out.push(cut(half.copysign(b.0)));
            }
            (false, true) => {
                out.push(cut(half.copysign(a.0)));
                out.push(b);
            }
            (false, false) => {}
        }
    }
    out.dedup();
    out
}

/// `hysteresis.{svg,png}`: left, the hysteresis curve of every stage (output twist against
/// output torque, input locked, averaged over a mesh cycle: `0 -> +T_r -> -T_r -> +T_r`) with
/// its solved torques marked; right, the same curves near zero torque with the +-3 % region
/// shaded and the twists that set the catalogue lost motion marked. Notes in the legend say
/// why the loops are thin (frictionless contacts retrace: the only width is the play) and when
/// the negative branches coincide (negative torque loads the flank that does not wear).
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub fn hysteresis(study: &Study, dir: &Path) -> Result<()> {
    let n = study.stages.len();
    let t = study.model.rating.rated_torque;
    let m = study.model.te.measuring_torque_fraction;
    let curves: Vec<(f64, Polyline)> = study
        .stages
        .iter()
        .map(|s| {
            let c = s.hysteresis.curve();
            (
                s.hours,
                c.torque
                    .iter()
                    .zip(&c.twist)
                    .map(|(t, x)| (*t, x * ARCMIN_PER_RAD))
                    .collect(),
            )
        })
        .collect();
    // The twists at +-the measuring torque, arcmin: their gap is the lost motion.
    let lost_motion: Vec<[f64; 2]> = study
        .stages
        .iter()
        .map(|s| {
            let i = s
                .hysteresis
                .fractions
                .iter()
                .position(|f| (f - m).abs() < 1e-12)
                .unwrap_or(0);
            [
                s.hysteresis.negative[i] * ARCMIN_PER_RAD,
                s.hysteresis.positive[i] * ARCMIN_PER_RAD,
            ]
        })
        .collect();
    let (y0, y1) = series_range(curves.iter().flat_map(|c| c.1.iter().map(|p| p.1)));
    let half = ZOOM * m * t;
    let zoomed: Vec<Polyline> = curves.iter().map(|c| clip_x(&c.1, half)).collect();
    let (z0, z1) = series_range(zoomed.iter().flatten().map(|p| p.1));
    // Do the negative branches coincide (the flank loaded by negative torque unworn)?
    let spread = |side: f64| {
        let v: Vec<f64> = study
            .stages
            .iter()
            .map(|s| {
                let last = s.hysteresis.positive.len() - 1;
                if side > 0.0 {
                    s.hysteresis.positive[last]
                } else {
                    s.hysteresis.negative[last]
                }
            })
            .collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(*x), b.max(*x))
            });
        hi - lo
    };
    let negative_coincide = n > 1 && spread(-1.0) < 0.05 * spread(1.0);
    figure!(
        dir,
        "hysteresis",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plots, strip) = with_legend_strip(root);
            let w = plots.dim_in_pixel().0;
            let (left, right) = plots.split_horizontally(w * 11 / 20);
            let axes = ("output torque (N m)", "output twist (arcmin)");
            let mut chart = panel(
                &left,
                "Hysteresis curves (input locked)",
                axes,
                -1.05 * t..1.05 * t,
                y0..y1,
                true,
            )?;
            let mut legend = Legend::new();
            for (i, (h, pts)) in curves.iter().enumerate() {
                let c = stage_color(i, n);
                chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
                chart.draw_series(pts.iter().map(|p| Circle::new(*p, 2, c.filled())))?;
                legend.push((format!("{h:.0} h"), Key::Marker(c)));
            }
            let mut zoom = panel(
                &right,
                &format!("Near zero: +-{:.0} % of rated torque", 100.0 * ZOOM * m),
                axes,
                -half..half,
                z0..z1,
                true,
            )?;
            let grey = RGBColor(120, 120, 120);
            zoom.draw_series(std::iter::once(Rectangle::new(
                [(-m * t, z0), (m * t, z1)],
                grey.mix(0.15).filled(),
            )))?;
            for (i, pts) in zoomed.iter().enumerate() {
                let c = stage_color(i, n);
                zoom.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
                let [neg, pos] = lost_motion[i];
                zoom.draw_series(
                    [(-m * t, neg), (m * t, pos)]
                        .into_iter()
                        .map(|p| Circle::new(p, 5, c.filled())),
                )?;
            }
            legend.push((
                format!(
                    "shaded: +-{:.0} % of rated torque; dots: the twists whose gap is the lost motion",
                    100.0 * m
                ),
                Key::Band(grey),
            ));
            legend.push((
                "frictionless contacts: loading and unloading retrace, the jump at zero torque is the backlash"
                    .to_string(),
                Key::Note,
            ));
            if negative_coincide {
                legend.push((
                    "negative torque loads the flank that does not wear: its branches coincide"
                        .to_string(),
                    Key::Note,
                ));
            }
            draw_legend(&strip, 40, &legend)?;
            Ok(())
        }
    )
}
