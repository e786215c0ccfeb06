// Thickness pass: every sphere adds the length of the pixel's ray inside it, weighted by
// its share of water (additive blending), the water's thickness for Beer-Lambert absorption and refraction.

#import bevy_sph_fluid::surface_impostor::{impostor_vertex, eye_ray, hit_sphere, surface, ImpostorVarying}

@vertex
fn vertex(@builtin(vertex_index) vertex: u32) -> ImpostorVarying {
    return impostor_vertex(vertex);
}

@fragment
fn fragment(in: ImpostorVarying) -> @location(0) f32 {
    let hit = hit_sphere(eye_ray(in.on_billboard), in.center);
    if hit.chord < 0.0 {
        discard;
    }
    // Overlapping spheres hold more volume than their particles: weighted back to water.
    return hit.chord * surface.chord_weight;
}
