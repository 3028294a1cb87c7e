//! Session text → load and validation → the cost estimate and budget of every analysis: any
//! input must end in a value or an error, never a panic, an abort or a hang.

#![no_main]

use libfuzzer_sys::fuzz_target;

use isola::session::Session;
use isola::session::budget::{self, Budget};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(session) = Session::parse(std::path::Path::new("fuzz.toml"), text) else {
        return;
    };
    let budget = Budget {
        seconds: 60.0,
        bytes: 4e9,
        threads: 2,
        force: false,
    };
    for entry in &session.analyses {
        let _ = session.fingerprint(entry);
        if let Ok(cost) = budget::cost_of(&session, entry) {
            let _ = budget.check(&entry.name, &cost);
        }
    }
});
