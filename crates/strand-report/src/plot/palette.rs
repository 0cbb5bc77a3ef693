//! The colours of every plot. Lines (study, batch summary, motion, report plots): the
//! Okabe–Ito palette for colour-blind viewers, without its yellow (too faint on white).
//! Every pair stays distinguishable under deuteranopia: the tests simulate it
//! (Machado, Oliveira & Fernandes 2009, severity 1, on linear sRGB) and require a CIE
//! 1976 colour difference ΔE*ab of at least [`MIN_DEUTERANOPIA_DELTA_E`] between any
//! two colours as a deuteranope sees them.

/// Line colours, in order of use (`#rrggbb`): blue, orange, bluish green, reddish
/// purple, sky blue, vermillion, black.
pub const LINE_COLOURS: [&str; 7] = [
    "#0072b2", "#e69f00", "#009e73", "#cc79a7", "#56b4e9", "#d55e00", "#000000",
];

/// Smallest ΔE*ab between two line colours as seen under simulated deuteranopia.
pub const MIN_DEUTERANOPIA_DELTA_E: f64 = 15.0;

/// Dash patterns (`stroke-dasharray`) that tell apart lines of one colour (variants,
/// slices of a grid), after the first, solid one: sixteen lines of one colour are all
/// different (a study of eleven variants used to repeat its dashes from the seventh);
/// reused cyclically beyond.
pub const DASH_PATTERNS: [&str; 15] = [
    "8 5",
    "2 4",
    "12 4 2 4",
    "4 4",
    "16 6",
    "12 4 2 4 2 4",
    "1 3",
    "20 4 4 4",
    "6 2",
    "10 3 2 3 2 3 2 3",
    "3 6",
    "24 6 2 6",
    "8 3 8 8",
    "14 3 3 3 3 3",
    "5 10",
];

/// The dash pattern of line `k` of one colour: `None` (solid) for the first.
pub fn dash_pattern(k: usize) -> Option<&'static str> {
    (k > 0).then(|| DASH_PATTERNS[(k - 1) % DASH_PATTERNS.len()])
}

/// The colour of line `k` (cyclic).
pub fn line_colour(k: usize) -> &'static str {
    LINE_COLOURS[k % LINE_COLOURS.len()]
}

/// The ` stroke-dasharray="…"` attribute of `dash` (empty for a solid line).
pub fn dash_attribute(dash: Option<&str>) -> String {
    dash.map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""))
}

/// Colour of contact markers and force arrows (Okabe–Ito vermillion), in the plots and
/// the views.
pub const CONTACT_COLOUR: &str = "#d55e00";

/// Viridis at five stops (sRGB 0–255), interpolated linearly: the scale of lines
/// coloured by a quantity (perceptually ordered, readable in grey and under
/// colour-vision deficiencies).
pub const VIRIDIS: [[f64; 3]; 5] = [
    [68.0, 1.0, 84.0],
    [59.0, 82.0, 139.0],
    [33.0, 145.0, 140.0],
    [94.0, 201.0, 98.0],
    [253.0, 231.0, 37.0],
];

/// The viridis colour of `t` in [0, 1] (clamped; NaN is magenta) as `#rrggbb`.
pub fn viridis(t: f64) -> String {
    if t.is_nan() {
        return "#ff00ff".into();
    }
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c = [0, 1, 2].map(|k| (VIRIDIS[i][k] + f * (VIRIDIS[i + 1][k] - VIRIDIS[i][k])).round());
    format!("#{:02x}{:02x}{:02x}", c[0] as u8, c[1] as u8, c[2] as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_lines_of_one_colour_have_sixteen_different_dashes() {
        let dashes: Vec<Option<&str>> = (0..16).map(dash_pattern).collect();
        for (i, a) in dashes.iter().enumerate() {
            for b in &dashes[i + 1..] {
                assert_ne!(a, b);
            }
        }
        assert_eq!(dash_pattern(0), None);
        assert_eq!(dash_pattern(16), dash_pattern(1));
    }

    /// `#rrggbb` as linear sRGB in [0, 1].
    fn linear(hex: &str) -> [f64; 3] {
        let channel = |i: usize| {
            let c = f64::from(u8::from_str_radix(&hex[1 + 2 * i..3 + 2 * i], 16).unwrap()) / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        [channel(0), channel(1), channel(2)]
    }

    /// Deuteranopia, severity 1 (Machado et al. 2009), on linear sRGB, clamped.
    fn deuteranope(rgb: [f64; 3]) -> [f64; 3] {
        const M: [[f64; 3]; 3] = [
            [0.367322, 0.860646, -0.227968],
            [0.280085, 0.672501, 0.047413],
            [-0.011820, 0.042940, 0.968881],
        ];
        M.map(|row| (row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]).clamp(0.0, 1.0))
    }

    /// CIE L*a*b* (D65) of linear sRGB.
    fn lab(rgb: [f64; 3]) -> [f64; 3] {
        let [r, g, b] = rgb;
        let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
        let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
        let f = |t: f64| {
            if t > 0.008856 {
                t.cbrt()
            } else {
                7.787 * t + 16.0 / 116.0
            }
        };
        let (fx, fy, fz) = (f(x), f(y), f(z));
        [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
    }

    fn delta_e_deuteranope(a: &str, b: &str) -> f64 {
        let (p, q) = (lab(deuteranope(linear(a))), lab(deuteranope(linear(b))));
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    }

    #[test]
    fn every_pair_of_line_colours_is_distinct_under_deuteranopia() {
        let mut worst = f64::INFINITY;
        for (i, a) in LINE_COLOURS.iter().enumerate() {
            for b in &LINE_COLOURS[i + 1..] {
                let d = delta_e_deuteranope(a, b);
                assert!(d >= MIN_DEUTERANOPIA_DELTA_E, "{a} and {b}: ΔE {d:.1}");
                worst = worst.min(d);
            }
        }
        // The check has teeth: Tableau's red and green (the plots' hose 2 and 3
        // before) fall together for a deuteranope, and black and white do not.
        assert!(delta_e_deuteranope("#d62728", "#2ca02c") < 8.0);
        assert!(delta_e_deuteranope("#000000", "#ffffff") > 99.0);
        assert!(
            worst < 20.0,
            "the bound is near the palette's worst pair: {worst}"
        );
    }

    #[test]
    fn the_simulation_keeps_greys_and_blue_yellow_and_merges_red_green() {
        // Greys are unchanged (rows of the matrix sum to 1).
        for grey in ["#808080", "#ffffff", "#000000"] {
            let g = linear(grey);
            let d = deuteranope(g);
            assert!((0..3).all(|i| (d[i] - g[i]).abs() < 1e-5), "{grey}");
        }
        // Pure red and pure green land close in hue: their b* have the same sign and
        // a* nearly vanish, while blue and yellow stay far apart.
        let red = lab(deuteranope(linear("#ff0000")));
        let green = lab(deuteranope(linear("#00ff00")));
        assert!(
            red[1].abs() < 15.0 && green[1].abs() < 15.0,
            "{red:?} {green:?}"
        );
        assert!(red[2] > 0.0 && green[2] > 0.0);
        assert!(delta_e_deuteranope("#0000ff", "#ffff00") > 80.0);
    }
}
