//! Devices that move and measure water: pumps ([`pump`]), drains ([`sink`]), probes
//! ([`probe`]) and the regions they act on ([`region`]).

pub mod probe;
pub mod pump;
pub mod region;
pub mod sink;
