//! Publication figures of a result: one file per view the workbench draws, rendered by
//! `plotters` to SVG, PNG or PDF with the DejaVu Sans font shipped in `assets/fonts/`, so a
//! figure looks the same on a machine with no fonts installed (a PDF embeds the glyphs it
//! uses; PNG and PDF text is set by isola's own `text` layout, with SVG's metrics).
//!
//! Axes are in the model's non-dimensional quantities (MODEL.md §3); where the session's
//! device gives them, a second axis shows the physical units (ω_e in Hz, Δλ in mm, τ in s).

mod basin;
mod continued;
mod family;
mod force;
mod history;
mod map;
mod palette;
mod pdf;
mod raster;
pub mod report;
mod response;
mod sweep;
pub mod text;

use std::cell::RefCell;
use std::error::Error;
use std::ops::Range;
use std::rc::Rc;
use std::str::FromStr;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::analysis::orbit::scalogram::Scalogram;
use crate::model::Device;
use crate::model::equations::EquationModel;
use crate::session::results::{ChirpView, ResultView};
use crate::session::{AnalysisEntry, Session, Settings};

use palette::Palette;
pub use palette::Theme;
pub use sweep::{chirp_scalogram, reverse_sweep};

/// The font every figure is drawn with (and its name in an SVG's `font-family`, a fallback
/// after it for a viewer without it).
const FONT: &str = "DejaVu Sans, sans-serif";
/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/DejaVuSans-LICENSE.txt`).
static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The largest width or height of a figure, in pixels.
pub const MAX_SIZE: u32 = 8000;

/// The file format of a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics, text as text.
    Svg,
    /// An 8-bit RGB bitmap.
    Png,
    /// One vector page, a pixel a CSS pixel (0.75 pt), the font's glyphs embedded.
    Pdf,
}

impl Format {
    /// Every format, by name.
    pub const NAMES: [&str; 3] = ["svg", "png", "pdf"];

    /// The file extension (and the name on the command line).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }
}

impl FromStr for Format {
    type Err = FigureError;
    fn from_str(s: &str) -> Result<Self, FigureError> {
        match s {
            "svg" => Ok(Format::Svg),
            "png" => Ok(Format::Png),
            "pdf" => Ok(Format::Pdf),
            _ => Err(FigureError::Unknown {
                what: "format",
                value: s.into(),
                allowed: Format::NAMES.join(", "),
            }),
        }
    }
}

/// How a figure is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    pub format: Format,
    /// Pixels (an SVG's user units).
    pub width: u32,
    pub height: u32,
    pub theme: Theme,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            format: Format::Svg,
            width: 960,
            height: 600,
            theme: Theme::Paper,
        }
    }
}

/// What a figure shows: a result and what its axes need besides.
#[derive(Debug, Clone)]
pub struct Subject<'a> {
    /// The analysis' name, the figure's title.
    pub title: String,
    pub view: &'a ResultView,
    /// The device for physical units; `None` for a written model (its units are its own).
    pub device: Option<Device>,
    /// A written model's names for the axes (`None`: the built-in model's).
    pub names: Option<AxisNames>,
    /// The ω_e range of a frequency response or hunt, as its settings give it.
    pub omega_range: Option<(f64, f64)>,
    /// A chirp sweep's scalogram, drawn under its envelope.
    pub scalogram: Option<&'a Scalogram>,
    /// A chirp sweep's partner the other way over the same ω_e range (see
    /// [`reverse_sweep`]), its envelope drawn with the sweep's.
    pub reverse: Option<&'a ChirpView>,
}

/// What a written model calls the quantities on a figure's axes.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisNames {
    /// The two states a basin's grid spans.
    pub grid: [String; 2],
    /// The forcing-frequency parameter.
    pub frequency: String,
    /// The output whose max − min is the amplitude, as written.
    pub amplitude: String,
}

impl AxisNames {
    /// The names `model` gives its grid's states, its frequency and its amplitude.
    pub fn of(model: &EquationModel) -> Self {
        let states = model.states();
        AxisNames {
            grid: model.grid().map(|i| states[i].clone()),
            frequency: model.frequency_name().to_string(),
            amplitude: model.amplitude_text().to_string(),
        }
    }
}

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error("{what} '{value}' is not known: one of {allowed}")]
    Unknown {
        what: &'static str,
        value: String,
        allowed: String,
    },
    #[error("{what} {value}: must be 1 to {MAX_SIZE} pixels")]
    Size { what: &'static str, value: u32 },
    #[error("nothing to draw: {0}")]
    Empty(String),
    #[error("drawing the figure: {0}")]
    Draw(String),
}

/// What drawing returns: plotters' errors carry the backend's type, boxed here.
type Drawn = Result<(), Box<dyn Error>>;

/// The figure of `subject`, as the bytes of an SVG, PNG or PDF file.
pub fn render(subject: &Subject, options: &Options) -> Result<Vec<u8>, FigureError> {
    for (what, value) in [("width", options.width), ("height", options.height)] {
        if value == 0 || value > MAX_SIZE {
            return Err(FigureError::Size { what, value });
        }
    }
    register_the_font();
    let size = (options.width, options.height);
    let style = Style::new(options);
    let drawn = match options.format {
        Format::Svg => {
            let mut svg = String::new();
            let drawn = {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw(subject, &root, &style).and_then(|()| Ok(root.present()?))
            };
            drawn.map(|()| svg.into_bytes())
        }
        Format::Png => {
            let mut rgb = vec![0u8; 3 * options.width as usize * options.height as usize];
            let drawn = {
                let root =
                    raster::Raster(BitMapBackend::with_buffer(&mut rgb, size)).into_drawing_area();
                draw(subject, &root, &style).and_then(|()| Ok(root.present()?))
            };
            drawn.and_then(|()| encode_png(&rgb, size))
        }
        Format::Pdf => {
            // the page is kept here to be written once every area drawing on it is gone
            let page = Rc::new(RefCell::new(pdf::Pdf::new(size)));
            let drawn = draw(subject, &DrawingArea::from(&page), &style);
            drawn.and_then(|()| match Rc::try_unwrap(page) {
                Ok(page) => Ok(page.into_inner().finish()?),
                Err(_) => Err("the PDF page is still being drawn on".into()),
            })
        }
    };
    drawn.map_err(|e| match e.downcast::<Nothing>() {
        Ok(nothing) => FigureError::Empty(nothing.0),
        Err(e) => FigureError::Draw(e.to_string()),
    })
}

/// A view with nothing to draw (no points, no cells).
#[derive(Debug)]
struct Nothing(String);

impl std::fmt::Display for Nothing {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl Error for Nothing {}

/// Refuses a view without data, saying what is missing.
/// Half the spacing of grid `values` (a cell's half width).
pub(super) fn half_step(values: &[f64]) -> f64 {
    match values {
        [first, .., last] => 0.5 * (last - first) / (values.len() - 1) as f64,
        _ => 0.5,
    }
}

fn nothing(what: &str) -> Box<dyn Error> {
    Box::new(Nothing(what.into()))
}

fn register_the_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // the bytes are a TrueType font checked in: a failure here is a broken checkout
        register_font(FONT, FontStyle::Normal, FONT_BYTES)
            .unwrap_or_else(|_| panic!("assets/fonts/DejaVuSans.ttf is not a font"));
    });
}

/// RGB pixels as a PNG file.
fn encode_png(rgb: &[u8], (width, height): (u32, u32)) -> Result<Vec<u8>, Box<dyn Error>> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(bytes)
}

/// Draws the figure of `subject`'s view on `root`.
fn draw<DB: DrawingBackend>(subject: &Subject, root: &DrawingArea<DB, Shift>, s: &Style) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&s.palette.background)?;
    let root = root.margin(s.pad, s.pad, s.pad, s.pad);
    let (title, body) = root.split_vertically(s.text * 2);
    title.draw(&Text::new(
        subject.title.clone(),
        (0, 0),
        s.font(s.text + s.text / 4).color(&s.palette.text),
    ))?;
    let device = subject.device.as_ref();
    let units = Units {
        device,
        names: subject.names.as_ref(),
    };
    match subject.view {
        ResultView::Response(points) => {
            response::draw(&body, points, &[], subject.omega_range, false, units, s)
        }
        ResultView::Stepped(points) => response::draw(&body, points, &[], None, true, units, s),
        ResultView::Hunt(h) => response::draw(
            &body,
            &h.responses,
            &h.continued,
            subject.omega_range,
            false,
            units,
            s,
        ),
        ResultView::Basin(b) => basin::draw(&body, b, units, s),
        ResultView::History(h) => history::draw(&body, h, device, s),
        ResultView::Chirp(c) => sweep::draw(&body, c, subject.reverse, subject.scalogram, units, s),
        ResultView::Force(f) => force::draw(&body, f, device, s),
        ResultView::Family(f) => family::draw(&body, f, units, s),
        ResultView::Continuation(c) => continued::draw(&body, c, units, s),
        ResultView::Map(m) => map::draw(&body, m, units, s),
    }
}

/// Sizes and colours of one figure, from its size and theme.
struct Style {
    palette: Palette,
    /// Text height in pixels.
    text: u32,
    /// Margin around the figure and between panels.
    pad: u32,
    /// Width of a data line.
    line: u32,
    /// Radius of a marker.
    marker: u32,
}

impl Style {
    fn new(options: &Options) -> Self {
        let short = options.width.min(options.height);
        let text = (short / 38).clamp(9, 40);
        Style {
            palette: Palette::of(options.theme),
            text,
            pad: (text * 2 / 3).max(4),
            line: (short / 300).max(1),
            marker: (short / 150).max(2),
        }
    }

    fn font(&self, size: u32) -> TextStyle<'static> {
        TextStyle::from((FONT, size).into_font())
    }

    /// Text of the normal size in the text colour.
    fn label(&self) -> TextStyle<'_> {
        self.font(self.text).color(&self.palette.text)
    }

    /// Smaller text in the muted colour, for annotations.
    fn note(&self) -> TextStyle<'_> {
        self.font(self.text * 5 / 6).color(&self.palette.muted)
    }
}

/// One axis: its range, its name, and where the device gives them, the physical units of
/// the same range (a second axis, top or right).
struct AxisSpec {
    range: Range<f64>,
    name: String,
    physical: Option<(Range<f64>, String)>,
}

/// How a figure's axes are named: the built-in model's, with the device's physical units
/// where it has one, or a written model's own names.
#[derive(Debug, Clone, Copy)]
struct Units<'a> {
    device: Option<&'a Device>,
    names: Option<&'a AxisNames>,
}

impl Units<'_> {
    /// The forcing frequency in labels: `ωₑ`, or a written model's frequency parameter.
    fn omega(&self) -> &str {
        self.names.map_or("ωₑ", |n| n.frequency.as_str())
    }
}

impl AxisSpec {
    fn new(name: impl Into<String>, range: Range<f64>) -> Self {
        AxisSpec {
            range,
            name: name.into(),
            physical: None,
        }
    }

    /// The same axis, also in physical units `to` (linear) named `name`.
    fn with_physical(mut self, name: impl Into<String>, to: impl Fn(f64) -> f64) -> Self {
        self.physical = Some((to(self.range.start)..to(self.range.end), name.into()));
        self
    }

    /// ω_e over `range`, in Hz on the device; a written model's frequency by its name.
    fn omega(range: Range<f64>, units: Units) -> Self {
        if let Some(names) = units.names {
            return AxisSpec::new(names.frequency.clone(), range);
        }
        let axis = AxisSpec::new("excitation frequency ωₑ", range);
        match units.device {
            Some(d) => axis.with_physical("f (Hz)", |w| d.hz(w)),
            None => axis,
        }
    }

    /// An amplitude of Δλ from 0 to `top`, in mm of stretch (Δλ·L₁) on the device; a
    /// written model's of its output.
    fn amplitude(top: f64, units: Units) -> Self {
        if let Some(names) = units.names {
            return AxisSpec::new(format!("amplitude of {}", names.amplitude), 0.0..top);
        }
        match units.device {
            Some(d) => AxisSpec::new("amplitude Δλ", 0.0..top)
                .with_physical("amplitude Δλ·L₁ (mm)", |a| a * d.l1 * 1e3),
            None => AxisSpec::new("amplitude", 0.0..top),
        }
    }
}

/// The range of `values` widened by `margin` of its span on each side (a unit range about a
/// single value, 0..1 for none).
fn fit(values: impl Iterator<Item = f64>, margin: f64) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    if span <= f64::EPSILON * hi.abs().max(1.0) {
        return lo - 0.5 * lo.abs().max(1.0)..hi + 0.5 * hi.abs().max(1.0);
    }
    lo - margin * span..hi + margin * span
}

/// A chart with both axes in two systems: the primary one the data is drawn in, the second
/// only to label the physical units.
type Chart<'a, DB> = plotters::chart::DualCoordChartContext<
    'a,
    DB,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
    Cartesian2d<RangedCoordf64, RangedCoordf64>,
>;

/// A framed panel on `area` with a light grid, its axes named, and the physical axes where
/// given.
fn panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: &AxisSpec,
    y: &AxisSpec,
    s: &Style,
) -> Result<Chart<'a, DB>, Box<dyn Error>>
where
    DB::ErrorType: 'static,
{
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(s.pad)
        .x_label_area_size(s.text * 3)
        .y_label_area_size(s.text * 4);
    if x.physical.is_some() {
        builder.top_x_label_area_size(s.text * 3);
    }
    if y.physical.is_some() {
        builder.right_y_label_area_size(s.text * 4);
    }
    let second = |a: &AxisSpec| {
        a.physical
            .as_ref()
            .map_or(a.range.clone(), |(r, _)| r.clone())
    };
    let mut chart = builder
        .build_cartesian_2d(x.range.clone(), y.range.clone())?
        .set_secondary_coord(second(x), second(y));
    let p = &s.palette;
    chart
        .configure_mesh()
        .x_desc(x.name.as_str())
        .y_desc(y.name.as_str())
        .label_style(s.font(s.text * 5 / 6).color(&p.text))
        .axis_desc_style(s.label())
        .axis_style(p.text.stroke_width(1))
        .bold_line_style(p.grid.stroke_width(1))
        .light_line_style(p.background.stroke_width(0))
        .x_labels(7)
        .y_labels(6)
        .x_label_formatter(&|v| tick(*v, x.range.end - x.range.start))
        .y_label_formatter(&|v| tick(*v, y.range.end - y.range.start))
        .draw()?;
    if x.physical.is_some() || y.physical.is_some() {
        let none = String::new();
        let name = |a: &AxisSpec| a.physical.as_ref().map_or(&none, |(_, n)| n).clone();
        let span = |a: &AxisSpec| a.physical.as_ref().map_or(0.0, |(r, _)| r.end - r.start);
        chart
            .configure_secondary_axes()
            .x_desc(name(x))
            .y_desc(name(y))
            .label_style(s.font(s.text * 5 / 6).color(&p.muted))
            .axis_desc_style(s.font(s.text).color(&p.muted))
            .axis_style(p.text.stroke_width(1))
            .x_labels(7)
            .y_labels(6)
            .x_label_formatter(&|v| tick(*v, span(x)))
            .y_label_formatter(&|v| tick(*v, span(y)))
            .draw()?;
    }
    Ok(chart)
}

/// A tick label: few digits, no trailing zeros, no `-0`.
fn number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let decimals = (2.0 - v.abs().log10().floor()).clamp(0.0, 6.0) as usize;
    with_decimals(v, decimals)
}

/// A tick label of an axis spanning `span`: as [`number`], but with the decimals a tick step
/// of the span needs, so ticks close together on a narrow axis (1.015, 1.02, 1.025) do not
/// read the same.
fn tick(v: f64, span: f64) -> String {
    let step = span.abs() / 20.0;
    if v == 0.0 || !step.is_normal() {
        return number(v);
    }
    let by_value = (2.0 - v.abs().log10().floor()).clamp(0.0, 6.0) as usize;
    let by_step = (-step.log10().floor()).clamp(0.0, 6.0) as usize;
    with_decimals(v, by_value.max(by_step))
}

/// `v` with `decimals` decimals, trailing zeros dropped, no `-0`.
fn with_decimals(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" { "0".into() } else { text }
}

/// The marker of a response type: a shape per type, filled when a sweep reaches the
/// response, outlined when it is hidden.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Marker {
    Circle,
    Diamond,
    Triangle,
    Square,
    Cross,
}

impl Marker {
    /// `1:1` a circle, `1:2` a diamond, `2:1` a triangle, `1:3` a square, others a cross.
    fn of(response_type: &str) -> Self {
        match response_type.split_whitespace().next().unwrap_or("") {
            "1:1" => Marker::Circle,
            "1:2" => Marker::Diamond,
            "2:1" => Marker::Triangle,
            "1:3" => Marker::Square,
            _ => Marker::Cross,
        }
    }

    /// The marker at `at` (data coordinates of a chart, or pixels of an area), radius `r`
    /// pixels.
    fn element<C>(self, at: C, r: i32, color: RGBColor, filled: bool) -> MarkerAt<C> {
        MarkerAt {
            at,
            shape: self,
            r,
            color,
            filled,
        }
    }

    /// The corners of the shape about (0, 0), radius `r`; `None` for a circle or cross.
    fn corners(self, r: i32) -> Option<Vec<(i32, i32)>> {
        match self {
            Marker::Diamond => Some(vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)]),
            Marker::Triangle => Some(vec![(0, -r - 1), (r + 1, r), (-r - 1, r)]),
            Marker::Square => Some(vec![(-r, -r), (r, -r), (r, r), (-r, r)]),
            Marker::Circle | Marker::Cross => None,
        }
    }
}

/// A marker drawn at one point: an element of its own, as plotters' are.
struct MarkerAt<C> {
    at: C,
    shape: Marker,
    r: i32,
    color: RGBColor,
    filled: bool,
}

impl<'a, C> plotters::element::PointCollection<'a, C> for &'a MarkerAt<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> plotters::element::Drawable<DB> for MarkerAt<C> {
    fn draw<I: Iterator<Item = (i32, i32)>>(
        &self,
        mut points: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), plotters_backend::DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = points.next() else {
            return Ok(());
        };
        let (r, stroke) = (self.r, self.color.stroke_width(2));
        let fill = self.color.filled();
        match (self.shape, self.shape.corners(r)) {
            (Marker::Circle, _) => backend.draw_circle(
                (x, y),
                r as u32,
                if self.filled { &fill } else { &stroke },
                self.filled,
            ),
            (_, Some(corners)) => {
                let at: Vec<(i32, i32)> = corners.iter().map(|&(u, v)| (x + u, y + v)).collect();
                if self.filled {
                    backend.fill_polygon(at, &fill)
                } else {
                    let mut closed = at.clone();
                    closed.push(at[0]);
                    backend.draw_path(closed, &stroke)
                }
            }
            _ => {
                backend.draw_path([(x - r, y - r), (x + r, y + r)], &stroke)?;
                backend.draw_path([(x - r, y + r), (x + r, y - r)], &stroke)
            }
        }
    }
}

/// `1:2` of `1:2 subharmonic` (`collision` as it is: a start that left the model, whichever
/// of its collision conditions it met).
pub fn short_type(response_type: &str) -> &str {
    response_type
        .split_whitespace()
        .next()
        .unwrap_or(response_type)
}

/// Lines of a legend box: a swatch and a text per entry, drawn in a corner of the plot clear
/// of the data, or as one row outside it.
struct Legend<'a> {
    entries: Vec<(Swatch, String)>,
    style: &'a Style,
}

/// What stands before a legend entry's text.
#[derive(Debug, Clone, Copy)]
enum Swatch {
    Marker(Marker, RGBColor, bool),
    Line(RGBColor, bool),
    Block(RGBColor),
    /// Text only.
    None,
}

/// Polylines in a chart's coordinates (a single point for a marker): what a legend must not
/// cover.
type Polylines = Vec<Vec<(f64, f64)>>;

/// Cells of this many pixels square count what data covers, for placing a legend.
const BUSY_CELL: i32 = 4;

impl<'a> Legend<'a> {
    fn new(style: &'a Style) -> Self {
        Legend {
            entries: Vec::new(),
            style,
        }
    }

    fn add(&mut self, swatch: Swatch, text: impl Into<String>) {
        self.entries.push((swatch, text.into()));
    }

    fn font(&self) -> TextStyle<'_> {
        self.style.font(self.style.text * 5 / 6)
    }

    fn line_height(&self) -> i32 {
        (self.style.text + self.style.text / 3) as i32
    }

    fn swatch_width(&self) -> i32 {
        (self.style.text * 2) as i32
    }

    fn pad(&self) -> i32 {
        (self.style.pad / 2) as i32
    }

    /// The width in pixels of `text` on `area`.
    fn text_width<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, text: &str) -> i32 {
        area.estimate_text_size(text, &self.font())
            .map_or(0, |(w, _)| w as i32)
    }

    /// The width of the legend's box in pixels of `area`.
    fn width<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> i32 {
        let widest = self
            .entries
            .iter()
            .map(|(_, t)| self.text_width(area, t))
            .max()
            .unwrap_or(0);
        widest + self.swatch_width() + 3 * self.pad()
    }

    /// The height of the legend's box in pixels.
    fn height(&self) -> i32 {
        self.line_height() * self.entries.len() as i32 + 2 * self.pad()
    }

    /// Draws the legend in a box whose top right corner is `corner` (pixels of `area`).
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, corner: (i32, i32)) -> Drawn
    where
        DB::ErrorType: 'static,
    {
        if self.entries.is_empty() {
            return Ok(());
        }
        let s = self.style;
        let (width, height, pad) = (self.width(area), self.height(), self.pad());
        let (x0, y0) = (corner.0 - width, corner.1);
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + width, y0 + height)],
            s.palette.background.mix(0.85).filled(),
        ))?;
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + width, y0 + height)],
            s.palette.grid.stroke_width(1),
        ))?;
        for (k, entry) in self.entries.iter().enumerate() {
            let y = y0 + pad + self.line_height() * k as i32 + self.line_height() / 2;
            self.draw_entry(area, (x0 + pad, y), entry)?;
        }
        Ok(())
    }

    /// Draws the legend in the corner of `chart`'s plot where its box covers the least of
    /// `data` (polylines, or single points, in the chart's coordinates): the upper right,
    /// upper left, lower right or lower left, the first of equals.
    fn draw_clear_of<DB: DrawingBackend>(
        &self,
        chart: &Chart<DB>,
        data: &[Vec<(f64, f64)>],
    ) -> Drawn
    where
        DB::ErrorType: 'static,
    {
        let plot = chart.plotting_area();
        let area = plot.strip_coord_spec();
        let (w, h) = area.dim_in_pixel();
        let (w, h) = (w as i32, h as i32);
        let (columns, rows) = (w / BUSY_CELL + 1, h / BUSY_CELL + 1);
        let mut busy = vec![false; (columns * rows) as usize];
        let base = plot.get_base_pixel();
        let mut mark = |(x, y): (i32, i32)| {
            let (c, r) = ((x - base.0) / BUSY_CELL, (y - base.1) / BUSY_CELL);
            if (0..columns).contains(&c) && (0..rows).contains(&r) {
                busy[(r * columns + c) as usize] = true;
            }
        };
        for line in data {
            let pixels: Vec<(i32, i32)> = line.iter().map(|p| plot.map_coordinate(p)).collect();
            if let [only] = pixels[..] {
                mark(only);
            }
            for pair in pixels.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / BUSY_CELL).clamp(1, 4096);
                for k in 0..=steps {
                    mark((a.0 + (b.0 - a.0) * k / steps, a.1 + (b.1 - a.1) * k / steps));
                }
            }
        }
        let (width, height, inset) = (self.width(&area), self.height(), 4);
        let corners = [
            (w - inset, inset),
            (width + inset, inset),
            (w - inset, h - inset - height),
            (width + inset, h - inset - height),
        ];
        let covered = |(right, top): (i32, i32)| {
            let cells =
                |lo: i32, hi: i32, n: i32| (lo / BUSY_CELL).max(0)..(hi / BUSY_CELL + 1).min(n);
            cells(top, top + height, rows)
                .flat_map(|r| cells(right - width, right, columns).map(move |c| (r, c)))
                .filter(|&(r, c)| busy[(r * columns + c) as usize])
                .count()
        };
        let corner = corners
            .iter()
            .copied()
            .min_by_key(|&c| covered(c))
            .unwrap_or(corners[0]);
        self.draw(&area, corner)
    }

    /// Draws the legend as one row from the left of `area`, centred in its height: outside a
    /// plot whose data fills every corner.
    fn draw_row<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, left: i32) -> Drawn
    where
        DB::ErrorType: 'static,
    {
        let y = area.dim_in_pixel().1 as i32 / 2;
        let mut x = left;
        for entry in &self.entries {
            self.draw_entry(area, (x, y), entry)?;
            x += self.swatch_width() + self.text_width(area, &entry.1) + 4 * self.pad();
        }
        Ok(())
    }

    /// Draws one entry: its swatch from `(x, y)` (the left of its middle line) and its text.
    fn draw_entry<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x, y): (i32, i32),
        (swatch, text): &(Swatch, String),
    ) -> Drawn
    where
        DB::ErrorType: 'static,
    {
        let s = self.style;
        let swatch_width = self.swatch_width();
        let centre = (x + swatch_width / 2, y);
        match *swatch {
            Swatch::Marker(m, color, filled) => {
                area.draw(&m.element(centre, s.marker as i32 + 1, color, filled))?;
            }
            Swatch::Line(color, dashed) => {
                let style = color.stroke_width(s.line + 1);
                if dashed {
                    let q = swatch_width / 4;
                    for k in [0, 2] {
                        area.draw(&PathElement::new(
                            vec![(x + k * q, y), (x + (k + 1) * q, y)],
                            style,
                        ))?;
                    }
                } else {
                    area.draw(&PathElement::new(
                        vec![(x, y), (x + swatch_width, y)],
                        style,
                    ))?;
                }
            }
            Swatch::Block(color) => {
                let h = self.line_height() / 3;
                area.draw(&Rectangle::new(
                    [(x, y - h), (x + swatch_width, y + h)],
                    color.filled(),
                ))?;
            }
            Swatch::None => {}
        }
        let text_x = match swatch {
            Swatch::None => x,
            _ => x + swatch_width + self.pad(),
        };
        area.draw(&Text::new(
            text.clone(),
            (text_x, y),
            self.font()
                .color(&s.palette.text)
                .pos(plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Left,
                    plotters::style::text_anchor::VPos::Center,
                )),
        ))?;
        Ok(())
    }
}

impl<'a> Subject<'a> {
    /// The figure of `entry`'s result `view` in `session`: its title, the device's units
    /// (none for a written model), the ω_e range its settings give.
    pub fn of(
        session: &Session,
        entry: &AnalysisEntry,
        view: &'a ResultView,
        scalogram: Option<&'a Scalogram>,
    ) -> Self {
        let omega_range = match &entry.settings {
            Settings::FrequencyResponse(s) => Some((s.omega.min, s.omega.max)),
            Settings::Hunt(s) => Some((s.response.omega.min, s.response.omega.max)),
            _ => None,
        };
        Subject {
            title: format!(
                "{}: {}",
                entry.name,
                entry.settings.kind().replace('_', " ")
            ),
            view,
            device: session.written.is_none().then(|| session.device()),
            names: session.written.as_ref().map(|w| AxisNames::of(&w.model)),
            omega_range,
            scalogram,
            reverse: None,
        }
    }

    /// The same figure with `reverse`, the result of the sweep's [`reverse_sweep`], drawn
    /// with it (nothing if that is no chirp sweep's result).
    pub fn with_reverse(mut self, reverse: Option<&'a ResultView>) -> Self {
        self.reverse = match reverse {
            Some(ResultView::Chirp(c)) => Some(c),
            _ => None,
        };
        self
    }
}
