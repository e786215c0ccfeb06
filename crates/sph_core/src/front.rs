//! The surge front of a dam break: how far the connected water body has run along the floor.
//!
//! Rule: two particles are connected when closer than `link`; the water body is the connected
//! component of the particle nearest the corner of the wall behind the column (smallest x + y);
//! the front is that body's largest x, measured from the wall. Detached droplets and lone splash
//! particles are not the front.

use crate::container::BoxContainer;
use crate::neighbor::grid::DenseGrid;
use glam::Vec3;

/// Distance of the connected water body's front from the wall at `container.min().x`, or `None`
/// without particles.
pub fn surge_front(positions: &[Vec3], container: &BoxContainer, link: f32) -> Option<f32> {
    if positions.is_empty() {
        return None;
    }
    let mut grid = DenseGrid::new(container, link).ok()?;
    let order = grid.sort(positions).to_vec();
    let sorted: Vec<Vec3> = order.iter().map(|&i| positions[i as usize]).collect();
    let wall = container.min();
    let start = (0..sorted.len()).min_by(|&a, &b| {
        let key = |p: Vec3| (p.x - wall.x) + (p.y - wall.y);
        key(sorted[a]).total_cmp(&key(sorted[b]))
    })?;
    let mut reached = vec![false; sorted.len()];
    let mut stack = vec![start];
    reached[start] = true;
    let mut front = sorted[start].x;
    while let Some(i) = stack.pop() {
        front = front.max(sorted[i].x);
        grid.for_each_neighbor(&sorted, sorted[i], |j, _, _| {
            if !reached[j] {
                reached[j] = true;
                stack.push(j);
            }
        });
    }
    Some(front - wall.x)
}
