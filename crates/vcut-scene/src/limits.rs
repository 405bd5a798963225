//! The one check of a number a user gives — a scene file's key, a command-line option, a Python
//! keyword: finite, within its range, and when it is not, a reason that states the range with
//! its unit, for the caller to put after the key's or the option's name.

/// One end of a range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum End {
    /// No limit on this side (but finite).
    None,
    /// The value may equal it.
    Closed(f64),
    /// The value must stay strictly beyond it.
    Open(f64),
}

/// A number's allowed range and unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// The lower end.
    pub low: End,
    /// The upper end.
    pub high: End,
    /// The unit, as a reader sees it after the number (`"MB"`, `"degrees"`; empty for none).
    pub unit: &'static str,
}

impl Limit {
    /// Any finite number.
    pub const fn finite(unit: &'static str) -> Limit {
        Limit { low: End::None, high: End::None, unit }
    }

    /// A finite number above `low`.
    pub const fn above(low: f64, unit: &'static str) -> Limit {
        Limit { low: End::Open(low), high: End::None, unit }
    }

    /// A finite number, at least `low`.
    pub const fn at_least(low: f64, unit: &'static str) -> Limit {
        Limit { low: End::Closed(low), high: End::None, unit }
    }

    /// A number in `[low, high]`.
    pub const fn within(low: f64, high: f64, unit: &'static str) -> Limit {
        Limit { low: End::Closed(low), high: End::Closed(high), unit }
    }

    /// A number in `(low, high)`.
    pub const fn between(low: f64, high: f64, unit: &'static str) -> Limit {
        Limit { low: End::Open(low), high: End::Open(high), unit }
    }

    /// A number in `(low, high]`.
    pub const fn above_up_to(low: f64, high: f64, unit: &'static str) -> Limit {
        Limit { low: End::Open(low), high: End::Closed(high), unit }
    }

    /// A number in `[low, high)`.
    pub const fn at_least_below(low: f64, high: f64, unit: &'static str) -> Limit {
        Limit { low: End::Closed(low), high: End::Open(high), unit }
    }

    /// Whether `v` is finite and within the range.
    pub fn contains(self, v: f64) -> bool {
        let low = match self.low {
            End::None => true,
            End::Closed(l) => v >= l,
            End::Open(l) => v > l,
        };
        let high = match self.high {
            End::None => true,
            End::Closed(h) => v <= h,
            End::Open(h) => v < h,
        };
        v.is_finite() && low && high
    }

    /// `v`, or the reason it is refused: `must be a number in (0, 1)`, `must be a finite number above 0
    /// MB`.
    pub fn check(self, v: f64) -> Result<f64, String> {
        if self.contains(v) { Ok(v) } else { Err(format!("must be {}", self.describe())) }
    }

    /// [`Limit::check`] of a number written as `text` (a command-line value): its error quotes
    /// the text.
    pub fn parse(self, text: &str) -> Result<f64, String> {
        let v: f64 =
            text.trim().parse().map_err(|_| format!("{text:?} is not a number: must be {}", self.describe()))?;
        self.check(v).map_err(|reason| format!("{text:?}: {reason}"))
    }

    /// [`Limit::parse`] into an f32: the range is checked on the value as an f32 holds it.
    pub fn parse_f32(self, text: &str) -> Result<f32, String> {
        let v = self.parse(text)? as f32;
        self.check(f64::from(v)).map(|_| v).map_err(|reason| format!("{text:?}: {reason}"))
    }

    /// A whole number written as `text` (pixels, counts), within the range.
    pub fn parse_whole(self, text: &str) -> Result<u64, String> {
        let refuse = || format!("{text:?}: must be a whole {}", self.describe().trim_start_matches("a "));
        let n: u64 = text.trim().parse().map_err(|_| refuse())?;
        if self.contains(n as f64) { Ok(n) } else { Err(refuse()) }
    }

    /// What the range is, for messages and help: `a finite number above 0 MB`, `a number in
    /// [1.7, 10]`.
    pub fn describe(self) -> String {
        let unit = if self.unit.is_empty() { String::new() } else { format!(" {}", self.unit) };
        match (self.low, self.high) {
            (End::None, End::None) if self.unit.is_empty() => "a finite number".into(),
            (End::None, End::None) => format!("a finite number of {}", self.unit),
            (End::Open(l), End::None) => format!("a finite number above {l}{unit}"),
            (End::Closed(l), End::None) => format!("a finite number, at least {l}{unit}"),
            (End::None, End::Open(h)) => format!("a number below {h}{unit}"),
            (End::None, End::Closed(h)) => format!("a number at most {h}{unit}"),
            (low, high) => {
                let (a, l) = match low {
                    End::Open(l) => ('(', l),
                    End::Closed(l) => ('[', l),
                    End::None => unreachable!("matched above"),
                };
                let (b, h) = match high {
                    End::Open(h) => (')', h),
                    End::Closed(h) => (']', h),
                    End::None => unreachable!("matched above"),
                };
                format!("a number in {a}{l}, {h}{b}{unit}")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_hold_and_say_what_they_are() {
        let share = Limit::between(0.0, 1.0, "");
        assert!(share.contains(0.5) && !share.contains(0.0) && !share.contains(1.0) && !share.contains(f64::NAN));
        assert_eq!(share.check(2.0).unwrap_err(), "must be a number in (0, 1)");
        let mb = Limit::above(0.0, "MB");
        assert_eq!(mb.parse("0").unwrap_err(), "\"0\": must be a finite number above 0 MB");
        assert_eq!(mb.parse("inf").unwrap_err(), "\"inf\": must be a finite number above 0 MB");
        assert!(mb.parse("x").unwrap_err().starts_with("\"x\" is not a number"));
        assert_eq!(mb.parse(" 2.5 ").unwrap(), 2.5);
        assert_eq!(Limit::within(1.7, 10.0, "").check(1.7).unwrap(), 1.7);
        assert_eq!(
            Limit::finite("degrees").check(f64::NEG_INFINITY).unwrap_err(),
            "must be a finite number of degrees"
        );
        // A value an f64 holds but an f32 does not is refused as the f32 it would become.
        assert!(Limit::finite("").parse_f32("1e39").is_err());
        assert_eq!(Limit::at_least(0.0, "ms").describe(), "a finite number, at least 0 ms");
        assert_eq!(Limit::above_up_to(0.0, 45.0, "degrees").describe(), "a number in (0, 45] degrees");
        let side = Limit::within(1.0, 16384.0, "pixels");
        assert_eq!(side.parse_whole("640").unwrap(), 640);
        for bad in ["0", "16385", "-1", "1.5", "", "1e3", "99999999999999999999999"] {
            assert_eq!(
                side.parse_whole(bad).unwrap_err(),
                format!("{bad:?}: must be a whole number in [1, 16384] pixels")
            );
        }
    }
}
