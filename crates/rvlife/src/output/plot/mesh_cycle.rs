//! The plots of a study over the mesh cycle: the wear along the tooth, the pins' load at one
//! crank angle, and the STE (over the mesh cycle, or over the output revolution with part
//! errors).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::*;
use crate::study::Study;
use crate::te::{input_deg, over_revolution};

/// `wear.{svg,png}`: the wear depth along the tooth profile (mesh angle) of every stage. The
/// axis spans the worn part of the profile (to the nearest 10 deg); a note names the part left
/// out as unworn.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(super) fn wear(study: &Study, dir: &Path) -> Result<()> {
    let n = study.stages.len();
    let angles: Vec<f64> = study.wear.angles().iter().map(|a| a.to_degrees()).collect();
    let wear_max = study
        .wear
        .max_depths()
        .into_iter()
        .fold(0.0, f64::max)
        .max(1e-9)
        * 1e6;
    // The worn range: where any stage's depth exceeds 0.1 % of the largest.
    let worn: Vec<f64> = angles
        .iter()
        .enumerate()
        .filter(|(k, _)| {
            study
                .wear
                .maps
                .iter()
                .any(|m| m[*k] * 1e6 > 1e-3 * wear_max)
        })
        .map(|(_, a)| *a)
        .collect();
    let (lo, hi) = match (worn.first(), worn.last()) {
        (Some(a), Some(b)) if study.wear.max_depths().iter().any(|d| *d > 0.0) => (
            (10.0 * ((a - 5.0) / 10.0).floor()).max(0.0),
            (10.0 * ((b + 5.0) / 10.0).ceil()).min(360.0),
        ),
        _ => (0.0, 360.0),
    };
    let hours: Vec<f64> = study.stages.iter().map(|s| s.hours).collect();
    figure!(
        dir,
        "wear",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = ChartBuilder::on(&plot)
                .caption("Wear depth along the tooth profile", ("sans-serif", 24))
                .margin(15)
                .x_label_area_size(50)
                .y_label_area_size(65)
                .build_cartesian_2d(lo..hi, 0.0..wear_max * 1.08)?;
            chart
                .configure_mesh()
                .x_desc("mesh angle (deg): 0 root, 180 tip, 360 root")
                .y_desc("wear depth (um)")
                .label_style(("sans-serif", TICK_PX))
                .axis_desc_style(("sans-serif", TICK_PX))
                .x_label_formatter(&|v| format!("{v:.0}"))
                .draw()?;
            let mut legend = Legend::new();
            for (i, map) in study.wear.maps.iter().enumerate() {
                let c = stage_color(i, n);
                chart.draw_series(LineSeries::new(
                    angles
                        .iter()
                        .zip(map)
                        .filter(|(a, _)| (lo..=hi).contains(*a))
                        .map(|(a, h)| (*a, h * 1e6)),
                    c.stroke_width(2),
                ))?;
                legend.push((format!("{:.0} h", hours[i]), Key::Line(c)));
            }
            legend.push((
                "0-180 deg: the flank loaded by positive torque; 180-360: by negative".to_string(),
                Key::Note,
            ));
            if lo > 0.0 || hi < 360.0 {
                legend.push((
                    format!("not drawn: unworn outside {lo:.0}-{hi:.0} deg"),
                    Key::Note,
                ));
            }
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// The pins of `forces` (`(pin, N)` of every stage, `zp` pins) that carry load at some stage,
/// as one arc of the pin ring: `(first pin, count)`, the arc the shortest that holds them all
/// (it may wrap past pin `zp - 1`). `(0, zp)` when no pin is loaded.
fn loaded_arc(forces: &[Vec<f64>], zp: usize) -> (usize, usize) {
    let loaded: Vec<bool> = (0..zp).map(|j| forces.iter().any(|f| f[j] > 0.0)).collect();
    if !loaded.iter().any(|l| *l) {
        return (0, zp);
    }
    // The longest run of unloaded pins, around the ring.
    let (mut best, mut best_end, mut run) = (0, 0, 0);
    for k in 0..2 * zp {
        if loaded[k % zp] {
            run = 0;
        } else {
            run += 1;
            if run > best && run <= zp {
                best = run;
                best_end = k;
            }
        }
    }
    if best == 0 {
        return (0, zp);
    }
    ((best_end + 1) % zp, zp - best)
}

/// `load.{svg,png}`: the force on each pin of disc 1 at the rated torque, every stage at one
/// crank angle (the last stage's largest pin force), over the arc of pins that carry load.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(super) fn load(study: &Study, dir: &Path) -> Result<()> {
    let n = study.stages.len();
    let last = study.stages.last().expect("at least one stage");
    let zp = last.profile.geometry().pins;
    // One crank angle for every stage: the last stage's of its largest pin force.
    let k = (0..last.loaded.solutions.len())
        .max_by(|a, b| {
            let f = |i: usize| last.loaded.solutions[i].max_force();
            f(*a).total_cmp(&f(*b))
        })
        .unwrap_or(0);
    let crank_deg = last.loaded.crank_angle[k].to_degrees();
    let forces: Vec<Vec<f64>> = study
        .stages
        .iter()
        .map(|s| {
            let mut f = vec![0.0; zp];
            for p in &s.loaded.solutions[k].discs[0].pins {
                f[p.pin] = p.force;
            }
            f
        })
        .collect();
    let fmax = forces.iter().flatten().copied().fold(1.0, f64::max);
    let (first, count) = loaded_arc(&forces, zp);
    // Position along the arc: one pin either side of it.
    let span = (count + 2).min(zp);
    let start = (first + zp - (span - count) / 2) % zp;
    let along = |j: usize| ((j + zp - start) % zp) as f64;
    let label = move |x: &f64| format!("{}", (start + x.round() as usize) % zp);
    let torque = study.model.te.loaded_torque;
    figure!(
        dir,
        "load",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = ChartBuilder::on(&plot)
                .caption(
                    format!("Pin forces on disc 1 at {torque:.0} N m, crank {crank_deg:.2} deg"),
                    ("sans-serif", 22),
                )
                .margin(15)
                .x_label_area_size(50)
                .y_label_area_size(70)
                .build_cartesian_2d(-0.5..span as f64 - 0.5, 0.0..fmax * 1.1)?;
            chart
                .configure_mesh()
                .x_desc("pin number j (counter-clockwise from the +x axis)")
                .y_desc("pin force (N)")
                .label_style(("sans-serif", TICK_PX))
                .axis_desc_style(("sans-serif", TICK_PX))
                .x_labels(span.min(25))
                .x_label_formatter(&label)
                .y_label_formatter(&|v| format!("{v:.0}"))
                .draw()?;
            let mut legend = Legend::new();
            for (i, (s, f)) in study.stages.iter().zip(&forces).enumerate() {
                let c = stage_color(i, n);
                let pts: Vec<(f64, f64)> = {
                    let mut p: Vec<(f64, f64)> = (0..zp)
                        .filter(|j| along(*j) < span as f64)
                        .map(|j| (along(j), f[j]))
                        .collect();
                    p.sort_by(|a, b| a.0.total_cmp(&b.0));
                    p
                };
                chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
                chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))?;
                legend.push((format!("{:.0} h", s.hours), Key::Marker(c)));
            }
            legend.push((
                format!(
                    "one crank angle for every stage: that of the largest pin force at {:.0} h",
                    last.hours
                ),
                Key::Note,
            ));
            if span < zp {
                legend.push((
                    format!("the other {} pins carry no load", zp - span),
                    Key::Note,
                ));
            }
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// `te.{svg,png}`: the static TE. Without part errors every mesh cycle of an output
/// revolution is the same: the forward STE (the flank that wears) over two mesh cycles on
/// top, the reverse below, each on its own scale. With part errors the top panel is the
/// forward STE over the output revolution (the mean over each bin of whole mesh cycles per
/// stage, the ripple's range in each bin for the last stage) and the bottom its first three
/// mesh cycles, both directions.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(super) fn te(study: &Study, dir: &Path) -> Result<()> {
    let n = study.stages.len();
    let hours: Vec<f64> = study.stages.iter().map(|s| s.hours).collect();
    let zp = study.model.reducer.geometry.pins;
    let ratio = study.model.reducer.ratio;
    let period = std::f64::consts::TAU / zp as f64;
    let with_errors = study.stages.iter().all(|s| s.revolution.is_some());
    // Mesh cycles drawn: in input degrees (the input angle of crank angle phi is i_H phi / Zc).
    let cycles = if with_errors { 3usize } else { 2 };
    let mesh_cycles = |s: &crate::study::Stage, v: &[f64]| -> Polyline {
        let (x, y) = over_revolution(&s.ste.crank_angle, v, zp, ratio);
        x.into_iter()
            .zip(y)
            .take(cycles * v.len())
            .map(|(x, y)| (x, y * ARCMIN_PER_RAD))
            .collect()
    };
    // With part errors, the revolution's own first mesh cycles (the same definition as the
    // top panel: rigid first contacts with the errors, section 10.2); without, the mesh cycle.
    let first_cycles = |s: &crate::study::Stage,
                        pick: fn(&crate::te::RevolutionTe) -> &Vec<f64>| {
        s.revolution.as_ref().map(|rev| -> Polyline {
            let n = cycles * rev.crank_angle.len() / (zp * (zp - 1));
            rev.crank_angle
                .iter()
                .zip(pick(rev))
                .take(n)
                .map(|(phi, y)| (input_deg(*phi, zp, ratio), y * ARCMIN_PER_RAD))
                .collect()
        })
    };
    let forward: Vec<Polyline> = study
        .stages
        .iter()
        .map(|s| first_cycles(s, |r| &r.forward).unwrap_or_else(|| mesh_cycles(s, &s.ste.forward)))
        .collect();
    let reverse: Vec<Polyline> = study
        .stages
        .iter()
        .map(|s| first_cycles(s, |r| &r.reverse).unwrap_or_else(|| mesh_cycles(s, &s.ste.reverse)))
        .collect();
    let zoom_end = input_deg(cycles as f64 * period, zp, ratio);
    let range = |c: &[Polyline]| series_range(c.iter().flatten().map(|p| p.1));
    // With part errors: per stage, (bin centre deg, min, mean, max) in arcmin over the output
    // revolution, in the most bins (at most 360) holding a whole number of mesh cycles each.
    let all_cycles = zp * (zp - 1);
    let bins = (1..=all_cycles.min(360))
        .rev()
        .find(|b| all_cycles % b == 0)
        .unwrap_or(1);
    let envelopes: Vec<Vec<[f64; 4]>> = study
        .stages
        .iter()
        .filter_map(|s| s.revolution.as_ref())
        .map(|rev| {
            let per_cycle = rev.crank_angle.len() / all_cycles;
            let mut acc = vec![(f64::INFINITY, 0.0, f64::NEG_INFINITY, 0usize); bins];
            for (k, yi) in rev.forward.iter().enumerate() {
                let b = (k / per_cycle.max(1) * bins / all_cycles).min(bins - 1);
                let v = yi * ARCMIN_PER_RAD;
                let a = &mut acc[b];
                *a = (a.0.min(v), a.1 + v, a.2.max(v), a.3 + 1);
            }
            acc.iter()
                .enumerate()
                .filter(|(_, a)| a.3 > 0)
                .map(|(b, a)| {
                    let centre = (b as f64 + 0.5) * 360.0 / bins as f64;
                    [centre, a.0, a.1 / a.3 as f64, a.2]
                })
                .collect()
        })
        .collect();
    figure!(
        dir,
        "te",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plots, strip) = with_legend_strip(root);
            let (top, bottom) = plots.split_vertically(SIZE.1 / 2);
            let mut legend = Legend::new();
            let grey = RGBColor(90, 90, 90);
            if with_errors {
                let (t0, t1) = series_range(envelopes.iter().flatten().flat_map(|e| [e[1], e[3]]));
                let mut chart = panel(
                    &top,
                    &format!("Forward STE over one output revolution ({all_cycles} mesh cycles)"),
                    (
                        &format!("output angle (deg) = input angle / {ratio:.0}"),
                        "STE (arcmin)",
                    ),
                    0.0..360.0,
                    t0..t1,
                    false,
                )?;
                for (i, env) in envelopes.iter().enumerate() {
                    let c = stage_color(i, n);
                    if i + 1 == envelopes.len() {
                        let band: Vec<(f64, f64)> = env
                            .iter()
                            .map(|e| (e[0], e[3]))
                            .chain(env.iter().rev().map(|e| (e[0], e[1])))
                            .collect();
                        chart.draw_series(std::iter::once(Polygon::new(
                            band,
                            c.mix(0.25).filled(),
                        )))?;
                    }
                    chart.draw_series(LineSeries::new(
                        env.iter().map(|e| (e[0], e[2])),
                        c.stroke_width(2),
                    ))?;
                }
            } else {
                let (f0, f1) = range(&forward);
                let mut chart = panel(
                    &top,
                    &format!("Forward STE (the flank that wears), {cycles} mesh cycles"),
                    ("input angle (deg)", "STE (arcmin)"),
                    0.0..zoom_end,
                    f0..f1,
                    false,
                )?;
                for (i, f) in forward.iter().enumerate() {
                    let c = stage_color(i, n);
                    chart.draw_series(LineSeries::new(f.iter().copied(), c.stroke_width(2)))?;
                }
            }
            let (r0, r1) = if with_errors {
                let (a, b) = range(&forward);
                let (c, d) = range(&reverse);
                (a.min(c), b.max(d))
            } else {
                range(&reverse)
            };
            let caption = if with_errors {
                format!("{cycles} mesh cycles, forward and reverse")
            } else {
                format!("Reverse STE (the flank loaded by negative torque), {cycles} mesh cycles")
            };
            let mut chart = panel(
                &bottom,
                &caption,
                ("input angle (deg)", "STE (arcmin)"),
                0.0..zoom_end,
                r0..r1,
                false,
            )?;
            for (i, (f, r)) in forward.iter().zip(&reverse).enumerate() {
                let c = stage_color(i, n);
                if with_errors {
                    chart.draw_series(LineSeries::new(f.iter().copied(), c.stroke_width(2)))?;
                    chart.draw_series(DashedLineSeries::new(
                        r.iter().copied(),
                        6,
                        4,
                        c.stroke_width(1),
                    ))?;
                } else {
                    chart.draw_series(LineSeries::new(r.iter().copied(), c.stroke_width(2)))?;
                }
                legend.push((format!("{:.0} h", hours[i]), Key::Line(c)));
            }
            if with_errors {
                legend.push((
                    format!(
                        "top: mean over each {:.2} deg bin of whole mesh cycles; band: the ripple's range, {:.0} h",
                        360.0 / bins as f64,
                        hours.last().copied().unwrap_or(0.0)
                    ),
                    Key::Band(stage_color(n - 1, n)),
                ));
                legend.push((
                    "STE with part errors: rigid first contacts over the revolution".to_string(),
                    Key::Note,
                ));
                legend.push(("bottom: forward (solid)".to_string(), Key::Line(grey)));
                legend.push((
                    "bottom: reverse direction (dashed)".to_string(),
                    Key::Dashed(grey),
                ));
            } else {
                legend.push((
                    "no part errors: every mesh cycle of the output revolution is the same, the angular TE is the forward STE's peak-to-peak"
                        .to_string(),
                    Key::Note,
                ));
            }
            draw_legend(&strip, 40, &legend)?;
            Ok(())
        }
    )
}
