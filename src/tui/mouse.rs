//! The mouse: a click focuses the pane under it and selects the row or plot point there; the
//! wheel moves the selection of the pane under it. Panes are found in the layout of the last
//! frame drawn.

use crossterm::event::{MouseButton, MouseEvent, MouseEventKind};
use ratatui::layout::Rect;

use super::app::{App, Focus};
use super::plots::frame::Drawn;

/// Where things were on the last frame drawn.
#[derive(Debug, Clone, Default)]
pub struct Layout {
    pub analyses: Rect,
    pub params: Rect,
    pub plot: Rect,
    pub jobs: Rect,
    /// The analysis, parameter row (by index into all rows) and job on each row of their
    /// panes, top down (the first is the row under the top border).
    pub analysis_rows: Vec<usize>,
    pub param_rows: Vec<Option<usize>>,
    pub job_rows: Vec<usize>,
    /// The plot's data areas.
    pub frames: Vec<Drawn>,
}

/// What the mouse can act on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    Analysis(usize),
    Param(usize),
    Job(usize),
    /// A point of the plot, in its data coordinates.
    Point(f64, f64),
    /// A pane, not on a row or point.
    Pane(Focus),
    Nothing,
}

fn inside(r: Rect, col: u16, row: u16) -> bool {
    col >= r.x && col < r.x + r.width && row >= r.y && row < r.y + r.height
}

impl Layout {
    /// What is at terminal cell (col, row).
    pub fn target(&self, col: u16, row: u16) -> Target {
        let line = |r: Rect| (row > r.y).then(|| (row - r.y - 1) as usize);
        if inside(self.analyses, col, row) {
            match line(self.analyses).and_then(|l| self.analysis_rows.get(l)) {
                Some(&i) => Target::Analysis(i),
                None => Target::Pane(Focus::Analyses),
            }
        } else if inside(self.params, col, row) {
            match line(self.params).and_then(|l| self.param_rows.get(l).copied().flatten()) {
                Some(i) => Target::Param(i),
                None => Target::Pane(Focus::Params),
            }
        } else if inside(self.jobs, col, row) {
            match line(self.jobs).and_then(|l| self.job_rows.get(l)) {
                Some(&i) => Target::Job(i),
                None => Target::Pane(Focus::Jobs),
            }
        } else if inside(self.plot, col, row) {
            match self.frames.iter().find_map(|f| f.at(col, row)) {
                Some((x, y)) => Target::Point(x, y),
                None => Target::Pane(Focus::Plot),
            }
        } else {
            Target::Nothing
        }
    }
}

impl App {
    /// A mouse event: clicks focus and select, the wheel scrolls the pane under it.
    pub fn handle_mouse(&mut self, event: MouseEvent) {
        // overlays and edits keep the keys; the mouse waits
        if self.overlay.is_some() || self.editing.is_some() {
            return;
        }
        let target = self.layout.borrow().target(event.column, event.row);
        match event.kind {
            MouseEventKind::Down(MouseButton::Left) => self.click(target),
            MouseEventKind::ScrollUp | MouseEventKind::ScrollDown => {
                let by = if event.kind == MouseEventKind::ScrollUp {
                    -1
                } else {
                    1
                };
                let pane = match target {
                    Target::Analysis(_) => Focus::Analyses,
                    Target::Param(_) => Focus::Params,
                    Target::Job(_) => Focus::Jobs,
                    Target::Point(..) => Focus::Plot,
                    Target::Pane(p) => p,
                    Target::Nothing => return,
                };
                self.scroll(pane, by);
            }
            _ => return,
        }
        self.dirty = true;
    }
}
