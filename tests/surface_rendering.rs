//! The water surface (`SphSurface`) drawn on lavapipe into an image: it shows water where the
//! particles are, an opaque box in front hides it, every pass's output matches its CPU twin
//! (`bevy_sph_fluid::surface::cpu_twin`), the whitewater's billboards included, and refused
//! settings leave the previous ones drawing.

mod common;

use bevy::camera::{Hdr, RenderTarget, Viewport};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy_sph_fluid::prelude::*;
use bevy_sph_fluid::surface::cpu_twin;
use bevy_sph_fluid::surface::view::GpuSurfaceUniform;
use common::{headless_app, GPU};
use sph_core::{BlockSpawn, BoxContainer, SpacingDerivation};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
const CLEAR: Color = Color::srgb(0.0, 0.0, 0.0);
const EYE: Vec3 = Vec3::new(0.5, 0.8, 1.8);
const LOOK_AT: Vec3 = Vec3::new(0.5, 0.2, 0.5);

#[derive(Resource, Default)]
struct Captured(Option<Image>);

/// Particle spacing of the test scenes [m].
const SPACING: f32 = 0.04;

/// A paused GPU app: a 1 m box holding a block of water from `min` to `max` at [`SPACING`].
fn paused_block(min: Vec3, max: Vec3) -> App {
    let mut app = headless_app(8192, SphBackend::Gpu);
    app.insert_resource(SphParams(sph_core::SphParams::from_spacing(
        SpacingDerivation {
            spacing: SPACING,
            ..Default::default()
        },
    )));
    let world = app.world_mut();
    world.spawn(SphContainer(BoxContainer::from_min_max(
        Vec3::ZERO,
        Vec3::ONE,
    )));
    world.spawn(SphBlockSpawn {
        block: BlockSpawn::new(min, max, SPACING),
        velocity: Vec3::ZERO,
    });
    app
}

/// A paused GPU app: a 1 m box with a block of water 0.7 x 0.4 x 0.7 m (spacing 0.04 m), a
/// camera with `SphSurface` and default MSAA rendering into an image; with `hdr`, an HDR camera
/// (its main texture is `Rgba16Float`) with Bevy's default tonemapping.
fn water_in_view(hdr: bool) -> (App, Handle<Image>) {
    water_in_viewport(hdr, None)
}

/// [`water_in_view`] with the camera drawing into `viewport` of the image only.
fn water_in_viewport(hdr: bool, viewport: Option<Viewport>) -> (App, Handle<Image>) {
    let mut app = paused_block(Vec3::new(0.1, 0.0, 0.1), Vec3::new(0.8, 0.4, 0.8));
    let world = app.world_mut();
    let mut image = Image::new_target_texture(WIDTH, HEIGHT, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = world.resource_mut::<Assets<Image>>().add(image);
    let mut camera = world.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(CLEAR),
            viewport,
            ..default()
        },
        RenderTarget::Image(target.clone().into()),
        Transform::from_translation(EYE).looking_at(LOOK_AT, Vec3::Y),
        SphSurface::default(),
    ));
    if hdr {
        camera.insert(Hdr);
    } else {
        camera.insert(Tonemapping::None);
    }
    world.init_resource::<Captured>();
    for _ in 0..5 {
        app.update();
    }
    (app, target)
}

/// The target's pixels (RGBA8, sRGB) after the next frames.
fn capture(app: &mut App, target: &Handle<Image>) -> Vec<u8> {
    app.world_mut().resource_mut::<Captured>().0 = None;
    app.world_mut()
        .spawn(Screenshot::image(target.clone()))
        .observe(
            |captured: On<ScreenshotCaptured>, mut out: ResMut<Captured>| {
                out.0 = Some(captured.image.clone());
            },
        );
    for _ in 0..100 {
        app.update();
        if let Some(image) = app.world_mut().resource_mut::<Captured>().0.take() {
            return image.data.expect("captured pixels");
        }
    }
    panic!("no screenshot after 100 frames");
}

/// Saves `rgba` as a binary PPM under the temp directory, for a look after a failure.
fn save(rgba: &[u8], name: &str) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("sph_surface_{name}.ppm"));
    let mut bytes = format!("P6 {WIDTH} {HEIGHT} 255\n").into_bytes();
    for px in rgba.chunks_exact(4) {
        bytes.extend_from_slice(&px[..3]);
    }
    std::fs::write(&path, bytes).unwrap();
    path
}

fn pixel(rgba: &[u8], x: u32, y: u32) -> [u8; 3] {
    let i = 4 * (y * WIDTH + x) as usize;
    [rgba[i], rgba[i + 1], rgba[i + 2]]
}

/// Pixels that differ from the clear colour.
fn drawn(rgba: &[u8]) -> Vec<(u32, u32)> {
    (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|&(x, y)| pixel(rgba, x, y).iter().map(|&c| c as u32).sum::<u32>() > 30)
        .collect()
}

/// An unlit `mesh` of `color` at `transform`.
fn spawn_unlit(world: &mut World, mesh: Mesh, color: Color, transform: Transform) {
    let mesh = world.resource_mut::<Assets<Mesh>>().add(mesh);
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: color,
            unlit: true,
            ..default()
        });
    world.spawn((Mesh3d(mesh), MeshMaterial3d(material), transform));
}

/// An unlit red cube, 0.15 m, on the line of sight from [`EYE`] to [`LOOK_AT`], in front of
/// the water.
fn spawn_red_cube(world: &mut World) {
    spawn_unlit(
        world,
        Cuboid::from_length(0.15).into(),
        Color::srgb(1.0, 0.0, 0.0),
        Transform::from_translation(EYE.lerp(LOOK_AT, 0.4)),
    );
}

#[test]
fn the_surface_is_drawn_and_an_opaque_box_in_front_hides_it() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    surface_drawn_and_hidden_by_a_box(false);
}

#[test]
fn a_camera_with_a_viewport_draws_its_water_inside_it_only() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    // The right half of the image; the left half is only cleared (Bevy's clear colour).
    let viewport = Viewport {
        physical_position: UVec2::new(WIDTH / 2, 0),
        physical_size: UVec2::new(WIDTH / 2, HEIGHT),
        ..default()
    };
    let (mut app, target) = water_in_viewport(false, Some(viewport));
    let picture = capture(&mut app, &target);
    let saved = save(&picture, "viewport");
    let background = pixel(&picture, 0, 0);
    let left_drawn = (0..HEIGHT)
        .flat_map(|y| (0..WIDTH / 2).map(move |x| (x, y)))
        .filter(|&(x, y)| pixel(&picture, x, y) != background)
        .count();
    assert_eq!(
        left_drawn,
        0,
        "drawn left of the viewport ({})",
        saved.display()
    );
    let water = drawn(&picture)
        .into_iter()
        .filter(|&(x, _)| x >= WIDTH / 2)
        .count();
    assert!(
        water > (WIDTH * HEIGHT / 20) as usize,
        "{water} water pixels in the viewport ({})",
        saved.display()
    );
}

#[test]
fn the_surface_works_with_hdr_and_tonemapping() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    surface_drawn_and_hidden_by_a_box(true);
}

fn surface_drawn_and_hidden_by_a_box(hdr: bool) {
    let (mut app, target) = water_in_view(hdr);
    let before = capture(&mut app, &target);
    let saved = save(&before, &format!("water_hdr_{hdr}"));
    let water = drawn(&before);
    let (cx, cy) = (WIDTH / 2, HEIGHT / 2);
    assert!(
        water.len() > (WIDTH * HEIGHT / 10) as usize,
        "the water covers {} of {} pixels ({})",
        water.len(),
        WIDTH * HEIGHT,
        saved.display()
    );
    assert!(
        water.contains(&(cx, cy)),
        "water at the centre: {:?}",
        pixel(&before, cx, cy)
    );
    // An unlit red cube on the line of sight to the image centre, in front of the water.
    spawn_red_cube(app.world_mut());
    let after = capture(&mut app, &target);
    let saved = save(&after, &format!("box_hdr_{hdr}"));
    for y in cy - 3..=cy + 3 {
        for x in cx - 3..=cx + 3 {
            let [r, g, b] = pixel(&after, x, y);
            // Unlit red, through Bevy's tonemapping on the HDR camera.
            assert!(
                r > 150 && g < 60 && b < 60,
                "the box hides the water at ({x}, {y}): {:?} (water there: {:?}; {})",
                [r, g, b],
                pixel(&before, x, y),
                saved.display()
            );
        }
    }
    // Away from the box the water is unchanged (the simulation is paused).
    let untouched = water
        .iter()
        .filter(|&&(x, y)| x.abs_diff(cx) > 40 || y.abs_diff(cy) > 40)
        .filter(|&&(x, y)| pixel(&after, x, y) == pixel(&before, x, y))
        .count();
    let away = water
        .iter()
        .filter(|&&(x, y)| x.abs_diff(cx) > 40 || y.abs_diff(cy) > 40)
        .count();
    assert!(
        untouched * 100 >= away * 95,
        "{untouched} of {away} water pixels away from the box unchanged"
    );
}

#[test]
fn refused_surface_settings_are_named_and_the_previous_ones_stay() {
    // Validation runs in the main world: the CPU backend (no GPU) is enough.
    let mut app = headless_app(64, SphBackend::Cpu);
    let good = SphSurface {
        filter_radius: 0.05,
        ..default()
    };
    let camera = app
        .world_mut()
        .spawn((Camera3d::default(), good.clone()))
        .id();
    app.update();
    let status = |app: &App| app.world().get::<SphSurfaceStatus>(camera).unwrap().clone();
    assert_eq!(status(&app).applied, good);
    assert_eq!(status(&app).error, None);
    let bad = [
        (
            SphSurface {
                resolution_scale: 0.0,
                ..good.clone()
            },
            ["resolution_scale", "= 0", "0 < scale <= 1"],
        ),
        (
            SphSurface {
                resolution_scale: 1.5,
                ..good.clone()
            },
            ["resolution_scale", "= 1.5", "0 < scale <= 1"],
        ),
        (
            SphSurface {
                filter_radius: -0.1,
                ..good.clone()
            },
            ["filter_radius", "= -0.1", ">= 0"],
        ),
        (
            SphSurface {
                absorption: Vec3::new(f32::NAN, 1.0, 1.0),
                ..good.clone()
            },
            ["absorption", "NaN", "0 ..= 1000"],
        ),
        (
            SphSurface {
                sky_color: Vec3::new(0.5, f32::NAN, 0.5),
                ..good.clone()
            },
            ["sky_color", "NaN", "0 ..= 100"],
        ),
        (
            SphSurface {
                sphere_scale: 0.1,
                ..good.clone()
            },
            ["sphere_scale", "= 0.1", "0.25 ..= 4"],
        ),
        (
            SphSurface {
                filter_iterations: 17,
                ..good.clone()
            },
            ["filter_iterations", "= 17", "0 ..= 16"],
        ),
        (
            SphSurface {
                sun_direction: Vec3::ZERO,
                ..good.clone()
            },
            ["sun_direction", "Vec3(0.0, 0.0, 0.0)", "normalizes"],
        ),
        (
            SphSurface {
                specular: f32::INFINITY,
                ..good.clone()
            },
            ["specular", "inf", "0 ..= 100"],
        ),
    ];
    for (settings, words) in bad {
        *app.world_mut().get_mut::<SphSurface>(camera).unwrap() = settings;
        app.update();
        let status = status(&app);
        let error = status.error.expect("refused");
        for word in words {
            assert!(error.contains(word), "{error:?} names {word:?}");
        }
        assert_eq!(status.applied, good, "the previous settings stay");
    }
    // A valid edit is applied and clears the error.
    let better = SphSurface {
        filter_iterations: 3,
        ..good
    };
    *app.world_mut().get_mut::<SphSurface>(camera).unwrap() = better.clone();
    app.update();
    assert_eq!(status(&app).applied, better);
    assert_eq!(status(&app).error, None);
}

const TWIN_WIDTH: u32 = 160;
const TWIN_HEIGHT: u32 = 120;

/// Draws `settings` (a debug view, at full resolution) into an `Rgba32Float` image through an
/// HDR camera without tonemapping; returns each pixel's rgb.
fn draw_debug_view(
    app: &mut App,
    camera: Entity,
    target: &Handle<Image>,
    settings: SphSurface,
) -> Vec<Vec3> {
    *app.world_mut().get_mut::<SphSurface>(camera).unwrap() = settings;
    for _ in 0..3 {
        app.update();
    }
    app.world_mut().resource_mut::<Captured>().0 = None;
    app.world_mut()
        .spawn(Screenshot::image(target.clone()))
        .observe(
            |captured: On<ScreenshotCaptured>, mut out: ResMut<Captured>| {
                out.0 = Some(captured.image.clone());
            },
        );
    for _ in 0..100 {
        app.update();
        if let Some(image) = app.world_mut().resource_mut::<Captured>().0.take() {
            let bytes = image.data.expect("captured pixels");
            let floats: Vec<f32> = bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect();
            return floats
                .chunks_exact(4)
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect();
        }
    }
    panic!("no screenshot after 100 frames");
}

/// A `TWIN_WIDTH` × `TWIN_HEIGHT` `Rgba32Float` image and an HDR camera at `pose` drawing into
/// it without tonemapping or MSAA, with `surface`: what the twin tests read their passes from.
fn twin_camera(world: &mut World, pose: Transform, surface: SphSurface) -> (Entity, Handle<Image>) {
    let mut image =
        Image::new_target_texture(TWIN_WIDTH, TWIN_HEIGHT, TextureFormat::Rgba32Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = world.resource_mut::<Assets<Image>>().add(image);
    let camera = world
        .spawn((
            Camera3d::default(),
            Camera {
                clear_color: ClearColorConfig::Custom(CLEAR),
                ..default()
            },
            RenderTarget::Image(target.clone().into()),
            Hdr,
            Tonemapping::None,
            Msaa::Off,
            pose,
            surface,
        ))
        .id();
    (camera, target)
}

/// The share of `pairs` within `tolerance` of each other, and the largest difference.
fn agreement(pairs: &[(f32, f32)], tolerance: impl Fn(f32) -> f32) -> (f64, f32) {
    let within = pairs
        .iter()
        .filter(|(g, c)| (g - c).abs() <= tolerance(*c))
        .count();
    let worst = pairs.iter().map(|(g, c)| (g - c).abs()).fold(0.0, f32::max);
    (within as f64 / pairs.len().max(1) as f64, worst)
}

#[test]
fn every_surface_pass_matches_its_cpu_twin() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut app = paused_block(Vec3::new(0.4, 0.0, 0.4), Vec3::new(0.6, 0.16, 0.6));
    let spacing = SPACING;
    let (camera, target) = twin_camera(
        app.world_mut(),
        Transform::from_xyz(0.62, 0.42, 0.98).looking_at(Vec3::new(0.5, 0.08, 0.5), Vec3::Y),
        SphSurface::default(),
    );
    let world = app.world_mut();
    world.init_resource::<Captured>();
    for _ in 0..5 {
        app.update();
    }
    let twin = |iterations: u32, debug_view: SphSurfaceDebugView| SphSurface {
        resolution_scale: 1.0,
        filter_iterations: iterations,
        debug_view,
        ..default()
    };
    let depth_raw = draw_debug_view(
        &mut app,
        camera,
        &target,
        twin(0, SphSurfaceDebugView::Depth),
    );
    let depth_smooth = draw_debug_view(
        &mut app,
        camera,
        &target,
        twin(2, SphSurfaceDebugView::Depth),
    );
    let thickness = draw_debug_view(
        &mut app,
        camera,
        &target,
        twin(0, SphSurfaceDebugView::Thickness),
    );
    let normals = draw_debug_view(
        &mut app,
        camera,
        &target,
        twin(2, SphSurfaceDebugView::Normals),
    );

    // The CPU twins on the same particles, seen by the same camera.
    let positions = common::snapshot(&mut app).positions;
    let world = app.world();
    let clip_from_view = world.get::<Camera>(camera).unwrap().clip_from_view();
    let world_from_view = world.get::<GlobalTransform>(camera).unwrap().to_matrix();
    let block = |settings: &SphSurface| {
        GpuSurfaceUniform::new(
            settings,
            clip_from_view,
            world_from_view,
            UVec2::new(TWIN_WIDTH, TWIN_HEIGHT),
            positions.len() as u32,
            spacing,
        )
    };
    let raw_block = block(&twin(0, SphSurfaceDebugView::Depth));
    let smooth_block = block(&twin(2, SphSurfaceDebugView::Depth));
    let cpu_raw = cpu_twin::depth_pass(&raw_block, &positions);
    let cpu_smooth = cpu_twin::filtered_depth(&smooth_block, &cpu_raw, 2);
    let cpu_thickness = cpu_twin::thickness_pass(&raw_block, &positions);
    let cpu_normals = cpu_twin::normals_pass(&smooth_block, &cpu_smooth);

    let water = cpu_raw.iter().filter(|&&d| d > 0.0).count();
    assert!(water > 2_000, "the block covers {water} pixels");
    let mask_differences = cpu_raw
        .iter()
        .zip(&depth_raw)
        .filter(|(c, g)| (**c > 0.0) != (g.x > 0.0))
        .count();
    // The GPU's image is f16 (the HDR view target): 1e-3 m at these distances.
    let pairs = |gpu: &[Vec3], cpu: &[f32]| -> Vec<(f32, f32)> {
        gpu.iter()
            .zip(cpu)
            .filter(|(g, c)| g.x > 0.0 && **c > 0.0)
            .map(|(g, c)| (g.x, *c))
            .collect()
    };
    let (raw_share, raw_worst) = agreement(&pairs(&depth_raw, &cpu_raw), |_| 1.5e-3);
    let (smooth_share, smooth_worst) = agreement(&pairs(&depth_smooth, &cpu_smooth), |_| 1.5e-3);
    let (thickness_share, thickness_worst) =
        agreement(&pairs(&thickness, &cpu_thickness), |c| 1e-3 + 0.01 * c);
    let normal_pairs: Vec<f32> = normals
        .iter()
        .zip(&cpu_normals)
        .filter(|(g, c)| c.w > 0.5 && g.length_squared() > 0.0)
        .map(|(g, c)| (2.0 * *g - Vec3::ONE).normalize_or_zero().dot(c.truncate()))
        .collect();
    let normals_within = normal_pairs.iter().filter(|&&d| d >= 0.99).count() as f64
        / normal_pairs.len().max(1) as f64;
    println!(
        "{water} water pixels, {mask_differences} differ in coverage; depth: {:.2} % within \
         1.5 mm (worst {raw_worst:.2e} m); filtered depth: {:.2} % (worst {smooth_worst:.2e} m); \
         thickness: {:.2} % within 1 mm + 1 % (worst {thickness_worst:.2e} m); normals: {:.2} % \
         within 8° ({} pixels)",
        100.0 * raw_share,
        100.0 * smooth_share,
        100.0 * thickness_share,
        100.0 * normals_within,
        normal_pairs.len()
    );
    assert!(
        mask_differences * 100 <= water,
        "{mask_differences} of {water} pixels differ in coverage"
    );
    assert!(raw_share >= 0.99, "depth: {raw_share}");
    assert!(smooth_share >= 0.99, "filtered depth: {smooth_share}");
    assert!(thickness_share >= 0.99, "thickness: {thickness_share}");
    assert!(normals_within >= 0.98, "normals: {normals_within}");
}

/// The whitewater pass against its CPU twin: a CPU app throws a block at a wall with whitewater
/// on, pauses, and draws the class view (`SphSurfaceDebugView::Whitewater`, 1 - e^(-1.5 w) per
/// class, at full resolution); the twin draws `SphDiffuseParticles` seen by the same camera.
#[test]
fn the_whitewater_pass_matches_its_cpu_twin() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    common::require_gpu_adapter();
    let mut app = bevy_sph_fluid::headless::headless_app_that_draws(
        DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>(),
        4_000,
        SphBackend::Cpu,
    );
    app.insert_resource(SphWhitewater::default());
    let world = app.world_mut();
    let extent = Vec3::new(0.4, 0.3, 0.2);
    world.spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, extent)));
    world.spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::ZERO, Vec3::new(0.1, 0.1, 0.2), 0.02),
        velocity: Vec3::new(3.0, 0.0, 0.0),
    });
    app.update();
    common::step_to(&mut app, 120);
    let settings = SphSurface {
        resolution_scale: 1.0,
        debug_view: SphSurfaceDebugView::Whitewater,
        ..default()
    };
    let (camera, target) = twin_camera(
        app.world_mut(),
        Transform::from_xyz(0.25, 0.35, 0.75).looking_at(Vec3::new(0.28, 0.08, 0.1), Vec3::Y),
        settings.clone(),
    );
    let world = app.world_mut();
    world.init_resource::<Captured>();
    let gpu = draw_debug_view(&mut app, camera, &target, settings.clone());

    let world = app.world();
    let diffuse = world.resource::<SphDiffuseParticles>();
    let particles: Vec<(Vec3, u32)> = diffuse
        .position
        .iter()
        .zip(&diffuse.kind)
        .map(|(&p, &kind)| (p, bevy_sph_fluid::whitewater::diffuse_class_w(kind) as u32))
        .collect();
    assert!(
        particles.len() >= 20,
        "{} diffuse particles",
        particles.len()
    );
    let mut block = GpuSurfaceUniform::new(
        &settings,
        world.get::<Camera>(camera).unwrap().clip_from_view(),
        world.get::<GlobalTransform>(camera).unwrap().to_matrix(),
        UVec2::new(TWIN_WIDTH, TWIN_HEIGHT),
        0,
        world.resource::<SphParams>().0.spacing(),
    );
    block.diffuse_count = particles.len() as u32;
    let cpu: Vec<Vec3> = cpu_twin::whitewater_pass(&block, &particles)
        .iter()
        .map(|w| Vec3::ONE - (-1.5 * w.truncate()).exp())
        .collect();
    // Every channel of every pixel that either side colours; the target is f16.
    let pairs: Vec<(f32, f32)> = gpu
        .iter()
        .zip(&cpu)
        .flat_map(|(g, c)| (0..3).map(move |k| (g[k], c[k])))
        .filter(|(g, c)| *g > 0.0 || *c > 0.0)
        .collect();
    let coloured = cpu.iter().filter(|c| c.max_element() > 0.0).count();
    let (share, worst) = agreement(&pairs, |_| 0.01);
    println!(
        "{} diffuse particles, {coloured} pixels coloured; {:.2} % of the channels within 0.01 \
         (worst {worst:.3})",
        particles.len(),
        100.0 * share
    );
    assert!(
        coloured >= 50,
        "the diffuse particles cover {coloured} pixels"
    );
    assert!(share >= 0.98, "{share}");
}

/// Near-white pixels of `rgba`: the sun's highlight (the water's own colour is blue, and its
/// Fresnel reflection of the sky at normal incidence is 2 %).
fn highlighted(rgba: &[u8]) -> usize {
    (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|&(x, y)| pixel(rgba, x, y).iter().all(|&c| c >= 230))
        .count()
}

/// The highlight pixels of a paused block of water whose front face lies at `front` [m] in the
/// 1 m box, seen face on from in front of the box's front wall (z = 1) with the sun behind the
/// eye, so the face's normal is the half-way vector: a free face catches the sun over its whole
/// area.
fn front_face_highlight(front: f32) -> usize {
    let mut app = paused_block(Vec3::new(0.2, 0.0, 0.2), Vec3::new(0.8, 0.4, front));
    let world = app.world_mut();
    let mut image = Image::new_target_texture(WIDTH, HEIGHT, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = world.resource_mut::<Assets<Image>>().add(image);
    world.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(CLEAR),
            ..default()
        },
        RenderTarget::Image(target.clone().into()),
        Tonemapping::None,
        Transform::from_xyz(0.5, 0.2, 2.2).looking_at(Vec3::new(0.5, 0.2, 0.5), Vec3::Y),
        SphSurface {
            sun_direction: Vec3::Z,
            ..default()
        },
    ));
    world.init_resource::<Captured>();
    for _ in 0..5 {
        app.update();
    }
    let rgba = capture(&mut app, &target);
    let saved = save(&rgba, &format!("front_face_{front}"));
    let water = drawn(&rgba).len();
    assert!(
        water > (WIDTH * HEIGHT / 20) as usize,
        "the front face covers {water} pixels ({})",
        saved.display()
    );
    highlighted(&rgba)
}

/// The water's face against a container wall, seen through the wall, meets no air and catches
/// no sun: the default dam break's front face drew a bright dashed line along its particle layer.
/// The same face in open air, in the same light, does catch it.
#[test]
fn the_waters_face_against_a_container_wall_catches_no_sun() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let open_air = front_face_highlight(0.8);
    let against_the_wall = front_face_highlight(1.0);
    assert!(
        open_air > 500,
        "a free face toward the sun shows a highlight: {open_air} pixels"
    );
    assert!(
        against_the_wall * 50 < open_air,
        "the face against the wall shows {against_the_wall} highlight pixels, the free face \
         {open_air}"
    );
}

/// Whether the pixel shows the unlit red cube, directly or refracted (through the water's
/// blue-green tint it comes out dark red, about (110, 60, 60); the water alone has r < g).
fn red(rgba: &[u8], x: u32, y: u32) -> bool {
    let [r, g, b] = pixel(rgba, x, y).map(|c| c as u32);
    r >= g + 30 && r >= b + 30
}

/// Refraction bends the light from behind the water only: where the moved sample lands on
/// geometry in front of the water (a red cube), the water draws the scene straight behind it, so
/// no red shows outside the cube's own outline however strong the refraction. Thick water beside
/// the island drew the island's wall into the channel in vertical bands.
#[test]
fn refraction_does_not_draw_geometry_in_front_of_the_water() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (mut app, target) = water_in_view(false);
    spawn_red_cube(app.world_mut());
    let set_refraction = |app: &mut App, strength: f32| {
        let world = app.world_mut();
        let mut cameras = world.query::<&mut SphSurface>();
        for mut surface in cameras.iter_mut(world) {
            surface.refraction_strength = strength;
        }
    };
    set_refraction(&mut app, 0.0);
    let straight = capture(&mut app, &target);
    set_refraction(&mut app, 1.0);
    let bent = capture(&mut app, &target);
    let saved = save(&bent, "refraction_beside_a_cube");
    // The cube's outline, one pixel wider.
    let near_the_cube = |x: u32, y: u32| {
        (x.saturating_sub(1)..=(x + 1).min(WIDTH - 1))
            .any(|u| (y.saturating_sub(1)..=(y + 1).min(HEIGHT - 1)).any(|v| red(&straight, u, v)))
    };
    let cube = drawn(&straight)
        .iter()
        .filter(|&&(x, y)| red(&straight, x, y))
        .count();
    let leaks: Vec<_> = drawn(&bent)
        .into_iter()
        .filter(|&(x, y)| red(&bent, x, y) && !near_the_cube(x, y))
        .collect();
    assert!(cube > 200, "the cube covers {cube} pixels");
    assert!(
        leaks.len() * 100 < cube,
        "{} water pixels outside the cube's outline show it (first {:?}; the cube covers {cube}; \
         {})",
        leaks.len(),
        leaks.first(),
        saved.display()
    );
}

/// The share of the view's pixels in which a bright green floor shows, directly or refracted
/// through the water, for the camera of [`water_in_viewport`] drawing into `viewport`.
fn green_share(viewport: Option<Viewport>) -> f64 {
    let (mut app, target) = water_in_viewport(false, viewport.clone());
    spawn_unlit(
        app.world_mut(),
        Plane3d::default().mesh().size(1.0, 1.0).into(),
        Color::srgb(0.0, 1.0, 0.0),
        Transform::from_xyz(0.5, -0.002, 0.5),
    );
    let picture = capture(&mut app, &target);
    let saved = save(&picture, &format!("green_floor_{}", viewport.is_some()));
    let (origin, size) = viewport.map_or((UVec2::ZERO, UVec2::new(WIDTH, HEIGHT)), |v| {
        (v.physical_position, v.physical_size)
    });
    let green = (origin.y..origin.y + size.y)
        .flat_map(|y| (origin.x..origin.x + size.x).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b] = pixel(&picture, x, y).map(|c| c as u32);
            g >= r + 40 && g >= b + 20
        })
        .count();
    let share = green as f64 / (size.x * size.y) as f64;
    eprintln!("green share {share:.3} ({})", saved.display());
    share
}

/// Refraction reads the scene behind from the camera's own viewport: a quarter-size viewport of
/// the same aspect sees the green floor through the water in the same share of its pixels as the
/// whole image does (it read the whole target as if it were the viewport).
#[test]
fn refraction_in_a_viewport_reads_the_viewports_own_pixels() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let whole = green_share(None);
    let quarter = green_share(Some(Viewport {
        physical_position: UVec2::new(WIDTH / 2, HEIGHT / 2),
        physical_size: UVec2::new(WIDTH / 2, HEIGHT / 2),
        ..default()
    }));
    assert!(whole > 0.1, "the floor shows in {whole:.3} of the image");
    assert!(
        (quarter - whole).abs() < 0.1 * whole,
        "the floor shows in {quarter:.3} of the viewport against {whole:.3} of the whole image"
    );
}
