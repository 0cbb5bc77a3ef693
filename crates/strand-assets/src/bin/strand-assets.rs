//! `strand-assets`: writes the engine-compartment OBJ files, large benchmark surfaces,
//! and measures hose clearances against OBJ files.
//!
//! ```text
//! strand-assets engine-bay --out assets/engine_bay
//! strand-assets surface --triangles 1000000 --out target/meshes/surface_1M.obj
//! strand-assets clearance --result out/cooler/result.json --radius hose1=18.4 \
//!     --radius hose2=12.9 --radius hose3=18.4 assets/engine_bay/*.obj
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use nalgebra::Point3;
use strand_assets::engine_bay::{tube_clearance, write_engine_bay};
use strand_assets::{ObjOptions, read_obj, wavy_surface, write_obj};

/// Mesh generators for Strand's assets and benchmarks.
#[derive(Parser)]
#[command(name = "strand-assets", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write the engine-compartment OBJ files of the cooler-hose case (mm).
    EngineBay {
        /// Output directory (created if missing), e.g. assets/engine_bay.
        #[arg(long)]
        out: PathBuf,
    },
    /// Write the single-part OBJ files of the bundled cases (mm): box, V-groove.
    Parts {
        /// Output directory (created if missing), e.g. assets/parts.
        #[arg(long)]
        out: PathBuf,
    },
    /// Write a wavy benchmark surface with exactly N triangles (not for committing).
    Surface {
        /// Number of triangles, e.g. 1000000.
        #[arg(long)]
        triangles: usize,
        /// Side of the square the surface covers, in m.
        #[arg(long, default_value_t = 2.0)]
        extent: f64,
        /// Unit of the coordinates written to the file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        unit: Unit,
        /// Output OBJ file, e.g. target/meshes/surface_1M.obj.
        #[arg(long)]
        out: PathBuf,
    },
    /// Smallest gap between the rods of a result.json (tubes) and each object of OBJ files.
    Clearance {
        /// A result.json written by `strand solve`.
        #[arg(long)]
        result: PathBuf,
        /// Outer radius of a rod in mm, as NAME=RADIUS (one per rod).
        #[arg(long = "radius", value_parser = parse_radius)]
        radii: Vec<(String, f64)>,
        /// Unit of the OBJ files.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        unit: Unit,
        /// OBJ files to measure against.
        #[arg(required = true)]
        meshes: Vec<PathBuf>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum Unit {
    /// Millimetres.
    Mm,
    /// Metres.
    M,
}

impl Unit {
    /// Metres per file unit.
    fn metres(self) -> f64 {
        match self {
            Unit::Mm => 1e-3,
            Unit::M => 1.0,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Unit::Mm => "mm",
            Unit::M => "m",
        }
    }
}

/// Largest triangle count `surface` accepts (vertex indices must fit in u32).
const MAX_TRIANGLES: usize = 1_000_000_000;

fn parse_radius(text: &str) -> Result<(String, f64), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("'{text}': write NAME=RADIUS_MM, e.g. hose1=18.4"))?;
    let radius: f64 = value
        .parse()
        .map_err(|_| format!("'{value}' is not a number (radius of '{name}' in mm)"))?;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(format!("radius of '{name}' = {radius}: must be > 0 mm"));
    }
    Ok((name.to_string(), radius))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(command: Command) -> Result<(), String> {
    match command {
        Command::EngineBay { out } => {
            for path in write_engine_bay(&out).map_err(|e| e.to_string())? {
                let objects = read_obj(&path).map_err(|e| e.to_string())?;
                let triangles: usize = objects.iter().map(|o| o.mesh.triangles.len()).sum();
                let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
                println!(
                    "written {} ({triangles} triangles, {bytes} bytes)",
                    path.display()
                );
            }
            Ok(())
        }
        Command::Parts { out } => {
            for path in strand_assets::parts::write_parts(&out).map_err(|e| e.to_string())? {
                println!("written {}", path.display());
            }
            Ok(())
        }
        Command::Surface {
            triangles,
            extent,
            unit,
            out,
        } => {
            if !(1..=MAX_TRIANGLES).contains(&triangles) {
                return Err(format!(
                    "--triangles {triangles}: must be between 1 and {MAX_TRIANGLES}"
                ));
            }
            if !(extent.is_finite() && extent > 0.0) {
                return Err(format!("--extent {extent}: must be a length > 0 in m"));
            }
            let mesh = wavy_surface(extent, triangles);
            let header = format!(
                "wavy benchmark surface: {triangles} triangles over a {extent} m square \
                 (z = extent/50 · sin(2πx/λ) cos(2πy/λ), λ = extent/5)\nunits: {}\n\
                 generated by `strand-assets surface`; not committed (regenerate on demand)",
                unit.name()
            );
            let options = ObjOptions {
                header,
                scale: 1.0 / unit.metres(),
                decimals: if matches!(unit, Unit::Mm) { 4 } else { 7 },
            };
            write_obj(&out, &[("surface", &mesh)], &options).map_err(|e| e.to_string())?;
            let bytes = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
            println!(
                "written {} ({} triangles, {} vertices, {bytes} bytes)",
                out.display(),
                mesh.triangles.len(),
                mesh.vertices.len()
            );
            Ok(())
        }
        Command::Clearance {
            result,
            radii,
            unit,
            meshes,
        } => clearance(&result, &radii, unit, &meshes),
    }
}

/// Prints, per rod and OBJ object, the smallest gap in mm.
fn clearance(
    result: &std::path::Path,
    radii: &[(String, f64)],
    unit: Unit,
    meshes: &[PathBuf],
) -> Result<(), String> {
    let text = std::fs::read_to_string(result).map_err(|e| format!("{}: {e}", result.display()))?;
    let doc: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", result.display()))?;
    let rods = doc["rods"].as_array().ok_or_else(|| {
        format!(
            "{}: no 'rods' array (is it a strand result.json?)",
            result.display()
        )
    })?;
    let names: Vec<&str> = rods
        .iter()
        .map(|r| r["name"].as_str().unwrap_or("?"))
        .collect();
    if let Some(missing) = names.iter().find(|n| !radii.iter().any(|(r, _)| r == *n)) {
        return Err(format!(
            "no radius for rod '{missing}': add --radius {missing}=OUTER_RADIUS_MM"
        ));
    }
    let mut objects = Vec::new();
    for path in meshes {
        for object in read_obj(path).map_err(|e| e.to_string())? {
            let label = format!("{}:{}", path.display(), object.name);
            objects.push((label, object.mesh.scaled(unit.metres() * 1e3)));
        }
    }
    println!("{:<8} {:<48} {:>9}  at (mm)", "rod", "object", "gap (mm)");
    for rod in rods {
        let name = rod["name"].as_str().unwrap_or("?");
        let radius = radii
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, r)| *r)
            .ok_or_else(|| {
                format!("no radius for rod '{name}': add --radius {name}=OUTER_RADIUS_MM")
            })?;
        let polyline: Vec<Point3<f64>> = rod["position_m"]
            .as_array()
            .ok_or_else(|| format!("{}: rod '{name}' has no position_m", result.display()))?
            .iter()
            .map(|p| {
                let c = |k: usize| p[k].as_f64().unwrap_or(f64::NAN) * 1e3;
                Point3::new(c(0), c(1), c(2))
            })
            .collect();
        for (label, mesh) in &objects {
            if let Some(c) = tube_clearance(mesh, &polyline, radius, 1.0) {
                println!(
                    "{name:<8} {label:<48} {:>9.1}  ({:.0}, {:.0}, {:.0})",
                    c.gap, c.at.x, c.at.y, c.at.z
                );
            }
        }
    }
    Ok(())
}
