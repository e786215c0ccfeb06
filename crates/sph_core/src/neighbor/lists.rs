//! Neighbour lists with their weighted kernel gradients, built once per step for the iterative
//! solvers: DFSPH visits the same pairs at the same positions a dozen times a step, and reading
//! a list is several times cheaper than walking 27 cells with a distance test each time.
//!
//! The lists are kept in chunks of [`CHUNK`] particles, built in parallel and never gathered into
//! one array, so a rebuild reuses every allocation and copies nothing. [`NeighborLists`] holds
//! [`Pair`]s with their gradients (DFSPH); [`IndexLists`] holds the indices alone (PBF, whose
//! passes evaluate the kernel at positions that move every iteration: 4 bytes a pair to read
//! instead of 16).

use crate::boundary::samples::Boundary;
use crate::gpu_dfsph_pairs;
use crate::kernel::CubicSpline;
use crate::neighbor::grid::GROUP;
use crate::neighbor::pair_lanes::{lane_sum, wide_lanes, Lanes, LANES};
use crate::neighbor::Neighbors;
use glam::Vec3;
use rayon::prelude::*;

/// Particles per chunk.
pub const CHUNK: usize = 256;

/// A neighbour j of particle i with a weighted gradient: m_j ∇W(x_i - x_j) for a fluid
/// neighbour, Ψ_b ∇W(x_i - x_b) = ρ0 V_b ∇W for a boundary sample (units kg/m⁴).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pair {
    /// The neighbour's index (sorted fluid particle, or sorted boundary sample).
    pub index: u32,
    /// The weighted kernel gradient.
    pub grad: Vec3,
}

/// The lists of [`CHUNK`] consecutive particles.
#[derive(Clone, Debug)]
struct ListChunk<P> {
    /// Fluid pairs of particle k of the chunk: `fluid[fluid_start[k]..fluid_start[k + 1]]`.
    fluid_start: Vec<u32>,
    fluid: Vec<P>,
    /// Boundary pairs, laid out likewise.
    boundary_start: Vec<u32>,
    boundary: Vec<P>,
}

impl<P> Default for ListChunk<P> {
    fn default() -> Self {
        Self {
            fluid_start: Vec::new(),
            fluid: Vec::new(),
            boundary_start: Vec::new(),
            boundary: Vec::new(),
        }
    }
}

impl<P> ListChunk<P> {
    /// Empties the lists, keeping the allocations, and opens particle 0's.
    fn restart(&mut self) {
        self.fluid_start.clear();
        self.fluid.clear();
        self.boundary_start.clear();
        self.boundary.clear();
        self.fluid_start.push(0);
        self.boundary_start.push(0);
    }
}

/// The fluid and boundary neighbours (i itself excluded) of every particle: [`Pair`]s with their
/// gradients by default, or bare `u32` indices ([`IndexLists`]).
#[derive(Clone, Debug)]
pub struct NeighborLists<P = Pair> {
    chunks: Vec<ListChunk<P>>,
    len: usize,
}

impl<P> Default for NeighborLists<P> {
    fn default() -> Self {
        Self {
            chunks: Vec::new(),
            len: 0,
        }
    }
}

/// The neighbours' indices alone: the lists of PBF, which evaluates the kernel itself.
pub type IndexLists = NeighborLists<u32>;

/// What the list of one particle holds, handed to the passes.
#[derive(Clone, Copy, Debug)]
pub struct PairsOf<'a, P = Pair> {
    /// Fluid neighbours.
    pub fluid: &'a [P],
    /// Boundary samples.
    pub boundary: &'a [P],
}

/// What the lists are built from: the sorted particles, their search structure, the boundary
/// samples and the weights of the gradients (m for fluid pairs, ρ0 V_b for boundary pairs).
#[derive(Clone, Copy)]
pub struct ListSource<'a> {
    /// The search structure of `positions`.
    pub neighbors: &'a Neighbors,
    /// Sorted positions.
    pub positions: &'a [Vec3],
    /// The boundary samples, if any.
    pub boundary: Option<&'a Boundary>,
    /// Particle mass m.
    pub mass: f32,
    /// Rest density ρ0.
    pub rest_density: f32,
}

/// The kernel the lists are built with: (W, ∇W) of r = x_i - x_j with |r|² = r2.
pub trait PairKernel: Fn(Vec3, f32) -> (f32, Vec3) + Sync {}
impl<T: Fn(Vec3, f32) -> (f32, Vec3) + Sync> PairKernel for T {}

impl<P: Send + Sync> NeighborLists<P> {
    /// Particles listed.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no particle is listed.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Pairs listed in total (fluid, boundary).
    pub fn pair_counts(&self) -> (usize, usize) {
        self.chunks.iter().fold((0, 0), |(f, b), c| {
            (f + c.fluid.len(), b + c.boundary.len())
        })
    }

    /// `f(i, pairs of i, &mut out[i])` for every particle, in parallel.
    pub fn update<T: Send>(&self, out: &mut [T], f: impl Fn(usize, PairsOf<P>, &mut T) + Sync) {
        out[..self.len]
            .par_chunks_mut(CHUNK)
            .zip(self.chunks.par_iter())
            .enumerate()
            .for_each(|(c, (out, chunk))| {
                for (k, o) in out.iter_mut().enumerate() {
                    f(c * CHUNK + k, chunk.pairs(k), o);
                }
            });
    }

    /// `f(i, pairs of i, &mut a[i], &mut b[i])` for every particle, in parallel: a pass with two
    /// outputs.
    pub fn update_pair<A: Send, B: Send>(
        &self,
        a: &mut [A],
        b: &mut [B],
        f: impl Fn(usize, PairsOf<P>, &mut A, &mut B) + Sync,
    ) {
        a[..self.len]
            .par_chunks_mut(CHUNK)
            .zip(b[..self.len].par_chunks_mut(CHUNK))
            .zip(self.chunks.par_iter())
            .enumerate()
            .for_each(|(c, ((a, b), chunk))| {
                for (k, (a, b)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
                    f(c * CHUNK + k, chunk.pairs(k), a, b);
                }
            });
    }

    /// `f(acc, i, pairs of i, &mut a[i], &mut b[i])` for every particle, in parallel, folded per
    /// chunk from `identity()` and combined with `reduce`: a pass with two outputs and a sum.
    pub fn update_fold<A: Send, B: Send, R: Send>(
        &self,
        a: &mut [A],
        b: &mut [B],
        identity: impl Fn() -> R + Sync + Send,
        f: impl Fn(R, usize, PairsOf<P>, &mut A, &mut B) -> R + Sync + Send,
        reduce: impl Fn(R, R) -> R + Sync + Send,
    ) -> R {
        a[..self.len]
            .par_chunks_mut(CHUNK)
            .zip(b[..self.len].par_chunks_mut(CHUNK))
            .zip(self.chunks.par_iter())
            .enumerate()
            .fold(&identity, |acc, (c, ((a, b), chunk))| {
                a.iter_mut()
                    .zip(b.iter_mut())
                    .enumerate()
                    .fold(acc, |acc, (k, (a, b))| {
                        f(acc, c * CHUNK + k, chunk.pairs(k), a, b)
                    })
            })
            .reduce(&identity, reduce)
    }

    /// Σ_i f(i, pairs of i) folded per chunk with `fold` and combined with `reduce`, in parallel.
    pub fn fold<A: Send>(
        &self,
        identity: impl Fn() -> A + Sync + Send,
        fold: impl Fn(A, usize, PairsOf<P>) -> A + Sync + Send,
        reduce: impl Fn(A, A) -> A + Sync + Send,
    ) -> A {
        self.chunks
            .par_iter()
            .enumerate()
            .map(|(c, chunk)| {
                let count = chunk.fluid_start.len() - 1;
                (0..count).fold(identity(), |acc, k| {
                    fold(acc, c * CHUNK + k, chunk.pairs(k))
                })
            })
            .reduce(&identity, reduce)
    }
}

/// Calls `emit(i, fluid neighbours of i, boundary samples of i)` for the particles
/// `from..end` of `positions` (sorted, searched by `neighbors`) in order, i itself excluded;
/// `scratch` holds the index lists between calls. On the dense grid, the particles that share a
/// cell are searched together ([`crate::neighbor::DenseGrid::append_group_neighbors`]); the
/// lists are in increasing index order either way.
fn for_each_listed(
    neighbors: &Neighbors,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    (from, end): (usize, usize),
    scratch: &mut ListScratch,
    mut emit: impl FnMut(usize, &[u32], &[u32]),
) {
    let ListScratch { fluid, solid } = scratch;
    let mut i = from;
    while i < end {
        fluid.iter_mut().for_each(Vec::clear);
        // The particles from i that share its cell (sorted by cell, they follow it).
        let count = match neighbors {
            Neighbors::Grid(grid) => {
                let members = &positions[i..end.min(i + GROUP)];
                let skip = std::array::from_fn(|g| i + g);
                grid.append_group_neighbors(positions, members, skip, fluid)
            }
            Neighbors::Hash(hash) => {
                hash.for_each_neighbor(positions, positions[i], |j, _, _| {
                    if j != i {
                        fluid[0].push(j as u32);
                    }
                });
                1
            }
        };
        // The boundary samples near them, likewise (the samples' grid may be laid out
        // differently, so the run may split).
        let mut solid_listed = 0;
        while solid_listed < count {
            solid.iter_mut().for_each(Vec::clear);
            let first = i + solid_listed;
            let listed = match boundary {
                Some(b) => b.grid.append_group_neighbors(
                    &b.position,
                    &positions[first..i + count],
                    [usize::MAX; GROUP],
                    solid,
                ),
                None => count - solid_listed,
            };
            for (g, samples) in solid.iter().enumerate().take(listed) {
                emit(first + g, &fluid[solid_listed + g], samples);
            }
            solid_listed += listed;
        }
        i += count;
    }
}

/// The index lists of one run of particles, reused between runs.
#[derive(Default)]
struct ListScratch {
    fluid: [Vec<u32>; GROUP],
    solid: [Vec<u32>; GROUP],
}

impl IndexLists {
    /// Rebuilds the lists of `positions` (sorted, searched by `neighbors`) and of the boundary
    /// samples within h of them, reusing the allocations.
    pub fn rebuild_indices(
        &mut self,
        neighbors: &Neighbors,
        positions: &[Vec3],
        boundary: Option<&Boundary>,
    ) {
        let n = positions.len();
        self.len = n;
        self.chunks
            .resize_with(n.div_ceil(CHUNK), ListChunk::default);
        self.chunks
            .par_iter_mut()
            .enumerate()
            .for_each(|(c, chunk)| {
                chunk.restart();
                let range = (c * CHUNK, ((c + 1) * CHUNK).min(n));
                let mut scratch = ListScratch::default();
                for_each_listed(
                    neighbors,
                    positions,
                    boundary,
                    range,
                    &mut scratch,
                    |_, fluid, samples| {
                        chunk.fluid.extend_from_slice(fluid);
                        chunk.fluid_start.push(chunk.fluid.len() as u32);
                        chunk.boundary.extend_from_slice(samples);
                        chunk.boundary_start.push(chunk.boundary.len() as u32);
                    },
                );
            });
    }
}

impl NeighborLists {
    /// Rebuilds the lists of `source`'s particles with `kernel`'s gradient scaled by m (fluid)
    /// and by ρ0 V_b (boundary), reusing the allocations; writes the densities
    /// ρ_i = m Σ_j W_ij + ρ0 Σ_b V_b W_ib (i included) of the same kernel on the way. The pairs
    /// are found as [`IndexLists::rebuild_indices`] finds them, then evaluated in list order.
    pub fn rebuild(&mut self, source: ListSource, kernel: impl PairKernel, density: &mut [f32]) {
        let (positions, mass) = (source.positions, source.mass);
        let self_weight = kernel(Vec3::ZERO, 0.0).0;
        self.rebuild_by(
            source,
            density,
            |x_i, list, out| {
                let mut fluid = self_weight;
                for &j in list {
                    let r = x_i - positions[j as usize];
                    let (w, grad) = kernel(r, r.length_squared());
                    fluid += w;
                    out.push(Pair {
                        index: j,
                        grad: grad * mass,
                    });
                }
                fluid
            },
            |r, psi| {
                let (w, grad) = kernel(r, r.length_squared());
                (w, grad * psi)
            },
        );
    }

    /// [`Self::rebuild`] with the cubic spline `kernel` (DFSPH's), the fluid pairs evaluated
    /// eight at a time ([`crate::neighbor::pair_lanes`], in the AVX2 copy where the CPU has it) with the
    /// fused [`CubicSpline::value_and_gradient_factor`]: the same pairs, W and ∇W to rounding.
    /// The fluid pairs' m ∇W_ij are rounded as the GPU packs them ([`gpu_dfsph_pairs::round`]),
    /// so that both backends' DFSPH solve with the same g_ij.
    pub fn rebuild_cubic_spline(
        &mut self,
        source: ListSource,
        kernel: &CubicSpline,
        density: &mut [f32],
    ) {
        let (positions, mass) = (source.positions, source.mass);
        let self_weight = kernel.value(0.0);
        let scale = gpu_dfsph_pairs::scale(mass, kernel.l);
        let wide = wide_lanes();
        self.rebuild_by(
            source,
            density,
            |x_i, list, out| {
                let pass = FluidPairs {
                    kernel,
                    x_i,
                    list,
                    positions,
                    mass,
                    scale,
                };
                self_weight + pass.append(wide, out)
            },
            |r, psi| {
                let (w, f) = kernel.value_and_gradient_factor(r.length_squared());
                (w, r * (f * psi))
            },
        );
    }

    /// The walk both rebuilds share: the pairs found by [`for_each_listed`], then per particle
    /// `fluid(x_i, list, pairs)` appends the fluid pairs and returns Σ_j W_ij (i included), and
    /// `solid(r, Ψ_b)` gives a boundary pair's (W, Ψ_b ∇W); the densities on the way.
    fn rebuild_by(
        &mut self,
        source: ListSource,
        density: &mut [f32],
        fluid: impl Fn(Vec3, &[u32], &mut Vec<Pair>) -> f32 + Sync,
        solid: impl Fn(Vec3, f32) -> (f32, Vec3) + Sync,
    ) {
        let ListSource {
            neighbors,
            positions,
            boundary,
            mass,
            rest_density,
        } = source;
        let n = positions.len();
        self.len = n;
        self.chunks
            .resize_with(n.div_ceil(CHUNK), ListChunk::default);
        density[..n]
            .par_chunks_mut(CHUNK)
            .zip(self.chunks.par_iter_mut())
            .enumerate()
            .for_each(|(c, (density, chunk))| {
                chunk.restart();
                let from = c * CHUNK;
                let mut scratch = ListScratch::default();
                for_each_listed(
                    neighbors,
                    positions,
                    boundary,
                    (from, from + density.len()),
                    &mut scratch,
                    |i, fluid_list, samples| {
                        let x_i = positions[i];
                        let fluid_weight = fluid(x_i, fluid_list, &mut chunk.fluid);
                        chunk.fluid_start.push(chunk.fluid.len() as u32);
                        let mut solid_weight = 0.0;
                        if let Some(b) = boundary {
                            for &k in samples {
                                let psi = rest_density * b.volume[k as usize];
                                let (w, grad) = solid(x_i - b.position[k as usize], psi);
                                solid_weight += psi * w;
                                chunk.boundary.push(Pair { index: k, grad });
                            }
                        }
                        chunk.boundary_start.push(chunk.boundary.len() as u32);
                        density[i - from] = mass * fluid_weight + solid_weight;
                    },
                );
            });
    }
}

/// One particle's fluid pairs of [`NeighborLists::rebuild_cubic_spline`].
struct FluidPairs<'a> {
    kernel: &'a CubicSpline,
    x_i: Vec3,
    list: &'a [u32],
    positions: &'a [Vec3],
    mass: f32,
    /// The packed pairs' scale ([`gpu_dfsph_pairs::scale`]).
    scale: f32,
}

impl FluidPairs<'_> {
    /// Appends the pairs (m ∇W_ij, rounded as packed) to `out` and returns Σ_j W_ij, in the
    /// AVX2 copy when `wide`.
    #[inline]
    fn append(&self, wide: bool, out: &mut Vec<Pair>) -> f32 {
        #[cfg(target_arch = "x86_64")]
        if wide {
            #[target_feature(enable = "avx2,fma")]
            fn avx2(pass: &FluidPairs, out: &mut Vec<Pair>) -> f32 {
                pass.in_lanes::<true>(out)
            }
            // SAFETY: `wide` comes from `wide_lanes()`: this CPU has AVX2 and FMA.
            return unsafe { avx2(self, out) };
        }
        let _ = wide;
        self.in_lanes::<false>(out)
    }

    #[inline(always)]
    fn in_lanes<const WIDE: bool>(&self, out: &mut Vec<Pair>) -> f32 {
        let beyond = 2.0 * self.kernel.h;
        let mut w_sum = [0.0f32; LANES];
        for block in self.list.chunks(LANES) {
            let r = Lanes::gather::<WIDE>(self.x_i, self.positions, block, beyond);
            let mut f = [0.0f32; LANES];
            for l in 0..LANES {
                let (w, factor) = self.kernel.value_and_gradient_factor(r.r2::<WIDE>(l));
                w_sum[l] += w;
                f[l] = factor * self.mass;
            }
            for (l, &j) in block.iter().enumerate() {
                out.push(Pair {
                    index: j,
                    grad: gpu_dfsph_pairs::round(
                        Vec3::new(r.x[l], r.y[l], r.z[l]) * f[l],
                        self.scale,
                    ),
                });
            }
        }
        lane_sum(&w_sum)
    }
}

impl<P> ListChunk<P> {
    fn fluid_range(&self, k: usize) -> std::ops::Range<usize> {
        self.fluid_start[k] as usize..self.fluid_start[k + 1] as usize
    }

    fn pairs(&self, k: usize) -> PairsOf<'_, P> {
        let f = self.fluid_range(k);
        let b = self.boundary_start[k] as usize..self.boundary_start[k + 1] as usize;
        PairsOf {
            fluid: &self.fluid[f],
            boundary: &self.boundary[b],
        }
    }
}
