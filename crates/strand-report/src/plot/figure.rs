//! The `<svg>` element of a figure: size, class and `data-*` attributes, `<title>`,
//! white background and a heading.

use std::fmt::Write;

use super::escape::escape;

/// Left position of the heading, px (the panels' left margin is at least this).
const HEADING_X: f64 = 72.0;

/// What a figure's `<svg>` element says about itself.
#[derive(Clone, Copy, Debug)]
pub struct Figure<'a> {
    /// Width, px.
    pub width: f64,
    /// Height, px.
    pub height: f64,
    /// The `id` attribute (none if empty).
    pub id: &'a str,
    /// The `class` attribute (none if empty).
    pub class: &'a str,
    /// `data-KEY="VALUE"` attributes (values escaped here).
    pub data: &'a [(&'a str, &'a str)],
    /// The `<title>` and the bold heading at the top (none if empty).
    pub title: &'a str,
    /// Whether to start with an XML declaration (a standalone `.svg` file), or not
    /// (inlined into the report).
    pub standalone: bool,
}

impl<'a> Figure<'a> {
    /// A figure of `width` × `height` px headed `title`, for inlining, without id,
    /// class or data attributes.
    pub fn new(width: f64, height: f64, title: &'a str) -> Self {
        Figure {
            width,
            height,
            id: "",
            class: "",
            data: &[],
            title,
            standalone: false,
        }
    }

    /// With the `id` attribute `id`.
    pub fn id(self, id: &'a str) -> Self {
        Figure { id, ..self }
    }

    /// With the `class` attribute `class`.
    pub fn class(self, class: &'a str) -> Self {
        Figure { class, ..self }
    }

    /// With the `data-*` attributes `data`.
    pub fn data(self, data: &'a [(&'a str, &'a str)]) -> Self {
        Figure { data, ..self }
    }

    /// As a standalone `.svg` file (with the XML declaration).
    pub fn standalone(self) -> Self {
        Figure {
            standalone: true,
            ..self
        }
    }
}

/// Opens `figure` in `svg`: the declaration if standalone, `<svg …>`, its title, a
/// white background and the heading. Close it with [`close_figure`].
pub fn open_figure(svg: &mut String, figure: &Figure) {
    let Figure {
        width,
        height,
        id,
        class,
        data,
        title,
        standalone,
    } = *figure;
    if standalone {
        let _ = writeln!(svg, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    }
    let mut attributes = String::new();
    if !id.is_empty() {
        let _ = write!(attributes, " id=\"{}\"", escape(id));
    }
    if !class.is_empty() {
        let _ = write!(attributes, " class=\"{}\"", escape(class));
    }
    for (key, value) in data {
        let _ = write!(attributes, " data-{key}=\"{}\"", escape(value));
    }
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\"{attributes} width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    if !title.is_empty() {
        let _ = writeln!(svg, "<title>{}</title>", escape(title));
    }
    let _ = writeln!(
        svg,
        "<rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"#ffffff\"/>"
    );
    if !title.is_empty() {
        let _ = writeln!(
            svg,
            "<text class=\"heading\" x=\"{HEADING_X}\" y=\"22\" font-size=\"15\" font-weight=\"bold\">{}</text>",
            escape(title)
        );
    }
}

/// Closes a figure opened with [`open_figure`].
pub fn close_figure(svg: &mut String) {
    svg.push_str("</svg>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_figure_is_well_formed_svg_with_its_title_and_attributes() {
        let mut svg = String::new();
        let data = [("rod", "h\"1")];
        let figure = Figure::new(300.0, 200.0, "a & b")
            .class("hose-plot")
            .data(&data)
            .standalone();
        open_figure(&mut svg, &figure);
        close_figure(&mut svg);
        let xml = roxmltree::Document::parse(&svg).unwrap();
        let root = xml.root_element();
        assert_eq!(
            root.tag_name().namespace(),
            Some("http://www.w3.org/2000/svg")
        );
        assert_eq!(root.attribute("class"), Some("hose-plot"));
        assert_eq!(root.attribute("data-rod"), Some("h\"1"));
        assert_eq!(root.attribute("viewBox"), Some("0 0 300 200"));
        let title = root.children().find(|n| n.has_tag_name("title")).unwrap();
        assert_eq!(title.text(), Some("a & b"));
    }
}
