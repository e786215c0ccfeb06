//! Particles drawn straight from the simulation's GPU buffers: one mesh of camera-facing quads,
//! one per particle slot, whose vertex shader reads `positions[slot]`. No CPU copy per frame.
//! The whitewater's diffuse particles, while it is on, are a second such mesh over their buffer.

use crate::{AppState, SandboxSet};
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::reflect::TypePath;
use bevy::render::render_resource::{AsBindGroup, ShaderType};
use bevy::render::storage::ShaderBuffer;
use bevy::shader::ShaderRef;
use bevy_sph_fluid::prelude::*;

const SHADER: &str = "shaders/sandbox_particles.wgsl";

/// How particles are coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorMode {
    /// Pale to strong blue with density (the design's colouring).
    #[default]
    Density,
    /// Speed.
    Speed,
    /// Pressure (Tait ratio).
    Pressure,
    /// Neighbours within h (debug view; the density pass records them while shown).
    Neighbors,
}

/// The shader's colour mode of the whitewater's diffuse particles: by class, from w.
const DIFFUSE_COLOR_MODE: u32 = 4;
/// A diffuse particle's drawn radius per particle spacing (the water's is 0.6).
const DIFFUSE_RADIUS_SCALE: f32 = 0.3;

/// The draw settings the shader reads.
#[derive(Clone, Copy, Debug, Default, ShaderType)]
pub struct ParticleDraw {
    count: u32,
    color_mode: u32,
    radius: f32,
    rest_density: f32,
    max_speed: f32,
    pad_a: f32,
    pad_b: f32,
    pad_c: f32,
}

/// Binds the simulation's position, velocity and density buffers for drawing.
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
pub struct ParticleMaterial {
    #[storage(0, read_only)]
    positions: Handle<ShaderBuffer>,
    #[storage(1, read_only)]
    velocities: Handle<ShaderBuffer>,
    #[storage(2, read_only)]
    densities: Handle<ShaderBuffer>,
    #[uniform(3)]
    draw: ParticleDraw,
    #[storage(4, read_only)]
    neighbor_counts: Handle<ShaderBuffer>,
}

impl Material for ParticleMaterial {
    fn vertex_shader() -> ShaderRef {
        SHADER.into()
    }

    fn fragment_shader() -> ShaderRef {
        SHADER.into()
    }

    // The prepass and shadow shaders would not read the particle buffer.
    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
    }
}

/// The particle-drawing entity and its material.
#[derive(Resource)]
pub struct ParticleDrawing {
    material: Handle<ParticleMaterial>,
    /// Colour mode chosen in the panel.
    pub color_mode: ColorMode,
}

/// One quad per slot: corners in ATTRIBUTE_POSITION, the slot index in ATTRIBUTE_UV_0.x.
fn quads(slots: u32) -> Mesh {
    let corners = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    let mut positions = Vec::with_capacity(4 * slots as usize);
    let mut slot_of = Vec::with_capacity(4 * slots as usize);
    let mut indices = Vec::with_capacity(6 * slots as usize);
    for slot in 0..slots {
        positions.extend(corners);
        slot_of.extend([[slot as f32, 0.0]; 4]);
        let base = 4 * slot;
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, slot_of)
    .with_inserted_indices(Indices::U32(indices))
}

/// Spawns the particle mesh for the plugin's current buffers (tagged for despawn with `tag`).
pub fn spawn_particles(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<ParticleMaterial>,
    buffers: &SphGpuBuffers,
    capacity: u32,
    radius: f32,
    tag: impl Bundle,
) {
    let material = materials.add(ParticleMaterial {
        positions: buffers.position.clone(),
        velocities: buffers.velocity.clone(),
        densities: buffers.density.clone(),
        neighbor_counts: buffers.neighbor_count.clone(),
        draw: ParticleDraw {
            radius,
            rest_density: 1.0,
            max_speed: 3.0,
            ..default()
        },
    });
    commands.spawn((
        Mesh3d(meshes.add(quads(capacity))),
        MeshMaterial3d(material.clone()),
        Transform::IDENTITY,
        NoFrustumCulling,
        tag,
    ));
    commands.insert_resource(ParticleDrawing {
        material,
        color_mode: ColorMode::Density,
    });
}

/// Keeps the draw uniform in step with the simulation (count, rest density, colour mode), and
/// has the density pass record neighbour counts only while they are shown.
pub fn update_particle_draw(
    drawing: Option<Res<ParticleDrawing>>,
    stats: Res<SphStats>,
    params: Res<SphParams>,
    mut control: ResMut<SphControl>,
    mut materials: ResMut<Assets<ParticleMaterial>>,
) {
    let Some(drawing) = drawing else {
        return;
    };
    let record = drawing.color_mode == ColorMode::Neighbors;
    if control.record_neighbor_counts != record {
        control.record_neighbor_counts = record;
    }
    let color_mode = match drawing.color_mode {
        ColorMode::Density => 0,
        ColorMode::Speed => 1,
        ColorMode::Pressure => 2,
        ColorMode::Neighbors => 3,
    };
    let wanted = (stats.particle_count, color_mode, params.rest_density);
    let Some(material) = materials.get(&drawing.material) else {
        return;
    };
    let d = material.draw;
    if (d.count, d.color_mode, d.rest_density) == wanted {
        return;
    }
    if let Some(mut material) = materials.get_mut(&drawing.material) {
        material.draw.count = wanted.0;
        material.draw.color_mode = wanted.1;
        material.draw.rest_density = wanted.2;
    }
}

/// The whitewater's mesh and the diffuse buffer it draws.
#[derive(Component)]
pub struct DiffuseMesh {
    buffer: Handle<ShaderBuffer>,
    material: Handle<ParticleMaterial>,
}

/// What the whitewater's mesh is drawn from: the diffuse particles, the pool's settings (its
/// capacity) and the water's spacing.
#[derive(bevy::ecs::system::SystemParam)]
pub struct DiffuseSource<'w> {
    diffuse: Res<'w, SphDiffuseParticles>,
    whitewater: Option<Res<'w, SphWhitewater>>,
    params: Res<'w, SphParams>,
}

/// Draws the whitewater's diffuse particles in the particle view: a mesh of one quad per pool
/// slot over `SphDiffuseParticles::buffer`, coloured by class, its count kept to the live
/// particles; rebuilt when the buffer changes, gone when whitewater is off.
pub fn sync_diffuse_mesh(
    mut commands: Commands,
    source: DiffuseSource,
    view: Res<crate::surface::RenderView>,
    mut existing: Query<(Entity, &DiffuseMesh, &mut Visibility)>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<ParticleMaterial>>,
) {
    let DiffuseSource {
        diffuse,
        whitewater,
        params,
    } = source;
    let wanted = diffuse.buffer.as_ref().zip(whitewater);
    let mut current = None;
    for (entity, mesh, visibility) in &mut existing {
        if wanted
            .as_ref()
            .is_some_and(|(buffer, _)| **buffer == mesh.buffer)
        {
            current = Some((mesh.material.clone(), visibility));
        } else {
            commands.entity(entity).despawn();
        }
    }
    let Some((buffer, whitewater)) = wanted else {
        return;
    };
    let shown = view.mode == crate::surface::RenderMode::Particles && !view.hide_water;
    let count = diffuse.slots;
    let Some((material, mut visibility)) = current else {
        let material = materials.add(ParticleMaterial {
            positions: buffer.clone(),
            velocities: buffer.clone(),
            densities: buffer.clone(),
            neighbor_counts: buffer.clone(),
            draw: ParticleDraw {
                count,
                color_mode: DIFFUSE_COLOR_MODE,
                radius: DIFFUSE_RADIUS_SCALE * params.spacing(),
                rest_density: 1.0,
                max_speed: 1.0,
                ..default()
            },
        });
        commands.spawn((
            Mesh3d(meshes.add(quads(whitewater.capacity))),
            MeshMaterial3d(material.clone()),
            Transform::IDENTITY,
            NoFrustumCulling,
            if shown {
                Visibility::Inherited
            } else {
                Visibility::Hidden
            },
            crate::scene::SceneEntity,
            DiffuseMesh {
                buffer: buffer.clone(),
                material,
            },
        ));
        return;
    };
    let wanted_visibility = if shown {
        Visibility::Inherited
    } else {
        Visibility::Hidden
    };
    if *visibility != wanted_visibility {
        *visibility = wanted_visibility;
    }
    if materials
        .get(&material)
        .is_some_and(|m| m.draw.count != count)
    {
        if let Some(mut m) = materials.get_mut(&material) {
            m.draw.count = count;
        }
    }
}

/// The particles drawn as sphere impostors.
pub struct ParticlesPlugin;

impl Plugin for ParticlesPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(MaterialPlugin::<ParticleMaterial>::default())
            .add_systems(
                Update,
                (update_particle_draw, sync_diffuse_mesh)
                    .in_set(SandboxSet::Draw)
                    .run_if(in_state(AppState::Running)),
            );
    }
}
