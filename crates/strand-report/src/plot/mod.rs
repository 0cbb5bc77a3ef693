//! The one SVG plotting module of Strand: every figure (`study.svg`, the batch's
//! `summary.svg`, `motion.svg`, the report's per-hose plots, its side/top/front
//! projections and its 3D view) is drawn with these pieces, so that they share one
//! look, one palette and one escaping:
//!
//! - [`figure`]: the `<svg>` element (size, class and `data-*` attributes, `<title>`,
//!   white background, heading); [`layout`]: panels stacked with a legend column;
//! - [`ticks`]: nice tick steps (1, 2, 2.5, 5 × 10^k) and their labels;
//! - [`axes`]: a [`Panel`] (data rectangle ↔ pixels) with its grid, ticks
//!   (`class="x-tick"`, `"y-tick"`), axis titles (`"x-title"`, `"y-title"`) and title;
//! - [`series`]: curves (`<path class="curve">` with `data-*` attributes; non-finite
//!   values break the line) and markers;
//! - [`legend`]: a column of keyed entries (lines with their dash, markers, headings);
//! - [`palette`]: line colours (Okabe–Ito, tested under simulated deuteranopia), dash
//!   patterns, the viridis scale and the contact colour; [`colour_bar`]: a viridis bar;
//! - [`escape`](fn@escape): text for XML character data and attributes.
//!
//! Plain SVG 1.1, text in the generic `sans-serif` family; no scripts, fonts, images
//! or links.

pub mod axes;
pub mod colour_bar;
pub mod escape;
pub mod figure;
pub mod layout;
pub mod legend;
pub mod palette;
pub mod series;
pub mod ticks;

pub use axes::Panel;
pub use colour_bar::colour_bar;
pub use escape::escape;
pub use figure::{Figure, close_figure, open_figure};
pub use layout::{Layout, WIDE};
pub use legend::Legend;
pub use palette::{
    CONTACT_COLOUR, DASH_PATTERNS, LINE_COLOURS, MIN_DEUTERANOPIA_DELTA_E, VIRIDIS, dash_attribute,
    dash_pattern, line_colour, viridis,
};
pub use series::{LineStyle, curve, diamond, path_data};
pub use ticks::{axis_label, axis_ticks, tick_range, ticks};
