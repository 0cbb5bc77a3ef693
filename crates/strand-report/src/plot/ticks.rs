//! Axis ticks: steps of 1, 2, 2.5 or 5 × 10^k, about five intervals, axes rounded
//! outwards to whole steps, labels with as few decimals as the step needs.

/// A "nice" tick step (1, 2, 2.5 or 5 × 10^k) for about five intervals up to `max`, and
/// the axis top (the first tick at or above `max`); `max ≤ 0` or not finite gives the
/// axis `[0, 1]`.
pub fn ticks(max: f64) -> (f64, f64) {
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

/// A tick label of `value` on an axis of `step`: as few decimals as the step needs
/// (`4.5`, `10`, `0.25`; never `-0`).
pub fn axis_label(value: f64, step: f64) -> String {
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

/// A nice tick step for about five intervals over `[min, max]` and the axis range
/// `(step, low, high)` rounded outwards to whole steps, without forcing zero in (for
/// an axis of parameter values); a single value gets one step on either side.
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

/// As [`axis_ticks`] with zero always in the range (for an axis of magnitudes or of
/// signed quantities): `[0, max]` gives [`ticks`].
pub fn tick_range(min: f64, max: f64) -> (f64, f64, f64) {
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
        assert_eq!(axis_label(12.5, 2.5), "12.5");
        assert_eq!(axis_label(0.06, 0.02), "0.06");
        assert_eq!(axis_label(300.0, 100.0), "300");
        assert_eq!(axis_label(-1e-17, 0.1), "0.0");
    }

    #[test]
    fn ranges_round_outwards_to_whole_steps() {
        // The summary's complaint (4.5, 8.99, 13.5): offsets 0..30 mm tick at 0, 10, 20, 30.
        assert_eq!(axis_ticks(0.0, 30.0), (10.0, 0.0, 30.0));
        assert_eq!(axis_ticks(3.0, 17.0), (5.0, 0.0, 20.0));
        // One value: one step either side.
        assert_eq!(axis_ticks(5.0, 5.0), (1.0, 4.0, 6.0));
        // Signed values keep zero in.
        assert_eq!(tick_range(-3.0, 7.0), (2.0, -4.0, 8.0));
        assert_eq!(tick_range(2.0, 9.0), (2.0, 0.0, 10.0));
    }
}
