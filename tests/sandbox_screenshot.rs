//! Runs the sandbox under Xvfb on the software Vulkan driver, lets it render, saves a screenshot
//! and looks at it: blue particle pixels inside the box, the obstacles (`--obstacles`: a ball and
//! a box in orange, and the gate) and the runtime panel present; every shipped scene file drawn
//! (the sandbox runs each on the GPU, drains included); the water surface
//! (`--render surface`) smoother than the particles and covering at least as much, on both
//! backends; a close view of the water's edge against aquaplay.ron's island without strands. The
//! `minimal` example's surface in its lit scene.

use std::path::PathBuf;
use std::process::Command;

fn example_binary(name: &str) -> PathBuf {
    // target/<profile>/deps/<this test> -> target/<profile>/examples/<name>
    let exe = std::env::current_exe().expect("test executable path");
    let profile_dir = exe.parent().and_then(|d| d.parent()).expect("target dir");
    profile_dir.join("examples").join(name)
}

fn decode(path: &PathBuf) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).expect("screenshot written");
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    let channels = info.color_type.samples();
    let rgb: Vec<u8> = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, rgb)
}

/// One sandbox at a time: on 2 cores, concurrent software renderers can spend a screenshot's
/// frames compiling pipelines and draw nothing.
static SANDBOX: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs the sandbox under Xvfb with `args` and `--screenshot`; returns the decoded picture.
fn screenshot(args: &[&str]) -> (u32, u32, Vec<u8>) {
    example_screenshot("sandbox", args)
}

/// Runs example `name` under Xvfb with `args` and `--screenshot`; returns the decoded picture.
fn example_screenshot(name: &str, args: &[&str]) -> (u32, u32, Vec<u8>) {
    let _one_at_a_time = SANDBOX.lock().unwrap_or_else(|e| e.into_inner());
    let binary = example_binary(name);
    assert!(
        binary.exists(),
        "{} missing: build it with `cargo build --release --example {name}`",
        binary.display()
    );
    let xvfb = Command::new("xvfb-run").arg("--help").output();
    assert!(
        xvfb.is_ok(),
        "xvfb-run not found: install it with `sudo apt-get install xvfb xauth` (scripts/test.sh does this)"
    );
    let shot = std::env::temp_dir().join(format!(
        "{name}-{}-{}.png",
        std::process::id(),
        // One file name per argument list (a path's separators become underscores).
        args.join("").replace('-', "").replace(['/', '.'], "_")
    ));
    let _ = std::fs::remove_file(&shot);
    let output = Command::new("timeout")
        .args(["600", "xvfb-run", "-a", "-s", "-screen 0 1280x720x24"])
        .arg(&binary)
        .args(args)
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .expect("run the sandbox");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "{name} failed ({}):\n{}",
        output.status,
        log.lines().rev().take(30).collect::<Vec<_>>().join("\n")
    );
    let picture = decode(&shot);
    let _ = std::fs::remove_file(&shot);
    picture
}

/// Clearly blue pixels (blue well above red) in the box's part of the view.
fn blue_pixels(w: u32, rgb: &[u8]) -> usize {
    let mut blue = 0;
    for y in 100..620 {
        for x in 330..1000 {
            let i = 3 * (y * w + x) as usize;
            let (r, b) = (rgb[i] as i32, rgb[i + 2] as i32);
            if b >= 100 && b - r >= 40 {
                blue += 1;
            }
        }
    }
    blue
}

#[test]
fn minimal_example_draws_the_water_surface_in_a_lit_scene() {
    let (w, h, rgb) = example_screenshot("minimal", &[]);
    assert_eq!((w, h), (1280, 720));
    // The surface's deep colour and refraction tint the water blue-green; nothing else in the
    // scene (stone walls and floor, a grey sky) is blue.
    let (mut water, mut stone) = (0, 0);
    for p in rgb.chunks(3) {
        let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
        if b >= 100 && b - r >= 40 {
            water += 1;
        } else if r >= 140 && (r - b).abs() <= 30 && (r - g).abs() <= 20 {
            stone += 1;
        }
    }
    let total = (w * h) as usize;
    println!("minimal: {water} water pixels, {stone} lit stone pixels of {total}");
    assert!(water >= total / 100, "only {water} water pixels of {total}");
    assert!(
        stone >= total / 4,
        "only {stone} lit floor and wall pixels of {total}: the scene is not lit"
    );
}

#[test]
fn dfsph_water_is_drawn_on_both_backends() {
    // The GPU backend draws its own buffers; with `--cpu` the plugin copies the CPU solver's
    // particles into them.
    for backend in [None, Some("--cpu")] {
        let mut args = vec![
            "--particles",
            "4096",
            "--frames",
            "20",
            "--solver",
            "dfsph",
            "--render",
            "particles",
        ];
        args.extend(backend);
        let (w, _, rgb) = screenshot(&args);
        let blue = blue_pixels(w, &rgb);
        assert!(
            blue >= 3_000,
            "{backend:?}: only {blue} blue particle pixels in the box"
        );
    }
}

#[test]
fn every_shipped_scene_file_renders() {
    for file in [
        "assets/scenes/dam_break.ron",
        "assets/scenes/pipe_fill.ron",
        "assets/scenes/gate.ron",
        "assets/scenes/lock.ron",
        "assets/scenes/aquaplay.ron",
        "assets/scenes/ramp.ron",
        "assets/scenes/basin_jet.ron",
    ] {
        let path = format!("{}/{file}", env!("CARGO_MANIFEST_DIR"));
        // The pipe starts empty and its water arrives with the steps taken, and the first
        // frames take none until the scene is loaded and the shaders compiled, later on a
        // loaded machine: 40 frames showed 3,158 blue pixels alone and 1,830 in one CI run.
        let frames = if file.ends_with("pipe_fill.ron") {
            "80"
        } else {
            "40"
        };
        let (w, _, rgb) = screenshot(&[
            "--scene",
            &path,
            "--frames",
            frames,
            "--render",
            "particles",
        ]);
        let blue = blue_pixels(w, &rgb);
        println!("{file}: {blue} blue particle pixels");
        assert!(
            blue >= 2_000,
            "{file}: only {blue} blue particle pixels in the box"
        );
    }
}

#[test]
fn sandbox_screenshot_shows_water_in_the_box_and_the_panel() {
    let (w, h, rgb) = screenshot(&[
        "--particles",
        "8192",
        "--frames",
        "30",
        "--obstacles",
        "--render",
        "particles",
    ]);
    assert_eq!((w, h), (1280, 720));
    let pixel = |x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        (rgb[i] as i32, rgb[i + 1] as i32, rgb[i + 2] as i32)
    };
    let blue = blue_pixels(w, &rgb);
    assert!(blue >= 5_000, "only {blue} blue particle pixels in the box");
    // The obstacles (`--obstacles`): the ball and the box in flat orange, seen through the glass
    // wall as salmon, about (190, 133, 118).
    let mut orange = 0;
    for y in 100..620 {
        for x in 330..1000 {
            let (r, g, b) = pixel(x, y);
            if r >= 160 && r - b >= 50 && r - g >= 35 {
                orange += 1;
            }
        }
    }
    assert!(
        orange >= 300,
        "only {orange} orange obstacle pixels in the box"
    );
    // The runtime panel: egui's dark window fill over the top-left corner.
    let mut dark = 0;
    let mut total = 0;
    for y in 40..500 {
        for x in 12..300 {
            let (r, g, b) = pixel(x, y);
            total += 1;
            if r < 36 && g < 36 && b < 36 {
                dark += 1;
            }
        }
    }
    assert!(
        dark * 2 > total,
        "panel not found: {dark} of {total} dark pixels"
    );
    // The background outside the box and the panel is not dark panel colour.
    let (r, g, b) = pixel(1200, 680);
    assert!(
        r >= 36 || g >= 36 || b >= 36,
        "background looks like the panel"
    );
}

/// The pixels right of the runtime panel where `picture` differs from `empty` (the same view
/// without water) by more than 10 in the sum of the channels: the water, faint or not (the
/// same scene renders identically, so any change is the water's).
fn water_mask(w: u32, h: u32, empty: &[u8], picture: &[u8]) -> Vec<bool> {
    (0..w * h)
        .map(|p| {
            let (x, i) = (p % w, 3 * p as usize);
            let difference: i32 = (0..3)
                .map(|c| (picture[i + c] as i32 - empty[i + c] as i32).abs())
                .sum();
            x >= WATER_VIEW_LEFT && difference > 10
        })
        .collect()
}

/// Left edge of the part of the window the water tests look at (the panel is left of it).
const WATER_VIEW_LEFT: u32 = 390;

/// Mean absolute Laplacian of luminance over the water pixels whose four neighbours are water
/// too (silhouettes excluded), and the number of such pixels.
fn mean_laplacian(w: u32, h: u32, rgb: &[u8], water: &[bool]) -> (f64, usize) {
    let luminance = |x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        0.299 * rgb[i] as f64 + 0.587 * rgb[i + 1] as f64 + 0.114 * rgb[i + 2] as f64
    };
    let (mut sum, mut count) = (0.0, 0);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let at = |x: u32, y: u32| water[(y * w + x) as usize];
            if at(x, y) && at(x - 1, y) && at(x + 1, y) && at(x, y - 1) && at(x, y + 1) {
                let laplacian = 4.0 * luminance(x, y)
                    - luminance(x - 1, y)
                    - luminance(x + 1, y)
                    - luminance(x, y - 1)
                    - luminance(x, y + 1);
                sum += laplacian.abs();
                count += 1;
            }
        }
    }
    (sum / count.max(1) as f64, count)
}

#[test]
fn the_surface_is_smoother_than_the_particles_and_covers_as_much_on_both_backends() {
    // Paused: the three pictures show the same water (the block before it falls).
    let base = ["--particles", "8192", "--frames", "30", "--paused"];
    let run = |more: &[&str]| {
        let mut args = base.to_vec();
        args.extend(more);
        screenshot(&args)
    };
    // The same view without water: what is not in it is water.
    let (w, h, empty) = run(&["--hide-particles"]);
    let (_, _, particles) = run(&["--render", "particles"]);
    let (_, _, surface) = run(&["--render", "surface"]);
    let particle_water = water_mask(w, h, &empty, &particles);
    let surface_water = water_mask(w, h, &empty, &surface);
    let covered = |mask: &[bool]| mask.iter().filter(|&&m| m).count();
    let (particle_roughness, particle_inside) = mean_laplacian(w, h, &particles, &particle_water);
    let (surface_roughness, surface_inside) = mean_laplacian(w, h, &surface, &surface_water);
    println!(
        "particles: {} water pixels, mean |Laplacian| {particle_roughness:.2} over {particle_inside}; \
         surface: {} water pixels, mean |Laplacian| {surface_roughness:.2} over {surface_inside}",
        covered(&particle_water),
        covered(&surface_water)
    );
    assert!(
        covered(&particle_water) >= 20_000,
        "the particles cover only {} pixels",
        covered(&particle_water)
    );
    assert!(
        covered(&surface_water) >= covered(&particle_water),
        "the surface covers {} pixels, the particles {}",
        covered(&surface_water),
        covered(&particle_water)
    );
    assert!(
        surface_roughness <= 0.5 * particle_roughness,
        "surface mean |Laplacian| {surface_roughness:.2} against the particles' {particle_roughness:.2}"
    );
    // The CPU backend's particles are copied into the same buffers: its surface is drawn too.
    let (_, _, cpu_surface) = run(&["--render", "surface", "--cpu"]);
    let cpu_water = covered(&water_mask(w, h, &empty, &cpu_surface));
    assert!(
        cpu_water >= 20_000,
        "the CPU backend's surface covers only {cpu_water} pixels"
    );
}

/// The water pixels (by `water`) whose luminance is above or below both of its horizontal
/// neighbours two pixels away by more than 30 of 255: a vertical strand one or two pixels wide.
fn strand_pixels(w: u32, h: u32, rgb: &[u8], water: &[bool]) -> usize {
    let luminance = |x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        0.299 * rgb[i] as f64 + 0.587 * rgb[i + 1] as f64 + 0.114 * rgb[i + 2] as f64
    };
    let mut strands = 0;
    for y in 0..h {
        for x in 2..w - 2 {
            if !water[(y * w + x) as usize] {
                continue;
            }
            let (here, left, right) = (luminance(x, y), luminance(x - 2, y), luminance(x + 2, y));
            if here - left.max(right) > 30.0 || left.min(right) - here > 30.0 {
                strands += 1;
            }
        }
    }
    strands
}

/// A close, low view of aquaplay.ron's island, where the front channel's water meets the
/// island's wall at a grazing angle (paused, so every picture shows the same water): the lit
/// surface has no strands, pixels brighter or darker than both of their neighbours. A depth
/// filter whose window turns one-sided at the silhouette draws them here, in vertical lines along
/// the edge (`surface_filter.wgsl`).
#[test]
fn a_close_view_of_the_waters_edge_against_the_island_shows_no_strands() {
    let base = [
        "--scene",
        "scenes/aquaplay.ron",
        "--camera",
        "0.45,0.30,-0.15,0.6,0.12,0.18",
        // Enough for the scene file to load and spawn: about 26 frames on lavapipe, where the
        // moved bodies' shaders compose at start-up beside the loading.
        "--frames",
        "40",
        "--paused",
    ];
    let run = |more: &[&str]| {
        let mut args = base.to_vec();
        args.extend(more);
        screenshot(&args)
    };
    let (w, h, empty) = run(&["--hide-particles"]);
    let (_, _, surface) = run(&[]);
    let water = water_mask(w, h, &empty, &surface);
    let covered = water.iter().filter(|&&m| m).count();
    let strands = strand_pixels(w, h, &surface, &water);
    println!("{covered} water pixels, {strands} strand pixels");
    assert!(covered >= 100_000, "the water covers only {covered} pixels");
    assert!(strands <= 30, "{strands} strand pixels in the water");
}

/// The command line refuses a bad value by option and value, with the allowed ones, before any
/// window opens (exit code 2), and `--help` lists every option.
#[test]
fn sandbox_refuses_bad_options_by_name_and_lists_them() {
    let binary = example_binary("sandbox");
    assert!(
        binary.exists(),
        "{} missing: build it with `cargo build --release --example sandbox`",
        binary.display()
    );
    for (option, value, allowed) in [
        ("--solver", "sph", "pbf"),
        ("--particles", "12", "262144"),
        ("--render", "voxels", "surface"),
        ("--scene", "/etc/hosts", "asset folder"),
    ] {
        let output = Command::new(&binary)
            .args([option, value])
            .output()
            .expect("run the sandbox");
        let text = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{option} {value}: {text}");
        for part in [option, value, allowed] {
            assert!(
                text.contains(part),
                "{option} {value}: {part:?} missing from {text}"
            );
        }
    }
    let help = Command::new(&binary).arg("--help").output().expect("run");
    let text = String::from_utf8_lossy(&help.stdout);
    assert!(help.status.success(), "{text}");
    for option in [
        "--solver",
        "--render",
        "--scene",
        "--screenshot",
        "--cpu",
        "--real-time",
    ] {
        assert!(
            text.contains(option),
            "{option} missing from --help: {text}"
        );
    }
}

/// The pixel column and row of the world point `p` seen from `eye` looking at `focus` (the
/// sandbox's `--camera`, Bevy's default vertical field of view of π/4) in a `w` × `h` view.
fn project(eye: [f32; 3], focus: [f32; 3], p: [f32; 3], w: u32, h: u32) -> (f32, f32) {
    use bevy::math::{Mat4, Vec3};
    let view = Mat4::look_at_rh(Vec3::from(eye), Vec3::from(focus), Vec3::Y);
    let projection = Mat4::perspective_rh(
        std::f32::consts::FRAC_PI_4,
        w as f32 / h as f32,
        0.01,
        100.0,
    );
    let ndc = (projection * view).project_point3(Vec3::from(p));
    (
        (ndc.x + 1.0) / 2.0 * w as f32,
        (1.0 - ndc.y) / 2.0 * h as f32,
    )
}

/// The pixels `[first, last)` in x and in y where the basin's slice `x0 ..= x1` [m] shows: every
/// corner of the slice's box (the container's full height and depth) projected.
fn pixels_of(
    (eye, focus): ([f32; 3], [f32; 3]),
    (x0, x1): (f32, f32),
    (w, h): (u32, u32),
) -> [(u32, u32); 2] {
    let mut corners = Vec::new();
    for x in [x0, x1] {
        for y in [0.0, 0.35] {
            for z in [0.0, 0.3] {
                corners.push(project(eye, focus, [x, y, z], w, h));
            }
        }
    }
    let range = |values: Vec<f32>, size: u32| {
        let first = values.iter().cloned().fold(f32::MAX, f32::min).max(0.0);
        let last = values
            .iter()
            .cloned()
            .fold(f32::MIN, f32::max)
            .min(size as f32);
        (first as u32, last as u32)
    };
    [
        range(corners.iter().map(|c| c.0).collect(), w),
        range(corners.iter().map(|c| c.1).collect(), h),
    ]
}

/// basin_jet.ron with `--whitewater` on both backends: where the jet breaks into the basin
/// (0.35 m from the pipe's wall) the lit surface shows white pixels and the class view (spray
/// red, foam green, bubbles blue over black) shows whitewater; over the basin's far end, still
/// water, the class view shows none. (On the GPU a jet whose emitter ran ahead of the device's
/// steps burst and shed whitewater everywhere.)
#[test]
fn whitewater_shows_where_the_jet_breaks_in_and_not_over_the_still_far_end() {
    let camera = ([0.2, 0.75, 1.35], [0.2, 0.0, 0.15]);
    let base = [
        "--scene",
        "scenes/basin_jet.ron",
        "--whitewater",
        "--camera",
        "0.2,0.75,1.35,0.2,0.0,0.15",
        "--frames",
        "60",
    ];
    for backend in [&["--cpu"][..], &[]] {
        let run = |more: &[&str]| {
            let mut args = base.to_vec();
            args.extend(backend);
            args.extend(more);
            screenshot(&args)
        };
        let (w, h, lit) = run(&[]);
        let (_, _, classes) = run(&["--surface-view", "whitewater"]);
        check_whitewater_pixels(camera, (w, h), &lit, &classes, backend);
    }
}

/// The checks of [`whitewater_shows_where_the_jet_breaks_in_and_not_over_the_still_far_end`] on
/// one backend's pictures (`backend`: its options, for the messages).
fn check_whitewater_pixels(
    camera: ([f32; 3], [f32; 3]),
    (w, h): (u32, u32),
    lit: &[u8],
    classes: &[u8],
    backend: &[&str],
) {
    let count = |rgb: &[u8], [columns, rows]: [(u32, u32); 2], pick: &dyn Fn(&[u8]) -> bool| {
        (rows.0..rows.1)
            .flat_map(|y| (columns.0..columns.1).map(move |x| 3 * (y * w + x) as usize))
            .filter(|&i| pick(&rgb[i..i + 3]))
            .count()
    };
    let white = |p: &[u8]| p.iter().all(|&c| c >= 200);
    let coloured = |p: &[u8]| p.iter().any(|&c| c >= 40);
    let impact = pixels_of(camera, (0.25, 0.45), (w, h));
    // The far end: right of everything nearer than 0.85 m, over the end's rows.
    let [end_columns, end_rows] = pixels_of(camera, (0.85, 1.0), (w, h));
    let nearer = pixels_of(camera, (0.0, 0.85), (w, h))[0].1;
    let far = [(nearer, end_columns.1), end_rows];
    let (white_at_impact, whitewater_at_impact, whitewater_far) = (
        count(lit, impact, &white),
        count(classes, impact, &coloured),
        count(classes, far, &coloured),
    );
    println!(
        "{backend:?}: impact {impact:?}: {white_at_impact} white, {whitewater_at_impact} whitewater; \
         far end {far:?}: {whitewater_far} whitewater"
    );
    assert!(
        white_at_impact >= 200,
        "{backend:?}: {white_at_impact} white pixels at the impact"
    );
    assert!(
        whitewater_at_impact >= 500,
        "{backend:?}: {whitewater_at_impact} whitewater pixels at the impact"
    );
    assert_eq!(
        whitewater_far, 0,
        "{backend:?}: whitewater over the still far end"
    );
}
