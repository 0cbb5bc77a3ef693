//! The study plot (`study.svg`), written by hand as plain SVG 1.1: two stacked panels,
//! the internal force magnitude `|f̄|` [N] and the internal moment magnitude `|m|`
//! [N·m] against arc length, one colour per rod, the first variant solid and the
//! others dashed, with a legend. The file is self-contained (no scripts, external
//! fonts, images or links; text uses the generic `sans-serif` family).
//!
//! Every curve is one `<path class="curve">` with `data-panel` (`force` or `moment`),
//! `data-rod` and `data-variant` attributes, so tests and tools can find them.

use std::fmt::Write;

use crate::study::{ArcOrigin, StudyRun, arc, magnitude, origin_of};

const WIDTH: f64 = 900.0;
const LEFT: f64 = 84.0;
const PLOT_RIGHT: f64 = 680.0;
const LEGEND_X: f64 = 704.0;
const TOP: f64 = 58.0;
const PANEL_HEIGHT: f64 = 240.0;
const PANEL_GAP: f64 = 78.0;
const HEIGHT: f64 = TOP + 2.0 * PANEL_HEIGHT + PANEL_GAP + 64.0;

/// One colour per rod (colour-blind safe, [`crate::palette`]), reused cyclically.
pub(crate) const COLOURS: [&str; 7] = crate::palette::LINE_COLOURS;
/// Dash patterns of the variants after the first (which is solid), reused cyclically.
/// The `stroke-dasharray` of variant `k` (`None`: solid; see
/// [`crate::palette::dash_pattern`]).
pub(crate) fn dash(k: usize) -> Option<&'static str> {
    crate::palette::dash_pattern(k)
}

/// `text` escaped for XML character data and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// A "nice" tick step (1, 2 or 5 × 10^k) for about five intervals up to `max`, and the
/// axis top (the first tick at or above `max`).
pub(crate) fn ticks(max: f64) -> (f64, f64) {
    let max = if max.is_finite() && max > 0.0 {
        max
    } else {
        1.0
    };
    let raw = max / 5.0;
    let power = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|s| *s >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * power);
    let top = (max / step - 1e-9).ceil().max(1.0) * step;
    (step, top)
}

/// A tick label: as few decimals as the step needs.
pub(crate) fn tick_label(value: f64, step: f64) -> String {
    let exponent = step.log10().floor();
    // A step of 2.5 × 10^k needs one decimal more than 1, 2 or 5 × 10^k.
    let quarter = f64::from(u8::from((step / 10f64.powf(exponent) - 2.5).abs() < 1e-9));
    let decimals = (quarter - exponent).max(0.0) as usize;
    let text = format!("{value:.decimals$}");
    if text.starts_with('-') && text.trim_start_matches(['-', '0', '.']).is_empty() {
        text[1..].to_string()
    } else {
        text
    }
}

/// A nice tick step (1, 2, 2.5 or 5 × 10^k) for about five intervals over `[min, max]`
/// and the axis range `(step, low, high)` rounded outwards to whole steps, without
/// forcing zero in (for an axis of parameter values); a single value gets one step on
/// either side.
pub fn axis_ticks(min: f64, max: f64) -> (f64, f64, f64) {
    let (min, max) = if min.is_finite() && max.is_finite() && min <= max {
        (min, max)
    } else {
        (0.0, 1.0)
    };
    let span = if max > min {
        max - min
    } else {
        min.abs().max(1.0)
    };
    let (step, _) = ticks(span);
    let low = (min / step + 1e-9).floor() * step;
    let high = ((max / step - 1e-9).ceil() * step).max(low + step);
    if max > min {
        (step, low, high)
    } else {
        (step, low - step, high.max(low + step))
    }
}

/// A tick label of `value` on an axis of `step`: as few decimals as the step needs
/// (`4.5`, `10`, `0.25`; never `-0`).
pub fn axis_label(value: f64, step: f64) -> String {
    tick_label(value, step)
}

/// A nice tick step for about five intervals over `[min, max]` and the axis range
/// `(step, low, high)` rounded outwards to whole steps; `[0, max]` gives [`ticks`].
pub(crate) fn tick_range(min: f64, max: f64) -> (f64, f64, f64) {
    let (min, max) = (min.min(0.0), max.max(0.0));
    let (min, max) = if min.is_finite() && max.is_finite() {
        (min, max)
    } else {
        (0.0, 1.0)
    };
    let (step, _) = ticks(max - min);
    let low = (min / step + 1e-9).floor() * step;
    let high = ((max / step - 1e-9).ceil() * step).max(low + step);
    (step, low, high)
}

/// One panel's frame, grid, ticks and labels: the data rectangle
/// `[x_min, x_max] × [y_min, y_max]` drawn at `left..right`, `top..top + height` (px).
pub(crate) struct Panel {
    pub(crate) left: f64,
    pub(crate) right: f64,
    pub(crate) top: f64,
    pub(crate) height: f64,
    pub(crate) x_min: f64,
    pub(crate) x_max: f64,
    pub(crate) y_min: f64,
    pub(crate) y_max: f64,
}

impl Panel {
    /// A study panel: the fixed study geometry, axes from 0.
    fn study(top: f64, x_max: f64, y_max: f64) -> Self {
        Panel {
            left: LEFT,
            right: PLOT_RIGHT,
            top,
            height: PANEL_HEIGHT,
            x_min: 0.0,
            x_max,
            y_min: 0.0,
            y_max,
        }
    }

    pub(crate) fn x(&self, value: f64) -> f64 {
        self.left + (self.right - self.left) * (value - self.x_min) / (self.x_max - self.x_min)
    }

    pub(crate) fn y(&self, value: f64) -> f64 {
        self.top + self.height * (self.y_max - value) / (self.y_max - self.y_min)
    }

    pub(crate) fn draw_axes(
        &self,
        svg: &mut String,
        x_step: f64,
        y_step: f64,
        x_label: &str,
        y_label: &str,
        title: &str,
    ) {
        let bottom = self.top + self.height;
        let (left, right, height) = (self.left, self.right, self.height);
        let _ = writeln!(svg, "<g class=\"axes\">");
        // Grid and ticks.
        let count = |min: f64, max: f64, step: f64| ((max - min) / step + 1e-9).floor() as usize;
        for i in 0..=count(self.x_min, self.x_max, x_step) {
            let v = self.x_min + i as f64 * x_step;
            let x = self.x(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x:.2}\" y1=\"{:.2}\" x2=\"{x:.2}\" y2=\"{bottom:.2}\" stroke=\"#e3e3e3\" stroke-width=\"1\"/>",
                self.top
            );
            let _ = writeln!(
                svg,
                "<text x=\"{x:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
                bottom + 17.0,
                tick_label(v, x_step)
            );
        }
        for i in 0..=count(self.y_min, self.y_max, y_step) {
            let v = self.y_min + i as f64 * y_step;
            let y = self.y(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{left:.2}\" y1=\"{y:.2}\" x2=\"{right:.2}\" y2=\"{y:.2}\" stroke=\"#e3e3e3\" stroke-width=\"1\"/>"
            );
            let _ = writeln!(
                svg,
                "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
                left - 7.0,
                y + 4.0,
                tick_label(v, y_step)
            );
        }
        let _ = writeln!(
            svg,
            "<rect x=\"{left:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{height:.2}\" fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>",
            self.top,
            right - left
        );
        let _ = writeln!(
            svg,
            "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            0.5 * (left + right),
            bottom + 38.0,
            escape(x_label)
        );
        let (cx, cy) = (left - 50.0, self.top + 0.5 * height);
        let _ = writeln!(
            svg,
            "<text x=\"{cx:.2}\" y=\"{cy:.2}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx:.2} {cy:.2})\">{}</text>",
            escape(y_label)
        );
        let _ = writeln!(
            svg,
            "<text x=\"{left:.2}\" y=\"{:.2}\" font-weight=\"bold\">{}</text>",
            self.top - 8.0,
            escape(title)
        );
        let _ = writeln!(svg, "</g>");
    }
}

/// The path data of one curve (`M x y L x y …`); non-finite values break the curve.
pub(crate) fn path_data(panel: &Panel, points: impl Iterator<Item = (f64, f64)>) -> String {
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

/// The study plot. `runs` are the variants (the first drawn solid), `origins[r]` the
/// arc-length origin of rod `r`, and arc length is shown in `length_unit` (its size in
/// m is `metres_per_unit`, e.g. `"mm"` and 0.001). `title` heads the figure.
pub fn study_svg(
    title: &str,
    runs: &[StudyRun],
    origins: &[ArcOrigin],
    length_unit: &str,
    metres_per_unit: f64,
) -> String {
    // Rods in order of first appearance (normally every variant has the same rods).
    let mut rods: Vec<&str> = Vec::new();
    for run in runs {
        for rod in &run.doc.rods {
            if !rods.contains(&rod.name.as_str()) {
                rods.push(&rod.name);
            }
        }
    }
    let finite_max = |values: &mut dyn Iterator<Item = f64>| {
        values.filter(|v| v.is_finite()).fold(0.0f64, f64::max)
    };
    let all_rods = || runs.iter().flat_map(|run| run.doc.rods.iter());
    let x_max = finite_max(&mut all_rods().map(|r| r.length_m / metres_per_unit));
    let f_max = finite_max(&mut all_rods().flat_map(|r| r.force_n.iter().map(magnitude)));
    let m_max = finite_max(&mut all_rods().flat_map(|r| r.moment_nm.iter().map(magnitude)));
    let (x_step, x_top) = ticks(x_max);
    let (f_step, f_top) = ticks(f_max);
    let (m_step, m_top) = ticks(m_max);
    let panels = [
        (
            "force",
            Panel::study(TOP, x_top, f_top),
            f_step,
            "|f| [N]",
            "internal force magnitude |f|",
        ),
        (
            "moment",
            Panel::study(TOP + PANEL_HEIGHT + PANEL_GAP, x_top, m_top),
            m_step,
            "|m| [N·m]",
            "internal moment magnitude |m|",
        ),
    ];
    let any_from_end = origins.contains(&ArcOrigin::End);
    let x_label = if any_from_end {
        format!("arc length s [{length_unit}] (from the start unless marked ← end)")
    } else {
        format!("arc length s [{length_unit}]")
    };

    let mut svg = String::with_capacity(4096 + 64 * 1024 * runs.len());
    let _ = writeln!(svg, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    let _ = writeln!(svg, "<title>{}</title>", escape(title));
    let _ = writeln!(
        svg,
        "<rect x=\"0\" y=\"0\" width=\"{WIDTH}\" height=\"{HEIGHT}\" fill=\"#ffffff\"/>"
    );
    let _ = writeln!(
        svg,
        "<text x=\"{LEFT:.2}\" y=\"20\" font-size=\"14\" font-weight=\"bold\">{}</text>",
        escape(title)
    );
    for (kind, panel, y_step, y_label, panel_title) in &panels {
        panel.draw_axes(&mut svg, x_step, *y_step, &x_label, y_label, panel_title);
        let _ = writeln!(svg, "<g class=\"curves\" data-panel=\"{kind}\">");
        for (k, run) in runs.iter().enumerate() {
            for (r, rod) in run.doc.rods.iter().enumerate() {
                let origin = origin_of(origins, r);
                let colour =
                    COLOURS[rods.iter().position(|n| *n == rod.name).unwrap_or(0) % COLOURS.len()];
                let values = if *kind == "force" {
                    &rod.force_n
                } else {
                    &rod.moment_nm
                };
                let points = values
                    .iter()
                    .enumerate()
                    .map(|(j, v)| (arc(rod, origin, j) / metres_per_unit, magnitude(v)));
                let dash_attr = dash(k)
                    .map(|d| format!(" stroke-dasharray=\"{d}\""))
                    .unwrap_or_default();
                let _ = writeln!(
                    svg,
                    "<path class=\"curve\" data-panel=\"{kind}\" data-rod=\"{}\" data-variant=\"{}\" d=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.8\" stroke-linejoin=\"round\"{dash_attr}/>",
                    escape(&rod.name),
                    escape(run.variant),
                    path_data(panel, points)
                );
            }
        }
        let _ = writeln!(svg, "</g>");
    }

    // Legend: rods by colour, variants by line style.
    let _ = writeln!(svg, "<g class=\"legend\">");
    let mut y = TOP + 4.0;
    let _ = writeln!(
        svg,
        "<text x=\"{LEGEND_X:.2}\" y=\"{y:.2}\" font-weight=\"bold\">rods</text>"
    );
    for (i, name) in rods.iter().enumerate() {
        y += 20.0;
        let from_end = origins.get(i) == Some(&ArcOrigin::End);
        let _ = writeln!(
            svg,
            "<line x1=\"{LEGEND_X:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"3\"/>",
            y - 4.0,
            LEGEND_X + 28.0,
            y - 4.0,
            COLOURS[i % COLOURS.len()]
        );
        let _ = writeln!(
            svg,
            "<text x=\"{:.2}\" y=\"{y:.2}\">{}{}</text>",
            LEGEND_X + 36.0,
            escape(name),
            if from_end { " (s ← end)" } else { "" }
        );
    }
    y += 34.0;
    let _ = writeln!(
        svg,
        "<text x=\"{LEGEND_X:.2}\" y=\"{y:.2}\" font-weight=\"bold\">variants</text>"
    );
    for (k, run) in runs.iter().enumerate() {
        y += 20.0;
        let dash_attr = dash(k)
            .map(|d| format!(" stroke-dasharray=\"{d}\""))
            .unwrap_or_default();
        let _ = writeln!(
            svg,
            "<line x1=\"{LEGEND_X:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"#333333\" stroke-width=\"1.8\"{dash_attr}/>",
            y - 4.0,
            LEGEND_X + 28.0,
            y - 4.0
        );
        let _ = writeln!(
            svg,
            "<text x=\"{:.2}\" y=\"{y:.2}\">{}{}</text>",
            LEGEND_X + 36.0,
            escape(run.variant),
            if k == 0 { " (reference)" } else { "" }
        );
    }
    let _ = writeln!(svg, "</g>");
    let _ = writeln!(svg, "</svg>");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_cover_the_maximum() {
        assert_eq!(ticks(400.0), (100.0, 400.0));
        assert_eq!(ticks(450.0), (100.0, 500.0));
        assert_eq!(ticks(0.0), (0.2, 1.0));
        let (step, top) = ticks(0.0734);
        assert!(
            (step - 0.02).abs() < 1e-15 && (top - 0.08).abs() < 1e-12,
            "{step} {top}"
        );
        let (step, top) = ticks(11.3);
        assert_eq!((step, top), (2.5, 12.5));
        assert_eq!(tick_label(12.5, 2.5), "12.5");
        assert_eq!(tick_label(0.06, 0.02), "0.06");
        assert_eq!(tick_label(300.0, 100.0), "300");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}

#[cfg(test)]
mod plot_tests {
    use super::*;
    use crate::study::tests::doc;

    #[test]
    fn the_plot_is_well_formed_with_one_path_per_rod_per_variant_and_panel() {
        let (base, longer) = (doc(1.0), doc(1.5));
        let runs = [
            StudyRun {
                variant: "base",
                doc: &base,
            },
            StudyRun {
                variant: "long&er",
                doc: &longer,
            },
        ];
        let svg = study_svg("sample <study>", &runs, &[ArcOrigin::Start], "mm", 1e-3);
        let xml = roxmltree::Document::parse(&svg).expect("well-formed XML");
        let root = xml.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(
            root.tag_name().namespace(),
            Some("http://www.w3.org/2000/svg")
        );
        let curves: Vec<_> = xml
            .descendants()
            .filter(|n| n.has_tag_name("path") && n.attribute("class") == Some("curve"))
            .collect();
        assert_eq!(curves.len(), 2 * 2 * 2);
        for panel in ["force", "moment"] {
            for variant in ["base", "long&er"] {
                for rod in ["rod", "other"] {
                    let found: Vec<_> = curves
                        .iter()
                        .filter(|n| {
                            n.attribute("data-panel") == Some(panel)
                                && n.attribute("data-variant") == Some(variant)
                                && n.attribute("data-rod") == Some(rod)
                        })
                        .collect();
                    assert_eq!(found.len(), 1, "{panel} {variant} {rod}");
                    let d = found[0].attribute("d").unwrap();
                    assert_eq!(d.matches('M').count(), 1);
                    assert_eq!(d.matches('L').count(), 2, "3 vertices: {d}");
                    let solid = variant == "base";
                    assert_eq!(found[0].attribute("stroke-dasharray").is_none(), solid);
                }
            }
        }
        // Same colour for the same rod in both variants, different rods differ.
        let colour = |rod: &str, variant: &str| {
            curves
                .iter()
                .find(|n| {
                    n.attribute("data-rod") == Some(rod)
                        && n.attribute("data-variant") == Some(variant)
                })
                .and_then(|n| n.attribute("stroke"))
                .unwrap()
        };
        assert_eq!(colour("rod", "base"), colour("rod", "long&er"));
        assert_ne!(colour("rod", "base"), colour("other", "base"));
        // Axis labels with units, a legend, and nothing external.
        let text: String = xml
            .descendants()
            .filter(|n| n.is_text())
            .filter_map(|n| n.text())
            .collect::<Vec<_>>()
            .join("|");
        for needle in [
            "arc length s [mm]",
            "|f| [N]",
            "|m| [N·m]",
            "long&er",
            "sample <study>",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        assert!(!svg.contains("href") && !svg.contains("url(") && !svg.contains("@import"));
    }

    #[test]
    fn non_finite_values_break_the_curve() {
        let mut bad = doc(1.0);
        bad.rods[0].force_n[1] = [f64::NAN, 0.0, 0.0];
        let runs = [StudyRun {
            variant: "base",
            doc: &bad,
        }];
        let svg = study_svg("t", &runs, &[], "m", 1.0);
        roxmltree::Document::parse(&svg).expect("well-formed XML");
        assert!(!svg.contains("NaN"));
    }
}
