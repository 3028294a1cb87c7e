//! One view per analysis kind, drawn from plot-ready results; the cursor that reads values off
//! a view and picks a point to integrate.

pub mod basin;
pub mod continued;
pub mod family;
pub mod force;
pub mod frame;
pub mod heatmap;
pub mod history;
pub mod map;
pub mod previous;
pub mod response;
pub mod sweep;

use isola::figure::AxisNames;
use isola::model::Device;
use isola::session::results::{HuntView, ResponsePoint, ResultView};

use super::theme::Theme;

/// What every view needs besides its data.
pub struct PlotContext<'a> {
    pub theme: &'a Theme,
    /// The device frequencies are given in Hz for: none for a written model.
    pub device: Option<&'a Device>,
    /// A written model's names (its grid states, frequency and output); `None` for the
    /// built-in model's Δλ, v, ω_e and τ.
    pub names: Option<AxisNames>,
    pub cursor: (usize, usize),
    /// Enter opens the orbit under the cursor (the result is current and not held): its
    /// hint is shown.
    pub pickable: bool,
}

impl PlotContext<'_> {
    /// A written model's two grid states (the built-in model's are Δλ and v).
    pub fn grid(&self) -> Option<&[String; 2]> {
        self.names.as_ref().map(|n| &n.grid)
    }

    /// The forcing frequency's axis: `ω_e`, or a written model's frequency parameter.
    pub fn omega_axis(&self) -> &str {
        self.names.as_ref().map_or("ω_e", |n| n.frequency.as_str())
    }

    /// The forcing frequency in readouts and labels: `ω`, or a written model's parameter.
    pub fn omega(&self) -> &str {
        self.names.as_ref().map_or("ω", |n| n.frequency.as_str())
    }

    /// `what` of the amplitude's quantity, as an axis: `amplitude Δλ`, or `amplitude of x`
    /// for a written model's output.
    pub fn of_output(&self, what: &str) -> String {
        match &self.names {
            Some(n) => format!("{what} of {}", n.amplitude),
            None => format!("{what} Δλ"),
        }
    }

    /// The time's name: the built-in's dimensionless `τ`, or a written model's `t`.
    pub fn time(&self) -> &'static str {
        if self.names.is_some() { "t" } else { "τ" }
    }

    /// ` (52.67 Hz)`: ω_e in Hz on the device with `decimals`, or nothing without one.
    pub fn in_hz(&self, omega: f64, decimals: usize) -> String {
        self.device.map_or(String::new(), |d| {
            format!(" ({:.decimals$} Hz)", d.hz(omega))
        })
    }
}

/// Points grouped by ω_e (columns, in ω order) and sorted by amplitude within a column: the
/// cursor moves across columns with ←/→ and within one with ↑/↓.
pub struct PointCursor<'a> {
    columns: Vec<Vec<(Option<f64>, &'a ResponsePoint)>>,
}

impl<'a> PointCursor<'a> {
    pub fn new(points: &'a [ResponsePoint]) -> Self {
        Self::tagged(points.iter().map(|p| (None, p)))
    }

    /// Points tagged with the family member they belong to.
    pub fn tagged(points: impl Iterator<Item = (Option<f64>, &'a ResponsePoint)>) -> Self {
        let mut all: Vec<_> = points.collect();
        all.sort_by(|a, b| {
            a.1.omega.total_cmp(&b.1.omega).then(
                a.1.amplitude
                    .unwrap_or(-1.0)
                    .total_cmp(&b.1.amplitude.unwrap_or(-1.0)),
            )
        });
        let mut columns: Vec<Vec<(Option<f64>, &ResponsePoint)>> = Vec::new();
        for p in all {
            match columns.last_mut() {
                Some(c) if (c[0].1.omega - p.1.omega).abs() < 1e-12 => c.push(p),
                _ => columns.push(vec![p]),
            }
        }
        PointCursor { columns }
    }

    fn at(&self, cursor: (usize, usize)) -> Option<(Option<f64>, &'a ResponsePoint)> {
        let column = self
            .columns
            .get(cursor.0.min(self.columns.len().checked_sub(1)?))?;
        column.get(cursor.1.min(column.len() - 1)).copied()
    }

    pub fn point(&self, cursor: (usize, usize)) -> Option<&'a ResponsePoint> {
        self.at(cursor).map(|(_, p)| p)
    }

    pub fn member(&self, cursor: (usize, usize)) -> Option<f64> {
        self.at(cursor).and_then(|(m, _)| m)
    }

    fn bounds(&self, column: usize) -> (usize, usize) {
        let c = column.min(self.columns.len().saturating_sub(1));
        (self.columns.len(), self.columns.get(c).map_or(0, Vec::len))
    }
}

/// Where a picked orbit starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// A stroboscopic point of a response: the grid's two states ([λ_I, v]), then a written
    /// model's others ([`isola::session::results::ResponsePoint::start`]).
    Absolute(Vec<f64>),
    /// A cell of a basin: [Δλ, v].
    Offset([f64; 2]),
}

/// A point picked off a plot: integrate from `start` at `omega` (and at `member`, the value of
/// a family's or a continuation's parameter).
#[derive(Debug, Clone, PartialEq)]
pub struct Pick {
    pub omega: Option<f64>,
    pub member: Option<f64>,
    pub start: Start,
}

fn step(i: usize, by: isize, len: usize) -> usize {
    if len == 0 {
        return 0;
    }
    (i.min(len - 1) as isize + by).clamp(0, len as isize - 1) as usize
}

/// The cursor moved by (dx, dy) steps on `view` (a step is a point, a cell, or 1 % of a long
/// series).
pub fn move_cursor(
    view: &ResultView,
    cursor: (usize, usize),
    dx: isize,
    dy: isize,
) -> (usize, usize) {
    let fine = |n: usize| (n / 100).max(1) as isize;
    match view {
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(HuntView {
            responses: points, ..
        }) => {
            let c = PointCursor::new(points);
            move_point(&c, cursor, dx, dy)
        }
        ResultView::Continuation(c) => {
            let branch = step(cursor.1, dy, c.branches.len());
            let n = c.branches.get(branch).map_or(0, |b| b.points.len());
            (step(cursor.0, dx * fine(n), n), branch)
        }
        ResultView::Family(f) => {
            let c = PointCursor::tagged(
                f.members
                    .iter()
                    .flat_map(|(v, pts)| pts.iter().map(move |p| (Some(*v), p))),
            );
            move_point(&c, cursor, dx, dy)
        }
        ResultView::Basin(b) => (
            step(cursor.0, dx, b.dx.len()),
            step(cursor.1, dy, b.v.len()),
        ),
        ResultView::Map(m) => (
            step(cursor.0, dx, m.omegas.len()),
            step(cursor.1, dy, m.values.len()),
        ),
        ResultView::History(h) => (step(cursor.0, dx * fine(h.tau.len()), h.tau.len()), 0),
        ResultView::Chirp(c) => (
            step(cursor.0, dx * fine(c.envelope.len()), c.envelope.len()),
            0,
        ),
        ResultView::Force(f) => {
            let curve = step(cursor.1, dy, f.curves.len());
            let n = f.curves.get(curve).map_or(0, |c| c.2.len());
            (step(cursor.0, dx * fine(n), n), curve)
        }
    }
}

fn move_point(c: &PointCursor, cursor: (usize, usize), dx: isize, dy: isize) -> (usize, usize) {
    let (columns, _) = c.bounds(cursor.0);
    let column = step(cursor.0, dx, columns);
    let (_, rows) = c.bounds(column);
    (column, step(cursor.1, dy, rows))
}

/// The index of the value of `values` nearest `x`.
fn nearest(values: impl Iterator<Item = f64>, x: f64) -> Option<usize> {
    values
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs()))
        .map(|(i, _)| i)
}

/// The cursor on the point of `view` nearest `at`, in the view's own coordinates: ω_e (and
/// an amplitude) on a response or family, Δλ and v on a basin, ω_e (or x) and the parameter
/// on a map, τ on a time history, ω_e on a chirp, the parameter (and the branch's second
/// coordinate) on a continuation. A coordinate not given keeps the cursor's. `None` for a
/// view without such points (force curves).
pub fn cursor_near(
    view: &ResultView,
    cursor: (usize, usize),
    at: &[f64],
) -> Option<(usize, usize)> {
    let (x, y) = (*at.first()?, at.get(1).copied());
    let in_column = |c: &PointCursor, column: usize| -> usize {
        let points = &c.columns[column];
        match y {
            Some(y) => nearest(points.iter().map(|p| p.1.amplitude.unwrap_or(f64::NAN)), y)
                .unwrap_or(points.len() - 1),
            None => points.len() - 1,
        }
    };
    let on_points = |c: PointCursor| -> Option<(usize, usize)> {
        let column = nearest(c.columns.iter().map(|col| col[0].1.omega), x)?;
        Some((column, in_column(&c, column)))
    };
    match view {
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(HuntView {
            responses: points, ..
        }) => on_points(PointCursor::new(points)),
        ResultView::Family(f) => on_points(PointCursor::tagged(
            f.members
                .iter()
                .flat_map(|(v, pts)| pts.iter().map(move |p| (Some(*v), p))),
        )),
        ResultView::Basin(b) => Some((
            nearest(b.dx.iter().copied(), x)?,
            y.and_then(|y| nearest(b.v.iter().copied(), y))
                .unwrap_or(cursor.1),
        )),
        ResultView::Map(m) => Some((
            nearest(m.omegas.iter().copied(), x)?,
            y.and_then(|y| nearest(m.values.iter().copied(), y))
                .unwrap_or(cursor.1),
        )),
        ResultView::History(h) => Some((nearest(h.tau.iter().copied(), x)?, 0)),
        ResultView::Chirp(c) => Some((nearest(c.envelope.iter().map(|e| e[0]), x)?, 0)),
        ResultView::Continuation(c) => {
            let branch = c.branches.get(cursor.1)?;
            Some((
                nearest(branch.points.iter().map(|p| p.parameter), x)?,
                cursor.1,
            ))
        }
        ResultView::Force(_) => None,
    }
}

/// The orbit under the cursor, if the view has one.
pub fn pick(view: &ResultView, cursor: (usize, usize)) -> Option<Pick> {
    match view {
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(HuntView {
            responses: points, ..
        }) => {
            let p = PointCursor::new(points).point(cursor)?;
            Some(Pick {
                omega: Some(p.omega),
                member: None,
                start: Start::Absolute(p.start.clone()?),
            })
        }
        ResultView::Family(f) => {
            let c = PointCursor::tagged(
                f.members
                    .iter()
                    .flat_map(|(v, pts)| pts.iter().map(move |p| (Some(*v), p))),
            );
            let p = c.point(cursor)?;
            Some(Pick {
                omega: Some(p.omega),
                member: c.member(cursor),
                start: Start::Absolute(p.start.clone()?),
            })
        }
        ResultView::Basin(b) => Some(Pick {
            omega: None,
            member: None,
            start: Start::Offset([*b.dx.get(cursor.0)?, *b.v.get(cursor.1)?]),
        }),
        ResultView::Continuation(c) => {
            let p = continued::point(c, cursor)?;
            Some(Pick {
                omega: Some(p.omega),
                member: Some(p.parameter),
                start: Start::Absolute(p.start.to_vec()),
            })
        }
        _ => None,
    }
}

/// Where the cursor starts on a fresh view: the middle of a basin, the first point otherwise.
pub fn initial_cursor(view: &ResultView) -> (usize, usize) {
    match view {
        ResultView::Basin(b) => (b.dx.len() / 2, b.v.len() / 2),
        ResultView::Map(m) => (m.omegas.len() / 2, m.values.len() / 2),
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(HuntView {
            responses: points, ..
        }) => largest(&PointCursor::new(points)),
        ResultView::Family(f) => largest(&PointCursor::tagged(
            f.members
                .iter()
                .flat_map(|(v, pts)| pts.iter().map(move |p| (Some(*v), p))),
        )),
        _ => (0, 0),
    }
}

/// The cursor on the largest response (the last of its column).
fn largest(c: &PointCursor) -> (usize, usize) {
    c.columns
        .iter()
        .enumerate()
        .filter_map(|(i, col)| Some((i, col.len() - 1, col.last()?.1.amplitude?)))
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .map_or((0, 0), |(i, j, _)| (i, j))
}
