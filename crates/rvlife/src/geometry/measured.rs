//! Measured disc profiles (`[cycloid] measured_profile`): points measured on one or more teeth,
//! fitted as a normal deviation map over the profile the config describes (nominal geometry
//! with its modifications), which then replaces that profile everywhere: contact, TE, the
//! starting point of the wear study.
//!
//! **Fit.** Each point is projected on the described profile ([`Profile::project`], from the
//! nearest of 64 samples per tooth): its mesh angle and signed normal deviation (positive where
//! material is missing, the sign of wear). The deviation map is the same periodic cubic spline
//! on the wear grid as a wear map ([`WearMap`]), its node values fitted to the points by least
//! squares (the spline is linear in them; several teeth's points fall on one tooth's grid),
//! with a light penalty on second differences where the points leave nodes undetermined.
//! A profile that is such a spline (a profile rvlife wrote) is recovered to round-off. The fit
//! residual is each point's deviation minus the map's there: measurement noise, and
//! tooth-to-tooth differences that a one-tooth map cannot hold.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};

use crate::geometry::{mesh_angle, Profile, Vec2, WearMap};

/// Key of the measured profile in the config.
pub(crate) const KEY: &str = "cycloid.measured_profile";

/// Largest normal distance (m) of a measured point from the described profile: 0.3 mm (wear
/// and manufacturing deviations are tens of micrometres; beyond this the points are in other
/// units or another frame).
pub(crate) const MAX_DEVIATION: f64 = 0.3e-3;

/// Fewest points accepted.
pub(crate) const MIN_POINTS: usize = 20;

/// A measured profile fitted as a normal deviation map.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredProfile {
    /// The file read.
    pub source: PathBuf,
    /// Deviation along the inward normal on the uniform mesh-angle grid (`n` points per tooth,
    /// `deviation[m]` at `2 pi m / n`), m; positive where material is missing.
    pub deviation: Vec<f64>,
    /// Points read.
    pub points: usize,
    /// RMS of the points' residual from the fitted map, m.
    pub fit_rms: f64,
    /// Largest residual, m.
    pub fit_max: f64,
}

fn bad(path: &Path, allowed: impl Into<String>) -> Error {
    Error::invalid(KEY, format!("\"{}\"", path.display()), allowed.into())
}

/// Reads the points (m, disc frame) of a CSV file with columns `x_mm` and `y_mm` (others
/// ignored; the format `rvlife profile --out x.csv` writes) or of a DXF file's LWPOLYLINE and
/// POLYLINE vertices (mm).
///
/// # Errors
/// [`Error::Invalid`] naming [`KEY`] and the file: missing or unreadable file, no `x_mm`/`y_mm`
/// columns, a value that is not a finite number, fewer than [`MIN_POINTS`] points.
pub(crate) fn read_points(path: &Path) -> Result<Vec<Vec2>> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let pts = if ext == "dxf" {
        let mut file = crate::input::open(path)
            .map_err(|e| bad(path, format!("must be a readable DXF file ({e})")))?;
        let drawing = dxf::Drawing::load(&mut file)
            .map_err(|e| bad(path, format!("must be a readable DXF file ({e})")))?;
        let mut pts = Vec::new();
        for ent in drawing.entities() {
            match &ent.specific {
                dxf::entities::EntityType::LwPolyline(p) => {
                    pts.extend(p.vertices.iter().map(|v| Vec2::new(v.x, v.y) * 1e-3));
                }
                dxf::entities::EntityType::Polyline(p) => {
                    pts.extend(
                        p.vertices()
                            .map(|v| Vec2::new(v.location.x, v.location.y) * 1e-3),
                    );
                }
                _ => {}
            }
        }
        pts
    } else {
        let file = crate::input::open(path).map_err(|e| {
            bad(
                path,
                format!("must be a readable CSV file with columns x_mm, y_mm ({e})"),
            )
        })?;
        let mut rd = csv::Reader::from_reader(file);
        let headers = rd
            .headers()
            .map_err(|e| bad(path, format!("must start with a header line ({e})")))?
            .clone();
        let col = |name: &str| headers.iter().position(|h| h.trim() == name);
        let (Some(ix), Some(iy)) = (col("x_mm"), col("y_mm")) else {
            return Err(bad(
                path,
                format!(
                    "must have columns x_mm and y_mm (found {:?})",
                    headers.iter().collect::<Vec<_>>()
                ),
            ));
        };
        let mut pts = Vec::new();
        for (i, row) in rd.records().enumerate() {
            let row = row.map_err(|e| bad(path, format!("row {}: {e}", i + 2)))?;
            let num = |j: usize| -> Result<f64> {
                let f = row.get(j).unwrap_or("").trim();
                f.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        bad(
                            path,
                            format!("row {}: \"{f}\" must be a finite number", i + 2),
                        )
                    })
            };
            pts.push(Vec2::new(num(ix)?, num(iy)?) * 1e-3);
        }
        pts
    };
    if pts.len() < MIN_POINTS {
        return Err(bad(
            path,
            format!(
                "holds {} points; at least {MIN_POINTS} are needed",
                pts.len()
            ),
        ));
    }
    Ok(pts)
}

/// Fits `points` (m, disc frame) as a normal deviation map over `profile` (the described
/// profile, without wear) on a grid of `n` mesh angles (module documentation).
///
/// # Errors
/// [`Error::Invalid`] naming `KEY` and `source`: a point farther than `MAX_DEVIATION` from
/// the profile (with its distance), or a mesh-angle range without points.
pub fn fit(profile: &Profile, points: &[Vec2], n: usize, source: &Path) -> Result<MeasuredProfile> {
    let tau = std::f64::consts::TAU;
    let zc = profile.geometry().disc_teeth();
    let per_tooth = 64;
    let m_samples = per_tooth * zc;
    let dt = tau * zc as f64 / m_samples as f64;
    let samples: Vec<(f64, Vec2)> = (0..m_samples)
        .map(|k| {
            let t = k as f64 * dt;
            (t, profile.position(t))
        })
        .collect();
    let mut obs: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for q in points {
        let (t0, _) = samples
            .iter()
            .min_by(|a, b| {
                (a.1 - q)
                    .norm_squared()
                    .total_cmp(&(b.1 - q).norm_squared())
            })
            .expect("samples");
        let pr = profile.project(q, *t0).map_err(|e| {
            bad(
                source,
                format!("a point cannot be placed on the profile ({e})"),
            )
        })?;
        if pr.distance.abs() > MAX_DEVIATION {
            return Err(bad(
                source,
                format!(
                    "the point ({:.4}, {:.4}) mm lies {:.4} mm from the profile the config \
                     describes; points must be within {:.1} mm of it (millimetres, in the disc's \
                     frame as `rvlife profile --out` writes them)",
                    q.x * 1e3,
                    q.y * 1e3,
                    pr.distance.abs() * 1e3,
                    MAX_DEVIATION * 1e3
                ),
            ));
        }
        obs.push((mesh_angle(pr.point.t), -pr.distance));
    }
    obs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let step = tau / n as f64;
    // Coverage: every grid interval needs a point within two grid steps.
    for m in 0..n {
        let x = step * m as f64;
        let wrap = |d: f64| d - tau * (d / tau).round();
        if !obs.iter().any(|&(a, _)| wrap(a - x).abs() <= 2.0 * step) {
            return Err(bad(
                source,
                format!(
                    "has no points near mesh angle {:.1} deg: the points must cover a whole \
                     tooth (0-360 deg of mesh angle, a point every {:.2} deg)",
                    x.to_degrees(),
                    (2.0 * step).to_degrees()
                ),
            ));
        }
    }
    // The map is the wear map's periodic cubic spline through its node values, linear in them:
    // least squares on the node values (normal equations, Cholesky), each basis function the
    // spline of a unit node.
    let basis: Vec<WearMap> = (0..n)
        .map(|m| {
            let mut e = vec![0.0; n];
            e[m] = 1.0;
            WearMap::deviation(e)
        })
        .collect::<Result<_>>()?;
    // Points within a sixteenth of a grid step in mesh angle (the same point on several
    // teeth) are one observation: their mean, weighted by their number.
    let mut groups: Vec<(f64, f64, f64)> = Vec::new();
    for &(t, v) in &obs {
        match groups.last_mut() {
            Some(g) if t - g.0 / g.2 < step / 16.0 => {
                g.0 += t;
                g.1 += v;
                g.2 += 1.0;
            }
            _ => groups.push((t, v, 1.0)),
        }
    }
    let a = DMatrix::from_fn(groups.len(), n, |i, m| {
        let g = groups[i];
        basis[m].eval(g.0 / g.2).0 * g.2.sqrt()
    });
    let y = DVector::from_iterator(groups.len(), groups.iter().map(|g| g.1 / g.2.sqrt()));
    let mut ata = a.transpose() * &a;
    let aty = a.transpose() * &y;
    // Where the points are sparser than the grid (a profile sampled at fewer mesh angles than
    // the grid has nodes) the node values are not all determined: a light penalty on the
    // periodic second differences, 1e-6 of the data's weight, picks the smoothest map among
    // those that fit the points.
    let lambda = 1e-6 * ata.trace() / n as f64;
    for m in 0..n {
        let idx = [(m + n - 1) % n, m, (m + 1) % n];
        let w = [1.0, -2.0, 1.0];
        for (i, wi) in idx.iter().zip(w) {
            for (j, wj) in idx.iter().zip(w) {
                ata[(*i, *j)] += lambda * wi * wj;
            }
        }
    }
    let deviation: Vec<f64> = ata
        .cholesky()
        .ok_or_else(|| {
            bad(
                source,
                "the points do not determine the deviation map (too few or bunched)",
            )
        })?
        .solve(&aty)
        .iter()
        .copied()
        .collect();
    let map = WearMap::deviation(deviation.clone())?;
    let at = |t: f64| map.eval(t).0;
    let res: Vec<f64> = obs.iter().map(|&(a, v)| v - at(a)).collect();
    let fit_rms = (res.iter().map(|r| r * r).sum::<f64>() / res.len() as f64).sqrt();
    let fit_max = res.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    Ok(MeasuredProfile {
        source: source.to_path_buf(),
        deviation,
        points: points.len(),
        fit_rms,
        fit_max,
    })
}
