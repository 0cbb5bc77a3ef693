//! A legend: a column of entries (line samples with their dash, markers, headings)
//! that grows downwards from where it starts.

use std::fmt::Write;

use super::escape::escape;
use super::palette::dash_attribute;
use super::series::LineStyle;

/// Length of a line sample, px.
const SAMPLE: f64 = 28.0;
/// Gap between the sample and its label, px.
const LABEL_GAP: f64 = 8.0;

/// A legend column at `x` whose next entry's text baseline is `y` (px).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Legend {
    /// Left edge, px.
    pub x: f64,
    /// Text baseline of the next entry, px.
    pub y: f64,
    /// Vertical distance between entries, px.
    pub row: f64,
}

impl Legend {
    /// A legend at `x` with its first baseline at `y`, rows 20 px apart.
    pub fn new(x: f64, y: f64) -> Self {
        Legend { x, y, row: 20.0 }
    }

    /// Leaves `px` of space.
    pub fn skip(&mut self, px: f64) {
        self.y += px;
    }

    /// Moves the next entry down to `y` if it is above it.
    pub fn at_least(&mut self, y: f64) {
        self.y = self.y.max(y);
    }

    /// A bold heading.
    pub fn heading(&mut self, svg: &mut String, text: &str) {
        let _ = writeln!(
            svg,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-weight=\"bold\">{}</text>",
            self.x,
            self.y,
            escape(text)
        );
        self.y += self.row;
    }

    /// A line sample in `style` labelled `label`; `class` marks the sample (e.g.
    /// `"slice"`) for tests and tools.
    pub fn line(&mut self, svg: &mut String, style: &LineStyle, label: &str, class: Option<&str>) {
        let y = self.y - 4.0;
        let _ = writeln!(
            svg,
            "<line{} x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"{}\" stroke-width=\"{}\"{}/><text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            class.map_or(String::new(), |c| format!(" class=\"{c}\"")),
            self.x,
            self.x + SAMPLE,
            style.colour,
            style.width,
            dash_attribute(style.dash),
            self.x + SAMPLE + LABEL_GAP,
            self.y,
            escape(label)
        );
        self.y += self.row;
    }

    /// A filled marker (SVG path data from `shape(centre_x, centre_y)`) labelled
    /// `label`.
    pub fn marker(
        &mut self,
        svg: &mut String,
        shape: impl Fn(f64, f64) -> String,
        colour: &str,
        label: &str,
    ) {
        let _ = writeln!(
            svg,
            "<path d=\"{}\" fill=\"{colour}\"/><text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            shape(self.x + 0.5 * SAMPLE, self.y - 4.0),
            self.x + SAMPLE + LABEL_GAP,
            self.y,
            escape(label)
        );
        self.y += self.row;
    }

    /// A line of text in `colour` with `class`.
    pub fn note(&mut self, svg: &mut String, text: &str, colour: &str, class: &str) {
        let _ = writeln!(
            svg,
            "<text class=\"{class}\" x=\"{:.1}\" y=\"{:.1}\" fill=\"{colour}\">{}</text>",
            self.x,
            self.y,
            escape(text)
        );
        self.y += self.row;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_stack_downwards_with_escaped_labels() {
        let mut svg = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\">");
        let mut legend = Legend::new(10.0, 20.0);
        legend.heading(&mut svg, "rods");
        let style = LineStyle {
            colour: "#000000",
            width: 2.0,
            dash: Some("2 4"),
        };
        legend.line(&mut svg, &style, "a<b", Some("slice"));
        legend.marker(
            &mut svg,
            |x, y| crate::plot::diamond(x, y, 5.0),
            "#d55e00",
            "contact",
        );
        svg.push_str("</svg>");
        assert_eq!(legend.y, 80.0);
        let xml = roxmltree::Document::parse(&svg).unwrap();
        let texts: Vec<(&str, f64)> = xml
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .map(|n| {
                (
                    n.text().unwrap(),
                    n.attribute("y").unwrap().parse().unwrap(),
                )
            })
            .collect();
        assert_eq!(texts, [("rods", 20.0), ("a<b", 40.0), ("contact", 60.0)]);
        let sample = xml
            .descendants()
            .find(|n| n.attribute("class") == Some("slice"))
            .unwrap();
        assert_eq!(sample.attribute("stroke-dasharray"), Some("2 4"));
    }
}
