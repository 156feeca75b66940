//! The Weibull probability plot of a Monte Carlo run's accuracy lives (IEC 61649 section 9):
//! the Kaplan-Meier estimate of the fraction out of spec against hours on Weibull paper, the
//! maximum-likelihood fit as its straight line, and the fit's two-sided likelihood-ratio
//! bounds on the quantiles as the band around it.

use super::*;
use crate::montecarlo::weibull::{BoundedQuantile, Weibull};

/// The Weibull paper's ordinate of the fraction `p` out of spec: `ln(-ln(1 - p))`.
fn weibull_y(p: f64) -> f64 {
    (-(-p).ln_1p()).ln()
}

/// The fraction out of spec of the ordinate `y`, as a percentage label.
fn percent_label(y: f64) -> String {
    let p = 100.0 * -(-(y.exp())).exp_m1();
    if p >= 10.0 {
        format!("{p:.0} %")
    } else if p >= 1.0 {
        format!("{p:.1} %")
    } else {
        format!("{p:.2} %")
    }
}

/// Writes `<stem>.{svg,png}` in `dir`: the Weibull plot of the accuracy lives. `km`: the
/// Kaplan-Meier steps `(t, S(t))` of the lives (`montecarlo::weibull::kaplan_meier`), each
/// drawn at the middle of its step (`1 - (S(t-) + S(t))/2`, Hazen's plotting position, so the
/// last failure of an uncensored batch is not at 100 %); `fit` the maximum-likelihood line;
/// `bands` the quantiles with their bounds at fractions `p` (`(p, quantile)`), drawn as the
/// band's lower and upper curves where the samples bound them; `confidence` their level.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn weibull_plot(
    dir: &Path,
    stem: &str,
    km: &[(f64, f64)],
    fit: &Weibull,
    bands: &[(f64, BoundedQuantile)],
    confidence: f64,
) -> Result<()> {
    let mut before = 1.0;
    let points: Vec<(f64, f64)> = km
        .iter()
        .map(|&(t, s)| {
            let p = 1.0 - 0.5 * (before + s);
            before = s;
            (t, weibull_y(p))
        })
        .collect();
    let (p_lo, p_hi) = (0.01, 0.99);
    let hours = points
        .iter()
        .map(|p| p.0)
        .chain(bands.iter().flat_map(|(_, q)| [q.lower, q.estimate]))
        .chain([fit.quantile(p_lo), fit.quantile(p_hi)])
        .filter(|t| t.is_finite() && *t > 0.0);
    let (t_lo, t_hi) = hours.fold((f64::INFINITY, 0.0_f64), |(a, b), t| (a.min(t), b.max(t)));
    let (t_lo, t_hi) = (0.7 * t_lo, 1.4 * t_hi);
    let line: Vec<(f64, f64)> = (0..=60)
        .map(|i| p_lo * (p_hi / p_lo).powf(i as f64 / 60.0))
        .map(|p| (fit.quantile(p), weibull_y(p)))
        .filter(|(t, _)| (t_lo..=t_hi).contains(t))
        .collect();
    let lower: Vec<(f64, f64)> = bands
        .iter()
        .map(|(p, q)| (q.lower, weibull_y(*p)))
        .filter(|(t, _)| (t_lo..=t_hi).contains(t))
        .collect();
    let upper: Vec<(f64, f64)> = bands
        .iter()
        .filter_map(|(p, q)| q.upper.map(|u| (u, weibull_y(*p))))
        .filter(|(t, _)| (t_lo..=t_hi).contains(t))
        .collect();
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = ChartBuilder::on(&plot)
                .caption("Weibull plot of the accuracy lives", ("sans-serif", 22))
                .margin(15)
                .x_label_area_size(50)
                .y_label_area_size(75)
                .build_cartesian_2d((t_lo..t_hi).log_scale(), weibull_y(p_lo)..weibull_y(p_hi))?;
            chart
                .configure_mesh()
                .x_desc("accuracy life (h, logarithmic)")
                .y_desc("fraction out of spec")
                .label_style(("sans-serif", AXIS_LABEL_PX))
                .axis_desc_style(("sans-serif", AXIS_LABEL_PX))
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| percent_label(*v))
                .draw()?;
            chart.draw_series(LineSeries::new(line.iter().copied(), BLUE.stroke_width(3)))?;
            for band in [&lower, &upper] {
                chart.draw_series(DashedLineSeries::new(
                    band.iter().copied(),
                    8,
                    5,
                    BLUE.stroke_width(2),
                ))?;
            }
            chart.draw_series(
                points
                    .iter()
                    .map(|&(t, y)| Circle::new((t, y), 4, RED.filled())),
            )?;
            let legend = vec![
                (
                    format!("fit: shape {:.2}, scale {:.0} h", fit.shape, fit.scale),
                    Key::Line(BLUE),
                ),
                (
                    format!("{:.0} % likelihood-ratio bounds", 100.0 * confidence),
                    Key::Dashed(BLUE),
                ),
                ("Kaplan-Meier (mid-step)".to_string(), Key::Marker(RED)),
            ];
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's ordinate and its label are inverse: 10 % and 63.2 % (the scale) read back.
    #[test]
    fn weibull_paper_ordinate_round_trips() {
        assert_eq!(percent_label(weibull_y(0.1)), "10 %");
        assert_eq!(percent_label(weibull_y(1.0 - (-1.0f64).exp())), "63 %");
        assert!(weibull_y(1.0 - (-1.0f64).exp()).abs() < 1e-12);
        assert_eq!(percent_label(weibull_y(0.02)), "2.0 %");
    }
}
