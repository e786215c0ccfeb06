//! The study's figure: cost per simulated second against the density error and the front error,
//! written as `trade.png` and `trade.svg`.

use super::table::Row;
use crate::plot::{write_stacked_png, write_stacked_svg, Marker, ScatterPlot, Series, PALETTE};
use crate::report::Report;
use std::path::Path;

/// Plots cost per simulated second against the density error and the front error, one series
/// per backend × integrator; writes `trade.png` and `trade.svg` into `dir`.
pub(super) fn plot(rows: &[Row], dir: &Path) -> Result<(), String> {
    let mut keys: Vec<String> = Vec::new();
    for row in rows {
        let key = series_key(&row.report);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let series = |y: &dyn Fn(&Report) -> Option<f64>| -> Vec<Series> {
        keys.iter()
            .enumerate()
            .map(|(k, key)| Series {
                label: key.clone(),
                color: PALETTE[k % PALETTE.len()],
                marker: marker_of(key),
                points: rows
                    .iter()
                    .filter(|r| series_key(&r.report) == *key && r.report.health == "ok")
                    .filter_map(|r| Some((r.report.cost_per_sim_second_s, y(&r.report)?)))
                    .collect(),
            })
            .collect()
    };
    let density = ScatterPlot {
        title: "Mean compression error at the end (stable runs)".into(),
        x_label: "cost: wall-clock seconds per simulated second [s/s]".into(),
        y_label: "mean density error [%]".into(),
        series: series(&|r| Some(r.density_error_mean_pct as f64)),
    };
    let front = ScatterPlot {
        title: "Dam-break front vs Martin & Moyce: RMS Z error (shifted)".into(),
        x_label: "cost: wall-clock seconds per simulated second [s/s]".into(),
        y_label: "RMS error of Z = x/a [column widths a]".into(),
        series: series(&|r| r.dam_break.as_ref().map(|d| d.rms_z_shifted)),
    };
    let plots = [density, front];
    write_stacked_png(&plots, &dir.join("trade.png"), 1000, 640)?;
    write_stacked_svg(&plots, &dir.join("trade.svg"), 1000, 640)
}

/// One marker shape per solver: discs for WCSPH, triangles for DFSPH, squares for PBF.
fn marker_of(series_key: &str) -> Marker {
    if series_key.ends_with("dfsph") {
        Marker::Triangle
    } else if series_key.ends_with("pbf") {
        Marker::Square
    } else {
        Marker::Circle
    }
}

/// The plot series of a run: backend and integrator for WCSPH, backend and solver otherwise.
fn series_key(r: &Report) -> String {
    if r.solver == "wcsph" {
        format!("{} {}", r.backend, r.integrator)
    } else {
        format!("{} {}", r.backend, r.solver)
    }
}
