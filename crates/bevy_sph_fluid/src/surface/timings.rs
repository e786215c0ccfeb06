//! The surface passes' GPU times into [`SphStats::surface_ms`], from Bevy's render diagnostics
//! (timestamp queries; present when `RenderDiagnosticsPlugin` is added and the adapter has them).

use super::composite::NAME as COMPOSITE;
use super::depth::NAME as DEPTH;
use super::filter::NAME as FILTER;
use super::normals::NAME as NORMALS;
use super::passes::filter_pass_name;
use super::settings::SphSurfaceStatus;
use super::thickness::NAME as THICKNESS;
use super::whitewater::NAME as WHITEWATER;
use crate::api::SphStats;
use bevy::diagnostic::{DiagnosticPath, DiagnosticsStore};
use bevy::prelude::*;

/// The last measured GPU milliseconds of the pass called `name`.
fn measured(store: &DiagnosticsStore, name: &str) -> Option<f64> {
    store
        .get(&DiagnosticPath::new(format!("render/{name}/elapsed_gpu")))
        .and_then(|d| d.value())
}

/// Depth, thickness, whitewater (while on), the filter's passes summed, normals and the
/// composite, of the first surface camera; empty without timestamps.
pub(crate) fn sph_record_surface_timings(
    store: Option<Res<DiagnosticsStore>>,
    cameras: Query<&SphSurfaceStatus>,
    mut stats: ResMut<SphStats>,
) {
    let (Some(store), Some(status)) = (store, cameras.iter().next()) else {
        if !stats.surface_ms.is_empty() {
            stats.surface_ms.clear();
        }
        return;
    };
    let mut times = Vec::new();
    for name in [DEPTH, THICKNESS, WHITEWATER] {
        if let Some(ms) = measured(&store, name) {
            times.push((name.to_string(), ms));
        }
    }
    let filter: Vec<f64> = (0..2 * status.applied.filter_iterations)
        .filter_map(|k| measured(&store, &filter_pass_name(k)))
        .collect();
    if !filter.is_empty() {
        times.push((FILTER.to_string(), filter.iter().sum()));
    }
    for name in [NORMALS, COMPOSITE] {
        if let Some(ms) = measured(&store, name) {
            times.push((name.to_string(), ms));
        }
    }
    if stats.surface_ms != times {
        stats.surface_ms = times;
    }
}
