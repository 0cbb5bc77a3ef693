//! Number formatting and HTML table building for the report.

use std::fmt::Write;

use crate::plot::escape;

/// `value` rounded to 4 significant digits: positional for magnitudes in
/// [1e-3, 1e6), exponent form (`1.235e-5`) otherwise; `0` for zero, `NaN`/`inf` for
/// non-finite values. The text parses back as an `f64`.
pub(crate) fn sig(value: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    if value == 0.0 {
        return "0".to_string();
    }
    let exponent = value.abs().log10().floor();
    let scale = 10f64.powf(exponent - 3.0);
    let rounded = (value / scale).round() * scale;
    let exponent = rounded.abs().log10().floor() as i32;
    if !(-3..6).contains(&exponent) {
        return format!("{value:.3e}");
    }
    let decimals = (3 - exponent).max(0) as usize;
    format!("{rounded:.decimals$}")
}

/// One table cell.
pub(crate) enum Cell {
    /// Text (escaped when written).
    Text(String),
    /// A number, formatted with [`sig`] and right-aligned.
    Num(f64),
    /// A count, right-aligned.
    Int(usize),
    /// A pass/fail mark: `true` shows the first text in green, `false` the second in red.
    Check(bool, &'static str, &'static str),
    /// Absent value: an en dash.
    None,
}

impl Cell {
    /// A text cell.
    pub(crate) fn text(text: impl Into<String>) -> Self {
        Cell::Text(text.into())
    }

    /// A number cell, or an en dash for `None`.
    pub(crate) fn opt(value: Option<f64>) -> Self {
        value.map_or(Cell::None, Cell::Num)
    }
}

/// One table row: its `data-*` attributes (`key`, value) and its cells.
pub(crate) type Row = (Vec<(&'static str, String)>, Vec<Cell>);

/// Appends a table inside a horizontally scrolling `div.scroll`: `id` (also its
/// class), column `headers` (plain text, escaped), and `rows`; each row's `data-result`/`data-rod` attributes come from `keys`.
pub(crate) fn push_table(html: &mut String, id: &str, headers: &[&str], rows: &[Row]) {
    // Wrapped so that a wide table scrolls on a narrow screen instead of running off it.
    let _ = writeln!(
        html,
        "<div class=\"scroll\">\n<table id=\"{id}\" class=\"data {id}\">"
    );
    html.push_str("<thead><tr>");
    for h in headers {
        let _ = write!(html, "<th>{}</th>", escape(h));
    }
    html.push_str("</tr></thead>\n<tbody>\n");
    for (keys, cells) in rows {
        html.push_str("<tr");
        for (key, value) in keys {
            let _ = write!(html, " data-{key}=\"{}\"", escape(value));
        }
        html.push('>');
        for cell in cells {
            match cell {
                Cell::Text(t) => {
                    let _ = write!(html, "<td>{}</td>", escape(t));
                }
                Cell::Num(v) => {
                    let _ = write!(html, "<td class=\"num\">{}</td>", sig(*v));
                }
                Cell::Int(n) => {
                    let _ = write!(html, "<td class=\"num\">{n}</td>");
                }
                Cell::Check(true, good, _) => {
                    let _ = write!(html, "<td class=\"ok\">{}</td>", escape(good));
                }
                Cell::Check(false, _, bad) => {
                    let _ = write!(html, "<td class=\"bad\">{}</td>", escape(bad));
                }
                Cell::None => html.push_str("<td class=\"none\">–</td>"),
            }
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody>\n</table>\n</div>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_significant_digits_that_parse_back() {
        for (value, text) in [
            (0.0, "0"),
            (1.0, "1.000"),
            (-12.3456, "-12.35"),
            (9.99996, "10.00"),
            (123456.0, "123500"),
            (0.0123456, "0.01235"),
            (0.00098765, "9.877e-4"),
            (2.5e7, "2.500e7"),
        ] {
            assert_eq!(sig(value), text, "{value}");
            let back: f64 = sig(value).parse().unwrap();
            assert!((back - value).abs() <= 5e-4 * value.abs(), "{value} {back}");
        }
        assert_eq!(sig(f64::NAN), "NaN");
    }
}
