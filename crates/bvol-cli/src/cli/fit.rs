//! `bvol fit MESH.obj`: every fitter on one mesh, as a table or JSON.

use std::path::Path;
use std::time::{Duration, Instant};

use bvol::volumes::{Aabb, FitError, Kdop, Obb, ObbMethod, Sphere, SphereMethod};
use bvol::{MAX_COORDINATE, ShapeError};
use glam::Vec3;
use serde_json::{Value, json};

/// One fitted bound.
struct Fitted {
    kind: &'static str,
    method: String,
    /// Radius for spheres, else `None`.
    radius: Option<f64>,
    volume: f64,
    micros: f64,
    bound: Value,
}

impl Fitted {
    /// What the ratio compares within a kind: radius for spheres, else volume.
    fn size(&self) -> f64 {
        self.radius.unwrap_or(self.volume)
    }
}

pub fn run(path: &Path, as_json: bool) -> Result<(), String> {
    let meshes = bvol::load_obj(path).map_err(|e| e.to_string())?;
    in_range(&meshes).map_err(|e| format!("{}: {e}", path.display()))?;
    let points: Vec<Vec3> = meshes.iter().flat_map(|m| m.positions.iter().copied()).collect();
    let fitted = fit_all(&points).map_err(|e| format!("{}: {e}", path.display()))?;
    if as_json {
        println!("{}", to_json(&fitted));
    } else {
        print_table(path, points.len(), &fitted);
    }
    Ok(())
}

/// The limit a [`bvol::World`] puts on coordinates, with its error: beyond
/// it, bounds' sizes overflow f32 (a radius past 3e38 came out as `null`).
fn in_range(meshes: &[bvol::Mesh]) -> Result<(), ShapeError> {
    for m in meshes {
        let beyond = |p: &Vec3| p.abs().cmpgt(Vec3::splat(MAX_COORDINATE)).any();
        if let Some(point) = m.positions.iter().position(beyond) {
            return Err(ShapeError::OutOfRange { part: m.name.clone(), point });
        }
    }
    Ok(())
}

fn fit_all(points: &[Vec3]) -> Result<Vec<Fitted>, FitError> {
    let mut out = Vec::new();
    for &m in SphereMethod::ALL {
        let (s, micros) = timed(|| Sphere::fit(points, m))?;
        let bound = json!({ "center": s.center.to_array(), "radius": s.radius });
        let radius = Some(s.radius as f64);
        out.push(Fitted {
            kind: "sphere",
            method: m.to_string(),
            radius,
            volume: s.volume_f64(),
            micros,
            bound,
        });
    }
    let (b, micros) = timed(|| Aabb::fit(points))?;
    let bound = json!({ "min": b.min.to_array(), "max": b.max.to_array() });
    out.push(Fitted {
        kind: "aabb",
        method: "exact".into(),
        radius: None,
        volume: b.volume_f64(),
        micros,
        bound,
    });
    for &m in ObbMethod::ALL {
        let (o, micros) = timed(|| Obb::fit(points, m))?;
        let bound = json!({
            "center": o.center.to_array(),
            "axes": [o.axes.x_axis.to_array(), o.axes.y_axis.to_array(), o.axes.z_axis.to_array()],
            "half_extents": o.half_extents.to_array(),
        });
        out.push(Fitted {
            kind: "obb",
            method: m.to_string(),
            radius: None,
            volume: o.volume_f64(),
            micros,
            bound,
        });
    }
    out.push(kdop::<3>(points)?);
    out.push(kdop::<7>(points)?);
    out.push(kdop::<9>(points)?);
    out.push(kdop::<13>(points)?);
    Ok(out)
}

fn kdop<const N: usize>(points: &[Vec3]) -> Result<Fitted, FitError> {
    let (k, micros) = timed(|| Kdop::<N>::fit(points))?;
    let bound = json!({
        "directions": Kdop::<N>::DIRECTIONS.as_slice(),
        "min": k.min.as_slice(),
        "max": k.max.as_slice(),
    });
    let method = format!("{}-dop", 2 * N);
    Ok(Fitted { kind: "kdop", method, radius: None, volume: k.volume_f64(), micros, bound })
}

/// Runs a fitter repeatedly (at least 3 times, for about 20 ms) and returns its
/// result with the fastest run's time in microseconds: the least disturbed by
/// a busy machine.
fn timed<T>(fit: impl Fn() -> Result<T, FitError>) -> Result<(T, f64), FitError> {
    let started = Instant::now();
    let mut best = Duration::MAX;
    let mut runs = 0;
    loop {
        let t = Instant::now();
        let result = fit()?;
        best = best.min(t.elapsed());
        runs += 1;
        if runs >= 3 && started.elapsed() > Duration::from_millis(20) {
            return Ok((result, best.as_secs_f64() * 1e6));
        }
    }
}

/// The smallest size of each result's kind.
fn best_of_kind(fitted: &[Fitted], kind: &str) -> f64 {
    fitted.iter().filter(|f| f.kind == kind).map(Fitted::size).fold(f64::INFINITY, f64::min)
}

fn ratio(fitted: &[Fitted], f: &Fitted) -> f64 {
    let best = best_of_kind(fitted, f.kind);
    if best > 0.0 { f.size() / best } else { 1.0 }
}

fn to_json(fitted: &[Fitted]) -> Value {
    let rows = fitted.iter().map(|f| {
        let mut row = json!({
            "kind": f.kind,
            "method": f.method,
            "volume": f.volume,
            "ratio": ratio(fitted, f),
            "micros": f.micros,
            "bound": f.bound,
        });
        if let Some(r) = f.radius {
            row["radius"] = json!(r);
        }
        row
    });
    Value::Array(rows.collect())
}

fn print_table(path: &Path, vertices: usize, fitted: &[Fitted]) {
    println!("{}: {vertices} vertices", path.display());
    println!(
        "{:<7} {:<11} {:>16} {:>16} {:>7} {:>11}",
        "kind", "method", "radius", "volume", "ratio", "micros"
    );
    for f in fitted {
        let radius = f.radius.map_or(String::new(), |r| format!("{r:.6}"));
        println!(
            "{:<7} {:<11} {:>16} {:>16.6} {:>7.4} {:>11.1}",
            f.kind,
            f.method,
            radius,
            f.volume,
            ratio(fitted, f),
            f.micros
        );
    }
}
