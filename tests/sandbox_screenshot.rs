//! Runs the sandbox under Xvfb on the software Vulkan driver, lets it render, saves a screenshot
//! and looks at it: blue particle pixels inside the box, the obstacles (`--obstacles`: a ball and
//! a box in orange, and the gate) and the runtime panel present.

use std::path::PathBuf;
use std::process::Command;

fn sandbox_binary() -> PathBuf {
    // target/<profile>/deps/<this test> -> target/<profile>/examples/sandbox
    let exe = std::env::current_exe().expect("test executable path");
    let profile_dir = exe.parent().and_then(|d| d.parent()).expect("target dir");
    profile_dir.join("examples").join("sandbox")
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

/// Runs the sandbox under Xvfb with `args` and `--screenshot`; returns the decoded picture.
fn screenshot(args: &[&str]) -> (u32, u32, Vec<u8>) {
    let binary = sandbox_binary();
    assert!(
        binary.exists(),
        "{} missing: build it with `cargo build --release --example sandbox`",
        binary.display()
    );
    let xvfb = Command::new("xvfb-run").arg("--help").output();
    assert!(
        xvfb.is_ok(),
        "xvfb-run not found: install it with `sudo apt-get install xvfb xauth` (scripts/test.sh does this)"
    );
    let shot = std::env::temp_dir().join(format!(
        "sandbox-{}-{}.png",
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
        "sandbox failed ({}):\n{}",
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
fn dfsph_water_is_drawn_on_both_backends() {
    // The GPU backend draws its own buffers; with `--cpu` the plugin copies the CPU solver's
    // particles into them.
    for backend in [None, Some("--cpu")] {
        let mut args = vec!["--particles", "4096", "--frames", "20", "--solver", "dfsph"];
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
fn the_lock_aquaplay_and_ramp_scene_files_render() {
    for file in [
        "assets/scenes/lock.ron",
        "assets/scenes/aquaplay.ron",
        "assets/scenes/ramp.ron",
    ] {
        let path = format!("{}/{file}", env!("CARGO_MANIFEST_DIR"));
        let (w, _, rgb) = screenshot(&["--scene", &path, "--frames", "20"]);
        let blue = blue_pixels(w, &rgb);
        assert!(
            blue >= 2_000,
            "{file}: only {blue} blue particle pixels in the box"
        );
    }
}

#[test]
fn sandbox_screenshot_shows_water_in_the_box_and_the_panel() {
    let (w, h, rgb) = screenshot(&["--particles", "8192", "--frames", "30", "--obstacles"]);
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
