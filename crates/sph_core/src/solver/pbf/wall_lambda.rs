//! The walls' share of PBF's pressure: each boundary sample takes the λ of the water around it,
//! λ_b = Σ_i λ_i W_ib / Σ_i W_ib (the Shepard average of Adami et al. 2012's pressure
//! extrapolation onto the wall, eq. 27 without its hydrostatic term, in λ's units), and the
//! corrections of [`crate::solver::pbf::macklin2013::compute_corrections`] push with
//! V_b (λ_i + λ_b) ∇W_ib, as a fluid neighbour pushes with (m/ρ0) (λ_i + λ_j) ∇W_ij.
//!
//! Why: with the samples pushing by λ_i alone, a particle against a wall carries the wall's half
//! of every pair itself, and its λ reads up to twice the water's pressure (a tank's floor layer
//! +78 %, the particles along the side walls +15 to +28 %, docs/pbf.md). One λ_b per sample,
//! shared by all the particles around it, makes the sample a neighbour like any other; a λ
//! mirrored per pair (λ_b = λ_i, a different one for every particle the sample touches) is no
//! neighbour's push, and it keeps a tank at rest boiling at 0.1 m/s (docs/pbf.md).
//!
//! The pairs are the step's ([`SampleNeighbors::rebuild`] transposes the lists' boundary pairs,
//! found at the predicted positions); the kernel is evaluated at the iteration's positions, as
//! in every PBF pass. GPU twins: `render/solvers/pbf/pbf_wall_lists.wgsl` (the transpose, found
//! again from the samples' side, at most `gpu_layout::PBF_MAX_WALL_NEIGHBORS` a sample) and
//! `pbf_wall_lambda.wgsl`.

use crate::boundary::samples::Boundary;
use crate::neighbor::lists::IndexLists;
use crate::solver::pbf::macklin2013::{Constraint, PbfContext};
use glam::Vec3;
use rayon::prelude::*;

/// The fluid particles within reach of every boundary sample over a step: the transpose of
/// [`IndexLists`]' boundary pairs, each sample's particles in ascending order.
#[derive(Clone, Debug, Default)]
pub struct SampleNeighbors {
    /// Sample b's particles are `fluid[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    fluid: Vec<u32>,
}

impl SampleNeighbors {
    /// Transposes the boundary pairs of `lists` for `samples` boundary samples.
    pub fn rebuild(&mut self, lists: &IndexLists, samples: usize) {
        let pairs = boundary_pairs(lists);
        self.start.clear();
        self.start.resize(samples + 1, 0);
        for &(b, _) in &pairs {
            self.start[b as usize + 1] += 1;
        }
        for b in 0..samples {
            self.start[b + 1] += self.start[b];
        }
        self.fluid.clear();
        self.fluid.resize(pairs.len(), 0);
        let mut next: Vec<u32> = self.start[..samples].to_vec();
        // `fold` visits the particles in order, so each sample's particles stay ascending.
        for &(b, i) in &pairs {
            let slot = &mut next[b as usize];
            self.fluid[*slot as usize] = i;
            *slot += 1;
        }
    }

    /// The samples the lists were transposed for.
    pub fn samples(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// The particles within reach of sample `b`.
    pub fn of(&self, b: usize) -> &[u32] {
        &self.fluid[self.start[b] as usize..self.start[b + 1] as usize]
    }
}

/// The boundary pairs of `lists` as (sample, particle), in the particles' order.
fn boundary_pairs(lists: &IndexLists) -> Vec<(u32, u32)> {
    lists.fold(
        Vec::new,
        |mut pairs, i, of| {
            pairs.extend(of.boundary.iter().map(|&b| (b, i as u32)));
            pairs
        },
        |mut a, mut b| {
            a.append(&mut b);
            a
        },
    )
}

/// λ_b = Σ_i λ_i W_ib / Σ_i W_ib for every sample of `boundary`, over its particles of
/// `neighbors` at `positions`, with the iteration's λ in `constraint` (0 for a sample with no
/// particle within h at its positions).
pub fn extrapolate_wall_lambda(
    ctx: &PbfContext,
    neighbors: &SampleNeighbors,
    positions: &[Vec3],
    boundary: &Boundary,
    constraint: &[Constraint],
    out: &mut Vec<f32>,
) {
    let k = &ctx.kernel;
    out.resize(neighbors.samples(), 0.0);
    out.par_iter_mut().enumerate().for_each(|(b, lambda)| {
        let x_b = boundary.position[b];
        let (mut weighted, mut weight) = (0.0, 0.0);
        for &i in neighbors.of(b) {
            let i = i as usize;
            let w = k
                .value_and_gradient_factor((positions[i] - x_b).length_squared())
                .0;
            weighted += w * constraint[i].lambda;
            weight += w;
        }
        *lambda = if weight > 0.0 { weighted / weight } else { 0.0 };
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::collider::Slip;
    use crate::container::BoxContainer;
    use crate::neighbor::Neighbors;
    use crate::params::SphParams;
    use crate::spawn::BlockSpawn;

    /// The transpose holds every boundary pair of the lists once, and a uniform λ reaches every
    /// sample in reach unchanged (the Shepard average of a constant), the others 0.
    #[test]
    fn the_samples_take_the_lambda_of_the_water_in_reach() {
        let params = SphParams::water();
        let (h, dx) = (params.smoothing_radius, params.spacing());
        let ctx = PbfContext::of(&params);
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.2));
        let mut boundary = Boundary::new(&container, &params, Slip::Free).unwrap();
        boundary.sort();
        let raw = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 4.0 * dx, 0.1), dx).positions();
        let n = raw.len();
        let mut neighbors = Neighbors::new(params.neighbor_search, &container, h, n).unwrap();
        let order = neighbors.sort(&raw).to_vec();
        let positions: Vec<Vec3> = order.iter().map(|&i| raw[i as usize]).collect();
        let mut lists = IndexLists::default();
        lists.rebuild_indices(&neighbors, &positions, Some(&boundary));
        let samples = boundary.position.len();
        let mut transposed = SampleNeighbors::default();
        transposed.rebuild(&lists, samples);
        assert_eq!(transposed.samples(), samples);
        let mut pairs = boundary_pairs(&lists);
        pairs.sort_unstable();
        let back: Vec<(u32, u32)> = (0..samples)
            .flat_map(|b| transposed.of(b).iter().map(move |&i| (b as u32, i)))
            .collect();
        assert!(pairs.len() > 1000, "{} pairs", pairs.len());
        assert_eq!(back, pairs);
        let lambda = -1e-6;
        let constraint = vec![
            Constraint {
                lambda,
                density: params.rest_density,
            };
            n
        ];
        let mut wall = Vec::new();
        extrapolate_wall_lambda(
            &ctx,
            &transposed,
            &positions,
            &boundary,
            &constraint,
            &mut wall,
        );
        let reached = (0..samples).filter(|&b| !transposed.of(b).is_empty());
        let mut count = 0;
        for b in reached {
            assert!(
                (wall[b] - lambda).abs() <= 1e-5 * lambda.abs(),
                "{}",
                wall[b]
            );
            count += 1;
        }
        assert!(count > 100 && count < samples, "{count} of {samples}");
        let unreached = (0..samples).filter(|&b| transposed.of(b).is_empty());
        assert!(unreached.map(|b| wall[b]).all(|l| l == 0.0));
    }
}
