//! A vertical viridis colour bar (a legend for lines coloured by a quantity).

use std::fmt::Write;

use super::palette::viridis;

/// Number of bands of a colour bar.
const BANDS: usize = 24;

/// Draws a bar `width` × `height` px at (`x`, `top`), viridis from 0 at the bottom to
/// 1 at the top, as `<g class="colour-bar">` (labels are the caller's: they differ
/// per quantity and the 3D view's script changes them).
pub fn colour_bar(svg: &mut String, x: f64, top: f64, width: f64, height: f64) {
    let h = height / BANDS as f64;
    let _ = writeln!(svg, "<g class=\"colour-bar\">");
    for i in 0..BANDS {
        let t = (i as f64 + 0.5) / BANDS as f64;
        let _ = writeln!(
            svg,
            "<rect x=\"{x:.1}\" y=\"{:.2}\" width=\"{width}\" height=\"{:.2}\" fill=\"{}\"/>",
            top + height - (i + 1) as f64 * h,
            h + 0.3,
            viridis(t)
        );
    }
    let _ = writeln!(svg, "</g>");
}
