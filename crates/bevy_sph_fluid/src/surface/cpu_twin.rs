//! CPU twins of the surface's passes, line for line after their WGSL (`surface_depth`,
//! `surface_thickness`, `surface_whitewater`, `surface_filter`, `surface_normals`), over images
//! of the scaled target's
//! size stored row by row. The parity test (`tests/surface_rendering.rs`) draws the GPU passes'
//! outputs through [`SphSurfaceDebugView`](super::settings::SphSurfaceDebugView) and compares.

use super::view::GpuSurfaceUniform;
use bevy::math::{IVec2, UVec2, Vec2, Vec3, Vec4, Vec4Swizzles};

/// The view-space point of normalized device coordinates `ndc` at clip depth `z`.
fn unproject(u: &GpuSurfaceUniform, ndc: Vec2, z: f32) -> Vec3 {
    let p = u.view_from_clip * Vec4::new(ndc.x, ndc.y, z, 1.0);
    p.xyz() / p.w
}

/// Normalized device coordinates of `pixel` (a pixel centre is `+ 0.5`) in a target of `size`.
fn pixel_ndc(pixel: Vec2, size: Vec2) -> Vec2 {
    let uv = pixel / size;
    Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0)
}

/// The view-space point at distance `depth` along the view axis on the ray through `ndc`
/// (`surface_types.wgsl`'s `view_position`).
fn view_position(u: &GpuSurfaceUniform, ndc: Vec2, depth: f32) -> Vec3 {
    let near = unproject(u, ndc, 1.0);
    let farther = unproject(u, ndc, 0.5);
    let t = (-depth - near.z) / (farther.z - near.z);
    near + t * (farther - near)
}

/// Pixels of the scaled target per metre across the view at distance `depth`.
fn pixels_per_metre(u: &GpuSurfaceUniform, depth: f32) -> f32 {
    let scale = u.clip_from_view.y_axis.y * 0.5 * u.target_size.y;
    if u.orthographic == 1 {
        scale
    } else {
        scale / depth.max(1e-6)
    }
}

fn size(u: &GpuSurfaceUniform) -> UVec2 {
    u.target_size.as_uvec2()
}

/// The ray through the centre of `pixel`: origin and unit direction, view space (the GPU's
/// fragment ray runs through the same point of its billboard).
fn pixel_ray(u: &GpuSurfaceUniform, pixel: UVec2) -> (Vec3, Vec3) {
    let ndc = pixel_ndc(pixel.as_vec2() + 0.5, u.target_size);
    let on_ray = unproject(u, ndc, 0.5);
    if u.orthographic == 1 {
        (on_ray.with_z(0.0), Vec3::NEG_Z)
    } else {
        (Vec3::ZERO, on_ray.normalize())
    }
}

/// Where the ray enters the sphere around `center` of radius `r`, and the chord inside it
/// (negative when the ray misses).
fn hit_sphere(origin: Vec3, direction: Vec3, center: Vec3, r: f32) -> (f32, f32) {
    let to_origin = origin - center;
    let b = direction.dot(to_origin);
    let c = to_origin.dot(to_origin) - r * r;
    let discriminant = b * b - c;
    if discriminant < 0.0 {
        return (0.0, -1.0);
    }
    let half_chord = discriminant.sqrt();
    (-b - half_chord, 2.0 * half_chord)
}

/// Each pixel's ray against every particle's sphere: `visit(pixel index, t, chord)` per hit.
fn trace(u: &GpuSurfaceUniform, positions: &[Vec3], mut visit: impl FnMut(usize, Vec3, f32)) {
    let centers: Vec<Vec3> = positions
        .iter()
        .map(|&p| u.view_from_world.transform_point3(p))
        .collect();
    let s = size(u);
    for y in 0..s.y {
        for x in 0..s.x {
            let (origin, direction) = pixel_ray(u, UVec2::new(x, y));
            let index = (y * s.x + x) as usize;
            for &center in &centers {
                let (t, chord) = hit_sphere(origin, direction, center, u.sphere_radius);
                if chord >= 0.0 {
                    visit(index, origin + t * direction, chord);
                }
            }
        }
    }
}

/// The depth pass: the nearest sphere's distance along the view axis [m], 0 without water.
pub fn depth_pass(u: &GpuSurfaceUniform, positions: &[Vec3]) -> Vec<f32> {
    let s = size(u);
    let mut depth = vec![0.0f32; (s.x * s.y) as usize];
    trace(u, positions, |index, point, _| {
        let distance = -point.z;
        // The GPU clips what lies behind the eye.
        if distance <= 0.0 {
            return;
        }
        if depth[index] == 0.0 || distance < depth[index] {
            depth[index] = distance;
        }
    });
    depth
}

/// The thickness pass: every sphere's chord times the water's share of the sphere, summed.
pub fn thickness_pass(u: &GpuSurfaceUniform, positions: &[Vec3]) -> Vec<f32> {
    let s = size(u);
    let mut thickness = vec![0.0f32; (s.x * s.y) as usize];
    trace(u, positions, |index, _, chord| {
        thickness[index] += chord * u.chord_weight;
    });
    thickness
}

/// The whitewater pass (`surface_whitewater.wgsl`): for every diffuse particle at `position`
/// of class `class` (0 spray, 1 foam, 2 bubble) whose disc of `u.diffuse_radius` the pixel's ray
/// crosses at q radii from its centre, (1 - q²)² added to its class's channel, and for spray and
/// foam that weight times the centre's distance along the view axis to w.
pub fn whitewater_pass(u: &GpuSurfaceUniform, particles: &[(Vec3, u32)]) -> Vec<Vec4> {
    let s = size(u);
    let mut out = vec![Vec4::ZERO; (s.x * s.y) as usize];
    let centers: Vec<(Vec3, u32)> = particles
        .iter()
        .map(|&(p, class)| (u.view_from_world.transform_point3(p), class.min(2)))
        .collect();
    for y in 0..s.y {
        for x in 0..s.x {
            let (origin, direction) = pixel_ray(u, UVec2::new(x, y));
            let index = (y * s.x + x) as usize;
            for &(center, class) in &centers {
                let to_center = center - origin;
                let along = to_center.dot(direction);
                let off_axis = (to_center - along * direction).length() / u.diffuse_radius;
                if off_axis >= 1.0 {
                    continue;
                }
                let weight = (1.0 - off_axis * off_axis).powi(2);
                out[index][class as usize] += weight;
                if class < 2 {
                    out[index].w += weight * -center.z;
                }
            }
        }
    }
    out
}

/// One direction of the narrow-range filter (`surface_filter.wgsl`).
pub fn filter_pass(u: &GpuSurfaceUniform, depth_in: &[f32], vertical: bool) -> Vec<f32> {
    let s = size(u).as_ivec2();
    let at = |p: IVec2| depth_in[(p.y * s.x + p.x) as usize];
    let step = if vertical { IVec2::Y } else { IVec2::X };
    let mut out = vec![0.0f32; depth_in.len()];
    for y in 0..s.y {
        for x in 0..s.x {
            let pixel = IVec2::new(x, y);
            let depth = at(pixel);
            let index = (y * s.x + x) as usize;
            if depth <= 0.0 {
                continue;
            }
            let radius = (u.filter_radius * pixels_per_metre(u, depth)).min(u.filter_max_pixels);
            let taps = radius.ceil() as i32;
            if taps < 1 {
                out[index] = depth;
                continue;
            }
            let sigma = (0.5 * radius).max(0.5);
            let range = u.depth_range;
            // The centre, then the pairs at k and -k, each only with both samples on this
            // surface (the WGSL says why).
            let (mut sum, mut weights) = (depth, 1.0);
            for k in 1..=taps {
                let ahead = at((pixel + k * step).clamp(IVec2::ZERO, s - 1));
                let behind = at((pixel - k * step).clamp(IVec2::ZERO, s - 1));
                let off = |d: f32| d <= 0.0 || d < depth - range;
                if off(ahead) || off(behind) {
                    continue;
                }
                let w = (-(k * k) as f32 / (2.0 * sigma * sigma)).exp();
                sum += w * (ahead.min(depth + range) + behind.min(depth + range));
                weights += 2.0 * w;
            }
            out[index] = sum / weights;
        }
    }
    out
}

/// `iterations` horizontal-then-vertical filter passes.
pub fn filtered_depth(u: &GpuSurfaceUniform, depth: &[f32], iterations: u32) -> Vec<f32> {
    let mut depth = depth.to_vec();
    for _ in 0..iterations {
        depth = filter_pass(u, &filter_pass(u, &depth, false), true);
    }
    depth
}

/// The normals pass (`surface_normals.wgsl`): xyz the view-space normal facing the eye, w = 1
/// where there is water.
pub fn normals_pass(u: &GpuSurfaceUniform, depth: &[f32]) -> Vec<Vec4> {
    let s = size(u).as_ivec2();
    let depth_at = |p: IVec2| {
        depth[(p.clamp(IVec2::ZERO, s - 1).y * s.x + p.clamp(IVec2::ZERO, s - 1).x) as usize]
    };
    let position_at =
        |p: IVec2, d: f32| view_position(u, pixel_ndc(p.as_vec2() + 0.5, u.target_size), d);
    let difference = |p: IVec2, here: Vec3, step: IVec2| {
        let (ahead_depth, behind_depth) = (depth_at(p + step), depth_at(p - step));
        let ahead = position_at(p + step, ahead_depth) - here;
        let behind = here - position_at(p - step, behind_depth);
        if ahead_depth <= 0.0 && behind_depth <= 0.0 {
            Vec3::ZERO
        } else if ahead_depth <= 0.0 {
            behind
        } else if behind_depth <= 0.0 || ahead.z.abs() < behind.z.abs() {
            ahead
        } else {
            behind
        }
    };
    let mut out = vec![Vec4::ZERO; depth.len()];
    for y in 0..s.y {
        for x in 0..s.x {
            let pixel = IVec2::new(x, y);
            let d = depth_at(pixel);
            if d <= 0.0 {
                continue;
            }
            let here = position_at(pixel, d);
            let mut normal =
                difference(pixel, here, IVec2::X).cross(difference(pixel, here, IVec2::Y));
            if normal.length_squared() < 1e-20 {
                normal = -here;
            }
            normal = normal.normalize();
            let to_eye = if u.orthographic == 0 { -here } else { Vec3::Z };
            if normal.dot(to_eye) < 0.0 {
                normal = -normal;
            }
            out[(y * s.x + x) as usize] = normal.extend(1.0);
        }
    }
    out
}
