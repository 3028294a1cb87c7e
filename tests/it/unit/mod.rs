//! The library's unit tests, beside its integration tests in this one test binary (the
//! library is then compiled once for the tests, not twice).

pub mod analysis {
    mod cost;
    pub mod global {
        mod batch;
        mod capture;
        mod chirp;
        mod ellipse;
        pub mod history;
        mod stepped_sweep;
    }
    mod orbit {
        mod attractor;
        mod floquet;
        mod force_curve;
        mod ratio;
        mod scalogram;
        mod shooting;
        mod steady_state;
        mod time_history;
        mod variational;
    }
    mod resolution;
}
mod figure {
    mod text;
}
mod jobs;
mod model {
    mod drive;
    mod equations {
        mod graph;
        mod parse;
        mod written;
    }
    mod forces;
    mod forcing;
    mod params;
    mod statics;
    mod units;
}
mod session {
    mod atomic;
    mod budget;
    mod edit;
    mod locate;
    mod model_section;
    mod output;
    mod preview;
    mod select;
    mod store {
        mod chunk;
        mod copy;
        mod finite;
        mod lock;
        mod manifest;
        mod saver;
    }
}
mod solver {
    mod drive_table;
    mod field;
    mod hermite;
    mod rk4;
}
