//! Log-log scatter plots drawn with plotters, written as PNG and SVG. The text is set in Ubuntu
//! Light from `epaint_default_fonts` (registered with plotters' `ab_glyph` renderer), so no system
//! font or font library is needed.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;
use std::path::Path;
use std::sync::OnceLock;

/// A few distinct colours for series (matplotlib's "tab10").
pub const PALETTE: [[u8; 3]; 8] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [23, 190, 207],
];

/// The shape of a series' markers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Marker {
    /// A filled disc.
    #[default]
    Circle,
    /// A filled triangle.
    Triangle,
    /// A filled square.
    Square,
}

/// One series of points, drawn with its own colour and marker and listed in the legend.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Marker colour (RGB).
    pub color: [u8; 3],
    /// Marker shape.
    pub marker: Marker,
    /// (x, y) data; non-finite or non-positive values are skipped.
    pub points: Vec<(f64, f64)>,
}

/// A scatter plot with logarithmic axes.
pub struct ScatterPlot {
    /// Centred above the plot.
    pub title: String,
    /// Under the x axis, with the unit.
    pub x_label: String,
    /// Beside the y axis, with the unit.
    pub y_label: String,
    /// Drawn in order; later series paint over earlier ones.
    pub series: Vec<Series>,
}

/// The family every text of the plots asks for.
const FONT: &str = "sans-serif";
const MARKER_RADIUS: i32 = 5;
const GRID_GREY: RGBColor = RGBColor(225, 225, 225);
const FRAME_GREY: RGBColor = RGBColor(150, 150, 150);

/// Registers the font once (plotters keeps a process-wide table).
fn register_fonts() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
                .map_err(|_| "the plot font (Ubuntu Light) does not load".to_string())
        })
        .clone()
}

fn usable(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// Axis range in log10 units: padded, snapped outwards to half decades, at least one decade.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let logs = values.filter(|v| usable(*v)).map(f64::log10);
    let (lo, hi) = logs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), l| {
        (lo.min(l), hi.max(l))
    });
    if lo > hi {
        return (0.0, 1.0); // no usable data: 1..10
    }
    let pad = if hi - lo < 1e-9 {
        0.5
    } else {
        0.05 + 0.02 * (hi - lo)
    };
    let (lo, hi) = (lo - pad, hi + pad);
    // Beyond f64's range the decades would be infinite: clamp to what plotters can map.
    let clamp = |v: f64| v.clamp(-300.0, 300.0);
    (
        clamp((lo * 2.0).floor() / 2.0),
        clamp((hi * 2.0).ceil() / 2.0),
    )
}

/// Tick positions inside 10^lo ..= 10^hi: 1, 2 and 5 × 10^k over up to two decades; decades beyond
/// (every second, fifth, ... decade so that about ten remain at most).
fn ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    let (first, last) = (lo.floor() as i32, hi.ceil() as i32);
    let mantissas: &[f64] = if hi - lo <= 2.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let steps = [1, 2, 5, 10, 20, 50, 100];
    let step = (steps.into_iter())
        .find(|s| (last - first) / s < 10)
        .unwrap_or(100);
    let inside = |v: &f64| (lo - 1e-9..=hi + 1e-9).contains(&v.log10());
    (first..=last)
        .filter(|e| e.rem_euclid(step) == 0)
        .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
        .filter(inside)
        .collect()
}

/// A compact tick label: `0.02`, `0.5`, `3`, `200`, else `1e-5`, `2e6`.
fn tick_label(v: f64) -> String {
    if !usable(v) {
        return String::new();
    }
    let exponent = v.log10().floor() as i32;
    if (-3..4).contains(&exponent) {
        let scale = 10f64.powi(2 - exponent);
        format!("{}", (v * scale).round() / scale)
    } else {
        format!("{v:.0e}")
    }
}

/// The inside corner whose quarter of the plot holds the fewest points (in log coordinates).
fn legend_corner(plot: &ScatterPlot, xr: (f64, f64), yr: (f64, f64)) -> SeriesLabelPosition {
    let unit = |v: f64, (lo, hi): (f64, f64)| (v.log10() - lo) / (hi - lo);
    let points: Vec<(f64, f64)> = (plot.series.iter())
        .flat_map(|s| s.points.iter())
        .filter(|p| usable(p.0) && usable(p.1))
        .map(|p| (unit(p.0, xr), unit(p.1, yr)))
        .collect();
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let near = |v: f64, high: bool| if high { v > 0.55 } else { v < 0.45 };
    let hidden = |&(_, right, top): &(SeriesLabelPosition, bool, bool)| {
        let inside = |p: &&(f64, f64)| near(p.0, right) && near(p.1, top);
        points.iter().filter(inside).count()
    };
    let best = corners.iter().min_by_key(|c| hidden(c));
    best.map_or(SeriesLabelPosition::UpperRight, |c| c.0.clone())
}

/// Draws one plot into `area`.
fn draw_plot<DB: DrawingBackend>(
    plot: &ScatterPlot,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let points = || plot.series.iter().flat_map(|s| s.points.iter());
    let xr = log_range(points().map(|p| p.0));
    let yr = log_range(points().map(|p| p.1));
    let decades = |(lo, hi): (f64, f64)| 10f64.powf(lo)..10f64.powf(hi);
    let mut chart = ChartBuilder::on(area)
        .caption(&plot.title, (FONT, 24))
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(72)
        .build_cartesian_2d(
            decades(xr).log_scale().with_key_points(ticks(xr)),
            decades(yr).log_scale().with_key_points(ticks(yr)),
        )?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc(plot.y_label.as_str())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .bold_line_style(GRID_GREY)
        .max_light_lines(0)
        .axis_style(BLACK)
        .draw()?;
    for s in &plot.series {
        let color = RGBColor(s.color[0], s.color[1], s.color[2]);
        let points = (s.points.iter().copied()).filter(|p| usable(p.0) && usable(p.1));
        let r = MARKER_RADIUS;
        let square = move |r: i32| Rectangle::new([(-r, -r), (r, r)], color.filled());
        let drawn = match s.marker {
            Marker::Circle => chart
                .draw_series(points.map(move |p| Circle::new(p, r, color.filled())))?
                .legend(move |p| Circle::new(p, r + 1, color.filled())),
            Marker::Triangle => chart
                .draw_series(points.map(move |p| TriangleMarker::new(p, r + 2, color.filled())))?
                .legend(move |p| TriangleMarker::new(p, r + 3, color.filled())),
            Marker::Square => chart
                .draw_series(points.map(move |p| EmptyElement::at(p) + square(r)))?
                .legend(move |p| EmptyElement::at(p) + square(r + 1)),
        };
        drawn.label(s.label.as_str());
    }
    if !plot.series.is_empty() {
        chart
            .configure_series_labels()
            .position(legend_corner(plot, xr, yr))
            .label_font((FONT, 16))
            .background_style(WHITE)
            .border_style(FRAME_GREY)
            .margin(12)
            .draw()?;
    }
    Ok(())
}

/// Fills `root` white and draws `plots` one under the other.
fn draw_stacked<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    plots: &[ScatterPlot],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    for (plot, area) in plots.iter().zip(root.split_evenly((plots.len().max(1), 1))) {
        draw_plot(plot, &area).map_err(err)?;
    }
    root.present().map_err(err)
}

/// Renders `plots` one under the other (each `width` × `height` pixels) into one PNG.
pub fn write_stacked_png(
    plots: &[ScatterPlot],
    path: &Path,
    width: u32,
    height: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("writing plot {}: {e}", path.display());
    register_fonts().map_err(|e| err(&e))?;
    let total_height = height * plots.len().max(1) as u32;
    let mut pixels = vec![255; width as usize * total_height as usize * 3];
    let root = BitMapBackend::with_buffer(&mut pixels, (width, total_height)).into_drawing_area();
    draw_stacked(root, plots).map_err(|e| err(&e))?;
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, total_height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| err(&e))?;
    writer.write_image_data(&pixels).map_err(|e| err(&e))?;
    writer.finish().map_err(|e| err(&e))
}

/// Renders `plots` one under the other (each `width` × `height`) into one SVG.
pub fn write_stacked_svg(
    plots: &[ScatterPlot],
    path: &Path,
    width: u32,
    height: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("writing plot {}: {e}", path.display());
    register_fonts().map_err(|e| err(&e))?;
    let total_height = height * plots.len().max(1) as u32;
    let mut svg = String::new();
    let root = SVGBackend::with_string(&mut svg, (width, total_height)).into_drawing_area();
    draw_stacked(root, plots).map_err(|e| err(&e))?;
    std::fs::write(path, svg).map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: [u8; 3] = [200, 10, 30];

    fn plot(series: Vec<Series>) -> ScatterPlot {
        ScatterPlot {
            title: "Cost against accuracy".into(),
            x_label: "cost per simulated second [s/s]".into(),
            y_label: "density error [%]".into(),
            series,
        }
    }

    fn one(points: Vec<(f64, f64)>) -> Vec<Series> {
        vec![Series {
            label: "cpu kdk".into(),
            color: RED,
            marker: Marker::Circle,
            points,
        }]
    }

    /// A directory of its own for the test `test` (tests run in parallel).
    fn temp_dir(test: &str) -> std::path::PathBuf {
        let name = format!("sph_bench_plot_{}_{test}", std::process::id());
        let dir = std::env::temp_dir().join(name);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Where a test's plots go: `SPH_BENCH_PLOT_DIR` to keep them and look at them, else a
    /// temporary directory removed at the end.
    fn plot_dir(test: &str) -> (std::path::PathBuf, bool) {
        match std::env::var_os("SPH_BENCH_PLOT_DIR") {
            Some(dir) => {
                std::fs::create_dir_all(&dir).unwrap();
                (dir.into(), true)
            }
            None => (temp_dir(test), false),
        }
    }

    fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
        let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut pixels).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        (info.width, info.height, pixels)
    }

    #[test]
    fn png_and_svg_are_written_with_axes_labels_and_points() {
        let mut series = one(vec![(0.5, 2.0), (3.0, 0.04), (40.0, 0.3)]);
        series.push(Series {
            label: "gpu kdk".into(),
            color: PALETTE[0],
            marker: Marker::Triangle,
            points: vec![(8.0, 0.05), (20.0, 0.02), (150.0, 0.01)],
        });
        series.push(Series {
            label: "cpu pbf".into(),
            color: PALETTE[2],
            marker: Marker::Square,
            points: vec![(2.0, 1.0)],
        });
        let plots = [plot(series), plot(vec![])];
        let (dir, keep) = plot_dir("written");
        let (png_path, svg_path) = (dir.join("trade.png"), dir.join("trade.svg"));
        write_stacked_png(&plots, &png_path, 600, 400).unwrap();
        write_stacked_svg(&plots, &svg_path, 600, 400).unwrap();
        let (w, h, pixels) = decode(&png_path);
        assert_eq!((w, h), (600, 800));
        let count = |c: [u8; 3]| pixels.chunks(3).filter(|p| *p == c).count();
        // Three markers and the legend's, 5 px in radius: well over 100 pixels of their colour.
        assert!(count(RED) > 100, "{} marker pixels", count(RED));
        // The triangles and the square are drawn in their own colours.
        assert!(
            count(PALETTE[0]) > 100,
            "{} triangle pixels",
            count(PALETTE[0])
        );
        assert!(
            count(PALETTE[2]) > 50,
            "{} square pixels",
            count(PALETTE[2])
        );
        // Text: dark pixels besides the frame (a frame alone is about 4 × 600 pixels).
        assert!(
            count([0, 0, 0]) > 2_000,
            "{} black pixels",
            count([0, 0, 0])
        );
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        for text in [
            "Cost against accuracy",
            "cost per simulated second [s/s]",
            "density error [%]",
            "cpu kdk",
            "cpu pbf",
            "<circle",
            "<polygon",
            "<rect",
        ] {
            assert!(svg.contains(text), "no {text:?} in the SVG");
        }
        if !keep {
            std::fs::remove_dir_all(dir).unwrap();
        }
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let bad = vec![
            (f64::NAN, 1.0),
            (-1.0, 2.0),
            (0.0, 0.0),
            (f64::INFINITY, 3.0),
            (f64::MIN_POSITIVE, f64::MAX),
        ];
        let dir = temp_dir("degenerate");
        let path = dir.join("plot.png");
        for series in [vec![], one(vec![]), one(vec![(5.0, 5.0)]), one(bad)] {
            write_stacked_png(&[plot(series)], &path, 640, 480).unwrap();
        }
        std::fs::remove_dir_all(dir).unwrap();
        assert_eq!(log_range(std::iter::empty()), (0.0, 1.0));
        assert_eq!(log_range([5.0, 5.0].into_iter()), (0.0, 1.5));
        let bad = Path::new("/nonexistent-dir/plot.png");
        let e = write_stacked_png(&[plot(vec![])], bad, 100, 100).unwrap_err();
        assert!(e.contains("/nonexistent-dir/plot.png"), "{e}");
    }

    #[test]
    fn tick_labels_are_compact() {
        let labels: Vec<String> = [1e-5, 0.002, 0.05, 1.0, 20.0, 300.0, 2e6]
            .into_iter()
            .map(tick_label)
            .collect();
        assert_eq!(labels, ["1e-5", "0.002", "0.05", "1", "20", "300", "2e6"]);
    }

    #[test]
    fn ticks_step_by_1_2_5_or_by_decades() {
        assert_eq!(ticks((-1.5, 0.0)), [0.05, 0.1, 0.2, 0.5, 1.0]);
        assert_eq!(ticks((-0.5, 3.0)), [1.0, 10.0, 100.0, 1000.0]);
        let wide = ticks((-300.0, 300.0));
        assert!(wide.len() <= 13 && wide.contains(&1.0), "{wide:?}");
        assert!(ticks((0.1, 0.2)).is_empty());
    }

    #[test]
    fn the_legend_avoids_the_points() {
        // Points in the upper right: the legend goes elsewhere.
        let p = plot(one(vec![(50.0, 50.0), (60.0, 40.0), (1.0, 1.0)]));
        let (xr, yr) = (
            log_range([1.0, 60.0].into_iter()),
            log_range([1.0, 50.0].into_iter()),
        );
        assert_ne!(legend_corner(&p, xr, yr), SeriesLabelPosition::UpperRight);
    }
}
