//! Curves and markers in a [`Panel`].

use std::fmt::Write;

use super::axes::Panel;
use super::escape::escape;
use super::palette::dash_attribute;

/// How a line is stroked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineStyle<'a> {
    /// Stroke colour (`#rrggbb`).
    pub colour: &'a str,
    /// Stroke width, px.
    pub width: f64,
    /// `stroke-dasharray`, `None` for a solid line.
    pub dash: Option<&'a str>,
}

/// The path data of one curve (`M x y L x y …`, px) through data `points`;
/// non-finite values break the curve (no `NaN` in the output).
pub fn path_data(panel: &Panel, points: impl Iterator<Item = (f64, f64)>) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for (x, y) in points {
        if !(x.is_finite() && y.is_finite()) {
            pen_down = false;
            continue;
        }
        let _ = write!(
            d,
            "{}{:.2} {:.2} ",
            if pen_down { "L" } else { "M" },
            panel.x(x),
            panel.y(y)
        );
        pen_down = true;
    }
    d.trim_end().to_string()
}

/// Appends one curve through data `points` as
/// `<path class="curve" data-KEY="VALUE"… d="…">` in `style`; `data` names it for
/// tests and tools (values escaped here).
pub fn curve(
    svg: &mut String,
    panel: &Panel,
    data: &[(&str, &str)],
    style: &LineStyle,
    points: impl Iterator<Item = (f64, f64)>,
) {
    let mut attributes = String::new();
    for (key, value) in data {
        let _ = write!(attributes, " data-{key}=\"{}\"", escape(value));
    }
    let _ = writeln!(
        svg,
        "<path class=\"curve\"{attributes} d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\"{}/>",
        path_data(panel, points),
        style.colour,
        style.width,
        dash_attribute(style.dash)
    );
}

/// SVG path data of a diamond marker of half-diagonal `size` centred at (`x`, `y`),
/// px.
pub fn diamond(x: f64, y: f64, size: f64) -> String {
    format!(
        "M{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z",
        x,
        y - size,
        x + size,
        y,
        x,
        y + size,
        x - size,
        y
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel() -> Panel {
        Panel {
            left: 0.0,
            right: 100.0,
            top: 0.0,
            height: 100.0,
            x_min: 0.0,
            x_max: 1.0,
            y_min: 0.0,
            y_max: 1.0,
        }
    }

    #[test]
    fn non_finite_values_break_the_curve() {
        let d = path_data(
            &panel(),
            [(0.0, 0.0), (0.5, f64::NAN), (0.6, 1.0), (1.0, 0.5)].into_iter(),
        );
        assert_eq!(d, "M0.00 100.00 M60.00 0.00 L100.00 50.00");
    }

    #[test]
    fn a_curve_carries_its_data_attributes_and_dash() {
        let mut svg = String::new();
        let style = LineStyle {
            colour: "#0072b2",
            width: 1.5,
            dash: Some("8 5"),
        };
        curve(
            &mut svg,
            &panel(),
            &[("rod", "a&b")],
            &style,
            [(0.0, 0.0), (1.0, 1.0)].into_iter(),
        );
        assert!(svg.contains("data-rod=\"a&amp;b\""), "{svg}");
        assert!(svg.contains("stroke-dasharray=\"8 5\""), "{svg}");
        assert!(svg.contains("d=\"M0.00 100.00 L100.00 0.00\""), "{svg}");
    }
}
