//! A plot panel: a data rectangle mapped to pixels, with its frame, grid, tick labels,
//! axis titles and title.

use std::fmt::Write;

use super::escape::escape;
use super::ticks::axis_label;

/// Colour of grid lines.
const GRID: &str = "#e3e3e3";
/// Colour of the frame and of the zero line.
const FRAME: &str = "#333333";

/// One panel: the data rectangle `[x_min, x_max] × [y_min, y_max]` drawn at
/// `left..right`, `top..top + height` (px; y grows downwards on screen).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Left edge, px.
    pub left: f64,
    /// Right edge, px.
    pub right: f64,
    /// Top edge, px.
    pub top: f64,
    /// Height, px.
    pub height: f64,
    /// Data value at the left edge.
    pub x_min: f64,
    /// Data value at the right edge.
    pub x_max: f64,
    /// Data value at the bottom edge.
    pub y_min: f64,
    /// Data value at the top edge.
    pub y_max: f64,
}

impl Panel {
    /// The screen x (px) of data value `value`.
    pub fn x(&self, value: f64) -> f64 {
        self.left + (self.right - self.left) * (value - self.x_min) / (self.x_max - self.x_min)
    }

    /// The screen y (px) of data value `value`.
    pub fn y(&self, value: f64) -> f64 {
        self.top + self.height * (self.y_max - value) / (self.y_max - self.y_min)
    }

    /// The bottom edge, px.
    pub fn bottom(&self) -> f64 {
        self.top + self.height
    }

    /// Draws the grid and tick labels every `x_step` / `y_step` (from `x_min` /
    /// `y_min`), the frame, the axis titles `x_label` (below) and `y_label` (rotated,
    /// left) and `title` (bold, above; none if empty), as one `<g class="axes">`. Tick
    /// labels are `<text class="x-tick">` / `"y-tick"`, the titles `"x-title"` /
    /// `"y-title"`.
    pub fn draw_axes(
        &self,
        svg: &mut String,
        x_step: f64,
        y_step: f64,
        x_label: &str,
        y_label: &str,
        title: &str,
    ) {
        let bottom = self.bottom();
        let (left, right, height) = (self.left, self.right, self.height);
        let _ = writeln!(svg, "<g class=\"axes\">");
        let count = |min: f64, max: f64, step: f64| ((max - min) / step + 1e-9).floor() as usize;
        for i in 0..=count(self.x_min, self.x_max, x_step) {
            let v = self.x_min + i as f64 * x_step;
            let x = self.x(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x:.2}\" y1=\"{:.2}\" x2=\"{x:.2}\" y2=\"{bottom:.2}\" stroke=\"{GRID}\" stroke-width=\"1\"/>",
                self.top
            );
            let _ = writeln!(
                svg,
                "<text class=\"x-tick\" x=\"{x:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
                bottom + 17.0,
                axis_label(v, x_step)
            );
        }
        for i in 0..=count(self.y_min, self.y_max, y_step) {
            let v = self.y_min + i as f64 * y_step;
            let y = self.y(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{left:.2}\" y1=\"{y:.2}\" x2=\"{right:.2}\" y2=\"{y:.2}\" stroke=\"{GRID}\" stroke-width=\"1\"/>"
            );
            let _ = writeln!(
                svg,
                "<text class=\"y-tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
                left - 7.0,
                y + 4.0,
                axis_label(v, y_step)
            );
        }
        let _ = writeln!(
            svg,
            "<rect x=\"{left:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{height:.2}\" fill=\"none\" stroke=\"{FRAME}\" stroke-width=\"1\"/>",
            self.top,
            right - left
        );
        let _ = writeln!(
            svg,
            "<text class=\"x-title\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            0.5 * (left + right),
            bottom + 38.0,
            escape(x_label)
        );
        let (cx, cy) = (left - 52.0, self.top + 0.5 * height);
        let _ = writeln!(
            svg,
            "<text class=\"y-title\" x=\"{cx:.2}\" y=\"{cy:.2}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx:.2} {cy:.2})\">{}</text>",
            escape(y_label)
        );
        if !title.is_empty() {
            let _ = writeln!(
                svg,
                "<text class=\"panel-title\" x=\"{left:.2}\" y=\"{:.2}\" font-weight=\"bold\">{}</text>",
                self.top - 8.0,
                escape(title)
            );
        }
        let _ = writeln!(svg, "</g>");
    }

    /// A horizontal line at `y = 0` when zero lies strictly inside the panel (signed
    /// quantities).
    pub fn draw_zero_line(&self, svg: &mut String) {
        if self.y_min < 0.0 && self.y_max > 0.0 {
            let y0 = self.y(0.0);
            let _ = writeln!(
                svg,
                "<line class=\"zero\" x1=\"{:.2}\" y1=\"{y0:.2}\" x2=\"{:.2}\" y2=\"{y0:.2}\" stroke=\"#888888\" stroke-width=\"1\"/>",
                self.left, self.right
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_maps_to_the_rectangle_and_ticks_land_on_the_grid() {
        let panel = Panel {
            left: 100.0,
            right: 300.0,
            top: 50.0,
            height: 100.0,
            x_min: -10.0,
            x_max: 10.0,
            y_min: 0.0,
            y_max: 4.0,
        };
        assert_eq!(panel.x(-10.0), 100.0);
        assert_eq!(panel.x(0.0), 200.0);
        assert_eq!(panel.y(0.0), 150.0);
        assert_eq!(panel.y(4.0), 50.0);
        let mut svg = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\">");
        panel.draw_axes(&mut svg, 5.0, 1.0, "x [mm] <", "y", "");
        svg.push_str("</svg>");
        let xml = roxmltree::Document::parse(&svg).unwrap();
        let texts = |class: &str| -> Vec<(f64, String)> {
            xml.descendants()
                .filter(|n| n.attribute("class") == Some(class))
                .map(|n| {
                    (
                        n.attribute("x").unwrap().parse().unwrap(),
                        n.text().unwrap().into(),
                    )
                })
                .collect()
        };
        let x_ticks = texts("x-tick");
        assert_eq!(
            x_ticks.iter().map(|t| t.1.as_str()).collect::<Vec<_>>(),
            ["-10", "-5", "0", "5", "10"]
        );
        for (x, label) in &x_ticks {
            let value: f64 = label.parse().unwrap();
            assert!((x - panel.x(value)).abs() < 0.01);
        }
        assert_eq!(texts("y-tick").len(), 5);
        assert_eq!(texts("x-title")[0].1, "x [mm] <");
        assert!(texts("panel-title").is_empty());
    }
}
