//! Whitewater: diffuse particles after Ihmsen, Akinci, Akinci & Teschner 2012, "Unified spray,
//! foam and bubbles for particle-based fluids" ([`ihmsen2012`]). Where the water traps air, breaks
//! at a crest or moves fast, it sheds diffuse particles; each step classifies them by the fluid
//! around them as spray (ballistic), foam (carried by the surface, with a lifetime) or bubbles
//! (buoyant, dragged by the water). They never act on the water. They live in a pool of fixed
//! capacity ([`pool`]); a particle that finds it full is counted, never lost without a trace.
//!
//! This is the CPU reference: the plugin runs it on its CPU backend (its surface draws the
//! diffuse particles); GPU stages are to follow it.

pub mod ihmsen2012;
pub mod pool;
pub mod settings;
