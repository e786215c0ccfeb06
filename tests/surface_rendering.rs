//! The water surface (`SphSurface`) drawn on lavapipe into an image: it shows water where the
//! particles are, an opaque box in front hides it, and refused settings leave the previous ones
//! drawing.

mod common;

use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy_sph_fluid::prelude::*;
use common::{headless_app, GPU};
use sph_core::{BlockSpawn, BoxContainer, SpacingDerivation};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
const CLEAR: Color = Color::srgb(0.0, 0.0, 0.0);
const EYE: Vec3 = Vec3::new(0.5, 0.8, 1.8);
const LOOK_AT: Vec3 = Vec3::new(0.5, 0.2, 0.5);

#[derive(Resource, Default)]
struct Captured(Option<Image>);

/// A paused GPU app: a 1 m box with a block of water 0.8 x 0.4 x 0.8 m (spacing 0.04 m), a
/// camera with `SphSurface` and default MSAA rendering into an image; with `hdr`, an HDR camera
/// (its main texture is `Rgba16Float`) with Bevy's default tonemapping.
fn water_in_view(hdr: bool) -> (App, Handle<Image>) {
    let mut app = headless_app(8192, SphBackend::Gpu);
    let spacing = 0.04;
    app.insert_resource(SphParams(sph_core::SphParams::from_spacing(
        SpacingDerivation {
            spacing,
            ..Default::default()
        },
    )));
    let world = app.world_mut();
    world.spawn(SphContainer(BoxContainer::from_min_max(
        Vec3::ZERO,
        Vec3::ONE,
    )));
    world.spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::new(0.1, 0.0, 0.1), Vec3::new(0.8, 0.4, 0.8), spacing),
        velocity: Vec3::ZERO,
    });
    let mut image = Image::new_target_texture(WIDTH, HEIGHT, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = world.resource_mut::<Assets<Image>>().add(image);
    let mut camera = world.spawn((
        Camera3d::default(),
        Camera {
            clear_color: ClearColorConfig::Custom(CLEAR),
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

#[test]
fn the_surface_is_drawn_and_an_opaque_box_in_front_hides_it() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    surface_drawn_and_hidden_by_a_box(false);
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
    let world = app.world_mut();
    let mesh = world
        .resource_mut::<Assets<Mesh>>()
        .add(Cuboid::from_length(0.15));
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::srgb(1.0, 0.0, 0.0),
            unlit: true,
            ..default()
        });
    world.spawn((
        Mesh3d(mesh),
        MeshMaterial3d(material),
        Transform::from_translation(EYE.lerp(LOOK_AT, 0.4)),
    ));
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
