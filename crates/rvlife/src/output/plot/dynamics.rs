//! The plots of a dynamic simulation (`plots/` of `rvlife dynamics --out`): speeds and TE
//! against time.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::*;

/// Draws a time history: one panel per group of curves, sharing the time axis.
fn time_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    panels: &[(&str, Vec<Curve>)],
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let (plots, strip) = with_legend_strip(root);
    let areas = plots.split_evenly((panels.len(), 1));
    let strips = strip.split_evenly((panels.len(), 1));
    for (k, (((ylabel, curves), area), strip)) in panels
        .iter()
        .zip(areas.iter())
        .zip(strips.iter())
        .enumerate()
    {
        let t_end = curves
            .iter()
            .flat_map(|c| c.1.last().map(|p| p.0))
            .fold(0.0, f64::max)
            .max(1e-6);
        let (lo, hi) = series_range(curves.iter().flat_map(|c| c.1.iter().map(|p| p.1)));
        let mut b = ChartBuilder::on(area);
        b.margin(12).x_label_area_size(40).y_label_area_size(75);
        if k == 0 {
            b.caption(title, ("sans-serif", 24));
        }
        let mut chart = b.build_cartesian_2d(0.0..t_end, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc(*ylabel)
            .label_style(("sans-serif", TICK_PX))
            .axis_desc_style(("sans-serif", TICK_PX))
            .draw()?;
        let mut legend = Legend::new();
        for (label, pts, c) in curves {
            chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(1)))?;
            legend.push((label.clone(), Key::Line(*c)));
        }
        draw_legend(strip, if k == 0 { 50 } else { 15 }, &legend)?;
    }
    Ok(())
}

/// Writes the plots of one dynamic simulation into `dir`: `speeds` (input and output speed,
/// paper Figs 11 and 14) and `te` (TE and load against time, paper Figs 12 and 15), SVG and PNG.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub fn dynamics(res: &crate::dynamics::DynamicsResult, dir: &Path) -> Result<()> {
    let s = &res.samples;
    let line = |f: fn(&crate::dynamics::Sample) -> f64| -> Polyline {
        s.iter().map(|x| (x.time_s, f(x))).collect()
    };
    let speeds = [
        (
            "input speed (deg/s)",
            vec![("input".to_string(), line(|x| x.input_speed_deg_s), BLUE)],
        ),
        (
            "output speed (deg/s)",
            vec![("output".to_string(), line(|x| x.output_speed_deg_s), RED)],
        ),
    ];
    figure!(dir, "speeds", |root: &DrawingArea<_, Shift>| {
        time_panels(root, "Input and output speeds", &speeds)
    })?;
    let sm = &res.summary;
    let te = [
        (
            "TE (arcmin)",
            vec![(
                format!(
                    "TE: mean {:.3}, p-p {:.3} arcmin over {}-{} s",
                    sm.te_mean_arcmin,
                    sm.te_peak_to_peak_arcmin,
                    sm.window_start_s,
                    sm.window_end_s
                ),
                line(|x| x.te_arcmin),
                BLUE,
            )],
        ),
        (
            "load (N m)",
            vec![("output load".to_string(), line(|x| x.load_nm), BLACK)],
        ),
    ];
    figure!(dir, "te", |root: &DrawingArea<_, Shift>| {
        time_panels(root, "Dynamic transmission error", &te)
    })
}
