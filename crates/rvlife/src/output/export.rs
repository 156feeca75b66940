//! Export of a disc profile (nominal, modified or worn) to CSV, DXF and SVG.
//!
//! - CSV: `x_mm,y_mm,mesh_angle_deg,wear_um`, one row per point, clockwise, closed implicitly.
//! - DXF: one closed `LWPOLYLINE` in millimetres, header version AutoCAD 2000 (the R12 default
//!   of the `dxf` crate silently drops LWPOLYLINE), so it opens in CAD as a closed polyline.
//!   The header's dates and GUIDs are fixed, not taken from the clock or a random generator:
//!   same input, same bytes.
//! - SVG: the closed outline in millimetres, y up, with the pin circle for reference.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::geometry::{mesh_angle, Profile};

/// Points per tooth used for exports: fine enough that the chord error is below 0.01 um.
pub(crate) const EXPORT_POINTS_PER_TOOTH: usize = 400;

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

/// Writes `profile` to `path` in `format`, with at least two points per node of its
/// deviation map ([`points_per_tooth`]), so that the file determines the profile: read back
/// as `cycloid.measured_profile` it gives the same profile to the file's rounding.
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
pub fn write_profile(profile: &Profile, path: &Path, format: ProfileFormat) -> Result<()> {
    write_profile_sampled(profile, path, format, points_per_tooth(profile))
}

/// Points per tooth of [`write_profile`]: `EXPORT_POINTS_PER_TOOTH`, or twice the nodes of
/// the profile's wear (deviation) map if more.
pub fn points_per_tooth(profile: &Profile) -> usize {
    EXPORT_POINTS_PER_TOOTH.max(2 * profile.wear().map_or(0, |w| w.depths().len()))
}

/// [`write_profile`] with `per_tooth` points per tooth (the study's stage profiles for CAD use
/// [`EXPORT_POINTS_PER_TOOTH`]).
///
/// # Errors
/// [`Error::Io`] if the file cannot be written.
pub(crate) fn write_profile_sampled(
    profile: &Profile,
    path: &Path,
    format: ProfileFormat,
    per_tooth: usize,
) -> Result<()> {
    let bytes = profile_bytes(profile, format, per_tooth)?;
    let mut f = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    f.write_all(&bytes).map_err(|e| Error::io(path, e))
}

/// The bytes of [`write_profile`]'s file for `profile` in `format` with `per_tooth` points per
/// tooth: what the file holds, for a caller that keeps results in memory (the web page).
///
/// # Errors
/// [`Error::Numerical`] if the CSV or DXF writer fails.
pub fn profile_bytes(
    profile: &Profile,
    format: ProfileFormat,
    per_tooth: usize,
) -> Result<Vec<u8>> {
    match format {
        ProfileFormat::Csv => csv_bytes(profile, per_tooth),
        ProfileFormat::Dxf => dxf_bytes(profile, per_tooth),
        ProfileFormat::Svg => Ok(svg_text(profile, per_tooth).into_bytes()),
    }
}

/// `per_tooth` points per tooth of the whole profile, from parameter 0: `(x_mm, y_mm,
/// mesh_angle_deg, wear_um)` each (disc frame; mesh angle 0 at the root, 180 at the tip; wear
/// depth along the normal).
pub fn profile_points(profile: &Profile, per_tooth: usize) -> Vec<(f64, f64, f64, f64)> {
    let zc = profile.geometry().disc_teeth();
    let n = per_tooth * zc;
    let dt = std::f64::consts::TAU * zc as f64 / n as f64;
    (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let p = profile.position(t);
            let wear = profile.wear().map_or(0.0, |w| w.eval(t).0);
            (p.x * 1e3, p.y * 1e3, mesh_angle(t).to_degrees(), wear * 1e6)
        })
        .collect()
}

fn csv_bytes(profile: &Profile, per_tooth: usize) -> Result<Vec<u8>> {
    let points = profile_points(profile, per_tooth);
    let header = ["x_mm", "y_mm", "mesh_angle_deg", "wear_um"];
    Ok(super::numbers_bytes(&header, points.len(), 4, |i, j| {
        let (x, y, t, h) = points[i];
        [(x, 9), (y, 9), (t, 6), (h, 6)][j]
    }))
}

fn dxf_bytes(profile: &Profile, per_tooth: usize) -> Result<Vec<u8>> {
    use dxf::entities::{Entity, EntityType, LwPolyline};
    use dxf::enums::AcadVersion;
    use dxf::{Drawing, LwPolylineVertex};
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    let mut poly = LwPolyline::default();
    poly.set_is_closed(true);
    poly.vertices = profile_points(profile, per_tooth)
        .into_iter()
        .map(|(x, y, _, _)| LwPolylineVertex {
            x,
            y,
            ..Default::default()
        })
        .collect();
    let guid = content_guid(poly.vertices.iter().flat_map(|v| [v.x, v.y]));
    fix_header(&mut drawing.header, guid);
    drawing.add_entity(Entity::new(EntityType::LwPolyline(poly)));
    let mut bytes = Vec::new();
    drawing
        .save(&mut bytes)
        .map_err(|e| Error::numerical("DXF export", e.to_string()))?;
    Ok(bytes)
}

/// Days from 1900-01-01 to 2000-01-01: the fixed header dates are this far from the `dxf`
/// crate's own epoch (1900-01-01 00:00, written 2415021.0), so they are written 2451545.0
/// (the DXF convention: Julian day counted from midnight, 2000-01-01 00:00).
const DAYS_1900_TO_2000: i64 = 36_524;

/// Sets every header field the `dxf` crate fills from the clock or from a random generator
/// to a fixed value, so that the same profile gives the same bytes on every run, on every
/// machine and in every time zone.
///
/// - `$TDCREATE`, `$TDUPDATE` (local) and `$TDUCREATE`, `$TDUUPDATE` (universal), which
///   `Header::default` takes from `Local::now()` and `Utc::now()`: all written as
///   2000-01-01 00:00 (2451545.0).
/// - `$TDINDWG`, `$TDUSRTIMER`: zero (already the crate's default, set here so it stays so).
/// - `$FINGERPRINTGUID`, `$VERSIONGUID`, which the crate draws with `Uuid::new_v4()`:
///   `guid`, named from the drawing's content by the caller.
///
/// The crate writes a local date as the wall-clock days since its local 1900-01-01 00:00, an
/// instant whose offset (the local mean time of many zones) differs from today's; the local
/// dates are therefore built from that same instant, which makes them 2451545.0 in every
/// zone. Handles are allocated in order from a fixed seed and nothing is written from a hash
/// map, so the rest of the file is already a function of the entities alone.
fn fix_header(header: &mut dxf::Header, guid: uuid::Uuid) {
    use chrono::TimeZone;
    let days = chrono::TimeDelta::days(DAYS_1900_TO_2000);
    let utc = chrono::Utc.with_ymd_and_hms(1900, 1, 1, 0, 0, 0).unwrap() + days;
    let local = chrono::Local
        .with_ymd_and_hms(1900, 1, 1, 0, 0, 0)
        .single()
        .map_or_else(|| utc.with_timezone(&chrono::Local), |e| e + days);
    header.creation_date = local;
    header.update_date = local;
    header.creation_date_universal = utc;
    header.update_date_universal = utc;
    header.time_in_drawing = std::time::Duration::ZERO;
    header.user_elapsed_timer = std::time::Duration::ZERO;
    header.fingerprint_guid = guid;
    header.version_guid = guid;
}

/// A GUID named from `values` (their exact bits, little-endian): a name-based UUID version 5
/// (SHA-1, RFC 9562 section 5.5) in the URL namespace of rvlife's repository. Same values,
/// same GUID, on every run, machine and toolchain.
fn content_guid(values: impl IntoIterator<Item = f64>) -> uuid::Uuid {
    let namespace = uuid::Uuid::new_v5(
        &uuid::Uuid::NAMESPACE_URL,
        b"https://github.com/rvlife/rvlife",
    );
    let bytes: Vec<u8> = values
        .into_iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .collect();
    uuid::Uuid::new_v5(&namespace, &bytes)
}

fn svg_text(profile: &Profile, per_tooth: usize) -> String {
    let g = profile.geometry();
    let r = (g.pin_circle_radius + g.pin_radius) * 1e3 * 1.05;
    let pts = profile_points(profile, per_tooth);
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
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}mm\" height=\"{w}mm\" viewBox=\"{x0} {x0} {w} {w}\">\n\
         <title>rvlife cycloid disc profile ({n} teeth), millimetres</title>\n\
         {pins}<path d=\"{d}\" fill=\"#cfe0f5\" stroke=\"#1f4e8c\" stroke-width=\"0.05\"/>\n</svg>\n",
        w = 2.0 * r,
        x0 = -r,
        n = g.disc_teeth(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example_profile() -> Profile {
        let model = crate::config::Config::paper().validate().unwrap();
        model.profile().unwrap()
    }

    /// The value written after the header variable `name` (name, group code, value lines).
    fn header_value<'a>(text: &'a str, name: &str) -> &'a str {
        let lines: Vec<&str> = text.lines().collect();
        let i = lines
            .iter()
            .position(|l| l.trim() == name)
            .unwrap_or_else(|| panic!("{name} not in the header"));
        lines[i + 2].trim()
    }

    #[test]
    fn dxf_export_is_byte_deterministic() {
        let profile = example_profile();
        let n = points_per_tooth(&profile);
        let a = profile_bytes(&profile, ProfileFormat::Dxf, n).unwrap();
        // A later clock reading and fresh random GUIDs would show up in the second file.
        std::thread::sleep(std::time::Duration::from_millis(20));
        let b = profile_bytes(&profile, ProfileFormat::Dxf, n).unwrap();
        assert!(a == b, "two exports of the same profile differ");

        let text = String::from_utf8(a).unwrap();
        // 2000-01-01 00:00 in every time zone, zero timers.
        for name in ["$TDCREATE", "$TDUPDATE", "$TDUCREATE", "$TDUUPDATE"] {
            assert_eq!(header_value(&text, name), "2451545.0", "{name}");
        }
        for name in ["$TDINDWG", "$TDUSRTIMER"] {
            assert_eq!(header_value(&text, name), "0.0", "{name}");
        }
        let guid = content_guid(
            profile_points(&profile, points_per_tooth(&profile))
                .into_iter()
                .flat_map(|(x, y, _, _)| [x, y]),
        )
        .to_string();
        assert_eq!(header_value(&text, "$FINGERPRINTGUID"), guid);
        assert_eq!(header_value(&text, "$VERSIONGUID"), guid);
        // Today's date, as the header would write it (days since 1970-01-01 plus 2440588),
        // appears nowhere; the coordinates are millimetres well below 1e6.
        let days = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_secs()
            / 86_400;
        let today = format!("{}", 2_440_588 + days);
        assert!(!text.contains(&today), "today's date {today} in the DXF");
    }

    #[test]
    fn content_guid_is_fixed_and_follows_the_content() {
        // Pinned: the GUID must not change with the toolchain or between runs.
        let g = content_guid([1.0, 2.0]);
        assert_eq!(g, content_guid([1.0, 2.0]));
        assert_eq!(g.get_version_num(), 5);
        assert_ne!(g, content_guid([1.0, 2.000_000_1]));
        assert_eq!(content_guid([]).to_string(), GUID_OF_NOTHING);
    }

    /// UUID v5 of no bytes in rvlife's namespace (the same value from Python: `uuid5(uuid5(NAMESPACE_URL, url), "")`).
    const GUID_OF_NOTHING: &str = "6ba24191-7fa7-55e4-b9e6-22960ff06131";
}
