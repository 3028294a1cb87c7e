//! Result files are read on a thread of their own, so that a large result (a chirp's CSV is
//! 12 MB) never holds up a key press: the app asks for a poll of some analyses and takes the
//! updates that come back.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::{Duration, Instant};

use isola::session::Session;
use isola::session::results::{ResultReader, ResultStatus, ResultView};
use isola::session::run::glance_of;
use isola::session::store::survey::Survey;

/// What the app knows of one analysis' stored result.
#[derive(Debug, Clone)]
pub struct Stored {
    pub status: ResultStatus,
    pub view: Option<Arc<ResultView>>,
    /// The complete result of the settings before, while a partial one of the current
    /// settings is shown.
    pub previous: Option<Arc<ResultView>>,
    pub error: Option<String>,
    /// The chunks done and claimed, by host, while no current result is stored: work under
    /// way here or elsewhere (another terminal, the nodes of a cluster).
    pub work: Option<Arc<Survey>>,
}

impl Default for Stored {
    fn default() -> Self {
        Stored {
            status: ResultStatus::Missing,
            view: None,
            previous: None,
            error: None,
            work: None,
        }
    }
}

struct Request {
    session: Arc<Session>,
    which: Vec<usize>,
    /// Send every analysis' state, changed or not (the app has just forgotten them).
    resend: bool,
}

enum Reply {
    /// Analysis `name`, number `index` in the session polled, changed.
    Update {
        index: usize,
        name: String,
        stored: Stored,
    },
    /// A request was answered in full.
    Done,
}

/// The reading thread and the app's end of it.
pub struct Watcher {
    requests: Sender<Request>,
    replies: Receiver<Reply>,
    /// Requests sent and not answered yet.
    pending: usize,
}

impl Watcher {
    pub fn start() -> Watcher {
        let (requests, rx) = channel::<Request>();
        let (tx, replies) = channel();
        std::thread::Builder::new()
            .name("isola-results".into())
            .spawn(move || read_loop(rx, tx))
            .expect("a thread to read results");
        Watcher {
            requests,
            replies,
            pending: 0,
        }
    }

    /// Asks for analyses `which` of `session` to be read again (what changed on disk).
    pub fn poll(&mut self, session: &Arc<Session>, which: Vec<usize>) {
        self.request(session, which, false);
    }

    /// Asks for the state of analyses `which`, changed or not (after the app reset its own).
    pub fn poll_all(&mut self, session: &Arc<Session>, which: Vec<usize>) {
        self.request(session, which, true);
    }

    fn request(&mut self, session: &Arc<Session>, which: Vec<usize>, resend: bool) {
        if self
            .requests
            .send(Request {
                session: session.clone(),
                which,
                resend,
            })
            .is_ok()
        {
            self.pending += 1;
        }
    }

    /// Updates received so far: (index, analysis name, what is stored).
    pub fn updates(&mut self) -> Vec<(usize, String, Stored)> {
        let mut out = Vec::new();
        while let Ok(reply) = self.replies.try_recv() {
            match reply {
                Reply::Update {
                    index,
                    name,
                    stored,
                } => out.push((index, name, stored)),
                Reply::Done => self.pending = self.pending.saturating_sub(1),
            }
        }
        out
    }

    /// True while a poll is being answered.
    pub fn busy(&self) -> bool {
        self.pending > 0
    }
}

/// How often the chunk files of work under way are looked at when nothing else changed.
pub const GLANCE_EVERY: Duration = Duration::from_secs(2);

/// One analysis as the reading thread follows it.
struct Followed {
    reader: ResultReader,
    /// The work under way as last seen, and when it was looked at.
    work: Option<Arc<Survey>>,
    glanced: Option<Instant>,
}

fn read_loop(requests: Receiver<Request>, replies: Sender<Reply>) {
    // by session file and analysis name: opening another session starts afresh
    let mut readers: HashMap<(std::path::PathBuf, String), Followed> = HashMap::new();
    while let Ok(request) = requests.recv() {
        for index in request.which {
            let Some(entry) = request.session.analyses.get(index) else {
                continue;
            };
            let Followed {
                reader,
                work,
                glanced,
            } = readers
                .entry((request.session.path.clone(), entry.name.clone()))
                .or_insert_with(|| Followed {
                    reader: ResultReader::new(entry),
                    work: None,
                    glanced: None,
                });
            let changed = reader.poll(&request.session, entry);
            // the chunk files' headers are read again when chunks came in, and every
            // GLANCE_EVERY otherwise (claims come and go without a file changing)
            let due =
                changed || request.resend || glanced.is_none_or(|at| at.elapsed() >= GLANCE_EVERY);
            let mut work_changed = false;
            if reader.status == ResultStatus::Complete {
                work_changed = work.take().is_some();
            } else if due {
                *glanced = Some(Instant::now());
                let now_work = Some(glance_of(&request.session, entry))
                    .filter(|s| !(s.done.is_empty() && s.claimed.is_empty()));
                work_changed = now_work.as_ref() != work.as_deref();
                if work_changed {
                    *work = now_work.map(Arc::new);
                }
            }
            if changed || work_changed || request.resend {
                let stored = Stored {
                    status: reader.status,
                    view: reader.view.clone().map(Arc::new),
                    previous: reader.previous.clone(),
                    error: reader.error.clone(),
                    work: work.clone(),
                };
                let update = Reply::Update {
                    index,
                    name: entry.name.clone(),
                    stored,
                };
                if replies.send(update).is_err() {
                    return;
                }
            }
        }
        if replies.send(Reply::Done).is_err() {
            return;
        }
    }
}
