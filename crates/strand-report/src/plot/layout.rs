//! The layout of a figure: panels stacked top to bottom, all of one size, with a
//! legend column to their right.

use super::axes::Panel;

/// Where a figure's panels and legend go, px.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layout {
    /// Figure width.
    pub width: f64,
    /// Left edge of every panel (the y tick labels and title are to its left).
    pub left: f64,
    /// Right edge of every panel.
    pub right: f64,
    /// Left edge of the legend column.
    pub legend_x: f64,
    /// Top edge of the first panel (the heading is above it).
    pub top: f64,
    /// Height of each panel.
    pub panel_height: f64,
    /// Space between one panel's bottom and the next one's top (x tick labels and
    /// title, the next panel's title).
    pub gap: f64,
    /// Space below the last panel.
    pub bottom: f64,
}

/// The wide figures (`study.svg`, `motion.svg`): 900 px, panels 84–680 px, the
/// legend from 704 px, 240 px high panels 78 px apart.
pub const WIDE: Layout = Layout {
    width: 900.0,
    left: 84.0,
    right: 680.0,
    legend_x: 704.0,
    top: 58.0,
    panel_height: 240.0,
    gap: 78.0,
    bottom: 64.0,
};

impl Layout {
    /// Top edge of panel `k` (0 the first).
    pub fn panel_top(&self, k: usize) -> f64 {
        self.top + k as f64 * (self.panel_height + self.gap)
    }

    /// Figure height for `panels` panels.
    pub fn height(&self, panels: usize) -> f64 {
        self.panel_top(panels.max(1) - 1) + self.panel_height + self.bottom
    }

    /// Panel `k` showing `[x_min, x_max] × [y_min, y_max]`.
    pub fn panel(&self, k: usize, [x_min, x_max]: [f64; 2], [y_min, y_max]: [f64; 2]) -> Panel {
        Panel {
            left: self.left,
            right: self.right,
            top: self.panel_top(k),
            height: self.panel_height,
            x_min,
            x_max,
            y_min,
            y_max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_stack_with_their_gaps() {
        let layout = Layout {
            width: 600.0,
            left: 70.0,
            right: 440.0,
            legend_x: 460.0,
            top: 50.0,
            panel_height: 100.0,
            gap: 30.0,
            bottom: 40.0,
        };
        assert_eq!(layout.panel_top(0), 50.0);
        assert_eq!(layout.panel_top(2), 310.0);
        assert_eq!(layout.height(1), 190.0);
        assert_eq!(layout.height(3), 450.0);
        let panel = layout.panel(1, [0.0, 2.0], [-1.0, 1.0]);
        assert_eq!((panel.top, panel.bottom()), (180.0, 280.0));
        assert_eq!((panel.x(1.0), panel.y(0.0)), (255.0, 230.0));
    }
}
