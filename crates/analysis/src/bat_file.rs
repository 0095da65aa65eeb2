//! The bat file format: TOML with the profile either in a CSV file beside it or inline as `[[station]]`.
//!
//! ```toml
//! name = "my-bat"              # optional; defaults to the file stem
//! slice_length = 0.01          # m, slice thickness of the beam model
//! profile = "my-bat.csv"       # CSV resolved relative to this file (or give [[station]] entries instead)
//!
//! [shell]                      # the bat's material
//! density = 649.0              # kg/m³
//! youngs_modulus = 1.814e10    # Pa
//! shear_modulus = 1.05e9       # Pa
//!
//! [core]                       # optional fill of the bore between z_start and z_end (m from the knob)
//! density = 200.0
//! youngs_modulus = 3.0e7
//! shear_modulus = 6.0e6
//! z_start = 0.5860
//! z_end = 0.8400
//! ```
//!
//! The CSV has a header naming its columns `z_m,outer_radius_m,inner_radius_m` (any order; `inner_radius_m`
//! may be left out for a solid bat); one row per station, z strictly increasing from the knob.
//!
//! Parsing is pure ([`parse_bat_toml`] takes the text and a closure that reads the CSV); only
//! [`load_bat_file`] and [`write_bat_files`] touch the file system.

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use serde::{Deserialize, Serialize};

use sweetspot_physics::{Bat, CoreFill, Material, Station};

/// Column names of the profile CSV, in the order they are written.
pub const PROFILE_COLUMNS: [&str; 3] = ["z_m", "outer_radius_m", "inner_radius_m"];

/// The TOML document of a bat file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatSpec {
    /// Bat name; the file stem when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Slice thickness Δz of the beam model, m.
    pub slice_length: f64,
    /// CSV profile file, relative to the TOML file (exclusive with `station`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    /// Shell material.
    pub shell: MaterialSpec,
    /// Optional core fill.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub core: Option<CoreSpec>,
    /// Inline profile stations (exclusive with `profile`).
    #[serde(default, rename = "station", skip_serializing_if = "Vec::is_empty")]
    pub stations: Vec<StationSpec>,
}

/// A material in a bat file, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// kg/m³.
    pub density: f64,
    /// Pa.
    pub youngs_modulus: f64,
    /// Pa.
    pub shear_modulus: f64,
}

/// A core fill in a bat file: its material and its z-range, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoreSpec {
    /// kg/m³.
    pub density: f64,
    /// Pa.
    pub youngs_modulus: f64,
    /// Pa.
    pub shear_modulus: f64,
    /// Start of the filled range, m from the knob.
    pub z_start: f64,
    /// End of the filled range, m from the knob.
    pub z_end: f64,
}

/// One inline station, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StationSpec {
    /// Distance from the knob, m.
    pub z: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// Inner (bore) radius, m; 0 when absent.
    #[serde(default)]
    pub inner_radius: f64,
}

impl From<MaterialSpec> for Material {
    fn from(m: MaterialSpec) -> Material {
        Material { density: m.density, youngs_modulus: m.youngs_modulus, shear_modulus: m.shear_modulus }
    }
}

impl From<Material> for MaterialSpec {
    fn from(m: Material) -> MaterialSpec {
        MaterialSpec { density: m.density, youngs_modulus: m.youngs_modulus, shear_modulus: m.shear_modulus }
    }
}

impl BatSpec {
    /// Builds the validated bat; `read_profile` returns the text of the CSV named by `profile`.
    pub fn into_bat(self, default_name: &str, read_profile: impl FnOnce(&str) -> Result<String>) -> Result<Bat> {
        let stations = match (&self.profile, self.stations.is_empty()) {
            (Some(_), false) => bail!("give either `profile` (a CSV file) or `[[station]]` entries, not both"),
            (None, true) => bail!("the bat has no profile: give `profile = \"FILE.csv\"` or `[[station]]` entries"),
            (Some(file), true) => {
                let text = read_profile(file).with_context(|| format!("cannot read profile '{file}'"))?;
                parse_profile_csv(&text).with_context(|| format!("profile '{file}'"))?
            }
            (None, false) => {
                let stations: Vec<Station> = self
                    .stations
                    .iter()
                    .map(|s| Station { z: s.z, outer_radius: s.outer_radius, inner_radius: s.inner_radius })
                    .collect();
                check_increasing(&stations, |i| format!("station[{i}]"))?;
                stations
            }
        };
        let core = self.core.map(|c| CoreFill {
            material: Material { density: c.density, youngs_modulus: c.youngs_modulus, shear_modulus: c.shear_modulus },
            z_start: c.z_start,
            z_end: c.z_end,
        });
        let name = self.name.unwrap_or_else(|| default_name.to_string());
        Ok(Bat::new(name, stations, self.shell.into(), core, self.slice_length)?)
    }

    /// The spec of `bat` with its profile either inline or pointing at `profile_file`.
    pub fn from_bat(bat: &Bat, profile_file: Option<&str>) -> BatSpec {
        let stations = match profile_file {
            Some(_) => Vec::new(),
            None => bat
                .stations
                .iter()
                .map(|s| StationSpec { z: s.z, outer_radius: s.outer_radius, inner_radius: s.inner_radius })
                .collect(),
        };
        BatSpec {
            name: Some(bat.name.clone()),
            slice_length: bat.slice_length,
            profile: profile_file.map(str::to_string),
            shell: bat.shell.into(),
            core: bat.core.map(|c| CoreSpec {
                density: c.material.density,
                youngs_modulus: c.material.youngs_modulus,
                shear_modulus: c.material.shear_modulus,
                z_start: c.z_start,
                z_end: c.z_end,
            }),
            stations,
        }
    }
}

/// Parses a bat file's TOML text; `read_profile` returns the CSV text for the `profile` name it is given.
pub fn parse_bat_toml(
    text: &str,
    default_name: &str,
    read_profile: impl FnOnce(&str) -> Result<String>,
) -> Result<Bat> {
    let spec: BatSpec = toml::from_str(text).map_err(|e| anyhow!("{}", e.to_string().trim_end()))?;
    spec.into_bat(default_name, read_profile)
}

/// Parses a profile CSV (header `z_m,outer_radius_m[,inner_radius_m]`) into stations.
pub fn parse_profile_csv(text: &str) -> Result<Vec<Station>> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(text.as_bytes());
    let headers = reader.headers().context("cannot read the CSV header")?.clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    let z_col =
        column("z_m").ok_or_else(|| anyhow!("the CSV header must name a `z_m` column (found: {})", join(&headers)))?;
    let outer_col = column("outer_radius_m")
        .ok_or_else(|| anyhow!("the CSV header must name an `outer_radius_m` column (found: {})", join(&headers)))?;
    let inner_col = column("inner_radius_m");
    for h in headers.iter() {
        if !PROFILE_COLUMNS.contains(&h) {
            bail!("unknown CSV column `{h}` (allowed: {})", PROFILE_COLUMNS.join(", "));
        }
    }
    let mut stations = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.with_context(|| format!("line {line}"))?;
        let number = |col: usize, name: &str| -> Result<f64> {
            let cell = record.get(col).ok_or_else(|| anyhow!("line {line}: missing `{name}`"))?;
            cell.parse::<f64>().map_err(|_| anyhow!("line {line}: `{name}` = '{cell}' is not a number"))
        };
        let z = number(z_col, "z_m")?;
        let outer_radius = number(outer_col, "outer_radius_m")?;
        let inner_radius = match inner_col {
            Some(col) => number(col, "inner_radius_m")?,
            None => 0.0,
        };
        stations.push(Station { z, outer_radius, inner_radius });
    }
    check_increasing(&stations, |i| format!("line {}: z_m", i + 2))?;
    Ok(stations)
}

fn join(headers: &csv::StringRecord) -> String {
    headers.iter().collect::<Vec<_>>().join(", ")
}

/// Names the first station whose z is not strictly greater than the previous one.
fn check_increasing(stations: &[Station], locate: impl Fn(usize) -> String) -> Result<()> {
    for (i, pair) in stations.windows(2).enumerate() {
        if !(pair[1].z > pair[0].z) {
            bail!(
                "{}: z = {} m is not greater than the previous station's z = {} m (stations must be strictly increasing)",
                locate(i + 1),
                pair[1].z,
                pair[0].z
            );
        }
    }
    Ok(())
}

/// The CSV text of a profile, with the header [`PROFILE_COLUMNS`]; numbers round-trip exactly.
pub fn profile_to_csv(stations: &[Station]) -> String {
    let mut out = PROFILE_COLUMNS.join(",");
    out.push('\n');
    for s in stations {
        out.push_str(&format!("{:?},{:?},{:?}\n", s.z, s.outer_radius, s.inner_radius));
    }
    out
}

/// A float as TOML: shortest round-trip text, scientific for very large or small magnitudes.
fn toml_float(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude != 0.0 && !(1e-3..1e5).contains(&magnitude) {
        format!("{value:e}")
    } else {
        format!("{value:?}")
    }
}

/// The TOML text of `spec`, commented with units; numbers round-trip exactly.
pub fn spec_to_toml(spec: &BatSpec) -> String {
    let mut out = String::from("# sweetspot bat file (docs/file-formats.md): SI units, z in metres from the knob.\n");
    let line = |out: &mut String, key: &str, value: String, comment: &str| {
        let text = format!("{key} = {value}");
        if comment.is_empty() {
            out.push_str(&format!("{text}\n"));
        } else {
            out.push_str(&format!("{text:<32}# {comment}\n"));
        }
    };
    if let Some(name) = &spec.name {
        line(&mut out, "name", toml::Value::String(name.clone()).to_string(), "");
    }
    line(&mut out, "slice_length", toml_float(spec.slice_length), "m, slice thickness of the beam model");
    if let Some(profile) = &spec.profile {
        line(
            &mut out,
            "profile",
            toml::Value::String(profile.clone()).to_string(),
            "CSV: z_m, outer_radius_m, inner_radius_m",
        );
    }
    out.push_str("\n[shell]\n");
    line(&mut out, "density", toml_float(spec.shell.density), "kg/m³");
    line(&mut out, "youngs_modulus", toml_float(spec.shell.youngs_modulus), "Pa");
    line(&mut out, "shear_modulus", toml_float(spec.shell.shear_modulus), "Pa");
    if let Some(core) = &spec.core {
        out.push_str("\n[core]                          # fill of the bore between z_start and z_end\n");
        line(&mut out, "density", toml_float(core.density), "kg/m³");
        line(&mut out, "youngs_modulus", toml_float(core.youngs_modulus), "Pa");
        line(&mut out, "shear_modulus", toml_float(core.shear_modulus), "Pa");
        line(&mut out, "z_start", toml_float(core.z_start), "m from the knob");
        line(&mut out, "z_end", toml_float(core.z_end), "m from the knob");
    }
    for station in &spec.stations {
        out.push_str("\n[[station]]\n");
        line(&mut out, "z", toml_float(station.z), "m from the knob");
        line(&mut out, "outer_radius", toml_float(station.outer_radius), "m");
        line(&mut out, "inner_radius", toml_float(station.inner_radius), "m");
    }
    out
}

/// Reads a bat file from disk; the CSV profile is resolved relative to the TOML file.
pub fn load_bat_file(path: &Path) -> Result<Bat> {
    let text = sweetspot_model::files::read_text(path, "bat file")?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("bat").to_string();
    parse_bat_toml(&text, &stem, |file| {
        let csv_path = base.join(file);
        Ok(sweetspot_model::files::read_text(&csv_path, "bat profile")?)
    })
    .with_context(|| format!("bat file '{}'", path.display()))
}

/// Writes `bat` as `DIR/STEM.toml` plus `DIR/STEM.csv`; returns the TOML path.
pub fn write_bat_files(bat: &Bat, dir: &Path, stem: &str) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))?;
    let csv_name = format!("{stem}.csv");
    let toml_path = dir.join(format!("{stem}.toml"));
    let spec = BatSpec::from_bat(bat, Some(&csv_name));
    std::fs::write(dir.join(&csv_name), profile_to_csv(&bat.stations))
        .with_context(|| format!("cannot write '{}'", dir.join(&csv_name).display()))?;
    std::fs::write(&toml_path, spec_to_toml(&spec))
        .with_context(|| format!("cannot write '{}'", toml_path.display()))?;
    Ok(toml_path)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CSV: &str = "z_m,outer_radius_m,inner_radius_m\n0.0,0.02,0.0\n0.5,0.03,0.01\n";

    #[test]
    fn profile_csv_parses_and_checks_order() {
        let stations = parse_profile_csv(CSV).unwrap();
        assert_eq!(stations.len(), 2);
        assert_eq!(stations[1], Station { z: 0.5, outer_radius: 0.03, inner_radius: 0.01 });
        let solid = parse_profile_csv("outer_radius_m,z_m\n0.02,0\n0.03,0.4\n").unwrap();
        assert_eq!(solid[1], Station { z: 0.4, outer_radius: 0.03, inner_radius: 0.0 });
        let err = parse_profile_csv("z_m,outer_radius_m\n0.0,0.02\n0.5,0.03\n0.5,0.03\n").unwrap_err();
        assert!(format!("{err:#}").contains("line 4: z_m"), "{err:#}");
        let err = parse_profile_csv("z,outer_radius_m\n0.0,0.02\n").unwrap_err();
        assert!(format!("{err:#}").contains("z_m"), "{err:#}");
        let err = parse_profile_csv("z_m,outer_radius_m\n0.0,abc\n").unwrap_err();
        assert!(format!("{err:#}").contains("outer_radius_m"), "{err:#}");
    }

    #[test]
    fn csv_round_trips_exactly() {
        let stations = vec![
            Station { z: 0.005, outer_radius: 0.1 + 0.2, inner_radius: 1.0 / 3.0 },
            Station { z: 0.015, outer_radius: 0.025_25, inner_radius: 0.0 },
        ];
        assert_eq!(parse_profile_csv(&profile_to_csv(&stations)).unwrap(), stations);
    }

    #[test]
    fn toml_rejects_unknown_fields_and_double_profiles() {
        let text = "slice_length = 0.01\nprofile = \"p.csv\"\ncolour = 3\n[shell]\ndensity = 1\nyoungs_modulus = 1\nshear_modulus = 1\n";
        let err = parse_bat_toml(text, "x", |_| Ok(CSV.to_string())).unwrap_err();
        assert!(format!("{err:#}").contains("colour"), "{err:#}");
        let text = "slice_length = 0.01\nprofile = \"p.csv\"\n[shell]\ndensity = 1\nyoungs_modulus = 1\nshear_modulus = 1\n[[station]]\nz = 0\nouter_radius = 0.1\n";
        let err = parse_bat_toml(text, "x", |_| Ok(CSV.to_string())).unwrap_err();
        assert!(format!("{err:#}").contains("not both"), "{err:#}");
    }

    #[test]
    fn inline_stations_must_increase() {
        let text = "slice_length = 0.01\n[shell]\ndensity = 649\nyoungs_modulus = 1.8e10\nshear_modulus = 1e9\n\
                    [[station]]\nz = 0.0\nouter_radius = 0.02\n[[station]]\nz = 0.0\nouter_radius = 0.03\n";
        let err = parse_bat_toml(text, "x", |_| bail!("no CSV expected")).unwrap_err();
        assert!(format!("{err:#}").contains("station[1]"), "{err:#}");
    }

    #[test]
    fn spec_toml_round_trips() {
        let spec = BatSpec {
            name: Some("b".into()),
            slice_length: 0.01,
            profile: None,
            shell: MaterialSpec { density: 649.0, youngs_modulus: 1.814e10, shear_modulus: 1.05e9 },
            core: Some(CoreSpec {
                density: 200.0,
                youngs_modulus: 3e7,
                shear_modulus: 6e6,
                z_start: 0.586,
                z_end: 0.84,
            }),
            stations: vec![
                StationSpec { z: 0.0, outer_radius: 0.025, inner_radius: 0.0 },
                StationSpec { z: 0.1 + 0.2, outer_radius: 1.0 / 30.0, inner_radius: 1e-7 / 3.0 },
            ],
        };
        let text = spec_to_toml(&spec);
        let back: BatSpec = toml::from_str(&text).unwrap();
        assert_eq!(back, spec);
    }
}
