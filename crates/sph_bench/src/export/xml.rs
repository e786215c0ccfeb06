//! A small XML writer for DualSPHysics's case definition: indented elements and attributes
//! whose numbers are written with [`decimal`].

use super::common::decimal;
use sph_core::glam::Vec3;

/// Indented XML text.
#[derive(Default)]
pub struct Xml {
    /// The text so far.
    pub out: String,
    /// The current nesting.
    depth: usize,
}

/// Attributes: (name, value) pairs.
pub type Attrs<'a> = &'a [(&'a str, String)];

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl Xml {
    /// An empty text whose lines start at nesting `depth`.
    pub fn at(depth: usize) -> Self {
        Self {
            out: String::new(),
            depth,
        }
    }
    /// One line at the current nesting.
    pub fn line(&mut self, text: &str) {
        self.out += &"    ".repeat(self.depth);
        self.out += text;
        self.out.push('\n');
    }
    fn tag(name: &str, attrs: Attrs) -> String {
        let list: String = attrs
            .iter()
            .map(|(k, v)| format!(" {k}=\"{}\"", escape(v)))
            .collect();
        format!("<{name}{list}")
    }
    /// `<name attrs>`, nesting what follows.
    pub fn open(&mut self, name: &str, attrs: Attrs) {
        self.line(&(Self::tag(name, attrs) + ">"));
        self.depth += 1;
    }
    /// `</name>`.
    pub fn close(&mut self, name: &str) {
        self.depth -= 1;
        self.line(&format!("</{name}>"));
    }
    /// `<name attrs />`.
    pub fn empty(&mut self, name: &str, attrs: Attrs) {
        self.line(&(Self::tag(name, attrs) + " />"));
    }
    /// `<name>text</name>`.
    pub fn text(&mut self, name: &str, text: &str) {
        self.line(&format!("<{name}>{}</{name}>", escape(text)));
    }
    /// `<!-- text -->` (a `--` in the text is split).
    pub fn comment(&mut self, text: &str) {
        self.line(&format!("<!-- {} -->", text.replace("--", "- -")));
    }
    /// `<name x=".." y=".." z=".." />`.
    pub fn point(&mut self, name: &str, p: Vec3) {
        self.empty(name, &xyz(p));
    }
    /// GenCase's `drawbox` from `lo` to `hi` with its `boxfill` (`solid`, `all`, ...).
    pub fn draw_box(&mut self, fill: &str, lo: Vec3, hi: Vec3) {
        self.open("drawbox", &[]);
        self.text("boxfill", fill);
        self.point("point", lo);
        self.point("size", hi - lo);
        self.close("drawbox");
    }
    /// GenCase's `drawsphere` of `radius` about `centre`.
    pub fn draw_sphere(&mut self, radius: f32, centre: Vec3) {
        self.open("drawsphere", &[("radius", num(radius))]);
        self.point("point", centre);
        self.close("drawsphere");
    }
}

/// A number as written ([`decimal`]).
pub fn num(x: f32) -> String {
    decimal(x).to_string()
}

/// The attributes x, y, z of `p`.
pub fn xyz(p: Vec3) -> [(&'static str, String); 3] {
    [("x", num(p.x)), ("y", num(p.y)), ("z", num(p.z))]
}

/// The attribute `value`.
pub fn value(v: f32) -> [(&'static str, String); 1] {
    [("value", num(v))]
}
