//! The plots of a study (`plots/` of `rvlife run`): the worn profile, wear, load, TE, TE against
//! hours, hysteresis loops, the flexible disc's TE and its stress field.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::*;
use crate::study::Study;

/// Writes every plot of the study into `dir`: `profile_wear`, `wear`, `load`, `te`,
/// `te_hours`, `hysteresis` (each as SVG and PNG), and with the flexible disc
/// `flexible_te_hours` and `von_mises`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn write_all(study: &Study, dir: &Path) -> Result<()> {
    let n = study.stages.len();

    super::mesh_cycle::wear(study, dir)?;

    // 2. Profile with magnified wear: the loaded flank (root to tip) of the tooth at the top of
    //    the disc, at equal scales on both axes.
    let max_wear = study.wear.max_depths().into_iter().fold(0.0, f64::max);
    let nominal = study.model.profile()?;
    let flank = |wear: Option<&crate::geometry::WearMap>, magnify: f64| -> Vec<(f64, f64)> {
        let k = 400;
        (0..=k)
            .map(|i| {
                // Local parameter from just before the root (0) to just past the tip (pi).
                let t = std::f64::consts::PI * (-0.08 + 1.16 * i as f64 / k as f64);
                let pt = nominal.point(t);
                let h = wear.map_or(0.0, |w| w.eval(t).0) * magnify;
                let p: Vec2 = pt.p - pt.normal * h;
                let r = rotate(&p, std::f64::consts::FRAC_PI_2);
                (r.x * 1e3, r.y * 1e3)
            })
            .collect()
    };
    let outline = flank(None, 0.0);
    let (x0, x1) = series_range(outline.iter().map(|p| p.0));
    let (y0, y1) = series_range(outline.iter().map(|p| p.1));
    // The largest wear drawn as about 8 % of the flank's extent, at a 1-2-5 magnification.
    let extent_mm = (x1 - x0).max(y1 - y0);
    let magnify = if max_wear > 0.0 {
        let raw = (0.08 * extent_mm * 1e-3 / max_wear).max(1.0);
        let decade = 10f64.powf(raw.log10().floor());
        [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * decade)
            .filter(|m| *m <= raw)
            .fold(1.0, f64::max)
    } else {
        1.0
    };
    let mut tooth_profiles: Vec<Curve> = vec![("nominal".to_string(), outline, BLACK)];
    for (i, s) in study.stages.iter().enumerate().skip(1) {
        tooth_profiles.push((
            format!("{:.0} h ({:.1} um max)", s.hours, s.summary.max_wear_um),
            flank(s.wear.as_ref(), magnify),
            stage_color(i, n),
        ));
    }
    let (x0, x1) = series_range(tooth_profiles.iter().flat_map(|t| t.1.iter().map(|p| p.0)));
    let (y0, y1) = series_range(tooth_profiles.iter().flat_map(|t| t.1.iter().map(|p| p.1)));
    // Equal scales: the plot area is about (figure - legend - labels) by (figure - caption -
    // labels) px; widen the range of the axis with room to spare.
    let area_px = ((SIZE.0 - LEGEND_WIDTH - 95) as f64, (SIZE.1 - 110) as f64);
    let mm_per_px = ((x1 - x0) / area_px.0).max((y1 - y0) / area_px.1);
    let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (hx, hy) = (0.5 * mm_per_px * area_px.0, 0.5 * mm_per_px * area_px.1);
    figure!(
        dir,
        "profile_wear",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = ChartBuilder::on(&plot)
                .caption(
                    format!(
                        "Loaded flank of the top tooth, wear magnified x{magnify:.0} (equal scales)"
                    ),
                    ("sans-serif", 22),
                )
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(65)
                .build_cartesian_2d(xc - hx..xc + hx, yc - hy..yc + hy)?;
            chart
                .configure_mesh()
                .x_desc("x (mm)")
                .y_desc("y (mm), disc frame")
                .label_style(("sans-serif", TICK_PX))
                .axis_desc_style(("sans-serif", TICK_PX))
                .draw()?;
            let mut legend = Legend::new();
            for (label, pts, c) in &tooth_profiles {
                chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
                legend.push((label.clone(), Key::Line(*c)));
            }
            legend.push((
                format!("wear depth drawn x{magnify:.0} along the normal; root left, tip right"),
                Key::Note,
            ));
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )?;

    super::mesh_cycle::load(study, dir)?;
    super::mesh_cycle::te(study, dir)?;

    // 5. TE and lost motion against working hours, with the spec and the accuracy life; the
    // DTE on its own plot (its range would set the scale).
    let sums: Vec<_> = study.stages.iter().map(|s| s.summary.clone()).collect();
    let (ymin, ymax) = sums
        .iter()
        .flat_map(|s| {
            [
                s.ste_mean_arcmin,
                s.lost_motion_arcmin,
                s.backlash_arcmin,
                s.loaded_te_mean_arcmin,
                s.angular_te_arcmin,
            ]
        })
        .chain(spec_values(study, &TE_HOURS_SPEC))
        .fold((0.0f64, 0.1f64), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.06 * (ymax - ymin);
    let hmax = hours_with_life(study);
    figure!(
        dir,
        "te_hours",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = ChartBuilder::on(&plot)
                .caption(
                    "TE, backlash and lost motion against working hours",
                    ("sans-serif", 24),
                )
                .margin(15)
                .x_label_area_size(50)
                .y_label_area_size(70)
                .build_cartesian_2d(
                    -0.02 * hmax..hmax * 1.04,
                    (ymin - if ymin < 0.0 { pad } else { 0.0 })..ymax + pad,
                )?;
            chart
                .configure_mesh()
                .x_desc("working hours (h)")
                .y_desc("arcmin")
                .label_style(("sans-serif", AXIS_LABEL_PX))
                .axis_desc_style(("sans-serif", AXIS_LABEL_PX))
                .x_label_formatter(&|v| format!("{v:.0}"))
                .draw()?;
            // The STE solid and wide, the backlash dashed over it: where they coincide (no
            // elastic play at zero load) both stay visible.
            let lines: [(&str, RGBColor, StageValue); 4] = [
                ("STE mean (no load)", BLUE, |s| s.ste_mean_arcmin),
                ("lost motion (+-3 % of rated torque)", RED, |s| {
                    s.lost_motion_arcmin
                }),
                ("loaded TE mean (rated torque)", GREEN, |s| {
                    s.loaded_te_mean_arcmin
                }),
                ("angular TE (over an output revolution)", BLACK, |s| {
                    s.angular_te_arcmin
                }),
            ];
            let mut legend = stage_lines(&mut chart, &sums, &lines)?;
            chart.draw_series(DashedLineSeries::new(
                sums.iter().map(|s| (s.hours, s.backlash_arcmin)),
                7,
                5,
                CYAN.stroke_width(3),
            ))?;
            legend.push(("backlash (dashed)".to_string(), Key::Dashed(CYAN)));
            spec_and_life(&mut chart, study, &TE_HOURS_SPEC, hmax, &mut legend)?;
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )?;
    if sums.iter().all(|s| s.dte_mean_arcmin.is_some()) {
        dte_hours(&sums, dir)?;
    }
    lost_motion_sources(study, dir)?;
    angular_te_sources(study, dir)?;
    stage_drawing(study, dir)?;
    hysteresis(study, dir)?;
    if study.stages.iter().all(|s| s.flexible.is_some()) {
        flexible_te_hours(study, dir)?;
        if let Some((fl, mesh)) = study.stages.last().and_then(|s| s.flexible.as_ref()) {
            let hours = study.stages.last().map_or(0.0, |s| s.hours);
            // The crank angle within the mesh cycle, as in the load plot (the mesh repeats every
            // 360 / Zp degrees of crank angle).
            let cycle_deg = 360.0 / study.model.reducer.geometry.pins as f64;
            let crank_deg = fl.stress.crank_angle.to_degrees();
            super::stress::von_mises(
                mesh,
                &fl.stress.nodal,
                &format!(
                    "{:.0} h, {:.0} N m, crank {:.1} deg ({:.2} deg into its {:.0} deg mesh cycle): max {:.0} MPa off the pin patches",
                    hours,
                    fl.stress.torque,
                    crank_deg,
                    crank_deg.rem_euclid(cycle_deg),
                    cycle_deg,
                    fl.stress.max_von_mises * 1e-6
                ),
                fl.stress.max_von_mises,
                dir,
                "von_mises",
            )?;
        }
    }
    Ok(())
}

/// The pins' wear in the sources' plots (orange).
const PIN_COLOUR: RGBColor = RGBColor(230, 120, 0);

/// `lost_motion_sources`: each stage's lost motion stacked by its sources (elastic, assembly
/// play, bearing wear, pin wear, disc wear; docs/model.md section 6.5) against the hours, each part an
/// area between the running sums, the total lost motion as a line on top.
fn lost_motion_sources(study: &Study, dir: &Path) -> Result<()> {
    let sums: Vec<&crate::quantities::StageSummary> =
        study.stages.iter().map(|s| &s.summary).collect();
    let parts: [(&str, RGBColor, StageValue); 5] = [
        ("elastic (lost motion beyond the backlash)", BLUE, |s| {
            s.lost_motion_elastic_arcmin
        }),
        ("assembly play (new reducer's backlash)", GREEN, |s| {
            s.lost_motion_assembly_arcmin
        }),
        ("crank bearings' wear", MAGENTA, |s| {
            s.lost_motion_bearing_wear_arcmin
        }),
        ("pins' wear", PIN_COLOUR, |s| s.lost_motion_pin_wear_arcmin),
        ("discs' wear", RED, |s| s.lost_motion_disc_wear_arcmin),
    ];
    const SPEC: [(&str, RGBColor); 1] = [("lost_motion_arcmin", BLACK)];
    let ymax = sums
        .iter()
        .map(|s| s.lost_motion_arcmin)
        .chain(spec_values(study, &SPEC))
        .fold(0.05f64, f64::max);
    let hmax = hours_with_life(study);
    figure!(dir, "lost_motion_sources", |root: &DrawingArea<
        _,
        Shift,
    >|
     -> std::result::Result<
        (),
        Box<dyn std::error::Error>,
    > {
        let (plot, strip) = with_legend_strip(root);
        let mut chart = ChartBuilder::on(&plot)
            .caption("Where the lost motion comes from", ("sans-serif", 24))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(0.0..hmax * 1.02, 0.0..ymax * 1.1)?;
        chart
            .configure_mesh()
            .x_desc("working hours (h)")
            .y_desc("lost motion (arcmin), stacked by source")
            .label_style(("sans-serif", AXIS_LABEL_PX))
            .axis_desc_style(("sans-serif", AXIS_LABEL_PX))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .draw()?;
        let mut legend = Legend::new();
        let mut below: Vec<f64> = vec![0.0; sums.len()];
        for (label, c, value) in parts {
            let top: Vec<f64> = sums
                .iter()
                .zip(&below)
                .map(|(s, b)| b + value(s).max(0.0))
                .collect();
            let mut outline: Vec<(f64, f64)> =
                sums.iter().zip(&top).map(|(s, t)| (s.hours, *t)).collect();
            outline.extend(sums.iter().zip(&below).rev().map(|(s, b)| (s.hours, *b)));
            chart.draw_series(std::iter::once(Polygon::new(outline, c.mix(0.35).filled())))?;
            chart.draw_series(LineSeries::new(
                sums.iter().zip(&top).map(|(s, t)| (s.hours, *t)),
                c.stroke_width(1),
            ))?;
            legend.push((label.to_string(), Key::Band(c)));
            below = top;
        }
        chart.draw_series(LineSeries::new(
            sums.iter().map(|s| (s.hours, s.lost_motion_arcmin)),
            BLACK.stroke_width(2),
        ))?;
        legend.push((
            "lost motion (+-3 % of rated torque)".to_string(),
            Key::Line(BLACK),
        ));
        spec_and_life(&mut chart, study, &SPEC, hmax, &mut legend)?;
        draw_legend(&strip, 60, &legend)?;
        Ok(())
    })
}

/// `angular_te_sources`: each stage's angular TE and its parts against the hours (the new
/// reducer's, the change from the crank bearings', the pins' and the discs' wear; docs/model.md
/// section 6.5). Lines, not stacked areas: a peak-to-peak value's parts can be negative.
fn angular_te_sources(study: &Study, dir: &Path) -> Result<()> {
    let sums: Vec<_> = study.stages.iter().map(|s| s.summary.clone()).collect();
    let lines: [(&str, RGBColor, StageValue); 5] = [
        ("angular TE", BLACK, |s| s.angular_te_arcmin),
        ("new reducer's", GREEN, |s| s.angular_te_assembly_arcmin),
        ("change from the crank bearings' wear", MAGENTA, |s| {
            s.angular_te_bearing_wear_arcmin
        }),
        ("change from the pins' wear", PIN_COLOUR, |s| {
            s.angular_te_pin_wear_arcmin
        }),
        ("change from the discs' wear", RED, |s| {
            s.angular_te_disc_wear_arcmin
        }),
    ];
    const SPEC: [(&str, RGBColor); 1] = [("angular_te_arcmin", BLACK)];
    let h_max = hours_with_life(study);
    let (lo, hi) = series_range(
        sums.iter()
            .flat_map(|s| lines.iter().map(move |l| (l.2)(s)))
            .chain(spec_values(study, &SPEC)),
    );
    figure!(
        dir,
        "angular_te_sources",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(
                &plot,
                "Where the angular TE comes from",
                "angular TE and its parts (arcmin)",
                h_max,
                (lo.min(0.0), hi.max(1e-3)),
            )?;
            let mut legend = stage_lines(&mut chart, &sums, &lines)?;
            spec_and_life(&mut chart, study, &SPEC, h_max, &mut legend)?;
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// The accuracy quantities of `te_hours` whose `[life]` thresholds it draws, with their lines'
/// colours.
const TE_HOURS_SPEC: [(&str, RGBColor); 3] = [
    ("lost_motion_arcmin", RED),
    ("backlash_arcmin", CYAN),
    ("angular_te_arcmin", BLACK),
];

/// The `[life]` thresholds of the study on the quantities `drawn` (name, colour).
fn spec_values<'a>(
    study: &'a Study,
    drawn: &'a [(&str, RGBColor)],
) -> impl Iterator<Item = f64> + 'a {
    crate::quantities::LIFE.iter().filter_map(move |l| {
        drawn
            .iter()
            .any(|(name, _)| *name == l.quantity.name)
            .then(|| study.model.life.threshold(l.key))
            .flatten()
    })
}

/// The hours axis' end of a plot against hours: the last stage, or the accuracy life where it
/// lies beyond (found by stepping the wear on), h.
fn hours_with_life(study: &Study) -> f64 {
    let last = study.stages.last().map_or(1.0, |s| s.hours).max(1.0);
    study
        .life
        .as_ref()
        .and_then(|l| l.accuracy_life_h)
        .map_or(last, |h| last.max(h))
}

/// Draws the `[life]` thresholds on the quantities `drawn` (name, the colour of its line) as
/// dashed horizontals, and the accuracy life as a dotted black vertical with what limits it
/// (or, within spec to the horizon, a note), adding them to `legend`; `hmax` is the hours
/// axis' end (h).
fn spec_and_life<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    study: &Study,
    drawn: &[(&str, RGBColor)],
    hmax: f64,
    legend: &mut Legend,
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    // Thresholds of one value and unit share a line (lost motion and backlash at 1 arcmin):
    // the first one's colour, every label.
    let mut specs: Vec<(f64, &str, RGBColor, Vec<&str>)> = Vec::new();
    for l in &crate::quantities::LIFE {
        let Some((_, c)) = drawn.iter().find(|(name, _)| *name == l.quantity.name) else {
            continue;
        };
        let Some(v) = study.model.life.threshold(l.key) else {
            continue;
        };
        match specs
            .iter_mut()
            .find(|s| s.0 == v && s.1 == l.quantity.unit)
        {
            Some(s) => s.3.push(l.quantity.label),
            None => specs.push((v, l.quantity.unit, *c, vec![l.quantity.label])),
        }
    }
    if specs.is_empty() {
        return Ok(());
    }
    for (v, unit, c, labels) in &specs {
        chart.draw_series(DashedLineSeries::new(
            [(0.0, *v), (hmax, *v)],
            14,
            8,
            c.stroke_width(2),
        ))?;
        legend.push((
            format!("spec: {} {} {unit}", labels.join(" and "), short(*v)),
            Key::Dashed(*c),
        ));
    }
    let (y0, y1) = {
        let r = chart.plotting_area().get_y_range();
        (r.start, r.end)
    };
    if let Some(life) = &study.life {
        match life.accuracy_life_h {
            Some(h) => {
                chart.draw_series(DashedLineSeries::new(
                    [(h, y0), (h, y1)],
                    3,
                    4,
                    BLACK.stroke_width(2),
                ))?;
                let by = life
                    .limited_by
                    .and_then(|k| crate::quantities::LIFE.iter().find(|l| l.key == k))
                    .map_or(String::new(), |l| format!(" ({})", l.quantity.label));
                legend.push((format!("accuracy life {h:.0} h{by}"), Key::Dashed(BLACK)));
            }
            None => legend.push((format!("within spec to {:.0} h", life.horizon_h), Key::Note)),
        }
    }
    Ok(())
}

/// `stage`: the disc over its pins at crank angle 0 (disc frame turned with the eccentric,
/// equal scales, mm), with its crank bores and holes (those of `[fem]`), the flank worn more
/// than a fifth of the last stage's largest depth drawn thick in red; the dimensions in the
/// title.
fn stage_drawing(study: &Study, dir: &Path) -> Result<()> {
    let Some(last) = study.stages.last() else {
        return Ok(());
    };
    let m = &study.model;
    let g = &m.cycloid.geometry;
    let a = g.eccentricity * 1e3;
    let profile = &last.profile;
    let zc = g.disc_teeth();
    let n = 240 * zc;
    let dt = std::f64::consts::TAU * zc as f64 / n as f64;
    let max_wear = profile.wear().map_or(0.0, |w| w.max_depth());
    let pts: Vec<((f64, f64), bool)> = (0..=n)
        .map(|k| {
            let t = (k % n) as f64 * dt;
            let p = profile.position(t);
            let worn =
                max_wear > 0.0 && profile.wear().is_some_and(|w| w.eval(t).0 > 0.2 * max_wear);
            ((p.x * 1e3 + a, p.y * 1e3), worn)
        })
        .collect();
    let r = (g.pin_circle_radius + 2.0 * g.pin_radius) * 1e3;
    let title = format!(
        "{} pins of {} mm on a {} mm circle, {} teeth, a = {} mm, disc {} mm wide",
        g.pins,
        short(2e3 * g.pin_radius),
        short(2e3 * g.pin_circle_radius),
        zc,
        short(a),
        short(g.width * 1e3)
    );
    figure!(
        dir,
        "stage",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let (w, h) = plot.dim_in_pixel();
            let side = w.min(h);
            let (square, _) = plot.split_horizontally(side);
            let mut chart = ChartBuilder::on(&square)
                .caption(&title, ("sans-serif", 17))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(-r..r, -r..r)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("x (mm)")
                .y_desc("y (mm)")
                .label_style(("sans-serif", 14))
                .draw()?;
            let circle = |c: (f64, f64), radius: f64| -> Vec<(f64, f64)> {
                (0..=72)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / 72.0;
                        (c.0 + radius * t.cos(), c.1 + radius * t.sin())
                    })
                    .collect()
            };
            let grey = RGBColor(120, 120, 120);
            for j in 0..g.pins {
                let c = g.pin_centre(j);
                chart.draw_series(std::iter::once(Polygon::new(
                    circle((c.x * 1e3, c.y * 1e3), g.pin_radius * 1e3),
                    grey.mix(0.5).filled(),
                )))?;
            }
            let fem = &m.fem.params;
            for hole in fem.bores.iter().chain(&fem.holes) {
                chart.draw_series(LineSeries::new(
                    circle(
                        (hole.centre.x * 1e3 + a, hole.centre.y * 1e3),
                        hole.radius * 1e3,
                    ),
                    BLACK.stroke_width(1),
                ))?;
            }
            chart.draw_series(LineSeries::new(
                pts.iter().map(|p| p.0),
                BLUE.stroke_width(1),
            ))?;
            for pair in pts.windows(2) {
                if pair[0].1 && pair[1].1 {
                    chart.draw_series(LineSeries::new(
                        [pair[0].0, pair[1].0],
                        RED.stroke_width(4),
                    ))?;
                }
            }
            let mut legend = vec![
                ("disc (crank angle 0)".to_string(), Key::Line(BLUE)),
                ("pins".to_string(), Key::Band(grey)),
                ("crank bores and holes".to_string(), Key::Line(BLACK)),
            ];
            if max_wear > 0.0 {
                legend.push((
                    format!(
                        "worn beyond a fifth of {:.1} um at {:.0} h",
                        max_wear * 1e6,
                        last.hours
                    ),
                    Key::Line(RED),
                ));
            }
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// `dte_hours`: the dynamic TE's mean against working hours with its range (min to max over
/// the dynamic run) as bars, on its own scale.
fn dte_hours(sums: &[crate::quantities::StageSummary], dir: &Path) -> Result<()> {
    let h_max = sums.iter().map(|s| s.hours).fold(1.0, f64::max);
    let (lo, hi) = series_range(sums.iter().flat_map(|s| {
        let [a, b] = s.dte_range_arcmin.unwrap_or([0.0, 0.0]);
        [a, b, s.dte_mean_arcmin.unwrap_or(0.0)]
    }));
    figure!(
        dir,
        "dte_hours",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(
                &plot,
                "Dynamic TE against working hours",
                "DTE (arcmin)",
                h_max,
                (lo.min(0.0), hi),
            )?;
            let c = MAGENTA;
            chart.draw_series(LineSeries::new(
                sums.iter()
                    .map(|s| (s.hours, s.dte_mean_arcmin.unwrap_or(0.0))),
                c.stroke_width(2),
            ))?;
            let cap = 0.008 * h_max;
            chart.draw_series(sums.iter().flat_map(|s| {
                let [lo, hi] = s.dte_range_arcmin.unwrap_or([0.0, 0.0]);
                [
                    vec![(s.hours, lo), (s.hours, hi)],
                    vec![(s.hours - cap, lo), (s.hours + cap, lo)],
                    vec![(s.hours - cap, hi), (s.hours + cap, hi)],
                ]
                .map(|v| PathElement::new(v, c.stroke_width(1)))
            }))?;
            let legend = vec![
                ("DTE mean (dynamic model)".to_string(), Key::Line(c)),
                (
                    "DTE range (min to max over the dynamic run)".to_string(),
                    Key::Range(c),
                ),
            ];
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// Draws one labelled line with markers per `(label, colour, value)` against the stages' hours.
fn stage_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    sums: &[crate::quantities::StageSummary],
    lines: &[(&str, RGBColor, StageValue)],
) -> std::result::Result<Legend, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let mut legend = Legend::new();
    for (label, c, f) in lines {
        let c = *c;
        chart.draw_series(LineSeries::new(
            sums.iter().map(|s| (s.hours, f(s))),
            c.stroke_width(2),
        ))?;
        chart.draw_series(
            sums.iter()
                .map(|s| Circle::new((s.hours, f(s)), 4, c.filled())),
        )?;
        legend.push((label.to_string(), Key::Marker(c)));
    }
    Ok(legend)
}

/// Rigid against flexible TE over working hours (the paper's Fig. 19b): rigid STE, flexible
/// STE at the measuring torque, rigid and flexible loaded TE at the rated torque, written to
/// `flexible_te_hours.{svg,png}`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn flexible_te_hours(study: &Study, dir: &Path) -> Result<()> {
    let sums: Vec<_> = study.stages.iter().map(|s| s.summary.clone()).collect();
    let lines: [(&str, RGBColor, StageValue); 4] = [
        ("rigid STE mean (no load)", BLUE, |s| s.ste_mean_arcmin),
        ("flexible STE mean (measuring torque)", CYAN, |s| {
            s.flexible_ste_mean_arcmin.unwrap_or(0.0)
        }),
        ("rigid loaded TE mean (rated torque)", GREEN, |s| {
            s.rigid_loaded_te_revolution_mean_arcmin.unwrap_or(0.0)
        }),
        ("flexible loaded TE mean (rated torque)", RED, |s| {
            s.flexible_loaded_te_mean_arcmin.unwrap_or(0.0)
        }),
    ];
    let h_max = sums.iter().map(|s| s.hours).fold(1.0, f64::max);
    let (_, hi) = series_range(
        sums.iter()
            .flat_map(|s| lines.iter().map(move |l| (l.2)(s))),
    );
    figure!(
        dir,
        "flexible_te_hours",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(
                &plot,
                "Rigid against flexible disc: TE over working hours",
                "TE (arcmin)",
                h_max,
                (0.0, hi.max(1e-3)),
            )?;
            let legend = stage_lines(&mut chart, &sums, &lines)?;
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}
