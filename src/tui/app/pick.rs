//! The picked point of a plot and the scalogram under a chirp.

use isola::analysis::Oscillator;
use isola::analysis::orbit::scalogram::{Scalogram, ScalogramSpec};
use isola::session::results::{ChirpView, ResultStatus, ResultView};
use isola::session::written::ModelPoint;

use super::{App, Picked};
use crate::tui::jobs::Work;
use crate::tui::orbit;
use crate::tui::plots::{self, Pick};

impl App {
    /// Why Enter opens no orbit from the plot shown, whatever the point under the cursor: an
    /// orbit is shown already, the plot is held, or its result is of other settings (an orbit
    /// is integrated on the current settings, so it is picked from their result only). The
    /// reason, and whether it is an error; the status bar and the plot offer Enter without one.
    pub fn pick_blocked(&self) -> Option<(String, bool)> {
        use crate::tui::keymap::Action;
        if self.picked.is_some() {
            let back = self.keymap.label(Action::Back);
            Some((
                format!("an orbit is shown: {back} returns to the result"),
                false,
            ))
        } else if self.frozen.is_some() {
            let key = self.keymap.label(Action::Freeze);
            Some((
                format!("the plot is held: {key} resumes it, then pick"),
                false,
            ))
        } else if self.status_of(self.selected) == ResultStatus::Stale {
            let run = self.keymap.label(Action::Run);
            Some((
                format!("the result shown is of other settings: {run} runs these, then pick"),
                true,
            ))
        } else {
            None
        }
    }

    /// Integrates the orbit under the plot cursor.
    pub(super) fn pick(&mut self) {
        if let Some((why, error)) = self.pick_blocked() {
            self.say(why, error);
            return;
        }
        let Some(view) = self.view() else { return };
        let Some(Pick {
            omega,
            member,
            start,
        }) = plots::pick(view, self.cursor)
        else {
            let why = match view {
                // a result stored before the steps kept their starts
                ResultView::Stepped(_) => {
                    "this stepped sweep was stored without its steps' starts: r runs it again, \
                     then pick"
                }
                _ => "nothing to pick here",
            };
            self.say(why, false);
            return;
        };
        let Some(entry) = self.session.analyses.get(self.selected) else {
            return;
        };
        let model = self
            .session
            .point(Some(entry))
            .and_then(|model| orbit::at_pick(model, &entry.settings, member, omega));
        let model = match model {
            Ok(model) => model,
            Err(e) => {
                self.say(e.to_string(), true);
                return;
            }
        };
        let (name, omega) = match &model {
            ModelPoint::BuiltIn(p) => ("ω".to_string(), p.omega()),
            ModelPoint::Written(sys) => (
                sys.model().frequency_name().to_string(),
                sys.value_of(sys.frequency()),
            ),
        };
        let (model, spec, from) = orbit::orbit_from(model, &start);
        let label = format!("orbit {name} {omega:.3} {from}");
        let job = self.jobs.push(label.clone(), Work::Orbit { model, spec });
        let fingerprint = self.session.fingerprint(entry);
        self.picked = Some(Picked {
            label,
            job,
            fingerprint,
            history: None,
            view: None,
            cursor: (0, 0),
            summary: None,
        });
        self.tick();
    }

    pub(super) fn toggle_scalogram(&mut self) {
        if !matches!(self.view(), Some(ResultView::Chirp(_))) {
            self.say("the scalogram is drawn for chirp sweeps", false);
            return;
        }
        self.show_scalogram = !self.show_scalogram;
        self.ensure_scalogram();
        self.tick();
    }

    /// While the scalogram is shown, starts computing the selected chirp's if none is of
    /// the response shown and the analysis' settings, nor being computed.
    pub(super) fn ensure_scalogram(&mut self) {
        if !self.show_scalogram {
            return;
        }
        let Some(ResultView::Chirp(c)) = self.view() else {
            return;
        };
        let entry = &self.session.analyses[self.selected];
        let spec = entry.settings.scalogram_spec();
        let source = scalogram_source(c, &spec);
        let name = entry.name.clone();
        let current = self
            .scalograms
            .get(&name)
            .is_some_and(|(s, _)| *s == source);
        let computing = self
            .scalogram_jobs
            .values()
            .any(|(n, s)| *n == name && *s == source);
        if !current && !computing {
            let work = Work::Scalogram {
                lambda: c.lambda.clone(),
                dt: c.dt,
                spec,
            };
            let id = self.jobs.push(format!("scalogram {name}"), work);
            self.scalogram_jobs.insert(id, (name, source));
        }
    }

    /// `entry`'s scalogram if `view` is its chirp response and one is current for it.
    pub(super) fn scalogram_of_view(
        &self,
        entry: &isola::session::AnalysisEntry,
        view: &ResultView,
    ) -> Option<&Scalogram> {
        match view {
            ResultView::Chirp(c) => self.scalogram(&entry.name, c),
            _ => None,
        }
    }

    /// Analysis `name`'s scalogram, if one was computed from chirp response `c` by the
    /// analysis' current settings (never one of an earlier result).
    pub fn scalogram(&self, name: &str, c: &ChirpView) -> Option<&Scalogram> {
        let entry = self.session.analysis(name)?;
        let (source, s) = self.scalograms.get(name)?;
        (*source == scalogram_source(c, &entry.settings.scalogram_spec())).then_some(s)
    }
}

/// What a scalogram is computed from, as one number: the response's samples and their
/// interval, and the scalogram's settings. A stored scalogram is shown only while this is
/// unchanged.
fn scalogram_source(c: &ChirpView, spec: &ScalogramSpec) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::hash::DefaultHasher::new();
    c.dt.to_bits().hash(&mut h);
    for x in &c.lambda {
        x.to_bits().hash(&mut h);
    }
    let f = &spec.frequencies;
    (f.min.to_bits(), f.max.to_bits(), f.points, spec.columns).hash(&mut h);
    h.finish()
}
