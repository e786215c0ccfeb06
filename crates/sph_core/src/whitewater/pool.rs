//! The diffuse particles: a pool of fixed capacity, structure of arrays. A particle born into a
//! full pool is counted in [`DiffusePool::dropped`]; one that dies (a foam particle's lifetime
//! ends, or any leaves the container) in [`DiffusePool::expired`].

use glam::Vec3;

/// What a diffuse particle is, from the fluid around it (Ihmsen et al. 2012, §4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiffuseKind {
    /// Few fluid neighbours: ballistic, under gravity.
    Spray,
    /// At the surface: carried by the water's velocity, dissolving over its lifetime.
    Foam,
    /// Inside the water: buoyant and dragged by it.
    Bubble,
}

/// The diffuse particles.
#[derive(Clone, Debug, Default)]
pub struct DiffusePool {
    capacity: usize,
    /// Positions [m].
    pub position: Vec<Vec3>,
    /// Velocities [m/s].
    pub velocity: Vec<Vec3>,
    /// Lifetime left [s] (it runs down for foam only).
    pub lifetime: Vec<f32>,
    /// The class of each particle, as of the last step.
    pub kind: Vec<DiffuseKind>,
    /// Particles refused because the pool was full, since it was made.
    pub dropped: u64,
    /// Particles that died, since it was made.
    pub expired: u64,
    /// Particles born, since it was made.
    pub born: u64,
}

impl DiffusePool {
    /// An empty pool of `capacity` particles.
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity,
            ..Default::default()
        }
    }

    /// Live particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether no particle lives.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// The most particles the pool holds.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Adds a particle, or counts it in `dropped` when the pool is full; returns whether it was
    /// added.
    pub fn spawn(&mut self, position: Vec3, velocity: Vec3, lifetime: f32) -> bool {
        if self.len() >= self.capacity {
            self.dropped += 1;
            return false;
        }
        self.position.push(position);
        self.velocity.push(velocity);
        self.lifetime.push(lifetime);
        self.kind.push(DiffuseKind::Spray);
        self.born += 1;
        true
    }

    /// Removes every particle for which `dies(index)` holds, keeping the others in order, and
    /// counts them in `expired`.
    pub fn remove_where(&mut self, dies: impl Fn(usize) -> bool) {
        let mut kept = 0;
        for i in 0..self.len() {
            if dies(i) {
                continue;
            }
            self.position[kept] = self.position[i];
            self.velocity[kept] = self.velocity[i];
            self.lifetime[kept] = self.lifetime[i];
            self.kind[kept] = self.kind[i];
            kept += 1;
        }
        self.expired += (self.len() - kept) as u64;
        self.position.truncate(kept);
        self.velocity.truncate(kept);
        self.lifetime.truncate(kept);
        self.kind.truncate(kept);
    }

    /// Live particles of each kind: spray, foam, bubbles.
    pub fn counts(&self) -> [usize; 3] {
        let mut counts = [0; 3];
        for kind in &self.kind {
            counts[*kind as usize] += 1;
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_pool_counts_what_it_refuses_and_removal_counts_the_dead() {
        let mut pool = DiffusePool::new(3);
        for k in 0..5 {
            pool.spawn(Vec3::splat(k as f32), Vec3::ZERO, 1.0);
        }
        assert_eq!((pool.len(), pool.born, pool.dropped), (3, 3, 2));
        pool.remove_where(|i| i == 1);
        assert_eq!(pool.len(), 2);
        assert_eq!(pool.expired, 1);
        assert_eq!(pool.position, vec![Vec3::ZERO, Vec3::splat(2.0)]);
        // Every particle offered is accounted for.
        assert_eq!(pool.born + pool.dropped, 5);
        assert_eq!(pool.born - pool.expired, pool.len() as u64);
    }
}
