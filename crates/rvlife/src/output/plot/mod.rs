//! Plots of a study (SVG and PNG, via plotters with the DejaVu Sans font embedded, so no system
//! fonts are needed).

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::geometry::{rotate, Vec2};
use crate::units::ARCMIN_PER_RAD;

const SIZE: (u32, u32) = (1000, 640);

/// Points of a polyline in plot coordinates.
type Polyline = Vec<(f64, f64)>;
/// A labelled, coloured polyline in plot coordinates.
type Curve = (String, Vec<(f64, f64)>, RGBColor);
/// A chart with `f64` axes both ways, as every plot here draws.
type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;
/// One number of a stage summary, for the against-hours plot.
type StageValue = fn(&crate::quantities::StageSummary) -> f64;

fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is valid; registration cannot fail for it.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

fn stage_color(i: usize, n: usize) -> RGBColor {
    let c = ViridisRGB::get_color_normalized(i as f64, 0.0, (n.max(2) - 1) as f64 * 1.1);
    RGBColor(c.0, c.1, c.2)
}

fn plot_err<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> Error + '_ {
    move |e| Error::io(path, std::io::Error::other(e.to_string()))
}

type Draw<'a> = dyn Fn(&DrawingArea<SVGBackend, Shift>) -> std::result::Result<(), String> + 'a;
type DrawPng<'a> =
    dyn Fn(&DrawingArea<BitMapBackend, Shift>) -> std::result::Result<(), String> + 'a;

/// Draws one figure to `<stem>.svg` and `<stem>.png` in `dir`.
fn both(dir: &Path, stem: &str, svg: &Draw, png: &DrawPng) -> Result<()> {
    register_fonts();
    let p = dir.join(format!("{stem}.svg"));
    {
        let root = SVGBackend::new(&p, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err(&p))?;
        svg(&root).map_err(plot_err(&p))?;
        root.present().map_err(plot_err(&p))?;
    }
    let p = dir.join(format!("{stem}.png"));
    let root = BitMapBackend::new(&p, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err(&p))?;
    png(&root).map_err(plot_err(&p))?;
    root.present().map_err(plot_err(&p))?;
    Ok(())
}

macro_rules! figure {
    ($dir:expr, $stem:expr, $f:expr) => {
        both(
            $dir,
            $stem,
            &|r: &DrawingArea<SVGBackend, Shift>| $f(r).map_err(|e| e.to_string()),
            &|r: &DrawingArea<BitMapBackend, Shift>| $f(r).map_err(|e| e.to_string()),
        )
    };
}

// After the macro, so that the figures of the submodules see it.
mod dynamics;
mod hysteresis;
mod mesh_cycle;
mod stress;
mod study;
mod weibull;

pub use dynamics::dynamics;
pub use hysteresis::hysteresis;
pub(crate) use study::write_all;
pub(crate) use weibull::weibull_plot;

/// Width of the legend strip at the right of every figure, px: legends never cover data.
const LEGEND_WIDTH: u32 = 235;

/// What a legend entry's sample shows.
#[derive(Debug, Clone, Copy)]
enum Key {
    /// A solid line, 2 px.
    Line(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A line with a filled circle.
    Marker(RGBColor),
    /// A shaded band (translucent fill).
    Band(RGBColor),
    /// A vertical range bar with caps.
    Range(RGBColor),
    /// No sample: a note about the plot.
    Note,
}

/// A legend: `(label, sample)` per entry, drawn in the strip beside the plot.
type Legend = Vec<(String, Key)>;

/// Splits a figure area into the plot (left) and the legend strip (right, [`LEGEND_WIDTH`]).
fn with_legend_strip<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>) {
    let w = root.dim_in_pixel().0;
    root.split_horizontally(w.saturating_sub(LEGEND_WIDTH))
}

/// Draws `entries` top-down in the legend strip `area`, starting `top` px below its top edge;
/// labels longer than a line are wrapped at spaces.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    top: i32,
    entries: &[(String, Key)],
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let line_h = 17;
    let mut y = top;
    for (label, key) in entries {
        let mut lines: Vec<String> = Vec::new();
        for word in label.split(' ') {
            match lines.last_mut() {
                Some(l) if l.len() + 1 + word.len() <= 26 => {
                    l.push(' ');
                    l.push_str(word);
                }
                _ => lines.push(word.to_string()),
            }
        }
        let yc = y + line_h / 2;
        let (x0, x1) = (6, 32);
        match *key {
            Key::Line(c) => area.draw(&PathElement::new(
                vec![(x0, yc), (x1, yc)],
                c.stroke_width(2),
            ))?,
            Key::Dashed(c) => {
                for k in 0..3 {
                    let a = x0 + k * 10;
                    area.draw(&PathElement::new(
                        vec![(a, yc), (a + 6, yc)],
                        c.stroke_width(1),
                    ))?;
                }
            }
            Key::Marker(c) => {
                area.draw(&PathElement::new(
                    vec![(x0, yc), (x1, yc)],
                    c.stroke_width(2),
                ))?;
                area.draw(&Circle::new(((x0 + x1) / 2, yc), 4, c.filled()))?;
            }
            Key::Band(c) => area.draw(&Rectangle::new(
                [(x0, yc - 6), (x1, yc + 6)],
                c.mix(0.25).filled(),
            ))?,
            Key::Range(c) => {
                let xm = (x0 + x1) / 2;
                for (a, b) in [
                    ((xm, yc - 7), (xm, yc + 7)),
                    ((xm - 4, yc - 7), (xm + 4, yc - 7)),
                ] {
                    area.draw(&PathElement::new(vec![a, b], c.stroke_width(1)))?;
                }
                area.draw(&PathElement::new(
                    vec![(xm - 4, yc + 7), (xm + 4, yc + 7)],
                    c.stroke_width(1),
                ))?;
            }
            Key::Note => {}
        }
        for (k, l) in lines.iter().enumerate() {
            area.draw(&Text::new(
                l.clone(),
                (x1 + 6, y + k as i32 * line_h),
                font.clone(),
            ))?;
        }
        y += line_h * lines.len() as i32 + 7;
    }
    Ok(())
}

fn series_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    // A constant series (a constant load, say) gets +-2 % of its magnitude, so the axis
    // ticks stay distinct.
    let pad = ((hi - lo) * 0.08)
        .max(2e-2 * hi.abs().max(lo.abs()))
        .max(1e-9);
    (lo - pad, hi + pad)
}

/// Axes of a quantity against working hours (`0 ..= 1.04 h_max` by `y`), captioned `title`,
/// the y axis labelled `y_desc`.
fn hours_axes<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    y_desc: &str,
    h_max: f64,
    y: (f64, f64),
) -> std::result::Result<Chart<'a, DB>, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(75)
        .build_cartesian_2d(0.0..h_max * 1.04, y.0..y.1)?;
    chart
        .configure_mesh()
        .x_desc("working hours (h)")
        .y_desc(y_desc)
        .label_style(("sans-serif", AXIS_LABEL_PX))
        .axis_desc_style(("sans-serif", AXIS_LABEL_PX))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .draw()?;
    Ok(chart)
}

/// Axes of one panel of a detailed plot on `area`: `caption` above, the axis titles
/// `(x_desc, y_desc)`, tick labels and titles at [`TICK_PX`], the y ticks by [`tick_label`]; with
/// `whole_x`, five x ticks as whole numbers.
fn panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    (x_desc, y_desc): (&str, &str),
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    whole_x: bool,
) -> std::result::Result<Chart<'a, DB>, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(x, y)?;
    let whole = |v: &f64| format!("{v:.0}");
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .y_label_formatter(&tick_label)
        .label_style(("sans-serif", TICK_PX))
        .axis_desc_style(("sans-serif", TICK_PX));
    if whole_x {
        mesh.x_labels(5).x_label_formatter(&whole);
    }
    mesh.draw()?;
    Ok(chart)
}

/// Size of the tick labels and axis titles of the plots against hours, px (readable at the
/// default 1000 px width).
const AXIS_LABEL_PX: u32 = 16;

/// Size of the tick labels and axis titles of the detailed plots, px (at least 12 px at the
/// default 1000 px width).
const TICK_PX: u32 = 14;

/// Draws each curve of `curves` on `chart` as a line with markers in its own colour (markers
/// alone where `joined[k]` is false; missing entries are true); returns their legend.
fn marked_curves<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    curves: &[(String, Vec<(f64, f64)>)],
    joined: &[bool],
) -> std::result::Result<Legend, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let colours = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];
    let mut legend = Legend::new();
    for (k, (label, pts)) in curves.iter().enumerate() {
        let c = colours[k % colours.len()];
        if joined.get(k).copied().unwrap_or(true) {
            chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
        }
        chart.draw_series(pts.iter().map(|p| Circle::new(*p, 4, c.filled())))?;
        legend.push((label.clone(), Key::Marker(c)));
    }
    Ok(legend)
}

/// Named curves `(label, points (hours, value))` against working hours, written to
/// `<stem>.{svg,png}` in `dir` with the caption `title` and the y-axis label `y_desc` (the
/// paper's Fig. 19b style: one line with markers per model).
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub fn curves_against_hours(
    dir: &Path,
    stem: &str,
    title: &str,
    y_desc: &str,
    curves: &[(String, Vec<(f64, f64)>)],
) -> Result<()> {
    let h_max = curves
        .iter()
        .flat_map(|c| c.1.iter().map(|p| p.0))
        .fold(1.0, f64::max);
    let (lo, hi) = series_range(curves.iter().flat_map(|c| c.1.iter().map(|p| p.1)));
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(&plot, title, y_desc, h_max, (lo.min(0.0), hi))?;
            let legend = marked_curves(&mut chart, curves, &[])?;
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// Named curves `(label, points (x, y))` against any quantity `x`, written to
/// `<stem>.{svg,png}` in `dir` with the caption `title` and the axis titles `(x_desc,
/// y_desc)`: one line with markers per curve (markers alone where `joined[k]` is false; missing
/// entries are true), each in its own colour and listed in the legend (a design sweep's
/// accuracy life against a varied key).
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn curves_against(
    dir: &Path,
    stem: &str,
    title: &str,
    axes: (&str, &str),
    curves: &[(String, Vec<(f64, f64)>)],
    joined: &[bool],
) -> Result<()> {
    let (x0, x1) = series_range(curves.iter().flat_map(|c| c.1.iter().map(|p| p.0)));
    let (lo, hi) = series_range(curves.iter().flat_map(|c| c.1.iter().map(|p| p.1)));
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = panel(&plot, title, axes, x0..x1, lo.min(0.0)..hi, false)?;
            let legend = marked_curves(&mut chart, curves, joined)?;
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// A fan chart: the median of a quantity against working hours with its 5-95 % band, written
/// to `<stem>.{svg,png}` in `dir`. `hours` and the three bands (5, 50 and 95 %) have one
/// value per stage.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn fan_chart(
    dir: &Path,
    stem: &str,
    title: &str,
    y_desc: &str,
    hours: &[f64],
    [p5, p50, p95]: [&[f64]; 3],
    spec: Option<f64>,
) -> Result<()> {
    let h_max = hours.iter().copied().fold(1.0, f64::max);
    let (lo, hi) = series_range(p5.iter().chain(p95).chain(spec.iter()).copied());
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(&plot, title, y_desc, h_max, (lo.min(0.0), hi))?;
            let mut legend = Vec::new();
            if let Some(limit) = spec {
                chart.draw_series(DashedLineSeries::new(
                    [(0.0, limit), (h_max, limit)],
                    8,
                    5,
                    RED.stroke_width(2),
                ))?;
                legend.push((format!("spec {}", short(limit)), Key::Dashed(RED)));
            }
            let band: Vec<(f64, f64)> = hours
                .iter()
                .zip(p95)
                .map(|(h, v)| (*h, *v))
                .chain(hours.iter().zip(p5).rev().map(|(h, v)| (*h, *v)))
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(band, BLUE.mix(0.2).filled())))?;
            chart.draw_series(LineSeries::new(
                hours.iter().zip(p50).map(|(h, v)| (*h, *v)),
                BLUE.stroke_width(2),
            ))?;
            legend.push(("5-95 % of the samples".to_string(), Key::Band(BLUE)));
            legend.push(("median".to_string(), Key::Line(BLUE)));
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// A tick label: up to 4 decimals, trailing zeros dropped, never `-0`.
fn tick_label(v: &f64) -> String {
    let s = short(*v);
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// A number for a legend: up to 4 significant digits.
pub(super) fn short(v: f64) -> String {
    let s = format!("{v:.4}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The reliability curve of a Monte Carlo run: the fraction of the sampled reducers within
/// spec against working hours (`curve` from [`crate::montecarlo::reliability`]), with the B10
/// and B50 lives marked where they were reached (h), written to `<stem>.{svg,png}` in `dir`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn reliability_curve(
    dir: &Path,
    stem: &str,
    curve: &[(f64, f64)],
    marks: &[(&str, Option<f64>)],
) -> Result<()> {
    let h_max = curve.iter().map(|p| p.0).fold(1.0, f64::max);
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plot, strip) = with_legend_strip(root);
            let mut chart = hours_axes(
                &plot,
                "Reliability: reducers within the accuracy spec",
                "fraction within spec",
                h_max,
                (0.0, 1.0),
            )?;
            chart.draw_series(LineSeries::new(curve.iter().copied(), BLUE.stroke_width(3)))?;
            let mut legend = vec![(
                "within spec (survivors to the horizon included)".to_string(),
                Key::Line(BLUE),
            )];
            for (k, (name, at)) in marks.iter().enumerate() {
                let Some(h) = at else {
                    continue;
                };
                let c = [RED, MAGENTA][k % 2];
                chart.draw_series(DashedLineSeries::new(
                    [(*h, 0.0), (*h, 1.0)],
                    8,
                    5,
                    c.stroke_width(2),
                ))?;
                legend.push((format!("{name} {h:.0} h"), Key::Dashed(c)));
            }
            draw_legend(&strip, 60, &legend)?;
            Ok(())
        }
    )
}

/// A histogram of `values` in `bins` equal bins, with `marks` (name, value) drawn as dashed
/// verticals (red, then magenta; the caller names them in `title`), written to
/// `<stem>.{svg,png}` in `dir`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn histogram(
    dir: &Path,
    stem: &str,
    title: &str,
    x_desc: &str,
    values: &[f64],
    bins: usize,
    marks: &[(String, f64)],
) -> Result<()> {
    let (lo, hi) = series_range(values.iter().chain(marks.iter().map(|m| &m.1)).copied());
    let bins = bins.max(1);
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in values {
        let i = (((v - lo) / width) as usize).min(bins - 1);
        counts[i] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.1;
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let mut chart = ChartBuilder::on(root)
                .caption(title, ("sans-serif", 26))
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(65)
                .build_cartesian_2d(lo..hi, 0.0..top)?;
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc("samples")
                .label_style(("sans-serif", TICK_PX))
                .axis_desc_style(("sans-serif", TICK_PX))
                .draw()?;
            chart.draw_series(counts.iter().enumerate().map(|(i, &c)| {
                let x0 = lo + i as f64 * width;
                Rectangle::new([(x0, 0.0), (x0 + width, c as f64)], BLUE.mix(0.5).filled())
            }))?;
            // The marks (named in the caller's title, red then magenta): dashed verticals.
            for (k, (_, x)) in marks.iter().enumerate() {
                let c = [RED, MAGENTA][k % 2];
                chart.draw_series(DashedLineSeries::new(
                    [(*x, 0.0), (*x, top)],
                    8,
                    5,
                    c.stroke_width(2),
                ))?;
            }
            Ok(())
        }
    )
}

/// `calibration.{svg,png}`: the measured values (markers) and the fitted model (line) of every
/// measured quantity against working hours, one panel per quantity, with the fitted Archard
/// coefficient and its interval in the title ([`crate::calibration`]).
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub fn calibration(cal: &crate::calibration::Calibration, dir: &Path) -> Result<()> {
    let k = &cal.archard_coefficient_mm3_per_n_m;
    let mut title = format!(
        "Calibration: k = {:.4e} mm^3/(N m), {:.0} % CI [{:.4e}, {:.4e}]",
        k.value,
        cal.confidence * 100.0,
        k.lower,
        k.upper
    );
    if let Some(b) = &cal.running_in_backlash_arcmin {
        title.push_str(&format!(", b0 = {:.3} arcmin", b.value));
    }
    let colours = [RED, BLUE, GREEN, MAGENTA];
    figure!(
        dir,
        "calibration",
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (plots, strip) = with_legend_strip(root);
            let areas = plots.split_evenly((cal.curves.len().max(1), 1));
            let strips = strip.split_evenly((cal.curves.len().max(1), 1));
            for (i, ((curve, area), strip)) in cal
                .curves
                .iter()
                .zip(areas.iter())
                .zip(strips.iter())
                .enumerate()
            {
                let c = colours[i % colours.len()];
                let measured: Vec<(f64, f64)> = cal
                    .residuals
                    .iter()
                    .filter(|r| r.column == curve.column)
                    .map(|r| (r.hours, r.measured))
                    .collect();
                let h_end = curve.hours.last().copied().unwrap_or(1.0).max(1e-6);
                let (lo, hi) = series_range(
                    curve
                        .values
                        .iter()
                        .copied()
                        .chain(measured.iter().map(|p| p.1)),
                );
                let mut b = ChartBuilder::on(area);
                b.margin(12).x_label_area_size(40).y_label_area_size(75);
                if i == 0 {
                    b.caption(title.as_str(), ("sans-serif", 22));
                }
                let mut chart = b.build_cartesian_2d(0.0..h_end, lo.min(0.0)..hi)?;
                chart
                    .configure_mesh()
                    .x_desc("working hours (h)")
                    .y_desc(format!("{} ({})", curve.column, curve.unit))
                    .label_style(("sans-serif", TICK_PX))
                    .axis_desc_style(("sans-serif", TICK_PX))
                    .draw()?;
                chart.draw_series(LineSeries::new(
                    curve
                        .hours
                        .iter()
                        .copied()
                        .zip(curve.values.iter().copied()),
                    c.stroke_width(2),
                ))?;
                chart.draw_series(measured.iter().map(|&p| Circle::new(p, 4, BLACK.filled())))?;
                let legend = vec![
                    ("fitted model".to_string(), Key::Line(c)),
                    ("measured".to_string(), Key::Marker(BLACK)),
                ];
                draw_legend(strip, if i == 0 { 50 } else { 15 }, &legend)?;
            }
            Ok(())
        }
    )
}
