//! A session's report: one self-contained HTML page with each analysis' figure inline (SVG)
//! and its tables (branches, attractors with their fractions, bifurcations, curves), which
//! opens in any browser without a network or anything installed.

use std::fmt::Write as _;

use super::{AxisNames, FigureError, Format, Options, Subject, render, short_type};
use crate::model::Device;
use crate::session::results::{ResultView, branches};
use crate::session::{AnalysisEntry, Session};

/// One analysis of the report.
pub struct Section<'a> {
    pub entry: &'a AnalysisEntry,
    pub subject: Subject<'a>,
}

/// The page's own style: no font, script or sheet from elsewhere.
const STYLE: &str = "body{font-family:'DejaVu Sans',sans-serif;max-width:1000px;margin:2em auto;\
padding:0 1em;color:#141414}h1{font-size:1.5em}h2{font-size:1.2em;margin-top:2em;\
border-bottom:1px solid #ddd}table{border-collapse:collapse;margin:.6em 0;font-size:.9em}\
th,td{border:1px solid #ccc;padding:.2em .6em;text-align:right}th{background:#f2f2f2}\
td.l,th.l{text-align:left}figure{margin:0}svg{max-width:100%;height:auto}\
p.note{color:#666;font-size:.9em}";

/// Text with `&`, `<`, `>` and `"` escaped for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A table: a caption, a header and rows of cells (the first column left-aligned).
struct Table {
    caption: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn new<S: Into<String>>(caption: impl Into<String>, header: Vec<S>) -> Self {
        Table {
            caption: caption.into(),
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    fn write(&self, html: &mut String) {
        if self.rows.is_empty() {
            return;
        }
        let _ = write!(
            html,
            "<table><caption>{}</caption><tr>",
            escape(&self.caption)
        );
        for (i, h) in self.header.iter().enumerate() {
            let class = if i == 0 { " class=\"l\"" } else { "" };
            let _ = write!(html, "<th{class}>{}</th>", escape(h));
        }
        html.push_str("</tr>");
        for row in &self.rows {
            html.push_str("<tr>");
            for (i, cell) in row.iter().enumerate() {
                let class = if i == 0 { " class=\"l\"" } else { "" };
                let _ = write!(html, "<td{class}>{}</td>", escape(cell));
            }
            html.push_str("</tr>");
        }
        html.push_str("</table>\n");
    }
}

/// Frequencies `omegas` as cells, then their Hz on the device (none without one).
fn with_hz(device: Option<&Device>, omegas: &[f64]) -> Vec<String> {
    let mut cells: Vec<String> = omegas.iter().map(|w| format!("{w:.3}")).collect();
    if let Some(d) = device {
        cells.extend(omegas.iter().map(|&w| format!("{:.2}", d.hz(w))));
    }
    cells
}

/// The tables of one result; `names`: a written model's (its frequency's name; no device,
/// so no Hz, and no membranes to go slack).
fn tables(view: &ResultView, device: Option<&Device>, names: Option<&AxisNames>) -> Vec<Table> {
    let omega = names.map_or("ω_e", |n| n.frequency.as_str());
    // frequency columns `labels`, then their Hz on the device
    let omega_columns = |labels: &[&str]| -> Vec<String> {
        let mut header: Vec<String> = labels.iter().map(|l| format!("{omega}{l}")).collect();
        if device.is_some() {
            header.extend(labels.iter().map(|l| format!("Hz{l}")));
        }
        header
    };
    let mut out = Vec::new();
    match view {
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(crate::session::results::HuntView {
            responses: points, ..
        }) => {
            let mut header = vec!["branch".to_string(), "type".into()];
            header.extend(omega_columns(&[" from", " to"]));
            header.extend([
                "peak A".into(),
                format!("at {omega}"),
                "points".into(),
                "reached".into(),
            ]);
            let mut t = Table::new("Branches", header);
            for b in branches(points) {
                let mut row = vec![b.id.to_string(), b.response_type.clone()];
                row.extend(with_hz(device, &[b.omega_min, b.omega_max]));
                let reached = if b.hidden {
                    "hidden"
                } else if b.partly_hidden {
                    "partly hidden"
                } else {
                    "by a sweep"
                };
                row.extend([
                    format!("{:.4}", b.peak_amplitude),
                    format!("{:.3}", b.peak_omega),
                    b.points.to_string(),
                    reached.into(),
                ]);
                t.rows.push(row);
            }
            out.push(t);
        }
        ResultView::Basin(b) => {
            let mut t = Table::new(
                "Attractors",
                vec!["attractor", "type", "amplitude", "cells", "fraction"],
            );
            for a in &b.attractors {
                t.rows.push(vec![
                    a.id.to_string(),
                    a.response_type.clone(),
                    a.amplitude.map_or("—".into(), |x| format!("{x:.4}")),
                    a.cells.to_string(),
                    format!("{:.2} %", 100.0 * a.fraction),
                ]);
            }
            out.push(t);
        }
        ResultView::History(h) => {
            if let Some(s) = &h.summary {
                let mut header = omega_columns(&[""]);
                header.extend(["period".into(), "amplitude".into()]);
                let mut row = with_hz(device, &[s.omega]);
                row.extend([
                    s.period_forcing_periods
                        .map_or("none within the record".into(), |k| format!("1:{k}")),
                    format!("{:.4}", s.amplitude),
                ]);
                if let Some(slack) = s.slack {
                    header.extend(["slack I".into(), "slack II".into()]);
                    row.extend(slack.map(|share| format!("{:.0} %", 100.0 * share)));
                }
                let mut t = Table::new("Steady state", header);
                t.rows.push(row);
                out.push(t);
            }
        }
        ResultView::Chirp(c) => {
            let mut header = omega_columns(&[""]);
            header.push("amplitude".into());
            let mut t = Table::new("Envelope peak", header);
            if let Some(e) = c.envelope.iter().max_by(|a, b| a[1].total_cmp(&b[1])) {
                let mut row = with_hz(device, &[e[0]]);
                row.push(format!("{:.4}", e[1]));
                t.rows.push(row);
            }
            out.push(t);
        }
        ResultView::Force(f) => {
            let mut t = Table::new("Force curves", vec!["λ_p", "φ_I", "points"]);
            for (lambda_p, phi_i, curve) in &f.curves {
                t.rows.push(vec![
                    lambda_p.to_string(),
                    phi_i.to_string(),
                    curve.len().to_string(),
                ]);
            }
            out.push(t);
        }
        ResultView::Family(f) => {
            let mut t = Table::new(
                "Branches per member",
                vec![
                    "member".to_string(),
                    "branch".into(),
                    "type".into(),
                    format!("{omega} from"),
                    format!("{omega} to"),
                    "peak A".into(),
                    "reached".into(),
                ],
            );
            for (value, points) in &f.members {
                for b in branches(points) {
                    t.rows.push(vec![
                        format!("{} = {value}", f.parameter),
                        b.id.to_string(),
                        short_type(&b.response_type).into(),
                        format!("{:.3}", b.omega_min),
                        format!("{:.3}", b.omega_max),
                        format!("{:.4}", b.peak_amplitude),
                        if b.hidden { "hidden" } else { "by a sweep" }.into(),
                    ]);
                }
            }
            out.push(t);
        }
        ResultView::Continuation(_) | ResultView::Map(_) => {}
    }
    let continued = match view {
        ResultView::Continuation(c) => Some((c.parameter.as_str(), &c.branches)),
        ResultView::Hunt(h) => Some((
            names.map_or("omega", |n| n.frequency.as_str()),
            &h.continued,
        )),
        _ => None,
    };
    if let Some((parameter, branches)) = continued {
        let mut t = Table::new(
            "Continued branches",
            vec!["branch", "period", "verdict", "points", "stable points"],
        );
        let mut f = Table::new(
            "Bifurcations",
            vec!["branch", "kind", "parameter", omega, "amplitude"],
        );
        for (i, b) in branches.iter().enumerate() {
            t.rows.push(vec![
                i.to_string(),
                b.period.to_string(),
                b.verdict.clone(),
                b.points.len().to_string(),
                b.points.iter().filter(|p| p.stable).count().to_string(),
            ]);
            for p in &b.bifurcations {
                f.rows.push(vec![
                    i.to_string(),
                    p.kind.clone(),
                    format!("{parameter} = {:.4}", p.parameter),
                    format!("{:.4}", p.omega),
                    format!("{:.4}", p.amplitude),
                ]);
            }
        }
        out.push(t);
        out.push(f);
    }
    if let ResultView::Map(m) = view {
        let mut t = Table::new(
            "Turning points of the curves",
            vec!["curve", "kind", "period", "turning", "of", "x", "value"],
        );
        for (i, c) in m.curves.iter().enumerate() {
            for (turning, of, at) in &c.extrema {
                t.rows.push(vec![
                    i.to_string(),
                    c.kind.clone(),
                    c.period.to_string(),
                    turning.clone(),
                    of.clone(),
                    format!("{:.4}", at[0]),
                    format!("{:.4}", at[1]),
                ]);
            }
        }
        out.push(t);
    }
    out
}

/// The report of `session`: every section's figure (SVG, inline) and tables. Figures are
/// drawn with `options` but always as SVG.
pub fn html(
    session: &Session,
    sections: &[Section],
    options: &Options,
) -> Result<String, FigureError> {
    let options = Options {
        format: Format::Svg,
        ..*options
    };
    let title = session
        .file
        .description
        .clone()
        .unwrap_or_else(|| session.path.display().to_string());
    let mut html = String::new();
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\
         <style>{STYLE}</style></head><body>\n<h1>{}</h1>\n<p class=\"note\">{} · isola {}</p>\n",
        escape(&title),
        escape(&title),
        escape(&session.path.display().to_string()),
        escape(crate::BUILD)
    );
    for section in sections {
        let entry = section.entry;
        let _ = writeln!(
            html,
            "<section id=\"{}\"><h2>{} ({})</h2>",
            escape(&entry.name),
            escape(&entry.name),
            escape(&entry.settings.kind().replace('_', " "))
        );
        let svg = render(&section.subject, &options)?;
        let svg = String::from_utf8_lossy(&svg);
        // the XML declaration has no place inside HTML, nor does the namespace (HTML gives
        // it): the page names no address at all
        let svg = match svg.find("<svg") {
            Some(i) => &svg[i..],
            None => &svg,
        }
        .replacen(" xmlns=\"http://www.w3.org/2000/svg\"", "", 1);
        let _ = writeln!(html, "<figure>{svg}</figure>");
        let subject = &section.subject;
        for table in tables(
            subject.view,
            subject.device.as_ref(),
            subject.names.as_ref(),
        ) {
            table.write(&mut html);
        }
        html.push_str("</section>\n");
    }
    html.push_str("</body></html>\n");
    Ok(html)
}
