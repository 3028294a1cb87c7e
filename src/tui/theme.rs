//! Themes (`themes/*.toml`) and the colour depth of the terminal: a theme's true colours are
//! mapped to 256 or 16 colours when the terminal has fewer, and to none at all under
//! `NO_COLOR` or `--color none`, where emphasis is by bold, reverse and glyphs instead.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Context;
use ratatui::style::{Color, Modifier, Style};
use serde::Deserialize;

/// The themes every build carries.
const BUILT_IN: [(&str, &str); 3] = [
    ("dark", include_str!("../../themes/dark.toml")),
    ("light", include_str!("../../themes/light.toml")),
    ("mono", include_str!("../../themes/mono.toml")),
];

/// How many colours to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorMode {
    /// From COLORTERM and TERM (NO_COLOR turns colour off).
    Auto,
    Truecolor,
    #[value(name = "256")]
    Ansi256,
    #[value(name = "16")]
    Ansi16,
    None,
}

impl ColorMode {
    /// `Auto` made concrete from the environment.
    pub fn resolve(self, env: impl Fn(&str) -> Option<String>) -> ColorMode {
        if self != ColorMode::Auto {
            return self;
        }
        if env("NO_COLOR").is_some_and(|v| !v.is_empty()) {
            return ColorMode::None;
        }
        let colorterm = env("COLORTERM").unwrap_or_default();
        if colorterm == "truecolor" || colorterm == "24bit" {
            ColorMode::Truecolor
        } else if env("TERM").unwrap_or_default().contains("256") {
            ColorMode::Ansi256
        } else {
            ColorMode::Ansi16
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ThemeFile {
    name: String,
    #[serde(default)]
    monochrome: bool,
    foreground: String,
    muted: String,
    border: String,
    focus: String,
    selection: String,
    error: String,
    ok: String,
    warn: String,
    hidden: String,
    cursor: String,
    types: BTreeMap<String, String>,
    palette: Colors,
    ramp: Colors,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Colors {
    colors: Vec<String>,
}

/// A theme resolved for the terminal's colour depth.
#[derive(Debug, Clone)]
pub struct Theme {
    pub name: String,
    /// The colour depth it was resolved for (another theme is loaded for the same).
    pub mode: ColorMode,
    /// No colours: styles use modifiers, maps use glyphs.
    pub monochrome: bool,
    pub foreground: Color,
    pub muted: Color,
    pub border: Color,
    pub focus: Color,
    pub selection: Color,
    pub error: Color,
    pub ok: Color,
    pub warn: Color,
    pub hidden: Color,
    pub cursor: Color,
    types: BTreeMap<String, Color>,
    palette: Vec<Color>,
    ramp: Vec<Color>,
}

impl Theme {
    /// The theme `name_or_path`: a built-in name, a file in the user's theme folder, or a path.
    pub fn load(
        name_or_path: &str,
        mode: ColorMode,
        user_dir: Option<&Path>,
    ) -> anyhow::Result<Theme> {
        let text = if let Some((_, text)) = BUILT_IN.iter().find(|(n, _)| *n == name_or_path) {
            text.to_string()
        } else {
            let candidates = [
                user_dir.map(|d| d.join(format!("{name_or_path}.toml"))),
                Some(Path::new(name_or_path).to_path_buf()),
            ];
            let path = candidates
                .into_iter()
                .flatten()
                .find(|p| p.is_file())
                .with_context(|| {
                    let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
                    format!(
                        "theme '{name_or_path}': not a built-in theme ({}) nor a file",
                        names.join(", ")
                    )
                })?;
            std::fs::read_to_string(&path).with_context(|| format!("theme {}", path.display()))?
        };
        let file: ThemeFile =
            toml::from_str(&text).with_context(|| format!("theme '{name_or_path}'"))?;
        Theme::from_file(file, mode)
    }

    fn from_file(f: ThemeFile, mode: ColorMode) -> anyhow::Result<Theme> {
        let monochrome = f.monochrome || mode == ColorMode::None;
        let c = |s: &str| -> anyhow::Result<Color> {
            let color =
                parse_color(s).with_context(|| format!("theme '{}': colour '{s}'", f.name))?;
            Ok(if monochrome {
                Color::Reset
            } else {
                downgrade(color, mode)
            })
        };
        let list = |v: &[String]| v.iter().map(|s| c(s)).collect::<anyhow::Result<Vec<_>>>();
        Ok(Theme {
            mode,
            name: f.name.clone(),
            monochrome,
            foreground: c(&f.foreground)?,
            muted: c(&f.muted)?,
            border: c(&f.border)?,
            focus: c(&f.focus)?,
            selection: c(&f.selection)?,
            error: c(&f.error)?,
            ok: c(&f.ok)?,
            warn: c(&f.warn)?,
            hidden: c(&f.hidden)?,
            cursor: c(&f.cursor)?,
            types: f
                .types
                .iter()
                .map(|(k, v)| Ok((k.clone(), c(v)?)))
                .collect::<anyhow::Result<_>>()?,
            palette: list(&f.palette.colors)?,
            ramp: list(&f.ramp.colors)?,
        })
    }

    /// The colour of a response type (`1:2`, `1:3 subharmonic`, `collision`...).
    pub fn type_color(&self, response_type: &str) -> Color {
        let key = response_type.split_whitespace().next().unwrap_or("");
        self.types
            .get(key)
            .or_else(|| self.types.get("other"))
            .copied()
            .unwrap_or(Color::Reset)
    }

    /// The `i`-th series colour.
    pub fn series(&self, i: usize) -> Color {
        if self.palette.is_empty() {
            Color::Reset
        } else {
            self.palette[i % self.palette.len()]
        }
    }

    /// A heat-map colour for `x` in [0, 1].
    pub fn ramp(&self, x: f64) -> Color {
        let n = self.ramp.len();
        if n == 0 {
            return Color::Reset;
        }
        let t = x.clamp(0.0, 1.0) * (n - 1) as f64;
        let (i, frac) = (t.floor() as usize, t.fract());
        if i + 1 >= n {
            return self.ramp[n - 1];
        }
        match (self.ramp[i], self.ramp[i + 1]) {
            (Color::Rgb(r0, g0, b0), Color::Rgb(r1, g1, b1)) => {
                let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * frac).round() as u8;
                Color::Rgb(mix(r0, r1), mix(g0, g1), mix(b0, b1))
            }
            (a, b) => {
                if frac < 0.5 {
                    a
                } else {
                    b
                }
            }
        }
    }

    pub fn text(&self) -> Style {
        Style::default().fg(self.foreground)
    }

    /// `color` faded halfway to the muted colour: a previous result drawn under a new one.
    /// A 256-colour index is faded through its RGB and back; with 16 colours or none, the
    /// muted colour itself.
    pub fn dim(&self, color: Color) -> Color {
        match (rgb_of(color), rgb_of(self.muted)) {
            (Some((r, g, b)), Some((mr, mg, mb))) if self.mode != ColorMode::Ansi16 => {
                let mix = |a: u8, m: u8| ((a as u16 + m as u16) / 2) as u8;
                downgrade(Color::Rgb(mix(r, mr), mix(g, mg), mix(b, mb)), self.mode)
            }
            _ => self.muted,
        }
    }

    pub fn muted(&self) -> Style {
        if self.monochrome {
            Style::default().add_modifier(Modifier::DIM)
        } else {
            Style::default().fg(self.muted)
        }
    }

    pub fn border(&self, focused: bool) -> Style {
        match (focused, self.monochrome) {
            (true, true) => Style::default().add_modifier(Modifier::BOLD),
            (true, false) => Style::default().fg(self.focus).add_modifier(Modifier::BOLD),
            (false, _) => Style::default().fg(self.border),
        }
    }

    pub fn selected(&self) -> Style {
        if self.monochrome {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default().bg(self.selection)
        }
    }

    pub fn error(&self) -> Style {
        Style::default().fg(self.error).add_modifier(Modifier::BOLD)
    }

    pub fn ok(&self) -> Style {
        Style::default().fg(self.ok)
    }

    pub fn warn(&self) -> Style {
        Style::default().fg(self.warn)
    }

    /// Hidden responses stand out.
    pub fn hidden(&self) -> Style {
        Style::default()
            .fg(self.hidden)
            .add_modifier(Modifier::BOLD)
    }

    pub fn cursor(&self) -> Style {
        Style::default()
            .fg(self.cursor)
            .add_modifier(Modifier::BOLD | Modifier::REVERSED)
    }

    /// Text selected in a line being typed (replaced by what is typed): the cursor's style,
    /// underlined, so that it reads as being edited on the selected row too.
    pub fn selection(&self) -> Style {
        self.cursor().add_modifier(Modifier::UNDERLINED)
    }

    pub fn key(&self) -> Style {
        if self.monochrome {
            Style::default().add_modifier(Modifier::BOLD)
        } else {
            Style::default().fg(self.focus).add_modifier(Modifier::BOLD)
        }
    }
}

/// `#rrggbb` or `reset`.
fn parse_color(s: &str) -> Option<Color> {
    if s == "reset" {
        return Some(Color::Reset);
    }
    let hex = s.strip_prefix('#')?;
    if hex.len() != 6 {
        return None;
    }
    let v = u32::from_str_radix(hex, 16).ok()?;
    Some(Color::Rgb((v >> 16) as u8, (v >> 8) as u8, v as u8))
}

/// A true colour as the nearest the terminal can show.
pub fn downgrade(color: Color, mode: ColorMode) -> Color {
    let Color::Rgb(r, g, b) = color else {
        return color;
    };
    match mode {
        ColorMode::Auto | ColorMode::Truecolor => color,
        ColorMode::Ansi256 => Color::Indexed(nearest_256(r, g, b)),
        ColorMode::Ansi16 => nearest_16(r, g, b),
        ColorMode::None => Color::Reset,
    }
}

fn dist2(a: (u8, u8, u8), b: (u8, u8, u8)) -> i32 {
    let d = |x: u8, y: u8| x as i32 - y as i32;
    d(a.0, b.0).pow(2) + d(a.1, b.1).pow(2) + d(a.2, b.2).pow(2)
}

/// The xterm 256-colour index nearest to (r, g, b): the 6×6×6 cube or the grey ramp.
/// The levels of each channel in the xterm 256-colour cube (indices 16 to 231).
const LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];

/// The RGB of a true colour or of an xterm 256-colour index past the first 16 (whose
/// colours each terminal sets its own way).
fn rgb_of(color: Color) -> Option<(u8, u8, u8)> {
    match color {
        Color::Rgb(r, g, b) => Some((r, g, b)),
        Color::Indexed(i @ 16..=231) => {
            let i = (i - 16) as usize;
            Some((LEVELS[i / 36], LEVELS[i / 6 % 6], LEVELS[i % 6]))
        }
        Color::Indexed(i @ 232..) => {
            let grey = 8 + 10 * (i - 232);
            Some((grey, grey, grey))
        }
        _ => None,
    }
}

fn nearest_256(r: u8, g: u8, b: u8) -> u8 {
    let level = |x: u8| {
        (0..6)
            .min_by_key(|&i| (LEVELS[i] as i32 - x as i32).abs())
            .unwrap_or(0)
    };
    let (ri, gi, bi) = (level(r), level(g), level(b));
    let cube = (LEVELS[ri], LEVELS[gi], LEVELS[bi]);
    let cube_index = 16 + 36 * ri + 6 * gi + bi;
    let grey_i = ((r as i32 + g as i32 + b as i32) / 3 - 8).clamp(0, 230) / 10;
    let grey = (8 + 10 * grey_i) as u8;
    if dist2((grey, grey, grey), (r, g, b)) < dist2(cube, (r, g, b)) {
        (232 + grey_i) as u8
    } else {
        cube_index as u8
    }
}

/// One of the 16 ANSI colours for (r, g, b), by hue rather than by distance: a terminal's 16
/// colours are far apart and its palette varies, so the nearest by distance turns pastel
/// colours grey (#87d787 became light grey, and a dark blue selection grey on grey). A colour
/// with little saturation is a grey by its brightness; any other takes the nearest of the six
/// hues, bright if it is near full brightness.
fn nearest_16(r: u8, g: u8, b: u8) -> Color {
    let (max, min) = (r.max(g).max(b) as f64, r.min(g).min(b) as f64);
    let value = max / 255.0;
    let saturation = if max > 0.0 { (max - min) / max } else { 0.0 };
    if saturation < 0.2 {
        return match value {
            v if v < 0.2 => Color::Black,
            v if v < 0.6 => Color::DarkGray,
            v if v < 0.9 => Color::Gray,
            _ => Color::White,
        };
    }
    let (r, g, b) = (r as f64, g as f64, b as f64);
    let hue = if max == r {
        60.0 * ((g - b) / (max - min)).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / (max - min) + 2.0)
    } else {
        60.0 * ((r - g) / (max - min) + 4.0)
    };
    const HUES: [(Color, Color); 6] = [
        (Color::Red, Color::LightRed),
        (Color::Yellow, Color::LightYellow),
        (Color::Green, Color::LightGreen),
        (Color::Cyan, Color::LightCyan),
        (Color::Blue, Color::LightBlue),
        (Color::Magenta, Color::LightMagenta),
    ];
    let (normal, bright) = HUES[((hue + 30.0) / 60.0) as usize % 6];
    if value >= 0.9 { bright } else { normal }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A faded colour keeps its hue in true colour and in 256 colours (an index is faded
    /// through its RGB), and is the muted colour itself with 16.
    #[test]
    fn a_faded_colour_keeps_its_hue() {
        for mode in [ColorMode::Truecolor, ColorMode::Ansi256] {
            let t = Theme::load("dark", mode, None).unwrap();
            let (blue, orange) = (t.type_color("1:1"), t.type_color("1:2"));
            let (a, b) = (t.dim(blue), t.dim(orange));
            assert!(
                a != b && a != t.muted && b != t.muted,
                "{mode:?}: {a:?} {b:?}"
            );
            let (r, _, bl) = rgb_of(a).unwrap();
            assert!(bl > r, "{mode:?}: the 1:1 blue stays bluish: {a:?}");
        }
        let t = Theme::load("dark", ColorMode::Ansi16, None).unwrap();
        assert_eq!(t.dim(t.type_color("1:2")), t.muted);
        assert_eq!(rgb_of(Color::Indexed(16 + 36 * 5)), Some((255, 0, 0)));
        assert_eq!(rgb_of(Color::Indexed(232)), Some((8, 8, 8)));
    }

    #[test]
    fn every_built_in_theme_loads_in_every_mode() {
        for (name, _) in BUILT_IN {
            for mode in [
                ColorMode::Truecolor,
                ColorMode::Ansi256,
                ColorMode::Ansi16,
                ColorMode::None,
            ] {
                let t = Theme::load(name, mode, None).unwrap();
                assert_eq!(t.name, name);
                if mode == ColorMode::None {
                    assert!(t.monochrome);
                    assert_eq!(t.type_color("1:2"), Color::Reset);
                }
            }
        }
    }

    #[test]
    fn colours_fall_back_to_the_nearest() {
        assert_eq!(nearest_256(255, 135, 0), 208);
        assert_eq!(nearest_256(128, 128, 128), 244);
        assert_eq!(nearest_16(255, 10, 10), Color::LightRed);
        assert_eq!(nearest_16(0, 0, 200), Color::Blue);
        // by hue: the dark theme's pastel green stays green, its dark blue selection blue,
        // its orange and yellow apart, its greys grey
        assert_eq!(nearest_16(0x87, 0xd7, 0x87), Color::Green);
        assert_eq!(nearest_16(0x26, 0x4f, 0x78), Color::Blue);
        assert_eq!(nearest_16(0xff, 0x87, 0x00), Color::LightYellow);
        assert_eq!(nearest_16(0xd7, 0xd7, 0x00), Color::Yellow);
        assert_eq!(nearest_16(0x5f, 0xaf, 0xff), Color::LightBlue);
        assert_eq!(nearest_16(0x8a, 0x8a, 0x8a), Color::DarkGray);
        assert_eq!(nearest_16(0x9e, 0x9e, 0x9e), Color::Gray);
        assert_eq!(nearest_16(0, 0, 0), Color::Black);
        assert_eq!(nearest_16(255, 255, 255), Color::White);
        // in 16 colours the dark theme's response types stay apart where they can
        let t = Theme::load("dark", ColorMode::Ansi16, None).unwrap();
        let types = ["1:1", "1:2", "2:1", "1:3", "non-periodic", "collision"];
        let colours: Vec<Color> = types.iter().map(|k| t.type_color(k)).collect();
        for (i, a) in colours.iter().enumerate() {
            for (j, b) in colours.iter().enumerate().skip(i + 1) {
                assert_ne!(a, b, "{} and {} look the same", types[i], types[j]);
            }
        }
        assert_ne!(
            t.selected().bg,
            t.muted().fg,
            "the selected row is not grey on grey"
        );
        let t = Theme::load("dark", ColorMode::Ansi256, None).unwrap();
        assert!(matches!(t.type_color("1:2"), Color::Indexed(_)));
        assert_eq!(t.type_color("1:3 subharmonic"), t.type_color("1:3"));
    }

    #[test]
    fn no_color_wins_over_the_terminal_unless_a_mode_is_asked() {
        let env = |k: &str| match k {
            "NO_COLOR" => Some("1".to_string()),
            "COLORTERM" => Some("truecolor".to_string()),
            _ => None,
        };
        assert_eq!(ColorMode::Auto.resolve(env), ColorMode::None);
        assert_eq!(ColorMode::Ansi16.resolve(env), ColorMode::Ansi16);
        let env = |k: &str| (k == "TERM").then(|| "xterm-256color".to_string());
        assert_eq!(ColorMode::Auto.resolve(env), ColorMode::Ansi256);
    }

    #[test]
    fn an_unknown_theme_names_the_built_in_ones() {
        let e = Theme::load("solarised", ColorMode::Truecolor, None).unwrap_err();
        assert!(format!("{e:#}").contains("dark, light, mono"), "{e:#}");
    }
}
