//! The figures' drawing: an SVG canvas with a linear map from the world into a plot area, and
//! the colour ramp of the value maps. Written here by hand (lines, circles, rectangles, text):
//! no font or plotting dependency.

use std::fmt::Write as _;
use std::path::Path;

/// A drawing: an SVG canvas and a linear map from a world rectangle into a plot area.
pub(crate) struct Figure {
    pub(crate) body: String,
    pub(crate) width: f64,
    pub(crate) height: f64,
    /// World x range, y range.
    pub(crate) x: (f64, f64),
    pub(crate) y: (f64, f64),
    /// Plot area in pixels: left, top, width, height.
    pub(crate) area: (f64, f64, f64, f64),
}

impl Figure {
    pub(crate) fn new(width: f64, height: f64, x: (f64, f64), y: (f64, f64)) -> Self {
        Figure {
            body: String::new(),
            width,
            height,
            x,
            y,
            area: (60.0, 40.0, width - 90.0, height - 90.0),
        }
    }

    /// A figure whose world rectangle keeps equal scales on both axes (for geometry).
    pub(crate) fn equal(size: f64, centre: (f64, f64), half: f64) -> Self {
        Figure::new(
            size,
            size,
            (centre.0 - half, centre.0 + half),
            (centre.1 - half, centre.1 + half),
        )
    }

    pub(crate) fn px(&self, x: f64, y: f64) -> (f64, f64) {
        let (left, top, w, h) = self.area;
        (
            left + (x - self.x.0) / (self.x.1 - self.x.0) * w,
            top + h - (y - self.y.0) / (self.y.1 - self.y.0) * h,
        )
    }

    pub(crate) fn scale(&self) -> f64 {
        self.area.2 / (self.x.1 - self.x.0)
    }

    pub(crate) fn polyline(&mut self, points: &[(f64, f64)], colour: &str, width: f64, dash: &str) {
        let mut d = String::new();
        for &(x, y) in points {
            let (a, b) = self.px(x, y);
            let _ = write!(d, "{a:.1},{b:.1} ");
        }
        let _ = writeln!(
            self.body,
            r#"<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="{width}" stroke-dasharray="{dash}"/>"#
        );
    }

    pub(crate) fn circle(
        &mut self,
        x: f64,
        y: f64,
        r_world: f64,
        stroke: &str,
        fill: &str,
        dash: &str,
    ) {
        let (a, b) = self.px(x, y);
        let r = r_world * self.scale();
        let _ = writeln!(
            self.body,
            r#"<circle cx="{a:.1}" cy="{b:.1}" r="{r:.1}" stroke="{stroke}" fill="{fill}" stroke-dasharray="{dash}"/>"#
        );
    }

    pub(crate) fn dot(&mut self, x: f64, y: f64, radius_px: f64, fill: &str) {
        let (a, b) = self.px(x, y);
        let _ = writeln!(
            self.body,
            r#"<circle cx="{a:.1}" cy="{b:.1}" r="{radius_px}" fill="{fill}"/>"#
        );
    }

    pub(crate) fn cell(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str) {
        let (a, b) = self.px(x, y + h);
        let (c, d) = self.px(x + w, y);
        let _ = writeln!(
            self.body,
            r#"<rect x="{a:.1}" y="{b:.1}" width="{:.1}" height="{:.1}" fill="{fill}"/>"#,
            c - a + 0.5,
            d - b + 0.5
        );
    }

    pub(crate) fn text(&mut self, x_px: f64, y_px: f64, size: f64, anchor: &str, text: &str) {
        let text = text
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        let _ = writeln!(
            self.body,
            r#"<text x="{x_px:.1}" y="{y_px:.1}" font-family="sans-serif" font-size="{size}" text-anchor="{anchor}">{text}</text>"#
        );
    }

    /// Frame, ticks at `step` (world units; labels through `label`), axis names and a title.
    pub(crate) fn axes(
        &mut self,
        step: (f64, f64),
        label: fn(f64) -> String,
        names: (&str, &str),
        title: &str,
    ) {
        let (left, top, w, h) = self.area;
        let _ = writeln!(
            self.body,
            r#"<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="none" stroke="black"/>"#
        );
        let mut v = (self.x.0 / step.0).ceil() * step.0;
        while v <= self.x.1 + 1e-9 {
            let (a, _) = self.px(v, self.y.0);
            self.text(a, top + h + 16.0, 11.0, "middle", &label(v));
            v += step.0;
        }
        let mut v = (self.y.0 / step.1).ceil() * step.1;
        while v <= self.y.1 + 1e-9 {
            let (_, b) = self.px(self.x.0, v);
            self.text(left - 6.0, b + 4.0, 11.0, "end", &label(v));
            v += step.1;
        }
        self.text(left + w / 2.0, top + h + 34.0, 12.0, "middle", names.0);
        let _ = writeln!(
            self.body,
            r#"<text x="16" y="{:.1}" font-family="sans-serif" font-size="12" text-anchor="middle" transform="rotate(-90 16 {:.1})">{}</text>"#,
            top + h / 2.0,
            top + h / 2.0,
            names.1
        );
        self.text(self.width / 2.0, 22.0, 14.0, "middle", title);
    }

    /// Lines of explanation at the top left of the plot area.
    pub(crate) fn legend(&mut self, lines: &[&str]) {
        let (left, top, _, _) = self.area;
        for (i, line) in lines.iter().enumerate() {
            self.text(
                left + 8.0,
                top + 16.0 + 14.0 * i as f64,
                11.0,
                "start",
                line,
            );
        }
    }

    pub(crate) fn save(&self, path: &Path) -> std::io::Result<()> {
        std::fs::write(path, svg(self.width, self.height, &self.body))
    }

    /// Two figures of one size in one file, `left` beside `right`.
    pub(crate) fn save_side_by_side(
        left: &Figure,
        right: &Figure,
        path: &Path,
    ) -> std::io::Result<()> {
        let body = format!(
            "<g>\n{}</g>\n<g transform=\"translate({} 0)\">\n{}</g>\n",
            left.body, left.width, right.body
        );
        std::fs::write(path, svg(left.width + right.width, left.height, &body))
    }
}

/// An SVG document of `width` x `height` px on white with `body`.
impl Figure {
    /// The colour ramp's scale from 0 to `top` above the plot area, seven ticks.
    pub(crate) fn colour_scale(&mut self, top: f64) {
        let (left, t, w, _) = self.area;
        for k in 0..=6 {
            let v = top * k as f64 / 6.0;
            let x = left + w * k as f64 / 6.0;
            self.cell_px(x - 12.0, t - 14.0, 24.0, 8.0, &ramp(v / top));
            self.text(x, t - 2.0, 9.0, "middle", &format!("{v:.0}"));
        }
    }

    pub(crate) fn cell_px(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str) {
        let _ = writeln!(
            self.body,
            r#"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="{fill}"/>"#
        );
    }
}

/// An SVG document of `width` x `height` pixels around `body`.
fn svg(width: f64, height: f64, body: &str) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{body}</svg>\n"
    )
}

/// A tick label in metres: whole numbers, no -0.
pub(crate) fn metres(v: f64) -> String {
    // Ticks that land a rounding error below zero print as 0, not -0.
    let v = if v.abs() < 1e-9 { 0.0 } else { v };
    format!("{v:.0}")
}

/// A colour for a value in [0, 1]: dark blue through green to yellow.
pub(crate) fn ramp(t: f64) -> String {
    let t = t.clamp(0.0, 1.0);
    let stops = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let f = t * (stops.len() - 1) as f64;
    let i = (f.floor() as usize).min(stops.len() - 2);
    let u = f - i as f64;
    let (a, b) = (stops[i], stops[i + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * u).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}
