//! The frame's probes and their sums, read back every frame.

use crate::params::SphParams;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Most probes the GPU measures (the rest are left out and reported).
pub const MAX_GPU_PROBES: usize = 16;

/// The flux sums' fixed-point unit [m/s]: Σ v·n is summed as i32 multiples of it.
pub const PROBE_SPEED_UNIT: f32 = 1e-4;

/// A probe as the GPU reads it (WGSL `GpuProbe`). Rust twin: [`crate::flow::probe::ProbeKind`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuProbe {
    /// Level: (x, 0, z); flux: the rectangle's centre; count: the box's centre [m]. w = the
    /// kind: 0 level, 1 flux, 2 count.
    pub center_kind: [f32; 4],
    /// World to probe frame, quaternion (x, y, z, w) (identity for a level).
    pub to_local: [f32; 4],
    /// Level: (radius, 0, 0); flux: (half width, half height, half slab thickness); count: the
    /// half extents [m].
    pub half: [f32; 4],
    /// Flux: the unit normal (world). Level: the column's bins
    /// ([`crate::flow::probe::LevelColumn`]): (floor, bin height, 0, 0) [m].
    pub normal: [f32; 4],
}

/// The frame's probes and their sums (WGSL `SphProbes`), written whole by the CPU with zeroed
/// sums every frame that steps, summed by every closing kick, read back every frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuProbes {
    /// Probes in use.
    pub count: u32,
    /// The main world's frame number, so a readback is matched with its probes.
    pub frame: u32,
    /// Steps summed (each closing kick of particle 0 adds one).
    pub samples: u32,
    /// The last step summed (the clock's step count at its closing kick).
    pub step: u32,
    /// The simulated time at the end of that step [ns], low and high words.
    pub time_ns: [u32; 2],
    /// Padding.
    pub pad: [u32; 2],
    /// The probes.
    pub probes: [GpuProbe; MAX_GPU_PROBES],
    /// Per probe: [unused, particles, Σ v·n in [`PROBE_SPEED_UNIT`] (i32 bits), unused],
    /// summed over the frame's steps.
    pub sums: [[u32; 4]; MAX_GPU_PROBES],
    /// Per Level probe and bin: the [`float_key`] of the bin's highest particle centre over
    /// the frame's steps (0: empty).
    pub level_tops: [[u32; crate::flow::probe::LEVEL_BINS]; MAX_GPU_PROBES],
}

impl Default for GpuProbes {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// A key that orders f32 as u32 (atomicMax on positions): negative values flipped, positive
/// ones with the sign bit set. 0 is below every finite value's key.
pub fn float_key(x: f32) -> u32 {
    let b = x.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The value of a [`float_key`] (`None` for the 0 key of no particle).
pub fn key_float(key: u32) -> Option<f32> {
    if key == 0 {
        return None;
    }
    let b = if key & 0x8000_0000 != 0 {
        key & 0x7fff_ffff
    } else {
        !key
    };
    Some(f32::from_bits(b))
}

impl GpuProbes {
    /// The simulated time at the end of the last step summed [s].
    pub fn time(&self) -> f64 {
        ((self.time_ns[1] as u64) << 32 | self.time_ns[0] as u64) as f64 * 1e-9
    }

    /// The GPU form of the first [`MAX_GPU_PROBES`] of `kinds` in `container` for particles
    /// of spacing `spacing`, for frame `frame`, with zero sums.
    pub fn of(
        kinds: &[crate::flow::probe::ProbeKind],
        container: &crate::container::BoxContainer,
        spacing: f32,
        frame: u32,
    ) -> Self {
        use crate::flow::probe::{flux_slab_thickness, LevelColumn, ProbeKind};
        let column = LevelColumn::of(container, spacing);
        let mut out = Self {
            count: kinds.len().min(MAX_GPU_PROBES) as u32,
            frame,
            ..Self::default()
        };
        for (slot, kind) in out.probes.iter_mut().zip(kinds) {
            let q = |r: glam::Quat| {
                let r = r.inverse();
                [r.x, r.y, r.z, r.w]
            };
            *slot = match *kind {
                ProbeKind::Level { x, z, radius } => GpuProbe {
                    center_kind: [x, 0.0, z, 0.0],
                    to_local: [0.0, 0.0, 0.0, 1.0],
                    half: [radius, 0.0, 0.0, 0.0],
                    normal: [column.floor, column.bin, 0.0, 0.0],
                },
                ProbeKind::Flux { pose, half_size } => {
                    let c = pose.translation;
                    let n = pose.rotation * Vec3::Z;
                    GpuProbe {
                        center_kind: [c.x, c.y, c.z, 1.0],
                        to_local: q(pose.rotation),
                        half: [
                            half_size[0],
                            half_size[1],
                            0.5 * flux_slab_thickness(spacing),
                            0.0,
                        ],
                        normal: [n.x, n.y, n.z, 0.0],
                    }
                }
                ProbeKind::Count { region } => {
                    let c = region.pose.translation;
                    let h = region.half_extents;
                    GpuProbe {
                        center_kind: [c.x, c.y, c.z, 2.0],
                        to_local: q(region.pose.rotation),
                        half: [h.x, h.y, h.z, 0.0],
                        normal: [0.0; 4],
                    }
                }
            };
        }
        out
    }

    /// Probe `k`'s reading, averaged over the summed steps (level: the column of all of them
    /// together), for particles of `params`; `None` before a step was summed.
    pub fn reading(
        &self,
        k: usize,
        params: &SphParams,
    ) -> Option<crate::flow::probe::ProbeReading> {
        use crate::flow::probe::flux_slab_thickness;
        if self.samples == 0 || k >= self.count as usize {
            return None;
        }
        let samples = self.samples as f64;
        let [_, particles, flux, _] = self.sums[k];
        let mean_particles = particles as f64 / samples;
        let count = mean_particles.round() as u32;
        let spacing = params.spacing();
        Some(match self.probes[k].center_kind[3] as u32 {
            0 => crate::flow::probe::ProbeReading {
                value: crate::flow::probe::column_surface(&self.level_tops[k].map(key_float))
                    .map(|y| y + 0.5 * spacing),
                particles: count,
                mean_speed: None,
            },
            1 => {
                let sum = flux as i32 as f64 * PROBE_SPEED_UNIT as f64;
                let volume = (params.particle_mass / params.rest_density) as f64;
                crate::flow::probe::ProbeReading {
                    value: Some(
                        (sum / samples * volume / flux_slab_thickness(spacing) as f64) as f32,
                    ),
                    particles: count,
                    mean_speed: (particles > 0).then(|| (sum / particles as f64) as f32),
                }
            }
            _ => crate::flow::probe::ProbeReading {
                value: Some(mean_particles as f32),
                particles: count,
                mean_speed: None,
            },
        })
    }
}

#[cfg(test)]
mod probe_layout_tests {
    use super::*;

    #[test]
    fn float_keys_keep_the_order_of_floats() {
        let xs = [-3.5f32, -0.01, -0.0, 0.0, 1e-6, 0.25, 7.0];
        let keys: Vec<u32> = xs.iter().map(|&x| float_key(x)).collect();
        assert!(keys.windows(2).all(|w| w[0] <= w[1]), "{keys:?}");
        for &x in &xs {
            assert_eq!(key_float(float_key(x)), Some(x));
        }
        assert_eq!(key_float(0), None);
    }
}
