//! Unit tests of `session::locate` (`src/session/locate.rs`).

use isola::session::locate::*;

const TEXT: &str = "schema = 1\n[model]\nadr = 1e-9\n\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = -3 }\n[analysis.settings.steady]\nresolution = { max_step = 1.0e-300 }\n";

#[test]
fn finds_lines_and_text_as_written() {
    let w = locate(TEXT, Table::Model, "adr");
    assert_eq!((w.line, w.text.as_deref()), (Some(3), Some("1e-9")));
    let w = locate(TEXT, Table::AnalysisSettings(0), "dx.points");
    assert_eq!((w.line, w.text.as_deref()), (Some(9), Some("-3")));
    let w = locate(
        TEXT,
        Table::AnalysisSettings(0),
        "steady.resolution.max_step",
    );
    assert_eq!((w.line, w.text.as_deref()), (Some(11), Some("1.0e-300")));
    // not written: the line of its nearest parent
    let w = locate(TEXT, Table::AnalysisSettings(0), "steady.max_period");
    assert_eq!((w.line, w.text), (Some(10), None));
    let w = locate(TEXT, Table::Model, "omega");
    assert_eq!((w.line, w.text), (Some(2), None));
}

#[test]
fn serde_messages_in_plain_words() {
    // a number or a list where a table goes names the table's keys
    assert_eq!(
        plain("invalid type: floating point `0.00000000000000000001`, expected struct Tolerance"),
        "a table { rtol = …, atol = … } is expected, not a number"
    );
    assert_eq!(
        plain("invalid length 1, expected struct Axis with 3 elements"),
        "a table { min = …, max = …, points = … } is expected, not a list"
    );
    assert_eq!(
        plain("invalid value: integer `-3`, expected usize"),
        "-3 is not allowed: a whole number >= 0 is expected"
    );
    assert_eq!(
        plain("invalid type: integer `3`, expected a boolean"),
        "3 is not allowed: true or false is expected"
    );
    assert_eq!(
        plain("invalid type: string \"x\", expected f64"),
        "\"x\" is not allowed: a number is expected"
    );
    assert_eq!(plain("unknown field `stpe`"), "unknown field `stpe`");
}
