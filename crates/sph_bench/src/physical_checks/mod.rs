//! Physical checks against textbook answers, for choosing the solvers' defaults by physics rather
//! than by eye: a U-tube's oscillation period ([`u_tube`], T = 2π √(L / 2g)) and the discharge
//! through a sluice's slot ([`orifice`], Q = Cd b W √(2 g H)). Each file holds its geometry (the
//! scenarios build their setups from it), its sampler and the reduction of the samples to figures
//! with the textbook value beside them. Nothing here imports the rest of `sph-bench`.

pub mod orifice;
pub mod u_tube;
