//! Grid and hash neighbour sets, and the neighbour lists built from them (PBF's indices and
//! DFSPH's weighted pairs), equal a brute-force O(n²) search.

use sph_core::glam::Vec3;
use sph_core::gpu_dfsph_pairs;
use sph_core::kernel::CubicSpline;
use sph_core::neighbor::lists::{IndexLists, ListSource, NeighborLists};
use sph_core::neighbor::Neighbors;
use sph_core::rng::SplitMix64;
use sph_core::{BoxContainer, NeighborSearch};
use std::collections::BTreeSet;

fn brute_force(positions: &[Vec3], h: f32) -> Vec<BTreeSet<usize>> {
    positions
        .iter()
        .map(|&x_i| {
            (0..positions.len())
                .filter(|&j| (x_i - positions[j]).length_squared() < h * h)
                .collect()
        })
        .collect()
}

/// The search structure of `mode` over `positions`, its order (checked to be a permutation)
/// and the sorted positions.
fn sort(
    mode: NeighborSearch,
    container: &BoxContainer,
    h: f32,
    capacity: usize,
    positions: &[Vec3],
) -> (Neighbors, Vec<u32>, Vec<Vec3>) {
    let mut neighbors = Neighbors::new(mode, container, h, capacity).unwrap();
    let order = neighbors.sort(positions).to_vec();
    assert_eq!(order.len(), positions.len());
    let mut seen: Vec<u32> = order.clone();
    seen.sort();
    assert!(
        seen.iter().copied().eq(0..positions.len() as u32),
        "order is a permutation"
    );
    let sorted: Vec<Vec3> = order.iter().map(|&i| positions[i as usize]).collect();
    (neighbors, order, sorted)
}

/// Sorts with `mode` and returns, per original particle, its neighbours as original indices.
fn search(
    mode: NeighborSearch,
    container: &BoxContainer,
    h: f32,
    capacity: usize,
    positions: &[Vec3],
) -> Vec<BTreeSet<usize>> {
    let (neighbors, order, sorted) = sort(mode, container, h, capacity, positions);
    let mut result = vec![BTreeSet::new(); positions.len()];
    for (k, &x) in sorted.iter().enumerate() {
        let mut set = BTreeSet::new();
        neighbors.for_each_neighbor(&sorted, x, |j, r, r2| {
            assert!((r - (x - sorted[j])).length() < 1e-6);
            assert!(r2 < h * h);
            assert!(set.insert(order[j] as usize), "neighbour {j} visited twice");
        });
        result[order[k] as usize] = set;
    }
    result
}

/// Sorts with `mode`, builds the PBF index lists (the grid's runs of particles sharing a cell
/// are listed together) and returns, per original particle, its listed neighbours as original
/// indices, itself included (as [`brute_force`] counts it).
fn listed(
    mode: NeighborSearch,
    container: &BoxContainer,
    h: f32,
    capacity: usize,
    positions: &[Vec3],
) -> Vec<BTreeSet<usize>> {
    let (neighbors, order, sorted) = sort(mode, container, h, capacity, positions);
    let mut lists = IndexLists::default();
    lists.rebuild_indices(&neighbors, &sorted, None);
    let mut per_sorted = vec![BTreeSet::new(); positions.len()];
    lists.update(&mut per_sorted, |i, pairs, set| {
        set.insert(order[i] as usize);
        for &j in pairs.fluid {
            assert_ne!(j as usize, i, "particle {i} lists itself");
            assert!(set.insert(order[j as usize] as usize), "{j} listed twice");
        }
        assert!(pairs.boundary.is_empty());
    });
    // DFSPH's lists with weighted gradients list the same pairs, in the same order, with the
    // kernel evaluated at each pair and the densities summed over them (a test kernel: W = 1,
    // ∇W = r, so ρ_i = m (1 + neighbours) and each gradient is m (x_i - x_j)).
    let mut weighted = NeighborLists::default();
    let mut density = vec![0.0; sorted.len()];
    let mass = 2.0;
    let source = ListSource {
        neighbors: &neighbors,
        positions: &sorted,
        boundary: None,
        mass,
        rest_density: 1000.0,
    };
    weighted.rebuild(source, |r, _| (1.0, r), &mut density);
    let mut indices = vec![Vec::new(); sorted.len()];
    lists.update(&mut indices, |_, pairs, out| *out = pairs.fluid.to_vec());
    weighted.fold(
        || (),
        |_, i, pairs| {
            let listed: Vec<u32> = pairs.fluid.iter().map(|p| p.index).collect();
            assert_eq!(listed, indices[i], "{mode:?}: particle {i}'s weighted list");
            for p in pairs.fluid {
                let r = sorted[i] - sorted[p.index as usize];
                assert!(
                    (p.grad - r * mass).length() <= 1e-6,
                    "{mode:?}: pair ({i}, {})",
                    p.index
                );
            }
            assert_eq!(
                density[i],
                mass * (1 + listed.len()) as f32,
                "{mode:?}: ρ_{i}"
            );
        },
        |_, _| (),
    );
    // DFSPH's lists (the cubic spline, pairs evaluated in lanes) hold the same pairs as the
    // scalar evaluation of the same kernel, W to rounding and m ∇W to the packed pairs'
    // rounding (half a step of sph_core::gpu_dfsph_pairs).
    let kernel = CubicSpline::new(h, 0.5 * h);
    let mut exact = NeighborLists::default();
    let mut exact_density = vec![0.0; sorted.len()];
    exact.rebuild(
        source,
        |r, r2| {
            let r_len = r2.sqrt();
            (kernel.value(r_len), kernel.gradient(r, r_len))
        },
        &mut exact_density,
    );
    let mut fast = NeighborLists::default();
    let mut fast_density = vec![0.0; sorted.len()];
    fast.rebuild_cubic_spline(source, &kernel, &mut fast_density);
    let mut fast_pairs = vec![Vec::new(); sorted.len()];
    fast.update(&mut fast_pairs, |_, pairs, out| *out = pairs.fluid.to_vec());
    let scale = mass * kernel.l;
    let half_step = 0.5 * gpu_dfsph_pairs::step(gpu_dfsph_pairs::scale(mass, kernel.l));
    exact.fold(
        || (),
        |_, i, pairs| {
            assert_eq!(
                pairs.fluid.len(),
                fast_pairs[i].len(),
                "{mode:?}: particle {i}"
            );
            for (a, b) in pairs.fluid.iter().zip(&fast_pairs[i]) {
                assert_eq!(a.index, b.index);
                let off = (a.grad - b.grad).abs().max_element();
                assert!(off <= half_step + 1e-6 * scale, "{a:?} {b:?}");
            }
            let (a, b) = (exact_density[i], fast_density[i]);
            assert!(
                (a - b).abs() <= 1e-5 * a.abs().max(mass * kernel.k),
                "ρ {a} {b}"
            );
        },
        |_, _| (),
    );
    let mut result = vec![BTreeSet::new(); positions.len()];
    for (k, set) in per_sorted.into_iter().enumerate() {
        result[order[k] as usize] = set;
    }
    result
}

fn check_all_modes(container: &BoxContainer, h: f32, positions: &[Vec3], capacity: usize) {
    let expected = brute_force(positions, h);
    for mode in [NeighborSearch::Grid, NeighborSearch::Hash] {
        let got = search(mode, container, h, capacity, positions);
        let lists = listed(mode, container, h, capacity, positions);
        for i in 0..positions.len() {
            assert_eq!(
                got[i],
                expected[i],
                "{mode:?}: particle {i} of {}",
                positions.len()
            );
            assert_eq!(
                lists[i],
                expected[i],
                "{mode:?} lists: particle {i} of {}",
                positions.len()
            );
        }
    }
}

fn random_positions(container: &BoxContainer, n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let (lo, hi) = (container.min(), container.max());
    (0..n)
        .map(|_| {
            Vec3::new(
                rng.range(lo.x, hi.x),
                rng.range(lo.y, hi.y),
                rng.range(lo.z, hi.z),
            )
        })
        .collect()
}

#[test]
fn random_configurations_match_brute_force() {
    let container =
        BoxContainer::from_min_max(Vec3::new(-0.3, 0.0, -0.2), Vec3::new(0.5, 0.4, 0.2));
    for (n, seed) in [(0, 1), (1, 2), (2, 3), (3, 4), (17, 5), (500, 6), (3000, 7)] {
        let positions = random_positions(&container, n, seed);
        check_all_modes(&container, 0.05, &positions, n.max(1));
    }
}

#[test]
fn all_particles_in_one_cell_match_brute_force() {
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
    let h = 0.1;
    let cell = BoxContainer::from_min_max(Vec3::splat(0.41), Vec3::splat(0.49));
    let positions = random_positions(&cell, 300, 8);
    check_all_modes(&container, h, &positions, 300);
}

#[test]
fn particles_on_walls_and_corners_match_brute_force() {
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.3));
    let mut positions = random_positions(&container, 400, 9);
    // Snap some onto the walls, including exactly onto the upper corner.
    for (k, p) in positions.iter_mut().enumerate() {
        match k % 4 {
            0 => p.x = 0.0,
            1 => p.y = 0.3,
            2 => *p = Vec3::splat(0.3),
            _ => {}
        }
    }
    check_all_modes(&container, 0.07, &positions, 400);
}

#[test]
fn hash_collisions_never_change_the_neighbour_set() {
    // A tiny table (64 buckets) for 2,000 particles in a large box: many cells share a bucket.
    let container = BoxContainer::from_min_max(Vec3::splat(-2.0), Vec3::splat(2.0));
    let positions = random_positions(&container, 2000, 10);
    let expected = brute_force(&positions, 0.3);
    let got = search(NeighborSearch::Hash, &container, 0.3, 1, &positions);
    assert_eq!(got, expected);
}

#[test]
fn hash_uses_the_designs_primes() {
    let hash = sph_core::neighbor::SpatialHash::new(1.0, 1000);
    let c = sph_core::glam::IVec3::new(1, 2, 3);
    let expected = (73_856_093u32 ^ 2u32.wrapping_mul(19_349_663) ^ 3u32.wrapping_mul(83_492_791))
        % hash.table_size;
    assert_eq!(hash.hash(c), expected);
    // Negative cells wrap like the GPU's u32 arithmetic.
    let neg = sph_core::glam::IVec3::new(-1, 0, 0);
    assert_eq!(
        hash.hash(neg),
        ((-1i32) as u32).wrapping_mul(73_856_093) % hash.table_size
    );
}
