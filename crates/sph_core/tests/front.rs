//! The surge-front rule: the connected body's furthest extent, not a lone splash particle.

use sph_core::front::surge_front;
use sph_core::glam::Vec3;
use sph_core::{BlockSpawn, BoxContainer};

fn tank() -> BoxContainer {
    BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(1.0, 0.5, 0.1))
}

#[test]
fn front_of_a_block_is_its_far_face() {
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.1), 0.01);
    let front = surge_front(&block.positions(), &tank(), 0.02).unwrap();
    assert!((front - 0.195).abs() < 1e-4, "front {front}");
}

#[test]
fn lone_splash_particles_and_droplets_are_not_the_front() {
    let mut positions = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.1), 0.01).positions();
    positions.push(Vec3::new(0.6, 0.05, 0.05));
    positions.extend(
        BlockSpawn::new(Vec3::new(0.7, 0.0, 0.0), Vec3::new(0.75, 0.05, 0.05), 0.01).positions(),
    );
    let front = surge_front(&positions, &tank(), 0.02).unwrap();
    assert!((front - 0.195).abs() < 1e-4, "front {front}");
}

#[test]
fn a_connected_tongue_moves_the_front() {
    let mut positions = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.1), 0.01).positions();
    // A thin layer along the floor, connected to the column.
    positions.extend(
        BlockSpawn::new(Vec3::new(0.2, 0.0, 0.0), Vec3::new(0.5, 0.01, 0.01), 0.01).positions(),
    );
    let front = surge_front(&positions, &tank(), 0.02).unwrap();
    assert!((front - 0.495).abs() < 1e-4, "front {front}");
    assert_eq!(surge_front(&[], &tank(), 0.02), None);
}
