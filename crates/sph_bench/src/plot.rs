//! A small log-log scatter plot written to PNG, with an embedded 8x8 bitmap font
//! (no system font or graphics libraries).

use font8x8::legacy::BASIC_LEGACY;
use std::path::Path;

/// A few distinct colours for series.
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

/// One series of points, drawn with its own colour and listed in the legend.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Marker colour (RGB).
    pub color: [u8; 3],
    /// (x, y) data; non-finite or non-positive values are skipped.
    pub points: Vec<(f64, f64)>,
}

/// A scatter plot with logarithmic axes.
pub struct ScatterPlot {
    /// Centred above the plot.
    pub title: String,
    /// Centred under the x axis.
    pub x_label: String,
    /// Written above the y axis.
    pub y_label: String,
    /// Drawn in order; later series paint over earlier ones.
    pub series: Vec<Series>,
}

const GLYPH: i64 = 16; // 8x8 font at scale 2
const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [220, 220, 220];
const FRAME_GREY: [u8; 3] = [150, 150, 150];
const RADIUS: i64 = 4;

/// An RGB pixel buffer that silently clips everything drawn outside it.
struct Canvas {
    w: i64,
    h: i64,
    px: Vec<u8>,
}

impl Canvas {
    fn new(w: u32, h: u32) -> Self {
        let px = vec![255; w as usize * h as usize * 3];
        Canvas {
            w: w.into(),
            h: h.into(),
            px,
        }
    }
    fn set(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if (0..self.w).contains(&x) && (0..self.h).contains(&y) {
            let i = ((y * self.w + x) * 3) as usize;
            self.px[i..i + 3].copy_from_slice(&c);
        }
    }
    /// Fills the half-open rectangle [x0, x1) x [y0, y1).
    fn rect(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, c: [u8; 3]) {
        for y in y0.max(0)..y1.min(self.h) {
            for x in x0.max(0)..x1.min(self.w) {
                self.set(x, y, c);
            }
        }
    }
    /// One-pixel outline of the inclusive rectangle (x0, y0)-(x1, y1).
    fn outline(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, c: [u8; 3]) {
        self.rect(x0, y0, x1 + 1, y0 + 1, c);
        self.rect(x0, y1, x1 + 1, y1 + 1, c);
        self.rect(x0, y0, x0 + 1, y1 + 1, c);
        self.rect(x1, y0, x1 + 1, y1 + 1, c);
    }
    fn disc(&mut self, cx: i64, cy: i64, r: i64, c: [u8; 3]) {
        for dy in -r..=r {
            for dx in -r..=r {
                if dx * dx + dy * dy <= r * r + r {
                    self.set(cx + dx, cy + dy, c);
                }
            }
        }
    }
    /// Draws `s` with its top-left corner at (x, y); non-ASCII shows as '?'.
    fn text(&mut self, x: i64, y: i64, s: &str, c: [u8; 3]) {
        let scale = GLYPH / 8;
        for (i, ch) in s.chars().enumerate() {
            let code = u8::try_from(ch).ok().filter(u8::is_ascii).unwrap_or(b'?');
            let glyph = BASIC_LEGACY[usize::from(code)];
            let gx = x + i as i64 * GLYPH;
            for (row, bits) in (0i64..).zip(glyph) {
                for col in 0..8i64 {
                    if bits & (1 << col) != 0 {
                        let (px, py) = (gx + col * scale, y + row * scale);
                        self.rect(px, py, px + scale, py + scale, c);
                    }
                }
            }
        }
    }
}

fn text_width(s: &str) -> i64 {
    s.chars().count() as i64 * GLYPH
}

/// Axis range in log10 units: padded, snapped outwards to half decades, at least one decade.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let logs = values.filter(|v| v.is_finite() && *v > 0.0).map(f64::log10);
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
    ((lo * 2.0).floor() / 2.0, (hi * 2.0).ceil() / 2.0)
}

/// Integer decades inside [lo, hi], thinned to multiples of 1, 2, 5, 10, ... (at most ~10).
fn decades(lo: f64, hi: f64) -> Vec<i32> {
    let (first, last) = (lo.ceil() as i32, hi.floor() as i32);
    let mut steps = [1, 2, 5, 10, 20, 50, 100, 200].into_iter();
    let step = steps.find(|s| (last - first) / s < 10).unwrap_or(200);
    (first..=last).filter(|e| e % step == 0).collect()
}

/// Positions of 2..9 times each decade strictly inside the range (none if it is very wide).
fn minor_ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    let decade = (lo.floor() as i32..=hi.ceil() as i32).filter(|_| hi - lo <= 8.0);
    let ticks = decade.flat_map(|e| (2..10).map(move |m| f64::from(e) + f64::from(m).log10()));
    ticks.filter(|v| *v > lo && *v < hi).collect()
}

/// Compact label for 10^e: `0.01`, `0.1`, `1`, `10`, `100`, else `1e-3`, `1e3`.
fn tick_label(e: i32) -> String {
    match e {
        -2 => "0.01".into(),
        -1 => "0.1".into(),
        0..=2 => 10i32.pow(e as u32).to_string(),
        _ => format!("1e{e}"),
    }
}

/// Where the plot area sits in the image and how data maps onto it.
struct Layout {
    x0: i64,
    y0: i64,
    x1: i64,
    y1: i64,
    xr: (f64, f64),
    yr: (f64, f64),
}

impl Layout {
    fn new(plot: &ScatterPlot, w: u32, h: u32) -> Self {
        let pts = || plot.series.iter().flat_map(|s| s.points.iter());
        let xr = log_range(pts().map(|p| p.0));
        let yr = log_range(pts().map(|p| p.1));
        let ticks = decades(yr.0, yr.1)
            .into_iter()
            .map(|e| text_width(&tick_label(e)));
        let x0 = ticks.max().unwrap_or(0) + 20;
        let y0 = 2 * GLYPH + 40;
        let x1 = (i64::from(w) - 30).max(x0 + 1);
        let y1 = (i64::from(h) - 2 * GLYPH - 36).max(y0 + 1);
        Layout {
            x0,
            y0,
            x1,
            y1,
            xr,
            yr,
        }
    }
    fn map_x(&self, lx: f64) -> i64 {
        let t = (lx - self.xr.0) / (self.xr.1 - self.xr.0);
        (self.x0 as f64 + t * (self.x1 - self.x0) as f64).round() as i64
    }
    fn map_y(&self, ly: f64) -> i64 {
        let t = (ly - self.yr.0) / (self.yr.1 - self.yr.0);
        (self.y1 as f64 - t * (self.y1 - self.y0) as f64).round() as i64
    }
}

impl ScatterPlot {
    /// Renders to RGB pixels (width*height*3), white background.
    pub fn render(&self, width: u32, height: u32) -> Vec<u8> {
        let mut cv = Canvas::new(width, height);
        let l = Layout::new(self, width, height);
        let (x0, y0, x1, y1) = (l.x0, l.y0, l.x1, l.y1);
        for v in minor_ticks(l.xr) {
            cv.rect(l.map_x(v), y1 - 4, l.map_x(v) + 1, y1, FRAME_GREY);
        }
        for v in minor_ticks(l.yr) {
            cv.rect(x0 + 1, l.map_y(v), x0 + 5, l.map_y(v) + 1, FRAME_GREY);
        }
        for e in decades(l.xr.0, l.xr.1) {
            let (px, s) = (l.map_x(f64::from(e)), tick_label(e));
            cv.rect(px, y0, px + 1, y1, GRID);
            cv.text(px - text_width(&s) / 2, y1 + 8, &s, BLACK);
        }
        for e in decades(l.yr.0, l.yr.1) {
            let (py, s) = (l.map_y(f64::from(e)), tick_label(e));
            cv.rect(x0, py, x1, py + 1, GRID);
            cv.text(x0 - 8 - text_width(&s), py - GLYPH / 2, &s, BLACK);
        }
        cv.outline(x0, y0, x1, y1, BLACK);
        let title_x = (i64::from(width) - text_width(&self.title)) / 2;
        cv.text(title_x.max(0), 10, &self.title, BLACK);
        let xl_x = x0 + (x1 - x0 - text_width(&self.x_label)) / 2;
        cv.text(xl_x.max(0), y1 + GLYPH + 20, &self.x_label, BLACK);
        cv.text(10, y0 - GLYPH - 14, &self.y_label, BLACK);
        let usable = |v: f64| v.is_finite() && v > 0.0;
        let marks: Vec<(i64, i64, [u8; 3])> = (self.series.iter())
            .flat_map(|s| s.points.iter().map(move |p| (p.0, p.1, s.color)))
            .filter(|p| usable(p.0) && usable(p.1))
            .map(|(x, y, c)| (l.map_x(x.log10()), l.map_y(y.log10()), c))
            .collect();
        for &(x, y, c) in &marks {
            cv.disc(x, y, RADIUS, c);
        }
        if self.series.is_empty() {
            return cv.px;
        }
        // Legend: top-right unless another inside corner hides fewer points.
        let row = GLYPH + 8;
        let lw = 44
            + self
                .series
                .iter()
                .map(|s| text_width(&s.label))
                .max()
                .unwrap_or(0);
        let lh = row * self.series.len() as i64 + 8;
        let (left, right, top, bottom) = (x0 + 10, x1 - 10 - lw, y0 + 10, y1 - 10 - lh);
        let corners = [(right, top), (left, top), (right, bottom), (left, bottom)];
        let hidden = |&(lx, ly): &(i64, i64)| {
            let near = |v: i64, lo: i64, len: i64| (lo - RADIUS..=lo + len + RADIUS).contains(&v);
            let inside = |m: &&(i64, i64, [u8; 3])| near(m.0, lx, lw) && near(m.1, ly, lh);
            marks.iter().filter(inside).count()
        };
        let (lx, ly) = corners.into_iter().min_by_key(hidden).unwrap_or(corners[0]);
        cv.rect(lx, ly, lx + lw, ly + lh, [255, 255, 255]);
        cv.outline(lx, ly, lx + lw, ly + lh, FRAME_GREY);
        for (i, s) in self.series.iter().enumerate() {
            let ry = ly + 8 + row * i as i64;
            cv.disc(lx + 18, ry + GLYPH / 2, RADIUS + 1, s.color);
            cv.text(lx + 32, ry, &s.label, BLACK);
        }
        cv.px
    }
}

/// Renders `plots` one under the other (each `width` × `height`) into one PNG.
pub fn write_stacked_png(
    plots: &[ScatterPlot],
    path: &Path,
    width: u32,
    height: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("writing plot {}: {e}", path.display());
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let total_height = height * plots.len().max(1) as u32;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, total_height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| err(&e))?;
    let mut pixels: Vec<u8> = plots.iter().flat_map(|p| p.render(width, height)).collect();
    pixels.resize((width * total_height * 3) as usize, 255);
    writer.write_image_data(&pixels).map_err(|e| err(&e))?;
    writer.finish().map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plot(series: Vec<Series>) -> ScatterPlot {
        let s = |t: &str| t.to_string();
        ScatterPlot {
            title: s("Title"),
            x_label: s("x"),
            y_label: s("y"),
            series,
        }
    }

    fn one(points: Vec<(f64, f64)>) -> Vec<Series> {
        vec![Series {
            label: "s".into(),
            color: [200, 10, 30],
            points,
        }]
    }

    #[test]
    fn render_has_requested_size() {
        assert_eq!(plot(vec![]).render(320, 240).len(), 320 * 240 * 3);
    }

    #[test]
    fn point_colour_appears_where_log_coordinates_map() {
        let p = plot(one(vec![(1.0, 1.0), (100.0, 1000.0)]));
        let l = Layout::new(&p, 400, 300);
        assert_eq!((l.xr, l.yr), ((-0.5, 2.5), (-0.5, 3.5)));
        let img = p.render(400, 300);
        let pixel = |x: i64, y: i64| &img[((y * 400 + x) * 3) as usize..][..3];
        // (1, 1) sits 1/6 of the way across and 1/8 up; (100, 1000) at 5/6 across, 7/8 up.
        let at = |fx: f64, fy: f64| {
            let x = l.x0 as f64 + fx * (l.x1 - l.x0) as f64;
            let y = l.y1 as f64 - fy * (l.y1 - l.y0) as f64;
            pixel(x.round() as i64, y.round() as i64)
        };
        assert_eq!(at(1.0 / 6.0, 1.0 / 8.0), [200, 10, 30]);
        assert_eq!(at(5.0 / 6.0, 7.0 / 8.0), [200, 10, 30]);
        // And not somewhere unrelated, e.g. the bottom-right of the plot area.
        assert_ne!(pixel(l.x1 - 20, l.y1 - 20), [200, 10, 30]);
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let bad = vec![
            (f64::NAN, 1.0),
            (-1.0, 2.0),
            (0.0, 0.0),
            (f64::INFINITY, 3.0),
        ];
        for series in [vec![], one(vec![]), one(vec![(5.0, 5.0)]), one(bad)] {
            let p = plot(series);
            for (w, h) in [(640, 480), (10, 10), (0, 0), (1, 300)] {
                assert_eq!(p.render(w, h).len(), (w * h * 3) as usize);
            }
        }
        assert_eq!(log_range(std::iter::empty()), (0.0, 1.0));
        assert_eq!(log_range([5.0, 5.0].into_iter()), (0.0, 1.5));
        let extreme = log_range([f64::MIN_POSITIVE, f64::MAX].into_iter());
        assert!(decades(extreme.0, extreme.1).len() <= 12);
    }

    #[test]
    fn tick_labels_are_compact() {
        let labels: Vec<String> = (-3..=3).map(tick_label).collect();
        assert_eq!(labels, ["1e-3", "0.01", "0.1", "1", "10", "100", "1e3"]);
    }

    #[test]
    fn write_png_round_trips() {
        let path = std::env::temp_dir().join(format!("plot_test_{}.png", std::process::id()));
        let plots = [plot(one(vec![(0.5, 2.0)])), plot(vec![])];
        write_stacked_png(&plots, &path, 300, 200).unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let reader = png::Decoder::new(file).read_info().unwrap();
        assert_eq!((reader.info().width, reader.info().height), (300, 400));
        std::fs::remove_file(&path).unwrap();
        let bad = Path::new("/nonexistent-dir/plot.png");
        let e = write_stacked_png(&[plot(vec![])], bad, 10, 10).unwrap_err();
        assert!(e.contains("/nonexistent-dir/plot.png"), "{e}");
    }
}
