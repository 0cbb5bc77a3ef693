//! The study plot (`study.svg`), drawn with [`crate::plot`]: two stacked panels, the
//! internal force magnitude `|f̄|` [N] and the internal moment magnitude `|m|` [N·m]
//! against arc length, one colour per rod, the first variant solid and the others
//! dashed, with a legend. The file is self-contained (no scripts, external fonts,
//! images or links; text uses the generic `sans-serif` family).
//!
//! Every curve is one `<path class="curve">` with `data-panel` (`force` or `moment`),
//! `data-rod` and `data-variant` attributes, so tests and tools can find them.

use std::fmt::Write;

use crate::plot::{
    Figure, Layout, Legend, LineStyle, WIDE, close_figure, curve, dash_pattern, line_colour,
    open_figure, ticks,
};
use crate::study::{ArcOrigin, StudyRun, arc, magnitude, origin_of};

/// Two panels (force over moment), the legend at the right.
const LAYOUT: Layout = WIDE;

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
            LAYOUT.panel(0, [0.0, x_top], [0.0, f_top]),
            f_step,
            "|f| [N]",
            "internal force magnitude |f|",
        ),
        (
            "moment",
            LAYOUT.panel(1, [0.0, x_top], [0.0, m_top]),
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
    let figure = Figure::new(LAYOUT.width, LAYOUT.height(2), title)
        .class("study")
        .standalone();
    open_figure(&mut svg, &figure);
    for (kind, panel, y_step, y_label, panel_title) in &panels {
        panel.draw_axes(&mut svg, x_step, *y_step, &x_label, y_label, panel_title);
        let _ = writeln!(svg, "<g class=\"curves\" data-panel=\"{kind}\">");
        for (k, run) in runs.iter().enumerate() {
            for (r, rod) in run.doc.rods.iter().enumerate() {
                let origin = origin_of(origins, r);
                let colour = line_colour(rods.iter().position(|n| *n == rod.name).unwrap_or(0));
                let values = if *kind == "force" {
                    &rod.force_n
                } else {
                    &rod.moment_nm
                };
                let points = values
                    .iter()
                    .enumerate()
                    .map(|(j, v)| (arc(rod, origin, j) / metres_per_unit, magnitude(v)));
                let style = LineStyle {
                    colour,
                    width: 1.8,
                    dash: dash_pattern(k),
                };
                curve(
                    &mut svg,
                    panel,
                    &[
                        ("panel", kind),
                        ("rod", &rod.name),
                        ("variant", run.variant),
                    ],
                    &style,
                    points,
                );
            }
        }
        let _ = writeln!(svg, "</g>");
    }

    // Legend: rods by colour, variants by line style.
    let _ = writeln!(svg, "<g class=\"legend\">");
    let mut legend = Legend::new(LAYOUT.legend_x, LAYOUT.top + 4.0);
    legend.heading(&mut svg, "rods");
    for (i, name) in rods.iter().enumerate() {
        let from_end = origins.get(i) == Some(&ArcOrigin::End);
        let style = LineStyle {
            colour: line_colour(i),
            width: 3.0,
            dash: None,
        };
        let label = format!("{name}{}", if from_end { " (s ← end)" } else { "" });
        legend.line(&mut svg, &style, &label, None);
    }
    legend.skip(14.0);
    legend.heading(&mut svg, "variants");
    for (k, run) in runs.iter().enumerate() {
        let style = LineStyle {
            colour: "#333333",
            width: 1.8,
            dash: dash_pattern(k),
        };
        let label = format!(
            "{}{}",
            run.variant,
            if k == 0 { " (reference)" } else { "" }
        );
        legend.line(&mut svg, &style, &label, None);
    }
    let _ = writeln!(svg, "</g>");
    close_figure(&mut svg);
    svg
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
