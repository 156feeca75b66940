//! The von Mises stress field of the flexible disc: the whole disc and a zoom on its hot spot,
//! on a logarithmic colour scale (the field spans three decades between the bulk of the disc
//! and the contact).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::*;

/// Decades of stress the colour scale spans below its top.
const DECADES: f64 = 3.0;

/// Half-width of the zoom window, as a fraction of the disc's outer radius.
const ZOOM_HALF: f64 = 0.12;

/// Position of `v` (Pa) on the logarithmic scale `[scale 10^-DECADES, scale]`, 0..1, clamped.
fn log_position(v: f64, scale: f64) -> f64 {
    let lo = scale * 10f64.powf(-DECADES);
    ((v.max(lo) / lo).log10() / DECADES).clamp(0.0, 1.0)
}

/// The polygon `poly` cut to the box `|x - c.0| <= hx`, `|y - c.1| <= hy`
/// (Sutherland-Hodgman, one edge of the box at a time): plotters would squash the parts outside
/// onto the axes.
fn clip_to_box(poly: &[(f64, f64)], c: (f64, f64), (hx, hy): (f64, f64)) -> Vec<(f64, f64)> {
    // Each edge as (axis, sign): inside where sign (p[axis] - c[axis]) <= half.
    let mut out = poly.to_vec();
    for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)] {
        let coord = |p: &(f64, f64)| if axis == 0 { p.0 - c.0 } else { p.1 - c.1 };
        let half = if axis == 0 { hx } else { hy };
        let inside = |p: &(f64, f64)| sign * coord(p) <= half;
        let input = std::mem::take(&mut out);
        for (k, b) in input.iter().enumerate() {
            let a = input[(k + input.len() - 1) % input.len()];
            let cross = || {
                let t = (sign * half - coord(&a)) / (coord(b) - coord(&a));
                (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
            };
            match (inside(&a), inside(b)) {
                (true, true) => out.push(*b),
                (true, false) => out.push(cross()),
                (false, true) => {
                    out.push(cross());
                    out.push(*b);
                }
                (false, false) => {}
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The quadratic triangles of `mesh` as four flat sub-triangles each (corners and mid-edge
/// nodes), each with its corners' mean stress: `(corners in mm, stress Pa)`.
fn patches(mesh: &crate::fem::mesh::Mesh, nodal: &[f64]) -> Vec<([(f64, f64); 3], f64)> {
    const SUB: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];
    mesh.triangles
        .iter()
        .flat_map(|t| {
            SUB.iter().map(move |s| {
                let n = s.map(|k| t[k]);
                (
                    n.map(|i| (mesh.nodes[i].x * 1e3, mesh.nodes[i].y * 1e3)),
                    (nodal[n[0]] + nodal[n[1]] + nodal[n[2]]) / 3.0,
                )
            })
        })
        .collect()
}

/// The von Mises field `nodal` (Pa, one per mesh node) on the disc mesh, written to
/// `<stem>.{svg,png}` in `dir`: left the whole disc, right a window around the largest nodal
/// stress, each triangle split at its mid-edge nodes and filled with viridis on a logarithmic
/// scale over [`DECADES`] decades up to `scale` (Pa; higher values saturate), the colour bar
/// with 1-2-5 ticks in MPa. `title` heads the figure.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn von_mises(
    mesh: &crate::fem::mesh::Mesh,
    nodal: &[f64],
    title: &str,
    scale: f64,
    dir: &Path,
    stem: &str,
) -> Result<()> {
    let r = mesh
        .nodes
        .iter()
        .map(|p| p.x.abs().max(p.y.abs()))
        .fold(0.0, f64::max)
        * 1e3
        * 1.02;
    let scale = scale.max(1.0);
    let cells = patches(mesh, nodal);
    let hot = (0..mesh.nodes.len().min(nodal.len()))
        .max_by(|a, b| nodal[*a].total_cmp(&nodal[*b]))
        .map_or((0.0, 0.0), |i| {
            (mesh.nodes[i].x * 1e3, mesh.nodes[i].y * 1e3)
        });
    let half = ZOOM_HALF * r;
    let colour = |v: f64| {
        let c = ViridisRGB::get_color_normalized(log_position(v, scale), 0.0, 1.0);
        RGBColor(c.0, c.1, c.2)
    };
    figure!(
        dir,
        stem,
        |root: &DrawingArea<_, Shift>| -> std::result::Result<(), Box<dyn std::error::Error>> {
            let (body, bar) = root.split_horizontally(SIZE.0 - 130);
            let (head, panels) = body.split_vertically(34);
            head.draw(&Text::new(
                title.to_string(),
                (10, 8),
                ("sans-serif", 17).into_font().color(&BLACK),
            ))?;
            let w = panels.dim_in_pixel().0;
            let (left, right) = panels.split_horizontally(w / 2);
            // Each panel: a caption line, then the chart at equal scales on both axes (its
            // plot area is the panel less the margins and the label areas).
            let (margin, x_area, y_area) = (8u32, 40u32, 50u32);
            let captioned = |area: &DrawingArea<_, Shift>, text: String| {
                let (cap, rest) = area.split_vertically(26);
                cap.draw(&Text::new(
                    text,
                    (y_area as i32 + 10, 4),
                    ("sans-serif", 18).into_font().color(&BLACK),
                ))
                .map(|_| rest)
            };
            let left = captioned(&left, "whole disc".to_string())?;
            let right = captioned(
                &right,
                format!("hot spot (red box on the left), {:.0} mm wide", 2.0 * half),
            )?;
            let (pw, ph) = left.dim_in_pixel();
            let (pw, ph) = (
                pw.saturating_sub(2 * margin + y_area).max(1) as f64,
                ph.saturating_sub(2 * margin + x_area).max(1) as f64,
            );
            // Half-ranges (x, y) holding `h` both ways at equal scales.
            let equal = |h: f64| {
                if ph >= pw {
                    (h, h * ph / pw)
                } else {
                    (h * pw / ph, h)
                }
            };
            let (wx, wy) = equal(r);
            let (zx, zy) = equal(half);
            let mut whole = ChartBuilder::on(&left)
                .margin(margin)
                .x_label_area_size(x_area)
                .y_label_area_size(y_area)
                .build_cartesian_2d(-wx..wx, -wy..wy)?;
            let mut zoom = ChartBuilder::on(&right)
                .margin(margin)
                .x_label_area_size(x_area)
                .y_label_area_size(y_area)
                .build_cartesian_2d(hot.0 - zx..hot.0 + zx, hot.1 - zy..hot.1 + zy)?;
            for chart in [&mut whole, &mut zoom] {
                chart
                    .configure_mesh()
                    .disable_mesh()
                    .x_desc("x (mm)")
                    .y_desc("y (mm)")
                    .label_style(("sans-serif", TICK_PX))
                    .axis_desc_style(("sans-serif", TICK_PX))
                    .x_labels(5)
                    .y_labels(5)
                    .x_label_formatter(&|v| format!("{v:.0}"))
                    .y_label_formatter(&|v| format!("{v:.0}"))
                    .draw()?;
            }
            whole.draw_series(
                cells
                    .iter()
                    .map(|(p, v)| Polygon::new(p.to_vec(), colour(*v).filled())),
            )?;
            // The window's outline on the whole disc.
            whole.draw_series(std::iter::once(Rectangle::new(
                [(hot.0 - zx, hot.1 - zy), (hot.0 + zx, hot.1 + zy)],
                RED.stroke_width(2),
            )))?;
            zoom.draw_series(cells.iter().filter_map(|(p, v)| {
                let cut = clip_to_box(p, hot, (zx, zy));
                (cut.len() >= 3).then(|| Polygon::new(cut, colour(*v).filled()))
            }))?;
            // Colour bar (logarithmic) with its ticks to the right.
            let (_, h) = bar.dim_in_pixel();
            let (top, bottom) = (70i32, h as i32 - 45);
            let (x0, x1) = (12i32, 42i32);
            let steps = 96;
            for k in 0..steps {
                let ya = bottom - (bottom - top) * k / steps;
                let yb = bottom - (bottom - top) * (k + 1) / steps;
                let c = ViridisRGB::get_color_normalized(k as f64 + 0.5, 0.0, steps as f64);
                bar.draw(&Rectangle::new(
                    [(x0, yb), (x1, ya)],
                    RGBColor(c.0, c.1, c.2).filled(),
                ))?;
            }
            bar.draw(&Rectangle::new(
                [(x0, top), (x1, bottom)],
                BLACK.stroke_width(1),
            ))?;
            let font = ("sans-serif", 15).into_font().color(&BLACK);
            bar.draw(&Text::new("von Mises", (4, top - 58), font.clone()))?;
            bar.draw(&Text::new("stress (MPa),", (4, top - 40), font.clone()))?;
            bar.draw(&Text::new("log scale", (4, top - 22), font.clone()))?;
            let max_mpa = scale * 1e-6;
            let lo_mpa = max_mpa * 10f64.powf(-DECADES);
            let mut decade = 10f64.powf(lo_mpa.log10().floor());
            while decade <= max_mpa * (1.0 + 1e-9) {
                for m in [1.0, 2.0, 5.0] {
                    let v = m * decade;
                    if v < lo_mpa * (1.0 - 1e-9) || v > max_mpa * (1.0 + 1e-9) {
                        continue;
                    }
                    let y = bottom
                        - ((bottom - top) as f64 * log_position(v * 1e6, scale)).round() as i32;
                    bar.draw(&PathElement::new(
                        vec![(x1, y), (x1 + 5, y)],
                        BLACK.stroke_width(1),
                    ))?;
                    if m != 5.0 {
                        bar.draw(&Text::new(short(v), (x1 + 8, y - 8), font.clone()))?;
                    }
                }
                decade *= 10.0;
            }
            Ok(())
        }
    )
}
