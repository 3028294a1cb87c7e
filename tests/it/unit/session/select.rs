//! Unit tests of `session::select` (`src/session/select.rs`).

use isola::session::select::*;

#[test]
fn where_is_parsed_strictly() {
    let f = parse_filter("omega >= 3.5").unwrap();
    assert_eq!(
        (f.column.as_str(), f.op, f.number),
        ("omega", ">=", Some(3.5))
    );
    assert_eq!(parse_filter("omega==3.7").unwrap().op, "=");
    assert!(parse_filter("ratio=1:2").unwrap().keeps("1:2"));
    for bad in [
        "omega<abc",
        "omega",
        "=3",
        "omega=",
        "omega=<3",
        "omega!3",
        "a<nan",
        "a>inf",
    ] {
        assert!(parse_filter(bad).is_err(), "{bad}");
    }
    let f = parse_filter("amplitude_stretch>0.1").unwrap();
    assert!(f.keeps("0.2") && !f.keeps("0.05") && !f.keeps(""));
    let f = parse_filter("branch!=3").unwrap();
    assert!(f.keeps("4") && !f.keeps("3.0") && f.keeps(""));
}
