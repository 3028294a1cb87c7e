//! The colours of a figure: a light theme for print, a dark one for slides.

use std::str::FromStr;

use plotters::style::RGBColor;

use super::FigureError;

/// A figure's colour theme.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Theme {
    /// Dark on white, for papers.
    Paper,
    /// Light on dark grey, for slides.
    Dark,
}

impl Theme {
    /// Every theme, by name.
    pub const NAMES: [&str; 2] = ["paper", "dark"];
}

impl FromStr for Theme {
    type Err = FigureError;
    fn from_str(s: &str) -> Result<Self, FigureError> {
        match s {
            "paper" => Ok(Theme::Paper),
            "dark" => Ok(Theme::Dark),
            _ => Err(FigureError::Unknown {
                what: "theme",
                value: s.into(),
                allowed: Theme::NAMES.join(", "),
            }),
        }
    }
}

/// The colours one theme draws with.
pub(super) struct Palette {
    pub background: RGBColor,
    pub text: RGBColor,
    /// Annotations, transients, the physical axes.
    pub muted: RGBColor,
    pub grid: RGBColor,
    /// Series in order (sweeps, curves, family members, attractors).
    series: [RGBColor; 8],
    /// Stops of the heat-map ramp, low to high.
    ramp: [RGBColor; 5],
}

impl Palette {
    pub fn of(theme: Theme) -> Self {
        match theme {
            // Okabe–Ito: told apart with the common colour-vision deficiencies
            Theme::Paper => Palette {
                background: RGBColor(255, 255, 255),
                text: RGBColor(20, 20, 20),
                muted: RGBColor(110, 110, 110),
                grid: RGBColor(222, 222, 222),
                series: [
                    RGBColor(0, 114, 178),
                    RGBColor(213, 94, 0),
                    RGBColor(0, 158, 115),
                    RGBColor(204, 121, 167),
                    RGBColor(230, 159, 0),
                    RGBColor(86, 180, 233),
                    RGBColor(120, 94, 60),
                    RGBColor(0, 0, 0),
                ],
                // viridis
                ramp: [
                    RGBColor(68, 1, 84),
                    RGBColor(59, 82, 139),
                    RGBColor(33, 145, 140),
                    RGBColor(94, 201, 98),
                    RGBColor(253, 231, 37),
                ],
            },
            Theme::Dark => Palette {
                background: RGBColor(28, 30, 34),
                text: RGBColor(225, 225, 225),
                muted: RGBColor(150, 150, 150),
                grid: RGBColor(62, 66, 72),
                series: [
                    RGBColor(86, 180, 233),
                    RGBColor(240, 128, 60),
                    RGBColor(60, 200, 150),
                    RGBColor(230, 150, 200),
                    RGBColor(240, 200, 60),
                    RGBColor(160, 140, 255),
                    RGBColor(200, 170, 120),
                    RGBColor(255, 255, 255),
                ],
                ramp: [
                    RGBColor(0, 0, 4),
                    RGBColor(87, 16, 110),
                    RGBColor(188, 55, 84),
                    RGBColor(249, 142, 9),
                    RGBColor(252, 255, 164),
                ],
            },
        }
    }

    /// The `i`-th series colour.
    pub fn series(&self, i: usize) -> RGBColor {
        self.series[i % self.series.len()]
    }

    /// The colour of a response type: `1:1`, `1:2`, `2:1`, `1:3` their own, others one more.
    pub fn response_type(&self, response_type: &str) -> RGBColor {
        match response_type.split_whitespace().next().unwrap_or("") {
            "1:1" => self.series[0],
            "1:2" => self.series[1],
            "2:1" => self.series[2],
            "1:3" => self.series[3],
            _ => self.series[6],
        }
    }

    /// The heat-map colour of `x` in [0, 1].
    pub fn ramp(&self, x: f64) -> RGBColor {
        let n = self.ramp.len();
        let t = x.clamp(0.0, 1.0) * (n - 1) as f64;
        let i = (t.floor() as usize).min(n - 2);
        let frac = t - i as f64;
        let (a, b) = (self.ramp[i], self.ramp[i + 1]);
        let mix = |p: u8, q: u8| (p as f64 + (q as f64 - p as f64) * frac).round() as u8;
        RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    }
}
