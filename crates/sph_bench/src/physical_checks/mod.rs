//! Physical checks against textbook answers, for choosing the solvers' defaults by physics rather
//! than by eye: a U-tube's oscillation period ([`u_tube`], T = 2π √(L / 2g)), the discharge
//! through a sluice's slot ([`orifice`], Q = Cd b W √(2 g H)), and no water through a wall one
//! spacing thick under a 3 m/s jet ([`thin_wall`]). Each file holds its geometry (the
//! scenarios build their setups from it), its sampler and the reduction of the samples to figures
//! with the textbook value beside them. Nothing here imports the rest of `sph-bench`.

pub mod orifice;
pub mod thin_wall;
pub mod u_tube;
