//! Export of a disc profile (nominal, modified or worn) to CSV, DXF and SVG.
//!
//! - CSV: `x_mm,y_mm,mesh_angle_deg,wear_um`, one row per point, clockwise, closed implicitly.
//! - DXF: one closed `LWPOLYLINE` in millimetres, header version AutoCAD 2000 (the R12 default
//!   of the `dxf` crate silently drops LWPOLYLINE), so it opens in CAD as a closed polyline.
//! - SVG: the closed outline in millimetres, y up, with the pin circle for reference.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::geometry::{mesh_angle, Profile};

/// Points per tooth used for exports: fine enough that the chord error is below 0.01 um.
pub const EXPORT_POINTS_PER_TOOTH: usize = 400;

/// Profile format, from the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileFormat {
    /// Comma-separated points.
    Csv,
    /// AutoCAD DXF (closed LWPOLYLINE).
    Dxf,
    /// Scalable vector graphics.
    Svg,
}

impl ProfileFormat {
    /// Format of `path` from its extension.
    ///
    /// # Errors
    /// [`Error::Invalid`] for another extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("csv") => Ok(ProfileFormat::Csv),
            Some("dxf") => Ok(ProfileFormat::Dxf),
            Some("svg") => Ok(ProfileFormat::Svg),
            _ => Err(Error::invalid(
                "--out",
                path.display(),
                "the file must end in .csv, .dxf or .svg",
            )),
        }
    }
}

/// Writes `profile` to `path` in `format`.
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
pub fn write_profile(profile: &Profile, path: &Path, format: ProfileFormat) -> Result<()> {
    match format {
        ProfileFormat::Csv => write_csv(profile, path),
        ProfileFormat::Dxf => write_dxf(profile, path),
        ProfileFormat::Svg => write_svg(profile, path),
    }
}

fn sample_with_params(profile: &Profile) -> Vec<(f64, f64, f64, f64)> {
    let zc = profile.geometry().disc_teeth();
    let n = EXPORT_POINTS_PER_TOOTH * zc;
    let dt = std::f64::consts::TAU * zc as f64 / n as f64;
    (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let p = profile.point(t).p;
            let wear = profile.wear().map_or(0.0, |w| w.eval(t).0);
            (p.x * 1e3, p.y * 1e3, mesh_angle(t).to_degrees(), wear * 1e6)
        })
        .collect()
}

fn write_csv(profile: &Profile, path: &Path) -> Result<()> {
    let mut w = csv::Writer::from_path(path)
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))?;
    let io = |e: csv::Error| Error::io(path, std::io::Error::other(e.to_string()));
    w.write_record(["x_mm", "y_mm", "mesh_angle_deg", "wear_um"])
        .map_err(io)?;
    for (x, y, t, h) in sample_with_params(profile) {
        w.write_record([
            format!("{x:.9}"),
            format!("{y:.9}"),
            format!("{t:.6}"),
            format!("{h:.6}"),
        ])
        .map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

fn write_dxf(profile: &Profile, path: &Path) -> Result<()> {
    use dxf::entities::{Entity, EntityType, LwPolyline};
    use dxf::enums::AcadVersion;
    use dxf::{Drawing, LwPolylineVertex};
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    // Same input, same bytes: the `dxf` crate stamps the clock and two random GUIDs into the
    // header; they are fixed here (2000-01-01 00:00 UTC, GUIDs named from the content).
    // The local-time fields are written as their wall-clock reading: 2000-01-01 00:00 in
    // every time zone.
    let epoch =
        chrono::DateTime::<chrono::Utc>::from_timestamp(946_684_800, 0).expect("a valid date");
    let local = {
        use chrono::TimeZone;
        chrono::Local
            .from_local_datetime(&epoch.naive_utc())
            .earliest()
            .unwrap_or_else(|| epoch.with_timezone(&chrono::Local))
    };
    drawing.header.creation_date = local;
    drawing.header.update_date = local;
    drawing.header.creation_date_universal = epoch;
    drawing.header.update_date_universal = epoch;
    let mut poly = LwPolyline::default();
    poly.set_is_closed(true);
    poly.vertices = sample_with_params(profile)
        .into_iter()
        .map(|(x, y, _, _)| LwPolylineVertex {
            x,
            y,
            ..Default::default()
        })
        .collect();
    let guid = {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for v in &poly.vertices {
            v.x.to_bits().hash(&mut h);
            v.y.to_bits().hash(&mut h);
        }
        let a = h.finish();
        a.rotate_left(17).hash(&mut h);
        uuid::Uuid::from_u64_pair(a, h.finish())
    };
    drawing.header.fingerprint_guid = guid;
    drawing.header.version_guid = guid;
    drawing.add_entity(Entity::new(EntityType::LwPolyline(poly)));
    drawing
        .save_file(path)
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))
}

fn write_svg(profile: &Profile, path: &Path) -> Result<()> {
    let g = profile.geometry();
    let r = (g.pin_circle_radius + g.pin_radius) * 1e3 * 1.05;
    let pts = sample_with_params(profile);
    let mut d = String::with_capacity(pts.len() * 24);
    for (i, (x, y, _, _)) in pts.iter().enumerate() {
        d.push_str(if i == 0 { "M" } else { "L" });
        d.push_str(&format!("{x:.5},{:.5} ", -y));
    }
    d.push('Z');
    let mut pins = String::new();
    for j in 0..g.pins {
        let c = g.pin_centre(j);
        // Pins drawn at crank angle 0 with the disc at (a, 0): shift the disc instead.
        pins.push_str(&format!(
            "<circle cx=\"{:.5}\" cy=\"{:.5}\" r=\"{:.5}\" fill=\"none\" stroke=\"#888\" stroke-width=\"0.05\"/>\n",
            (c.x - g.eccentricity) * 1e3,
            -c.y * 1e3,
            g.pin_radius * 1e3
        ));
    }
    let text = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}mm\" height=\"{w}mm\" viewBox=\"{x0} {x0} {w} {w}\">\n\
         <title>rvlife cycloid disc profile ({n} teeth), millimetres</title>\n\
         {pins}<path d=\"{d}\" fill=\"#cfe0f5\" stroke=\"#1f4e8c\" stroke-width=\"0.05\"/>\n</svg>\n",
        w = 2.0 * r,
        x0 = -r,
        n = g.disc_teeth(),
    );
    let mut f = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    f.write_all(text.as_bytes()).map_err(|e| Error::io(path, e))
}
